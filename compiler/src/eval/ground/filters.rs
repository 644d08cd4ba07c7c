//! Filters on sets and the matching single-place predicates (`Set<T>.near(x)` keeps elements,
//! `Object.near(x)` answers for one), plus `where`, `except`, `exists` and `is_empty`.
//!
//! A lambda filter evaluates its predicate once per candidate; sub-expressions of the predicate
//! that do not depend on the candidate are memoised by the evaluator (`expr.rs`).

use super::{Call, GroundFn};
use crate::eval::Grounder;
use crate::eval::value::{PlaceVal, Value};
use m2rc_stdlib::builtins::Builtin;
use m2rc_stdlib::grid::Cell;

pub(super) fn lookup(row: &Builtin) -> Option<GroundFn> {
    if !row.is_method() {
        return None;
    }
    match row.name {
        "in" | "near" | "on" | "inside" | "under" | "next_to" | "between" | "holding"
        | "containing" | "contains" | "adjacent_to" => Some(relation),
        "only_reachable_through" => Some(only_reachable_through),
        "except" => Some(except),
        "where" => Some(where_),
        "exists" => Some(exists),
        "is_empty" => Some(is_empty),
        _ => None,
    }
}

fn relation(g: &mut Grounder, c: Call) -> Value {
    let name = c.name();
    let (single, items) = match c.recv.clone() {
        Some(Value::Place(p)) => (true, vec![p]),
        Some(Value::Set(s)) => (false, s),
        _ => return g.unsupported(c.e),
    };
    let xs = c.places(0);
    let ys = c.places(1);
    let within = c.number(1).unwrap_or(g.q.thresholds.near_m);
    let corridors: Vec<Vec<Cell>> = if name == "between" {
        let mut v = Vec::new();
        for a in &xs {
            for b in &ys {
                if !a.same(b) {
                    v.push(g.q.hull_between(a.target(g.q), b.target(g.q)));
                }
            }
        }
        v
    } else {
        Vec::new()
    };
    let keep: Vec<PlaceVal> = items
        .into_iter()
        .filter(|p| holds(g, name, p, &xs, within, &corridors, &ys))
        .collect();
    if single {
        Value::Bool(!keep.is_empty())
    } else {
        Value::Set(keep)
    }
}

fn holds(
    g: &Grounder,
    name: &str,
    p: &PlaceVal,
    xs: &[PlaceVal],
    within: f64,
    corridors: &[Vec<Cell>],
    ys: &[PlaceVal],
) -> bool {
    let q = g.q;
    let obj = |x: &PlaceVal| match x {
        PlaceVal::Object(id) => q.map().object(*id),
        _ => None,
    };
    let room_ids = || super::room_ids(xs).into_iter();
    match name {
        "in" => xs.iter().any(|x| match x {
            PlaceVal::Region(r) => q.lies_in(p.target(q), &r.cells),
            _ => p.room_of(q).is_some_and(|r| room_ids().any(|x| x == r)),
        }),
        "near" => xs
            .iter()
            .any(|x| !x.same(p) && q.near(p.target(q), x.target(q), within)),
        "containing" | "contains" => match p {
            PlaceVal::Room(r) => xs.iter().any(|x| x.room_of(q) == Some(*r)),
            PlaceVal::Region(r) => xs.iter().any(|x| q.lies_in(x.target(q), &r.cells)),
            PlaceVal::Object(_) => false,
        },
        "adjacent_to" => {
            let PlaceVal::Room(r) = p else { return false };
            room_ids().any(|x| q.adjacent(*r, x))
        }
        "between" => {
            let Some(o) = obj(p) else { return false };
            if xs.iter().chain(ys).any(|x| x.same(p)) {
                return false;
            }
            let c = Cell::new(
                o.center[0].round().max(0.0) as u32,
                o.center[1].round().max(0.0) as u32,
            );
            corridors.iter().any(|cor| cor.binary_search(&c).is_ok())
        }
        "next_to" => {
            let Some(o) = obj(p) else { return false };
            xs.iter().any(|x| q.next_to_place(o, x.target(q)))
        }
        _ => {
            let Some(o) = obj(p) else { return false };
            xs.iter().filter_map(obj).any(|x| match name {
                "on" => q.on(o, x),
                "inside" => q.inside(o, x),
                "under" => q.under(o, x),
                "holding" => q.on(x, o) || q.inside(x, o),
                _ => false,
            })
        }
    }
}

fn only_reachable_through(g: &mut Grounder, c: Call) -> Value {
    let Some(Value::Place(PlaceVal::Room(r))) = c.recv else {
        return g.unsupported(c.e);
    };
    Value::Bool(g.q.only_reachable_through(r, &c.rooms(0)))
}

fn except(g: &mut Grounder, c: Call) -> Value {
    let Some(Value::Set(s)) = c.recv.clone() else {
        return g.unsupported(c.e);
    };
    let xs = c.places(0);
    Value::Set(
        s.into_iter()
            .filter(|p| !xs.iter().any(|x| x.same(p)))
            .collect(),
    )
}

fn where_(g: &mut Grounder, c: Call) -> Value {
    let (Some(Value::Set(s)), Some(Value::Lambda(f))) = (c.recv.clone(), c.arg(0)) else {
        return g.unsupported(c.e);
    };
    let mut out = Vec::new();
    g.memo.open();
    let mut failed = None;
    for p in s {
        match g.apply(&f, p.clone()) {
            Value::Bool(true) => out.push(p),
            Value::Bool(false) => {}
            Value::Unknown => {
                failed = Some(Value::Unknown);
                break;
            }
            _ => {
                failed = Some(g.unsupported(c.e));
                break;
            }
        }
    }
    g.memo.close();
    failed.unwrap_or(Value::Set(out))
}

fn exists(g: &mut Grounder, c: Call) -> Value {
    match c.recv {
        Some(Value::Set(s)) => Value::Bool(!s.is_empty()),
        _ => g.unsupported(c.e),
    }
}

fn is_empty(g: &mut Grounder, c: Call) -> Value {
    match c.recv {
        Some(Value::Set(s)) => Value::Bool(s.is_empty()),
        _ => g.unsupported(c.e),
    }
}
