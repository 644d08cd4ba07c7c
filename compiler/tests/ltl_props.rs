//! Property tests of the LTL backend: for random small formulas and random finite traces, the
//! automaton accepts exactly when the direct LTLf semantics holds; minimisation keeps the
//! language; printing parses back to the same formula; the JSON guards parse in the formula
//! syntax and select the same successor as the automaton.

use m2rc_compiler::ltl::formula::holds;
use m2rc_compiler::ltl::syntax::{Formula, Kind};
use m2rc_compiler::ltl::{Dfa, export, parse};
use proptest::prelude::*;

const ATOMS: [&str; 3] = ["a", "b", "c"];

fn names() -> Vec<String> {
    ATOMS.iter().map(|s| s.to_string()).collect()
}

fn index(n: &str) -> Option<u32> {
    ATOMS.iter().position(|a| *a == n).map(|i| i as u32)
}

fn formula() -> impl Strategy<Value = Formula> {
    let leaf = prop_oneof![
        Just(Formula::new(Kind::True)),
        Just(Formula::new(Kind::False)),
        (0..ATOMS.len()).prop_map(|i| Formula::atom(ATOMS[i])),
    ];
    leaf.prop_recursive(4, 24, 2, |inner| {
        let b = |k: fn(Box<Formula>, Box<Formula>) -> Kind| {
            (inner.clone(), inner.clone())
                .prop_map(move |(x, y)| Formula::new(k(Box::new(x), Box::new(y))))
        };
        let u = |k: fn(Box<Formula>) -> Kind| {
            inner
                .clone()
                .prop_map(move |x| Formula::new(k(Box::new(x))))
        };
        prop_oneof![
            u(Kind::Not),
            u(Kind::Next),
            u(Kind::WeakNext),
            u(Kind::Eventually),
            u(Kind::Always),
            b(Kind::And),
            b(Kind::Or),
            b(Kind::Implies),
            b(Kind::Iff),
            b(Kind::Until),
            b(Kind::Release),
            b(Kind::WeakUntil),
        ]
    })
}

fn trace() -> impl Strategy<Value = Vec<u64>> {
    prop::collection::vec(0u64..8, 1..7)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn automaton_matches_semantics(f in formula(), traces in prop::collection::vec(trace(), 12)) {
        let min = Dfa::build(&f, &names(), true).unwrap();
        let raw = Dfa::build(&f, &names(), false).unwrap();
        prop_assert!(min.states() <= raw.states());
        for t in &traces {
            let want = holds(&f, t, 0, &index);
            prop_assert_eq!(min.accepts(t), want, "minimised, formula {} trace {:?}", f, t);
            prop_assert_eq!(raw.accepts(t), want, "unminimised, formula {} trace {:?}", f, t);
        }
    }

    #[test]
    fn printed_formula_parses_to_the_same_language(f in formula(), traces in prop::collection::vec(trace(), 8)) {
        let text = f.to_string();
        let back = parse(&text).unwrap();
        prop_assert_eq!(back.to_string(), text.clone());
        for t in &traces {
            prop_assert_eq!(holds(&back, t, 0, &index), holds(&f, t, 0, &index), "{}", text);
        }
    }

    #[test]
    fn json_guards_are_formulas_that_agree_with_the_automaton(f in formula()) {
        let d = Dfa::build(&f, &names(), true).unwrap();
        let json = export::to_json(&d);
        for e in json["edges"].as_array().unwrap() {
            let g = parse(e["guard"].as_str().unwrap()).unwrap();
            let from = e["from"].as_u64().unwrap() as usize;
            let to = e["to"].as_u64().unwrap() as usize;
            for letter in 0..8u64 {
                let sat = holds(&g, &[letter], 0, &index);
                prop_assert_eq!(sat, d.step(from, letter) == to);
            }
        }
    }
}
