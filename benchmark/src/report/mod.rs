//! Reports over run directories: the paper's Table I (Markdown, CSV, JSON), the difficulty
//! analysis (tables and PNG bar charts), and per-episode pictures.

pub mod difficulty;
pub mod episode_png;
pub mod model;
pub mod plot;
pub mod score;
pub mod table;
pub mod table1;

use crate::rundir::collect::collect;
use crate::runner::RunError;
use serde_json::Value;
use std::path::Path;

/// The records of one method, read from one or more run directories (merged, or shards).
#[derive(Clone, Debug, Default)]
pub struct MethodRun {
    pub method: String,
    pub records: Vec<Value>,
    /// Episodes with a scored record.
    pub present: usize,
    /// Episodes a complete run of the method holds (the suite's split).
    pub expected: usize,
    /// Episodes waiting for a model reply (marked `*.pending`, no record yet).
    pub pending: usize,
    /// Records whose route is not drivable ([`crate::route::validity`]), by episode key, with
    /// the first problem of each.
    pub invalid_routes: Vec<(String, String)>,
}

impl MethodRun {
    pub fn is_complete(&self) -> bool {
        self.present >= self.expected
    }
}

/// How strictly [`load_runs_with`] reads.
#[derive(Clone, Copy, Debug, Default)]
pub struct LoadOptions {
    /// Report methods whose runs lack episodes (the table then says so) instead of refusing.
    pub allow_incomplete: bool,
    /// Report methods with routes that are not drivable (the table then says so) instead of
    /// refusing: their scores are the reference's, which does not check routes.
    pub allow_invalid_routes: bool,
}

/// Reads run directories strictly: every record valid, every method complete.
pub fn load_runs(dirs: &[impl AsRef<Path>]) -> Result<Vec<MethodRun>, RunError> {
    load_runs_with(dirs, LoadOptions::default())
}

/// The name a method's rows carry: every output the simulated model touched says so.
fn display_name(method: &str, dirs: &[std::path::PathBuf]) -> String {
    let simulated = dirs.iter().any(|d| {
        crate::runner::read_run_manifest(d).is_ok_and(|m| {
            m.method_config
                .as_ref()
                .and_then(|c| c.pointer("/backend/backend"))
                .and_then(Value::as_str)
                == Some("simulated")
        })
    });
    let gold = dirs.iter().any(|d| {
        crate::runner::read_run_manifest(d).is_ok_and(|m| {
            m.method_config
                .as_ref()
                .and_then(|c| c.pointer("/model/backend/backend"))
                .and_then(Value::as_str)
                == Some("gold")
        })
    });
    if simulated {
        format!("{method} [SIMULATED model]")
    } else if gold {
        format!("{method} [GOLD replies]")
    } else {
        method.to_string()
    }
}

/// Reads run directories, keeping the order methods first appear in and combining directories
/// of the same method (each episode once, a directory named twice once). Every record is
/// validated; an incomplete method is refused unless `opts.allow_incomplete`, and a method with
/// routes that are not drivable unless `opts.allow_invalid_routes`.
pub fn load_runs_with(
    dirs: &[impl AsRef<Path>],
    opts: LoadOptions,
) -> Result<Vec<MethodRun>, RunError> {
    let methods = collect(dirs)?;
    let mut runs = Vec::new();
    let mut incomplete = Vec::new();
    let mut invalid = Vec::new();
    for m in methods {
        let invalid_routes = invalid_routes(&m.records);
        if let Some((key, why)) = invalid_routes.first() {
            invalid.push(format!(
                "`{}` has {} of {} routes that are not drivable (first: {key}: {why})",
                m.method,
                invalid_routes.len(),
                m.present()
            ));
        }
        let pending: usize = m.dirs.iter().map(|d| count_pending(d)).sum();
        if !m.is_complete() {
            incomplete.push(format!(
                "`{}` has {} of {} episodes{} ({})",
                m.method,
                m.present(),
                m.expected,
                if pending > 0 {
                    format!(", {pending} waiting for a model reply")
                } else {
                    String::new()
                },
                m.dirs
                    .iter()
                    .map(|d| d.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        runs.push(MethodRun {
            method: display_name(&m.method, &m.dirs),
            present: m.present(),
            expected: m.expected,
            pending,
            records: m.records.into_values().collect(),
            invalid_routes,
        });
    }
    if !incomplete.is_empty() && !opts.allow_incomplete {
        return Err(RunError::Invalid(format!(
            "incomplete run(s): {}; resume them, give every shard, or pass --allow-incomplete to report what is there",
            incomplete.join("; ")
        )));
    }
    if !invalid.is_empty() && !opts.allow_invalid_routes {
        return Err(RunError::Invalid(format!(
            "cannot rank routes that teleport or cross obstacles: {}; the evaluator scores such routes as straight segments, as the reference does, so their scores are not comparable with drivable routes; fix the method, or pass --allow-invalid-routes to report them (the table marks the row)",
            invalid.join("; ")
        )));
    }
    Ok(runs)
}

/// The records (already validated, so each has a `route_validity`) whose route is not drivable,
/// with the first problem in words.
fn invalid_routes(records: &std::collections::BTreeMap<String, Value>) -> Vec<(String, String)> {
    records
        .iter()
        .filter_map(|(key, r)| {
            let v = crate::rundir::record::route_validity(r).ok()?;
            (!v.valid).then(|| (key.clone(), v.summary()))
        })
        .collect()
}

/// `*.pending` markers in the map directories of a run directory.
pub fn count_pending(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    entries
        .flatten()
        .filter(|e| e.path().is_dir())
        .filter_map(|e| std::fs::read_dir(e.path()).ok())
        .flat_map(|d| d.flatten())
        .filter(|f| f.file_name().to_string_lossy().ends_with(".pending"))
        .count()
}

/// [`markdown_report`] plus, for methods that use a model, the model columns and the results
/// after each repair round.
pub fn markdown_report_with(runs: &[MethodRun], prices: &model::Prices) -> String {
    let mut out = markdown_report(runs);
    let model = model::markdown(runs, prices);
    if !model.is_empty() {
        out.push('\n');
        out.push_str(&model);
    }
    out
}

/// The full Markdown report: Table I and the difficulty analysis.
pub fn markdown_report(runs: &[MethodRun]) -> String {
    let mut out = String::from("## Table I\n\n");
    out.push_str(&table::markdown(&table::table(runs)));
    out.push_str("\n## Difficulty analysis\n\n");
    out.push_str(&difficulty::markdown(&difficulty::analysis(runs)));
    out
}

/// Writes one PNG bar chart per difficulty factor into `dir`; returns the files written.
pub fn write_plots(runs: &[MethodRun], dir: &Path) -> Result<Vec<std::path::PathBuf>, RunError> {
    let mut written = Vec::new();
    for f in difficulty::analysis(runs) {
        let svg = plot::factor_svg(&f);
        let png = plot::svg_to_png(&svg)
            .map_err(|e| RunError::Invalid(format!("plot {}: {e}", f.key)))?;
        let path = dir.join(format!("hcs_by_{}.png", f.key));
        crate::runner::write_atomic(&path, &png).map_err(|e| RunError::Io {
            path: path.display().to_string(),
            source: e,
        })?;
        written.push(path);
    }
    Ok(written)
}
