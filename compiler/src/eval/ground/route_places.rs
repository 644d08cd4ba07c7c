//! Route-dependent places: read off the planned route when there is one, else off the shortest
//! traversable path from the current stage's start. Each resolution is recorded as a
//! [`RouteBinding`] so the pipeline can re-ground against the planned route until it is stable.

use super::{Call, GroundFn};
use crate::eval::value::{PlaceVal, Value};
use crate::eval::{Grounder, Problem, codes};
use crate::ir::{BoundAgainst, RouteBinding, SourceSpan};
use m2rc_grammar::ast::Expr;
use m2rc_stdlib::builtins::Builtin;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{Target, nominal_path};

pub(super) fn lookup(row: &Builtin) -> Option<GroundFn> {
    if row.is_method() {
        return None;
    }
    match row.name {
        "room_before_entering" | "doorway_leaving" | "doorway_entering" => Some(of_room),
        "first_entered" => Some(first_entered),
        "kth_entered" => Some(kth_entered),
        "visited" => Some(visited),
        "left_behind" => Some(left_behind),
        _ => None,
    }
}

fn of_room(g: &mut Grounder, c: Call) -> Value {
    let Some(Value::Place(PlaceVal::Room(room))) = c.arg(0) else {
        return g.unsupported(c.e);
    };
    g.route_place(c.e, c.name(), room)
}

fn first_entered(g: &mut Grounder, c: Call) -> Value {
    let rooms = c.rooms(0);
    g.first_entered(c.e, &rooms)
}

fn kth_entered(g: &mut Grounder, c: Call) -> Value {
    let rooms = c.rooms(0);
    let k = c.number(1).unwrap_or(1.0) as i64;
    let order: Vec<u32> = if let Some(r) = g.route {
        // Rooms of the set in the order the route first enters them; the start room last, as
        // in `first_entered`.
        let v = m2rc_stdlib::query::room_visits(g.q, r);
        let mut out: Vec<u32> = Vec::new();
        for x in v.iter().skip(1).chain(v.first()) {
            if rooms.contains(&x.room) && !out.contains(&x.room) {
                out.push(x.room);
            }
        }
        out
    } else {
        // Before planning: by travel distance from the stage start.
        let here = g.here.clone();
        let f = g.travel_from(&here);
        let mut keyed: Vec<(f64, u32)> = rooms
            .iter()
            .map(|&r| (f.to(g.q.room_cells(r)).unwrap_or(f64::INFINITY), r))
            .filter(|(d, _)| d.is_finite())
            .collect();
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        keyed.into_iter().map(|(_, r)| r).collect()
    };
    let n = order.len() as i64;
    if k < 1 || k > n {
        return g.report(
            Problem::error(
                codes::ROUTE_PLACE_UNDEFINED,
                c.e.span,
                format!("`kth_entered` is undefined here: k = {k}, but the route enters {n} of these rooms"),
            )
            .label(c.arg_span(1), "this ordinal"),
        );
    }
    let r = order[k as usize - 1];
    let l = PlaceVal::Room(r).label(g.q);
    g.bind(c.e, "kth_entered", l);
    Value::Place(PlaceVal::Room(r))
}

fn visited(g: &mut Grounder, c: Call) -> Value {
    let rooms = g.visited_rooms();
    bind_rooms(g, &c, rooms)
}

/// Records a set of rooms read off the route as the call's binding, and returns it.
fn bind_rooms(g: &mut Grounder, c: &Call, rooms: Vec<u32>) -> Value {
    let labels: Vec<String> = rooms
        .iter()
        .map(|&r| PlaceVal::Room(r).label(g.q))
        .collect();
    g.bind(c.e, c.name(), labels.join(", "));
    Value::Set(rooms.into_iter().map(PlaceVal::Room).collect())
}

/// `visited()` without the room the stage starts in: `avoid left_behind()` is "without going
/// back through a room you have already crossed".
fn left_behind(g: &mut Grounder, c: Call) -> Value {
    let (rooms, current) = g.visited_rooms_and_current();
    let rooms: Vec<u32> = rooms.into_iter().filter(|&r| Some(r) != current).collect();
    bind_rooms(g, &c, rooms)
}

impl Grounder<'_, '_> {
    fn visited_rooms(&mut self) -> Vec<u32> {
        self.visited_rooms_and_current().0
    }

    /// The rooms the route has been in before the current stage starts, in order: off the
    /// planned route up to its arrival at each earlier destination in turn, else off the
    /// shortest paths between the earlier destinations; and the room the stage starts in (the
    /// last room of that path, or the start's).
    fn visited_rooms_and_current(&mut self) -> (Vec<u32>, Option<u32>) {
        let mut path: Vec<Cell> = Vec::new();
        let mut from = self.start.clone();
        let mut pos = 0;
        for target in self.reached.clone() {
            let band: std::collections::HashSet<Cell> =
                self.q.band(target.target(self.q)).into_iter().collect();
            match self.route {
                Some(r) => {
                    let end = (pos..r.len())
                        .find(|&i| band.contains(&r[i]))
                        .map_or(r.len(), |i| i + 1);
                    path.extend_from_slice(&r[pos.min(end)..end]);
                    pos = end;
                }
                None => {
                    let mut goal: Vec<Cell> = band.into_iter().collect();
                    goal.sort_unstable();
                    path.extend(
                        nominal_path(self.q, from.target(self.q), &goal).unwrap_or_default(),
                    );
                }
            }
            from = target;
        }
        let mut out: Vec<u32> = self
            .q
            .room_of(self.start.target(self.q))
            .into_iter()
            .collect();
        let visits = m2rc_stdlib::query::room_visits(self.q, &path);
        let current = visits
            .last()
            .map(|v| v.room)
            .or_else(|| out.first().copied());
        for v in visits {
            if !out.contains(&v.room) {
                out.push(v.room);
            }
        }
        (out, current)
    }

