//! File-driven UI tests for the checker.
//!
//! * `tests/ui/errors/*.m2r`: broken programs with their expected diagnostics written inline. Each
//!   file is checked against the benchmark vocabulary; the set of (code, line[, columns]) produced
//!   must equal the set annotated, and the rendered diagnostics are snapshotted together with the
//!   source (`tests/tests/it/snapshots/`), so a reviewer sees input and message in one file.
//! * `tests/ui/real/*.m2r`: the real benchmark instructions, each of which must check with no error.
//!
//! Annotation forms (in `//` comments, which the checker ignores):
//! * `code //~ E0401` — a diagnostic with this code whose primary span starts on this line;
//! * `//~^ E0401` (one `^` per line up) — on an earlier line, for spans in the first columns;
//! * `//   ^^^^^ E0401` — a caret line under the code: the primary span starts at the first caret's
//!   column and covers the carets exactly, on the nearest line above that is not an annotation.
//!   Text after the code is a fragment the message must contain.
//!
//! Update snapshots with `INSTA_UPDATE=always cargo test -p m2rc-tests --test it ui::` or `cargo insta review`.

use m2rc_compiler::check::check;
use m2rc_compiler::diagnostic::{Diagnostic, LineIndex, render_text};
use m2rc_stdlib::vocab::Vocabulary;
use std::path::Path;

#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Expected {
    code: String,
    /// 1-based line.
    line: usize,
    /// 1-based start column and length in characters, for caret annotations.
    cols: Option<(usize, usize)>,
    fragment: String,
}

fn is_annotation(line: &str) -> bool {
    let t = line.trim_start();
    t.starts_with("//~") || (t.starts_with("//") && t[2..].trim_start().starts_with('^'))
}

fn parse_code_and_fragment(rest: &str, file: &Path, lineno: usize) -> (String, String) {
    let rest = rest.trim();
    let (code, fragment) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
    assert!(
        code.len() == 5 && code.starts_with('E') && code[1..].bytes().all(|b| b.is_ascii_digit()),
        "{}:{lineno}: annotation needs a code like E0401, found `{rest}`",
        file.display()
    );
    (code.to_string(), fragment.trim().to_string())
}

fn expectations(source: &str, file: &Path) -> Vec<Expected> {
    let lines: Vec<&str> = source.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let lineno = i + 1;
        if let Some(pos) = line.find("//~") {
            let after = &line[pos + 3..];
            let ups = after.chars().take_while(|&c| c == '^').count();
            let (code, fragment) = parse_code_and_fragment(&after[ups..], file, lineno);
            let target = if ups == 0 {
                lineno
            } else {
                // Count `^` upwards over code lines only.
                let mut l = i;
                let mut left = ups;
                while left > 0 {
                    assert!(
                        l > 0,
                        "{}:{lineno}: `//~^` points above the file",
                        file.display()
                    );
                    l -= 1;
                    if !is_annotation(lines[l]) {
                        left -= 1;
                    }
                }
                l + 1
            };
            out.push(Expected {
                code,
                line: target,
                cols: None,
                fragment,
            });
        } else if is_annotation(line) {
            let first = line.find('^').unwrap();
            let count = line[first..].chars().take_while(|&c| c == '^').count();
            let (code, fragment) = parse_code_and_fragment(&line[first + count..], file, lineno);
            let mut l = i;
            loop {
                assert!(
                    l > 0,
                    "{}:{lineno}: caret annotation above the first line",
                    file.display()
                );
                l -= 1;
                if !is_annotation(lines[l]) {
                    break;
                }
            }
            let col = line[..first].chars().count() + 1;
            out.push(Expected {
                code,
                line: l + 1,
                cols: Some((col, count)),
                fragment,
            });
        }
    }
    out.sort();
    out
}

fn matches(e: &Expected, d: &Diagnostic, idx: &LineIndex) -> bool {
    let (line, col) = idx.line_col(d.span.start);
    let (end_line, end_col) = idx.line_col(d.span.end);
    d.code.id() == e.code
        && line == e.line
        && e.cols
            .is_none_or(|(c, n)| col == c && end_line == line && end_col == c + n)
        && d.message.contains(&e.fragment)
}

