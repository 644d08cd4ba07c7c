use super::*;
use crate::grid::Grid;
use crate::map::{FREE, GridFrame, OBSTACLE, Object, Parent, Relation, Room};

fn object(id: u32, category: &str, footprint: Vec<Cell>) -> Object {
    let k = footprint.len().max(1) as f64;
    let center = [
        footprint.iter().map(|c| c.row as f64).sum::<f64>() / k,
        footprint.iter().map(|c| c.col as f64).sum::<f64>() / k,
    ];
    Object {
        id,
        category: category.into(),
        name: format!("{category}_{id}"),
        footprint,
        center,
        elevation_m: None,
        height_m: None,
        room: None,
        parent: None,
        attributes: Vec::new(),
    }
}

fn rect(r0: u32, c0: u32, r1: u32, c1: u32) -> Vec<Cell> {
    (r0..=r1)
        .flat_map(|r| (c0..=c1).map(move |c| Cell::new(r, c)))
        .collect()
}

/// A 20×20 two-room house: a kitchen (cols 1..=9) and a bedroom (cols 11..=18) split by a wall
/// with a doorway, a window on the outer wall, a table with a cup on it, and a start cell.
pub(super) fn tiny_house() -> SemanticMap {
    let n = 20;
    let mut occupancy = Grid::new(n, OBSTACLE);
    let mut room_layer = Grid::new(n, 0u32);
    let mut object_layer = Grid::new(n, 0u32);
    for c in rect(1, 1, 18, 18) {
        occupancy.set(c, FREE);
        room_layer.set(c, if c.col <= 9 { 1 } else { 2 });
    }
    let wall = rect(1, 10, 18, 10);
    let door = rect(8, 10, 10, 10);
    let window = rect(0, 3, 0, 6);
    let table = rect(4, 3, 6, 6);
    for c in &wall {
        occupancy.set(*c, OBSTACLE);
    }
    for c in &door {
        occupancy.set(*c, FREE);
    }
    for c in &table {
        occupancy.set(*c, OBSTACLE);
    }
    let mut objects = vec![
        object(1, "wall", wall),
        object(2, "doorway", door),
        object(3, "window", window),
        object(4, "dining_table", table),
        object(5, "cup", vec![Cell::new(5, 4)]),
    ];
    objects[4].parent = Some(Parent {
        id: 4,
        relation: Relation::On,
    });
    for o in &objects {
        for c in &o.footprint {
            object_layer.set(*c, o.id);
        }
    }
    let room = |id: u32, cat: &str, area: f64| Room {
        id,
        category: cat.into(),
        name: format!("{cat}_1"),
        area_m2: area,
        attributes: Vec::new(),
    };
    SemanticMap {
        map_id: "test/tiny".into(),
        frame: GridFrame {
            resolution: 0.25,
            x_min: 0.0,
            z_min: 0.0,
        },
        occupancy,
        room_layer,
        object_layer,
        rooms: vec![room(1, "kitchen", 10.1), room(2, "bedroom", 9.0)],
        objects,
        start: Some(Cell::new(15, 4)),
        open_boundaries: Vec::new(),
    }
}

fn empty_map(n: usize) -> SemanticMap {
    SemanticMap {
        map_id: String::new(),
        frame: GridFrame {
            resolution: 1.0,
            x_min: 0.0,
            z_min: 0.0,
        },
        occupancy: Grid::new(n, FREE),
        room_layer: Grid::new(n, 0),
        object_layer: Grid::new(n, 0),
        rooms: Vec::new(),
        objects: Vec::new(),
        open_boundaries: Vec::new(),
        start: None,
    }
}

/// Width and height from the PNG header (IHDR), checked against the signature.
fn png_size(png: &[u8]) -> (u32, u32) {
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
    (w, h)
}

pub(super) fn svg_size(svg: &str) -> (u32, u32) {
    let attr = |name: &str| -> u32 {
        let key = format!(" {name}=\"");
        let start = svg.find(&key).unwrap() + key.len();
        let end = start + svg[start..].find('"').unwrap();
        svg[start..end].parse().unwrap()
    };
    (attr("width"), attr("height"))
}

