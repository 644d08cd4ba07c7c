//! Fault injection on run directories (`bench run`): fingerprints, the directory lock, record
//! validation on resume, leftover temporary files, and records independent of the suite path.

use crate::common;
use common::*;

#[test]
fn a_run_into_a_directory_of_another_suite_or_method_is_refused_saying_what_differs() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    copy_dir(suite(3), &a);
    copy_dir(suite(4), &b);
    let out = tmp.path().join("run");
    bench_run(&a, "shortest", &out, &[]).expect(0);
    // Same suite name, other seed: refused, not "already done".
    let r = bench_run(&b, "shortest", &out, &[]).expect(1);
    assert!(r.stderr.contains("the suite differs"), "{}", r.stderr);
    // Another method: refused, naming the method configuration.
    let r = bench_run(&a, "hard-only", &out, &[]).expect(1);
    assert!(
        r.stderr.contains("method configuration differs"),
        "{}",
        r.stderr
    );
    // An edited episode file changes the suite fingerprint too.
    let (_, _, file, _) = &episodes(&a)[0];
    let mut ep = read_json(file);
    ep["instruction"] = serde_json::json!("Go somewhere else.");
    write_json(file, &ep);
    let r = bench_run(&a, "shortest", &out, &[]).expect(1);
    assert!(r.stderr.contains("the suite differs"), "{}", r.stderr);
}

#[test]
fn a_second_writer_is_refused_while_a_run_holds_the_lock() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let held = m2rc_benchmark::rundir::RunLock::acquire(&out).unwrap();
    let r = bench_run(suite(3), "shortest", &out, &[]).expect(1);
    assert!(r.stderr.contains("another m2rc process"), "{}", r.stderr);
    assert!(!out.join("run.json").exists());
    drop(held);
    bench_run(suite(3), "shortest", &out, &[]).expect(0);
}

#[test]
fn invalid_records_are_recomputed_on_resume_with_a_warning_naming_them() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    bench_run(suite(3), "shortest", &out, &[]).expect(0);
    let eps = episodes(suite(3));
    let paths: Vec<_> = eps.iter().map(|(m, i, _, _)| record(&out, m, i)).collect();
    let originals: Vec<Vec<u8>> = paths.iter().map(|p| std::fs::read(p).unwrap()).collect();

    // 0: an empty trajectory; 1: another episode's (valid) record; 2: an edited HCS.
    let mut r0 = read_json(&paths[0]);
    r0["trajectory"] = serde_json::json!([]);
    write_json(&paths[0], &r0);
    std::fs::write(&paths[1], &originals[2]).unwrap();
    let mut r2 = read_json(&paths[2]);
    r2["metrics"]["HCS"] = serde_json::json!(0.5);
    r2["metrics_summary"]["HCS"] = serde_json::json!(0.5);
    write_json(&paths[2], &r2);

    let r = bench_run(suite(3), "shortest", &out, &[]).expect(0);
    for (p, why) in paths
        .iter()
        .zip(["trajectory", "record of instruction", "changed"])
    {
        let name = p.display().to_string();
        assert!(
            r.stderr
                .lines()
                .any(|l| l.contains("warning: recomputed") && l.contains(&name) && l.contains(why)),
            "no warning for {name} ({why}):\n{}",
            r.stderr
        );
    }
    assert!(r.stdout.contains("3 recomputed"), "{}", r.stdout);
    for (p, o) in paths.iter().zip(&originals) {
        assert_eq!(
            &std::fs::read(p).unwrap(),
            o,
            "{} not restored",
            p.display()
        );
    }
}

#[test]
fn leftover_temporary_files_are_removed_on_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    bench_run(suite(3), "shortest", &out, &[]).expect(0);
    let (map_id, _, _, _) = &episodes(suite(3))[0];
    let junk = out
        .join(map_id)
        .join(".instruction_000001.json.tmp999.ThreadId(7)");
    std::fs::write(&junk, b"{\"half").unwrap();
    let r = bench_run(suite(3), "shortest", &out, &[]).expect(0);
    assert!(!junk.exists());
    assert!(
        r.stderr.contains("removed 1 temporary file"),
        "{}",
        r.stderr
    );
}

#[test]
fn records_do_not_depend_on_the_path_the_suite_was_named_by() {
    let tmp = tempfile::tempdir().unwrap();
    let suite_dir = tmp.path().join("s");
    copy_dir(suite(3), &suite_dir);
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    bench_run(&suite_dir, "shortest", &one, &[]).expect(0);
    // Through a relative path with a detour, from another working directory.
    std::fs::create_dir_all(tmp.path().join("w")).unwrap();
    m2rc(
        &[
            "bench",
            "run",
            "--suite",
            "../w/../s",
            "--method",
            "shortest",
            "--out",
            "../two",
            "--threads",
            "1",
        ],
        &tmp.path().join("w"),
    )
    .expect(0);
    for (m, i, _, _) in episodes(&suite_dir) {
        assert_eq!(
            std::fs::read(record(&one, &m, &i)).unwrap(),
            std::fs::read(record(&two, &m, &i)).unwrap()
        );
    }
    assert_eq!(
        std::fs::read(one.join("run.json")).unwrap(),
        std::fs::read(two.join("run.json")).unwrap()
    );
    let text = std::fs::read_to_string(one.join("run.json")).unwrap();
    assert!(!text.contains(tmp.path().to_str().unwrap()), "{text}");
}

#[test]
fn threads_are_capped_to_the_machine() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let r = bench_run(suite(3), "shortest", &out, &["--threads", "100000"]).expect(0);
    assert!(
        r.stderr.contains("--threads 100000 is more than the"),
        "{}",
        r.stderr
    );
    let r = bench_run(suite(3), "shortest", &out, &["--threads", "0"]).expect(2);
    assert!(r.stderr.contains("at least 1"), "{}", r.stderr);
}
