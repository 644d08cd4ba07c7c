//! `m2rc baseline explain`: the start is given as `compile` and `run` take it, and a backend
//! that needs an episode is refused with the command that has one.

use crate::common::*;

fn explain(extra: &[&str]) -> Run {
    let tmp = tempfile::tempdir().unwrap();
    let mut args = vec![
        "baseline", "explain", "--method", "sayplan", "--map", "demo",
    ];
    args.extend_from_slice(extra);
    args.push("go to the sofa");
    m2rc(&args, tmp.path())
}

#[test]
fn gold_and_simulated_replies_are_refused_without_an_episode() {
    for backend in ["gold", "simulated:0.5:1"] {
        let r = explain(&["--llm", backend]).expect(2);
        assert!(
            r.stderr.contains("bench run --method sayplan"),
            "{}",
            r.stderr
        );
    }
}

#[test]
fn the_start_is_metres_or_a_cell_as_in_compile() {
    let r = explain(&[
        "--start-cell",
        "0,0",
        "--llm-base-url",
        "http://127.0.0.1:9/v1",
    ])
    .expect(2);
    assert!(
        r.stderr.contains("start cell 0,0 is not a free cell"),
        "{}",
        r.stderr
    );
    let r = explain(&[
        "--start",
        "1e6,1e6",
        "--llm-base-url",
        "http://127.0.0.1:9/v1",
    ])
    .expect(2);
    assert!(r.stderr.contains("is outside the map"), "{}", r.stderr);
    assert!(!r.stderr.contains("   "), "{}", r.stderr);
    let r = explain(&["--start", "1,2", "--start-cell", "3,4"]).expect(2);
    assert!(r.stderr.contains("cannot be used with"), "{}", r.stderr);
}
