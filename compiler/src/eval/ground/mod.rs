//! Grounding of the built-ins, one module per family of the built-in table: queries, filters
//! (set filters and single-place predicates), rankings and measures, places, route-dependent
//! places and preferences.
//!
//! The checker has already chosen the table row of every call; [`grounding`] maps a row to the
//! function that gives it meaning on a map. A row without grounding semantics cannot ship: the
//! test `every_builtin_row_has_grounding_semantics` walks the whole table.

mod empty;
mod filters;
mod measures;
mod places;
mod preferences;
mod queries;
mod rankings;
mod route_places;
mod tour;

use super::Grounder;
use super::value::{PlaceVal, Value};
use m2rc_grammar::ast::{Arg, Expr, ExprKind, Span};
use m2rc_stdlib::builtins::Builtin;

/// The grounding semantics of one table row.
pub(super) type GroundFn = fn(&mut Grounder<'_, '_>, Call<'_>) -> Value;

/// One call of a built-in with its receiver and its arguments bound to the row's parameters
/// (defaults filled in).
pub(super) struct Call<'e> {
    pub e: &'e Expr,
    pub row: &'static Builtin,
    pub recv: Option<Value>,
    pub vals: Vec<Option<Value>>,
    pub args: &'e [Arg],
}

impl Call<'_> {
    pub fn name(&self) -> &'static str {
        self.row.name
    }

    /// The value bound to parameter `i`.
    pub fn arg(&self, i: usize) -> Option<Value> {
        self.vals.get(i).cloned().flatten()
    }

    /// The places of parameter `i` (a single place or a set), empty when absent.
    pub fn places(&self, i: usize) -> Vec<PlaceVal> {
        self.vals
            .get(i)
            .and_then(|v| v.as_ref())
            .and_then(Value::places)
            .unwrap_or_default()
    }

    /// The room ids among the places of parameter `i`.
    pub fn rooms(&self, i: usize) -> Vec<u32> {
        room_ids(&self.places(i))
    }

    pub fn number(&self, i: usize) -> Option<f64> {
        self.vals
            .get(i)
            .and_then(|v| v.as_ref())
            .and_then(Value::number)
    }

    pub fn travel(&self, i: usize) -> bool {
        matches!(self.vals.get(i), Some(Some(Value::Travel(true))))
    }

    /// The span of the `i`-th written argument (the call's span when there is none).
    pub fn arg_span(&self, i: usize) -> Span {
        self.args.get(i).map_or(self.e.span, |a| a.value.span)
    }

    pub fn recv_span(&self) -> Span {
        match &self.e.kind {
            ExprKind::Method { receiver, .. } => receiver.span,
            _ => self.e.span,
        }
    }
}

pub(super) fn room_ids(places: &[PlaceVal]) -> Vec<u32> {
    places
        .iter()
        .filter_map(|p| match p {
            PlaceVal::Room(x) => Some(*x),
            _ => None,
        })
        .collect()
}

/// The grounding function of a table row, or `None` when the row has no semantics (a bug the
/// table test catches).
pub(super) fn grounding(row: &Builtin) -> Option<GroundFn> {
    queries::lookup(row)
        .or_else(|| filters::lookup(row))
        .or_else(|| measures::lookup(row))
        .or_else(|| rankings::lookup(row))
        .or_else(|| places::lookup(row))
        .or_else(|| route_places::lookup(row))
        .or_else(|| preferences::lookup(row))
}

impl Grounder<'_, '_> {
    pub(super) fn call(
        &mut self,
        e: &Expr,
        name: &str,
        recv: Option<Value>,
        args: &[Arg],
    ) -> Value {
        let Some((row, vals)) = self.bind_args(name, recv.as_ref(), args) else {
            return self.unsupported(e);
        };
        if vals.iter().any(|v| matches!(v, Some(Value::Unknown))) {
            return Value::Unknown;
        }
        let Some(f) = grounding(row) else {
            return self.unsupported(e);
        };
        f(
            self,
            Call {
                e,
                row,
                recv,
                vals,
                args,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use m2rc_stdlib::builtins::BUILTINS;

    #[test]
    fn every_builtin_row_has_grounding_semantics() {
        let missing: Vec<String> = BUILTINS
            .iter()
            .filter(|b| super::grounding(b).is_none())
            .map(|b| b.signature(None))
            .collect();
        assert!(
            missing.is_empty(),
            "built-ins without grounding semantics: {missing:?}"
        );
    }

    #[test]
    fn families_do_not_overlap() {
        for b in BUILTINS {
            let n = [
                super::queries::lookup(b).is_some(),
                super::filters::lookup(b).is_some(),
                super::measures::lookup(b).is_some(),
                super::rankings::lookup(b).is_some(),
                super::places::lookup(b).is_some(),
                super::route_places::lookup(b).is_some(),
                super::preferences::lookup(b).is_some(),
            ]
            .iter()
            .filter(|x| **x)
            .count();
            assert_eq!(n, 1, "{} is grounded by {n} families", b.signature(None));
        }
    }
}
