//! The difficulty analysis of the reference (`difficulty_analysis_summary.json`): mean HCS per
//! method, binned by the episode's maximum reference depth, maximum candidate count, and number of
//! hard constraints beyond the start anchor. Bins are the reference's.

use super::MethodRun;
use serde::Serialize;
use serde_json::Value;

/// Per bin: (episodes, mean HCS, `None` when the bin is empty).
pub type BinCells = Vec<(usize, Option<f64>)>;

/// One factor: its bins, and per method the (episodes, mean HCS) of each bin.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Factor {
    pub name: String,
    pub key: String,
    pub bins: Vec<String>,
    /// (method, per-bin (n, mean HCS or None)).
    pub rows: Vec<(String, BinCells)>,
}

struct FactorSpec {
    name: &'static str,
    key: &'static str,
    /// Bin labels and inclusive lower bounds (the last bin is open-ended).
    bins: &'static [(&'static str, u64)],
}

const FACTORS: [FactorSpec; 3] = [
    FactorSpec {
        name: "Reference depth (episode max)",
        key: "max_depth",
        bins: &[("1–2", 0), ("3", 3), ("4", 4), ("≥5", 5)],
    },
    FactorSpec {
        name: "Candidate instances (episode max)",
        key: "max_candidates",
        bins: &[("1–4", 0), ("5–8", 5), ("9–16", 9), ("≥17", 17)],
    },
    FactorSpec {
        name: "Hard constraints (excluding the start anchor)",
        key: "hard_constraints",
        bins: &[("1", 0), ("2", 2), ("3", 3), ("≥4", 4)],
    },
];

fn bin_of(value: u64, bins: &[(&str, u64)]) -> usize {
    bins.iter().rposition(|(_, lo)| value >= *lo).unwrap_or(0)
}

pub fn analysis(runs: &[MethodRun]) -> Vec<Factor> {
    FACTORS
        .iter()
        .map(|spec| {
            let rows = runs
                .iter()
                .map(|run| {
                    let mut sums = vec![(0usize, 0.0f64); spec.bins.len()];
                    for r in &run.records {
                        let Some(v) = r
                            .get("episode_factors")
                            .and_then(|f| f.get(spec.key))
                            .and_then(Value::as_u64)
                        else {
                            continue;
                        };
                        let Some(h) = r
                            .get("metrics_summary")
                            .and_then(|s| s.get("HCS"))
                            .and_then(Value::as_f64)
                        else {
                            continue;
                        };
                        let b = bin_of(v, spec.bins);
                        sums[b].0 += 1;
                        sums[b].1 += h;
                    }
                    let cells = sums
                        .into_iter()
                        .map(|(n, s)| (n, (n > 0).then(|| s / n as f64)))
                        .collect();
                    (run.method.clone(), cells)
                })
                .collect();
            Factor {
                name: spec.name.to_string(),
                key: spec.key.to_string(),
                bins: spec.bins.iter().map(|(l, _)| l.to_string()).collect(),
                rows,
            }
        })
        .collect()
}

pub fn markdown(factors: &[Factor]) -> String {
    let mut out = String::new();
    for f in factors {
        out.push_str(&format!(
            "### Mean HCS by {}\n\n| Method |",
            f.name.to_lowercase()
        ));
        for b in &f.bins {
            out.push_str(&format!(" {b} |"));
        }
        out.push_str("\n|---|");
        out.push_str(&"---:|".repeat(f.bins.len()));
        out.push('\n');
        for (method, cells) in &f.rows {
            out.push_str(&format!("| {method} |"));
            for (n, v) in cells {
                match v {
                    Some(x) => out.push_str(&format!(" {x:.3} (n={n}) |")),
                    None => out.push_str(" – (n=0) |"),
                }
            }
            out.push('\n');
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_follow_the_reference_edges() {
        let depth = FACTORS[0].bins;
        assert_eq!(
            [1, 2, 3, 4, 5, 9].map(|v| bin_of(v, depth)),
            [0, 0, 1, 2, 3, 3]
        );
        let cands = FACTORS[1].bins;
        assert_eq!(
            [1, 4, 5, 8, 9, 16, 17, 300].map(|v| bin_of(v, cands)),
            [0, 0, 1, 1, 2, 2, 3, 3]
        );
    }
}
