//! The prepared-map cache as a user meets it: the second `compile` or `eval` of a map file reads
//! the prepared form; a stale, corrupt or other-version entry is rebuilt with a warning and never
//! changes a result; `M2RC_MAP_CACHE=off` turns it off.

use crate::common::{Run, fixtures, m2rc};
use std::path::{Path, PathBuf};
use std::process::Command;

const PROGRAM: &str = "route {\n  go rooms(bedroom).nearest()\n}\n";

/// Runs m2rc with the map cache in `cache` (or off when `None`).
fn run(args: &[&str], cwd: &Path, cache: Option<&Path>) -> Run {
    let out = Command::new(crate::common::bin())
        .args(args)
        .current_dir(cwd)
        .env(
            "M2RC_MAP_CACHE",
            cache.map_or("off".into(), |c| c.as_os_str().to_owned()),
        )
        .output()
        .expect("run m2rc");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// A Map2Route map of fixture house `n` at `dir/map.json`.
fn write_map(dir: &Path, n: &str) {
    let house = fixtures().join(format!("procthor10k_uniform_hard_val_150_{n}.json"));
    m2rc(
        &["map", "import", house.to_str().unwrap(), "-o", "map.json"],
        dir,
    )
    .expect(0);
}

/// Compiles the program on `dir/map.json`; the route file's bytes and the run's stderr.
fn compile(dir: &Path, cache: Option<&Path>) -> (Vec<u8>, String) {
    std::fs::write(dir.join("p.m2r"), PROGRAM).unwrap();
    let _ = std::fs::remove_file(dir.join("route.json"));
    let r = run(
        &["compile", "p.m2r", "--map", "map.json", "-o", "route.json"],
        dir,
        cache,
    )
    .expect(0);
    (std::fs::read(dir.join("route.json")).unwrap(), r.stderr)
}

fn entries(cache: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(cache)
        .map(|d| d.map(|e| e.unwrap().path()).collect())
        .unwrap_or_default();
    out.sort();
    out
}

#[test]
fn the_second_compile_hits_and_gives_the_same_route() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    write_map(dir.path(), "007");
    let (uncached, _) = compile(dir.path(), None);
    assert!(entries(&cache).is_empty(), "off writes nothing");
    let (first, err1) = compile(dir.path(), Some(&cache));
    let made = entries(&cache);
    assert_eq!(made.len(), 1, "{made:?}");
    let mtime = std::fs::metadata(&made[0]).unwrap().modified().unwrap();
    let (second, err2) = compile(dir.path(), Some(&cache));
    assert!(
        !err1.contains("warning") && !err2.contains("warning"),
        "{err1}\n{err2}"
    );
    assert_eq!(first, uncached);
    assert_eq!(second, uncached);
    assert_eq!(entries(&cache), made);
    let again = std::fs::metadata(&made[0]).unwrap().modified().unwrap();
    assert_eq!(mtime, again, "a hit does not rewrite the entry");
}

#[test]
fn a_changed_map_file_makes_the_entry_stale_and_it_is_rebuilt() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    write_map(dir.path(), "007");
    compile(dir.path(), Some(&cache));
    write_map(dir.path(), "149");
    let (uncached, _) = compile(dir.path(), None);
    let (cached, err) = compile(dir.path(), Some(&cache));
    assert!(err.contains("is stale; rebuilding it"), "{err}");
    assert_eq!(cached, uncached, "the stale entry was not used");
    let (hit, err) = compile(dir.path(), Some(&cache));
    assert!(!err.contains("warning"), "rebuilt: {err}");
    assert_eq!(hit, uncached);
}

#[test]
fn a_corrupt_or_other_version_entry_is_rebuilt_never_used() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    write_map(dir.path(), "007");
    let (uncached, _) = compile(dir.path(), None);
    compile(dir.path(), Some(&cache));
    let entry = entries(&cache).remove(0);
    let good = std::fs::read(&entry).unwrap();

    // A flipped byte in the room layer: it would change the map, were it used.
    let mut bad = good.clone();
    let mid = bad.len() / 2;
    bad[mid] ^= 0x01;
    std::fs::write(&entry, &bad).unwrap();
    let (route, err) = compile(dir.path(), Some(&cache));
    assert!(err.contains("checksum mismatch"), "{err}");
    assert_eq!(route, uncached);
    assert_eq!(std::fs::read(&entry).unwrap(), good, "rebuilt");

    // A truncated entry, and one of another format version.
    std::fs::write(&entry, &good[..good.len() / 3]).unwrap();
    let (route, err) = compile(dir.path(), Some(&cache));
    assert!(err.contains("cannot be used"), "{err}");
    assert_eq!(route, uncached);
    let mut other = good.clone();
    other[8..12].copy_from_slice(&999u32.to_le_bytes());
    std::fs::write(&entry, &other).unwrap();
    let (route, err) = compile(dir.path(), Some(&cache));
    assert!(err.contains("format version 999"), "{err}");
    assert_eq!(route, uncached);
    assert_eq!(std::fs::read(&entry).unwrap(), good);
}

#[test]
fn eval_scores_the_same_with_and_without_the_cache() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    write_map(dir.path(), "007");
    compile(dir.path(), None);
    let route: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("route.json")).unwrap()).unwrap();
    let traj = route["trajectory"].as_array().unwrap();
    let (a, b) = (traj[0].clone(), traj[traj.len() - 1].clone());
    let pass = |id: &str, c: &serde_json::Value, o: i64| serde_json::json!({"constraint_id": id, "kind": "must_pass", "shape": "freeform", "order": o, "cells": [c]});
    let episode =
        serde_json::json!({"hard_constraints": [pass("start", &a, 1), pass("goal", &b, 2)]});
    std::fs::write(dir.path().join("ep.json"), episode.to_string()).unwrap();
    std::fs::rename(dir.path().join("route.json"), dir.path().join("r.json")).unwrap();
    let args = [
        "eval",
        "--map",
        "map.json",
        "--episode",
        "ep.json",
        "--route",
        "r.json",
        "--any-map",
    ];
    let off = run(&args, dir.path(), None);
    let miss = run(&args, dir.path(), Some(&cache));
    let hit = run(&args, dir.path(), Some(&cache));
    assert_eq!(entries(&cache).len(), 1);
    assert!(off.stdout.contains("HCS  1.000000"), "{}", off.stdout);
    for r in [&miss, &hit] {
        assert_eq!(r.code, off.code, "{}", r.stderr);
        assert_eq!(r.stdout, off.stdout);
    }
}
