//! What a picture says in words: the caption under the title, the legend's list of named regions,
//! reference routes and blocked doorways.

use super::tests::{svg_size, tiny_house};
use super::*;

#[test]
fn the_caption_is_wrapped_under_the_title_and_makes_room_for_itself() {
    let map = tiny_house();
    let plain = render_svg(&map, &RenderOptions::default()).unwrap();
    let long = "Go to the cup on the table, then to the bed; keep away from the window. ".repeat(6);
    let opts = RenderOptions {
        caption: vec![long.clone(), "HCS 1.00 · PL 3.2 m".into()],
        ..RenderOptions::default()
    };
    let svg = render_svg(&map, &opts).unwrap();
    assert!(svg.contains(">HCS 1.00 · PL 3.2 m<"));
    let (w0, h0) = svg_size(&plain);
    let (w1, h1) = svg_size(&svg);
    assert_eq!(w0, w1, "a caption never widens the picture");
    assert!(h1 > h0 + 3 * 18, "wrapped over several lines: {h0} -> {h1}");
    assert!(
        !svg.contains(&long.trim().to_string()),
        "the long paragraph is wrapped"
    );
}

#[test]
fn named_regions_reference_routes_and_blocked_doorways_are_in_the_legend() {
    let map = tiny_house();
    let opts = RenderOptions {
        overlays: vec![
            Overlay::Region {
                cells: vec![Cell::new(3, 3), Cell::new(3, 4)],
                kind: RegionKind::Avoid,
                label: Some("avoid kitchen_1".into()),
            },
            Overlay::Region {
                cells: vec![Cell::new(9, 10)],
                kind: RegionKind::Blocked,
                label: Some("blocked door: bedroom_1 – kitchen_1".into()),
            },
            Overlay::Reference {
                cells: vec![Cell::new(5, 12), Cell::new(5, 16), Cell::new(9, 16)],
                label: Some("1. nDTW reference route".into()),
            },
            Overlay::Marker {
                cell: Cell::new(2, 2),
                label: "S".into(),
            },
        ],
        ..RenderOptions::default()
    };
    let svg = render_svg(&map, &opts).unwrap();
    for needle in [
        ">Regions<",
        ">avoid kitchen_1<",
        ">blocked door: bedroom_1 – kitchen_1<",
        ">blocked doorway<",
        ">1. nDTW reference route<",
        "stroke-dasharray=\"6 4\"",
    ] {
        assert!(svg.contains(needle), "missing {needle}");
    }
    assert!(
        !svg.contains(">stage destination<"),
        "an `S` marker is no stage destination"
    );
}
