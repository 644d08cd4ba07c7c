//! Fault injection on episodes and maps: an episode scored or compiled on another map, the start
//! of `compile --episode`, gold programs compiled from their suite, bad episode files, every map
//! kind for `eval`, room names and labels, 0-based house indices.

use crate::common;
use common::*;
use serde_json::json;
use std::path::PathBuf;

fn first() -> (String, String, PathBuf, PathBuf, PathBuf) {
    let (m, i, ep, prog) = episodes(suite(3)).remove(0);
    let map = suite(3).join("maps").join(&m).join(format!("{m}.json"));
    (m, i, ep, prog, map)
}

fn eval(map: &str, ep: &str, route: &str, cwd: &std::path::Path) -> Run {
    m2rc(
        &[
            "eval",
            "--map",
            map,
            "--episode",
            ep,
            "--route",
            route,
            "--format",
            "json",
        ],
        cwd,
    )
}

#[test]
fn a_gold_program_compiles_as_written_from_its_suite_and_scores_hcs_1() {
    let (_, _, ep, prog, map) = first();
    let tmp = tempfile::tempdir().unwrap();
    let route = tmp.path().join("route.json");
    let rel = prog
        .strip_prefix(suite(3))
        .unwrap()
        .to_str()
        .unwrap()
        .to_string();
    let r = m2rc(&["compile", &rel, "-o", route.to_str().unwrap()], suite(3)).expect(0);
    assert!(
        r.stderr.contains("planning from the start of the episode"),
        "{}",
        r.stderr
    );
    let episode = read_json(&ep);
    let start = &episode["start_pose"];
    let traj = read_json(&route)["trajectory"].clone();
    assert_eq!(
        traj[0],
        json!([start["row"], start["col"]]),
        "route starts at the episode's start"
    );
    let r = eval(
        map.to_str().unwrap(),
        ep.to_str().unwrap(),
        route.to_str().unwrap(),
        tmp.path(),
    )
    .expect(0);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(v["HCS"], 1.0, "{v}");
    // Room names in the summary are the map's (`bedroom_2`), never "bedroom 5".
    let r = m2rc(&["compile", &rel], suite(3)).expect(0);
    let re_like = ["bathroom ", "bedroom ", "kitchen ", "living_room "];
    for line in r.stdout.lines() {
        for w in re_like {
            if let Some(pos) = line.find(w) {
                let next = line[pos + w.len()..].chars().next();
                assert!(
                    !next.is_some_and(|c| c.is_ascii_digit()),
                    "room id instead of name: {line}"
                );
            }
        }
        assert!(
            !line.contains("-0.00 m") && !line.contains("followwall"),
            "{line}"
        );
    }
}

#[test]
fn compile_with_episode_takes_its_start_and_its_map() {
    let (_, _, ep, prog, _) = first();
    let tmp = tempfile::tempdir().unwrap();
    let program = std::fs::read_to_string(&prog).unwrap();
    // The program alone, outside the suite, with the episode given: map and start from the episode.
    std::fs::write(tmp.path().join("p.m2r"), &program).unwrap();
    let route = tmp.path().join("r.json");
    m2rc(
        &[
            "compile",
            "p.m2r",
            "--episode",
            ep.to_str().unwrap(),
            "-o",
            "r.json",
        ],
        tmp.path(),
    )
    .expect(0);
    let start = read_json(&ep)["start_pose"].clone();
    assert_eq!(
        read_json(&route)["trajectory"][0],
        json!([start["row"], start["col"]])
    );
}

