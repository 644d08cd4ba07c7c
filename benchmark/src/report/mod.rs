//! Reports over run directories: the paper's Table I (Markdown, CSV, JSON), the difficulty
//! analysis (tables and PNG bar charts), and per-episode pictures.

pub mod difficulty;
pub mod episode_png;
pub mod model;
pub mod plot;
pub mod score;
pub mod table;

use crate::runner::{RunError, read_records, read_run_manifest};
use serde_json::Value;
use std::path::Path;

/// The records of one method, read from a run directory (merged, or a single shard).
#[derive(Clone, Debug)]
pub struct MethodRun {
    pub method: String,
    pub records: Vec<Value>,
    /// Episodes waiting for a model reply (marked `*.pending`, no record yet).
    pub pending: usize,
}

/// Reads a run directory. Several directories of the same method (e.g. unmerged shards) are
/// combined by [`load_runs`].
pub fn load_run(dir: &Path) -> Result<MethodRun, RunError> {
    let manifest = read_run_manifest(dir)?;
    let records = read_records(dir)?;
    // Every output the simulated model touched says so, the report's rows included.
    let simulated = manifest
        .method_config
        .as_ref()
        .and_then(|c| c.pointer("/backend/backend"))
        .and_then(Value::as_str)
        == Some("simulated");
    Ok(MethodRun {
        method: if simulated {
            format!("{} [SIMULATED model]", manifest.method)
        } else {
            manifest.method
        },
        records,
        pending: count_pending(dir),
    })
}

/// Reads run directories, keeping the order methods first appear in and merging directories of
/// the same method.
pub fn load_runs(dirs: &[impl AsRef<Path>]) -> Result<Vec<MethodRun>, RunError> {
    let mut runs: Vec<MethodRun> = Vec::new();
    for d in dirs {
        let run = load_run(d.as_ref())?;
        match runs.iter_mut().find(|r| r.method == run.method) {
            Some(existing) => {
                existing.records.extend(run.records);
                existing.pending += run.pending;
            }
            None => runs.push(run),
        }
    }
    Ok(runs)
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
        out.push_str("\n");
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
