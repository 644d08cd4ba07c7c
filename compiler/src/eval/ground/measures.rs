//! Counts and measures: numbers and distances read off places.

use super::{Call, GroundFn};
use crate::eval::value::{PlaceVal, Value};
use crate::eval::{Grounder, Problem, codes};
use m2rc_stdlib::builtins::Builtin;

pub(super) fn lookup(row: &Builtin) -> Option<GroundFn> {
    if !row.is_method() {
        return None;
    }
    match row.name {
        "count" => Some(count),
        "distance" => Some(distance),
        "area" => Some(area),
        "room" => Some(room),
        "footprint_area" | "length" | "width" | "squareness" => Some(shape),
        _ => None,
    }
}

fn count(g: &mut Grounder, c: Call) -> Value {
    match c.recv {
        Some(Value::Set(s)) => Value::Int(s.len() as i64),
        _ => g.unsupported(c.e),
    }
}

fn distance(g: &mut Grounder, c: Call) -> Value {
    let (Some(Value::Place(a)), Some(Value::Place(b))) = (c.recv.clone(), c.arg(0)) else {
        return g.unsupported(c.e);
    };
    let travel = c.travel(1);
    match g.distance(&a, &b, travel) {
        Some(d) => Value::Distance(d),
        None => {
            let (la, lb) = (a.label(g.q), b.label(g.q));
            let p = if travel {
                Problem::error(
                    codes::UNREACHABLE,
                    c.e.span,
                    format!("no traversable path between {la} and {lb}"),
                )
            } else {
                Problem::error(
                    codes::EMPTY_PLACE,
                    c.e.span,
                    format!("{la} or {lb} covers no cell of the map"),
                )
            };
            g.report(p)
        }
    }
}

fn area(g: &mut Grounder, c: Call) -> Value {
    match c.recv {
        Some(Value::Place(PlaceVal::Room(r))) => Value::Number(g.q.room_area(r)),
        _ => g.unsupported(c.e),
    }
}

fn room(g: &mut Grounder, c: Call) -> Value {
    let Some(Value::Place(p)) = c.recv.clone() else {
        return g.unsupported(c.e);
    };
    match p.room_of(g.q) {
        Some(r) => Value::Place(PlaceVal::Room(r)),
        None => {
            let l = p.label(g.q);
            g.report(Problem::error(
                codes::NO_ROOM,
                c.recv_span(),
                format!("{l} lies in no room"),
            ))
        }
    }
}

/// Length and width of a footprint in metres: its extents along its principal axes (so a rotated
/// sofa measures the same as an axis-aligned one), each counted in whole cells.
pub(super) fn extents(cells: &[m2rc_stdlib::grid::Cell], res: f64) -> (f64, f64) {
    let n = cells.len() as f64;
    if cells.is_empty() {
        return (0.0, 0.0);
    }
    let (mr, mc) = cells.iter().fold((0.0, 0.0), |(r, c), x| {
        (r + x.row as f64 / n, c + x.col as f64 / n)
    });
    let (mut srr, mut scc, mut src) = (0.0, 0.0, 0.0);
    for x in cells {
        let (dr, dc) = (x.row as f64 - mr, x.col as f64 - mc);
        srr += dr * dr;
        scc += dc * dc;
        src += dr * dc;
    }
    let theta = 0.5 * (2.0 * src).atan2(srr - scc);
    let (u, v) = ([theta.cos(), theta.sin()], [-theta.sin(), theta.cos()]);
    let span = |axis: [f64; 2]| {
        let (lo, hi) = cells.iter().fold((f64::MAX, f64::MIN), |(lo, hi), x| {
            let t = x.row as f64 * axis[0] + x.col as f64 * axis[1];
            (lo.min(t), hi.max(t))
        });
        (hi - lo).round() + 1.0
    };
    let (a, b) = (span(u) * res, span(v) * res);
    (a.max(b), a.min(b))
}

fn shape(g: &mut Grounder, c: Call) -> Value {
    let Some(Value::Place(PlaceVal::Object(id))) = c.recv else {
        return g.unsupported(c.e);
    };
    let Some(o) = g.q.map().object(id) else {
        return g.unsupported(c.e);
    };
    let res = g.q.res();
    let (length, width) = extents(&o.footprint, res);
    match c.name() {
        "footprint_area" => Value::Number(o.footprint.len() as f64 * res * res),
        "length" => Value::Distance(length),
        "width" => Value::Distance(width),
        _ if length > 0.0 => Value::Number(width / length),
        _ => Value::Number(0.0),
    }
}

#[cfg(test)]
mod tests {
    use m2rc_stdlib::grid::Cell;

    #[test]
    fn extents_measure_along_the_footprint_axes() {
        // A 2 x 6 bar, axis-aligned, then along the diagonal.
        let bar: Vec<Cell> = (0..2)
            .flat_map(|r| (0..6).map(move |c| Cell::new(r, c)))
            .collect();
        let (l, w) = super::extents(&bar, 0.5);
        assert_eq!((l, w), (3.0, 1.0));
        let diag: Vec<Cell> = (0..6).map(|i| Cell::new(i + 10, i + 10)).collect();
        let (l, w) = super::extents(&diag, 1.0);
        assert!(l > 7.0 && w <= 1.0, "{l} {w}");
        let square: Vec<Cell> = (0..4)
            .flat_map(|r| (0..4).map(move |c| Cell::new(r, c)))
            .collect();
        assert_eq!(super::extents(&square, 1.0), (4.0, 4.0));
    }
}
