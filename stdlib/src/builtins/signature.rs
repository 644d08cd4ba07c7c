//! How a built-in's signature is written in the static table.
//!
//! Signatures are patterns over [`Type`] with one type variable `T`, the element type of the
//! receiver (`Set<T>.nearest() -> T`), so one row serves objects, rooms and regions alike.

use super::types::{Elem, Scalar, Type};
use std::fmt;

/// One alternative of a receiver, parameter or return type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// This type or any subtype.
    Is(Type),
    /// The receiver's element type.
    T,
    /// `Set<T>`.
    SetT,
    /// `T => Bool`, a predicate over the receiver's elements.
    PredT,
    /// `T => Int | Number | Distance`, a ranking key over the receiver's elements.
    KeyT,
}

impl Ty {
    pub const OBJECT: Ty = Ty::Is(Type::Object);
    pub const ROOM: Ty = Ty::Is(Type::Room);
    pub const PLACE: Ty = Ty::Is(Type::Place);
    pub const SET_OBJECT: Ty = Ty::Is(Type::Set(Elem::Object));
    pub const SET_ROOM: Ty = Ty::Is(Type::Set(Elem::Room));
    pub const SET_PLACE: Ty = Ty::Is(Type::Set(Elem::Place));

    /// Substitutes `T`; `None` for lambda patterns, which have no single type.
    pub fn instantiate(self, t: Elem) -> Option<Type> {
        match self {
            Ty::Is(ty) => Some(ty),
            Ty::T => Some(t.ty()),
            Ty::SetT => Some(Type::Set(t)),
            Ty::PredT => Some(Type::Fn(t, Scalar::Bool)),
            Ty::KeyT => None,
        }
    }

    /// Does a value of type `actual` fit this pattern, with `T` bound to `t`?
    pub fn accepts(self, actual: Type, t: Elem) -> bool {
        if actual == Type::Error {
            return true;
        }
        match self {
            Ty::KeyT => matches!(actual, Type::Fn(e, s) if t.is_subtype_of(e) && s != Scalar::Bool),
            other => other
                .instantiate(t)
                .is_some_and(|want| actual.is_subtype_of(want)),
        }
    }

    /// Writes the pattern as the language reference shows it.
    pub fn display(self, t: Option<Elem>) -> String {
        let tname = t.map_or("T", Elem::name);
        match self {
            Ty::Is(ty) => ty.to_string(),
            Ty::T => tname.to_string(),
            Ty::SetT => format!("Set<{tname}>"),
            Ty::PredT => format!("{tname} => Bool"),
            Ty::KeyT => format!("{tname} => Number"),
        }
    }
}

/// Writes a union of alternatives, `Object | Set<Object>`.
pub fn display_alternatives(alts: &[Ty], t: Option<Elem>) -> String {
    alts.iter()
        .map(|a| a.display(t))
        .collect::<Vec<_>>()
        .join(" | ")
}

/// A default argument value, typed so that the grounding evaluator need not parse text.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    /// The current stage's start (`start` outside stages).
    Here,
    Distance(f64),
    Direction(Direction),
    Metric(Metric),
}

impl fmt::Display for DefaultValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DefaultValue::Here => f.write_str("here"),
            DefaultValue::Distance(m) => write!(f, "{m}m"),
            DefaultValue::Direction(d) => f.write_str(d.word()),
            DefaultValue::Metric(m) => f.write_str(m.word()),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    Clockwise,
    Counterclockwise,
}

impl Direction {
    pub fn word(self) -> &'static str {
        match self {
            Direction::Clockwise => "clockwise",
            Direction::Counterclockwise => "counterclockwise",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Metric {
    /// Euclidean distance between places.
    Straight,
    /// Walking distance over free space (geodesic on the grid).
    Travel,
}

impl Metric {
    pub fn word(self) -> &'static str {
        match self {
            Metric::Straight => "straight",
            Metric::Travel => "travel",
        }
    }
}

/// When a parameter may be left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Requirement {
    Required,
    /// May be omitted; the built-in's doc says what omission means (`objects()` = all objects).
    Optional,
    Default(DefaultValue),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    pub name: &'static str,
    /// Accepted alternatives.
    pub ty: &'static [Ty],
    pub req: Requirement,
}

/// Whether a built-in is called as `f(...)` or as `receiver.f(...)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Receiver {
    Free,
    Method(&'static [Ty]),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Builtin {
    pub name: &'static str,
    pub receiver: Receiver,
    pub params: &'static [Param],
    pub ret: Ty,
    /// One line for hover text, the language reference and the LLM prompt.
    pub doc: &'static str,
    pub example: &'static str,
}

impl Builtin {
    pub fn is_method(&self) -> bool {
        matches!(self.receiver, Receiver::Method(_))
    }

    /// Binds `T` from the receiver's actual type, or `None` when this overload does not apply.
    pub fn bind_receiver(&self, actual: Type) -> Option<Elem> {
        let Receiver::Method(alts) = self.receiver else {
            return Some(Elem::Place);
        };
        let t = match actual {
            Type::Set(e) => e,
            other => other.as_place().unwrap_or(Elem::Place),
        };
        alts.iter().any(|a| a.accepts(actual, t)).then_some(t)
    }

    /// `Set<T>.nearest(to: Place = here, by: Metric = straight) -> T`, with `T` substituted when known.
    pub fn signature(&self, t: Option<Elem>) -> String {
        let mut s = String::new();
        if let Receiver::Method(alts) = self.receiver {
            let recv = display_alternatives(alts, t);
            if alts.len() > 1 {
                s.push_str(&format!("({recv})."));
            } else {
                s.push_str(&format!("{recv}."));
            }
        }
        s.push_str(self.name);
        s.push('(');
        let params: Vec<String> = self
            .params
            .iter()
            .map(|p| {
                let ty = display_alternatives(p.ty, t);
                match p.req {
                    Requirement::Required => format!("{}: {ty}", p.name),
                    Requirement::Optional => format!("{}: {ty}?", p.name),
                    Requirement::Default(d) => format!("{}: {ty} = {d}", p.name),
                }
            })
            .collect();
        s.push_str(&params.join(", "));
        s.push_str(") -> ");
        s.push_str(&self.ret.display(t));
        s
    }
}

/// A named value that needs no call: `start`, `here`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Constant {
    pub name: &'static str,
    pub ty: Type,
    pub doc: &'static str,
}

/// A word that is only meaningful in a slot of its type (`clockwise` where a `Direction` goes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnumWord {
    pub name: &'static str,
    pub ty: Type,
    pub doc: &'static str,
}
