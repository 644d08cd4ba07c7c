//! Rankings (`Set<T> -> T`) and orderings (`Set<T> -> Set<T>`): by distance, by area, by a key,
//! and the checked `only`.

use super::{Call, GroundFn};
use crate::eval::value::{Lambda, PlaceVal, Value};
use crate::eval::{Grounder, Problem, codes};
use m2rc_grammar::ast::{Expr, Span};
use m2rc_stdlib::builtins::Builtin;

pub(super) fn lookup(row: &Builtin) -> Option<GroundFn> {
    if !row.is_method() {
        return None;
    }
    match row.name {
        "nearest" | "farthest" | "kth_nearest" | "kth_farthest" => Some(by_distance),
        "largest" | "smallest" => Some(by_area),
        "max_by" | "min_by" => Some(by_key),
        "sorted_by" | "sorted_by_descending" => Some(sorted_by),
        "nearest_first" | "farthest_first" => Some(ordered_by_distance),
        "reversed" => Some(reversed),
        "kth" => Some(kth),
        "only" => Some(only),
        "tour" => Some(super::tour::tour),
        _ => None,
    }
}

fn set(c: &Call) -> Option<Vec<PlaceVal>> {
    match &c.recv {
        Some(Value::Set(s)) => Some(s.clone()),
        _ => None,
    }
}

fn by_distance(g: &mut Grounder, c: Call) -> Value {
    let name = c.name();
    let Some(s) = set(&c) else {
        return g.unsupported(c.e);
    };
    let kth = name.starts_with("kth");
    let off = usize::from(kth);
    let Some(to) = targets(c.arg(off)) else {
        return g.unsupported(c.e);
    };
    let travel = c.travel(off + 1);
    let k = if kth {
        c.number(0).unwrap_or(1.0) as i64
    } else {
        1
    };
    g.rank_by_distance(&c, s, &to, travel, k)
}

