//! Every program in `examples/` compiles on the map its first line names, and its route has the
//! properties a route must have: it starts at the start, every step is an 8-neighbour move onto a
//! free cell without cutting a corner, it reaches the destinations in order (passing the must-pass
//! places of each stage on the way), and it never enters an avoid region while that is active.
//! Together the examples cover every constraint kind and every kind of scope.

use m2rc_benchmark::pipeline::{CompiledRoute, PipelineOptions, compile_and_plan, stage_ends};
use m2rc_compiler::ir::{ConstraintKind, Place, PlaceKind, StageScope};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn examples() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(repo().join("examples"))
        .expect("examples/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "m2r"))
        .collect();
    v.sort();
    v
}

/// The map named on the program's first line (`// map: demo` or a path from the repo root).
fn map_of(source: &str) -> Option<SemanticMap> {
    let first = source.lines().next()?;
    let arg = first
        .trim()
        .strip_prefix("//")?
        .trim()
        .strip_prefix("map:")?
        .trim();
    let arg = if arg == "demo" {
        arg.to_string()
    } else {
        repo().join(arg).to_string_lossy().into_owned()
    };
    Some(m2rc_stdlib::load::load_map(&arg).unwrap_or_else(|e| panic!("map {arg}: {e}")))
}

/// Distance in metres from a cell to the nearest cell of a place.
fn dist_to(place: &Place, c: Cell, res: f64) -> f64 {
    place
        .cells
        .cells()
        .iter()
        .map(|x| x.dist(c))
        .fold(f64::INFINITY, f64::min)
        * res
}

fn check_route(name: &str, map: &SemanticMap, c: &CompiledRoute) {
    let t = &c.route.trajectory;
    let res = map.resolution();
    assert_eq!(
        t.first(),
        Some(&c.ir.start),
        "{name}: the route starts at the start"
    );
    assert!(map.is_free(t[0]), "{name}: the start is free");
    for w in t.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dr, dc) = (a.row.abs_diff(b.row), a.col.abs_diff(b.col));
        assert!(
            dr <= 1 && dc <= 1 && (dr, dc) != (0, 0),
            "{name}: step {a:?} -> {b:?} is not an 8-neighbour move"
        );
        assert!(map.is_free(b), "{name}: {b:?} is not free");
        if dr == 1 && dc == 1 {
            assert!(
                map.is_free(Cell::new(a.row, b.col)) && map.is_free(Cell::new(b.row, a.col)),
                "{name}: diagonal {a:?} -> {b:?} cuts a corner"
            );
        }
    }
    let ends = stage_ends(&c.route);
    assert_eq!(
        ends.len(),
        c.ir.stages.len(),
        "{name}: one planned segment per stage"
    );
    assert_eq!(
        ends.last().copied(),
        Some(t.len() - 1),
        "{name}: the last stage ends the route"
    );
    let mut from = 0;
    for (i, stage) in c.ir.stages.iter().enumerate() {
        let end = ends[i];
        assert!(
            end >= from && end < t.len(),
            "{name}: stage ends are in order"
        );
        // The destination is reached at the end of its stage: on its cells (room, region) or in the
        // approach band of an object (or the planner's fallback next to it).
        let d = dist_to(&stage.target, t[end], res);
        let object = |k: &PlaceKind| matches!(k, PlaceKind::Object { .. });
        let limit = if object(&stage.target.kind)
            || matches!(&stage.target.kind, PlaceKind::AnyOf { members } if members.iter().any(|m| object(&m.kind)))
        {
            1.0
        } else {
            0.3
        };
        assert!(
            d <= limit,
            "{name}: stage {} ends {d:.2} m from {}",
            i + 1,
            stage.target.label
        );
        // Must-pass places are passed, in order, within the stage.
        let mut k = from;
        for p in &stage.passes {
            let hit = (k..=end).find(|&j| dist_to(&p.place, t[j], res) <= 0.3);
            let Some(j) = hit else {
                panic!("{name}: stage {} never passes {}", i + 1, p.place.label)
            };
            k = j;
        }
        // A `through` chain is passed in the order written, within the stage.
        for con in c.ir.active(i) {
            if let ConstraintKind::PathShape {
                shape: m2rc_compiler::ir::Shape::Through,
                waypoints,
                ..
            } = &con.kind
            {
                let mut k = from;
                for w in waypoints {
                    let hit = (k..=end).find(|&j| w.cells.contains(t[j]));
                    let Some(j) = hit else {
                        panic!("{name}: stage {} never passes {} in order", i + 1, w.label)
                    };
                    k = j;
                }
            }
        }
        // No cell entered during the stage lies in an active avoid region (inside its scope).
        for &cell in &t[(from + 1).max(1)..=end] {
            for con in c.ir.active(i) {
                if let ConstraintKind::Avoid { place } = &con.kind {
                    let inside = place.cells.contains(cell)
                        && con
                            .spatial_scope
                            .as_ref()
                            .is_none_or(|s| s.cells.contains(cell));
                    assert!(
                        !inside,
                        "{name}: stage {} enters {} at {:?}",
                        i + 1,
                        place.label,
                        cell
                    );
                }
            }
        }
        from = end;
    }
}

