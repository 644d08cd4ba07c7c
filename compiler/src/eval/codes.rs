//! Stable codes of grounding (E05xx) and verification (E06xx) findings.

/// `.only()` on a selection with no candidate.
pub const EMPTY_SELECTION: &str = "E0501";
/// `.only()` on a selection with several candidates.
pub const AMBIGUOUS_SELECTION: &str = "E0502";
/// A ranking (`nearest`, `largest`, `max_by`, ...) of an empty set.
pub const EMPTY_RANKING: &str = "E0503";
/// `kth_nearest(k)` / `kth_farthest(k)` with k outside 1..=count.
pub const ORDINAL_OUT_OF_RANGE: &str = "E0504";
/// A travel distance between places with no traversable path between them.
pub const UNREACHABLE: &str = "E0505";
/// A place without cells where one is needed (a region that came out empty, a room off the grid).
pub const EMPTY_PLACE: &str = "E0506";
/// A route-dependent place the route does not define (the route starts in the room it never
/// enters, or never leaves it).
pub const ROUTE_PLACE_UNDEFINED: &str = "E0507";
/// A place that lies in no room where its room was asked for.
pub const NO_ROOM: &str = "E0508";
/// The map has no usable start position.
pub const NO_START: &str = "E0509";
/// A constraint whose place matches nothing on this map (warning: the constraint is dropped).
pub const EMPTY_CONSTRAINT: &str = "E0510";
/// `during` names a stage that no `go` produced on this map (a `for` over an empty set).
pub const UNKNOWN_STAGE: &str = "E0511";
/// An expression the evaluator cannot evaluate (an internal inconsistency with the checker).
pub const UNSUPPORTED: &str = "E0512";
/// The start cell is not traversable and was moved to the nearest free cell (warning).
pub const START_MOVED: &str = "E0513";

/// The route has no stage.
pub const NO_STAGES: &str = "E0601";
/// A stage target, must-pass place or scope with no cell.
pub const EMPTY_REFERENCE: &str = "E0602";
/// A target or must-pass place with no traversable cell in or next to it, or none reachable.
pub const TARGET_UNREACHABLE: &str = "E0603";
/// The start lies inside a region the first stage must avoid.
pub const START_FORBIDDEN: &str = "E0604";
/// Every approach of a stage target or must-pass place is inside an active avoid region.
pub const TARGET_FORBIDDEN: &str = "E0605";
/// A constraint whose spatial scope does not meet its place (it can never matter) (warning).
pub const SCOPE_MISMATCH: &str = "E0606";
/// `closer(a, b)` with `a` and `b` in different rooms (warning; the reference rejects it).
pub const RELATION_ROOMS: &str = "E0607";
/// A structural inconsistency of the IR (bad version, stage index, duplicate id, cells off the grid).
pub const MALFORMED_IR: &str = "E0608";

/// Every code with a one-line description, for the registry and the docs.
pub const ALL: &[(&str, &str)] = &[
    (
        EMPTY_SELECTION,
        "`.only()` on a selection with no candidate on this map",
    ),
    (
        AMBIGUOUS_SELECTION,
        "`.only()` on a selection with several candidates on this map",
    ),
    (EMPTY_RANKING, "a ranking of an empty set"),
    (
        ORDINAL_OUT_OF_RANGE,
        "k of `kth_nearest` / `kth_farthest` outside 1..=count",
    ),
    (
        UNREACHABLE,
        "travel distance between places with no path between them",
    ),
    (EMPTY_PLACE, "a place with no cells where one is needed"),
    (
        ROUTE_PLACE_UNDEFINED,
        "a route-dependent place the route does not define",
    ),
    (NO_ROOM, "a place in no room where its room was asked for"),
    (NO_START, "the map has no usable start position"),
    (
        EMPTY_CONSTRAINT,
        "a constraint whose place matches nothing (dropped)",
    ),
    (
        UNKNOWN_STAGE,
        "`during` names a stage that no `go` produced on this map",
    ),
    (UNSUPPORTED, "an expression the evaluator cannot evaluate"),
    (
        START_MOVED,
        "the start is not traversable; the route starts at the nearest free cell",
    ),
    (NO_STAGES, "the route has no stage"),
    (
        EMPTY_REFERENCE,
        "a target, must-pass place or scope with no cell",
    ),
    (
        TARGET_UNREACHABLE,
        "a target or must-pass place that cannot be reached",
    ),
    (
        START_FORBIDDEN,
        "the start lies in a region the first stage must avoid",
    ),
    (
        TARGET_FORBIDDEN,
        "every approach of a target lies in an active avoid region",
    ),
    (
        SCOPE_MISMATCH,
        "a spatial scope that does not meet its constraint's place",
    ),
    (
        RELATION_ROOMS,
        "`closer(a, b)` with `a` and `b` in different rooms",
    ),
    (MALFORMED_IR, "a structural inconsistency of the RouteIR"),
];
