//! `m2rc ablate` from the command line: `repair-rounds` with the labelled simulated model (one
//! row per R, one shared reply cache), refused without a model; `ltl-vs-routeir` adds the model's
//! rows planned both ways when a model is given; `oracle-planner` writes its table; `grounding`
//! runs the CaG and Schema rows.

use crate::common;
use common::*;

#[test]
fn repair_rounds_runs_every_r_with_the_simulated_model() {
    let tmp = tempfile::tempdir().unwrap();
    let s = suite(3).to_str().unwrap();
    let args = [
        "ablate",
        "repair-rounds",
        "--suite",
        s,
        "--out",
        "abl",
        "--llm",
        "simulated:0.9:4",
        "--repair-rounds",
        "2",
    ];
    let r = m2rc(&args, tmp.path()).expect(0);
    for row in ["repair-r0", "repair-r1", "repair-r2"] {
        assert!(r.stdout.contains(row), "{row} missing:\n{}", r.stdout);
    }
    assert!(r.stdout.contains("SIMULATED"), "{}", r.stdout);
    let dir = tmp.path().join("abl/repair-rounds");
    assert!(dir.join("table.md").is_file());
    assert!(
        dir.join("llm-cache").is_dir(),
        "one reply cache shared by every R"
    );
    let manifest = read_json(&dir.join("repair-r1/run.json"));
    assert_eq!(
        manifest["method_config"]["variant"], "repair-r1",
        "{manifest}"
    );
    // The same command again resumes: nothing is recomputed and the table is the same bytes.
    let table = std::fs::read(dir.join("table.md")).unwrap();
    m2rc(&args, tmp.path()).expect(0);
    assert_eq!(std::fs::read(dir.join("table.md")).unwrap(), table);
}

#[test]
fn ltl_vs_routeir_plans_the_models_programs_both_ways_when_a_model_is_given() {
    let tmp = tempfile::tempdir().unwrap();
    let s = suite(3).to_str().unwrap();
    let without = m2rc(
        &["ablate", "ltl-vs-routeir", "--suite", s, "--out", "a"],
        tmp.path(),
    )
    .expect(0);
    assert!(without.stdout.contains("gold+ltl"), "{}", without.stdout);
    assert!(!without.stdout.contains("llm+"), "{}", without.stdout);
    let args = [
        "ablate",
        "ltl-vs-routeir",
        "--suite",
        s,
        "--out",
        "b",
        "--llm",
        "simulated:0.5:3",
        "--repair-rounds",
        "1",
    ];
    let with = m2rc(&args, tmp.path()).expect(0);
    for row in ["gold+routeir", "gold+ltl", "llm+routeir", "llm+ltl"] {
        assert!(with.stdout.contains(row), "{row} missing:\n{}", with.stdout);
    }
    let dir = tmp.path().join("b/ltl-vs-routeir");
    let ltl = read_json(&dir.join("llm+ltl/run.json"));
    assert_eq!(ltl["method_config"]["planner"], "ltl", "{ltl}");
    assert_eq!(ltl["method_config"]["variant"], "llm+ltl", "{ltl}");
    let seq = read_json(&dir.join("llm+routeir/run.json"));
    assert!(seq["method_config"].get("planner").is_none(), "{seq}");
}

#[test]
fn repair_rounds_without_a_model_says_what_it_needs() {
    let tmp = tempfile::tempdir().unwrap();
    let s = suite(3).to_str().unwrap();
    let mut cmd = std::process::Command::new(bin());
    cmd.args(["ablate", "repair-rounds", "--suite", s, "--out", "abl"])
        .current_dir(tmp.path())
        .env_remove("M2R_LLM_BASE_URL");
    let out = cmd.output().unwrap();
    assert_ne!(out.status.code(), Some(0));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("needs a model"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// `ablate grounding`: CaG, Schema, Direct ID and catalog-LTL rows one-shot and with R, on one
/// reply cache; with gold replies, each representation's ceiling (ToolCall's too), labelled.
#[test]
fn grounding_runs_cag_and_schema_rows_on_one_reply_cache() {
    let tmp = tempfile::tempdir().unwrap();
    let s = suite(3).to_str().unwrap();
    let args = [
        "ablate",
        "grounding",
        "--suite",
        s,
        "--out",
        "g",
        "--llm",
        "simulated:0.5:1",
        "--repair-rounds",
        "2",
    ];
    let r = m2rc(&args, tmp.path()).expect(0);
    for row in [
        "cag-r0",
        "cag-r2",
        "schema-r0",
        "schema-r2",
        "directid-r0",
        "directid-r2",
        "catalog-ltl-r0",
        "catalog-ltl-r2",
    ] {
        assert!(r.stdout.contains(row), "{row} missing:\n{}", r.stdout);
    }
    // ToolCall has no simulated form: its row is left out, not failed.
    assert!(!r.stdout.contains("toolcall"), "{}", r.stdout);
    let dir = tmp.path().join("g/grounding");
    assert!(dir.join("llm-cache").is_dir(), "one reply cache");
    let schema = read_json(&dir.join("schema-r2/run.json"));
    assert_eq!(schema["method_config"]["repair_rounds"], 2, "{schema}");
    let ids = read_json(&dir.join("directid-r2/run.json"));
    assert_eq!(ids["method_config"]["repair_rounds"], 2, "{ids}");
    let gold = m2rc(
        &[
            "ablate",
            "grounding",
            "--suite",
            s,
            "--out",
            "gg",
            "--llm",
            "gold",
        ],
        tmp.path(),
    )
    .expect(0);
    for row in [
        "cag-gold",
        "schema-r0",
        "directid-r0",
        "catalog-ltl-r0",
        "toolcall-r0",
    ] {
        assert!(gold.stdout.contains(row), "{row} missing:\n{}", gold.stdout);
    }
    assert!(!gold.stdout.contains("schema-r3"), "{}", gold.stdout);
}
