//! The surface syntax tree of `.m2r`, exactly as written, with a byte span on every node.
//!
//! Names are not resolved here: `chair` in `objects(chair)` and `bed` in `.nearest(bed)` are both
//! `ExprKind::Name`; the resolver decides, from the built-in signature of the slot they sit in,
//! whether a name is a binding, an object or room category, or an enumeration word such as
//! `clockwise` or `travel`. Keeping the tree unresolved lets the parser recover from any error and
//! lets the pretty-printer reproduce the program without knowing the standard library.

use serde::Serialize;

/// Half-open byte range `[start, end)` into the source text.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct Span {
    pub start: usize,
    pub end: usize,
}

impl Span {
    pub const fn new(start: usize, end: usize) -> Self {
        Span { start, end }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span::new(self.start.min(other.start), self.end.max(other.end))
    }
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// A whole `.m2r` file: top-level `let` bindings and one `route` block (more than one is a
/// checker error, not a parse error, so that the message can point at both).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Program {
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum Item {
    Let(Let),
    Route(Route),
    /// Source the parser could not make sense of; its diagnostic is already reported.
    Error(Span),
}

/// `let name = value`
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Let {
    pub name: Ident,
    pub value: Expr,
    pub span: Span,
}

/// `route { ... }`: the ordered stages, plus constraints that hold for the whole route.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Route {
    pub items: Vec<RouteItem>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum RouteItem {
    Stage(Stage),
    /// A constraint outside every stage: active for the whole route unless it says `during`.
    Constraint(Constraint),
    Let(Let),
    For(ForStages),
    Error(Span),
    /// The formula of a `route ltl "..."` block (always its first item; the parser puts it there).
    Ltl(LtlForm),
}

/// `route ltl "<LTLf formula>" [{ avoid ... prefer ... }]`: the route is the cheapest one whose
/// trace satisfies the formula; atoms are place bindings (`compiler::ltl`, `docs/ltl.md`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LtlForm {
    /// The word after `route` (the checker insists on `ltl`).
    pub keyword: Ident,
    /// The string's value: the formula text.
    pub formula: String,
    /// The string literal, quotes included.
    pub formula_span: Span,
    pub span: Span,
}

/// `go target [as name] [{ constraints and lets active while heading to target }]`
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stage {
    pub target: Expr,
    pub name: Option<Ident>,
    pub body: Vec<StageItem>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum StageItem {
    Constraint(Constraint),
    Let(Let),
    Error(Span),
}

/// `for x in ordered_set { go ... }`: one group of stages per element, in the set's order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ForStages {
    pub var: Ident,
    pub iter: Expr,
    pub body: Vec<RouteItem>,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum ConstraintKind {
    /// `pass place`: must pass through, in declaration order, before the stage's destination.
    Pass,
    /// `avoid place`: must never enter while the constraint is active.
    Avoid,
    /// `prefer preference`: a soft preference (near, far, closer, path shape, clearance).
    Prefer,
}

/// `pass | avoid | prefer <value> [within <place>] [during <stage>, ...]`
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Constraint {
    pub kind: ConstraintKind,
    pub kind_span: Span,
    pub value: Expr,
    pub scopes: Vec<Scope>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum Scope {
    /// Spatial scope: the constraint only counts inside this place.
    Within { place: Expr, span: Span },
    /// Route-stage scope: the constraint is active only during the named stages.
    During { stages: Vec<Ident>, span: Span },
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum DistanceUnit {
    M,
    Cm,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum ExprKind {
    /// A bare name: binding, category or enumeration word (see module docs).
    Name(Ident),
    Int(i64),
    Number(f64),
    /// `1.5m`, `30cm`: the value as written plus its unit.
    Distance {
        value: f64,
        unit: DistanceUnit,
    },
    Bool(bool),
    /// A string literal. The language has no string-typed built-ins; the checker reports a
    /// string where a category was meant with a fix that drops the quotes.
    Str(String),
    /// `f(args)`
    Call {
        func: Ident,
        args: Vec<Arg>,
    },
    /// `receiver.method(args)`; `receiver.method` without parentheses is a call with no args.
    Method {
        receiver: Box<Expr>,
        method: Ident,
        args: Vec<Arg>,
        parens: bool,
    },
    /// `x => body`
    Lambda {
        param: Ident,
        body: Box<Expr>,
    },
    Binary {
        op: BinOp,
        op_span: Span,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
    Unary {
        op: UnOp,
        op_span: Span,
        operand: Box<Expr>,
    },
    /// `if cond { then } else { otherwise }` as an expression.
    If {
        cond: Box<Expr>,
        then: Box<Expr>,
        otherwise: Box<Expr>,
    },
    /// An expression the parser could not read; its diagnostic is already reported.
    Error,
}

/// A call argument, positional (`k`) or named (`by: travel`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Arg {
    pub name: Option<Ident>,
    pub value: Expr,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum BinOp {
    Or,
    And,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    /// `a | b`: union of categories or of sets.
    Union,
    Add,
    Sub,
    Mul,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum UnOp {
    Not,
    Neg,
}
