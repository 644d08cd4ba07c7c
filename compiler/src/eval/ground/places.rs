//! Places built from the map: corners, doorways, neighbouring rooms and constructed regions.

use super::{Call, GroundFn};
use crate::eval::value::{PlaceVal, Value};
use crate::eval::{Grounder, Problem, codes};
use m2rc_grammar::ast::Expr;
use m2rc_stdlib::builtins::Builtin;
use m2rc_stdlib::grid::Cell;

pub(super) fn lookup(row: &Builtin) -> Option<GroundFn> {
    match (row.name, row.is_method()) {
        ("corners", true) => Some(corners),
        ("doorways", true) => Some(doorways),
        ("adjacent", true) => Some(adjacent),
        ("open_area", true) => Some(open_area),
        ("doorways_between", false) => Some(doorways_between),
        ("area_between", false) => Some(area_between),
        ("area_near", false) => Some(area_near),
        ("center", false) => Some(center),
        ("area_enclosed", false) => Some(area_enclosed),
        ("house_corners", false) => Some(house_corners),
        ("house_center", false) => Some(house_center),
        _ => None,
    }
}

fn recv_rooms(c: &Call) -> Vec<u32> {
    super::room_ids(&c.recv.as_ref().and_then(Value::places).unwrap_or_default())
}

fn corners(g: &mut Grounder, c: Call) -> Value {
    let mut out = Vec::new();
    for room in recv_rooms(&c) {
        let rl = PlaceVal::Room(room).label(g.q);
        for (i, cells) in g.q.corners(room).into_iter().enumerate() {
            out.push(PlaceVal::region(
                cells,
                "corner",
                vec![rl.clone()],
                Some(g.q.thresholds.corner_radius_m),
                format!("corner {} of {rl}", i + 1),
            ));
        }
    }
    Value::Set(out)
}

fn doorways(g: &mut Grounder, c: Call) -> Value {
    let mut out = Vec::new();
    for room in recv_rooms(&c) {
        for (other, cells) in g.room_doors(room) {
            out.push(g.doorway_region(room, other, cells));
        }
    }
    Value::Set(out)
}

fn adjacent(g: &mut Grounder, c: Call) -> Value {
    match c.recv {
        Some(Value::Place(PlaceVal::Room(r))) => Value::Set(
            g.q.adjacent_rooms(r)
                .into_iter()
                .map(PlaceVal::Room)
                .collect(),
        ),
        _ => g.unsupported(c.e),
    }
}

/// The union of the receiver rooms' open-plan areas, by room id.
fn open_area(g: &mut Grounder, c: Call) -> Value {
    let mut rooms: Vec<u32> = recv_rooms(&c)
        .into_iter()
        .flat_map(|r| g.q.open_area(r))
        .collect();
    rooms.sort_unstable();
    rooms.dedup();
    Value::Set(rooms.into_iter().map(PlaceVal::Room).collect())
}

fn doorways_between(g: &mut Grounder, c: Call) -> Value {
    match (c.arg(0), c.arg(1)) {
        (Some(Value::Place(PlaceVal::Room(a))), Some(Value::Place(PlaceVal::Room(b)))) => {
            let doors: Vec<Vec<Cell>> =
                g.q.doorways_between(a, b)
                    .into_iter()
                    .map(|p| p.cells.clone())
                    .collect();
            Value::Set(
                doors
                    .into_iter()
                    .map(|cells| g.doorway_region(a, b, cells))
                    .collect(),
            )
        }
        _ => g.unsupported(c.e),
    }
}

fn area_between(g: &mut Grounder, c: Call) -> Value {
    let (xs, ys) = (c.places(0), c.places(1));
    // With sets, the nearest pair.
    let mut best: Option<(f64, PlaceVal, PlaceVal)> = None;
    for a in &xs {
        for b in &ys {
            if let Some(d) = g.q.distance(a.target(g.q), b.target(g.q))
                && best.as_ref().is_none_or(|x| d < x.0)
            {
                best = Some((d, a.clone(), b.clone()));
            }
        }
    }
    let Some((_, a, b)) = best else {
        return g.report(Problem::error(
            codes::EMPTY_PLACE,
            c.e.span,
            "`area_between` needs a place on each side, and one side matched nothing on this map",
        ));
    };
    let cells = g.q.corridor(a.target(g.q), b.target(g.q));
    let (la, lb) = (a.label(g.q), b.label(g.q));
    g.nonempty_region(
        c.e,
        cells,
        "area_between",
        vec![la.clone(), lb.clone()],
        None,
        format!("area between {la} and {lb}"),
    )
}

fn area_near(g: &mut Grounder, c: Call) -> Value {
    let Some(Value::Place(x)) = c.arg(0) else {
        return g.unsupported(c.e);
    };
    let within = c.number(1).unwrap_or(0.5);
    let cells = g.q.area_near(x.target(g.q), within);
    let l = x.label(g.q);
    g.nonempty_region(
        c.e,
        cells,
        "area_near",
        vec![l.clone()],
        Some(within),
        format!("area within {within} m of {l}"),
    )
}

