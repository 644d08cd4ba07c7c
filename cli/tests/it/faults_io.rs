//! Fault injection on the CLI's input and output: closed standard output, outputs that are
//! links, directories or devices, `-` for standard input and output, exit statuses, limits.

use crate::common;
use common::*;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};

const GOOD: &str = "// map: demo\nlet k = rooms(kitchen).only()\nroute {\n  go k\n}\n";

/// Runs m2rc with its standard output closed before it writes: it must end quietly.
fn closed_stdout(args: &[&str], cwd: &Path) {
    let mut child = Command::new(bin())
        .args(args)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let status = child.wait().unwrap();
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert_eq!(status.code(), Some(0), "{args:?}: {err}");
}

#[test]
fn every_printing_command_exits_quietly_on_a_closed_pipe() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("p.m2r"), GOOD).unwrap();
    let run = tmp.path().join("run");
    bench_run(suite(3), "shortest", &run, &[]).expect(0);
    let s = suite(3).to_str().unwrap();
    let r = run.to_str().unwrap();
    for args in [
        vec!["compile", "p.m2r", "--emit", "ir"],
        vec!["compile", "p.m2r"],
        vec!["compile", "p.m2r", "--format", "json"],
        vec!["check", "p.m2r", "--format", "json"],
        vec!["map", "info", "demo"],
        vec!["map", "info", "demo", "--format", "json"],
        vec!["map", "import", "demo", "-o", "-"],
        vec!["suite", "stats", s],
        vec!["bench", "report", r],
        vec!["bench", "report", r, "--format", "json"],
        vec!["--help"],
    ] {
        closed_stdout(&args, tmp.path());
    }
}

