//! The LTL backend as a user runs it: formulas too large for an automaton are refused with E0810
//! by every command (not after minutes and gigabytes), `--atoms` names each atom once, a
//! `route ltl` route's stages are the places it visits, and E0809 only where a preference is
//! really ignored.

use crate::common::{Run, m2rc};
use std::path::Path;

/// `F a0 & F a1 & ... & F a{n-1}`.
fn eventualities(n: usize) -> String {
    (0..n)
        .map(|i| format!("F a{i}"))
        .collect::<Vec<_>>()
        .join(" & ")
}

/// A demo-map program binding `a0..a{n-1}` to places and visiting all of them in any order.
fn unordered_program(n: usize) -> String {
    let mut src = String::from("// map: demo\n");
    for i in 0..n {
        src.push_str(&format!("let a{i} = rooms(kitchen).only()\n"));
    }
    src.push_str(&format!("route ltl \"{}\"\n", eventualities(n)));
    src
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    std::fs::write(dir.join(name), text).unwrap();
    name.to_string()
}

#[test]
fn too_many_eventualities_are_refused_by_every_command() {
    let dir = tempfile::tempdir().unwrap();
    for n in [30, 64] {
        let run = m2rc(&["ltl", &eventualities(n)], dir.path()).expect(1);
        assert!(run.stderr.contains("E0810"), "{n}: {}", run.stderr);
        let prog = write(dir.path(), &format!("p{n}.m2r"), &unordered_program(n));
        let run = m2rc(&["check", &prog], dir.path()).expect(1);
        assert!(run.stderr.contains("E0810"), "{n}: {}", run.stderr);
        let run = m2rc(
            &["compile", &prog, "--map", "demo", "--planner", "ltl"],
            dir.path(),
        )
        .expect(1);
        assert!(run.stderr.contains("E0810"), "{n}: {}", run.stderr);
        assert!(!dir.path().join("out.json").exists());
    }
}

#[test]
fn atoms_must_be_distinct_atom_names() {
    let dir = tempfile::tempdir().unwrap();
    let f = "F a & F b";
    let refused = |list: &str, named: &str| {
        let run: Run = m2rc(&["ltl", f, "--atoms", list, "--emit", "hoa"], dir.path()).expect(2);
        assert!(run.stdout.is_empty(), "{list}: {}", run.stdout);
        assert!(run.stderr.contains(named), "{list}: {}", run.stderr);
    };
    refused("a,a,b", "`a` twice");
    refused("a,,b", "empty");
    refused("a,b-c", "`b-c`");
    refused("a,b,X", "`X`");
    refused("a,b,true", "`true`");
    refused("a", "`b`");
    let run = m2rc(&["ltl", f, "--atoms", "b,a,c", "--emit", "hoa"], dir.path()).expect(0);
    assert!(
        run.stdout.contains("AP: 3 \"b\" \"a\" \"c\""),
        "{}",
        run.stdout
    );
}

const VISIT: &str = "// map: demo\n\
    let kitchen = rooms(kitchen).only()\n\
    let bed = objects(bed).nearest(start)\n\
    let bath = rooms(bathroom).smallest()\n";

/// Stages of a `route ltl` route: one per place the formula asks to enter, in the order the
/// route enters them, each ending at its first entry; never the place kept out of.
#[test]
fn ltl_route_stages_are_its_visits_cut_at_first_entry() {
    let dir = tempfile::tempdir().unwrap();
    let prog = write(
        dir.path(),
        "visit.m2r",
        &format!("{VISIT}route ltl \"F(kitchen & F bed) & G !bath\"\n"),
    );
    let run = m2rc(
        &["compile", &prog, "--map", "demo", "-o", "route.json"],
        dir.path(),
    )
    .expect(0);
    assert!(!run.stderr.contains("E0809"), "{}", run.stderr);
    assert!(!run.stderr.contains("note: an LTL route"), "{}", run.stderr);
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("route.json")).unwrap()).unwrap();
    let traj = doc["trajectory"].as_array().unwrap();
    let stages = doc["m2rc"]["stages"].as_array().unwrap();
    let targets: Vec<&str> = stages
        .iter()
        .map(|s| s["target"].as_str().unwrap())
        .collect();
    assert_eq!(targets.len(), 2, "{stages:?}");
    assert!(targets[0].contains("kitchen"), "{targets:?}");
    assert!(targets[1].contains("bed"), "{targets:?}");
    let ends: Vec<u64> = stages
        .iter()
        .map(|s| s["end_index"].as_u64().expect("an end index"))
        .collect();
    assert!(ends[0] > 0 && ends[0] < ends[1], "{ends:?}");
    assert_eq!(ends[1] as usize, traj.len() - 1);
    let total: f64 = stages.iter().map(|s| s["length_m"].as_f64().unwrap()).sum();
    assert!(
        (total - doc["m2rc"]["length_m"].as_f64().unwrap()).abs() < 1e-9,
        "{doc}"
    );
    for s in stages {
        assert!(s["length_m"].as_f64().unwrap() > 0.0, "{s}");
    }
    // The first stage ends at the first cell of the route in the kitchen.
    let summary = m2rc(&["compile", &prog, "--map", "demo"], dir.path()).expect(0);
    assert!(!summary.stdout.contains("bathroom"), "{}", summary.stdout);
}

