//! `m2rc compile` as a user runs it: the route file, the RouteIR and the picture on success; on a
//! program that fails on the map (grounding or planning), exit 1 with diagnostics and not one byte
//! of route written, so an earlier good result is never replaced by a partial one. The one output
//! a failure writes is the one asked for to see it: `--png` draws a plan that failed.

use std::path::{Path, PathBuf};
use std::process::Command;

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

fn m2rc(args: &[&str], cwd: &Path) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_m2rc"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run m2rc");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

fn write_program(dir: &Path, name: &str, source: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, source).unwrap();
    path
}

fn decode_png(path: &Path) -> tiny_skia::Pixmap {
    let bytes = std::fs::read(path).unwrap();
    tiny_skia::Pixmap::decode_png(&bytes)
        .unwrap_or_else(|e| panic!("{} is not a PNG: {e}", path.display()))
}

/// Pixels of exactly this colour (the first route colour is drawn opaque along the line's core).
fn count_color(p: &tiny_skia::Pixmap, rgb: (u8, u8, u8)) -> usize {
    p.pixels()
        .iter()
        .filter(|px| {
            let c = px.demultiply();
            c.alpha() == 255 && (c.red(), c.green(), c.blue()) == rgb
        })
        .count()
}

/// `[row, col]` pairs of a route file.
fn trajectory(v: &serde_json::Value) -> Vec<(i64, i64)> {
    v["trajectory"]
        .as_array()
        .expect("trajectory array")
        .iter()
        .map(|p| (p[0].as_i64().unwrap(), p[1].as_i64().unwrap()))
        .collect()
}

const GOOD: &str = "// map: demo\n\
                    let toilet = objects(toilet).nearest(start)\n\
                    route {\n  go toilet {\n    prefer clearance(0.4m)\n  }\n}\n";

#[test]
fn writes_route_ir_and_picture() {
    let dir = tempfile::tempdir().unwrap();
    let prog = write_program(dir.path(), "good.m2r", GOOD);
    let run = m2rc(
        &[
            "compile",
            prog.to_str().unwrap(),
            "-o",
            "route.json",
            "--png",
            "route.png",
        ],
        dir.path(),
    );
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(run.stdout.contains("route on `"), "{}", run.stdout);

    let route: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("route.json")).unwrap())
            .unwrap();
    let cells = trajectory(&route);
    assert!(cells.len() > 10, "a route of {} cells", cells.len());
    for w in cells.windows(2) {
        let (dr, dc) = ((w[1].0 - w[0].0).abs(), (w[1].1 - w[0].1).abs());
        assert!(
            dr <= 1 && dc <= 1 && (dr, dc) != (0, 0),
            "{w:?} is not a move"
        );
    }
    assert_eq!(route["m2rc"]["status"], "success", "{route}");
    let length = route["m2rc"]["length_m"].as_f64().unwrap();
    assert!(length > 0.5, "length {length}");

    // The picture is the map with the route on top: same renderer as `m2rc map render`, plus
    // many pixels of the first route colour that the bare map does not have.
    let with_route = decode_png(&dir.path().join("route.png"));
    let run = m2rc(&["map", "render", "demo", "-o", "map.png"], dir.path());
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let bare = decode_png(&dir.path().join("map.png"));
    assert!(with_route.width() >= 500 && with_route.height() >= 500);
    let red = (0xd6, 0x28, 0x28);
    let (on_route, on_map) = (count_color(&with_route, red), count_color(&bare, red));
    assert!(
        on_route > on_map + 200,
        "route colour: {on_route} pixels with the route, {on_map} without"
    );

    // `--emit ir`: the RouteIR instead of the route, same program, same map.
    let run = m2rc(
        &[
            "compile",
            prog.to_str().unwrap(),
            "--emit",
            "ir",
            "-o",
            "ir.json",
        ],
        dir.path(),
    );
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    let ir: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("ir.json")).unwrap())
            .unwrap();
    assert_eq!(ir["stages"].as_array().map(Vec::len), Some(1), "{ir}");
    assert_eq!(ir["map_id"], route["m2rc"]["map_id"]);
    let start = &ir["start"];
    assert_eq!(
        (start[0].as_i64().unwrap(), start[1].as_i64().unwrap()),
        cells[0],
        "the route starts at the RouteIR's start"
    );

    // Same inputs, same bytes.
    let run = m2rc(
        &["compile", prog.to_str().unwrap(), "-o", "again.json"],
        dir.path(),
    );
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert_eq!(
        std::fs::read(dir.path().join("route.json")).unwrap(),
        std::fs::read(dir.path().join("again.json")).unwrap()
    );
}

