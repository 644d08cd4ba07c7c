//! The plan of one episode before it is written: destinations, must-avoids and preferences, each
//! carrying what the annotation, the gold program and the sentence realiser need. Everything
//! downstream (`render`, `realise`) reads only this plan, so the three views of an episode come
//! from one source.

use super::refs::{ObjRef, RoomRef};
use m2rc_stdlib::grid::Cell;

/// What a stage heads to.
#[derive(Clone, Debug)]
pub enum Dest {
    /// An object ("the lamp on the desk").
    Object { id: u32, desc: ObjRef },
    /// A conditional destination: "if the bedroom has a lamp, go to it; otherwise go to the
    /// desk" (`if objects(lamp).in(r).exists() { ... } else { ... }`). `id` is the object the
    /// condition selects on this map.
    Conditional {
        id: u32,
        room: RoomRef,
        cond_cat: String,
        holds: bool,
        then_desc: ObjRef,
        else_desc: ObjRef,
    },
    /// A corner of a room, the one nearest an anchor object ("the corner of the kitchen nearest
    /// the fridge": `room.corners().nearest(to: fridge)`).
    Corner {
        room: u32,
        room_ref: RoomRef,
        anchor: ObjRef,
    },
    /// The small area between two objects ("the area between the counter and the fridge":
    /// `area_between(a, b)`).
    Between { a: ObjRef, b: ObjRef },
    /// The doorway between two rooms ("the doorway between the kitchen and the hall":
    /// `doorways_between(a, b).only()`), where exactly one passage joins them.
    Doorway { a: RoomRef, b: RoomRef },
    /// The second of a pair: "the other sofa", "the other one" (`objects(sofa).except(t1).only()`)
    /// when the house has exactly two and an earlier destination (stage `first`) was one of them.
    Other { id: u32, cat: String, first: usize },
    /// Back to where the route began ("then return to your starting point": `go start`); only
    /// ever the last destination, so its leg is "the way back".
    Return,
}

/// A stage of the episode.
#[derive(Clone, Debug)]
pub struct Stage {
    pub dest: Dest,
    /// The destination object, or the first anchor for regions (for exclusions and wording).
    pub anchor_objects: Vec<u32>,
    pub room: u32,
    /// The must-pass region (free cells, grid indices, ascending).
    pub goal: Vec<usize>,
    /// The must-pass disc's centre and radius (cells), as the annotation records them.
    pub center: [f64; 2],
    pub radius: f64,
    pub avoids: Vec<Avoid>,
    pub softs: Vec<SoftPlan>,
}

/// What a must-avoid names: a room, the area around an object, or the area between two objects.
#[derive(Clone, Debug)]
pub enum AvoidPlace {
    Room(RoomRef),
    Around(ObjRef),
    Between(ObjRef, ObjRef),
}

/// A must-avoid with its region: the free cells of the place the gold program's `avoid` resolves
/// to, which is also the annotated freeform region.
#[derive(Clone, Debug)]
pub struct Avoid {
    pub place: AvoidPlace,
    pub room: Option<u32>,
    pub cells: Vec<usize>,
}

/// Where an object preference is measured: a room the leg must cross, named as people do.
#[derive(Clone, Debug, PartialEq)]
pub enum RoomScope {
    /// The destination's room ("in that room", "once you are in the kitchen").
    Destination,
    /// The room the robot starts in ("while you are still in the starting room").
    Start,
    /// The room just before the destination's room (`room_before_entering(...)`).
    Before,
    /// Another room the leg cannot avoid ("as you pass through the living room").
    Crossed(RoomRef),
}

/// What a near / far preference is about: one object, or every object of a category in the
/// scope room ("all the windows in that room": a quantifier).
#[derive(Clone, Debug)]
pub enum Subject {
    /// One object; `None` when it is the only one of its category in the scope room, so that
    /// the room names it ("in the kitchen, keep away from the fridge":
    /// `objects(fridge).in(<scope room>).only()`), as people leave the scope implied.
    One(u32, Option<ObjRef>),
    All {
        cat: String,
        ids: Vec<u32>,
    },
}

impl Subject {
    pub fn ids(&self) -> Vec<u32> {
        match self {
            Subject::One(id, _) => vec![*id],
            Subject::All { ids, .. } => ids.clone(),
        }
    }
}

/// A preference.
#[derive(Clone, Debug)]
pub enum Pref {
    Near(Subject),
    Far(Subject),
    Relative(Subject, Subject),
    Shape(Box<ShapePlan>),
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShapeKind {
    /// Circle an object with a free ring around it.
    Circle,
    /// Patrol the start room along its walls, ending at the doorway used to leave it.
    Patrol,
    /// Follow the start room's walls once around.
    FollowWall,
    /// Weave past two or three objects of a room in a given order.
    Through,
}

/// A path-shape preference with its canonical reference trajectory and the area R it is
/// measured in.
#[derive(Clone, Debug)]
pub struct ShapePlan {
    pub kind: ShapeKind,
    /// The circled object (circle only), with its description (`None`: the only one of its
    /// category in the scope room).
    pub object: Option<(u32, Option<ObjRef>)>,
    /// The objects a `through` passes by, in order (empty for the other shapes).
    pub via: Vec<Subject>,
    pub clockwise: bool,
    pub reference: Vec<Cell>,
    /// R: free cells, grid indices.
    pub area: Vec<usize>,
    /// `within` of a circle's `area_near`, metres.
    pub within_m: f64,
}

/// A preference placed on a stage, with the room its scope R is (object preferences) and R's
/// cells.
#[derive(Clone, Debug)]
pub struct SoftPlan {
    pub pref: Pref,
    pub room: u32,
    pub scope: RoomScope,
    pub region: Vec<usize>,
    /// A near preference said of passing the subject ("stay close to the lamp as you pass it"):
    /// R is the floor of the scope room within [`super::place::near::PASSING_WITHIN_M`] of it.
    pub passing: bool,
}

impl SoftPlan {
    /// The objects the preference is about (a shape's circled or passed objects included).
    pub fn subject_ids(&self) -> Vec<u32> {
        match &self.pref {
            Pref::Near(s) | Pref::Far(s) => s.ids(),
            Pref::Relative(a, b) => a.ids().into_iter().chain(b.ids()).collect(),
            Pref::Shape(shape) => shape
                .object
                .iter()
                .map(|(id, _)| *id)
                .chain(shape.via.iter().flat_map(Subject::ids))
                .collect(),
        }
    }

    pub fn kind(&self) -> &'static str {
        match &self.pref {
            Pref::Near(..) => "near",
            Pref::Far(..) => "far",
            Pref::Relative(..) => "relative",
            Pref::Shape(..) => "path_shape",
        }
    }
}
