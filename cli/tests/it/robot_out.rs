//! `--emit nav-path|waypoints|geojson|mcap`: the route in the map frame, read back by
//! independent readers (PyYAML, the `mcap` and `rosbags` Python packages, through
//! `scripts/robot-roundtrip.sh`), and the outputs' own rules checked here.

use crate::common::{bin, m2rc};
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every format read back by its independent reader, on the demo house and a multi-stage
/// program (so stage goals and turns are checked). Skips, loudly, only when the readers cannot
/// be installed on this machine.
#[test]
fn every_robot_format_reads_back_onto_the_route_cells() {
    let dir = tempfile::tempdir().unwrap();
    for program in [
        "examples/01_smallest_bathroom.m2r",
        "examples/09_every_bathroom.m2r",
    ] {
        let out = dir.path().join(program.replace(['/', '.'], "_"));
        std::fs::create_dir_all(&out).unwrap();
        let run = Command::new(repo().join("scripts/robot-roundtrip.sh"))
            .arg(bin())
            .arg("demo")
            .arg(repo().join(program))
            .arg(&out)
            .output()
            .expect("run scripts/robot-roundtrip.sh");
        let stdout = String::from_utf8_lossy(&run.stdout);
        let stderr = String::from_utf8_lossy(&run.stderr);
        if run.status.code() == Some(77) {
            eprintln!(
                "\n!!!!!!!! SKIPPED: the independent readers (PyPI mcap, rosbags, pyyaml) \
                 cannot be installed here:\n{stderr}\n!!!!!!!!"
            );
            return;
        }
        assert!(
            run.status.success() && stdout.contains(", 0 failed"),
            "{program}:\n{stdout}\n{stderr}"
        );
    }
}

#[test]
fn mcap_needs_an_output_file_and_text_formats_go_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let root = repo();
    let prog = root.join("examples/01_smallest_bathroom.m2r");
    let prog = prog.to_str().unwrap();
    let r = m2rc(
        &["compile", prog, "--map", "demo", "--emit", "mcap"],
        dir.path(),
    )
    .expect(2);
    assert!(r.stderr.contains("-o route.mcap"), "{}", r.stderr);
    let r = m2rc(
        &["compile", prog, "--map", "demo", "--emit", "nav-path"],
        dir.path(),
    )
    .expect(0);
    assert!(r.stdout.contains("poses:\n  - header:"), "{}", r.stdout);
    assert!(r.stdout.contains("frame_id: map"), "{}", r.stdout);
}

#[test]
fn robot_outputs_are_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let prog = repo().join("examples/09_every_bathroom.m2r");
    let prog = prog.to_str().unwrap();
    for emit in ["mcap", "geojson", "waypoints"] {
        let mut bytes = Vec::new();
        for k in 0..2 {
            let out = dir.path().join(format!("{emit}{k}"));
            let o = out.to_str().unwrap();
            m2rc(
                &["compile", prog, "--map", "demo", "--emit", emit, "-o", o],
                dir.path(),
            )
            .expect(0);
            bytes.push(std::fs::read(&out).unwrap());
        }
        assert_eq!(bytes[0], bytes[1], "--emit {emit} differs between two runs");
    }
}

#[test]
fn eval_takes_no_start_and_says_how_to_score_from_one() {
    let dir = tempfile::tempdir().unwrap();
    for (flag, value) in [("--start", "-1.5,2.0"), ("--start-cell", "3,4")] {
        let r = m2rc(
            &[
                "eval",
                "--map",
                "demo",
                "--episode",
                "ep.json",
                "--route",
                "r.json",
                flag,
                value,
            ],
            dir.path(),
        )
        .expect(2);
        assert!(r.stderr.contains("takes no start"), "{}", r.stderr);
        assert!(
            r.stderr.contains(&format!(
                "m2rc compile PROGRAM.m2r --map MAP --episode EPISODE.json {flag}"
            )),
            "{}",
            r.stderr
        );
    }
}
