//! The automaton in three formats, all with the same atom names and guard syntax as `--emit ltl`:
//!
//! * JSON: `{"atoms": [...], "initial": q, "accepting": [q, ...], "edges": [{"from", "to",
//!   "guard"}]}`, guards in the formula text syntax;
//! * HOA v1 (<https://adl.github.io/hoaf/>): state-based acceptance `Inf(0)` marks the *final*
//!   states of the finite-word automaton (HOA has no finite-word acceptance; this is the usual
//!   encoding, documented in `docs/ltl.md`); `AP` lists the atoms in order;
//! * DOT, for Graphviz: final states double circles, edges labelled with their guards.

use super::dfa::{Cube, Dfa, Guard};
use serde_json::json;
use std::fmt::Write as _;

pub fn to_json(d: &Dfa) -> serde_json::Value {
    let edges: Vec<serde_json::Value> = d
        .edges
        .iter()
        .flatten()
        .map(|e| json!({"from": e.from, "to": e.to, "guard": e.guard.text(&d.atoms)}))
        .collect();
    json!({
        "atoms": d.atoms,
        "initial": d.initial,
        "accepting": (0..d.states()).filter(|&q| d.accepting[q]).collect::<Vec<_>>(),
        "edges": edges,
    })
}

fn hoa_cube(c: &Cube, atoms: usize) -> String {
    let lits: Vec<String> = (0..atoms)
        .filter_map(|i| {
            if c.pos >> i & 1 == 1 {
                Some(i.to_string())
            } else if c.neg >> i & 1 == 1 {
                Some(format!("!{i}"))
            } else {
                None
            }
        })
        .collect();
    if lits.is_empty() {
        "t".into()
    } else {
        lits.join("&")
    }
}

fn hoa_guard(g: &Guard, atoms: usize) -> String {
    match g.0.len() {
        0 => "f".into(),
        1 => hoa_cube(&g.0[0], atoms),
        _ => {
            g.0.iter()
                .map(|c| format!("({})", hoa_cube(c, atoms)))
                .collect::<Vec<_>>()
                .join(" | ")
        }
    }
}

fn quote(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

pub fn to_hoa(d: &Dfa, name: &str) -> String {
    let mut out = String::from("HOA: v1\n");
    let _ = writeln!(out, "name: {}", quote(name));
    let _ = writeln!(out, "States: {}", d.states());
    let _ = writeln!(out, "Start: {}", d.initial);
    let _ = write!(out, "AP: {}", d.atoms.len());
    for a in &d.atoms {
        let _ = write!(out, " {}", quote(a));
    }
    out.push('\n');
    out.push_str("acc-name: Buchi\nAcceptance: 1 Inf(0)\n");
    out.push_str("properties: trans-labels explicit-labels state-acc deterministic complete\n");
    out.push_str("--BODY--\n");
    for q in 0..d.states() {
        let _ = writeln!(
            out,
            "State: {q}{}",
            if d.accepting[q] { " {0}" } else { "" }
        );
        for e in &d.edges[q] {
            let _ = writeln!(out, "[{}] {}", hoa_guard(&e.guard, d.atoms.len()), e.to);
        }
    }
    out.push_str("--END--\n");
    out
}

pub fn to_dot(d: &Dfa, name: &str) -> String {
    let mut out = format!("digraph {} {{\n  rankdir=LR;\n", quote(name));
    out.push_str("  node [shape=circle];\n  init [shape=point];\n");
    for q in 0..d.states() {
        let _ = writeln!(
            out,
            "  q{q} [label=\"{q}\"{}];",
            if d.accepting[q] {
                ", shape=doublecircle"
            } else {
                ""
            }
        );
    }
    let _ = writeln!(out, "  init -> q{};", d.initial);
    for e in d.edges.iter().flatten() {
        let _ = writeln!(
            out,
            "  q{} -> q{} [label={}];",
            e.from,
            e.to,
            quote(&e.guard.text(&d.atoms))
        );
    }
    out.push_str("}\n");
    out
}