fn all_overlays() -> Vec<Overlay> {
    vec![
        Overlay::Region {
            cells: rect(2, 12, 5, 16),
            kind: RegionKind::Destination,
            label: Some("goal".into()),
        },
        Overlay::Region {
            cells: rect(10, 2, 12, 8),
            kind: RegionKind::Avoid,
            label: None,
        },
        Overlay::Route {
            cells: vec![
                Cell::new(15, 4),
                Cell::new(15, 5),
                Cell::new(15, 6),
                Cell::new(9, 9),
                Cell::new(9, 11),
                Cell::new(3, 14),
            ],
            label: Some("plan".into()),
            color: None,
        },
        Overlay::StagedRoute {
            stages: vec![
                vec![Cell::new(15, 4), Cell::new(9, 4)],
                vec![Cell::new(9, 4), Cell::new(9, 15)],
            ],
            label: None,
        },
        Overlay::Marker {
            cell: Cell::new(3, 14),
            label: "1".into(),
        },
    ]
}

#[test]
fn same_input_gives_same_bytes() {
    let map = tiny_house();
    let opts = RenderOptions {
        labels: true,
        overlays: all_overlays(),
        ..Default::default()
    };
    let a = render_map(&map, &opts).unwrap();
    let b = render_map(&map, &opts).unwrap();
    assert_eq!(a.svg, b.svg);
    assert_eq!(a.png, b.png);
}

#[test]
fn png_has_the_svg_size() {
    let map = tiny_house();
    let out = render_map(&map, &RenderOptions::default()).unwrap();
    let (w, h) = svg_size(&out.svg);
    assert_eq!(png_size(&out.png), (w, h));
    // Auto scale: 20 cells fit in 1400 px at the 40 px cap; the map area alone is 800 px wide.
    assert!(w > 800 && h > 800, "{w}×{h}");
}

#[test]
fn explicit_scale_sets_the_map_size() {
    let map = tiny_house();
    let small = render_svg(
        &map,
        &RenderOptions {
            scale: 5.0,
            ..Default::default()
        },
    )
    .unwrap();
    let large = render_svg(
        &map,
        &RenderOptions {
            scale: 10.0,
            ..Default::default()
        },
    )
    .unwrap();
    let (ws, _) = svg_size(&small);
    let (wl, _) = svg_size(&large);
    // The whole 20-cell grid is content (walls count), so doubling the scale adds 20×5 px.
    assert_eq!(wl - ws, 100);
}