/// Compiles `source` over existing outputs and checks that it fails with `code` and leaves them
/// exactly as they were (and creates no new file in the directory); with `draws`, the picture is
/// the exception: it shows the failed plan.
fn fails_without_touching_outputs(source: &str, code: &str) {
    fails_leaving_the_route_alone(source, code, false);
}

fn fails_leaving_the_route_alone(source: &str, code: &str, draws: bool) {
    let dir = tempfile::tempdir().unwrap();
    let prog = write_program(dir.path(), "bad.m2r", source);
    std::fs::write(dir.path().join("route.json"), b"earlier result").unwrap();
    std::fs::write(dir.path().join("route.png"), b"earlier picture").unwrap();
    let listing = |d: &Path| {
        let mut names: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    let before = listing(dir.path());
    for format in ["text", "json"] {
        let run = m2rc(
            &[
                "compile",
                prog.to_str().unwrap(),
                "-o",
                "route.json",
                "--png",
                "route.png",
                "--format",
                format,
            ],
            dir.path(),
        );
        assert_eq!(run.code, Some(1), "{}\n{}", run.stdout, run.stderr);
        if format == "text" {
            assert!(
                run.stderr.contains(code) && run.stderr.contains("bad.m2r:"),
                "expected {code} in:\n{}",
                run.stderr
            );
        } else {
            let v: serde_json::Value =
                serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("{e}: {}", run.stdout));
            assert!(
                v.as_array()
                    .is_some_and(|a| a.iter().any(|d| d["code"] == code)),
                "expected {code} in {v}"
            );
        }
        assert_eq!(
            std::fs::read(dir.path().join("route.json")).unwrap(),
            b"earlier result"
        );
        if draws {
            let png = decode_png(&dir.path().join("route.png"));
            assert!(png.width() >= 500, "the failed plan is drawn");
            assert!(
                run.stderr.contains("drew the failed plan"),
                "{}",
                run.stderr
            );
        } else {
            assert_eq!(
                std::fs::read(dir.path().join("route.png")).unwrap(),
                b"earlier picture"
            );
        }
        assert_eq!(listing(dir.path()), before, "no temporary file left behind");
    }
}

#[test]
fn ambiguous_reference_fails_at_grounding_and_writes_nothing() {
    // The demo house has three chairs, so `.only()` has no single answer.
    fails_without_touching_outputs(
        "// map: demo\nroute {\n  go objects(chair).only()\n}\n",
        "E0502",
    );
}

#[test]
fn target_cut_off_by_avoids_fails_at_planning_and_draws_only_the_picture() {
    // Avoiding every doorway of the toilet's room leaves no way in.
    fails_leaving_the_route_alone(
        "// map: demo\nlet t = objects(toilet).nearest(start)\nroute {\n  avoid t.room().doorways()\n  go t\n}\n",
        "E0706",
        true,
    );
}

/// The demo's smallest bedroom opens only into the kitchen: avoiding the kitchen cuts it off.
const CUT_OFF: &str = "// map: demo\n\
                       let small = rooms(bedroom).smallest()\n\
                       route {\n  go objects(sofa).only()\n  go objects(bed).in(small).only()\n  \
                       avoid rooms(kitchen).only()\n}\n";

