//! Fault injection on `bench report` and `bench merge`: incomplete runs, foreign or tampered
//! records, directories named twice, shards beside their merge, missing or unfinished shards.

use crate::common;
use common::*;
use std::path::Path;

fn report(dirs: &[&Path], extra: &[&str], cwd: &Path) -> Run {
    let mut args: Vec<String> = vec!["bench".into(), "report".into()];
    args.extend(dirs.iter().map(|d| d.display().to_string()));
    args.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    m2rc(&refs, cwd)
}

#[test]
fn an_incomplete_run_is_refused_unless_allowed_and_then_the_table_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("oracle");
    bench_run(suite(3), "shortest", &out, &[]).expect(0);
    let eps = episodes(suite(3));
    let (m, i, _, _) = &eps[0];
    std::fs::remove_file(record(&out, m, i)).unwrap();
    let r = report(&[&out], &[], tmp.path()).expect(1);
    assert!(
        r.stderr.contains("has 2 of 3 episodes") && r.stderr.contains("--allow-incomplete"),
        "{}",
        r.stderr
    );
    let r = report(&[&out], &["--allow-incomplete"], tmp.path()).expect(0);
    assert!(r.stdout.contains("shortest: 2 / 3"), "{}", r.stdout);
    assert!(r.stdout.contains("INCOMPLETE"), "{}", r.stdout);
    let r = report(
        &[&out],
        &["--allow-incomplete", "--format", "json"],
        tmp.path(),
    )
    .expect(0);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    assert_eq!(v["methods"][0]["episodes_present"], 2);
    assert_eq!(v["methods"][0]["episodes_expected"], 3);
}

#[test]
fn a_complete_report_states_present_and_expected() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("s");
    bench_run(suite(3), "shortest", &out, &[]).expect(0);
    let r = report(&[&out], &[], tmp.path()).expect(0);
    assert!(
        r.stdout.contains("shortest: 3 / 3") && !r.stdout.contains("INCOMPLETE"),
        "{}",
        r.stdout
    );
}

#[test]
fn tampered_and_foreign_records_are_refused_by_the_report() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("s");
    bench_run(suite(3), "shortest", &out, &[]).expect(0);
    let eps = episodes(suite(3));
    let p = record(&out, &eps[1].0, &eps[1].1);
    let good = std::fs::read(&p).unwrap();
    let mut v = read_json(&p);
    v["metrics"]["HCS"] = serde_json::json!(0.0);
    v["metrics_summary"]["HCS"] = serde_json::json!(0.0);
    write_json(&p, &v);
    let r = report(&[&out], &[], tmp.path()).expect(1);
    assert!(
        r.stderr.contains(&p.display().to_string()) && r.stderr.contains("invalid record"),
        "{}",
        r.stderr
    );
    // Another episode's record in its place.
    std::fs::write(
        &p,
        std::fs::read(record(&out, &eps[0].0, &eps[0].1)).unwrap(),
    )
    .unwrap();
    let r = report(&[&out], &[], tmp.path()).expect(1);
    assert!(r.stderr.contains("but it is stored as"), "{}", r.stderr);
    // A record of an episode the run does not cover.
    std::fs::write(&p, &good).unwrap();
    let stray = out.join(&eps[0].0).join("instruction_000999.json");
    std::fs::write(&stray, &good).unwrap();
    let r = report(&[&out], &[], tmp.path()).expect(1);
    assert!(
        r.stderr.contains("not an episode of this run"),
        "{}",
        r.stderr
    );
    std::fs::remove_file(&stray).unwrap();
    // A truncated record.
    std::fs::write(&p, &good[..good.len() / 2]).unwrap();
    let r = report(&[&out], &[], tmp.path()).expect(1);
    assert!(r.stderr.contains("not valid JSON"), "{}", r.stderr);
}