/// Checks against the benchmark vocabulary, or against the demo map's categories when the file's
/// first line is `// vocab: demo` (for the "not in this map" diagnostics).
fn check_file(path: &Path) -> (String, Vec<Diagnostic>) {
    let source = std::fs::read_to_string(path).unwrap();
    let vocab = if source.starts_with("// vocab: demo") {
        Vocabulary::from_map(&m2rc_stdlib::demo::demo_map().expect("the demo map builds"))
    } else {
        Vocabulary::benchmark()
    };
    let result = check(&source, &vocab);
    (source, result.diagnostics)
}

#[test]
fn error_programs_report_exactly_their_annotated_diagnostics() {
    // Every file is checked before failing, so one run lists every mismatch.
    let failures = std::cell::RefCell::new(Vec::<String>::new());
    insta::glob!("../../ui/errors", "*.m2r", |path| {
        let (source, diags) = check_file(path);
        let expected = expectations(&source, path);
        assert!(
            !expected.is_empty(),
            "{}: no `//~` annotation",
            path.display()
        );
        let idx = LineIndex::new(&source);
        let mut unmatched: Vec<&Diagnostic> = diags.iter().collect();
        let mut missing = Vec::new();
        for e in &expected {
            match unmatched.iter().position(|d| matches(e, d, &idx)) {
                Some(i) => {
                    unmatched.remove(i);
                }
                None => missing.push(e.clone()),
            }
        }
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let rendered = render_text(&diags, &name, &source);
        if !(missing.is_empty() && unmatched.is_empty()) {
            failures.borrow_mut().push(format!(
                "{}:\n  expected but not reported: {missing:?}\n  reported but not expected: {:?}\n\n{rendered}",
                path.display(),
                unmatched
                    .iter()
                    .map(|d| (d.code.id(), idx.line_col(d.span.start), d.message.as_str()))
                    .collect::<Vec<_>>(),
            ));
            return;
        }
        insta::assert_snapshot!(format!(
            "----- SOURCE\n{source}\n----- DIAGNOSTICS\n{rendered}"
        ));
    });
    let failures = failures.into_inner();
    assert!(
        failures.is_empty(),
        "{} file(s) disagree with their annotations:\n\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn real_instruction_programs_check_clean() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("ui/real");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "m2r"));
    files.sort();
    assert!(
        files.len() >= 21,
        "expected the 21 real instructions and the clauses, found {}",
        files.len()
    );
    let mut failures = String::new();
    for path in &files {
        let (source, diags) = check_file(path);
        let errors: Vec<Diagnostic> = diags.into_iter().filter(|d| d.is_error()).collect();
        if !errors.is_empty() {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            failures.push_str(&render_text(&errors, &name, &source));
        }
        // The instruction sits in a comment beside the program.
        assert!(
            source.starts_with("//"),
            "{}: must open with the instruction in a comment",
            path.display()
        );
    }
    assert!(
        failures.is_empty(),
        "real programs with errors:\n{failures}"
    );
}

/// The grammar crate's example programs and its benchmark program exercise the syntax; they must
/// also be programs the checker accepts, or they teach constructs the language rejects.
#[test]
fn grammar_example_programs_check_clean() {
    let grammar = Path::new(env!("CARGO_MANIFEST_DIR")).join("../grammar");
    let mut files: Vec<_> = std::fs::read_dir(grammar.join("tests/programs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "m2r"))
        .collect();
    files.push(grammar.join("benches/hard_instruction.m2r"));
    files.sort();
    assert!(files.len() >= 11, "found {} programs", files.len());
    let mut failures = String::new();
    for path in &files {
        let (source, diags) = check_file(path);
        let errors: Vec<Diagnostic> = diags.into_iter().filter(|d| d.is_error()).collect();
        if !errors.is_empty() {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            failures.push_str(&render_text(&errors, &name, &source));
        }
    }
    assert!(
        failures.is_empty(),
        "grammar programs with errors:\n{failures}"
    );
}

#[test]
fn every_diagnostic_code_has_a_ui_test() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("ui/errors");
    let mut covered = std::collections::BTreeSet::new();
    let mut files = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "m2r") {
            files += 1;
            let source = std::fs::read_to_string(&path).unwrap();
            covered.extend(expectations(&source, &path).into_iter().map(|e| e.code));
        }
    }
    assert!(files >= 60, "at least 60 broken programs, found {files}");
    // Every code the checker reports (parse, names, types, scopes, vocabulary) needs a UI test;
    // E0000 and E0004 are parser fallbacks that no known program triggers.
    let static_codes: Vec<&str> = m2rc_compiler::diagnostic::Code::registry()
        .map(|c| c.id)
        .filter(|id| ui_checkable(id) && !["E0000", "E0004"].contains(id))
        .collect();
    let missing: Vec<&&str> = static_codes
        .iter()
        .filter(|c| !covered.contains(**c))
        .collect();
    assert!(
        missing.is_empty(),
        "codes without a UI test in tests/ui/errors: {missing:?}"
    );
}

