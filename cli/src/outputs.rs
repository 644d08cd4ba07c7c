//! Output directories that would overwrite an input are refused before anything is written:
//! `bench merge --out` one of its own shards (it would rewrite that shard as a whole run), and
//! `bench run --out` a suite (run files among the suite's). Paths are compared after resolving
//! symbolic links and `..`, so `runs/a/../a.shard1` and a link to a shard are caught too.

use crate::io::unusable;
use anyhow::Result;
use std::path::{Component, Path, PathBuf};

/// `path` made absolute, with symbolic links resolved for the part that exists and `.`/`..`
/// removed from the rest (which does not exist yet, so holds no links).
pub fn resolved(path: &Path) -> PathBuf {
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .unwrap_or_else(|_| PathBuf::from("/"))
            .join(path)
    };
    let mut clean = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                clean.pop();
            }
            other => clean.push(other),
        }
    }
    // The longest existing ancestor, canonicalized, with the rest appended.
    let mut rest = Vec::new();
    let mut head = clean.as_path();
    loop {
        if let Ok(c) = std::fs::canonicalize(head) {
            let mut out = c;
            for part in rest.iter().rev() {
                out.push(part);
            }
            return out;
        }
        match (head.file_name(), head.parent()) {
            (Some(name), Some(parent)) => {
                rest.push(name.to_os_string());
                head = parent;
            }
            _ => return clean,
        }
    }
}

/// The directory at or above `dir` (resolved) that holds `suite.json`, if any.
fn suite_at_or_above(dir: &Path) -> Option<PathBuf> {
    resolved(dir)
        .ancestors()
        .find(|d| d.join("suite.json").is_file())
        .map(Path::to_path_buf)
}

/// Refuses (exit 2) an output directory that is one of `inputs`, lies inside one, holds one, or
/// is or lies inside a suite. `what` names an input in the message (`shard`).
pub fn refuse_output_among_inputs(out: &Path, inputs: &[PathBuf], what: &str) -> Result<()> {
    let o = resolved(out);
    for input in inputs {
        let i = resolved(input);
        let relation = if o == i {
            "is"
        } else if o.starts_with(&i) {
            "lies inside"
        } else if i.starts_with(&o) {
            "holds"
        } else {
            continue;
        };
        return Err(unusable(anyhow::anyhow!(
            "--out {} {relation} the {what} {}: an output never overwrites an input; choose a new \
             directory",
            out.display(),
            input.display()
        )));
    }
    refuse_suite(out)
}

/// Refuses (exit 2) `bench run --out` a suite directory, or a directory inside one: the records
/// and `run.json` would be written among the suite's files.
pub fn refuse_run_into_suite(out: &Path, suite: &Path) -> Result<()> {
    if resolved(out) == resolved(suite) {
        return Err(unusable(anyhow::anyhow!(
            "--out {} is the suite directory itself: a run would write its records among the \
             suite's files; choose another directory (e.g. runs/<method>)",
            out.display()
        )));
    }
    refuse_suite(out)
}

fn refuse_suite(out: &Path) -> Result<()> {
    match suite_at_or_above(out) {
        Some(s) => Err(unusable(anyhow::anyhow!(
            "--out {} {} a benchmark suite ({} holds suite.json): an output never overwrites an \
             input; choose a directory outside the suite (e.g. runs/<method>)",
            out.display(),
            if s == resolved(out) {
                "is"
            } else {
                "lies inside"
            },
            s.display()
        ))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_resolve_through_dots_and_links() {
        let tmp = tempfile::tempdir().unwrap();
        let a = tmp.path().join("a");
        std::fs::create_dir(&a).unwrap();
        std::os::unix::fs::symlink(&a, tmp.path().join("link")).unwrap();
        let real = std::fs::canonicalize(&a).unwrap();
        assert_eq!(resolved(&tmp.path().join("link")), real);
        assert_eq!(resolved(&tmp.path().join("a/x/../.")), real);
        assert_eq!(resolved(&tmp.path().join("link/new/y")), real.join("new/y"));
    }

    #[test]
    fn an_output_that_is_holds_or_lies_in_an_input_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let shard = tmp.path().join("runs/x.shard1");
        std::fs::create_dir_all(&shard).unwrap();
        let inputs = vec![shard.clone()];
        for out in [
            shard.clone(),
            shard.join("merged"),
            tmp.path().join("runs"),
            tmp.path().join("runs/../runs/x.shard1"),
        ] {
            assert!(
                refuse_output_among_inputs(&out, &inputs, "shard").is_err(),
                "{}",
                out.display()
            );
        }
        refuse_output_among_inputs(&tmp.path().join("runs/x"), &inputs, "shard").unwrap();
        std::fs::write(tmp.path().join("runs/suite.json"), b"{}").unwrap();
        assert!(refuse_run_into_suite(&tmp.path().join("runs/new"), &shard).is_err());
    }
}
