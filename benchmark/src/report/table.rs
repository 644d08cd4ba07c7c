//! The paper's Table I: one row per method, an Easy and a Hard block of HCS, Near, Far, Relative,
//! Path-Shape, Clearance, PL and SPL, aggregated as the reference does (C.7): plain means of the
//! episode HCS, PL and segment-wise SPL; for each soft metric, the mean over the episodes that
//! have a finite value of the per-episode mean.

use super::MethodRun;
use crate::metrics::aggregate::{EpisodeRecord, metric_block};
use crate::metrics::evaluate::EpisodeMetrics;
use serde::Serialize;
use serde_json::Value;

/// Column keys, in table order.
pub const KEYS: [&str; 8] = [
    "HCS",
    "Near",
    "Far",
    "Relative",
    "PathShape",
    "Clearance",
    "PL",
    "SPL",
];

/// One block (easy, hard or overall) of one method. `None` when no episode has a value.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Block {
    #[serde(rename = "HCS")]
    pub hcs: Option<f64>,
    #[serde(rename = "Near")]
    pub near: Option<f64>,
    #[serde(rename = "Far")]
    pub far: Option<f64>,
    #[serde(rename = "Relative")]
    pub relative: Option<f64>,
    #[serde(rename = "PathShape")]
    pub path_shape: Option<f64>,
    #[serde(rename = "Clearance")]
    pub clearance: Option<f64>,
    #[serde(rename = "PL")]
    pub pl: Option<f64>,
    #[serde(rename = "SPL")]
    pub spl: Option<f64>,
    /// Episodes in the block (not part of the JSON table, whose blocks hold exactly the eight keys).
    #[serde(skip)]
    pub episodes: usize,
}