    pub(in crate::eval) fn bind(&mut self, e: &Expr, function: &str, resolved: String) {
        let against = if self.route.is_some() {
            BoundAgainst::Planned
        } else {
            BoundAgainst::Nominal
        };
        self.bindings.push(RouteBinding {
            function: function.into(),
            resolved,
            against,
            span: SourceSpan::new(self.source, e.span),
        });
    }

    /// The path a route-dependent place is read from: the planned route, or the shortest path
    /// from the current stage's start into `room`.
    fn path_into(&mut self, room: u32) -> Option<Vec<Cell>> {
        if let Some(r) = self.route {
            return Some(r.to_vec());
        }
        let cells = self.q.room_cells(room).to_vec();
        nominal_path(self.q, self.here.target(self.q), &cells)
    }

    fn route_place(&mut self, e: &Expr, name: &str, room: u32) -> Value {
        let rl = PlaceVal::Room(room).label(self.q);
        let planned = self.route.is_some();
        let path = self.path_into(room).unwrap_or_default();
        let result: Option<PlaceVal> = match name {
            "room_before_entering" => self.q.room_before_entering(&path, room).map(PlaceVal::Room),
            "doorway_entering" => self
                .q
                .doorway_entering(&path, room)
                .map(|c| self.entering_region(&path, room, c)),
            _ if planned => self
                .q
                .doorway_leaving(&path, room)
                .map(|c| self.leaving_region(&path, room, c)),
            _ => {
                // Before planning: the doorway of the room nearest the stage's start.
                let here = self.here.clone();
                let mut best: Option<(f64, u32, Vec<Cell>)> = None;
                for (other, cells) in self.room_doors(room) {
                    let d = self
                        .q
                        .distance(Target::Cells(&cells), here.target(self.q))
                        .unwrap_or(f64::INFINITY);
                    if best.as_ref().is_none_or(|b| d < b.0) {
                        best = Some((d, other, cells));
                    }
                }
                best.map(|(_, other, cells)| self.doorway_region(room, other, cells))
            }
        };
        match result {
            Some(p) => {
                let l = p.label(self.q);
                self.bind(e, name, l);
                Value::Place(p)
            }
            None => {
                let why = match name {
                    "doorway_leaving" => format!("the route never leaves {rl}"),
                    _ if path.is_empty() => self.no_path_into(&rl),
                    _ => format!(
                        "the route never enters {rl} from another room (it starts there, or the room has no doorway)"
                    ),
                };
                self.report(
                    Problem::error(
                        codes::ROUTE_PLACE_UNDEFINED,
                        e.span,
                        format!("`{name}` is undefined here: {why}"),
                    )
                    .note(format!(
                        "read off {}",
                        if planned {
                            "the planned route"
                        } else {
                            "the shortest path from the stage start"
                        }
                    )),
                )
            }
        }
    }

    /// Why no path into a room could be read off: the stage start is named, since that (not the
    /// room) is usually what cannot be left.
    fn no_path_into(&self, room: &str) -> String {
        if self.route.is_some() {
            return format!("the planned route is empty, so it never reaches {room}");
        }
        let from = self.here.label(self.q);
        if self.q.band(self.here.target(self.q)).is_empty() {
            format!(
                "this stage starts at {from}, which has no free cell in or near it, so no path into {room} can be read off"
            )
        } else {
            format!("no free path leads from this stage's start ({from}) into {room}")
        }
    }

    fn entering_region(&self, path: &[Cell], room: u32, cells: Vec<Cell>) -> PlaceVal {
        let v = m2rc_stdlib::query::room_visits(self.q, path);
        let other = v
            .iter()
            .zip(v.iter().skip(1))
            .find(|(_, b)| b.room == room)
            .map_or(0, |(a, _)| a.room);
        self.doorway_region(other, room, cells)
    }

    fn leaving_region(&self, path: &[Cell], room: u32, cells: Vec<Cell>) -> PlaceVal {
        let v = m2rc_stdlib::query::room_visits(self.q, path);
        let other = v
            .iter()
            .zip(v.iter().skip(1))
            .find(|(a, _)| a.room == room)
            .map_or(0, |(_, b)| b.room);
        self.doorway_region(room, other, cells)
    }

    fn first_entered(&mut self, e: &Expr, rooms: &[u32]) -> Value {
        let found = if let Some(r) = self.route {
            self.q.first_entered(r, rooms)
        } else {
            // Before planning: the room of the set with the shortest travel from the stage start.
            let here = self.here.clone();
            let f = self.travel_from(&here);
            let mut best: Option<(f64, u32)> = None;
            for &r in rooms {
                let d = f.to(self.q.room_cells(r)).unwrap_or(f64::INFINITY);
                if d.is_finite() && best.is_none_or(|b| d < b.0) {
                    best = Some((d, r));
                }
            }
            best.map(|b| b.1)
        };
        match found {
            Some(r) => {
                let l = PlaceVal::Room(r).label(self.q);
                self.bind(e, "first_entered", l);
                Value::Place(PlaceVal::Room(r))
            }
            None => self.report(Problem::error(
                codes::ROUTE_PLACE_UNDEFINED,
                e.span,
                if rooms.is_empty() {
                    "`first_entered` of an empty set of rooms".to_string()
                } else {
                    "`first_entered` is undefined here: the route enters none of these rooms"
                        .to_string()
                },
            )),
        }
    }
}
