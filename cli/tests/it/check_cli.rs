//! `m2rc check` as a user runs it: exit 0 on a clean program, 1 with errors, 2 when the input cannot
//! be read, and never a panic, whatever bytes the file holds; `ok: N bindings, M stages` on success,
//! and `--fix` applying the suggestions the diagnostics carry.

use crate::common;
use common::*;
use proptest::prelude::*;
use std::path::Path;
use std::process::Command;

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

fn check_bytes(bytes: &[u8], extra: &[&str]) -> (Option<i32>, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("input.m2r");
    std::fs::write(&path, bytes).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_m2rc"))
        .arg("check")
        .arg(&path)
        .args(extra)
        .output()
        .expect("run m2rc check");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn clean_program_exits_zero_and_errors_exit_one() {
    let (code, _, err) = check_bytes(b"route {\n  go objects(bed).nearest(start)\n}\n", &[]);
    assert_eq!(code, Some(0), "{err}");
    let (code, _, err) = check_bytes(b"route {\n  go objects(chiar).nearest(start)\n}\n", &[]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("E0401") && err.contains("input.m2r:2:"),
        "{err}"
    );
    let (code, out, _) = check_bytes(
        b"route { go objects(chiar).nearest(start) }",
        &["--format", "json"],
    );
    assert_eq!(code, Some(1));
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON output");
    assert_eq!(v[0]["code"], "E0401", "{out}");
}

#[test]
fn unreadable_input_is_an_error_not_a_panic() {
    let (code, _, err) = check_bytes(&[0xff, 0xfe, b'r', 0x80], &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("input.m2r") && !err.contains("panicked"),
        "{err}"
    );
}

#[test]
fn check_says_ok_with_the_counts_on_success() {
    let tmp = tempfile::tempdir().unwrap();
    write(
        tmp.path(),
        "p.m2r",
        "let k = rooms(kitchen).only()\nlet b = objects(bed)\nroute {\n  go k\n  go b.nearest(start)\n}\n",
    );
    let r = m2rc(&["check", "p.m2r"], tmp.path()).expect(0);
    assert!(
        r.stderr.contains("ok: 2 bindings, 2 stages"),
        "{}",
        r.stderr
    );
    // The JSON form is unchanged: one array on standard output, nothing else there.
    let r = m2rc(&["check", "p.m2r", "--format", "json"], tmp.path()).expect(0);
    assert_eq!(r.stdout.trim(), "[]");
    // With errors there is no `ok`.
    write(tmp.path(), "bad.m2r", "route {\n  go objects(chiar)\n}\n");
    let r = m2rc(&["check", "bad.m2r"], tmp.path()).expect(1);
    assert!(!r.stderr.contains("ok:"), "{}", r.stderr);
}

#[test]
fn check_fix_applies_the_suggestions_atomically_and_says_what_changed() {
    let tmp = tempfile::tempdir().unwrap();
    let broken = "route {\n  go objects(bedd).nearest(start)\n}\n";
    write(tmp.path(), "p.m2r", broken);
    // To another file: the input stays as it was.
    let r = m2rc(&["check", "p.m2r", "--fix", "-o", "fixed.m2r"], tmp.path()).expect(0);
    assert!(r.stderr.contains("`bedd` -> `bed`"), "{}", r.stderr);
    assert!(r.stderr.contains("applied 1 fix(es)"), "{}", r.stderr);
    assert!(r.stderr.contains("ok: 0 bindings, 1 stage"), "{}", r.stderr);
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("p.m2r")).unwrap(),
        broken
    );
    let fixed = std::fs::read_to_string(tmp.path().join("fixed.m2r")).unwrap();
    assert_eq!(fixed, "route {\n  go objects(bed).nearest(start)\n}\n");
    // In place, through the same atomic write as every output.
    m2rc(&["check", "p.m2r", "--fix"], tmp.path()).expect(0);
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("p.m2r")).unwrap(),
        fixed
    );
    // Nothing left to fix: the file is not rewritten.
    let before = std::fs::metadata(tmp.path().join("p.m2r"))
        .unwrap()
        .modified()
        .unwrap();
    let r = m2rc(&["check", "p.m2r", "--fix"], tmp.path()).expect(0);
    assert!(r.stderr.contains("nothing to fix"), "{}", r.stderr);
    let after = std::fs::metadata(tmp.path().join("p.m2r"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, after);
    // An error without a machine-applicable fix stays, and the exit status says so.
    write(tmp.path(), "q.m2r", "route {\n  go objects(zzzzqqq)\n}\n");
    let r = m2rc(&["check", "q.m2r", "--fix"], tmp.path()).expect(1);
    assert!(r.stderr.contains("nothing to fix"), "{}", r.stderr);
    // Standard input: the fixed program goes to standard output.
    let r = m2rc_in(&["check", "-", "--fix"], tmp.path(), broken.as_bytes()).expect(0);
    assert_eq!(r.stdout, fixed);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn arbitrary_bytes_never_panic_the_binary(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let (code, _, err) = check_bytes(&bytes, &[]);
        prop_assert!(matches!(code, Some(0..=2)), "exit {code:?}: {err}");
        prop_assert!(!err.contains("panicked"), "{err}");
    }

    #[test]
    fn token_soups_never_panic_the_binary(toks in proptest::collection::vec(proptest::sample::select(vec![
        "let", "route", "go", "pass", "avoid", "prefer", "within", "during", "for", "in", "if", "else",
        "{", "}", "(", ")", ".", ",", "=", "==", "=>", "|", "x", "objects", "rooms", "chair", "start",
        "nearest", "only", "1.5m", "2", "\"s\"", "near", "far", "not", "and", ":",
    ]), 0..40)) {
        let (code, _, err) = check_bytes(toks.join(" ").as_bytes(), &[]);
        prop_assert!(matches!(code, Some(0..=2)), "exit {code:?}: {err}");
        prop_assert!(!err.contains("panicked"), "{err}");
    }
}
