//! Catalog ids as places: the same places, labels and cells the compiler's grounding gives the
//! same objects and rooms (`m2rc_compiler::eval`), so a route grounded from ids and one grounded
//! from a program plan over identical RouteIR.

use super::catalog::{START_ID, object_id, room_id};
use m2rc_compiler::eval::PlaceVal;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::MapQuery;

/// What a catalog id names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Ref {
    Start,
    Room(u32),
    Object(u32),
}

impl Ref {
    /// Reads `task_start`, `room_<id>` or `object_<id>`, whether or not the map has it.
    pub fn parse(id: &str) -> Option<Ref> {
        if id == START_ID {
            return Some(Ref::Start);
        }
        let number = |rest: &str| -> Option<u32> {
            (!rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit()))
                .then(|| rest.parse().ok())
                .flatten()
        };
        if let Some(rest) = id.strip_prefix("room_") {
            return number(rest).map(Ref::Room);
        }
        id.strip_prefix("object_").and_then(number).map(Ref::Object)
    }

    pub fn id(self) -> String {
        match self {
            Ref::Start => START_ID.to_string(),
            Ref::Room(r) => room_id(r),
            Ref::Object(o) => object_id(o),
        }
    }

    /// Whether the map has it (room 0 is "no room" in the room layer, never a room).
    pub fn exists(self, q: &MapQuery) -> bool {
        match self {
            Ref::Start => true,
            Ref::Room(r) => r != 0 && q.map().room(r).is_some(),
            Ref::Object(o) => q.map().object(o).is_some(),
        }
    }

    /// `room`, `object` or `start`, for messages.
    pub fn kind_word(self) -> &'static str {
        match self {
            Ref::Start => "the start",
            Ref::Room(_) => "a room",
            Ref::Object(_) => "an object",
        }
    }
}

/// The start as the compiler grounds it: a one-cell region.
pub fn start_place(start: Cell) -> PlaceVal {
    PlaceVal::region(vec![start], "start", vec![], None, "start".into())
}

/// The value of an id (which must exist).
pub fn value(r: Ref, start: Cell) -> PlaceVal {
    match r {
        Ref::Start => start_place(start),
        Ref::Room(id) => PlaceVal::Room(id),
        Ref::Object(id) => PlaceVal::Object(id),
    }
}

/// `area_near(x, within)` as the compiler builds it; `None` when it covers no cell.
pub fn area_near(q: &MapQuery, x: &PlaceVal, within_m: f64) -> Option<PlaceVal> {
    let cells = q.area_near(x.target(q), within_m);
    if cells.is_empty() {
        return None;
    }
    let l = x.label(q);
    Some(PlaceVal::region(
        cells,
        "area_near",
        vec![l.clone()],
        Some(within_m),
        format!("area within {within_m} m of {l}"),
    ))
}

/// The RouteIR's places, written as the compiler writes them.
pub use m2rc_compiler::eval::{ir_place, union_place};