/// Codes the checker can report without a map (parse, names, types, scopes, vocabulary); grounding,
/// verification and planning codes are covered by the compile tests.
fn ui_checkable(id: &str) -> bool {
    matches!(&id[..3], "E00" | "E01" | "E02" | "E03" | "E04")
}

/// The repair loop applies machine-applicable suggestions without reading them, so each one must
/// repair: applied alone, it removes its diagnostic and adds no error (every alternative of a
/// diagnostic is tried, since the writer may pick any).
#[test]
fn every_suggestion_removes_its_error_and_adds_none() {
    use std::collections::BTreeMap;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("ui/errors");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "m2r"))
        .collect();
    files.sort();
    let counts = |diags: &[Diagnostic]| {
        let mut m: BTreeMap<&'static str, usize> = BTreeMap::new();
        for d in diags.iter().filter(|d| d.is_error()) {
            *m.entry(d.code.id()).or_default() += 1;
        }
        m
    };
    let mut failures = Vec::new();
    let mut tried = 0;
    for path in &files {
        let (source, diags) = check_file(path);
        let vocab_line = source.starts_with("// vocab: demo");
        let before = counts(&diags);
        for d in diags.iter().filter(|d| d.is_error()) {
            for s in &d.suggestions {
                tried += 1;
                let fixed = m2rc_compiler::diagnostic::apply_suggestions(
                    &source,
                    &[Diagnostic {
                        suggestions: vec![s.clone()],
                        ..d.clone()
                    }],
                );
                let vocab = if vocab_line {
                    Vocabulary::from_map(&m2rc_stdlib::demo::demo_map().expect("demo map"))
                } else {
                    Vocabulary::benchmark()
                };
                let after_diags = check(&fixed, &vocab).diagnostics;
                let after = counts(&after_diags);
                let removed = after.get(d.code.id()).copied().unwrap_or(0)
                    < before.get(d.code.id()).copied().unwrap_or(0);
                let added: Vec<&str> = after
                    .iter()
                    .filter(|(c, n)| **n > before.get(*c).copied().unwrap_or(0))
                    .map(|(c, _)| *c)
                    .collect();
                if !removed || !added.is_empty() {
                    failures.push(format!(
                        "{}: {} `{}` -> `{}`: removed={removed}, added={added:?}\n{}",
                        path.file_name().unwrap().to_string_lossy(),
                        d.code.id(),
                        source.get(s.span.start..s.span.end).unwrap_or(""),
                        s.replacement,
                        render_text(&after_diags, "fixed.m2r", &fixed)
                    ));
                }
            }
        }
    }
    assert!(tried >= 30, "only {tried} suggestions found");
    assert!(
        failures.is_empty(),
        "{} suggestion(s) do not repair:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
