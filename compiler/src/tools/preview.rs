//! Short previews of query results: what a model needs to decide its next call (how many, which
//! ids, in which rooms), never the cells or distances fields behind them.

use crate::eval::{PlaceVal, Pref, Value};
use m2rc_stdlib::query::MapQuery;

/// At most this many elements of a set are named in its preview.
const SHOWN: usize = 6;

fn place_kind(p: &PlaceVal) -> &'static str {
    match p {
        PlaceVal::Object(_) => "object",
        PlaceVal::Room(_) => "room",
        PlaceVal::Region(_) => "region",
    }
}

fn area(p: &PlaceVal, q: &MapQuery) -> String {
    match p {
        PlaceVal::Room(id) => format!(" ({:.1} m²)", q.room_area(*id)),
        _ => String::new(),
    }
}

/// The handle kind and the preview text of a value.
pub fn preview(v: &Value, q: &MapQuery) -> (&'static str, String) {
    match v {
        Value::Place(p) => (place_kind(p), format!("{}{}", p.label(q), area(p, q))),
        Value::Set(s) => {
            let kinds: Vec<&str> = s.iter().map(place_kind).collect();
            let what = match kinds.first() {
                Some(k) if kinds.iter().all(|x| x == k) => format!("{k}s"),
                _ => "places".into(),
            };
            let mut names: Vec<String> = s
                .iter()
                .take(SHOWN)
                .map(|p| format!("{}{}", p.label(q), area(p, q)))
                .collect();
            if s.len() > SHOWN {
                names.push(format!("… {} more", s.len() - SHOWN));
            }
            ("set", format!("{} {what} [{}]", s.len(), names.join(", ")))
        }
        Value::Int(i) => ("number", i.to_string()),
        Value::Number(x) => ("number", format!("{x:.3}")),
        Value::Distance(m) => ("distance", format!("{m:.2} m")),
        Value::Bool(b) => ("bool", b.to_string()),
        Value::Category(c) => ("category", c.join(" | ")),
        Value::Direction(d) => ("word", format!("{d:?}").to_lowercase()),
        Value::Travel(t) => ("word", if *t { "travel" } else { "straight" }.into()),
        Value::Pref(p) => ("preference", pref_text(p, q)),
        Value::Lambda(l) => ("function", format!("a function of `{}`", l.param)),
        Value::Str(s) => ("text", s.clone()),
        Value::Unknown => ("value", "unknown".into()),
    }
}

fn labels(ps: &[PlaceVal], q: &MapQuery) -> String {
    let mut v: Vec<String> = ps.iter().take(SHOWN).map(|p| p.label(q)).collect();
    if ps.len() > SHOWN {
        v.push(format!("… {} more", ps.len() - SHOWN));
    }
    v.join(", ")
}

fn pref_text(p: &Pref, q: &MapQuery) -> String {
    match p {
        Pref::Near(ps) => format!("stay near {}", labels(ps, q)),
        Pref::NearEach(ps) => format!("pass near each of {}", labels(ps, q)),
        Pref::Far(ps) => format!("keep far from {}", labels(ps, q)),
        Pref::Closer(a, b) => format!("closer to {} than to {}", labels(a, q), labels(b, q)),
        Pref::Circle(c, _) => format!("circle {}", c.label(q)),
        Pref::FollowWall(_) => "follow a wall".into(),
        Pref::Patrol(_) => "patrol a room's walls".into(),
        Pref::Through(ps) => format!("pass through {}", labels(ps, q)),
        Pref::Clearance(m) => format!("keep {m:.2} m clearance"),
    }
}
