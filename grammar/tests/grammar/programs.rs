//! The realistic example programs in `tests/programs/`: each parses without errors, formats
//! idempotently without losing a comment, and its formatted text parses to the same tree.

use m2rc_grammar::{parse, print, print_with_comments, same_modulo_spans};
use std::path::PathBuf;

fn programs() -> Vec<(String, String)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/programs");
    let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
        .expect("tests/programs exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "m2r"))
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("readable program");
            (
                p.file_name()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned(),
                text,
            )
        })
        .collect();
    out.sort();
    out
}

#[test]
fn there_are_ten_programs() {
    assert_eq!(programs().len(), 10);
}

#[test]
fn every_program_parses_cleanly() {
    for (name, src) in programs() {
        let parsed = parse(&src);
        assert!(parsed.errors.is_empty(), "{name}: {:?}", parsed.errors);
        let routes = parsed
            .program
            .items
            .iter()
            .filter(|i| matches!(i, m2rc_grammar::ast::Item::Route(_)))
            .count();
        assert_eq!(routes, 1, "{name}");
    }
}

#[test]
fn formatting_is_idempotent_and_keeps_every_comment() {
    for (name, src) in programs() {
        let parsed = parse(&src);
        let once = print_with_comments(&parsed.program, &parsed.comments, &src);
        let reparsed = parse(&once);
        assert!(
            reparsed.errors.is_empty(),
            "{name}: {:?}\n{once}",
            reparsed.errors
        );
        assert!(
            same_modulo_spans(&parsed.program, &reparsed.program),
            "{name}:\n{once}"
        );
        let texts = |c: &[(m2rc_grammar::ast::Span, String)]| {
            c.iter().map(|(_, t)| t.clone()).collect::<Vec<_>>()
        };
        assert_eq!(texts(&parsed.comments), texts(&reparsed.comments), "{name}");
        let twice = print_with_comments(&reparsed.program, &reparsed.comments, &once);
        assert_eq!(once, twice, "{name}");
    }
}

#[test]
fn plain_printing_round_trips() {
    for (name, src) in programs() {
        let program = parse(&src).program;
        let text = print(&program);
        let again = parse(&text);
        assert!(again.errors.is_empty(), "{name}: {:?}", again.errors);
        assert!(
            same_modulo_spans(&program, &again.program),
            "{name}:\n{text}"
        );
        assert_eq!(print(&again.program), text, "{name}");
    }
}

#[test]
fn canonical_programs_are_left_unchanged() {
    for (name, src) in programs() {
        if name.starts_with("02_") || name.starts_with("06_") || name.starts_with("09_") {
            continue; // written in a non-canonical layout on purpose
        }
        let parsed = parse(&src);
        assert_eq!(
            print_with_comments(&parsed.program, &parsed.comments, &src),
            src,
            "{name}"
        );
    }
}

#[test]
fn non_canonical_layouts_are_normalised() {
    let src = programs()
        .into_iter()
        .find(|(n, _)| n.starts_with("06_"))
        .expect("06 exists")
        .1;
    let parsed = parse(&src);
    let out = print_with_comments(&parsed.program, &parsed.comments, &src);
    assert!(out.contains(
        "let target = if chairs.count() >= 2 { chairs.farthest(by: travel) } else { objects(sofa).nearest() }\n"
    ));
    assert!(
        out.contains(
            "let big = rooms().where(r => r.area() > 20.0 and not objects(chair).in(r).is_empty() == true)\n"
        )
    );
}