#[test]
fn an_episode_on_another_map_is_refused_by_eval_and_compile() {
    let (_, _, ep, prog, map) = first();
    let tmp = tempfile::tempdir().unwrap();
    let mut other = read_json(&ep);
    other["map_id"] = json!("procthor/002_valunseen");
    let other_path = tmp.path().join("other.json");
    write_json(&other_path, &other);
    let route = tmp.path().join("r.json");
    std::fs::write(
        &route,
        serde_json::to_vec(&json!([[
            other["start_pose"]["row"],
            other["start_pose"]["col"]
        ]]))
        .unwrap(),
    )
    .unwrap();
    let r = eval(
        map.to_str().unwrap(),
        other_path.to_str().unwrap(),
        route.to_str().unwrap(),
        tmp.path(),
    )
    .expect(1);
    assert!(
        r.stderr
            .contains("is an episode of map `procthor/002_valunseen`"),
        "{}",
        r.stderr
    );
    let r = m2rc(
        &[
            "compile",
            prog.to_str().unwrap(),
            "--map",
            map.to_str().unwrap(),
            "--episode",
            other_path.to_str().unwrap(),
        ],
        tmp.path(),
    )
    .expect(1);
    assert!(r.stderr.contains("is an episode of map"), "{}", r.stderr);
    // --any-map scores anyway.
    m2rc(
        &[
            "eval",
            "--map",
            map.to_str().unwrap(),
            "--episode",
            other_path.to_str().unwrap(),
            "--route",
            route.to_str().unwrap(),
            "--any-map",
        ],
        tmp.path(),
    )
    .expect(0);
}

#[test]
fn bad_episode_files_get_clear_errors_and_integral_floats_are_accepted() {
    let (_, _, ep, _, map) = first();
    let tmp = tempfile::tempdir().unwrap();
    let base = read_json(&ep);
    let start = json!([base["start_pose"]["row"], base["start_pose"]["col"]]);
    let route = tmp.path().join("r.json");
    write_json(&route, &json!([start]));
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|v| v["hard_constraints"][0]["cells"] = json!([[100000, 3]])),
            "outside the",
        ),
        (
            Box::new(|v| v["hard_constraints"][0]["cells"] = json!([[-4, 3]])),
            "is negative",
        ),
        (
            Box::new(|v| v["hard_constraints"][1]["order"] = json!(-2)),
            "order -2",
        ),
        (
            Box::new(|v| v["soft_constraints"][0]["preference_type"] = json!("nearby_preference")),
            "unknown preference type `nearby_preference`",
        ),
    ];
    for (edit, message) in cases {
        let mut v = base.clone();
        edit(&mut v);
        let p = tmp.path().join("bad.json");
        write_json(&p, &v);
        // The reference evaluator scores these files, so `eval` does, with a warning ...
        let r = eval(
            map.to_str().unwrap(),
            p.to_str().unwrap(),
            route.to_str().unwrap(),
            tmp.path(),
        )
        .expect(0);
        assert!(
            r.stderr.contains("warning: ")
                && r.stderr.contains(message)
                && r.stderr.contains("bad.json")
                && r.stderr.contains("--strict refuses it"),
            "{message}: {}",
            r.stderr
        );
        // ... and `--strict` refuses them, as planning does.
        let r = m2rc(
            &[
                "eval",
                "--map",
                map.to_str().unwrap(),
                "--episode",
                p.to_str().unwrap(),
                "--route",
                route.to_str().unwrap(),
                "--strict",
            ],
            tmp.path(),
        )
        .expect(2);
        assert!(
            r.stderr.contains(message) && r.stderr.contains("bad.json"),
            "{message}: {}",
            r.stderr
        );
    }
    // Cells written as 223.0 (as Python writers do) score exactly as integers.
    let text = serde_json::to_string(&base).unwrap();
    let floats = regex_like_floats(&text);
    let p = tmp.path().join("floats.json");
    std::fs::write(&p, &floats).unwrap();
    let a = eval(
        map.to_str().unwrap(),
        ep.to_str().unwrap(),
        route.to_str().unwrap(),
        tmp.path(),
    )
    .expect(0)
    .stdout;
    let b = eval(
        map.to_str().unwrap(),
        p.to_str().unwrap(),
        route.to_str().unwrap(),
        tmp.path(),
    )
    .expect(0)
    .stdout;
    assert_eq!(a, b);
}