#[test]
fn the_same_directory_twice_and_shards_beside_their_merge_count_once() {
    let tmp = tempfile::tempdir().unwrap();
    let runs = tmp.path().join("runs");
    let full = runs.join("shortest");
    bench_run(suite(3), "shortest", &full, &[]).expect(0);
    let once = report(&[&full], &["--format", "csv"], tmp.path())
        .expect(0)
        .stdout;
    let twice = m2rc(
        &[
            "bench",
            "report",
            "runs/shortest",
            "runs/./shortest",
            full.to_str().unwrap(),
            "--format",
            "csv",
        ],
        tmp.path(),
    )
    .expect(0)
    .stdout;
    assert_eq!(once, twice);
    // The documented layout: runs/oracle.shard* beside the merged runs/oracle, then runs/*.
    for k in 1..=2 {
        let shard = format!("{k}/2");
        bench_run(
            suite(3),
            "shortest",
            &runs.join(format!("shortest.shard{k}")),
            &["--shard", &shard],
        )
        .expect(0);
    }
    let all: Vec<std::path::PathBuf> = std::fs::read_dir(&runs)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .collect();
    assert_eq!(all.len(), 3);
    let refs: Vec<&Path> = all.iter().map(|p| p.as_path()).collect();
    let star = report(&refs, &["--format", "csv"], tmp.path())
        .expect(0)
        .stdout;
    assert_eq!(star, once);
}

#[test]
fn merge_needs_every_shard_complete_and_of_one_fingerprint() {
    let tmp = tempfile::tempdir().unwrap();
    let shard = |k: usize, s: &Path| {
        let tag = if s == suite(3) { "a" } else { "b" };
        let d = tmp.path().join(format!("sh{k}-{tag}"));
        bench_run(s, "shortest", &d, &["--shard", &format!("{k}/3")]).expect(0);
        d
    };
    let (s1, s2, s3) = (shard(1, suite(3)), shard(2, suite(3)), shard(3, suite(3)));
    let merge = |dirs: &[&Path], out: &str| {
        let mut args = vec!["bench", "merge"];
        let names: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
        args.extend(names.iter().map(String::as_str));
        args.extend(["--out", out]);
        m2rc(&args, tmp.path())
    };
    // Two of three shards.
    let r = merge(&[&s1, &s2], "m1").expect(1);
    assert!(r.stderr.contains("shard(s) 3/3"), "{}", r.stderr);
    assert!(!tmp.path().join("m1/run.json").exists());
    // An unfinished shard.
    let eps = episodes(suite(3));
    let p3 = record(&s3, &eps[2].0, &eps[2].1);
    let bytes = std::fs::read(&p3).unwrap();
    std::fs::remove_file(&p3).unwrap();
    let r = merge(&[&s1, &s2, &s3], "m2").expect(1);
    assert!(r.stderr.contains("is incomplete"), "{}", r.stderr);
    // A truncated record.
    std::fs::write(&p3, &bytes[..bytes.len() - 10]).unwrap();
    let r = merge(&[&s1, &s2, &s3], "m3").expect(1);
    assert!(r.stderr.contains("invalid record"), "{}", r.stderr);
    std::fs::write(&p3, &bytes).unwrap();
    // A shard of another suite.
    let other = shard(3, suite(4));
    let r = merge(&[&s1, &s2, &other], "m4").expect(1);
    assert!(r.stderr.contains("the suite differs"), "{}", r.stderr);
    // All three: the merge equals an unsharded run, run.json included.
    merge(&[&s1, &s2, &s3], "m5").expect(0);
    let single = tmp.path().join("single");
    bench_run(suite(3), "shortest", &single, &[]).expect(0);
    for (m, i, _, _) in &eps {
        assert_eq!(
            std::fs::read(record(&single, m, i)).unwrap(),
            std::fs::read(record(&tmp.path().join("m5"), m, i)).unwrap()
        );
    }
    assert_eq!(
        read_json(&single.join("run.json")),
        read_json(&tmp.path().join("m5/run.json"))
    );
    report(&[&tmp.path().join("m5")], &[], tmp.path()).expect(0);
}
