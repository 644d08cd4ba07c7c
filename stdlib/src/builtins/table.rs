//! The table of `.m2r` built-ins: the single source for the type checker, the language reference,
//! hover text and the LLM prompt. Add a built-in here and every consumer sees it; never list
//! built-ins anywhere else by hand.
//!
//! Several rows may share a name when their receivers differ (`Set<Object>.near(x)` filters,
//! `Object.near(x)` is a predicate, the free `near(x)` is a preference); the checker picks the row
//! whose receiver accepts the actual receiver type.

use super::signature::{
    Builtin, Constant, DefaultValue, EnumWord, Metric, Param, Receiver, Requirement, Ty,
};
use super::types::{Elem, Type};

use Requirement::{Default, Optional, Required};

const CATEGORY: &[Ty] = &[Ty::Is(Type::Category)];
const PLACE: &[Ty] = &[Ty::PLACE];
const ROOM: &[Ty] = &[Ty::ROOM];
const PLACES: &[Ty] = &[Ty::PLACE, Ty::SET_PLACE];
const OBJECTS: &[Ty] = &[Ty::OBJECT, Ty::SET_OBJECT];
const DISTANCE: &[Ty] = &[Ty::Is(Type::Distance)];
const DIRECTION: &[Ty] = &[Ty::Is(Type::Direction)];
const METRIC: &[Ty] = &[Ty::Is(Type::Metric)];
const INT: &[Ty] = &[Ty::Is(Type::Int)];
const BESIDE: &[Ty] = &[
    Ty::OBJECT,
    Ty::Is(Type::Region),
    Ty::SET_OBJECT,
    Ty::Is(Type::Set(Elem::Region)),
];

const SET_T: &[Ty] = &[Ty::SetT];
const SET_OBJECT: &[Ty] = &[Ty::SET_OBJECT];
const SET_ROOM: &[Ty] = &[Ty::SET_ROOM];
const SINGLE_OBJECT: &[Ty] = &[Ty::OBJECT];
const SINGLE_ROOM: &[Ty] = &[Ty::ROOM];
const SINGLE_PLACE: &[Ty] = &[Ty::PLACE];
const ROOM_OR_ROOMS: &[Ty] = &[Ty::ROOM, Ty::SET_ROOM];

const HERE: Requirement = Default(DefaultValue::Here);
const STRAIGHT: Requirement = Default(DefaultValue::Metric(Metric::Straight));

const fn p(name: &'static str, ty: &'static [Ty], req: Requirement) -> Param {
    Param { name, ty, req }
}

const RANK_PARAMS: &[Param] = &[p("to", PLACE, HERE), p("by", METRIC, STRAIGHT)];
const KTH_PARAMS: &[Param] = &[
    p("k", INT, Required),
    p("to", PLACE, HERE),
    p("by", METRIC, STRAIGHT),
];
/// `on`, `inside`, `under`, `holding`: physical relations between objects, so a room or a region
/// is refused at check time rather than silently never holding.
const X_OBJECTS: &[Param] = &[p("x", OBJECTS, Required)];
/// `next_to` reads a region's cells too ("the plunger next to the corner"); a room is refused,
/// since every object in it would be beside it.
const X_BESIDE: &[Param] = &[p("x", BESIDE, Required)];
const NEAR_PARAMS: &[Param] = &[
    p("x", PLACES, Required),
    p("within", DISTANCE, Default(DefaultValue::Distance(1.5))),
];
const BETWEEN_PARAMS: &[Param] = &[p("a", PLACES, Required), p("b", PLACES, Required)];
const PRED: &[Param] = &[p("pred", &[Ty::PredT], Required)];
const KEY: &[Param] = &[p("key", &[Ty::KeyT], Required)];
const NONE: &[Param] = &[];

const fn free(
    name: &'static str,
    params: &'static [Param],
    ret: Ty,
    doc: &'static str,
    example: &'static str,
) -> Builtin {
    Builtin {
        name,
        receiver: Receiver::Free,
        params,
        ret,
        doc,
        example,
    }
}

