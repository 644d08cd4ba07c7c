//! `docs/benchmark.md`'s quick start and "Score your own method" run as written (each `m2rc`
//! line, in a fresh folder beside `../shared`), and the records they write have exactly the keys
//! `docs/formats.md` documents.

use crate::common;
use common::*;
use serde_json::Value;
use std::path::Path;

fn doc(name: &str) -> String {
    std::fs::read_to_string(repo().join("docs").join(name)).unwrap()
}

/// The fenced code blocks (language, body) of the section starting at `heading`.
fn blocks(doc: &str, heading: &str) -> Vec<(String, String)> {
    let start = doc
        .find(heading)
        .unwrap_or_else(|| panic!("no `{heading}` in the doc"));
    let body = &doc[start + heading.len()..];
    let end = body.find("\n## ").unwrap_or(body.len());
    let mut out = Vec::new();
    let mut rest = &body[..end];
    while let Some(open) = rest.find("```") {
        let after = &rest[open + 3..];
        let (lang, code) = after.split_once('\n').unwrap();
        let close = code.find("```").unwrap();
        out.push((lang.trim().to_string(), code[..close].to_string()));
        rest = &code[close + 3..];
    }
    out
}

/// Runs every `m2rc ...` line of a shell block in `cwd`, with `../shared/` pointing at the
/// shared folder beside the repository; returns the outputs.
fn run_m2rc_lines(block: &str, cwd: &Path) -> Vec<Run> {
    let shared = repo().join("../shared/");
    let mut runs = Vec::new();
    for line in block.lines().map(str::trim) {
        let Some(args) = line.strip_prefix("m2rc ") else {
            continue;
        };
        let args: Vec<String> = args
            .split_whitespace()
            .map(|a| a.replace("../shared/", shared.to_str().unwrap()))
            .collect();
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let r = m2rc(&refs, cwd);
        assert_eq!(
            r.code,
            Some(0),
            "`{line}` failed\nstdout:\n{}\nstderr:\n{}",
            r.stdout,
            r.stderr
        );
        runs.push(r);
    }
    runs
}

fn python3() -> bool {
    std::process::Command::new("python3")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn the_quick_start_and_score_your_method_run_as_written() {
    let tmp = tempfile::tempdir().unwrap();
    let cwd = tmp.path();
    let bench = doc("benchmark.md");
    let quick = blocks(&bench, "## Quick start");
    assert_eq!(quick.len(), 1, "one shell block in the quick start");
    let steps = quick[0]
        .1
        .lines()
        .filter(|l| l.starts_with("m2rc "))
        .count();
    assert_eq!(steps, 5, "the quick start has five m2rc commands");
    let runs = run_m2rc_lines(&quick[0].1, cwd);
    assert!(runs[3].stdout.contains("## Table I"), "{}", runs[3].stdout);
    assert!(runs[3].stdout.contains("| oracle |"), "{}", runs[3].stdout);
    assert!(cwd.join("out/table1.csv").is_file());
    let plots: Vec<_> = std::fs::read_dir(cwd.join("out/plots")).unwrap().collect();
    assert!(!plots.is_empty(), "no plots written");

    let own = blocks(&bench, "## 5. Score your own method");
    let (lang, script) = &own[0];
    assert_eq!(lang, "python");
    let shell = &own[1].1;
    if python3() {
        std::fs::write(cwd.join("my_method.py"), script).unwrap();
        let out = std::process::Command::new("python3")
            .arg("my_method.py")
            .current_dir(cwd)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let runs = run_m2rc_lines(shell, cwd);
        assert!(
            runs[0]
                .stdout
                .contains("0 without a prediction, 0 with a malformed one")
                && runs[0]
                    .stdout
                    .contains("0 with a route that is not drivable"),
            "{}",
            runs[0].stdout
        );
        assert!(runs[1].stdout.contains("| bfs |"), "{}", runs[1].stdout);
        // bench table1 ranks the imported run beside the methods of Table I.
        assert!(runs[2].stdout.contains("| bfs |"), "{}", runs[2].stdout);
    } else {
        eprintln!("note: no python3 here; the script of \"Score your own method\" was not run");
    }

    // Every record key written is documented, and every documented key but the method-specific
    // ones is written.
    let formats = doc("formats.md");
    let start = formats.find("<!-- record keys").unwrap();
    let end = formats.find("<!-- end of record keys").unwrap();
    let documented: Vec<&str> = formats[start..end]
        .lines()
        .skip_while(|l| !l.starts_with("|---"))
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .collect();
    let mut written = std::collections::BTreeSet::new();
    for dir in ["oracle", "shortest", "bfs"] {
        let dir = cwd.join("out/runs").join(dir);
        if !dir.exists() {
            continue;
        }
        for m in std::fs::read_dir(&dir).unwrap().flatten() {
            if !m.path().is_dir() {
                continue;
            }
            for f in std::fs::read_dir(m.path()).unwrap().flatten() {
                let r: Value = read_json(&f.path());
                written.extend(r.as_object().unwrap().keys().cloned());
            }
        }
    }
    for k in &written {
        assert!(
            documented.contains(&k.as_str()),
            "record key `{k}` is not in docs/formats.md"
        );
    }
    for k in &documented {
        let method_specific = ["grounding2route", "prediction"].contains(k);
        assert!(
            method_specific || written.contains(*k),
            "docs/formats.md documents `{k}`, which no record has"
        );
    }
}
