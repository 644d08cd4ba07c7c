//! Preferences: soft terms of the route's cost.

use super::{Call, GroundFn};
use crate::eval::Grounder;
use crate::eval::value::{PlaceVal, Pref, Value, WallFollow};
use m2rc_stdlib::builtins::Builtin;

pub(super) fn lookup(row: &Builtin) -> Option<GroundFn> {
    if row.is_method() {
        return None;
    }
    match row.name {
        "near" | "far" => Some(near_far),
        "near_each" => Some(near_each),
        "closer" => Some(closer),
        "circle" | "follow_wall" | "patrol" => Some(path_shape),
        "through" => Some(through),
        "clearance" => Some(clearance),
        _ => None,
    }
}

fn near_far(_: &mut Grounder, c: Call) -> Value {
    let xs = c.places(0);
    Value::Pref(if c.name() == "near" {
        Pref::Near(xs)
    } else {
        Pref::Far(xs)
    })
}

fn near_each(_: &mut Grounder, c: Call) -> Value {
    Value::Pref(Pref::NearEach(c.places(0)))
}

fn closer(_: &mut Grounder, c: Call) -> Value {
    Value::Pref(Pref::Closer(c.places(0), c.places(1)))
}

fn path_shape(g: &mut Grounder, c: Call) -> Value {
    let dir = match c.arg(1) {
        Some(Value::Direction(d)) => Some(d),
        _ => None,
    };
    let place = |i: usize| match c.arg(i) {
        Some(Value::Place(p)) => Some(p),
        _ => None,
    };
    match (c.name(), c.arg(0)) {
        ("circle", Some(Value::Place(p))) => Value::Pref(Pref::Circle(p, dir)),
        (name, Some(Value::Place(PlaceVal::Room(room)))) => {
            let w = WallFollow {
                room,
                direction: dir,
                until: place(2),
                passing: place(3),
                avoiding: place(4),
            };
            Value::Pref(if name == "patrol" {
                Pref::Patrol(w)
            } else {
                Pref::FollowWall(w)
            })
        }
        _ => g.unsupported(c.e),
    }
}

fn through(_: &mut Grounder, c: Call) -> Value {
    let places = (0..4)
        .filter_map(|i| match c.arg(i) {
            Some(Value::Place(p)) => Some(p),
            _ => None,
        })
        .collect();
    Value::Pref(Pref::Through(places))
}

fn clearance(_: &mut Grounder, c: Call) -> Value {
    Value::Pref(Pref::Clearance(c.number(0).unwrap_or(0.5)))
}
