//! Reports over run directories: the paper's Table I (Markdown, CSV, JSON), the difficulty
//! analysis (tables and PNG bar charts), and per-episode pictures.

pub mod difficulty;
pub mod episode_png;
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
}

/// Reads a run directory. Several directories of the same method (e.g. unmerged shards) are
/// combined by [`load_runs`].
pub fn load_run(dir: &Path) -> Result<MethodRun, RunError> {
    let manifest = read_run_manifest(dir)?;
    let records = read_records(dir)?;
    Ok(MethodRun {
        method: manifest.method,
        records,
    })
}

/// Reads run directories, keeping the order methods first appear in and merging directories of
/// the same method.
pub fn load_runs(dirs: &[impl AsRef<Path>]) -> Result<Vec<MethodRun>, RunError> {
    let mut runs: Vec<MethodRun> = Vec::new();
    for d in dirs {
        let run = load_run(d.as_ref())?;
        match runs.iter_mut().find(|r| r.method == run.method) {
            Some(existing) => existing.records.extend(run.records),
            None => runs.push(run),
        }
    }
    Ok(runs)
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
