//! The planners' own semantics on a small hand-built map (`two_rooms`: a bedroom, columns 0..=8,
//! and a kitchen, columns 10..=19, joined by one door cell at row 8, column 9).

use m2rc_baselines::common::grid::GridSearch;
use m2rc_baselines::common::prefix_ltl::parse_prefix;
use m2rc_baselines::lang2ltl::planner::{Labels, plan};
use m2rc_baselines::limp::planner as limp;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::fixture::two_rooms;

fn rect(r0: u32, r1: u32, c0: u32, c1: u32) -> Vec<Cell> {
    (r0..=r1)
        .flat_map(|r| (c0..=c1).map(move |c| Cell::new(r, c)))
        .collect()
}

/// `a`: a patch of the kitchen; `c`: the door and the cells beside it (every way to `a`).
fn labels() -> Labels {
    Labels::new(
        20,
        vec![
            ("a".into(), rect(17, 18, 17, 18), [17.5, 17.5]),
            ("c".into(), rect(7, 9, 8, 10), [8.0, 9.0]),
        ],
    )
}

#[test]
fn lang2ltl_progresses_by_the_target_cell_only() {
    let map = two_rooms();
    let mut s = GridSearch::new(&map);
    let start = Cell::new(18, 2);
    // "stay out of c until a": every way to a crosses c, but only the target cell's labels
    // advance the formula, so the AP-MDP accepts a route through c.
    let (route, trace) = plan(
        &mut s,
        start,
        &parse_prefix("U ! c a").unwrap(),
        &labels(),
        5000,
    )
    .unwrap();
    assert_eq!(trace.mode, "ap-mdp");
    assert!(trace.accepted);
    assert!(
        route.contains(&Cell::new(8, 9)),
        "the route crosses the door"
    );
    assert!(rect(17, 18, 17, 18).contains(route.last().unwrap()));
    for w in route.windows(2) {
        assert!(w[0].dist(w[1]) < 1.5, "a drivable route");
    }
}

#[test]
fn lang2ltl_masks_global_avoids_and_falls_back_to_the_sequential_planner() {
    let map = two_rooms();
    let mut s = GridSearch::new(&map);
    let start = Cell::new(18, 2);
    // G !c masks the only door: no accepting AP-state, so `fast` goes there without masks.
    let f = parse_prefix("& F a G ! c").unwrap();
    let (route, trace) = plan(&mut s, start, &f, &labels(), 5000).unwrap();
    assert_eq!(trace.mode, "fast");
    assert_eq!(
        trace.fallback_reason.as_deref(),
        Some("no accepting AP-state is reachable")
    );
    assert!(route.contains(&Cell::new(8, 9)));
    // With an expansion limit of 0 the AP-MDP gives up at once.
    let (_, trace) = plan(&mut s, start, &parse_prefix("F a").unwrap(), &labels(), 0).unwrap();
    assert_eq!(trace.mode, "fast");
    assert!(trace.fallback_reason.unwrap().contains("limit of 0"));
}

#[test]
fn limp_forbids_cells_that_falsify_the_residual() {
    let map = two_rooms();
    let mut s = GridSearch::new(&map);
    let start = Cell::new(18, 2);
    let n = 20;
    let mask = |cells: Vec<Cell>| {
        let mut m = vec![false; n * n];
        for c in cells {
            m[c.row as usize * n + c.col as usize] = true;
        }
        m
    };
    let regions = vec![
        ("a".to_string(), mask(rect(17, 18, 17, 18))),
        ("c".to_string(), mask(rect(7, 9, 8, 10))),
    ];
    // Unlike Lang2LTL, LIMP sees every cell's valuation: G !c forbids the door, no path.
    let f = m2rc_compiler::ltl::parse("F a & G !c").unwrap();
    let e = limp::plan(&mut s, start, &f, &regions).unwrap_err();
    assert_eq!(e.status, "no_path");
    let f = m2rc_compiler::ltl::parse("F (c & F a)").unwrap();
    let (route, stages) = limp::plan(&mut s, start, &f, &regions).unwrap();
    assert_eq!(stages.len(), 2, "{stages:#?}");
    assert!(rect(17, 18, 17, 18).contains(route.last().unwrap()));
}
