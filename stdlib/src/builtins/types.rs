//! The static types of `.m2r`.
//!
//! Every type is `Copy` and finite: sets only hold places and lambdas only map a place to a scalar,
//! so the checker, the grounding evaluator and the hover text can pass types around freely and the
//! built-in table can be a `static` without allocation.

use serde::Serialize;
use std::fmt;

/// What a set, a lambda parameter or a place-typed slot holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Elem {
    Object,
    Room,
    Region,
    /// Any of the three; the element type of a mixed set such as `objects(sofa) | rooms(kitchen)`.
    Place,
}

impl Elem {
    /// `self <: other`: every element type is a `Place`.
    pub fn is_subtype_of(self, other: Elem) -> bool {
        self == other || other == Elem::Place
    }

    /// The least common supertype.
    pub fn join(self, other: Elem) -> Elem {
        if self == other { self } else { Elem::Place }
    }

    pub fn name(self) -> &'static str {
        match self {
            Elem::Object => "Object",
            Elem::Room => "Room",
            Elem::Region => "Region",
            Elem::Place => "Place",
        }
    }

    /// The singular type of this element.
    pub fn ty(self) -> Type {
        match self {
            Elem::Object => Type::Object,
            Elem::Room => Type::Room,
            Elem::Region => Type::Region,
            Elem::Place => Type::Place,
        }
    }
}

/// What a lambda returns: a truth value for `where`, an orderable key for rankings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Scalar {
    Bool,
    Int,
    Number,
    Distance,
}

impl Scalar {
    pub fn ty(self) -> Type {
        match self {
            Scalar::Bool => Type::Bool,
            Scalar::Int => Type::Int,
            Scalar::Number => Type::Number,
            Scalar::Distance => Type::Distance,
        }
    }

    pub fn from_type(t: Type) -> Option<Scalar> {
        match t {
            Type::Bool => Some(Scalar::Bool),
            Type::Int => Some(Scalar::Int),
            Type::Number => Some(Scalar::Number),
            Type::Distance => Some(Scalar::Distance),
            _ => None,
        }
    }
}

/// A `.m2r` type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Type {
    Object,
    Room,
    Region,
    /// Supertype of `Object`, `Room` and `Region`.
    Place,
    /// An ordered sequence of places (id order unless sorted). Never converts to its element.
    Set(Elem),
    Int,
    Number,
    /// A length in metres; written only as a literal with a unit (`1.5m`, `30cm`).
    Distance,
    Bool,
    /// An object or room category, or a union of categories.
    Category,
    /// `clockwise` / `counterclockwise`.
    Direction,
    /// `straight` / `travel`.
    Metric,
    /// A soft route preference, the value of `prefer`.
    Preference,
    /// A route stage named with `go ... as name`.
    Stage,
    /// A lambda `x => body` from an element to a scalar.
    Fn(Elem, Scalar),
    /// A string literal: no built-in accepts one; it exists so the checker can explain.
    Str,
    /// The type of an expression that already has an error; accepted everywhere so that one
    /// mistake gives one diagnostic.
    Error,
}

impl Type {
    /// `self <: other`. `Set<T>` never converts to `T`; `Int` widens to `Number`.
    pub fn is_subtype_of(self, other: Type) -> bool {
        if self == other || self == Type::Error || other == Type::Error {
            return true;
        }
        match (self, other) {
            (Type::Object | Type::Room | Type::Region, Type::Place) => true,
            (Type::Set(a), Type::Set(b)) => a.is_subtype_of(b),
            (Type::Int, Type::Number) => true,
            (Type::Fn(a, r), Type::Fn(b, s)) => {
                b.is_subtype_of(a) && Scalar::ty(r).is_subtype_of(s.ty())
            }
            _ => false,
        }
    }

    /// The element type when this is a single place.
    pub fn as_place(self) -> Option<Elem> {
        match self {
            Type::Object => Some(Elem::Object),
            Type::Room => Some(Elem::Room),
            Type::Region => Some(Elem::Region),
            Type::Place => Some(Elem::Place),
            _ => None,
        }
    }

    pub fn is_place(self) -> bool {
        self.as_place().is_some()
    }

    pub fn is_set(self) -> bool {
        matches!(self, Type::Set(_))
    }

    /// Numbers, integers and distances can be ranked and compared with `<`.
    pub fn is_orderable(self) -> bool {
        matches!(self, Type::Int | Type::Number | Type::Distance)
    }
}

impl fmt::Display for Type {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Type::Object => f.write_str("Object"),
            Type::Room => f.write_str("Room"),
            Type::Region => f.write_str("Region"),
            Type::Place => f.write_str("Place"),
            Type::Set(e) => write!(f, "Set<{}>", e.name()),
            Type::Int => f.write_str("Int"),
            Type::Number => f.write_str("Number"),
            Type::Distance => f.write_str("Distance"),
            Type::Bool => f.write_str("Bool"),
            Type::Category => f.write_str("Category"),
            Type::Direction => f.write_str("Direction"),
            Type::Metric => f.write_str("Metric"),
            Type::Preference => f.write_str("Preference"),
            Type::Stage => f.write_str("Stage"),
            Type::Fn(e, r) => write!(f, "{} => {}", e.name(), r.ty()),
            Type::Str => f.write_str("String"),
            Type::Error => f.write_str("{unknown}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_are_subtypes_of_place_but_sets_are_not_singular() {
        assert!(Type::Object.is_subtype_of(Type::Place));
        assert!(Type::Room.is_subtype_of(Type::Place));
        assert!(!Type::Place.is_subtype_of(Type::Object));
        assert!(!Type::Set(Elem::Object).is_subtype_of(Type::Object));
        assert!(Type::Set(Elem::Object).is_subtype_of(Type::Set(Elem::Place)));
        assert!(!Type::Set(Elem::Place).is_subtype_of(Type::Set(Elem::Room)));
        assert!(Type::Int.is_subtype_of(Type::Number));
        assert!(!Type::Number.is_subtype_of(Type::Distance));
    }

    #[test]
    fn display_matches_the_language_reference() {
        assert_eq!(Type::Set(Elem::Room).to_string(), "Set<Room>");
        assert_eq!(
            Type::Fn(Elem::Object, Scalar::Bool).to_string(),
            "Object => Bool"
        );
    }
}