/// What an IR exercises, for the coverage check.
fn features(c: &CompiledRoute) -> BTreeSet<&'static str> {
    let mut f = BTreeSet::new();
    if c.ir.stages.iter().any(|s| !s.passes.is_empty()) {
        f.insert("pass");
    }
    if !c.ir.route_bindings.is_empty() {
        f.insert("route-dependent");
    }
    for con in &c.ir.constraints {
        f.insert(match &con.kind {
            ConstraintKind::Avoid { .. } => "avoid",
            ConstraintKind::Near { .. } => "near",
            ConstraintKind::Far { .. } => "far",
            ConstraintKind::Relative { .. } => "relative",
            ConstraintKind::PathShape { shape, .. } => match shape {
                m2rc_compiler::ir::Shape::Circle => "circle",
                m2rc_compiler::ir::Shape::FollowWall => "follow_wall",
                m2rc_compiler::ir::Shape::Patrol => "patrol",
                m2rc_compiler::ir::Shape::Through => "through",
            },
            ConstraintKind::Clearance { .. } => "clearance",
        });
        f.insert(match &con.stage_scope {
            StageScope::Global => "scope:global",
            StageScope::Stages(s) if s.len() > 1 => "scope:during",
            StageScope::Stages(_) => "scope:stage",
        });
        if con.spatial_scope.is_some() {
            f.insert("scope:within");
        }
    }
    f
}

#[test]
fn every_example_compiles_to_a_sound_route() {
    let files = examples();
    assert!(
        files.len() >= 10,
        "at least ten examples, found {}",
        files.len()
    );
    let mut covered = BTreeSet::new();
    let mut maps = BTreeSet::new();
    for path in files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let source = std::fs::read_to_string(&path).unwrap();
        let map =
            map_of(&source).unwrap_or_else(|| panic!("{name}: first line must be `// map: ...`"));
        maps.insert(map.map_id.clone());
        let compiled =
            compile_and_plan(&source, &map, &PipelineOptions::default()).unwrap_or_else(|d| {
                panic!(
                    "{name} does not compile:\n{}",
                    m2rc_compiler::diagnostic::render_text(&d, &name, &source)
                )
            });
        check_route(&name, &map, &compiled);
        covered.extend(features(&compiled));
    }
    for f in [
        "pass",
        "avoid",
        "near",
        "far",
        "relative",
        "circle",
        "follow_wall",
        "patrol",
        "through",
        "clearance",
        "scope:global",
        "scope:stage",
        "scope:during",
        "scope:within",
        "route-dependent",
    ] {
        assert!(
            covered.contains(f),
            "no example exercises {f}; covered: {covered:?}"
        );
    }
    assert!(
        maps.len() >= 3,
        "examples run on the demo and on fixture houses: {maps:?}"
    );
}

#[test]
fn programs_that_fail_on_a_map_report_every_error_with_candidates() {
    let map = m2rc_stdlib::load::load_map("demo").unwrap();
    // Type-correct, but the demo house has three beds and no route into a wall.
    let src = "let bed = objects(bed).only()\nlet lamp = objects(desk_lamp).in(rooms(kitchen).only()).only()\nroute { go bed }";
    let diags = compile_and_plan(src, &map, &PipelineOptions::default()).expect_err("must fail");
    let errors: Vec<_> = diags.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 2, "{diags:#?}");
    let amb = errors
        .iter()
        .find(|d| d.code.id() == "E0502")
        .expect("ambiguous bed");
    assert_eq!(&src[amb.span.start..amb.span.end], "objects(bed).only()");
    assert_eq!(
        amb.notes.iter().filter(|n| n.contains("`bed`")).count(),
        3,
        "{:?}",
        amb.notes
    );
    assert!(errors.iter().any(|d| d.code.id() == "E0501"));
}

/// `go S` through the whole pipeline: the stage's goal is every chair, the route ends by one of
/// them, and the binding the compile output shows names that chair, read off the planned route.
#[test]
fn a_set_destination_is_bound_to_the_member_the_route_reached() {
    let map = m2rc_stdlib::load::load_map("demo").unwrap();
    let src = "route { go objects(chair) }";
    let c = compile_and_plan(src, &map, &PipelineOptions::default()).expect("plans");
    let PlaceKind::AnyOf { members } = &c.ir.stages[0].target.kind else {
        panic!("not a set goal: {:?}", c.ir.stages[0].target.kind);
    };
    assert!(members.len() >= 2, "the demo has several chairs");
    let b = &c.ir.route_bindings[0];
    assert_eq!(b.function, "go");
    assert_eq!(b.against, m2rc_compiler::ir::BoundAgainst::Planned);
    let end = *c.route.trajectory.last().unwrap();
    let res = map.resolution();
    let reached = members
        .iter()
        .find(|m| m.label == b.resolved)
        .expect("the binding names a member");
    // Within the approach band (0.3 m, or the planner's fallback next to it), as for any object.
    assert!(dist_to(reached, end, res) <= 1.0, "{}", b.resolved);
    for m in members.iter().filter(|m| m.label != b.resolved) {
        assert!(
            dist_to(m, end, res) >= dist_to(reached, end, res),
            "{}",
            m.label
        );
    }
    check_route("go objects(chair)", &map, &c);
}
