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

/// `F a0 & F a1 & ... & F a{n-1}`: n unordered visits, 2^n states.
fn eventualities(n: usize) -> String {
    (0..n)
        .map(|i| format!("F a{i}"))
        .collect::<Vec<_>>()
        .join(" & ")
}

/// A formula whose automaton is exponential is refused by the work budget, as it goes: the first
/// state of 30 (or 64) unordered visits alone has 2^30 guard cubes, so a state limit checked per
/// state would never be reached.
#[test]
fn exponential_formulas_are_refused_within_the_budget() {
    for n in [14, 30, 64] {
        let text = eventualities(n);
        let err = super::check_formula(&text, 0, &|_| super::AtomKind::Place, &[])
            .expect_err("refused")
            .remove(0);
        assert_eq!(err.code.id(), "E0810", "{n}: {}", err.message);
        assert!(err.message.contains("limit"), "{}", err.message);
        assert_eq!((err.span.start, err.span.end), (0, text.len()));
        let atoms: Vec<String> = (0..n).map(|i| format!("a{i}")).collect();
        let f = super::parse(&text).unwrap();
        for minimise in [true, false] {
            assert!(matches!(
                super::Dfa::build(&f, &atoms, minimise),
                Err(super::dfa::BuildError::Budget { .. })
            ));
        }
    }
    // Six unordered visits are an ordinary route: 64 states, built.
    let c = super::check_formula(&eventualities(6), 0, &|_| super::AtomKind::Place, &[]).unwrap();
    assert_eq!(c.dfa.states(), 64);
}

/// The same refusal inside a program: `check` (static, no map) reports E0810 on the formula.
#[test]
fn exponential_formula_in_a_program_is_an_error_of_check() {
    for n in [30, 64] {
        let mut src = String::new();
        for i in 0..n {
            src.push_str(&format!("let a{i} = rooms(kitchen).only()\n"));
        }
        src.push_str(&format!("route ltl \"{}\"\n", eventualities(n)));
        let got = found(&src);
        assert!(
            got.iter()
                .any(|(c, t)| *c == "E0810" && *t == eventualities(n)),
            "{n}: {got:?}"
        );
    }
}

/// The budget counts steps, not time: the same formula costs the same on every run, and a
/// smaller budget refuses what the default one builds.
#[test]
fn the_budget_is_deterministic() {
    use super::budget::Budget;
    let f = super::parse("F(a & F(b & F c)) & G !d & (e U f)").unwrap();
    let atoms: Vec<String> = ["a", "b", "c", "d", "e", "f"].map(String::from).to_vec();
    let used = |max: u64| {
        let mut b = Budget::new(max, super::budget::MAX_CUBES);
        super::dfa::build_with(&f, &atoms, true, &mut b).map(|d| (d.states(), b.used()))
    };
    let (states, spent) = used(super::budget::MAX_WORK).unwrap();
    assert_eq!(used(super::budget::MAX_WORK).unwrap(), (states, spent));
    assert!(spent > 0);
    assert!(matches!(
        used(spent - 1),
        Err(super::dfa::BuildError::Budget { .. })
    ));
    assert_eq!(used(spent).unwrap().0, states);
}

/// A chain of visits that returns to the same two places (`--planner ltl` on 200 alternating
/// stages) stays linear: each state keeps only the weakest of the positions it could be at, so
/// the automaton is built within the budget, one state per visit.
#[test]
fn long_chain_over_two_places_is_linear() {
    use super::{Skeleton, Visit};
    let names: Vec<String> = ["b", "k"].map(String::from).to_vec();
    let sk = Skeleton {
        visits: (0..200)
            .map(|i| Visit {
                atom: i % 2,
                avoids: vec![],
            })
            .collect(),
        global_avoids: vec![],
    };
    let f = sk.formula(&names);
    let raw = super::Dfa::build(&f, &names, false).unwrap();
    assert_eq!(raw.states(), 201);
    let d = super::Dfa::build(&f, &names, true).unwrap();
    assert_eq!(d.states(), 201);
    let trace: Vec<u64> = (0..200).map(|i| 1u64 << (i % 2)).collect();
    assert!(d.accepts(&trace));
    assert!(!d.accepts(&trace[..199]));
}
