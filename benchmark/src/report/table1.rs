//! Table I in the paper's layout: the rows in the paper's order (shortest, the seven adapted
//! baselines, Grounding2Route, then rows the paper does not have), Easy and Hard blocks, the
//! "Δ vs best baseline" line, and beside each of our rows the paper's published row for the same
//! method, marked as measured on other episodes. With gold replies (`--llm gold`) it is the table
//! of ceilings, and the paper's rows are left out (they are not ceilings).

use super::MethodRun;
use super::table::{Block, KEYS, MethodRow, table};

/// The paper's Table I (Easy then Hard: HCS, Near, Far, Relative, Path-Shape, Clearance, PL,
/// SPL), transcribed once from `../shared/reference/paper-results.md` ("Table I: methods on
/// Map2Route"; Map2Route / Grounding2Route paper). Measured on the paper's 1000 human-written
/// episodes in 40 ProcTHOR-10K train houses with Gemini-3.5-Flash, not on m2rc's suites.
pub const PAPER_TABLE1: &[(&str, [f64; 8], [f64; 8])] = &[
    (
        "Shortest feasible A*",
        [1.000, 3.13, 2.30, 1.10, 0.05, 0.53, 28.0, 1.00],
        [1.000, 2.99, 2.41, 1.24, 0.05, 0.53, 66.2, 1.00],
    ),
    (
        "Human demonstration",
        [1.000, 1.72, 3.71, 2.57, 0.99, 0.73, 37.1, 0.77],
        [1.000, 1.80, 3.59, 2.21, 0.99, 0.73, 88.2, 0.76],
    ),
    (
        "Lang2LTL",
        [0.300, 4.41, 0.76, 0.49, 0.01, 0.51, 30.1, 0.28],
        [0.124, 4.61, 0.41, 0.16, 0.00, 0.51, 72.7, 0.10],
    ),
    (
        "SayPlan",
        [0.102, 4.74, 0.35, 0.13, 0.00, 0.52, 20.2, 0.08],
        [0.029, 4.83, 0.14, 0.05, 0.00, 0.52, 44.8, 0.03],
    ),
    (
        "OSG-LLM",
        [0.368, 4.66, 0.93, 0.57, 0.02, 0.46, 21.6, 0.36],
        [0.120, 5.56, 0.38, 0.15, 0.00, 0.35, 31.8, 0.11],
    ),
    (
        "Lang2LTL-2",
        [0.248, 4.45, 0.63, 0.42, 0.02, 0.51, 31.3, 0.22],
        [0.094, 4.68, 0.29, 0.09, 0.01, 0.51, 53.7, 0.08],
    ),
    (
        "LIMP",
        [0.050, 4.90, 0.19, 0.11, 0.00, 0.48, 11.8, 0.04],
        [0.012, 4.96, 0.05, 0.00, 0.00, 0.43, 13.2, 0.01],
    ),
    (
        "LTLCodeGen",
        [0.274, 6.03, 0.65, 0.38, 0.02, 0.49, 26.2, 0.26],
        [0.101, 6.04, 0.34, 0.16, 0.01, 0.45, 57.6, 0.09],
    ),
    (
        "ILN",
        [0.063, 4.76, 0.24, 0.07, 0.00, 0.64, 21.2, 0.06],
        [0.011, 4.91, 0.07, 0.02, 0.00, 0.65, 19.0, 0.01],
    ),
    (
        "Grounding2Route",
        [0.667, 3.21, 2.76, 1.27, 0.16, 0.74, 31.2, 0.53],
        [0.375, 3.33, 2.24, 0.89, 0.08, 0.69, 54.7, 0.29],
    ),
];

/// A method name reduced for matching (`OSG-LLM`, `osg_llm` and `osgllm` are one method), with
/// the labels of a run (` [GOLD replies]`, ` [SIMULATED model]`) cut off.
pub fn base_name(name: &str) -> String {
    let name = name.split(" [").next().unwrap_or(name);
    name.chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

/// The paper's row name of one of our methods.
fn paper_name(method: &str) -> Option<&'static str> {
    let key = match base_name(method).as_str() {
        "shortest" => "shortestfeasiblea".to_string(),
        other => other.to_string(),
    };
    PAPER_TABLE1
        .iter()
        .map(|(n, _, _)| *n)
        .find(|n| base_name(n) == key)
}

