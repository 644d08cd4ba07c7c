//! `m2rc check` as a user runs it: exit 0 on a clean program, 1 with errors, 2 when the input cannot
//! be read, and never a panic, whatever bytes the file holds.

use proptest::prelude::*;
use std::process::Command;

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
