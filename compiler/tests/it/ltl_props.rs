//! Property tests of the LTL backend: for random small formulas and random finite traces, the
//! automaton accepts exactly when the direct LTLf semantics holds; minimisation keeps the
//! language; printing parses back to the same formula; the JSON guards parse in the formula
//! syntax and select the same successor as the automaton; the HOA output, read back by an
//! independent parser (`hoars`), is the same automaton.

use hoars::{AbstractLabelExpression as Label, HeaderItem, HoaAutomaton};
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

/// Whether a HOA label holds on `letter` (bit i = atom i in the route's cell).
fn label_holds(l: &Label, letter: u64) -> bool {
    match l {
        Label::Boolean(b) => *b,
        Label::Integer(i) => letter >> i & 1 == 1,
        Label::Negated(x) => !label_holds(x, letter),
        Label::Conjunction(xs) => xs.iter().all(|x| label_holds(x, letter)),
        Label::Disjunction(xs) => xs.iter().any(|x| label_holds(x, letter)),
    }
}

/// The successor of `state` on `letter` in the parsed automaton, when exactly one edge's label
/// holds (the export claims `deterministic complete`).
fn hoa_step(h: &HoaAutomaton, state: u32, letter: u64) -> Result<u32, String> {
    let s = h
        .body()
        .iter()
        .find(|s| s.id() == state)
        .ok_or(format!("state {state} is not in the body"))?;
    let targets: Vec<u32> = s
        .edges()
        .iter()
        .filter(|e| label_holds(e.label(), letter))
        .map(|e| {
            e.target()
                .ok_or("an edge with a state conjunction".to_string())
        })
        .collect::<Result<_, _>>()?;
    match targets[..] {
        [t] => Ok(t),
        _ => Err(format!(
            "state {state}, letter {letter:#b}: {} edges hold",
            targets.len()
        )),
    }
}

fn hoa_accepting(h: &HoaAutomaton, state: u32) -> bool {
    h.body().iter().find(|s| s.id() == state).is_some_and(|s| {
        s.edges()
            .iter()
            .any(|e| e.acceptance_signature().contains(&0))
    })
}

/// States of the minimal automaton of `d`, by the textbook construction: reachable states,
/// then Moore refinement letter by letter over all 8 letters of three atoms.
fn textbook_minimal_states(d: &Dfa) -> usize {
    let mut reach = vec![false; d.states()];
    let mut stack = vec![d.initial];
    reach[d.initial] = true;
    while let Some(q) = stack.pop() {
        for l in 0..8u64 {
            let t = d.step(q, l);
            if !reach[t] {
                reach[t] = true;
                stack.push(t);
            }
        }
    }
    let states: Vec<usize> = (0..d.states()).filter(|&q| reach[q]).collect();
    let mut block: Vec<usize> = (0..d.states()).map(|q| d.accepting[q] as usize).collect();
    loop {
        let sig = |q: usize, block: &[usize]| -> Vec<usize> {
            std::iter::once(block[q])
                .chain((0..8u64).map(|l| block[d.step(q, l)]))
                .collect()
        };
        let mut ids: std::collections::BTreeMap<Vec<usize>, usize> = Default::default();
        let mut next = block.clone();
        for &q in &states {
            let n = ids.len();
            next[q] = *ids.entry(sig(q, &block)).or_insert(n);
        }
        let before: std::collections::BTreeSet<usize> = states.iter().map(|&q| block[q]).collect();
        block = next;
        if ids.len() == before.len() {
            return ids.len();
        }
    }
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
        // Minimal, not only smaller: as many states as the textbook minimisation leaves.
        prop_assert_eq!(min.states(), textbook_minimal_states(&raw), "formula {}", f);
        prop_assert_eq!(textbook_minimal_states(&min), min.states(), "formula {}", f);
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

    #[test]
    fn hoa_output_reads_back_as_the_same_automaton(f in formula(), traces in prop::collection::vec(trace(), 12)) {
        let d = Dfa::build(&f, &names(), true).unwrap();
        let text = export::to_hoa(&d, "prop");
        let h = hoars::input::from_hoa(&text).map_err(|e| TestCaseError::fail(format!("{e:?}\n{text}")))?;
        prop_assert!(h.verify().is_ok(), "{:?}", h.verify());
        prop_assert_eq!(h.num_states(), Some(d.states()));
        let aps = h.header().iter().find_map(|i| match i { HeaderItem::AP(a) => Some(a.clone()), _ => None });
        prop_assert_eq!(aps, Some(names()));
        let start = h.start();
        prop_assert_eq!(start.len(), 1);
        let start = start[0].get_singleton().unwrap();
        prop_assert_eq!(start as usize, d.initial);
        for q in 0..d.states() {
            prop_assert_eq!(hoa_accepting(&h, q as u32), d.accepting[q], "state {}", q);
            for letter in 0..8u64 {
                let to = hoa_step(&h, q as u32, letter).map_err(TestCaseError::fail)?;
                prop_assert_eq!(to as usize, d.step(q, letter));
            }
        }
        for t in &traces {
            let mut q = start;
            for &letter in t {
                q = hoa_step(&h, q, letter).map_err(TestCaseError::fail)?;
            }
            prop_assert_eq!(hoa_accepting(&h, q), d.accepts(t), "formula {} trace {:?}", f, t);
        }
    }
}
