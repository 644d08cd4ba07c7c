//! Outputs never overwrite inputs: `bench merge --out` one of its own shards and `bench run --out`
//! a suite are refused (exit 2) before anything is written; `map import -o -` writes standard
//! output, not a file named `-`.

use crate::common;
use common::*;
use std::path::Path;

fn tree_bytes(dir: &Path) -> Vec<(std::path::PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push((p.clone(), std::fs::read(&p).unwrap()));
            }
        }
    }
    out.sort();
    out
}

#[test]
fn merge_into_one_of_its_own_shards_is_refused_and_the_shard_left_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let s1 = tmp.path().join("runs/x.shard1");
    let s2 = tmp.path().join("runs/x.shard2");
    bench_run(suite(3), "shortest", &s1, &["--shard", "1/2"]).expect(0);
    bench_run(suite(3), "shortest", &s2, &["--shard", "2/2"]).expect(0);
    let before = tree_bytes(&s1);
    for out in [
        "runs/x.shard1",
        "runs/x.shard2/../x.shard1",
        "runs",
        "runs/x.shard1/all",
    ] {
        let r = m2rc(
            &[
                "bench",
                "merge",
                "runs/x.shard1",
                "runs/x.shard2",
                "--out",
                out,
            ],
            tmp.path(),
        )
        .expect(2);
        assert!(
            r.stderr.contains("an output never overwrites an input")
                && r.stderr.contains("runs/x.shard1"),
            "{out}: {}",
            r.stderr
        );
    }
    assert_eq!(tree_bytes(&s1), before);
    assert!(!tmp.path().join("runs/run.json").exists());
    // A new directory is still fine.
    m2rc(
        &[
            "bench",
            "merge",
            "runs/x.shard1",
            "runs/x.shard2",
            "--out",
            "runs/x",
        ],
        tmp.path(),
    )
    .expect(0);
}

#[test]
fn a_run_into_a_suite_directory_is_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let s = tmp.path().join("suite");
    copy_dir(suite(3), &s);
    let before = tree_bytes(&s);
    for out in [s.clone(), s.join("runs/oracle"), s.join("maps")] {
        let r = bench_run(&s, "shortest", &out, &[]).expect(2);
        assert!(
            r.stderr.contains("suite") && r.stderr.contains("--out"),
            "{}: {}",
            out.display(),
            r.stderr
        );
    }
    assert_eq!(tree_bytes(&s), before, "the suite was written into");
    // Another suite's directory is refused as well.
    let other = tmp.path().join("other");
    copy_dir(suite(3), &other);
    let r = bench_run(&s, "shortest", &other, &[]).expect(2);
    assert!(r.stderr.contains("holds suite.json"), "{}", r.stderr);
    bench_run(&s, "shortest", &tmp.path().join("runs/shortest"), &[]).expect(0);
}

#[test]
fn map_import_to_dash_writes_standard_output() {
    let tmp = tempfile::tempdir().unwrap();
    let r = m2rc(&["map", "import", "demo", "-o", "-"], tmp.path()).expect(0);
    assert!(
        !tmp.path().join("-").exists(),
        "a file named `-` was written"
    );
    let v: serde_json::Value = serde_json::from_str(&r.stdout).expect("a map on stdout");
    assert!(
        v["grid_size"].as_u64().is_some_and(|n| n > 0),
        "{}",
        r.stdout
    );
    assert!(r.stderr.contains("standard output"), "{}", r.stderr);
    // The same bytes as a file import.
    m2rc(&["map", "import", "demo", "-o", "demo.json"], tmp.path()).expect(0);
    assert_eq!(
        std::fs::read(tmp.path().join("demo.json")).unwrap(),
        r.stdout.as_bytes()
    );
}