fn by_area(g: &mut Grounder, c: Call) -> Value {
    let Some(s) = set(&c) else {
        return g.unsupported(c.e);
    };
    let mut keyed: Vec<(f64, PlaceVal)> = s
        .into_iter()
        .map(|p| {
            let a = match &p {
                PlaceVal::Room(r) => g.q.room_area(*r),
                other => g.q.cells(other.target(g.q)).len() as f64,
            };
            (a, p)
        })
        .collect();
    if c.name() == "largest" {
        keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
    } else {
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    g.first_ranked(&c, keyed)
}

fn by_key(g: &mut Grounder, c: Call) -> Value {
    let (Some(s), Some(Value::Lambda(f))) = (set(&c), c.arg(0)) else {
        return g.unsupported(c.e);
    };
    let Some(mut keyed) = g.keys(&f, &s) else {
        return Value::Unknown;
    };
    if c.name() == "max_by" {
        keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
    } else {
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    g.first_ranked(&c, keyed)
}

fn sorted_by(g: &mut Grounder, c: Call) -> Value {
    let (Some(s), Some(Value::Lambda(f))) = (set(&c), c.arg(0)) else {
        return g.unsupported(c.e);
    };
    match g.keys(&f, &s) {
        Some(mut keyed) => {
            // Stable sorts: ties keep the set's order either way.
            if c.name() == "sorted_by_descending" {
                keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
            } else {
                keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            Value::Set(keyed.into_iter().map(|(_, p)| p).collect())
        }
        None => Value::Unknown,
    }
}

/// The `to:` of a ranking: one place, or a non-empty set meaning its nearest member ("the chair
/// nearest to any of the dressers").
fn targets(v: Option<Value>) -> Option<Vec<PlaceVal>> {
    match v? {
        Value::Place(p) => Some(vec![p]),
        Value::Set(s) if !s.is_empty() => Some(s),
        _ => None,
    }
}

fn ordered_by_distance(g: &mut Grounder, c: Call) -> Value {
    let (Some(s), Some(to)) = (set(&c), targets(c.arg(0))) else {
        return g.unsupported(c.e);
    };
    let travel = c.travel(1);
    let mut keyed: Vec<(f64, PlaceVal)> = s
        .into_iter()
        .map(|p| (g.distance_to_any(&p, &to, travel), p))
        .collect();
    let far = c.name() == "farthest_first";
    // Unreachable elements go last in both orders, as in the rankings.
    keyed.sort_by(|a, b| match (a.0.is_finite(), b.0.is_finite(), far) {
        (true, false, _) => std::cmp::Ordering::Less,
        (false, true, _) => std::cmp::Ordering::Greater,
        (_, _, true) => b.0.total_cmp(&a.0),
        _ => a.0.total_cmp(&b.0),
    });
    Value::Set(keyed.into_iter().map(|(_, p)| p).collect())
}

fn reversed(g: &mut Grounder, c: Call) -> Value {
    let Some(mut s) = set(&c) else {
        return g.unsupported(c.e);
    };
    s.reverse();
    Value::Set(s)
}

fn kth(g: &mut Grounder, c: Call) -> Value {
    let Some(s) = set(&c) else {
        return g.unsupported(c.e);
    };
    let k = c.number(0).unwrap_or(1.0) as i64;
    let n = s.len() as i64;
    if k < 1 || k > n {
        return g.report(
            Problem::error(
                codes::ORDINAL_OUT_OF_RANGE,
                c.arg_span(0),
                format!("k = {k}, but the selection has {n} element(s)"),
            )
            .label(c.recv_span(), format!("{n} candidate(s) on this map")),
        );
    }
    Value::Place(s[k as usize - 1].clone())
}

fn only(g: &mut Grounder, c: Call) -> Value {
    let Some(s) = set(&c) else {
        return g.unsupported(c.e);
    };
    g.only(c.e, c.recv_span(), s)
}

impl Grounder<'_, '_> {
    /// Evaluates a ranking key per element; `None` (with the error already reported) on failure.
    pub(super) fn keys(&mut self, f: &Lambda, s: &[PlaceVal]) -> Option<Vec<(f64, PlaceVal)>> {
        let mut out = Vec::with_capacity(s.len());
        self.memo.open();
        for p in s {
            match self.apply(f, p.clone()).number() {
                Some(k) => out.push((k, p.clone())),
                None => {
                    self.memo.close();
                    return None;
                }
            }
        }
        self.memo.close();
        Some(out)
    }

    fn first_ranked(&mut self, c: &Call, keyed: Vec<(f64, PlaceVal)>) -> Value {
        match keyed.into_iter().next() {
            Some((_, p)) => Value::Place(p),
            None => {
                let notes = self.category_notes(c.recv_span());
                self.report(
                    Problem::error(
                        codes::EMPTY_RANKING,
                        c.e.span,
                        format!("`.{}()` of an empty selection", c.name()),
                    )
                    .label(c.recv_span(), "this selection has no element on this map")
                    .notes(notes),
                )
            }
        }
    }

    /// The distance from `p` to the nearest of `to` (infinite when none is reachable). One travel
    /// field per member of `to`, each cached: the cost grows with the set, never beyond it.
    fn distance_to_any(&mut self, p: &PlaceVal, to: &[PlaceVal], travel: bool) -> f64 {
        to.iter()
            .filter_map(|t| self.distance(p, t, travel))
            .fold(f64::INFINITY, f64::min)
    }

    fn rank_by_distance(
        &mut self,
        c: &Call,
        s: Vec<PlaceVal>,
        to: &[PlaceVal],
        travel: bool,
        k: i64,
    ) -> Value {
        if s.is_empty() {
            return self.first_ranked(c, Vec::new());
        }
        let mut keyed: Vec<(f64, PlaceVal)> = s
            .into_iter()
            .map(|p| (self.distance_to_any(&p, to, travel), p))
            .collect();
        let far = c.name().contains("farthest");
        // Unreachable candidates rank last either way.
        keyed.sort_by(|a, b| match (a.0.is_finite(), b.0.is_finite(), far) {
            (true, false, _) => std::cmp::Ordering::Less,
            (false, true, _) => std::cmp::Ordering::Greater,
            (_, _, true) => b.0.total_cmp(&a.0),
            _ => a.0.total_cmp(&b.0),
        });
        let n = keyed.len() as i64;
        if k < 1 || k > n {
            return self.report(
                Problem::error(
                    codes::ORDINAL_OUT_OF_RANGE,
                    c.arg_span(0),
                    format!("k = {k}, but the selection has {n} element(s)"),
                )
                .label(c.recv_span(), format!("{n} candidate(s) on this map")),
            );
        }
        let (d, p) = keyed.swap_remove(k as usize - 1);
        if !d.is_finite() {
            let l = to
                .iter()
                .map(|t| t.label(self.q))
                .collect::<Vec<_>>()
                .join(" or ");
            return self.report(Problem::error(
                codes::UNREACHABLE,
                c.e.span,
                format!("no candidate can be reached from {l} (travel distance undefined)"),
            ));
        }
        Value::Place(p)
    }

    fn only(&mut self, e: &Expr, recv_span: Span, s: Vec<PlaceVal>) -> Value {
        match s.len() {
            1 => Value::Place(s.into_iter().next().unwrap_or(PlaceVal::Room(0))),
            0 => {
                let mut p = Problem::error(
                    codes::EMPTY_SELECTION,
                    e.span,
                    "`.only()` found no candidate on this map",
                )
                .label(recv_span, "this selection is empty here");
                for note in self.category_notes(recv_span) {
                    p = p.note(note);
                }
                self.report(p.help("check the category and filters, or guard the choice with `if s.exists() { ... } else { ... }`"))
            }
            n => {
                let notes: Vec<String> = s.iter().map(|p| self.describe(p)).collect();
                self.report(
                    Problem::error(codes::AMBIGUOUS_SELECTION, e.span, format!("`.only()` found {n} candidates on this map"))
                        .label(recv_span, format!("{n} candidates here"))
                        .notes(notes)
                        .help("pick one with a ranking (`.nearest()`, `.farthest()`, `.largest()`, `.min_by(...)`) or narrow it (`.in(room)`, `.near(x)`)"),
                )
            }
        }
    }
}