/// Rows that are not baselines: references and the method under test.
fn is_reference(method: &str) -> bool {
    matches!(
        base_name(method).as_str(),
        "shortest" | "oracle" | "hardonly" | "human" | "grounding2route"
    )
}

/// Position in the paper's order; rows the paper does not have come after it, in input order.
fn paper_rank(method: &str) -> usize {
    paper_name(method)
        .and_then(|n| PAPER_TABLE1.iter().position(|(p, _, _)| *p == n))
        .unwrap_or(PAPER_TABLE1.len())
}

/// Whether a column is better when higher (`Some(true)`), lower (Near), or has no direction (PL).
fn higher_is_better(key: &str) -> Option<bool> {
    match key {
        "Near" => Some(false),
        "PL" => None,
        _ => Some(true),
    }
}

fn fmt(key: &str, v: Option<f64>) -> String {
    match v {
        None => "–".into(),
        Some(x) if key == "HCS" => format!("{x:.3}"),
        Some(x) if key == "PL" => format!("{x:.1}"),
        Some(x) => format!("{x:.2}"),
    }
}

fn signed(key: &str, v: Option<f64>) -> String {
    match v {
        None => "–".into(),
        Some(x) => {
            let s = fmt(key, Some(x.abs()));
            if x < 0.0 {
                format!("−{s}")
            } else {
                format!("+{s}")
            }
        }
    }
}

/// For each column, `target − best baseline` (best: the highest, or the lowest for Near; none for
/// PL), over `baselines` (blocks of rows that are baselines).
fn delta(target: &Block, baselines: &[&Block]) -> Vec<Option<f64>> {
    KEYS.iter()
        .map(|&k| {
            let dir = higher_is_better(k)?;
            let t = target.get(k)?;
            let vals = baselines.iter().filter_map(|b| b.get(k));
            let best = if dir {
                vals.fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
            } else {
                vals.fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.min(v))))
            }?;
            Some(t - best)
        })
        .collect()
}

fn paper_block(values: &[f64; 8]) -> Block {
    let g = |i: usize| Some(values[i]);
    Block {
        hcs: g(0),
        near: g(1),
        far: g(2),
        relative: g(3),
        path_shape: g(4),
        clearance: g(5),
        pl: g(6),
        spl: g(7),
        episodes: 0,
    }
}

fn row_cells(out: &mut String, label: &str, easy: &Block, hard: &Block) {
    out.push_str(&format!("| {label} |"));
    for b in [easy, hard] {
        for k in KEYS {
            out.push_str(&format!(" {} |", fmt(k, b.get(k))));
        }
    }
    out.push('\n');
}

