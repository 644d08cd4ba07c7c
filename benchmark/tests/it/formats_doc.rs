//! `docs/formats.md` lists the `preference_type` names a user may write; this keeps the list the
//! one the episode check and the evaluator accept.

use m2rc_benchmark::episode::{Episode, PREFERENCE_TYPE_NAMES};
use m2rc_benchmark::episode_check::check_episode;
use m2rc_benchmark::metrics::{EvalMap, EvalOptions, evaluate};
use serde_json::json;

/// The first backticked word of each table row (below the header) between the line starting
/// with `begin` and the line starting with `end`.
pub fn documented(doc: &str, begin: &str, end: &str) -> Vec<String> {
    let start = doc
        .find(begin)
        .unwrap_or_else(|| panic!("no `{begin}` in the doc"));
    let stop = doc[start..]
        .find(end)
        .unwrap_or_else(|| panic!("no `{end}` in the doc"));
    doc[start..start + stop]
        .lines()
        .skip_while(|l| !l.starts_with("|---"))
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .map(str::to_string)
        .collect()
}

fn formats_doc() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/formats.md");
    std::fs::read_to_string(path).unwrap()
}

/// An episode with one soft constraint of type `t` (start (0,0), goal (0,2) on a free 3x3 map).
fn episode_with(t: &str) -> Episode {
    let pass = |id: &str, c: i64, o: i64| json!({"constraint_id": id, "kind": "must_pass", "shape": "freeform", "order": o, "cells": [[0, c]]});
    Episode::from_value(
        json!({"hard_constraints": [pass("start", 0, 1), pass("goal", 2, 2)],
               "soft_constraints": [{"constraint_id": "s", "preference_type": t,
                   "shape": "freeform", "cells": [[0, 1]],
                   "reference_region": {"cells": [[2, 2]]},
                   "reference_regions": [{"object_id": 1, "cells": [[2, 0]]}, {"object_id": 2, "cells": [[2, 2]]}],
                   "object_ids": [1, 2], "reference_trajectory": [[0, 0], [0, 1], [0, 2]]}]}),
        "ep.json",
    )
    .unwrap()
}

#[test]
fn the_documented_preference_types_are_exactly_the_ones_the_evaluator_accepts() {
    let doc = formats_doc();
    let names = documented(
        &doc,
        "<!-- preference types",
        "<!-- end of preference types",
    );
    let code: Vec<&str> = PREFERENCE_TYPE_NAMES.iter().map(|(n, _)| *n).collect();
    assert_eq!(names, code, "docs/formats.md lists other preference types");
    assert!(names.iter().any(|n| n == "geometric_path_preference"));
    let map = EvalMap::from_json(&json!({"grid_size": 3, "layers": {
        "occupancy": [[0, 0, 0], [0, 0, 0], [0, 0, 1]],
        "object_instance": [[0, 0, 0], [0, 0, 0], [0, 0, 0]]}}))
    .unwrap();
    for name in &names {
        let ep = episode_with(name);
        check_episode(&ep, Some(3), "ep.json").unwrap();
        let m = evaluate(
            &[[0, 0], [0, 1], [0, 2]],
            &ep,
            &map,
            &EvalOptions::default(),
        )
        .unwrap();
        let d = &m.details.soft_constraints[0];
        assert_eq!(d.status, "computed", "{name}: {d:?}");
        assert!(d.raw_value.is_some_and(f64::is_finite), "{name}: {d:?}");
    }
    // A name not in the list is refused, naming the list.
    let err = check_episode(&episode_with("nearish_preference"), Some(3), "ep.json")
        .unwrap_err()
        .to_string();
    assert!(err.contains(&code.join(", ")), "{err}");
}
