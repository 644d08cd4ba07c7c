//! The `route ltl "..."` form through the whole checker: each bad formula's code and the exact
//! text it points at, and a clean program.

use crate::check::check;
use m2rc_stdlib::vocab::Vocabulary;

fn found(src: &str) -> Vec<(&'static str, String)> {
    check(src, &Vocabulary::benchmark())
        .diagnostics
        .iter()
        .map(|d| {
            (
                d.code.id(),
                src.get(d.span.start..d.span.end)
                    .unwrap_or("<bad span>")
                    .to_string(),
            )
        })
        .collect()
}

const LETS: &str =
    "let k = 2\nlet bed = objects(bed).only()\nlet kitchen = rooms(kitchen).only()\n";

fn prog(route: &str) -> String {
    format!("{LETS}{route}\n")
}

#[test]
fn clean_ltl_route() {
    let src = "let bed = objects(bed).only()\nlet kitchen = rooms(kitchen).only()\nroute ltl \"F(kitchen & F bed) | F bed\"\n";
    assert_eq!(found(src), vec![]);
}

#[test]
fn bad_formulas_point_into_the_string() {
    let cases: &[(&str, &str, &str)] = &[
        ("route ltl \"F(bed & F kitchn)\"", "E01", "kitchn"),
        ("route ltl \"F k\"", "E0805", "k"),
        ("route ltl \"F(bed S kitchen)\"", "E0802", "S"),
        ("route ltl \"F(bed & F kitchen\"", "E0803", "("),
        ("route ltl \"F bed & G !bed\"", "E0807", "F bed & G !bed"),
        ("route ltl \"G F bed\"", "E0806", "G F bed"),
        ("route ltl \"F(bed &)\"", "E0801", ")"),
        ("route ltx \"F bed\"", "E0801", "ltx"),
        ("route ltl \"F bed\" { go kitchen }", "E0812", "go kitchen"),
    ];
    for (route, code, text) in cases {
        let src = prog(route);
        let got = found(&src);
        assert!(
            got.iter().any(|(c, t)| c.starts_with(code) && t == text),
            "{route}: want {code} at `{text}`, got {got:?}"
        );
    }
}

#[test]
fn preferences_in_an_ltl_route_are_dropped_with_a_warning() {
    let src = prog("route ltl \"F bed\" {\n  prefer near(kitchen)\n  avoid kitchen\n}");
    let got = found(&src);
    assert!(
        got.contains(&("E0809", "prefer near(kitchen)".to_string())),
        "{got:?}"
    );
    assert!(
        !got.iter()
            .any(|(c, _)| c.starts_with("E08") && *c != "E0809"),
        "{got:?}"
    );
}

#[test]
fn ltl_route_prints_and_parses_back() {
    let src = prog("route ltl \"F(kitchen & F bed)\" {\n  avoid kitchen\n}");
    let parsed = m2rc_grammar::parse(&src);
    assert!(parsed.errors.is_empty(), "{:?}", parsed.errors);
    let printed = m2rc_grammar::print(&parsed.program);
    assert!(
        printed.contains("route ltl \"F(kitchen & F bed)\" {"),
        "{printed}"
    );
    let again = m2rc_grammar::parse(&printed);
    assert!(again.errors.is_empty());
    assert_eq!(m2rc_grammar::print(&again.program), printed);
}

/// A formula nested past the limit is a diagnostic, not a stack overflow, at any depth.
#[test]
fn deep_nesting_is_refused_not_overflowed() {
    for depth in [250usize, 100_000] {
        let text = format!("{}a{}", "(".repeat(depth), ")".repeat(depth));
        let err = super::parse(&text).unwrap_err();
        assert!(err.message.contains("nests more than"), "{}", err.message);
        let text = format!("{}a", "F ".repeat(depth));
        assert!(super::parse(&text).is_err());
        let text = vec!["a"; depth].join(" -> ");
        assert!(super::parse(&text).is_err());
    }
    assert!(super::parse(&format!("{}a{}", "(".repeat(50), ")".repeat(50))).is_ok());
}

/// Progression must close on formulas whose residuals only absorption keeps finite (this one is
/// `true` on every trace: `F WX false` holds at the last position).
#[test]
fn progression_closes_with_absorption() {
    let f = super::parse("F false W F WX false").unwrap();
    let d = super::Dfa::build(&f, &["a".to_string()], true).unwrap();
    assert!(d.states() <= 2, "{} states", d.states());
    for t in [&[0u64][..], &[1], &[0, 1, 0], &[1, 1, 1, 1, 1, 1]] {
        assert!(d.accepts(t), "{t:?}");
    }
}
