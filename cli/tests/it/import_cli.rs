//! `bench import` (another program's routes into a run directory) and route validity wherever a
//! route is scored: `eval`'s warning and `route_valid`, the records, and `bench report`'s
//! refusal to rank routes that are not drivable.

use crate::common;
use common::*;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// A complete `shortest` run on the shared suite, made once per test binary; tests read it.
fn shortest_run() -> &'static Path {
    static RUN: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    RUN.get_or_init(|| {
        let dir: &'static tempfile::TempDir = Box::leak(Box::new(tempfile::tempdir().unwrap()));
        let out = dir.path().join("shortest");
        bench_run(suite(3), "shortest", &out, &[]).expect(0);
        out
    })
}

/// The shortest run's route of every episode, by (map_id, instruction_id).
fn routes() -> Vec<(String, String, Value)> {
    episodes(suite(3))
        .into_iter()
        .map(|(m, i, _, _)| {
            let r = read_json(&record(shortest_run(), &m, &i));
            (m, i, r["trajectory"].clone())
        })
        .collect()
}

fn import(preds: &Path, method: &str, out: &Path) -> Run {
    m2rc(
        &[
            "bench",
            "import",
            "--suite",
            suite(3).to_str().unwrap(),
            "--predictions",
            preds.to_str().unwrap(),
            "--method",
            method,
            "--out",
            out.to_str().unwrap(),
        ],
        preds.parent().unwrap(),
    )
}

