//! `bench merge`: combine the shard directories of one run into one directory that is
//! indistinguishable from an unsharded run, or refuse.

use super::RunLock;
use super::collect::{RunDir, read_run_dir, split_key};
use crate::runner::{
    RUN_MANIFEST, RunError, RunManifest, read_run_manifest, record_path, write_atomic,
};
use serde::Serialize;

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MergeSummary {
    pub shards: usize,
    pub records: usize,
    /// Records already present in the output with identical content.
    pub duplicates: usize,
}

fn invalid(msg: String) -> RunError {
    RunError::Invalid(msg)
}

/// Merges shard run directories of one method and suite into `out`. Every shard of the split
/// must be given (`k/N` for every k), be complete, and carry the same fingerprint; every record
/// is validated before anything is written; records are copied byte for byte.
pub fn merge(
    shards: &[std::path::PathBuf],
    out: &std::path::Path,
) -> Result<MergeSummary, RunError> {
    if shards.is_empty() {
        return Err(invalid("no shard directories given".into()));
    }
    let mut runs: Vec<RunDir> = Vec::new();
    let mut seen = Vec::new();
    for d in shards {
        let canonical = std::fs::canonicalize(d).map_err(|e| RunError::Io {
            path: d.display().to_string(),
            source: e,
        })?;
        if seen.contains(&canonical) {
            return Err(invalid(format!("{} is given twice", d.display())));
        }
        seen.push(canonical);
        runs.push(read_run_dir(d)?);
    }
    let first = &runs[0];
    for r in &runs[1..] {
        let (a, b) = (&first.manifest, &r.manifest);
        if a.method != b.method || a.split != b.split {
            return Err(invalid(format!(
                "{} is a run of `{}` ({}), but {} is `{}` ({})",
                r.path.display(),
                b.method,
                b.split,
                first.path.display(),
                a.method,
                a.split
            )));
        }
        if let Some(diff) = first.fingerprint.differences(&r.fingerprint) {
            return Err(invalid(format!(
                "{} and {} cannot be merged: {diff}",
                first.path.display(),
                r.path.display()
            )));
        }
    }
    // Every shard k/N exactly once, all with the same N.
    let count = match first.manifest.shard {
        Some(s) => s.count,
        None => 1,
    };
    let mut by_index: Vec<Option<&RunDir>> = vec![None; count];
    for r in &runs {
        let (index, n) = r.manifest.shard.map_or((1, 1), |s| (s.index, s.count));
        if n != count {
            return Err(invalid(format!(
                "{} is shard {index}/{n}, but {} is one of {count} shards",
                r.path.display(),
                first.path.display()
            )));
        }
        if let Some(other) = by_index[index - 1] {
            return Err(invalid(format!(
                "{} and {} are both shard {index}/{count}",
                other.path.display(),
                r.path.display()
            )));
        }
        by_index[index - 1] = Some(r);
    }
    let absent: Vec<String> = (1..=count)
        .filter(|k| by_index[k - 1].is_none())
        .map(|k| format!("{k}/{count}"))
        .collect();
    if !absent.is_empty() {
        return Err(invalid(format!(
            "shard(s) {} of the run are not given; a merge needs every shard",
            absent.join(", ")
        )));
    }
    for r in &runs {
        if !r.is_complete() {
            return Err(invalid(format!(
                "{} is incomplete: {} of {} episodes have a record (first missing: {}); resume that shard first",
                r.path.display(),
                r.records.len(),
                r.manifest.expected.len(),
                r.missing[0]
            )));
        }
    }
    let shards_in_order: Vec<&RunDir> = by_index.into_iter().flatten().collect();
    // Manifest order of the whole split: position i was run by shard i mod N.
    let total: usize = shards_in_order
        .iter()
        .map(|r| r.manifest.expected.len())
        .sum();
    let mut expected = Vec::with_capacity(total);
    for i in 0..total {
        let shard = &shards_in_order[i % count];
        match shard.manifest.expected.get(i / count) {
            Some(k) => expected.push(k.clone()),
            None => {
                return Err(invalid(format!(
                    "{} covers fewer episodes than shard {} of {count} should",
                    shard.path.display(),
                    i % count + 1
                )));
            }
        }
    }
    let merged = RunManifest {
        method: first.manifest.method.clone(),
        suite_name: first.manifest.suite_name.clone(),
        split: first.manifest.split.clone(),
        shard: None,
        episodes: total,
        fingerprint: Some(first.fingerprint.clone()),
        expected,
        split_episodes: first.manifest.split_episodes,
        method_config: first.manifest.method_config.clone(),
    };

    let _lock = RunLock::acquire(out)?;
    super::remove_leftover_temps(out)?;
    if out.join(RUN_MANIFEST).exists() {
        let old = read_run_manifest(out)?;
        if old.fingerprint != merged.fingerprint
            || old.method != merged.method
            || old.split != merged.split
        {
            return Err(invalid(format!(
                "{} already holds another run (`{}` on `{}`); merge into a new directory",
                out.display(),
                old.method,
                old.suite_name
            )));
        }
    }
    let mut summary = MergeSummary {
        shards: runs.len(),
        ..MergeSummary::default()
    };
    for r in &runs {
        for (key, _) in &r.records {
            let (map_dir, instruction_id) = split_key(key)?;
            let from = record_path(&r.path, map_dir, instruction_id);
            let bytes = std::fs::read(&from).map_err(|e| RunError::Io {
                path: from.display().to_string(),
                source: e,
            })?;
            let target = record_path(out, map_dir, instruction_id);
            if let Ok(existing) = std::fs::read(&target) {
                if existing != bytes {
                    return Err(invalid(format!(
                        "{} differs from the record already merged at {}",
                        from.display(),
                        target.display()
                    )));
                }
                summary.duplicates += 1;
                continue;
            }
            write_atomic(&target, &bytes).map_err(|e| RunError::Io {
                path: target.display().to_string(),
                source: e,
            })?;
            summary.records += 1;
        }
    }
    let path = out.join(RUN_MANIFEST);
    write_atomic(
        &path,
        &serde_json::to_vec_pretty(&merged).expect("manifest serializes"),
    )
    .map_err(|e| RunError::Io {
        path: path.display().to_string(),
        source: e,
    })?;
    Ok(summary)
}
