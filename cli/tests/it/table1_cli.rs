//! `bench table1`: every method of Table I into its own run directory with one shared cache,
//! the table in the paper's layout and Figure 4; resumable; `bench report --paper` on any runs;
//! an imported method may not take a baseline's name.

use crate::common::*;
use std::path::Path;

fn table1(out: &Path, extra: &[&str]) -> Run {
    let mut args = vec![
        "bench",
        "table1",
        "--suite",
        suite(3).to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "1",
    ];
    args.extend_from_slice(extra);
    m2rc(&args, out.parent().unwrap())
}

#[test]
fn table1_with_gold_replies_is_the_ceilings_table_in_the_papers_order() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("t1");
    let run = table1(&out, &["--llm", "gold"]).expect(0);
    let md = std::fs::read_to_string(out.join("table1.md")).unwrap();
    assert!(md.contains("Ceilings"), "{md}");
    // Every method ran into its own directory; the baselines' rows are labelled.
    for m in ["shortest", "oracle", "grounding2route", "sayplan", "iln"] {
        assert!(
            out.join(m).join("run.json").exists() || out.join(m).is_dir(),
            "{m}"
        );
    }
    let row = |name: &str| {
        md.lines()
            .position(|l| l.starts_with(&format!("| {name}")))
            .unwrap_or_else(|| panic!("no row {name} in\n{md}"))
    };
    // The paper's order: shortest, SayPlan before ILN, Grounding2Route, then rows it lacks.
    assert!(row("shortest") < row("sayplan [GOLD replies]"));
    assert!(row("sayplan [GOLD replies]") < row("iln [GOLD replies]"));
    assert!(row("iln [GOLD replies]") < row("grounding2route"));
    assert!(row("grounding2route") < row("oracle"));
    assert!(md.contains("| Δ vs best baseline |"));
    // Ceilings are not compared with the paper's published rows.
    assert!(!md.contains("(paper)†"));
    for f in ["max_depth", "max_candidates", "hard_constraints"] {
        assert!(
            out.join("figure4").join(format!("hcs_by_{f}.png")).exists(),
            "{f}"
        );
    }
    let fig = std::fs::read_to_string(out.join("figure4.md")).unwrap();
    assert!(fig.contains("| grounding2route"), "{fig}");
    assert!(run.stdout.contains("## Table I (ceilings)"));
    // A second run resumes: nothing is written again.
    let again = table1(&out, &["--llm", "gold"]).expect(0);
    assert!(again.stdout.contains("0 written"), "{}", again.stdout);
    assert!(!again.stdout.contains(" 1 written") && !again.stdout.contains(" 3 written"));
    // The gold replies went into the shared cache: a fresh table on the cache alone, with every
    // request a cache hit or a failure, gives the same rows (the cached-table benchmark's setup).
    let cached = tmp.path().join("t1-cached");
    let cache = out.join("llm-cache");
    let c = table1(
        &cached,
        &[
            "--llm",
            "gold",
            "--llm-cache-only",
            "--llm-cache",
            cache.to_str().unwrap(),
        ],
    )
    .expect(0);
    let all = format!("{}{}", c.stdout, c.stderr);
    assert!(!all.contains("fetched, 0 pending, 1 failed"), "{all}");
    assert!(all.contains("answered from the cache"), "{all}");
    let rows = |p: &Path| {
        std::fs::read_to_string(p.join("table1.md"))
            .unwrap()
            .lines()
            .filter(|l| l.starts_with("| "))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert_eq!(rows(&out), rows(&cached));
}

#[test]
fn report_paper_puts_the_published_rows_beside_ours_and_marks_them() {
    let tmp = tempfile::tempdir().unwrap();
    let shortest = tmp.path().join("shortest");
    let oracle = tmp.path().join("oracle");
    bench_run(suite(3), "shortest", &shortest, &[]).expect(0);
    bench_run(suite(3), "oracle", &oracle, &[]).expect(0);
    let r = m2rc(
        &[
            "bench",
            "report",
            "--paper",
            oracle.to_str().unwrap(),
            shortest.to_str().unwrap(),
        ],
        tmp.path(),
    )
    .expect(0);
    let lines: Vec<&str> = r.stdout.lines().collect();
    let at = |p: &str| lines.iter().position(|l| l.starts_with(p)).unwrap();
    // Shortest first (the paper's first row), its published row right under it.
    assert_eq!(
        at("| *Shortest feasible A* (paper)†*"),
        at("| shortest") + 1
    );
    assert!(at("| shortest") < at("| oracle"));
    assert!(r.stdout.contains("**other episodes**"));
}

#[test]
fn an_imported_method_cannot_take_a_baselines_name() {
    let tmp = tempfile::tempdir().unwrap();
    let preds = tmp.path().join("preds");
    std::fs::create_dir_all(&preds).unwrap();
    let r = m2rc(
        &[
            "bench",
            "import",
            "--suite",
            suite(3).to_str().unwrap(),
            "--predictions",
            preds.to_str().unwrap(),
            "--method",
            "sayplan",
            "--out",
            tmp.path().join("run").to_str().unwrap(),
        ],
        tmp.path(),
    )
    .expect(1);
    assert!(r.stderr.contains("baseline"), "{}", r.stderr);
}