fn report(dirs: &[&Path], extra: &[&str], cwd: &Path) -> Run {
    let mut args: Vec<String> = vec!["bench".into(), "report".into()];
    args.extend(dirs.iter().map(|d| d.display().to_string()));
    args.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    m2rc(&refs, cwd)
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

#[test]
fn good_predictions_in_either_form_score_exactly_as_the_method_that_wrote_them() {
    let tmp = tempfile::tempdir().unwrap();
    let preds = tmp.path().join("preds");
    for (k, (m, i, traj)) in routes().into_iter().enumerate() {
        if k == 0 {
            // The reference's method output, under any name.
            let v = json!({"method": "elsewhere", "map_id": format!("procthor/{m}"),
                           "instruction_id": i, "trajectory": traj});
            write(&preds.join("any_name.json"), &v.to_string());
        } else {
            write(&preds.join(&m).join(format!("{i}.json")), &traj.to_string());
        }
    }
    write(&preds.join("README.txt"), "not a prediction");
    let out = tmp.path().join("runs/mine");
    let r = import(&preds, "mine", &out).expect(0);
    assert!(
        r.stdout.contains(
            "3 scored from their prediction, 0 without a prediction, 0 with a malformed one"
        ) && r.stdout.contains("0 with a route that is not drivable"),
        "{}",
        r.stdout
    );
    assert!(r.stderr.contains("1 file(s)"), "{}", r.stderr);
    for (m, i, traj) in routes() {
        let rec = read_json(&record(&out, &m, &i));
        assert_eq!(rec["method"], "mine");
        assert_eq!(rec["status"], "ok");
        assert_eq!(rec["trajectory"], traj);
        assert_eq!(rec["route_validity"]["valid"], true);
        let theirs = read_json(&record(shortest_run(), &m, &i));
        assert_eq!(rec["metrics"], theirs["metrics"], "{m}/{i}");
    }
    // Reported beside m2rc's own run, with the same numbers.
    let r = report(&[shortest_run(), &out], &["--format", "json"], tmp.path()).expect(0);
    let v: Value = serde_json::from_str(&r.stdout).unwrap();
    let (a, b) = (&v["methods"][0], &v["methods"][1]);
    assert_eq!(
        (a["method"].as_str(), b["method"].as_str()),
        (Some("shortest"), Some("mine"))
    );
    for block in ["easy", "hard", "overall"] {
        assert_eq!(a[block], b[block], "{block}");
    }
    // Importing again changes nothing; a changed prediction is not mixed into the old import.
    let before = std::fs::read(record(&out, &routes()[1].0, &routes()[1].1)).unwrap();
    let r = import(&preds, "mine", &out).expect(0);
    assert!(
        r.stdout.contains("0 written, 3 already done"),
        "{}",
        r.stdout
    );
    assert_eq!(
        std::fs::read(record(&out, &routes()[1].0, &routes()[1].1)).unwrap(),
        before
    );
    let (m, i, traj) = &routes()[1];
    let mut shorter = traj.as_array().unwrap().clone();
    shorter.pop();
    write(
        &preds.join(m).join(format!("{i}.json")),
        &Value::Array(shorter).to_string(),
    );
    let r = import(&preds, "mine", &out).expect(1);
    assert!(
        r.stderr.contains("method configuration differs"),
        "{}",
        r.stderr
    );
}

#[test]
fn missing_and_malformed_predictions_are_scored_on_the_start_cell_and_say_why() {
    let tmp = tempfile::tempdir().unwrap();
    let preds = tmp.path().join("preds");
    let rs = routes();
    let (m0, i0, t0) = &rs[0];
    write(&preds.join(m0).join(format!("{i0}.json")), &t0.to_string());
    let (m1, i1, _) = &rs[1];
    write(&preds.join(m1).join(format!("{i1}.json")), "[[1, 2], [1,");
    // rs[2] has no prediction.
    let out = tmp.path().join("mine");
    let r = import(&preds, "mine", &out).expect(0);
    assert!(
        r.stdout.contains(
            "1 scored from their prediction, 1 without a prediction, 1 with a malformed one"
        ),
        "{}",
        r.stdout
    );
    assert!(
        r.stderr.contains(&format!(
            "no prediction, scored on the start cell: {}/{}",
            rs[2].0, rs[2].1
        )) && r.stderr.contains("not valid JSON"),
        "{}",
        r.stderr
    );
    let bad = read_json(&record(&out, m1, i1));
    assert_eq!(bad["status"], "malformed_prediction");
    assert!(
        bad["prediction"]["problem"]
            .as_str()
            .unwrap()
            .contains("not valid JSON"),
        "{bad}"
    );
    let missing = read_json(&record(&out, &rs[2].0, &rs[2].1));
    assert_eq!(missing["status"], "missing_prediction");
    assert_eq!(missing["prediction"]["file"], Value::Null);
    for (rec, k) in [(&bad, 1), (&missing, 2)] {
        let start = &read_json(&episodes(suite(3))[k].2)["start_pose"];
        assert_eq!(
            rec["trajectory"],
            json!([[start["row"], start["col"]]]),
            "{rec}"
        );
    }
    // Points that are not integers in the grid are malformed too, and say which point.
    write(&preds.join(m1).join(format!("{i1}.json")), "[[1.5, 2]]");
    let out2 = tmp.path().join("mine2");
    import(&preds, "mine", &out2).expect(0);
    let rec = read_json(&record(&out2, m1, i1));
    assert!(
        rec["prediction"]["problem"]
            .as_str()
            .unwrap()
            .contains("trajectory[0][0] must be an integer"),
        "{rec}"
    );
    // The report counts them as episodes (they cost points), not as missing.
    report(&[&out], &[], tmp.path()).expect(0);
}

#[test]
fn duplicated_foreign_unknown_and_unnamed_predictions_are_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let rs = routes();
    let (m, i, t) = &rs[0];
    // (case, files as (path, content), what the refusal says)
    type Case<'a> = (&'a str, Vec<(String, String)>, String);
    let cases: Vec<Case> = vec![
        (
            "duplicate",
            vec![
                (format!("{m}/{i}.json"), t.to_string()),
                (
                    "copy.json".into(),
                    json!({"map_id": format!("procthor/{m}"), "instruction_id": i, "trajectory": t})
                        .to_string(),
                ),
            ],
            format!("episode {m}/{i} has 2 predictions ({m}/{i}.json, copy.json)"),
        ),
        (
            "foreign map",
            vec![(
                "999_valunseen/instruction_000001.json".into(),
                t.to_string(),
            )],
            "predicts an episode of map `999_valunseen`, which is not in suite".into(),
        ),
        (
            "unknown episode",
            vec![(format!("{m}/instruction_000099.json"), t.to_string())],
            format!("map `{m}` of suite `map2route-procthor` has no episode instruction_000099"),
        ),
        (
            "unnamed",
            vec![("route.json".into(), t.to_string())],
            "route.json: cannot tell which episode it predicts".into(),
        ),
        (
            "disagreeing",
            vec![(
                format!("{m}/{i}.json"),
                json!({"instruction_id": "instruction_000002", "trajectory": t}).to_string(),
            )],
            format!("its instruction_id is `instruction_000002` but it is named `{i}.json`"),
        ),
    ];
    for (what, files, expected) in cases {
        let preds = tmp.path().join(what).join("preds");
        for (rel, text) in files {
            write(&preds.join(rel), &text);
        }
        let out = tmp.path().join(what).join("out");
        let r = import(&preds, "mine", &out).expect(1);
        assert!(
            r.stderr.contains(&expected) && r.stderr.contains("nothing imported"),
            "{what}: {}",
            r.stderr
        );
        assert!(!out.exists(), "{what}: the output was written");
    }
}

