//! The LTL backend: LTLf (linear temporal logic on finite traces) over a route's places.
//!
//! ```text
//! text --syntax::parse--> Formula --formula::Arena (NNF)--> dfa::Dfa (progression, minimised)
//! RouteIR --lower::lower--> LtlRoute (atoms + Formula + dropped soft constraints)
//! Dfa --export--> JSON | HOA | DOT
//! ```
//!
//! A route is a finite trace: one letter per grid cell of the route, start included, whose true
//! atoms are the places the cell is in. The planner side (the product of the grid with the
//! automaton) is `m2rc_planner::product`. See `docs/ltl.md`.

pub mod budget;
pub mod check;
pub mod dfa;
pub mod export;
pub mod formula;
pub mod lower;
mod minimise;
pub mod program;
mod scope;
pub mod syntax;

pub use check::{AtomKind, CheckedFormula, check_formula};
pub use dfa::{Dfa, Guard};
pub use lower::{AtomDef, AtomSource, LtlRoute, Skeleton, Visit, lower};
pub use syntax::{Formula, parse};

/// What `m2rc compile --emit` prints for the LTL backend.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EmitKind {
    /// The formula (last line), after `//` lines naming the atoms and the dropped constraints.
    Ltl,
    /// The minimal automaton as JSON.
    Dfa,
    Hoa,
    Dot,
}

/// The text of `kind` for formula `route` (lowered from a RouteIR, or written in the program).
pub fn emit(route: &LtlRoute, kind: EmitKind, name: &str) -> Result<String, String> {
    if kind == EmitKind::Ltl {
        return Ok(route.text());
    }
    let dfa = Dfa::build(&route.formula, &route.atom_names(), true).map_err(|e| e.to_string())?;
    Ok(match kind {
        EmitKind::Ltl => route.text(),
        EmitKind::Dfa => {
            serde_json::to_string_pretty(&export::to_json(&dfa)).unwrap_or_default() + "\n"
        }
        EmitKind::Hoa => export::to_hoa(&dfa, name),
        EmitKind::Dot => export::to_dot(&dfa, name),
    })
}

#[cfg(test)]
mod tests;
