//! A newcomer's stumbles, each answered by the command itself: a program copied out of its suite
//! is told to pass `--map`, and `map check` refuses what is not the house a map was made from.

use crate::common;
use common::*;
use std::path::Path;

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

#[test]
fn a_program_copied_out_of_its_suite_is_told_to_pass_map() {
    let tmp = tempfile::tempdir().unwrap();
    write(
        tmp.path(),
        "p.m2r",
        "// map: procthor/001_valunseen\nroute {\n  go rooms(kitchen).only()\n}\n",
    );
    let r = m2rc(&["compile", "p.m2r"], tmp.path()).expect(2);
    assert!(
        r.stderr
            .contains("--map <suite>/maps/001_valunseen/001_valunseen.json"),
        "{}",
        r.stderr
    );
    // A header path that does not exist gets the general hint.
    write(
        tmp.path(),
        "q.m2r",
        "// map: ../nowhere.json\nroute {\n  go rooms(kitchen).only()\n}\n",
    );
    let r = m2rc(&["compile", "q.m2r"], tmp.path()).expect(2);
    assert!(
        r.stderr.contains("help: the map comes from"),
        "{}",
        r.stderr
    );
    // `--map` wins over the header.
    m2rc(&["compile", "p.m2r", "--map", "demo"], tmp.path()).expect(0);
}

#[test]
fn map_check_refuses_what_is_not_the_house_and_its_help_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let r = m2rc(&["map", "check", "demo"], tmp.path()).expect(2);
    assert!(
        r.stderr.contains("not a ProcTHOR house") && !r.stderr.contains("No such file"),
        "{}",
        r.stderr
    );
    // A Map2Route map where the house belongs: unusable input, status 2.
    m2rc(&["map", "import", "demo", "-o", "demo.json"], tmp.path()).expect(0);
    let r = m2rc(&["map", "check", "demo.json"], tmp.path()).expect(2);
    assert!(r.stderr.contains("not a ProcTHOR house"), "{}", r.stderr);
    let help = m2rc(&["map", "check", "--help"], tmp.path())
        .expect(0)
        .stdout;
    assert!(
        help.contains("HOUSES") && !help.contains("a Map2Route map, `demo`, or"),
        "{help}"
    );
}

#[test]
fn map_check_with_a_map_of_another_house_says_so_instead_of_inventing_defects() {
    let tmp = tempfile::tempdir().unwrap();
    let fx = fixtures();
    let a = fx.join("procthor10k_uniform_hard_val_150_007.json");
    let b = fx.join("procthor10k_uniform_hard_val_150_023.json");
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    m2rc(&["map", "import", a, "-o", "a.json"], tmp.path()).expect(0);
    let r = m2rc(&["map", "check", b, "--maps", "a.json"], tmp.path()).expect(2);
    assert!(
        r.stderr.contains("was not made from this house"),
        "{}",
        r.stderr
    );
    assert!(!r.stdout.contains("misplaced"), "{}", r.stdout);
    // Its own house is checked as before.
    let r = m2rc(&["map", "check", a, "--maps", "a.json"], tmp.path());
    assert!(matches!(r.code, Some(0 | 1)), "{}", r.stderr);
    assert!(r.stdout.contains("houses 1:"), "{}", r.stdout);
}