#[test]
fn the_output_is_never_an_input_and_the_name_is_not_an_m2rc_method() {
    let tmp = tempfile::tempdir().unwrap();
    let preds = tmp.path().join("preds");
    let (m, i, t) = &routes()[0];
    let file = preds.join(m).join(format!("{i}.json"));
    write(&file, &t.to_string());
    let suite_copy = tmp.path().join("suite");
    copy_dir(suite(3), &suite_copy);
    let run = |out: &Path, method: &str| {
        m2rc(
            &[
                "bench",
                "import",
                "--suite",
                suite_copy.to_str().unwrap(),
                "--predictions",
                preds.to_str().unwrap(),
                "--method",
                method,
                "--out",
                out.to_str().unwrap(),
            ],
            tmp.path(),
        )
    };
    for (out, how) in [
        (preds.clone(), "is the --predictions folder"),
        (
            preds.join("runs/mine"),
            "lies inside the --predictions folder",
        ),
        (tmp.path().to_path_buf(), "holds the --predictions folder"),
        (suite_copy.clone(), "is a benchmark suite"),
        (suite_copy.join("run"), "lies inside a benchmark suite"),
        (tmp.path().join("x/../preds"), "is the --predictions folder"),
    ] {
        let r = run(&out, "mine").expect(2);
        assert!(r.stderr.contains(how), "{}: {}", out.display(), r.stderr);
    }
    assert!(!preds.join("runs").exists() && !suite_copy.join("run").exists());
    assert!(!tmp.path().join("run.json").exists() && !preds.join("run.json").exists());
    assert_eq!(std::fs::read_to_string(&file).unwrap(), t.to_string());
    let r = run(&tmp.path().join("o"), "oracle").expect(1);
    assert!(
        r.stderr.contains("one of m2rc's own methods"),
        "{}",
        r.stderr
    );
    let r = run(&tmp.path().join("o"), "my method").expect(1);
    assert!(r.stderr.contains("--method `my method`"), "{}", r.stderr);
}

#[test]
fn routes_that_teleport_keep_their_score_and_the_report_refuses_to_rank_them_unless_allowed() {
    let tmp = tempfile::tempdir().unwrap();
    let preds = tmp.path().join("preds");
    let rs = routes();
    for (k, (m, i, t)) in rs.iter().enumerate() {
        let t = t.as_array().unwrap();
        // The first route jumps from its start to its end in one step: the route.
        let route = if k == 0 {
            json!([t[0], t[t.len() - 1]])
        } else {
            Value::Array(t.clone())
        };
        write(&preds.join(m).join(format!("{i}.json")), &route.to_string());
    }
    let out = tmp.path().join("jumper");
    let r = import(&preds, "jumper", &out).expect(0);
    assert!(
        r.stdout.contains("1 with a route that is not drivable")
            && r.stderr.contains("route not drivable")
            && r.stderr.contains("step 0 jumps from"),
        "{}\n{}",
        r.stdout,
        r.stderr
    );
    let (m, i, _) = &rs[0];
    let rec = read_json(&record(&out, m, i));
    assert_eq!(rec["route_validity"]["valid"], false);
    assert_eq!(rec["route_validity"]["non_adjacent_steps"], 1);
    assert_eq!(
        rec["route_validity"]["first_problem"]["kind"],
        "non_adjacent_step"
    );
    let r = report(&[shortest_run(), &out], &[], tmp.path()).expect(1);
    assert!(
        r.stderr
            .contains("`jumper` has 1 of 3 routes that are not drivable")
            && r.stderr.contains("--allow-invalid-routes")
            && r.stdout.is_empty(),
        "{}",
        r.stderr
    );
    let r = report(
        &[shortest_run(), &out],
        &["--allow-invalid-routes"],
        tmp.path(),
    )
    .expect(0);
    assert!(
        r.stdout.contains("shortest: 0; jumper: 1")
            && r.stdout
                .contains("INVALID ROUTES: `jumper` has 1 of 3 routes"),
        "{}",
        r.stdout
    );
    let r = report(
        &[shortest_run(), &out],
        &["--allow-invalid-routes", "--format", "json"],
        tmp.path(),
    )
    .expect(0);
    let v: Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(v["methods"][0]["invalid_routes"], 0);
    assert_eq!(v["methods"][1]["invalid_routes"], 1);
    let r = report(
        &[&out],
        &["--allow-invalid-routes", "--format", "csv"],
        tmp.path(),
    )
    .expect(0);
    assert!(
        r.stdout
            .starts_with("method,block,episodes,present,expected,invalid_routes,")
            && r.stdout.contains("jumper,overall,3,3,3,1,"),
        "{}",
        r.stdout
    );
}