#[test]
fn outputs_write_through_links_and_never_replace_devices_or_directories() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("p.m2r"), GOOD).unwrap();
    // A symbolic link: its target is rewritten, the link stays a link.
    std::fs::write(tmp.path().join("real.json"), b"old").unwrap();
    std::os::unix::fs::symlink("real.json", tmp.path().join("link.json")).unwrap();
    m2rc(&["compile", "p.m2r", "-o", "link.json"], tmp.path()).expect(0);
    assert!(
        std::fs::symlink_metadata(tmp.path().join("link.json"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
    let v = read_json(&tmp.path().join("real.json"));
    assert!(v["trajectory"].as_array().is_some_and(|t| !t.is_empty()));
    // A directory and a device are refused and left alone.
    std::fs::create_dir(tmp.path().join("dir")).unwrap();
    let r = m2rc(&["compile", "p.m2r", "-o", "dir"], tmp.path()).expect(1);
    assert!(r.stderr.contains("is a directory"), "{}", r.stderr);
    assert!(tmp.path().join("dir").is_dir());
    let r = m2rc(&["compile", "p.m2r", "-o", "/dev/null"], tmp.path()).expect(1);
    assert!(r.stderr.contains("not a regular file"), "{}", r.stderr);
    assert!(!std::fs::metadata("/dev/null").unwrap().is_file());
    // `-o -` streams to standard output; the summary goes to standard error.
    let r = m2rc(&["compile", "p.m2r", "-o", "-"], tmp.path()).expect(0);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    assert!(v["trajectory"].is_array());
    assert!(r.stderr.contains("route on"), "{}", r.stderr);
    let r = m2rc(&["compile", "p.m2r", "--emit", "ir", "-o", "-"], tmp.path()).expect(0);
    let v: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    assert!(v["stages"].is_array(), "{v}");
}

#[test]
fn dash_reads_standard_input_wherever_a_file_is_read() {
    let tmp = tempfile::tempdir().unwrap();
    let r = m2rc_in(
        &["compile", "-", "--map", "demo", "-o", "route.json"],
        tmp.path(),
        GOOD.as_bytes(),
    )
    .expect(0);
    assert!(r.stdout.contains("route on"), "{}", r.stdout);
    m2rc_in(&["check", "-"], tmp.path(), GOOD.as_bytes()).expect(0);
    m2rc_in(&["fmt", "-"], tmp.path(), GOOD.as_bytes()).expect(0);
    // A map on standard input.
    m2rc(&["map", "import", "demo", "-o", "demo.json"], tmp.path()).expect(0);
    let map = std::fs::read(tmp.path().join("demo.json")).unwrap();
    let r = m2rc_in(&["map", "info", "-"], tmp.path(), &map).expect(0);
    assert!(r.stdout.contains("rooms"), "{}", r.stdout);
    std::fs::write(
        tmp.path().join("p.m2r"),
        "let k = rooms(kitchen).only()\nroute { go k }\n",
    )
    .unwrap();
    m2rc_in(&["compile", "p.m2r", "--map", "-"], tmp.path(), &map).expect(0);
    m2rc_in(&["check", "p.m2r", "--map", "-"], tmp.path(), &map).expect(0);
    // Houses on standard input, plain or gzip, give the same episodes as the file itself.
    let house = fixtures().join("procthor10k_uniform_hard_val_150_149.json");
    let assets = fixtures().join("../assets/asset-database.json");
    let build = |houses: &str, out: &str, stdin: &[u8]| {
        let args = [
            "suite",
            "build",
            "--houses",
            houses,
            "--assets",
            assets.to_str().unwrap(),
            "--scenes",
            "1",
            "--dev-scenes",
            "0",
            "--episodes-per-scene",
            "2",
            "--out",
            out,
        ];
        m2rc_in(&args, tmp.path(), stdin).expect(0);
    };
    let bytes = std::fs::read(&house).unwrap();
    build(house.to_str().unwrap(), "from-file", b"");
    build("-", "from-stdin", &bytes);
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, &bytes).unwrap();
    build("-", "from-gzip", &gz.finish().unwrap());
    let instructions = |dir: &str| {
        let root = tmp.path().join(dir).join("instructions");
        let mut files = Vec::new();
        for scene in std::fs::read_dir(&root).unwrap() {
            let d = scene.unwrap().path().join("instruction_files");
            for f in std::fs::read_dir(d).unwrap() {
                // Everything but the provenance line that names where the house came from.
                let mut v = read_json(&f.unwrap().path());
                v["m2rc_generation"]["house"] = serde_json::Value::Null;
                files.push(v.to_string());
            }
        }
        files.sort();
        files
    };
    assert!(!instructions("from-file").is_empty());
    assert_eq!(instructions("from-file"), instructions("from-stdin"));
    assert_eq!(instructions("from-file"), instructions("from-gzip"));
    let manifest = read_json(&tmp.path().join("from-stdin/suite.json"));
    assert_eq!(manifest["houses"], "<stdin>", "{manifest}");
    let r = m2rc_in(
        &["suite", "build", "--houses", "-", "--out", "bad"],
        tmp.path(),
        b"{\"rooms\": 3}",
    );
    assert!(matches!(r.code, Some(1 | 2)), "{:?}", r.code);
    assert!(r.stderr.contains("<stdin>: field `rooms`"), "{}", r.stderr);
    // Only one `-` per command.
    let r = m2rc_in(&["compile", "-", "--map", "-"], tmp.path(), GOOD.as_bytes()).expect(2);
    assert!(
        r.stderr.contains("only one input can be `-`"),
        "{}",
        r.stderr
    );
}

#[test]
fn exit_status_is_2_for_unusable_input_and_1_for_input_found_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("p.m2r"), GOOD).unwrap();
    std::fs::write(
        tmp.path().join("bad.m2r"),
        "// map: demo\nroute { go objects(chiar).first() }\n",
    )
    .unwrap();
    std::fs::write(tmp.path().join("x.json"), b"{not json").unwrap();
    m2rc(&["compile", "missing.m2r"], tmp.path()).expect(2);
    m2rc(&["compile", "bad.m2r"], tmp.path()).expect(1);
    m2rc(&["check", "missing.m2r"], tmp.path()).expect(2);
    m2rc(&["check", "bad.m2r"], tmp.path()).expect(1);
    m2rc(&["compile", "p.m2r", "--map", "x.json"], tmp.path()).expect(2);
    m2rc(&["map", "info", "x.json"], tmp.path()).expect(2);
    m2rc(
        &[
            "eval",
            "--map",
            "demo",
            "--episode",
            "x.json",
            "--route",
            "x.json",
        ],
        tmp.path(),
    )
    .expect(2);
    m2rc(&["bench", "report", "nowhere"], tmp.path()).expect(2);
    m2rc(&["compile", "p.m2r", "--planner", "nope"], tmp.path()).expect(2);
    let r = m2rc(&["--help"], tmp.path()).expect(0);
    assert!(
        r.stdout.contains("Exit status") && r.stdout.contains("2 an input cannot be used"),
        "{}",
        r.stdout
    );
}

