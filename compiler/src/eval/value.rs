//! Runtime values of grounding.

use crate::ir::{Construction, Direction};
use m2rc_grammar::ast::Expr;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target};
use std::rc::Rc;

/// A region built during grounding: its cells and how it was made.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    pub cells: Vec<Cell>,
    pub construction: Construction,
    pub label: String,
}

/// One place: a map object or room (by id), or a constructed region.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaceVal {
    Object(u32),
    Room(u32),
    Region(Rc<Region>),
}

impl PlaceVal {
    /// A constructed region: its cells, how it was built (`kind` from the places `from`, within
    /// `radius_m`), and its label.
    pub fn region(
        cells: Vec<Cell>,
        kind: &str,
        from: Vec<String>,
        radius_m: Option<f64>,
        label: String,
    ) -> PlaceVal {
        PlaceVal::Region(Rc::new(Region {
            cells,
            construction: Construction {
                kind: kind.into(),
                from,
                radius_m,
            },
            label,
        }))
    }

    /// Identity for set operations: objects and rooms by id, regions by their cells.
    pub fn same(&self, other: &PlaceVal) -> bool {
        match (self, other) {
            (PlaceVal::Object(a), PlaceVal::Object(b)) | (PlaceVal::Room(a), PlaceVal::Room(b)) => {
                a == b
            }
            (PlaceVal::Region(a), PlaceVal::Region(b)) => a.cells == b.cells,
            _ => false,
        }
    }

    pub fn target<'a>(&'a self, q: &'a MapQuery) -> Target<'a> {
        match self {
            PlaceVal::Object(id) => match q.map().object(*id) {
                Some(o) => Target::Object(o),
                None => Target::Cells(&[]),
            },
            PlaceVal::Room(id) => Target::Room(*id),
            PlaceVal::Region(r) => Target::Cells(&r.cells),
        }
    }

    /// `bed #12 (bedroom_2)`, `bedroom_2`, or the region's label: rooms by the map's own room
    /// names, as `map info` and the pictures show them.
    pub fn label(&self, q: &MapQuery) -> String {
        match self {
            PlaceVal::Object(id) => match q.map().object(*id) {
                Some(o) => match o.room.and_then(|r| q.map().room(r)) {
                    Some(r) => format!("{} #{} ({})", o.category, o.id, room_name(r)),
                    None => format!("{} #{}", o.category, o.id),
                },
                None => format!("object #{id}"),
            },
            PlaceVal::Room(id) => match q.map().room(*id) {
                Some(r) => room_name(r),
                None => format!("room {id}"),
            },
            PlaceVal::Region(r) => r.label.clone(),
        }
    }

    /// Where a place sits, in cell units: an object's centre, else the mean of its cells.
    pub fn center(&self, q: &MapQuery) -> Option<[f64; 2]> {
        match self {
            PlaceVal::Object(id) => q.map().object(*id).map(|o| o.center),
            _ => MapQuery::centroid(q.cells(self.target(q))),
        }
    }

    pub fn room_of(&self, q: &MapQuery) -> Option<u32> {
        q.room_of(self.target(q))
    }
}

/// A soft preference, before it is turned into a RouteIR constraint.
#[derive(Clone, Debug, PartialEq)]
pub enum Pref {
    Near(Vec<PlaceVal>),
    /// `near_each`: one near term per place, expanded when the constraint is placed.
    NearEach(Vec<PlaceVal>),
    Far(Vec<PlaceVal>),
    Closer(Vec<PlaceVal>, Vec<PlaceVal>),
    /// A direction of `None` was left out by the writer: grounding takes the shorter way.
    Circle(PlaceVal, Option<Direction>),
    FollowWall(WallFollow),
    Patrol(WallFollow),
    /// Places to pass by in this order.
    Through(Vec<PlaceVal>),
    Clearance(f64),
}

/// A wall-following shape around a room.
#[derive(Clone, Debug, PartialEq)]
pub struct WallFollow {
    pub room: u32,
    pub direction: Option<Direction>,
    /// Only as far as this place (a doorway, say) rather than once round.
    pub until: Option<PlaceVal>,
    /// Go round on the side that passes this place.
    pub passing: Option<PlaceVal>,
    /// Go round on the side that keeps farther from this place.
    pub avoiding: Option<PlaceVal>,
}

/// A lambda: its parameter and its body (shared, so applying it never copies the tree).
#[derive(Clone, Debug)]
pub struct Lambda {
    pub param: String,
    pub body: Rc<Expr>,
}

#[derive(Clone, Debug)]
pub enum Value {
    Place(PlaceVal),
    Set(Vec<PlaceVal>),
    Int(i64),
    Number(f64),
    /// Metres.
    Distance(f64),
    Bool(bool),
    /// One category, or a union.
    Category(Vec<String>),
    Direction(Direction),
    Travel(bool),
    Pref(Pref),
    Lambda(Rc<Lambda>),
    Str(String),
    /// The value of an expression that failed; its diagnostic is already recorded, and anything
    /// computed from it is `Unknown` too, so one mistake gives one diagnostic.
    Unknown,
}

impl Value {
    /// The places of a single place or a set.
    pub fn places(&self) -> Option<Vec<PlaceVal>> {
        match self {
            Value::Place(p) => Some(vec![p.clone()]),
            Value::Set(s) => Some(s.clone()),
            _ => None,
        }
    }

    pub fn number(&self) -> Option<f64> {
        match self {
            Value::Int(i) => Some(*i as f64),
            Value::Number(x) | Value::Distance(x) => Some(*x),
            _ => None,
        }
    }
}

/// A room as users see it everywhere (`map info`, pictures, summaries): the map's name for it
/// (`bathroom_2`), or `<category>_<id>` for a map without room names.
pub fn room_name(r: &m2rc_stdlib::map::Room) -> String {
    if r.name.is_empty() {
        format!("{}_{}", r.category, r.id)
    } else {
        r.name.clone()
    }
}
