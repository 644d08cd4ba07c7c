//! Report columns for methods that use a language model (records with a `grounding2route`
//! object): first-try check rate, success after each repair round, local fixes, tokens, latency
//! and cost per episode; and the Table I metrics after each repair round R = 0..R_max, computed
//! from the same run by truncating each episode's attempt history (an episode that succeeded in
//! round k > R is scored as the start-only route it would have had with budget R), as the
//! reference builds its R0–R2 ablation.

use super::MethodRun;
use super::table::{Block, block};
use serde_json::Value;

/// Prices per million tokens, when given.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Prices {
    pub input: Option<f64>,
    pub output: Option<f64>,
}

/// One model method's row.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelRow {
    pub method: String,
    pub model: String,
    pub episodes: usize,
    pub pending: usize,
    pub first_try: f64,
    /// Fraction succeeded by round r, for r = 0..=R.
    pub success_after: Vec<f64>,
    pub local_fixes: f64,
    pub prompt_tokens: f64,
    pub completion_tokens: f64,
    pub latency_s: f64,
    pub cost: Option<f64>,
}

fn info(r: &Value) -> Option<&Value> {
    r.get("grounding2route").filter(|v| v.is_object())
}

fn num(v: &Value, k: &str) -> f64 {
    v.get(k).and_then(Value::as_f64).unwrap_or(0.0)
}

fn rounds(records: &[&Value]) -> usize {
    records
        .iter()
        .filter_map(|r| info(r)?.get("repair_rounds")?.as_u64())
        .max()
        .unwrap_or(0) as usize
}

fn success_round(r: &Value) -> Option<usize> {
    info(r)?.get("success_round")?.as_u64().map(|k| k as usize)
}

pub fn rows(runs: &[MethodRun], prices: &Prices) -> Vec<ModelRow> {
    let mut out = Vec::new();
    for run in runs {
        let recs: Vec<&Value> = run.records.iter().filter(|r| info(r).is_some()).collect();
        if recs.is_empty() && run.pending == 0 {
            continue;
        }
        let n = recs.len().max(1) as f64;
        let mean = |k: &str| {
            recs.iter()
                .map(|r| info(r).map_or(0.0, |i| num(i, k)))
                .sum::<f64>()
                / n
        };
        let frac = |f: &dyn Fn(&Value) -> bool| recs.iter().filter(|r| f(r)).count() as f64 / n;
        let r_max = rounds(&recs);
        let (pt, ct) = (mean("prompt_tokens"), mean("completion_tokens"));
        let cost = match (prices.input, prices.output) {
            (None, None) => None,
            (i, o) => Some((pt * i.unwrap_or(0.0) + ct * o.unwrap_or(0.0)) / 1e6),
        };
        out.push(ModelRow {
            method: run.method.clone(),
            model: recs
                .first()
                .and_then(|r| info(r)?.get("model")?.as_str())
                .unwrap_or("?")
                .to_string(),
            episodes: recs.len(),
            pending: run.pending,
            first_try: frac(&|r| {
                info(r)
                    .and_then(|i| i.get("first_try_ok")?.as_bool())
                    .unwrap_or(false)
            }),
            success_after: (0..=r_max)
                .map(|k| frac(&|r| success_round(r).is_some_and(|s| s <= k)))
                .collect(),
            local_fixes: mean("local_fixes"),
            prompt_tokens: pt,
            completion_tokens: ct,
            latency_s: mean("latency_ms") / 1e3,
            cost,
        });
    }
    out
}

/// The overall block of `run` had its repair budget been `r`.
pub fn block_at_round(run: &MethodRun, r: usize) -> Block {
    let adjusted: Vec<Value> = run
        .records
        .iter()
        .filter(|rec| info(rec).is_some())
        .map(|rec| {
            let mut rec = rec.clone();
            if success_round(&rec).is_some_and(|k| k > r)
                && let Some(m) = info(&rec)
                    .and_then(|i| i.pointer("/fallback_metrics/metrics"))
                    .cloned()
            {
                rec["metrics"] = m;
            }
            rec
        })
        .collect();
    block(adjusted.iter())
}

fn f3(x: Option<f64>) -> String {
    x.map_or("–".into(), |v| format!("{v:.3}"))
}

/// The model sections of the Markdown report (empty when no run used a model).
pub fn markdown(runs: &[MethodRun], prices: &Prices) -> String {
    let rows = rows(runs, prices);
    if rows.is_empty() {
        return String::new();
    }
    let r_max = rows
        .iter()
        .map(|r| r.success_after.len())
        .max()
        .unwrap_or(1);
    let mut out = String::from(
        "## Model methods\n\n| Method | Model | Episodes | Pending | First-try check |",
    );
    for k in 0..r_max {
        out.push_str(&format!(" Success ≤R{k} |"));
    }
    out.push_str(" Local fixes/ep | Prompt tok/ep | Completion tok/ep | Latency/ep (s) | Cost/ep |\n|---|---|---|---|---|");
    out.push_str(&"---|".repeat(r_max));
    out.push_str("---|---|---|---|---|\n");
    for r in &rows {
        out.push_str(&format!(
            "| {} | {} | {} | {} | {:.3} |",
            r.method, r.model, r.episodes, r.pending, r.first_try
        ));
        for k in 0..r_max {
            out.push_str(&format!(" {} |", f3(r.success_after.get(k).copied())));
        }
        out.push_str(&format!(
            " {:.2} | {:.0} | {:.0} | {:.3} | {} |\n",
            r.local_fixes,
            r.prompt_tokens,
            r.completion_tokens,
            r.latency_s,
            r.cost.map_or("–".into(), |c| format!("${c:.5}"))
        ));
    }
    out.push_str("\n## Results after each repair round (overall; same run, attempt history truncated at R)\n\n| Method | R | HCS | Near | Far | Relative | PathShape | Clearance | SPL |\n|---|---|---|---|---|---|---|---|---|\n");
    for run in runs {
        let recs: Vec<&Value> = run.records.iter().filter(|r| info(r).is_some()).collect();
        if recs.is_empty() {
            continue;
        }
        for r in 0..=rounds(&recs) {
            let b = block_at_round(run, r);
            out.push_str(&format!(
                "| {} | {r} | {} | {} | {} | {} | {} | {} | {} |\n",
                run.method,
                f3(b.hcs),
                f3(b.near),
                f3(b.far),
                f3(b.relative),
                f3(b.path_shape),
                f3(b.clearance),
                f3(b.spl)
            ));
        }
    }
    out
}
