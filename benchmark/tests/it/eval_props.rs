//! Properties of the evaluator on arbitrary maps, episodes and routes: it never panics, scores
//! stay in range, and route parsing rejects rather than crashes.

use m2rc_benchmark::episode::{
    ConstraintKind, Episode, HardConstraint, ReferenceRegion, Scope, Shape, SoftConstraint,
};
use m2rc_benchmark::metrics::{EvalMap, EvalOptions, evaluate, evaluate_or_worst_case};
use m2rc_benchmark::route::parse_route;
use proptest::prelude::*;
use serde_json::json;

fn shape_strategy() -> impl Strategy<Value = Shape> {
    prop_oneof![
        Just(Shape::Circle),
        Just(Shape::Rectangle),
        Just(Shape::Freeform)
    ]
}

#[derive(Clone, Debug)]
struct RegionParts {
    shape: Shape,
    center: [f64; 2],
    size: [f64; 2],
    cells: Vec<[i64; 2]>,
}

fn region_strategy(n: i64) -> impl Strategy<Value = RegionParts> {
    (
        shape_strategy(),
        (-1.0..(n as f64 + 1.0), -1.0..(n as f64 + 1.0)),
        (0.0f64..4.0, 0.0f64..4.0),
        prop::collection::vec((-1..=n, -1..=n), 0..5),
    )
        .prop_map(|(shape, (r, c), (a, b), cells)| RegionParts {
            shape,
            center: [r, c],
            size: [a, b],
            cells: cells.into_iter().map(|(r, c)| [r, c]).collect(),
        })
}

fn scope_strategy() -> impl Strategy<Value = Option<Scope>> {
    prop_oneof![
        Just(None),
        Just(Some(Scope::global())),
        (0i64..5, 0i64..6).prop_map(|(a, b)| Some(Scope::between(a, b))),
        Just(Some(Scope {
            kind: Some("between_hard_constraints".into()),
            ..Scope::default()
        })),
    ]
}

fn hard(
    kind: ConstraintKind,
    r: RegionParts,
    order: Option<i64>,
    scope: Option<Scope>,
) -> HardConstraint {
    let mut c = HardConstraint::freeform("c", kind, r.cells);
    c.shape = r.shape;
    c.center = Some(r.center);
    c.radius = Some(r.size[0]);
    c.width = Some(r.size[0]);
    c.height = Some(r.size[1]);
    c.order = order;
    c.scope = scope;
    c
}

const TYPES: [&str; 7] = [
    "near_preference",
    "far_preference",
    "relative_preference",
    "path_shape_preference",
    "geometric_path_preference",
    "clearance",
    "move_smoothness",
];

fn soft(t: usize, r: RegionParts, scope: Option<Scope>, refs: Vec<[i64; 2]>) -> SoftConstraint {
    let region = ReferenceRegion {
        cells: Some(refs.clone()),
        ..ReferenceRegion::default()
    };
    SoftConstraint {
        constraint_id: Some(format!("s{t}")),
        preference_type: Some(TYPES[t].to_string()),
        shape: Some(r.shape),
        center: Some(r.center),
        radius: Some(r.size[0]),
        width: Some(r.size[0]),
        height: Some(r.size[1]),
        reference_region: Some(region.clone()),
        reference_regions: Some(vec![
            region,
            ReferenceRegion {
                cells: Some(r.cells.clone()),
                ..ReferenceRegion::default()
            },
        ]),
        reference_trajectory: Some(refs),
        scope,
        cells: Some(r.cells),
        ..SoftConstraint::default()
    }
}

#[derive(Debug)]
struct Case {
    map: EvalMap,
    episode: Episode,
    route: Vec<[i64; 2]>,
}