/// E0706 numbers stages as the summary does, says which avoided region cuts the way through
/// which doorway, and the picture shows the failed plan: the avoided kitchen, the unreachable
/// bed, the blocked door (with `--labels`, furniture names too).
#[test]
fn a_failed_plan_says_why_and_is_drawn() {
    let dir = tempfile::tempdir().unwrap();
    let prog = write_program(dir.path(), "cut.m2r", CUT_OFF);
    let run = m2rc(
        &[
            "compile",
            prog.to_str().unwrap(),
            "--png",
            "failed.png",
            "--labels",
        ],
        dir.path(),
    );
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("the destination of stage 2 is unreachable without entering a region"),
        "{}",
        run.stderr
    );
    assert!(!run.stderr.contains("stage 0"), "{}", run.stderr);
    assert!(
        run.stderr
            .contains("bedroom_3's only door opens into the avoided kitchen_1"),
        "{}",
        run.stderr
    );
    let png = decode_png(&dir.path().join("failed.png"));
    // The blocked doorway's outline is drawn in its own dark red.
    assert!(
        count_color(&png, (0x8b, 0x00, 0x00)) > 20,
        "no blocked doorway drawn"
    );
}

/// `--labels` writes furniture categories on the picture, as `map render --labels` does.
#[test]
fn compile_png_takes_labels() {
    let dir = tempfile::tempdir().unwrap();
    let prog = write_program(dir.path(), "good.m2r", GOOD);
    let p = prog.to_str().unwrap();
    let plain = m2rc(&["compile", p, "--png", "plain.png"], dir.path());
    assert_eq!(plain.code, Some(0), "{}", plain.stderr);
    let labelled = m2rc(
        &["compile", p, "--png", "labels.png", "--labels"],
        dir.path(),
    );
    assert_eq!(labelled.code, Some(0), "{}", labelled.stderr);
    let (a, b) = (
        decode_png(&dir.path().join("plain.png")),
        decode_png(&dir.path().join("labels.png")),
    );
    assert_eq!((a.width(), a.height()), (b.width(), b.height()));
    let differ = a
        .pixels()
        .iter()
        .zip(b.pixels())
        .filter(|(x, y)| x != y)
        .count();
    assert!(differ > 500, "the labels are drawn: {differ} pixels differ");
    let run = m2rc(&["compile", p, "--labels"], dir.path());
    assert_eq!(run.code, Some(2), "--labels needs --png: {}", run.stderr);
}

#[test]
fn checker_error_fails_before_the_map_is_used_and_writes_nothing() {
    fails_without_touching_outputs(
        "// map: demo\nroute {\n  go objects(chiar).nearest(start)\n}\n",
        "E0401",
    );
}

#[test]
fn unusable_inputs_are_named_and_exit_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let no_map_line = write_program(
        dir.path(),
        "plain.m2r",
        "route {\n  go objects(bed).nearest(start)\n}\n",
    );
    let plain = no_map_line.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (&["compile", "missing.m2r"], "missing.m2r"),
        (&["compile", plain], "--map"),
        (
            &["compile", plain, "--map", "no-such-map.json"],
            "no-such-map.json",
        ),
        (
            &["compile", plain, "--map", "demo", "--start", "99999,5"],
            "is outside the map",
        ),
    ];
    for (args, named) in cases {
        let run = m2rc(args, dir.path());
        assert!(
            matches!(run.code, Some(1) | Some(2)),
            "{args:?}: exit {:?}",
            run.code
        );
        assert!(run.stderr.contains(named), "{args:?}:\n{}", run.stderr);
        assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    }
    let run = m2rc(
        &["compile", plain, "--map", "demo", "--start", "abc"],
        dir.path(),
    );
    assert_eq!(run.code, Some(2), "a malformed flag is a usage error");
    assert!(run.stderr.contains("x,y"), "{}", run.stderr);
}
