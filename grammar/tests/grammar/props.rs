//! Property tests: printing round-trips through the parser, printing is idempotent, and no
//! input, however broken, panics the lexer, the parser or the printer.

use super::strategies::{VOCABULARY, expr, program};
use m2rc_grammar::{
    erase_expr_spans, erase_spans, parse, parse_expr, print, print_expr, print_with_comments,
};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    #[test]
    fn printed_programs_parse_back_to_the_same_tree(p in program()) {
        let text = print(&p);
        let parsed = parse(&text);
        prop_assert!(parsed.errors.is_empty(), "{text}\n{:#?}", parsed.errors);
        prop_assert_eq!(erase_spans(&parsed.program), p, "{}", text);
    }

    #[test]
    fn printing_is_idempotent(p in program()) {
        let text = print(&p);
        let again = print(&parse(&text).program);
        prop_assert_eq!(&again, &text);
        let parsed = parse(&text);
        prop_assert_eq!(print_with_comments(&parsed.program, &parsed.comments, &text), text);
    }

    #[test]
    fn printed_expressions_parse_back(e in expr()) {
        let text = print_expr(&e);
        let back = parse_expr(&text);
        prop_assert!(back.is_ok(), "{text}: {back:?}");
        prop_assert_eq!(back.map(|b| erase_expr_spans(&b)).ok(), Some(e), "{}", text);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        let text = String::from_utf8_lossy(&bytes);
        let parsed = parse(&text);
        let _ = print_with_comments(&parsed.program, &parsed.comments, &text);
        for e in &parsed.errors {
            prop_assert!(e.span.start <= e.span.end && e.span.end <= text.len());
            prop_assert!(!e.message.is_empty());
        }
    }

    #[test]
    fn token_soups_never_panic_and_clean_ones_round_trip(
        words in prop::collection::vec(prop::sample::select(VOCABULARY), 0..40),
        seps in prop::collection::vec(prop::sample::select(&[" ", "", "\n"][..]), 40),
    ) {
        let text: String = words.iter().zip(&seps).map(|(w, s)| format!("{w}{s}")).collect();
        let parsed = parse(&text);
        let _ = parse_expr(&text);
        let printed = print_with_comments(&parsed.program, &parsed.comments, &text);
        for e in &parsed.errors {
            prop_assert!(e.span.start <= e.span.end && e.span.end <= text.len(), "{e:?}");
            prop_assert!(text.is_char_boundary(e.span.start) && text.is_char_boundary(e.span.end));
        }
        if parsed.errors.is_empty() {
            let again = parse(&printed);
            prop_assert!(again.errors.is_empty(), "{text:?} -> {printed:?}: {:?}", again.errors);
            prop_assert_eq!(erase_spans(&again.program), erase_spans(&parsed.program));
            prop_assert_eq!(print_with_comments(&again.program, &again.comments, &printed), printed);
        }
    }
}

/// Deterministic soups from structured programs: dropping any one token from a valid program
/// must still give a result (with errors) and never a panic.
#[test]
fn dropping_any_token_of_a_real_program_is_survivable() {
    let src = include_str!("../programs/04_patrol_and_pass.m2r");
    let tokens = m2rc_grammar::lexer::tokenize(src).tokens;
    for (start, _, end) in tokens {
        let broken = format!("{}{}", &src[..start], &src[end..]);
        let parsed = parse(&broken);
        let _ = print_with_comments(&parsed.program, &parsed.comments, &broken);
    }
}