fn case_strategy() -> impl Strategy<Value = Case> {
    (3i64..9).prop_flat_map(|n| {
        let cells = (n * n) as usize;
        (
            prop::collection::vec(prop::bool::weighted(0.2), cells),
            prop::collection::vec((region_strategy(n), prop::option::of(0i64..6)), 0..5),
            prop::collection::vec((region_strategy(n), scope_strategy()), 0..3),
            prop::collection::vec(
                (0usize..TYPES.len(), region_strategy(n), scope_strategy(), prop::collection::vec((0..n, 0..n), 0..3)),
                0..4,
            ),
            prop::collection::vec((0..n, 0..n), 0..12),
        )
            .prop_map(move |(blocked, passes, avoids, softs, route)| {
                let occupancy: Vec<Vec<i64>> =
                    (0..n).map(|r| (0..n).map(|c| i64::from(blocked[(r * n + c) as usize])).collect()).collect();
                let map = EvalMap::from_json(&json!({
                    "grid_size": n,
                    "layers": {"occupancy": occupancy, "object_instance": vec![vec![0; n as usize]; n as usize]}
                }))
                .unwrap();
                let mut hard_list: Vec<HardConstraint> =
                    passes.into_iter().map(|(r, o)| hard(ConstraintKind::MustPass, r, o, None)).collect();
                hard_list.extend(avoids.into_iter().map(|(r, s)| hard(ConstraintKind::MustAvoid, r, None, s)));
                let soft_list = softs
                    .into_iter()
                    .map(|(t, r, s, refs)| soft(t, r, s, refs.into_iter().map(|(a, b)| [a, b]).collect()))
                    .collect();
                let episode = Episode { hard_constraints: hard_list, soft_constraints: soft_list, ..Episode::default() };
                Case { map, episode, route: route.into_iter().map(|(a, b)| [a, b]).collect() }
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn evaluation_never_panics_and_scores_stay_in_range(case in case_strategy()) {
        for dedup in [false, true] {
            let opts = EvalOptions { dedup_region_waypoints: dedup };
            if let Ok(m) = evaluate(&case.route, &case.episode, &case.map, &opts) {
                prop_assert!((0.0..=1.0).contains(&m.hcs), "HCS {}", m.hcs);
                prop_assert!((0.0..=1.0).contains(&m.segment_wise_spl), "SPL {}", m.segment_wise_spl);
                prop_assert!(m.pl >= 0.0);
                for s in &m.details.segments {
                    prop_assert!((0.0..=1.0).contains(&s.spl));
                    prop_assert_eq!(s.s == 1, s.status == "completed");
                }
                prop_assert_eq!(m.details.soft_constraints.len(), case.episode.soft_constraints.len());
            }
            let w = evaluate_or_worst_case(&case.route, &case.episode, &case.map, &opts);
            prop_assert!((0.0..=1.0).contains(&w.hcs));
            // The written episode reads back as the same episode.
            let text = case.episode.to_json_pretty();
            let back = Episode::from_json_str(&text, "x").unwrap();
            prop_assert_eq!(&back, &case.episode);
        }
    }

    #[test]
    fn route_parsing_never_panics(v in arb_json()) {
        let _ = parse_route(&v, 5, "route.json");
    }
}

fn arb_json() -> impl Strategy<Value = serde_json::Value> {
    let leaf = prop_oneof![
        Just(serde_json::Value::Null),
        any::<bool>().prop_map(serde_json::Value::from),
        any::<i64>().prop_map(serde_json::Value::from),
        (-10.0f64..10.0).prop_map(serde_json::Value::from),
        "[a-z]{0,3}".prop_map(serde_json::Value::from),
    ];
    leaf.prop_recursive(3, 24, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(serde_json::Value::Array),
            prop::collection::vec(
                (
                    prop_oneof![
                        Just("trajectory".to_string()),
                        Just("predicted_trajectory".to_string()),
                        "[a-z]{1,3}"
                    ],
                    inner
                ),
                0..3
            )
            .prop_map(|kv| serde_json::Value::Object(kv.into_iter().collect())),
        ]
    })
}