/// Rewrites every `"cells":[[r,c],...]` integer pair as floats (`[r.0,c.0]`).
fn regex_like_floats(text: &str) -> String {
    let mut v: serde_json::Value = serde_json::from_str(text).unwrap();
    fn walk(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(o) => {
                for (k, x) in o.iter_mut() {
                    if k == "cells" {
                        if let Some(a) = x.as_array_mut() {
                            for c in a {
                                if let Some(p) = c.as_array_mut() {
                                    for n in p {
                                        *n = json!(n.as_f64().unwrap());
                                    }
                                }
                            }
                        }
                    } else {
                        walk(x);
                    }
                }
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(walk),
            _ => {}
        }
    }
    walk(&mut v);
    let s = serde_json::to_string(&v).unwrap();
    assert!(s.contains(".0]"), "no float cells written");
    s
}

#[test]
fn eval_takes_every_map_kind() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("p.m2r"),
        "// map: demo\nlet k = rooms(kitchen).only()\nroute { go k }\n",
    )
    .unwrap();
    m2rc(&["compile", "p.m2r", "-o", "r.json"], tmp.path()).expect(0);
    let traj = read_json(&tmp.path().join("r.json"))["trajectory"].clone();
    let (a, b) = (
        traj[0].clone(),
        traj[traj.as_array().unwrap().len() - 1].clone(),
    );
    let pass = |id: &str, c: &serde_json::Value, o: i64| json!({"constraint_id": id, "kind": "must_pass", "shape": "freeform", "order": o, "cells": [c]});
    write_json(
        &tmp.path().join("ep.json"),
        &json!({"hard_constraints": [pass("start", &a, 1), pass("goal", &b, 2)]}),
    );
    let r = eval("demo", "ep.json", "r.json", tmp.path()).expect(0);
    assert!(r.stdout.contains("\"HCS\":1.0"), "{}", r.stdout);
    m2rc(&["map", "import", "demo", "-o", "demo.json"], tmp.path()).expect(0);
    eval("demo.json", "ep.json", "r.json", tmp.path()).expect(0);
    let house = fixtures().join("procthor10k_uniform_hard_val_150_007.json");
    eval(house.to_str().unwrap(), "ep.json", "r.json", tmp.path())
        .code
        .unwrap();
}

#[test]
fn suite_manifests_name_houses_by_0_based_index() {
    let m = read_json(&suite(3).join("suite.json"));
    let house = m["scenes"][0]["house"].as_str().unwrap().to_string();
    assert!(!house.contains(".jsonl") || house.contains('#'), "{house}");
    // A directory of .json houses names files; a .jsonl would name `file#i`, usable as a map.
    let tmp = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(fixtures().join("procthor10k_uniform_hard_val_150_007.json"))
        .unwrap();
    let v: serde_json::Value = serde_json::from_str(&src).unwrap();
    let line = serde_json::to_string(&v).unwrap();
    std::fs::write(
        tmp.path().join("h.jsonl"),
        format!("{line}\n\n{line}\n{line}\n"),
    )
    .unwrap();
    let s = tmp.path().join("s");
    m2rc(
        &[
            "suite",
            "build",
            "--houses",
            "h.jsonl",
            "--scenes",
            "1",
            "--dev-scenes",
            "0",
            "--episodes-per-scene",
            "1",
            "--validate",
            "shortest",
            "--out",
            "s",
        ],
        tmp.path(),
    )
    .expect(0);
    let m = read_json(&s.join("suite.json"));
    let house = m["scenes"][0]["house"].as_str().unwrap();
    let index: usize = house.rsplit('#').next().unwrap().parse().unwrap();
    assert!(index <= 2, "{house}");
    m2rc(&["map", "info", house], tmp.path()).expect(0);
}