#[test]
fn eval_warns_about_a_route_that_teleports_and_says_where() {
    let tmp = tempfile::tempdir().unwrap();
    let (m, _, ep, _) = episodes(suite(3)).remove(0);
    let map = suite(3).join("maps").join(&m).join(format!("{m}.json"));
    let traj = routes().remove(0).2;
    let t = traj.as_array().unwrap();
    let jump = json!([t[0], t[t.len() - 1]]);
    write(&tmp.path().join("jump.json"), &jump.to_string());
    write(&tmp.path().join("drive.json"), &traj.to_string());
    let eval = |route: &str, extra: &[&str]| {
        let mut args = vec![
            "eval",
            "--map",
            map.to_str().unwrap(),
            "--episode",
            ep.to_str().unwrap(),
            "--route",
            route,
        ];
        args.extend_from_slice(extra);
        m2rc(&args, tmp.path())
    };
    let r = eval("jump.json", &["--format", "json"]).expect(0);
    let v: Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(v["route_valid"], false);
    assert_eq!(v["route_validity"]["non_adjacent_steps"], 1);
    assert_eq!(
        v["route_validity"]["first_problem"],
        json!({"kind": "non_adjacent_step", "step": 0, "from": t[0], "to": t[t.len() - 1]})
    );
    assert!(
        r.stderr
            .contains("warning: jump.json: the route is not drivable")
            && r.stderr.contains("scored anyway"),
        "{}",
        r.stderr
    );
    let full = eval("jump.json", &["--full"]).expect(0);
    let v: Value = serde_json::from_str(&full.stdout).unwrap();
    assert_eq!(v["route_valid"], false);
    assert!(v["details"].is_object());
    let text = eval("jump.json", &[]).expect(0);
    assert!(
        text.stdout.contains("route INVALID (not drivable)"),
        "{}",
        text.stdout
    );
    let r = eval("drive.json", &["--format", "json"]).expect(0);
    let v: Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(v["route_valid"], true);
    assert!(!r.stderr.contains("warning"), "{}", r.stderr);
}

#[test]
fn eval_help_lists_every_route_form_eval_accepts_and_each_form_scores_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let help = m2rc(&["eval", "--help"], tmp.path()).expect(0).stdout;
    assert!(help.contains("bare [[row, col], ...] list"), "{help}");
    let (m, _, ep, _) = episodes(suite(3)).remove(0);
    let map = suite(3).join("maps").join(&m).join(format!("{m}.json"));
    let traj = routes().remove(0).2;
    let mut forms = vec![("bare".to_string(), traj.clone())];
    for key in m2rc_benchmark::route::TRAJECTORY_KEYS {
        assert!(
            help.contains(&format!("`{key}`")),
            "--help lacks `{key}`:\n{help}"
        );
        forms.push((key.to_string(), json!({ key: traj })));
    }
    let mut scores = Vec::new();
    for (name, route) in forms {
        let file = tmp.path().join(format!("{name}.json"));
        write(&file, &route.to_string());
        let r = m2rc(
            &[
                "eval",
                "--map",
                map.to_str().unwrap(),
                "--episode",
                ep.to_str().unwrap(),
                "--route",
                file.to_str().unwrap(),
                "--format",
                "json",
            ],
            tmp.path(),
        )
        .expect(0);
        scores.push(r.stdout);
    }
    assert!(scores.windows(2).all(|w| w[0] == w[1]), "{scores:?}");
}