fn center(g: &mut Grounder, c: Call) -> Value {
    let xs = c.places(0);
    let centers: Vec<[f64; 2]> = xs.iter().filter_map(|p| p.center(g.q)).collect();
    let labels: Vec<String> = xs.iter().map(|p| p.label(g.q)).collect();
    let label = format!(
        "centre of {}",
        if labels.len() == 1 {
            labels[0].clone()
        } else {
            format!("{} places", labels.len())
        }
    );
    let cells = g.q.center_of(&centers);
    g.nonempty_region(c.e, cells, "center", labels, Some(0.3), label)
}

fn area_enclosed(g: &mut Grounder, c: Call) -> Value {
    let xs = c.places(0);
    if xs.len() < 3 {
        return g.report(
            Problem::error(
                codes::EMPTY_PLACE,
                c.e.span,
                format!(
                    "`area_enclosed` needs three or more places, and {} matched here",
                    xs.len()
                ),
            )
            .help("for two places write `area_between(a, b)`"),
        );
    }
    let targets: Vec<_> = xs.iter().map(|p| p.target(g.q)).collect();
    let cells = g.q.enclosed(&targets);
    let labels: Vec<String> = xs.iter().map(|p| p.label(g.q)).collect();
    let label = format!("area enclosed by {}", labels.join(", "));
    g.nonempty_region(c.e, cells, "area_enclosed", labels, None, label)
}

/// Every room cell of the house, sorted.
fn house_cells(g: &Grounder) -> Vec<Cell> {
    let mut all: Vec<Cell> =
        g.q.map()
            .rooms
            .iter()
            .flat_map(|r| g.q.room_cells(r.id).iter().copied())
            .collect();
    all.sort_unstable();
    all.dedup();
    all
}

/// The house's corners: for each diagonal direction (north-west, north-east, south-east,
/// south-west on screen) the room cell farthest that way, with the room floor within the corner
/// radius of it. An L-shaped house thus gets its four outermost corners.
fn house_corners(g: &mut Grounder, c: Call) -> Value {
    let all = house_cells(g);
    if all.is_empty() {
        return g.report(Problem::error(
            codes::EMPTY_PLACE,
            c.e.span,
            "this map has no room cells, so the house has no corners",
        ));
    }
    let radius = g.q.thresholds.corner_radius_m;
    let rc = radius / g.q.res();
    let names = ["north-west", "north-east", "south-east", "south-west"];
    let dirs: [(f64, f64); 4] = [(-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (1.0, -1.0)];
    let mut out: Vec<PlaceVal> = Vec::new();
    for (name, (dr, dc)) in names.iter().zip(dirs) {
        let score = |x: &Cell| x.row as f64 * dr + x.col as f64 * dc;
        let Some(tip) = all
            .iter()
            .copied()
            .max_by(|a, b| score(a).total_cmp(&score(b)).then(b.cmp(a)))
        else {
            continue;
        };
        let cells: Vec<Cell> = all.iter().copied().filter(|x| x.dist(tip) <= rc).collect();
        let p = PlaceVal::region(
            cells,
            "house_corner",
            vec!["house".into()],
            Some(radius),
            format!("{name} corner of the house"),
        );
        if !out.iter().any(|q| q.same(&p)) {
            out.push(p);
        }
    }
    Value::Set(out)
}

fn house_center(g: &mut Grounder, c: Call) -> Value {
    let all = house_cells(g);
    let Some(centre) = m2rc_stdlib::query::MapQuery::centroid(&all) else {
        return g.report(Problem::error(
            codes::EMPTY_PLACE,
            c.e.span,
            "this map has no room cells, so the house has no centre",
        ));
    };
    let cells = g.q.center_of(&[centre]);
    g.nonempty_region(
        c.e,
        cells,
        "house_center",
        vec!["house".into()],
        Some(0.3),
        "centre of the house".into(),
    )
}

impl Grounder<'_, '_> {
    /// The doorways of a room, each with the room on its other side.
    pub(in crate::eval) fn room_doors(&self, room: u32) -> Vec<(u32, Vec<Cell>)> {
        self.q
            .doorways(room)
            .into_iter()
            .map(|p| {
                (
                    if p.rooms.0 == room {
                        p.rooms.1
                    } else {
                        p.rooms.0
                    },
                    p.cells.clone(),
                )
            })
            .collect()
    }

    pub(in crate::eval) fn doorway_region(&self, a: u32, b: u32, cells: Vec<Cell>) -> PlaceVal {
        let (la, lb) = (
            PlaceVal::Room(a).label(self.q),
            PlaceVal::Room(b).label(self.q),
        );
        PlaceVal::region(
            cells,
            "doorway",
            vec![la.clone(), lb.clone()],
            None,
            format!("doorway {la} / {lb}"),
        )
    }

    pub(in crate::eval) fn nonempty_region(
        &mut self,
        e: &Expr,
        cells: Vec<Cell>,
        kind: &str,
        from: Vec<String>,
        r: Option<f64>,
        label: String,
    ) -> Value {
        if cells.is_empty() {
            return self.report(Problem::error(
                codes::EMPTY_PLACE,
                e.span,
                format!("{label} covers no cell of the map"),
            ));
        }
        Value::Place(PlaceVal::region(cells, kind, from, r, label))
    }
}