const fn method(
    recv: &'static [Ty],
    name: &'static str,
    params: &'static [Param],
    ret: Ty,
    doc: &'static str,
    example: &'static str,
) -> Builtin {
    Builtin {
        name,
        receiver: Receiver::Method(recv),
        params,
        ret,
        doc,
        example,
    }
}

const BOOL: Ty = Ty::Is(Type::Bool);
const PREF: Ty = Ty::Is(Type::Preference);
const REGION: Ty = Ty::Is(Type::Region);
const SET_REGION: Ty = Ty::Is(Type::Set(Elem::Region));

/// Every built-in function and method, grouped as the language reference shows them.
pub static BUILTINS: &[Builtin] = &[
    // --- Queries -------------------------------------------------------------------------------
    free(
        "objects",
        &[p("category", CATEGORY, Optional)],
        Ty::SET_OBJECT,
        "All objects of a category (or of a union `a | b`); every object when left out.",
        "objects(chair | sofa)",
    ),
    free(
        "rooms",
        &[p("category", CATEGORY, Optional)],
        Ty::SET_ROOM,
        "All rooms of a room category; every room when left out.",
        "rooms(bathroom)",
    ),
    // --- Filters on sets -----------------------------------------------------------------------
    method(
        SET_T,
        "in",
        &[p("room", ROOM_OR_ROOMS, Required)],
        Ty::SetT,
        "Keeps the elements that lie in the room (or in any of the rooms).",
        "objects(sink).in(kitchen_room)",
    ),
    method(
        SET_T,
        "near",
        NEAR_PARAMS,
        Ty::SetT,
        "Keeps the elements within `within` of `x` (of any element of `x`).",
        "objects(chair).near(objects(cup), within: 1m)",
    ),
    method(
        SET_T,
        "except",
        &[p("x", &[Ty::T, Ty::SetT], Required)],
        Ty::SetT,
        "Removes the given element(s).",
        "rooms(bedroom).except(start.room())",
    ),
    method(
        SET_T,
        "where",
        PRED,
        Ty::SetT,
        "Keeps the elements for which the predicate is true.",
        "rooms().where(r => objects(stool).in(r).count() == 2)",
    ),
    method(
        SET_T,
        "sorted_by",
        KEY,
        Ty::SetT,
        "The same elements ordered by ascending key.",
        "rooms(bedroom).sorted_by(r => r.area())",
    ),
    method(
        SET_T,
        "sorted_by_descending",
        KEY,
        Ty::SetT,
        "The same elements ordered by descending key (largest first).",
        "objects(painting).sorted_by_descending(p => p.footprint_area())",
    ),
    method(
        SET_T,
        "nearest_first",
        RANK_PARAMS,
        Ty::SetT,
        "The same elements ordered from nearest to farthest from `to` (a `for` visits them in this order).",
        "objects(chair).nearest_first(to: objects(bed).only())",
    ),
    method(
        SET_T,
        "farthest_first",
        RANK_PARAMS,
        Ty::SetT,
        "The same elements ordered from farthest to nearest from `to`, without negating a distance.",
        "objects(lamp).farthest_first(by: travel)",
    ),
    method(
        SET_ROOM,
        "tour",
        &[p("k", INT, Required), p("from", PLACE, HERE)],
        Ty::SET_ROOM,
        "k distinct rooms of the set, in the order of the shortest walk from `from` that enters each in turn (the compiler chooses which): \"through two bedrooms\" is `for r in rooms(bedroom).tour(2) { go r }`.",
        "rooms(bedroom).tour(2)",
    ),
    method(
        SET_T,
        "reversed",
        NONE,
        Ty::SetT,
        "The same elements in the opposite order.",
        "rooms(bedroom).sorted_by(r => r.area()).reversed()",
    ),
    method(
        SET_OBJECT,
        "on",
        X_OBJECTS,
        Ty::SET_OBJECT,
        "Keeps the objects standing on `x` (on any of `x`).",
        "objects(bowl).on(table)",
    ),
    method(
        SET_OBJECT,
        "inside",
        X_OBJECTS,
        Ty::SET_OBJECT,
        "Keeps the objects inside `x` (a fridge, a cabinet, ...).",
        "objects(egg).inside(objects(fridge))",
    ),
    method(
        SET_OBJECT,
        "under",
        X_OBJECTS,
        Ty::SET_OBJECT,
        "Keeps the objects underneath `x`.",
        "objects(basket_ball).under(objects(dresser))",
    ),
    method(
        SET_OBJECT,
        "next_to",
        X_BESIDE,
        Ty::SET_OBJECT,
        "Keeps the objects directly beside `x` (touching or almost).",
        "objects(window).next_to(objects(fridge))",
    ),
    method(
        SET_OBJECT,
        "between",
        BETWEEN_PARAMS,
        Ty::SET_OBJECT,
        "Keeps the objects lying between `a` and `b`.",
        "objects(plunger).between(sink, toilet)",
    ),
    method(
        SET_OBJECT,
        "holding",
        X_OBJECTS,
        Ty::SET_OBJECT,
        "Keeps the objects that have `x` (any of `x`) on or inside them.",
        "objects(desk).holding(objects(laptop))",
    ),
    method(
        SET_ROOM,
        "containing",
        &[p("x", OBJECTS, Required)],
        Ty::SET_ROOM,
        "Keeps the rooms that contain `x` (any of `x`).",
        "rooms(bedroom).containing(objects(dog_bed))",
    ),
    method(
        SET_ROOM,
        "adjacent_to",
        &[p("room", ROOM_OR_ROOMS, Required)],
        Ty::SET_ROOM,
        "Keeps the rooms that share a doorway with the room (with any of the rooms).",
        "rooms(bedroom).adjacent_to(start.room())",
    ),
    // --- Predicates ----------------------------------------------------------------------------
    method(
        SINGLE_OBJECT,
        "in",
        &[p("room", ROOM_OR_ROOMS, Required)],
        BOOL,
        "Whether the object lies in the room (in any of the rooms).",
        "o => o.in(kitchen)",
    ),
    method(
        SINGLE_OBJECT,
        "near",
        NEAR_PARAMS,
        BOOL,
        "Whether the object is within `within` of `x`.",
        "o => o.near(objects(cup))",
    ),
    method(
        SINGLE_OBJECT,
        "on",
        X_OBJECTS,
        BOOL,
        "Whether the object stands on `x`.",
        "o => o.on(objects(dresser))",
    ),
    method(
        SINGLE_OBJECT,
        "inside",
        X_OBJECTS,
        BOOL,
        "Whether the object is inside `x`.",
        "o => o.inside(objects(fridge))",
    ),
    method(
        SINGLE_OBJECT,
        "under",
        X_OBJECTS,
        BOOL,
        "Whether the object is underneath `x`.",
        "b => not b.under(objects(dining_table))",
    ),
    method(
        SINGLE_OBJECT,
        "next_to",
        X_BESIDE,
        BOOL,
        "Whether the object is directly beside `x`.",
        "w => w.next_to(objects(fridge))",
    ),
    method(
        SINGLE_OBJECT,
        "between",
        BETWEEN_PARAMS,
        BOOL,
        "Whether the object lies between `a` and `b`.",
        "w => w.between(objects(bed), objects(tv_stand))",
    ),
    method(
        SINGLE_OBJECT,
        "holding",
        X_OBJECTS,
        BOOL,
        "Whether `x` (any of `x`) is on or inside the object.",
        "t => t.holding(objects(teddy_bear))",
    ),
    method(
        SINGLE_ROOM,
        "contains",
        &[p("x", OBJECTS, Required)],
        BOOL,
        "Whether the room contains `x` (any of `x`).",
        "r => r.contains(objects(desk))",
    ),
    method(
        SINGLE_ROOM,
        "adjacent_to",
        &[p("room", ROOM_OR_ROOMS, Required)],
        BOOL,
        "Whether the room shares a doorway with the room (with any of the rooms).",
        "r => r.adjacent_to(start.room())",
    ),
    method(
        SINGLE_ROOM,
        "only_reachable_through",
        &[p("rooms", ROOM_OR_ROOMS, Required)],
        BOOL,
        "Whether every path from the start into the room passes through one of the rooms.",
        "r => r.only_reachable_through(rooms(living_room))",
    ),
    method(
        SET_T,
        "exists",
        NONE,
        BOOL,
        "Whether the set has at least one element.",
        "objects(cup).near(c).exists()",
    ),
    method(
        SET_T,
        "is_empty",
        NONE,
        BOOL,
        "Whether the set has no element.",
        "objects().near(b).except(b).is_empty()",
    ),
    // --- Counts and measures -------------------------------------------------------------------
    method(
        SET_T,
        "count",
        NONE,
        Ty::Is(Type::Int),
        "The number of elements.",
        "objects(box).in(r).count()",
    ),
    method(
        SINGLE_PLACE,
        "distance",
        &[p("to", PLACE, Required), p("by", METRIC, STRAIGHT)],
        Ty::Is(Type::Distance),
        "The distance between two places, straight-line or travel.",
        "c => c.distance(doorway_entering(bath))",
    ),
    method(
        SINGLE_ROOM,
        "area",
        NONE,
        Ty::Is(Type::Number),
        "The floor area in square metres.",
        "r => r.area()",
    ),
    method(
        SINGLE_OBJECT,
        "footprint_area",
        NONE,
        Ty::Is(Type::Number),
        "The area the object covers on the floor, in square metres.",
        "objects(painting).max_by(p => p.footprint_area())",
    ),
    method(
        SINGLE_OBJECT,
        "length",
        NONE,
        Ty::Is(Type::Distance),
        "The longer side of the object's footprint.",
        "objects(sofa).max_by(s => s.length())",
    ),
    method(
        SINGLE_OBJECT,
        "width",
        NONE,
        Ty::Is(Type::Distance),
        "The shorter side of the object's footprint.",
        "objects(shelving_unit).min_by(s => s.width())",
    ),
    method(
        SINGLE_OBJECT,
        "squareness",
        NONE,
        Ty::Is(Type::Number),
        "Width over length of the footprint: 1 for a square, near 0 for a long thin object.",
        "objects(dining_table).max_by(t => t.squareness())",
    ),
    method(
        SINGLE_PLACE,
        "room",
        NONE,
        Ty::ROOM,
        "The room the place lies in.",
        "start.room()",
    ),
    // --- Rankings: Set<T> -> T -----------------------------------------------------------------
    method(
        SET_T,
        "nearest",
        RANK_PARAMS,
        Ty::T,
        "The element nearest to `to`.",
        "objects(desk).nearest()",
    ),
    method(
        SET_T,
        "farthest",
        RANK_PARAMS,
        Ty::T,
        "The element farthest from `to`.",
        "objects(garbage_can).farthest(by: travel)",
    ),
    method(
        SET_T,
        "kth_nearest",
        KTH_PARAMS,
        Ty::T,
        "The k-th nearest element to `to` (k = 1 is the nearest).",
        "objects(box).kth_nearest(2, to: dresser)",
    ),
    method(
        SET_T,
        "kth_farthest",
        KTH_PARAMS,
        Ty::T,
        "The k-th farthest element from `to` (k = 1 is the farthest).",
        "objects(chair).kth_farthest(2)",
    ),
    method(
        SET_T,
        "kth",
        &[p("k", INT, Required)],
        Ty::T,
        "The k-th element in the set's order (k = 1 is the first): the k-th of a sorted set.",
        "objects(chair).sorted_by(c => c.footprint_area()).kth(2)",
    ),
    method(
        SET_ROOM,
        "largest",
        NONE,
        Ty::ROOM,
        "The room with the largest floor area.",
        "rooms(bathroom).largest()",
    ),
    method(
        SET_ROOM,
        "smallest",
        NONE,
        Ty::ROOM,
        "The room with the smallest floor area.",
        "rooms(bathroom).smallest()",
    ),
    method(
        SET_OBJECT,
        "largest",
        NONE,
        Ty::OBJECT,
        "The object with the largest footprint area.",
        "objects(painting).largest()",
    ),
    method(
        SET_OBJECT,
        "smallest",
        NONE,
        Ty::OBJECT,
        "The object with the smallest footprint area (the smaller of two).",
        "objects(dining_table).smallest()",
    ),
    method(
        SET_T,
        "max_by",
        KEY,
        Ty::T,
        "The element with the largest key.",
        "rooms().max_by(r => objects(tennis_racket | pillow).in(r).count())",
    ),
    method(
        SET_T,
        "min_by",
        KEY,
        Ty::T,
        "The element with the smallest key.",
        "objects(chair).min_by(c => c.distance(center(objects(potato))))",
    ),
    method(
        SET_T,
        "only",
        NONE,
        Ty::T,
        "The single element; grounding fails, listing the candidates, unless exactly one remains.",
        "objects(bed).in(r).only()",
    ),
    // --- Places ---------------------------------------------------------------------------------
    method(
        ROOM_OR_ROOMS,
        "corners",
        NONE,
        SET_REGION,
        "The corners of the room (of all the rooms).",
        "bath.corners()",
    ),
    method(
        ROOM_OR_ROOMS,
        "doorways",
        NONE,
        SET_REGION,
        "The doorway passages of the room (of all the rooms).",
        "kitchen_room.doorways()",
    ),
    method(
        SINGLE_ROOM,
        "adjacent",
        NONE,
        Ty::SET_ROOM,
        "The rooms sharing a doorway with this room.",
        "start.room().adjacent()",
    ),
    method(
        ROOM_OR_ROOMS,
        "open_area",
        NONE,
        Ty::SET_ROOM,
        "The open-plan area of the room: the room and every room joined to it by open boundaries (no wall, no door), directly or through others; only the room itself when it has none. Each room keeps its own name.",
        "start.room().open_area()",
    ),
    free(
        "doorways_between",
        &[p("a", ROOM, Required), p("b", ROOM, Required)],
        SET_REGION,
        "The doorway passages connecting two rooms.",
        "doorways_between(kitchen_room, hall)",
    ),
    free(
        "area_between",
        BETWEEN_PARAMS,
        REGION,
        "The small area between two places (between the nearest pair when given sets).",
        "area_between(objects(counter_top).only(), objects(fridge).only())",
    ),
    free(
        "area_near",
        &[
            p("x", PLACE, Required),
            p("within", DISTANCE, Default(DefaultValue::Distance(0.5))),
        ],
        REGION,
        "The area within `within` of a place.",
        "area_near(bed)",
    ),
    free(
        "center",
        &[p("of", SET_PLACE_OR_PLACE, Required)],
        REGION,
        "The centre point of a place or of a set of places.",
        "center(objects(potato))",
    ),
    free(
        "area_enclosed",
        &[p("places", SET_PLACE_OR_PLACE, Required)],
        REGION,
        "The area enclosed by three or more places: the convex hull of their footprints, outside the footprints.",
        "area_enclosed([sofa, tv_stand, coffee_table])",
    ),
    free(
        "house_corners",
        NONE,
        SET_REGION,
        "The corners of the whole house outline, each as the floor within the corner radius.",
        "house_corners().farthest()",
    ),
    free(
        "house_center",
        NONE,
        REGION,
        "The free floor nearest the centre of the whole house.",
        "house_center()",
    ),
    // --- Route-dependent places -----------------------------------------------------------------
    free(
        "room_before_entering",
        &[p("room", ROOM, Required)],
        Ty::ROOM,
        "The room the route passes through immediately before entering `room`.",
        "room_before_entering(bath)",
    ),
    free(
        "doorway_leaving",
        &[p("room", ROOM, Required)],
        REGION,
        "The doorway the route uses to leave `room`.",
        "doorway_leaving(start.room())",
    ),
    free(
        "doorway_entering",
        &[p("room", ROOM, Required)],
        REGION,
        "The doorway the route uses to enter `room`.",
        "doorway_entering(bath)",
    ),
    free(
        "first_entered",
        &[p("rooms", SET_ROOM, Required)],
        Ty::ROOM,
        "The first of the rooms that the route enters.",
        "first_entered(rooms(bedroom))",
    ),
    free(
        "kth_entered",
        &[p("rooms", SET_ROOM, Required), p("k", INT, Required)],
        Ty::ROOM,
        "The k-th distinct room of the set that the route enters (k = 1 is `first_entered`).",
        "kth_entered(rooms(bedroom), 2)",
    ),
    free(
        "visited",
        NONE,
        Ty::SET_ROOM,
        "The rooms the route has been in before the current stage starts, the start room included.",
        "rooms(bathroom).except(visited())",
    ),
    free(
        "left_behind",
        NONE,
        Ty::SET_ROOM,
        "The rooms the route has been in and left before the current stage starts (`visited()` without the room the stage starts in): `avoid left_behind()` in a stage is \"without going back through a room you have already crossed\".",
        "avoid left_behind()",
    ),
    // --- Preferences ----------------------------------------------------------------------------
    free(
        "near",
        &[p("x", PLACES, Required)],
        PREF,
        "Stay as close as possible to `x`.",
        "prefer near(objects(sink).in(bath))",
    ),
    free(
        "far",
        &[p("x", PLACES, Required)],
        PREF,
        "Stay as far as possible from `x`.",
        "prefer far(objects(sofa))",
    ),
    free(
        "closer",
        &[p("a", PLACES, Required), p("b", PLACES, Required)],
        PREF,
        "Stay closer to `a` than to `b`.",
        "prefer closer(table, desk)",
    ),
    free(
        "circle",
        &[p("x", PLACE, Required), p("direction", DIRECTION, Optional)],
        PREF,
        "Circle once around the place; without a direction either way is taken (the binding says which).",
        "prefer circle(table, counterclockwise)",
    ),
    free(
        "follow_wall",
        &[
            p("room", ROOM, Required),
            p("direction", DIRECTION, Optional),
            p("until", PLACE, Optional),
            p("passing", PLACE, Optional),
        ],
        PREF,
        "Walk along the room's walls once round, or only as far as `until`; without a direction, on the side passing `passing`, else the shorter way (the binding says which).",
        "prefer follow_wall(start.room(), until: doorway_leaving(start.room()), passing: sofa)",
    ),
    free(
        "patrol",
        &[
            p("room", ROOM, Required),
            p("direction", DIRECTION, Optional),
        ],
        PREF,
        "A full loop along the room's walls that then ends at the doorway used to leave it; without a direction, the shorter way.",
        "prefer patrol(start.room(), counterclockwise)",
    ),
    free(
        "through",
        &[
            p("a", PLACE, Required),
            p("b", PLACE, Required),
            p("c", PLACE, Optional),
            p("d", PLACE, Optional),
        ],
        PREF,
        "Pass close by `a`, then `b` (then `c`, then `d`) in this order: within 0.5 m of an object or region, inside a room.",
        "prefer through(sofa, lamp, desk) within living",
    ),
    free(
        "clearance",
        &[p("min", DISTANCE, Default(DefaultValue::Distance(0.5)))],
        PREF,
        "Keep at least `min` away from obstacles where possible.",
        "prefer clearance(0.5m)",
    ),
];

const SET_PLACE_OR_PLACE: &[Ty] = &[Ty::PLACE, Ty::SET_PLACE];

/// Named values usable without a call.
pub static CONSTANTS: &[Constant] = &[
    Constant {
        name: "start",
        ty: Type::Region,
        doc: "The route's start position.",
    },
    Constant {
        name: "here",
        ty: Type::Region,
        doc: "Where the current stage starts (`start` before the first stage).",
    },
];

/// Enumeration words, meaningful only in a slot of their type.
pub static ENUM_WORDS: &[EnumWord] = &[
    EnumWord {
        name: "clockwise",
        ty: Type::Direction,
        doc: "Turning right around the centre.",
    },
    EnumWord {
        name: "counterclockwise",
        ty: Type::Direction,
        doc: "Turning left around the centre.",
    },
    EnumWord {
        name: "straight",
        ty: Type::Metric,
        doc: "Straight-line (Euclidean) distance.",
    },
    EnumWord {
        name: "travel",
        ty: Type::Metric,
        doc: "Walking distance over free space.",
    },
];