#[test]
fn a_start_outside_the_grid_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("p.m2r"), GOOD).unwrap();
    let r = m2rc(&["compile", "p.m2r", "--start", "5000,3"], tmp.path()).expect(2);
    assert!(
        r.stderr.contains("--start 5000,3 is outside the map"),
        "{}",
        r.stderr
    );
    assert!(!r.stderr.contains("not traversable"), "{}", r.stderr);
}

#[test]
fn routes_and_programs_past_the_documented_limits_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let many = format!(
        "// map: demo\nroute {{\n{}}}\n",
        "  go rooms(kitchen).only()\n".repeat(201)
    );
    std::fs::write(tmp.path().join("many.m2r"), many).unwrap();
    let r = m2rc(&["compile", "many.m2r"], tmp.path()).expect(2);
    assert!(
        r.stderr.contains("more than the limit of 200"),
        "{}",
        r.stderr
    );
    let (m, _, ep, _) = &episodes(suite(3))[0];
    let map = suite(3).join("maps").join(m).join(format!("{m}.json"));
    let route: Vec<[u32; 2]> = vec![[1, 1]; 100_001];
    std::fs::write(
        tmp.path().join("r.json"),
        serde_json::to_vec(&route).unwrap(),
    )
    .unwrap();
    let r = m2rc(
        &[
            "eval",
            "--map",
            map.to_str().unwrap(),
            "--episode",
            ep.to_str().unwrap(),
            "--route",
            "r.json",
        ],
        tmp.path(),
    )
    .expect(2);
    assert!(
        r.stderr.contains("more than the limit of 100000"),
        "{}",
        r.stderr
    );
}

/// A house in the ProcTHOR layout finds its asset database beside the houses folder, as `suite
/// build` does, so `map import` and `--assets` agree; a house elsewhere says that sizes come from
/// the built-in table.
#[test]
fn houses_find_their_asset_database_or_say_they_did_not() {
    let tmp = tempfile::tempdir().unwrap();
    let house = fixtures().join("procthor10k_uniform_hard_val_150_029.json");
    let house = if house.exists() {
        house
    } else {
        fixtures().join("procthor10k_uniform_hard_val_150_149.json")
    };
    let assets = fixtures().join("../assets/asset-database.json");
    let h = house.to_str().unwrap();
    let found = m2rc(&["map", "import", h, "-o", "found.json"], tmp.path()).expect(0);
    assert!(
        !found.stderr.contains("no asset database"),
        "{}",
        found.stderr
    );
    let given = &[
        "map",
        "import",
        h,
        "--assets",
        assets.to_str().unwrap(),
        "-o",
        "given.json",
    ];
    m2rc(given, tmp.path()).expect(0);
    assert_eq!(
        std::fs::read(tmp.path().join("found.json")).unwrap(),
        std::fs::read(tmp.path().join("given.json")).unwrap()
    );
    std::fs::copy(&house, tmp.path().join("alone.json")).unwrap();
    let alone = m2rc(
        &["map", "import", "alone.json", "-o", "alone-map.json"],
        tmp.path(),
    )
    .expect(0);
    assert!(
        alone.stderr.contains("no asset database"),
        "{}",
        alone.stderr
    );
    let info = m2rc(&["map", "info", "alone.json"], tmp.path()).expect(0);
    assert!(info.stderr.contains("built-in table"), "{}", info.stderr);
}