impl Block {
    pub fn get(&self, key: &str) -> Option<f64> {
        match key {
            "HCS" => self.hcs,
            "Near" => self.near,
            "Far" => self.far,
            "Relative" => self.relative,
            "PathShape" => self.path_shape,
            "Clearance" => self.clearance,
            "PL" => self.pl,
            "SPL" => self.spl,
            _ => None,
        }
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MethodRow {
    pub method: String,
    /// Episodes with a scored record, and episodes a complete run holds.
    pub episodes_present: usize,
    pub episodes_expected: usize,
    /// Episodes whose route is not drivable (reported only with `--allow-invalid-routes`).
    pub invalid_routes: usize,
    pub easy: Block,
    pub hard: Block,
    pub overall: Block,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Table {
    pub methods: Vec<MethodRow>,
}

/// Aggregates a set of prediction records into one block with the evaluator's aggregation
/// ([`metrics::aggregate::metric_block`], C.7) over each record's `metrics`. A record whose
/// metrics cannot be read (not written by this runner) counts as an episode without values.
pub fn block<'a>(records: impl Iterator<Item = &'a Value>) -> Block {
    let mut parsed: Vec<(String, String, EpisodeMetrics)> = Vec::new();
    let mut episodes = 0;
    for r in records {
        episodes += 1;
        let text = |k: &str| r.get(k).and_then(Value::as_str).unwrap_or("").to_string();
        if let Some(m) = r
            .get("metrics")
            .and_then(|m| serde_json::from_value::<EpisodeMetrics>(m.clone()).ok())
        {
            parsed.push((text("map_id"), text("instruction_id"), m));
        }
    }
    let records: Vec<EpisodeRecord<'_>> = parsed
        .iter()
        .map(|(map_id, instruction_id, metrics)| EpisodeRecord {
            map_id,
            instruction_id,
            difficulty: None,
            metrics,
        })
        .collect();
    let refs: Vec<&EpisodeRecord<'_>> = records.iter().collect();
    let b = metric_block(&refs);
    Block {
        hcs: b.hcs,
        near: b.scs.near,
        far: b.scs.far,
        relative: b.scs.relative,
        path_shape: b.scs.path_shape,
        clearance: b.scs.clearance,
        pl: b.path_efficiency.pl,
        spl: b.path_efficiency.h_spl,
        episodes,
    }
}

pub fn difficulty(r: &Value) -> &str {
    r.get("difficulty_level")
        .and_then(Value::as_str)
        .unwrap_or("unknown")
}

pub fn table(runs: &[MethodRun]) -> Table {
    Table {
        methods: runs
            .iter()
            .map(|run| MethodRow {
                method: run.method.clone(),
                episodes_present: run.present,
                episodes_expected: run.expected,
                invalid_routes: run.invalid_routes.len(),
                easy: block(run.records.iter().filter(|r| difficulty(r) == "easy")),
                hard: block(run.records.iter().filter(|r| difficulty(r) == "hard")),
                overall: block(run.records.iter()),
            })
            .collect(),
    }
}

fn cell(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.3}")).unwrap_or_else(|| "–".into())
}

const NOTE: &str = "Human demonstrations are not available for m2rc-generated suites, so there is no Human row; \
Near, Far, Clearance and PL are in metres (Near: lower is better), Relative is the distance ratio D_B/D_A, \
Path-Shape is nDTW, SPL is the segment-wise SPL.";

pub fn markdown(t: &Table) -> String {
    let mut out = String::new();
    out.push_str("| Method | Easy HCS↑ | Near↓ | Far↑ | Rel.↑ | Shape↑ | Clear.↑ | PL | SPL↑ | Hard HCS↑ | Near↓ | Far↑ | Rel.↑ | Shape↑ | Clear.↑ | PL | SPL↑ |\n");
    out.push_str("|---|");
    out.push_str(&"---:|".repeat(16));
    out.push('\n');
    for row in &t.methods {
        out.push_str(&format!("| {} |", row.method));
        for b in [&row.easy, &row.hard] {
            for k in KEYS {
                out.push_str(&format!(" {} |", cell(b.get(k))));
            }
        }
        out.push('\n');
    }
    let counts: Vec<String> = t
        .methods
        .iter()
        .map(|r| {
            format!(
                "{}: {} easy + {} hard",
                r.method, r.easy.episodes, r.hard.episodes
            )
        })
        .collect();
    out.push_str(&format!("\nEpisodes — {}.\n", counts.join("; ")));
    let invalid: Vec<String> = t
        .methods
        .iter()
        .map(|r| format!("{}: {}", r.method, r.invalid_routes))
        .collect();
    out.push_str(&format!(
        "\nInvalid routes (not drivable: a jump, a blocked cell or a cut corner) — {}.\n",
        invalid.join("; ")
    ));
    let coverage: Vec<String> = t
        .methods
        .iter()
        .map(|r| {
            format!(
                "{}: {} / {}",
                r.method, r.episodes_present, r.episodes_expected
            )
        })
        .collect();
    out.push_str(&format!(
        "\nEpisodes present / expected — {}.\n",
        coverage.join("; ")
    ));
    for r in t
        .methods
        .iter()
        .filter(|r| r.episodes_present < r.episodes_expected)
    {
        out.push_str(&format!(
            "\n**INCOMPLETE: `{}` has {} of {} episodes; its row averages only those and is not comparable with complete rows.**\n",
            r.method, r.episodes_present, r.episodes_expected
        ));
    }
    for r in t.methods.iter().filter(|r| r.invalid_routes > 0) {
        out.push_str(&format!(
            "\n**INVALID ROUTES: `{}` has {} of {} routes that are not drivable; they are scored as the reference scores them (straight segments), so its row is not comparable with rows of drivable routes.**\n",
            r.method, r.invalid_routes, r.episodes_present
        ));
    }
    out.push_str(&format!("\n{NOTE}\n"));
    out
}

pub fn csv(t: &Table) -> String {
    let mut out = String::from("method,block,episodes,present,expected,invalid_routes");
    for k in KEYS {
        out.push(',');
        out.push_str(k);
    }
    out.push('\n');
    for row in &t.methods {
        for (name, b) in [
            ("easy", &row.easy),
            ("hard", &row.hard),
            ("overall", &row.overall),
        ] {
            out.push_str(&format!(
                "{},{name},{},{},{},{}",
                csv_field(&row.method),
                b.episodes,
                row.episodes_present,
                row.episodes_expected,
                row.invalid_routes
            ));
            for k in KEYS {
                out.push(',');
                if let Some(x) = b.get(k) {
                    out.push_str(&format!("{x}"));
                }
            }
            out.push('\n');
        }
    }
    out
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub fn json(t: &Table) -> String {
    serde_json::to_string_pretty(t).expect("table serializes")
}
