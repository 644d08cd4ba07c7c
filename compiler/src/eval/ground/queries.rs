//! Queries: the sets every selection starts from.

use super::{Call, GroundFn};
use crate::eval::Grounder;
use crate::eval::value::{PlaceVal, Value};
use m2rc_stdlib::builtins::Builtin;

pub(super) fn lookup(row: &Builtin) -> Option<GroundFn> {
    match (row.name, row.is_method()) {
        ("objects", false) => Some(objects),
        ("rooms", false) => Some(rooms),
        _ => None,
    }
}

fn categories(c: &Call) -> Option<Vec<String>> {
    match c.arg(0) {
        Some(Value::Category(c)) => Some(c),
        _ => None,
    }
}

fn objects(g: &mut Grounder, c: Call) -> Value {
    let cats = categories(&c);
    Value::Set(
        g.q.map()
            .objects
            .iter()
            .filter(|o| cats.as_ref().is_none_or(|c| c.contains(&o.category)))
            .map(|o| PlaceVal::Object(o.id))
            .collect(),
    )
}

fn rooms(g: &mut Grounder, c: Call) -> Value {
    let cats = categories(&c);
    Value::Set(
        g.q.map()
            .rooms
            .iter()
            .filter(|r| cats.as_ref().is_none_or(|c| c.contains(&r.category)))
            .map(|r| PlaceVal::Room(r.id))
            .collect(),
    )
}