/// The Markdown table. `ceilings`: every model call was answered from the gold annotations.
pub fn markdown(runs: &[MethodRun], ceilings: bool) -> String {
    let t = table(runs);
    let mut rows: Vec<&MethodRow> = t.methods.iter().collect();
    rows.sort_by_key(|r| paper_rank(&r.method));
    let mut out = String::new();
    if ceilings {
        out.push_str(
            "Ceilings: every baseline's model calls answered from the episode's gold annotations \
             ([GOLD replies]), Grounding2Route given the gold program; what each representation \
             can reach when its language step is perfect.\n\n",
        );
    }
    out.push_str("| Method | Easy HCS↑ | Near↓ | Far↑ | Rel.↑ | Shape↑ | Clear.↑ | PL | SPL↑ | Hard HCS↑ | Near↓ | Far↑ | Rel.↑ | Shape↑ | Clear.↑ | PL | SPL↑ |\n|---|");
    out.push_str(&"---:|".repeat(16));
    out.push('\n');
    let mut paper_shown = false;
    for r in &rows {
        row_cells(&mut out, &r.method, &r.easy, &r.hard);
        if !ceilings
            && let Some(name) = paper_name(&r.method)
            && let Some((_, e, h)) = PAPER_TABLE1.iter().find(|(n, _, _)| *n == name)
        {
            row_cells(
                &mut out,
                &format!("*{name} (paper)†*"),
                &paper_block(e),
                &paper_block(h),
            );
            paper_shown = true;
        }
    }
    let baselines: Vec<&&MethodRow> = rows.iter().filter(|r| !is_reference(&r.method)).collect();
    if let Some(target) = rows
        .iter()
        .find(|r| base_name(&r.method) == "grounding2route")
        && !baselines.is_empty()
    {
        let de = delta(
            &target.easy,
            &baselines.iter().map(|r| &r.easy).collect::<Vec<_>>(),
        );
        let dh = delta(
            &target.hard,
            &baselines.iter().map(|r| &r.hard).collect::<Vec<_>>(),
        );
        out.push_str("| Δ vs best baseline |");
        for (i, d) in de.iter().chain(dh.iter()).enumerate() {
            out.push_str(&format!(" {} |", signed(KEYS[i % 8], *d)));
        }
        out.push('\n');
        if !ceilings {
            let paper_baselines: Vec<Block> = PAPER_TABLE1
                .iter()
                .filter(|(n, _, _)| !is_reference_paper(n))
                .map(|(_, e, _)| paper_block(e))
                .collect();
            let paper_hard: Vec<Block> = PAPER_TABLE1
                .iter()
                .filter(|(n, _, _)| !is_reference_paper(n))
                .map(|(_, _, h)| paper_block(h))
                .collect();
            let g = PAPER_TABLE1
                .iter()
                .find(|(n, _, _)| *n == "Grounding2Route")
                .expect("the paper's table has Grounding2Route");
            let de = delta(
                &paper_block(&g.1),
                &paper_baselines.iter().collect::<Vec<_>>(),
            );
            let dh = delta(&paper_block(&g.2), &paper_hard.iter().collect::<Vec<_>>());
            out.push_str("| *Δ vs best baseline (paper)†* |");
            for (i, d) in de.iter().chain(dh.iter()).enumerate() {
                out.push_str(&format!(" *{}* |", signed(KEYS[i % 8], *d)));
            }
            out.push('\n');
        }
    }
    out.push('\n');
    let baseline_names: Vec<&str> = baselines.iter().map(|r| r.method.as_str()).collect();
    out.push_str(&format!(
        "Δ vs best baseline: Grounding2Route minus the best of {} in each column (highest, lowest \
         for Near; none for PL).\n",
        if baseline_names.is_empty() {
            "no baseline".to_string()
        } else {
            baseline_names.join(", ")
        }
    ));
    let counts: Vec<String> = rows
        .iter()
        .map(|r| {
            format!(
                "{}: {} easy + {} hard",
                r.method, r.easy.episodes, r.hard.episodes
            )
        })
        .collect();
    out.push_str(&format!("\nEpisodes — {}.\n", counts.join("; ")));
    for r in rows
        .iter()
        .filter(|r| r.episodes_present < r.episodes_expected)
    {
        out.push_str(&format!(
            "\n**INCOMPLETE: `{}` has {} of {} episodes.**\n",
            r.method, r.episodes_present, r.episodes_expected
        ));
    }
    if paper_shown {
        out.push_str(
            "\n† The paper's published row (Map2Route / Grounding2Route paper, Table I), measured on \
             **other episodes**: its 1000 human-written episodes (700 Easy, 300 Hard) in 40 \
             ProcTHOR-10K train houses, with Gemini-3.5-Flash. A reference point, not a target; \
             m2rc's suites are generated in other houses.\n",
        );
    }
    out
}

fn is_reference_paper(name: &str) -> bool {
    matches!(
        base_name(name).as_str(),
        "shortestfeasiblea" | "humandemonstration" | "grounding2route"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_the_papers_rows() {
        assert_eq!(paper_name("osg-llm"), Some("OSG-LLM"));
        assert_eq!(paper_name("lang2ltl-2 [GOLD replies]"), Some("Lang2LTL-2"));
        assert_eq!(paper_name("shortest"), Some("Shortest feasible A*"));
        assert_eq!(paper_name("oracle"), None);
        assert!(paper_rank("sayplan") < paper_rank("iln"));
        assert!(paper_rank("grounding2route") < paper_rank("oracle"));
    }

    #[test]
    fn the_papers_delta_is_grounding2route_minus_osg_llm_on_easy_hcs() {
        let base: Vec<Block> = PAPER_TABLE1
            .iter()
            .filter(|(n, _, _)| !is_reference_paper(n))
            .map(|(_, e, _)| paper_block(e))
            .collect();
        let g = paper_block(&PAPER_TABLE1[9].1);
        let d = delta(&g, &base.iter().collect::<Vec<_>>());
        assert!((d[0].unwrap() - (0.667 - 0.368)).abs() < 1e-9);
        // Near: lower is better; the best baseline is Lang2LTL's 4.41.
        assert!((d[1].unwrap() - (3.21 - 4.41)).abs() < 1e-9);
        assert_eq!(d[6], None);
    }
}
