//! The vocabulary the built-in table is written in: parameter type unions, shared parameter lists
//! and the row constructors, kept apart so that the table itself is only rows.

pub(super) use super::signature::{
    Builtin, Constant, DefaultValue, EnumWord, Metric, Param, Receiver, Requirement, Ty,
};
pub(super) use super::types::{Elem, Type};

pub(super) use Requirement::{Default, Optional, Required};

pub(super) const CATEGORY: &[Ty] = &[Ty::Is(Type::Category)];
pub(super) const PLACE: &[Ty] = &[Ty::PLACE];
pub(super) const ROOM: &[Ty] = &[Ty::ROOM];
pub(super) const PLACES: &[Ty] = &[Ty::PLACE, Ty::SET_PLACE];
pub(super) const OBJECTS: &[Ty] = &[Ty::OBJECT, Ty::SET_OBJECT];
pub(super) const DISTANCE: &[Ty] = &[Ty::Is(Type::Distance)];
pub(super) const DIRECTION: &[Ty] = &[Ty::Is(Type::Direction)];
pub(super) const METRIC: &[Ty] = &[Ty::Is(Type::Metric)];
pub(super) const INT: &[Ty] = &[Ty::Is(Type::Int)];
pub(super) const BESIDE: &[Ty] = &[
    Ty::OBJECT,
    Ty::Is(Type::Region),
    Ty::SET_OBJECT,
    Ty::Is(Type::Set(Elem::Region)),
];

pub(super) const SET_T: &[Ty] = &[Ty::SetT];
pub(super) const SET_OBJECT: &[Ty] = &[Ty::SET_OBJECT];
pub(super) const SET_ROOM: &[Ty] = &[Ty::SET_ROOM];
pub(super) const SINGLE_OBJECT: &[Ty] = &[Ty::OBJECT];
pub(super) const SINGLE_ROOM: &[Ty] = &[Ty::ROOM];
pub(super) const SINGLE_PLACE: &[Ty] = &[Ty::PLACE];
pub(super) const ROOM_OR_ROOMS: &[Ty] = &[Ty::ROOM, Ty::SET_ROOM];
/// Where `in` looks: rooms, or regions (a corner, an area, a doorway), or sets of either.
pub(super) const AREAS: &[Ty] = &[
    Ty::ROOM,
    Ty::SET_ROOM,
    Ty::Is(Type::Region),
    Ty::Is(Type::Set(Elem::Region)),
];

pub(super) const HERE: Requirement = Default(DefaultValue::Here);
pub(super) const STRAIGHT: Requirement = Default(DefaultValue::Metric(Metric::Straight));

pub(super) const fn p(name: &'static str, ty: &'static [Ty], req: Requirement) -> Param {
    Param { name, ty, req }
}

/// `to:` may be a set: the distance to its nearest member ("nearest to any of the dressers").
pub(super) const RANK_PARAMS: &[Param] = &[p("to", PLACES, HERE), p("by", METRIC, STRAIGHT)];
pub(super) const KTH_PARAMS: &[Param] = &[
    p("k", INT, Required),
    p("to", PLACES, HERE),
    p("by", METRIC, STRAIGHT),
];
/// `on`, `inside`, `under`, `holding`: physical relations between objects, so a room or a region
/// is refused at check time rather than silently never holding.
pub(super) const X_OBJECTS: &[Param] = &[p("x", OBJECTS, Required)];
/// `next_to` reads a region's cells too ("the plunger next to the corner"); a room is refused,
/// since every object in it would be beside it.
pub(super) const X_BESIDE: &[Param] = &[p("x", BESIDE, Required)];
pub(super) const NEAR_PARAMS: &[Param] = &[
    p("x", PLACES, Required),
    p("within", DISTANCE, Default(DefaultValue::Distance(1.5))),
];
pub(super) const BETWEEN_PARAMS: &[Param] = &[p("a", PLACES, Required), p("b", PLACES, Required)];
pub(super) const PRED: &[Param] = &[p("pred", &[Ty::PredT], Required)];
pub(super) const KEY: &[Param] = &[p("key", &[Ty::KeyT], Required)];
pub(super) const NONE: &[Param] = &[];

pub(super) const fn free(
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

pub(super) const fn method(
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

pub(super) const BOOL: Ty = Ty::Is(Type::Bool);
pub(super) const PREF: Ty = Ty::Is(Type::Preference);
pub(super) const REGION: Ty = Ty::Is(Type::Region);
pub(super) const SET_REGION: Ty = Ty::Is(Type::Set(Elem::Region));