/// E0809 means "a preference the LTL planner ignores": not on every LTL route, but on a
/// preference inside one, and on the preferences of a program compiled with `--planner ltl`.
/// Another planner asked for explicitly gets a note, the default none.
#[test]
fn e0809_only_for_ignored_preferences() {
    let dir = tempfile::tempdir().unwrap();
    let plain = write(
        dir.path(),
        "plain.m2r",
        &format!("{VISIT}route ltl \"F(kitchen & F bed)\"\n"),
    );
    for planner in [None, Some("ltl")] {
        let mut args = vec!["compile", plain.as_str(), "--map", "demo"];
        args.extend(planner.map(|p| ["--planner", p]).into_iter().flatten());
        let run = m2rc(&args, dir.path()).expect(0);
        assert!(!run.stderr.contains("E0809"), "{planner:?}: {}", run.stderr);
        assert!(!run.stderr.contains("note: an LTL route"), "{}", run.stderr);
    }
    let run = m2rc(
        &["compile", &plain, "--map", "demo", "--planner", "global"],
        dir.path(),
    )
    .expect(0);
    assert!(!run.stderr.contains("E0809"), "{}", run.stderr);
    assert!(
        run.stderr.contains("`--planner global` does not apply"),
        "{}",
        run.stderr
    );
    let prefer = write(
        dir.path(),
        "prefer.m2r",
        &format!("{VISIT}route ltl \"F(kitchen & F bed)\" {{\n  prefer near(bath)\n}}\n"),
    );
    let run = m2rc(&["check", &prefer], dir.path()).expect(0);
    assert!(run.stderr.contains("E0809"), "{}", run.stderr);
    let routeir = write(
        dir.path(),
        "routeir.m2r",
        &format!("{VISIT}route {{\n  go kitchen\n  go bed {{\n    prefer near(bath)\n  }}\n}}\n"),
    );
    let run = m2rc(&["compile", &routeir, "--map", "demo"], dir.path()).expect(0);
    assert!(!run.stderr.contains("E0809"), "{}", run.stderr);
    let run = m2rc(
        &["compile", &routeir, "--map", "demo", "--planner", "ltl"],
        dir.path(),
    )
    .expect(0);
    assert!(run.stderr.contains("E0809"), "{}", run.stderr);
}

/// Stages that return to the same places share atoms: 20 alternating stages plan (the automaton
/// is a chain over two atoms), with one stage per `go`.
#[test]
fn alternating_stages_plan_with_the_ltl_planner() {
    let dir = tempfile::tempdir().unwrap();
    let mut src = String::from(
        "// map: demo\nlet bathroom = rooms(bathroom).smallest()\nlet kitchen = rooms(kitchen).only()\nroute {\n",
    );
    for i in 0..20 {
        src.push_str(if i % 2 == 0 {
            "  go bathroom\n"
        } else {
            "  go kitchen\n"
        });
    }
    src.push_str("}\n");
    let prog = write(dir.path(), "alt.m2r", &src);
    let run = m2rc(
        &[
            "compile",
            &prog,
            "--map",
            "demo",
            "--planner",
            "ltl",
            "-o",
            "alt.json",
        ],
        dir.path(),
    )
    .expect(0);
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("alt.json")).unwrap()).unwrap();
    assert_eq!(doc["m2rc"]["planner"], "ltl", "{}", run.stderr);
    let stages = doc["m2rc"]["stages"].as_array().unwrap();
    assert_eq!(stages.len(), 20);
    let ends: Vec<u64> = stages
        .iter()
        .map(|s| s["end_index"].as_u64().unwrap())
        .collect();
    assert!(ends.windows(2).all(|w| w[0] < w[1]), "{ends:?}");
}