#[test]
fn base_layers_appear() {
    let map = tiny_house();
    let svg = render_svg(&map, &RenderOptions::default()).unwrap();
    for needle in [
        style::room_fill("kitchen").hex(),
        style::room_fill("bedroom").hex(),
        style::WALL.to_string(),
        style::DOORWAY.to_string(),
        style::WINDOW.to_string(),
        style::FURNITURE_FILL.to_string(),
        ">kitchen_1<".into(),
        ">bedroom_1<".into(),
        ">10.1 m²<".into(),
        ">test/tiny<".into(),
        "id=\"start\"".into(),
        "id=\"legend\"".into(),
        "id=\"scale\"".into(),
        ">living room<".into(),
    ] {
        if needle == ">living room<" {
            assert!(
                !svg.contains(&needle),
                "legend lists only room types present"
            );
        } else {
            assert!(svg.contains(&needle), "missing {needle}");
        }
    }
    assert!(
        !svg.contains(">dining_table<"),
        "no object labels unless asked"
    );
    let labelled = render_svg(
        &map,
        &RenderOptions {
            labels: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(labelled.contains(">dining_table<"));
}

#[test]
fn overlays_appear_in_svg_and_legend() {
    let map = tiny_house();
    let opts = RenderOptions {
        overlays: all_overlays(),
        ..Default::default()
    };
    let svg = render_svg(&map, &opts).unwrap();
    let plain = render_svg(&map, &RenderOptions::default()).unwrap();
    assert!(!plain.contains("id=\"overlays\""));
    assert!(svg.contains("id=\"overlays\""));
    let (dest, _, _) = RegionKind::Destination.look();
    let (avoid, _, dash) = RegionKind::Avoid.look();
    assert!(svg.contains(&format!("fill=\"{}\" fill-opacity", dest.hex())));
    assert!(svg.contains(&format!("fill=\"{}\" fill-opacity", avoid.hex())));
    assert!(svg.contains(&format!("stroke-dasharray=\"{}\"", dash.unwrap())));
    // The route and the two stages each get their own palette colour.
    for c in &style::ROUTE_PALETTE[..3] {
        assert!(
            svg.contains(&format!("stroke=\"{}\" stroke-width", c.hex())),
            "{c:?}"
        );
    }
    assert!(!svg.contains(&format!("stroke=\"{}\"", style::ROUTE_PALETTE[3].hex())));
    for needle in [
        ">goal<",
        ">plan<",
        ">destination<",
        ">avoid<",
        ">stage 1<",
        ">stage 2<",
        ">stage destination<",
        ">1<",
    ] {
        assert!(svg.contains(needle), "missing {needle}");
    }
}

#[test]
fn straight_route_runs_collapse_to_corners() {
    let map = tiny_house();
    let cells: Vec<Cell> = (2..=17).map(|c| Cell::new(12, c)).collect();
    let opts = RenderOptions {
        scale: 10.0,
        title: Some(String::new()),
        overlays: vec![Overlay::Route {
            cells,
            label: None,
            color: Some(Rgb(1, 2, 3)),
        }],
        ..Default::default()
    };
    let svg = render_svg(&map, &opts).unwrap();
    let line = svg
        .lines()
        .find(|l| l.contains("stroke=\"#010203\" stroke-width"))
        .unwrap();
    let d = line
        .split("d=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    assert_eq!(d.matches('L').count(), 1, "{d}");
}

#[test]
fn overlay_outside_the_map_is_an_error() {
    let map = tiny_house();
    let opts = RenderOptions {
        overlays: vec![
            Overlay::Marker {
                cell: Cell::new(3, 3),
                label: "a".into(),
            },
            Overlay::Marker {
                cell: Cell::new(20, 0),
                label: "b".into(),
            },
        ],
        ..Default::default()
    };
    let err = render_svg(&map, &opts).unwrap_err();
    assert!(
        matches!(err, RenderError::OverlayOutOfMap { index: 1, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("[20, 0]"));
}

#[test]
fn bad_scales_are_errors_not_panics() {
    let map = tiny_house();
    for scale in [f64::NAN, f64::INFINITY] {
        let err = render_svg(
            &map,
            &RenderOptions {
                scale,
                ..Default::default()
            },
        )
        .unwrap_err();
        assert!(matches!(err, RenderError::InvalidScale(_)));
    }
    let err = render_svg(
        &map,
        &RenderOptions {
            scale: 5000.0,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(matches!(err, RenderError::TooLarge { .. }), "{err}");
    // Negative means automatic, like zero.
    assert!(
        render_svg(
            &map,
            &RenderOptions {
                scale: -1.0,
                ..Default::default()
            }
        )
        .is_ok()
    );
}

#[test]
fn empty_and_sparse_maps_render() {
    let zero = render_map(&empty_map(0), &RenderOptions::default()).unwrap();
    assert!(zero.svg.contains(">empty map<"));
    let (w, h) = svg_size(&zero.svg);
    assert_eq!(png_size(&zero.png), (w, h));

    // All free, no rooms, no objects, no resolution worth a scale bar.
    let mut open = empty_map(8);
    open.frame.resolution = f64::NAN;
    let out = render_map(&open, &RenderOptions::default()).unwrap();
    assert!(!out.svg.contains("id=\"scale\""));
    assert_eq!(png_size(&out.png).0, svg_size(&out.svg).0);

    // All obstacle: nothing to crop to, the whole grid is drawn.
    let mut blocked = empty_map(6);
    blocked.occupancy = Grid::new(6, OBSTACLE);
    render_map(&blocked, &RenderOptions::default()).unwrap();
}

#[test]
fn inconsistent_maps_do_not_panic() {
    let mut map = tiny_house();
    // Room ids without instances, footprints outside the grid, an object without footprint,
    // a start outside the grid, layers of the wrong size.
    map.room_layer.set(Cell::new(3, 3), 77);
    map.objects.push(object(
        9,
        "sofa",
        vec![Cell::new(500, 500), Cell::new(2, 2)],
    ));
    map.objects.push(object(10, "chair", Vec::new()));
    map.start = Some(Cell::new(99, 99));
    map.object_layer = Grid::new(3, 0);
    let out = render_map(
        &map,
        &RenderOptions {
            labels: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(out.svg.contains(">room 77<"));
}

#[test]
fn user_text_is_escaped() {
    let mut map = tiny_house();
    map.map_id = "a<b>&\"c\"".into();
    map.rooms[0].name = "<script>&amp;".into();
    map.objects[3].category = "x&y<z>".into();
    let opts = RenderOptions {
        labels: true,
        overlays: vec![Overlay::Marker {
            cell: Cell::new(3, 3),
            label: "<&>\u{7}".into(),
        }],
        ..Default::default()
    };
    let out = render_map(&map, &opts).unwrap();
    assert!(out.svg.contains(">a&lt;b&gt;&amp;&quot;c&quot;<"));
    assert!(out.svg.contains(">&lt;script&gt;&amp;amp;<"));
    assert!(out.svg.contains(">x&amp;y&lt;z&gt;<"));
    assert!(out.svg.contains(">&lt;&amp;&gt;<"));
    assert!(!out.svg.contains("<script"));
}

#[test]
fn tiny_house_svg_snapshot() {
    let map = tiny_house();
    let opts = RenderOptions {
        labels: true,
        scale: 8.0,
        overlays: all_overlays(),
        title: None,
        caption: Vec::new(),
    };
    insta::assert_snapshot!(render_svg(&map, &opts).unwrap());
}

/// The five fixture houses of `../shared/procthor/fixtures`.
fn fixture_paths() -> Vec<std::path::PathBuf> {
    let dir =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor/fixtures");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    paths.sort();
    paths
}

#[test]
fn fixture_house_renders_compactly() {
    let path = &fixture_paths()[0];
    let map = crate::load::load_map(path.to_str().unwrap()).unwrap();
    let out = render_map(
        &map,
        &RenderOptions {
            labels: true,
            ..Default::default()
        },
    )
    .unwrap();
    let (w, h) = svg_size(&out.svg);
    assert_eq!(png_size(&out.png), (w, h));
    assert!(out.svg.len() < 5_000_000, "svg is {} bytes", out.svg.len());
    for r in &map.rooms {
        assert!(
            out.svg.contains(&format!(">{}<", svg::esc(&r.name))),
            "room {} unlabelled",
            r.name
        );
    }
}

/// Renders every fixture house into `$M2RC_RENDER_OUT` (for looking at the pictures):
/// `M2RC_RENDER_OUT=/tmp/r cargo test -p m2rc-stdlib --lib render::tests::write_fixture_pictures -- --ignored`
#[test]
#[ignore]
fn write_fixture_pictures() {
    let dir =
        std::path::PathBuf::from(std::env::var("M2RC_RENDER_OUT").expect("set M2RC_RENDER_OUT"));
    std::fs::create_dir_all(&dir).unwrap();
    let tiny = RenderOptions {
        labels: true,
        overlays: all_overlays(),
        ..Default::default()
    };
    std::fs::write(
        dir.join("tiny.png"),
        render_map(&tiny_house(), &tiny).unwrap().png,
    )
    .unwrap();
    for path in fixture_paths() {
        let map = crate::load::load_map(path.to_str().unwrap()).unwrap();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        for labels in [false, true] {
            let t = std::time::Instant::now();
            let out = render_map(
                &map,
                &RenderOptions {
                    labels,
                    ..Default::default()
                },
            )
            .unwrap();
            let suffix = if labels { "-labels" } else { "" };
            std::fs::write(dir.join(format!("{stem}{suffix}.png")), &out.png).unwrap();
            std::fs::write(dir.join(format!("{stem}{suffix}.svg")), &out.svg).unwrap();
            eprintln!(
                "{stem}{suffix}: n={} svg {} B png {} B {:?}",
                map.n(),
                out.svg.len(),
                out.png.len(),
                t.elapsed()
            );
        }
    }
}

/// Shortest 4-connected path over free cells (test helper for drawing plausible routes).
fn bfs_path(map: &SemanticMap, from: Cell, to: Cell) -> Vec<Cell> {
    let n = map.n();
    let mut prev = vec![u32::MAX; n * n];
    let idx = |c: Cell| c.row as usize * n + c.col as usize;
    let mut queue = std::collections::VecDeque::from([from]);
    prev[idx(from)] = idx(from) as u32;
    while let Some(c) = queue.pop_front() {
        if c == to {
            break;
        }
        for (dr, dc) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
            let (r, cc) = (c.row as i64 + dr, c.col as i64 + dc);
            if r < 0 || cc < 0 || r >= n as i64 || cc >= n as i64 {
                continue;
            }
            let nb = Cell::new(r as u32, cc as u32);
            if map.is_free(nb) && prev[idx(nb)] == u32::MAX {
                prev[idx(nb)] = idx(c) as u32;
                queue.push_back(nb);
            }
        }
    }
    let mut path = vec![to];
    let mut cur = idx(to);
    while cur != idx(from) && prev[cur] != u32::MAX {
        cur = prev[cur] as usize;
        path.push(Cell::new((cur / n) as u32, (cur % n) as u32));
    }
    path.reverse();
    path
}

/// A fixture house with every overlay kind on it, written next to the plain pictures.
#[test]
#[ignore]
fn write_fixture_overlay_picture() {
    let dir =
        std::path::PathBuf::from(std::env::var("M2RC_RENDER_OUT").expect("set M2RC_RENDER_OUT"));
    let path = &fixture_paths()[2];
    let map = crate::load::load_map(path.to_str().unwrap()).unwrap();
    let start = map.start.unwrap();
    let room_cells = |cat: &str, k: usize| -> Vec<Cell> {
        let id = map
            .rooms
            .iter()
            .filter(|r| r.category == cat)
            .nth(k)
            .unwrap()
            .id;
        map.room_layer
            .iter_cells()
            .filter(|(_, r)| **r == id)
            .map(|(c, _)| c)
            .collect()
    };
    let free_pole = |cells: &[Cell]| -> Cell {
        let free: Vec<Cell> = cells.iter().copied().filter(|&c| map.is_free(c)).collect();
        layers::pole(&free).unwrap().0
    };
    let bed = map.objects.iter().find(|o| o.category == "bed").unwrap();
    let bed_room: Vec<Cell> = map
        .room_layer
        .iter_cells()
        .filter(|(_, r)| Some(**r) == bed.room)
        .map(|(c, _)| c)
        .collect();
    let goal1 = free_pole(&room_cells("kitchen", 0));
    let goal2 = free_pole(&bed_room);
    let leg1 = bfs_path(&map, start, goal1);
    let leg2 = bfs_path(&map, goal1, goal2);
    let opts = RenderOptions {
        labels: false,
        title: Some("go to the kitchen, then to the bed; avoid the bathroom".into()),
        overlays: vec![
            Overlay::Region {
                cells: room_cells("bathroom", 0),
                kind: RegionKind::Avoid,
                label: Some("avoid".into()),
            },
            Overlay::Region {
                cells: bed.footprint.clone(),
                kind: RegionKind::Destination,
                label: Some("bed".into()),
            },
            Overlay::StagedRoute {
                stages: vec![leg1, leg2],
                label: None,
            },
            Overlay::Marker {
                cell: goal1,
                label: "1".into(),
            },
            Overlay::Marker {
                cell: goal2,
                label: "2".into(),
            },
        ],
        ..Default::default()
    };
    let out = render_map(&map, &opts).unwrap();
    std::fs::write(dir.join("overlays.png"), &out.png).unwrap();
    std::fs::write(dir.join("overlays.svg"), &out.svg).unwrap();
}

/// An open boundary is drawn as a dashed line where the two rooms meet, not as a wall, and the
/// legend names it.
#[test]
fn open_boundary_is_drawn_open() {
    let mut map = tiny_house();
    // Take the wall away and mark its column as the open boundary between the two rooms.
    let wall = rect(1, 10, 18, 10);
    map.objects
        .retain(|o| o.category != "wall" && o.category != "doorway");
    for c in &wall {
        map.occupancy.set(*c, FREE);
        map.room_layer.set(*c, 1);
    }
    let cells: Vec<Cell> = rect(1, 10, 18, 11);
    map.open_boundaries = vec![crate::map::OpenBoundary {
        rooms: (1, 2),
        cells,
    }];
    let svg = render_svg(&map, &RenderOptions::default()).unwrap();
    let group = svg
        .split("<g id=\"open-boundaries\"")
        .nth(1)
        .expect("open boundaries drawn");
    let group = &group[..group.find("</g>").unwrap()];
    assert!(group.contains("stroke-dasharray"), "{group}");
    // One edge per row between col 10 (room 1) and col 11 (room 2): 18 segments.
    assert_eq!(group.matches('M').count(), 18, "{group}");
    assert!(svg.contains("open boundary"));
    assert!(!svg.contains(&format!("fill=\"{}\"", style::WALL)));
    // The plain house has none.
    let plain = render_svg(&tiny_house(), &RenderOptions::default()).unwrap();
    assert!(!plain.contains("open-boundaries"));
}

/// Every `<text>` of the map area as (x0, x1, y, content): its horizontal extent from the anchor
/// and the layout's width estimate.
fn map_texts(svg: &str) -> Vec<(f64, f64, f64, String)> {
    let attr = |t: &str, name: &str| -> Option<String> {
        let i = t.find(&format!(" {name}=\""))? + name.len() + 3;
        Some(t[i..i + t[i..].find('"')?].to_string())
    };
    let mut out = Vec::new();
    for part in svg.split("<text ").skip(1) {
        let head = &format!(" {}", &part[..part.find('>').unwrap()]);
        let content = &part[part.find('>').unwrap() + 1..part.find("</text>").unwrap()];
        let x: f64 = attr(head, "x").unwrap().parse().unwrap();
        let y: f64 = attr(head, "y").unwrap().parse().unwrap();
        let size: f64 = attr(head, "font-size").unwrap().parse().unwrap();
        let bold = head.contains("font-weight=\"bold\"");
        let plain = content
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&amp;", "&");
        let w = svg::text_width(&plain, size, bold);
        let (x0, x1) = if attr(head, "text-anchor").as_deref() == Some("middle") {
            (x - w / 2.0, x + w / 2.0)
        } else {
            (x, x + w)
        };
        out.push((x0, x1, y, content.to_string()));
    }
    out
}

/// Labels near the picture's edges stay inside the map area (not cut off, not over the legend),
/// and every label is drawn after the routes, so no route runs over a label.
#[test]
fn labels_stay_inside_and_above_the_route() {
    let map = tiny_house();
    let edge = Cell::new(1, (map.n() - 2) as u32);
    let opts = RenderOptions {
        labels: true,
        scale: 8.0,
        overlays: vec![
            Overlay::Route {
                cells: vec![Cell::new(2, 2), Cell::new(2, 18), edge],
                label: Some("edge label".into()),
                color: None,
            },
            Overlay::Marker {
                cell: edge,
                label: "edge marker".into(),
            },
        ],
        title: Some(String::new()),
        caption: Vec::new(),
    };
    let svg = render_svg(&map, &opts).unwrap();
    // The map area: the margin, then crop columns × scale; the legend starts 20 px after it.
    let map_right = svg
        .split("<g id=\"legend\"")
        .nth(1)
        .and_then(|l| l.split(" x=\"").nth(1))
        .map(|x| x[..x.find('"').unwrap()].parse::<f64>().unwrap() - 20.0)
        .unwrap();
    // Everything up to the end of the markers: map, overlays, labels (not the scale bar below
    // the map, nor the legend).
    let markers_at = svg.find("<g id=\"markers\"").unwrap();
    let markers_end = markers_at + svg[markers_at..].find("</g>").unwrap();
    let texts = map_texts(&svg[..markers_end]);
    assert!(texts.iter().any(|t| t.3.contains("edge label")));
    assert!(texts.iter().any(|t| t.3.contains("edge marker")));
    for (x0, x1, _, content) in &texts {
        assert!(
            *x0 >= 0.0 && *x1 <= map_right,
            "{content:?} spans {x0}..{x1}, map ends at {map_right}"
        );
    }
    let route = svg.find("<g id=\"overlays\"").expect("overlays drawn");
    let labels = svg.find("<g id=\"labels\"").expect("labels drawn");
    let markers = svg.find("<g id=\"markers\"").expect("markers drawn");
    assert!(
        route < labels && labels < markers,
        "order: overlays {route}, labels {labels}, markers {markers}"
    );
}
