//! What a position in the program expects: the context that decides how a bare name reads
//! (category, enumeration word, binding) and which diagnostic a mismatch gets.

use m2rc_grammar::ast::Span;
use m2rc_stdlib::builtins::{Elem, Scalar, Ty, Type, signature::display_alternatives};
use m2rc_stdlib::vocab::CategoryKind;

/// Category context: which kind of category the slot wants, and, when the argument is written
/// directly as `objects(word)` / `rooms(word)`, the span of the function name (so that
/// `objects(kitchen)` can be fixed to `rooms(kitchen)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct CatCtx {
    pub want: Option<CategoryKind>,
    pub func: Option<Span>,
}

#[derive(Clone, Copy, Debug)]
pub(crate) enum Slot {
    /// No expectation (a `let` right-hand side, an operand).
    Any,
    /// Exactly this type (or a subtype).
    Exact(Type),
    /// A built-in parameter, or a constraint position: the accepted alternatives with `T` bound.
    Alts {
        alts: &'static [Ty],
        t: Elem,
        cat: Option<CatCtx>,
    },
}

impl Slot {
    pub fn alts(alts: &'static [Ty]) -> Slot {
        Slot::Alts {
            alts,
            t: Elem::Place,
            cat: None,
        }
    }

    fn each(&self) -> Vec<Option<Type>> {
        match *self {
            Slot::Any => vec![],
            Slot::Exact(t) => vec![Some(t)],
            Slot::Alts { alts, t, .. } => alts.iter().map(|a| a.instantiate(t)).collect(),
        }
    }

    pub fn accepts(&self, actual: Type) -> bool {
        match *self {
            Slot::Any => true,
            Slot::Exact(t) => actual.is_subtype_of(t),
            Slot::Alts { alts, t, .. } => alts.iter().any(|a| a.accepts(actual, t)),
        }
    }

    pub fn category(&self) -> Option<CatCtx> {
        match *self {
            Slot::Alts { cat: Some(c), .. } => Some(c),
            _ if self.each().contains(&Some(Type::Category)) => Some(CatCtx {
                want: None,
                func: None,
            }),
            _ => None,
        }
    }

    /// `Direction` or `Metric` when the slot wants an enumeration word.
    pub fn enum_type(&self) -> Option<Type> {
        self.each()
            .into_iter()
            .flatten()
            .find(|t| matches!(t, Type::Direction | Type::Metric))
    }

    /// The lambda parameter's type and whether the body must be a `Bool` (a predicate) rather
    /// than a ranking key.
    pub fn lambda(&self) -> Option<(Elem, bool)> {
        match *self {
            Slot::Alts { alts, t, .. } => alts.iter().find_map(|a| match a {
                Ty::PredT => Some((t, true)),
                Ty::KeyT => Some((t, false)),
                Ty::Is(Type::Fn(e, s)) => Some((*e, *s == Scalar::Bool)),
                _ => None,
            }),
            Slot::Exact(Type::Fn(e, s)) => Some((e, s == Scalar::Bool)),
            _ => None,
        }
    }

    /// Whether a single place fits and a set does not.
    pub fn wants_single_place(&self) -> bool {
        let tys: Vec<Type> = self.each().into_iter().flatten().collect();
        tys.iter().any(|t| t.is_place()) && !tys.iter().any(|t| t.is_set())
    }

    /// How the expectation is written in messages: `Place | Set<Place>`.
    pub fn describe(&self) -> String {
        match *self {
            Slot::Any => "any value".to_string(),
            Slot::Exact(t) => t.to_string(),
            Slot::Alts { alts, t, .. } => display_alternatives(alts, Some(t)),
        }
    }
}
