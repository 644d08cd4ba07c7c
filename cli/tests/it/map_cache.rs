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

/// An entry without its header (which records when the file's identity was taken) and its CRC.
fn body(entry: &[u8]) -> &[u8] {
    &entry[104..entry.len() - 4]
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
    let before = std::fs::read(&made[0]).unwrap();
    let (second, err2) = compile(dir.path(), Some(&cache));
    assert!(
        !err1.contains("warning") && !err2.contains("warning"),
        "{err1}\n{err2}"
    );
    assert_eq!(first, uncached);
    assert_eq!(second, uncached);
    assert_eq!(entries(&cache), made);
    // A hit rewrites nothing but, once the file is old enough to be trusted by its identity, the
    // identity in the header (the 104 header bytes and the trailing CRC).
    let after = std::fs::read(&made[0]).unwrap();
    assert_eq!(body(&before), body(&after));
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
    assert_eq!(
        body(&std::fs::read(&entry).unwrap()),
        body(&good),
        "rebuilt"
    );

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
    assert_eq!(body(&std::fs::read(&entry).unwrap()), body(&good));
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
    // A clearance preference: its raw value comes from the obstacle distance field, which a hit
    // takes from the prepared map.
    let episode = serde_json::json!({
        "hard_constraints": [pass("start", &a, 1), pass("goal", &b, 2)],
        "soft_constraints": [{"constraint_id": "c", "preference_type": "clearance"}],
    });
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
    assert!(off.stdout.contains("clearance"), "{}", off.stdout);
    for r in [&miss, &hit] {
        assert_eq!(r.code, off.code, "{}", r.stderr);
        assert_eq!(r.stdout, off.stdout);
    }
}

/// Runs compile with `M2RC_TIMINGS=1`; whether the hit took the identity path, and the route.
fn timed_compile(dir: &Path, cache: &Path) -> (bool, serde_json::Value, String) {
    let _ = std::fs::remove_file(dir.join("route.json"));
    let out = Command::new(crate::common::bin())
        .args(["compile", "p.m2r", "--map", "map.json", "-o", "route.json"])
        .current_dir(dir)
        .env("M2RC_MAP_CACHE", cache)
        .env("M2RC_TIMINGS", "1")
        .output()
        .expect("run m2rc");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let route = serde_json::from_slice(&std::fs::read(dir.join("route.json")).unwrap()).unwrap();
    (stderr.contains("identity matched"), route, stderr)
}

#[test]
fn an_entry_trusted_by_the_file_identity_is_still_never_used_for_changed_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    write_map(dir.path(), "007");
    std::fs::write(dir.path().join("p.m2r"), PROGRAM).unwrap();
    // A file modified within a few seconds of the entry is checked by its bytes (racy); an older
    // one by its identity.
    let (by_identity, _, _) = timed_compile(dir.path(), &cache);
    assert!(!by_identity);
    std::thread::sleep(std::time::Duration::from_secs(
        m2rc_benchmark::map_cache::RACY_SECONDS as u64 + 1,
    ));
    timed_compile(dir.path(), &cache);
    let (by_identity, route, err) = timed_compile(dir.path(), &cache);
    assert!(by_identity, "{err}");
    let id = route["m2rc"]["map_id"]
        .as_str()
        .or(route["map_id"].as_str());
    let id = id.expect("route names its map").to_string();

    // Rewrite the map in place, same length, one byte of its id changed, and put its
    // modification time back: only the status-change time (which no program sets) tells.
    let path = dir.path().join("map.json");
    let modified = std::fs::metadata(&path).unwrap().modified().unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let key = format!("\"map_id\": \"{id}\"");
    let at = bytes
        .windows(key.len())
        .position(|w| w == key.as_bytes())
        .unwrap();
    let last = at + key.len() - 2;
    bytes[last] = if bytes[last] == b'x' { b'y' } else { b'x' };
    let f = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
    std::io::Write::write_all(&mut &f, &bytes).unwrap();
    f.set_modified(modified).unwrap();
    drop(f);
    let (by_identity, route, err) = timed_compile(dir.path(), &cache);
    assert!(!by_identity, "{err}");
    assert!(err.contains("is stale; rebuilding it"), "{err}");
    let new_id = route["m2rc"]["map_id"]
        .as_str()
        .or(route["map_id"].as_str());
    assert_ne!(new_id, Some(id.as_str()), "the stale entry was not used");
}

/// Every record file under `dir`, by its path below `dir`, with its bytes.
fn records(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for map in std::fs::read_dir(dir).unwrap().flatten() {
        if !map.path().is_dir() || map.file_name() == "llm-cache" {
            continue;
        }
        for f in std::fs::read_dir(map.path()).unwrap().flatten() {
            let rel = f.path().strip_prefix(dir).unwrap().to_path_buf();
            out.push((rel, std::fs::read(f.path()).unwrap()));
        }
    }
    out.sort();
    out
}

#[test]
fn bench_run_loads_each_map_through_the_cache_and_writes_the_same_records() {
    let suite = crate::common::suite(3);
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let bench = |out: &str, cache: Option<&Path>| {
        let args = [
            "bench",
            "run",
            "--suite",
            suite.to_str().unwrap(),
            "--method",
            "oracle",
            "--out",
            out,
        ];
        run(&args, dir.path(), cache).expect(0);
        records(&dir.path().join(out))
    };
    let off = bench("off", None);
    assert!(!off.is_empty());
    let miss = bench("miss", Some(&cache));
    let made = entries(&cache);
    assert_eq!(made.len(), 1, "one map, one entry: {made:?}");
    let hit = bench("hit", Some(&cache));
    assert_eq!(miss, off);
    assert_eq!(hit, off);
}