/// The reference evaluator's 5x5 fixture (obstacle at (0,0), resolution 1): record (0,0), goal
/// (0,2); a near preference whose region has a cell outside the grid, and a preference type the
/// reference does not know.
fn reference_fixture(dir: &std::path::Path) -> (PathBuf, PathBuf) {
    let mut occ = vec![vec![0; 5]; 5];
    occ[0][0] = 1;
    let map = dir.join("map5.json");
    write_json(
        &map,
        &json!({"grid_size": 5, "layers": {"occupancy": occ, "object_instance": vec![vec![0; 5]; 5]}}),
    );
    let pass = |id: &str, c: i64, o: i64| json!({"constraint_id": id, "kind": "must_pass", "shape": "freeform", "order": o, "cells": [[0, c]]});
    let ep = dir.join("instruction_000001.json");
    write_json(
        &ep,
        &json!({"hard_constraints": [pass("record", 0, 1), pass("goal", 2, 2)],
                "soft_constraints": [
                    {"constraint_id": "near", "preference_type": "near_preference", "shape": "freeform",
                     "cells": [[0, 1], [0, 2], [0, 9], [-1, 2]], "reference_region": {"cells": [[0, 0]]}},
                    {"constraint_id": "smooth", "preference_type": "move_smoothness", "shape": "freeform", "cells": []},
                    {"constraint_id": "__global_clearance__", "preference_type": "clearance"}]}),
    );
    (map, ep)
}

#[test]
fn eval_scores_what_the_reference_scores_out_of_grid_regions_and_unknown_preferences() {
    let tmp = tempfile::tempdir().unwrap();
    let (map, ep) = reference_fixture(tmp.path());
    let route = tmp.path().join("r.json");
    let score = |route_points: serde_json::Value, extra: &[&str]| {
        write_json(&route, &route_points);
        let mut args = vec![
            "eval",
            "--map",
            map.to_str().unwrap(),
            "--episode",
            ep.to_str().unwrap(),
            "--route",
            route.to_str().unwrap(),
            "--full",
        ];
        args.extend_from_slice(extra);
        m2rc(&args, tmp.path())
    };
    // A route that misses the near region (reference vector D.1.3 with two more cells): the
    // worst case is the farthest region cell inside the grid, (0,2), 2 cells from the object;
    // (0,9) (9 cells) and (-1,2) are left out, as the reference leaves them.
    let r = score(json!([[1, 1], [1, 2], [1, 3]]), &[]).expect(0);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    let soft = v["details"]["soft_constraints"].as_array().unwrap();
    assert_eq!(soft[0]["status"], "empty_region_max_distance", "{v}");
    assert_eq!(soft[0]["raw_value"], 2.0, "{v}");
    // The unknown type: reported unsupported, no value; the rest is scored.
    assert_eq!(soft[1]["status"], "unsupported_preference", "{v}");
    assert!(soft[1]["raw_value"].is_null(), "{v}");
    assert_eq!(soft[2]["status"], "computed", "{v}");
    for needle in [
        "soft_constraints[0].cells[2]",
        "soft_constraints[0].cells[3]",
        "unknown preference type `move_smoothness`",
        "unsupported_preference",
    ] {
        assert!(r.stderr.contains(needle), "{needle}: {}", r.stderr);
    }
    // A route through the region is measured on its waypoints there: (0,2), 2 cells away.
    let r = score(json!([[1, 1], [1, 2], [0, 2]]), &[]).expect(0);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(v["HCS"], 1.0, "{v}");
    assert_eq!(v["details"]["soft_constraints"][0]["status"], "computed");
    assert_eq!(v["details"]["soft_constraints"][0]["raw_value"], 2.0);
    // --strict refuses the file, naming the first field.
    let r = score(json!([[1, 1], [0, 2]]), &["--strict"]).expect(2);
    assert!(
        r.stderr.contains("soft_constraints[0].cells[2]") && r.stderr.contains("outside the 5x5"),
        "{}",
        r.stderr
    );
}
