//! Helpers of the fault-injection suites (`faults_*.rs`): run the real binary, build one small
//! real suite per test binary, copy directories, edit JSON files.
#![allow(dead_code)]

use serde_json::Value;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

pub struct Run {
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// Panics with the output when the exit status is not `code`.
    pub fn expect(self, code: i32) -> Run {
        assert_eq!(
            self.code,
            Some(code),
            "expected exit {code}\nstdout:\n{}\nstderr:\n{}",
            self.stdout,
            self.stderr
        );
        self
    }
}

pub fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_m2rc")
}

/// Runs m2rc in `cwd` with `stdin` as standard input.
pub fn m2rc_in(args: &[&str], cwd: &Path, stdin: &[u8]) -> Run {
    let mut child = Command::new(bin())
        .args(args)
        .current_dir(cwd)
        .env("CI", "1")
        // Tests read many temporary maps: keep their prepared forms out of the user's cache
        // (`map_cache.rs` turns it on in a directory of its own).
        .env("M2RC_MAP_CACHE", "off")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run m2rc");
    let mut input = child.stdin.take().unwrap();
    let bytes = stdin.to_vec();
    let feeder = std::thread::spawn(move || {
        let _ = input.write_all(&bytes);
    });
    let out = child.wait_with_output().expect("m2rc finished");
    let _ = feeder.join();
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

pub fn m2rc(args: &[&str], cwd: &Path) -> Run {
    m2rc_in(args, cwd, b"")
}

pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

pub fn fixtures() -> PathBuf {
    repo().join("../shared/procthor/fixtures")
}

/// A one-scene suite of real houses (validated by `shortest`), built once per test binary; tests
/// copy it before changing anything.
pub fn suite(seed: u64) -> &'static Path {
    static SUITES: OnceLock<std::sync::Mutex<Vec<(u64, &'static Path)>>> = OnceLock::new();
    let all = SUITES.get_or_init(Default::default);
    let mut all = all.lock().unwrap_or_else(|p| p.into_inner());
    if let Some((_, p)) = all.iter().find(|(s, _)| *s == seed) {
        return p;
    }
    let dir: &'static tempfile::TempDir = Box::leak(Box::new(tempfile::tempdir().unwrap()));
    let out = dir.path().join("suite");
    let seed_s = seed.to_string();
    m2rc(
        &[
            "suite",
            "build",
            "--houses",
            fixtures().to_str().unwrap(),
            "--scenes",
            "1",
            "--dev-scenes",
            "0",
            "--episodes-per-scene",
            "3",
            "--validate",
            "shortest",
            "--seed",
            &seed_s,
            "--out",
            out.to_str().unwrap(),
        ],
        dir.path(),
    )
    .expect(0);
    let p: &'static Path = Box::leak(out.into_boxed_path());
    all.push((seed, p));
    p
}

/// Copies a directory tree.
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let p = e.path();
        let t = to.join(e.file_name());
        if p.is_dir() {
            copy_dir(&p, &t);
        } else {
            std::fs::copy(&p, &t).unwrap();
        }
    }
}

pub fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

pub fn write_json(path: &Path, v: &Value) {
    std::fs::write(path, serde_json::to_vec(v).unwrap()).unwrap();
}

/// The suite's episodes as (map_id, instruction_id, episode file, program file).
pub fn episodes(suite: &Path) -> Vec<(String, String, PathBuf, PathBuf)> {
    let m = read_json(&suite.join("suite.json"));
    m["episodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            (
                e["map_id"].as_str().unwrap().to_string(),
                e["instruction_id"].as_str().unwrap().to_string(),
                suite.join(e["file"].as_str().unwrap()),
                suite.join(e["program"].as_str().unwrap()),
            )
        })
        .collect()
}

/// `m2rc bench run` of `method` on `suite` into `out` (extra args appended).
pub fn bench_run(suite: &Path, method: &str, out: &Path, extra: &[&str]) -> Run {
    let mut args = vec![
        "bench",
        "run",
        "--suite",
        suite.to_str().unwrap(),
        "--method",
        method,
        "--out",
        out.to_str().unwrap(),
    ];
    if !extra.contains(&"--threads") {
        args.extend_from_slice(&["--threads", "1"]);
    }
    args.extend_from_slice(extra);
    let cwd = out.parent().unwrap();
    std::fs::create_dir_all(cwd).unwrap();
    m2rc(&args, cwd)
}

/// The record file of an episode in a run directory.
pub fn record(out: &Path, map_id: &str, instruction_id: &str) -> PathBuf {
    out.join(map_id).join(format!("{instruction_id}.json"))
}
