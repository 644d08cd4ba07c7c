//! proptest strategies over the AST: every tree they generate is one the parser can produce
//! (identifiers are not keywords, literals are non-negative, a method with arguments has
//! parentheses), with all spans `0..0`.

use m2rc_grammar::ast::*;
use m2rc_grammar::lexer::{KEYWORDS, is_keyword};
use proptest::prelude::*;

const NO: Span = Span { start: 0, end: 0 };

pub fn ident() -> impl Strategy<Value = Ident> {
    "[a-z_][a-z0-9_]{0,7}"
        .prop_filter("not a keyword", |s| !is_keyword(s))
        .prop_map(|name| Ident { name, span: NO })
}

/// Method and argument names: any identifier or keyword.
fn member_name() -> impl Strategy<Value = Ident> {
    prop_oneof![
        4 => ident(),
        1 => prop::sample::select(KEYWORDS).prop_map(|k| Ident { name: k.to_string(), span: NO }),
    ]
}

fn non_negative_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        prop::num::f64::POSITIVE | prop::num::f64::ZERO | prop::num::f64::SUBNORMAL,
        (0u32..100_000, 0u32..5).prop_map(|(m, e)| f64::from(m) / 10f64.powi(e as i32)),
    ]
}

fn mk(kind: ExprKind) -> Expr {
    Expr { kind, span: NO }
}

fn leaf() -> impl Strategy<Value = Expr> {
    prop_oneof![
        4 => ident().prop_map(|i| mk(ExprKind::Name(i))),
        1 => (0i64..=i64::MAX).prop_map(|v| mk(ExprKind::Int(v))),
        1 => non_negative_f64().prop_map(|v| mk(ExprKind::Number(v))),
        1 => (non_negative_f64(), prop_oneof![Just(DistanceUnit::M), Just(DistanceUnit::Cm)])
            .prop_map(|(value, unit)| mk(ExprKind::Distance { value, unit })),
        1 => any::<bool>().prop_map(|b| mk(ExprKind::Bool(b))),
        1 => "[a-z \"\\\\\n\tä]{0,6}".prop_map(|s| mk(ExprKind::Str(s))),
    ]
}

fn bin_op() -> impl Strategy<Value = BinOp> {
    prop::sample::select(vec![
        BinOp::Or,
        BinOp::And,
        BinOp::Eq,
        BinOp::Ne,
        BinOp::Lt,
        BinOp::Le,
        BinOp::Gt,
        BinOp::Ge,
        BinOp::Union,
        BinOp::Add,
        BinOp::Sub,
        BinOp::Mul,
    ])
}

pub fn expr() -> impl Strategy<Value = Expr> {
    leaf().prop_recursive(5, 48, 4, |inner| {
        let args = prop::collection::vec((prop::option::of(member_name()), inner.clone()), 0..4)
            .prop_map(|v| {
                v.into_iter()
                    .map(|(name, value)| Arg {
                        name,
                        value,
                        span: NO,
                    })
                    .collect::<Vec<_>>()
            })
            .boxed();
        prop_oneof![
            (ident(), args.clone()).prop_map(|(func, args)| mk(ExprKind::Call { func, args })),
            (inner.clone(), member_name(), args, any::<bool>()).prop_map(
                |(r, method, args, parens)| {
                    let parens = parens || !args.is_empty();
                    mk(ExprKind::Method {
                        receiver: Box::new(r),
                        method,
                        args,
                        parens,
                    })
                }
            ),
            (ident(), inner.clone()).prop_map(|(param, body)| mk(ExprKind::Lambda {
                param,
                body: Box::new(body)
            })),
            (bin_op(), inner.clone(), inner.clone()).prop_map(|(op, l, r)| mk(ExprKind::Binary {
                op,
                op_span: NO,
                lhs: Box::new(l),
                rhs: Box::new(r)
            })),
            (prop_oneof![Just(UnOp::Not), Just(UnOp::Neg)], inner.clone()).prop_map(|(op, e)| mk(
                ExprKind::Unary {
                    op,
                    op_span: NO,
                    operand: Box::new(e)
                }
            )),
            (inner.clone(), inner.clone(), inner).prop_map(|(c, t, o)| mk(ExprKind::If {
                cond: Box::new(c),
                then: Box::new(t),
                otherwise: Box::new(o)
            })),
        ]
    })
}

fn let_() -> impl Strategy<Value = Let> {
    (ident(), expr()).prop_map(|(name, value)| Let {
        name,
        value,
        span: NO,
    })
}

fn scope() -> impl Strategy<Value = Scope> {
    prop_oneof![
        expr().prop_map(|place| Scope::Within { place, span: NO }),
        prop::collection::vec(ident(), 1..3).prop_map(|stages| Scope::During { stages, span: NO }),
    ]
}

fn constraint() -> impl Strategy<Value = Constraint> {
    (
        prop_oneof![
            Just(ConstraintKind::Pass),
            Just(ConstraintKind::Avoid),
            Just(ConstraintKind::Prefer)
        ],
        expr(),
        prop::collection::vec(scope(), 0..3),
    )
        .prop_map(|(kind, value, scopes)| Constraint {
            kind,
            kind_span: NO,
            value,
            scopes,
            span: NO,
        })
}

fn stage_item() -> impl Strategy<Value = StageItem> {
    prop_oneof![
        3 => constraint().prop_map(StageItem::Constraint),
        1 => let_().prop_map(StageItem::Let),
    ]
}

fn stage() -> impl Strategy<Value = Stage> {
    (
        expr(),
        prop::option::of(ident()),
        prop::collection::vec(stage_item(), 0..3),
    )
        .prop_map(|(target, name, body)| Stage {
            target,
            name,
            body,
            span: NO,
        })
}

fn route_item() -> impl Strategy<Value = RouteItem> {
    let flat = prop_oneof![
        3 => stage().prop_map(RouteItem::Stage),
        2 => constraint().prop_map(RouteItem::Constraint),
        1 => let_().prop_map(RouteItem::Let),
    ];
    flat.prop_recursive(2, 12, 3, |inner| {
        (ident(), expr(), prop::collection::vec(inner, 0..3)).prop_map(|(var, iter, body)| {
            RouteItem::For(ForStages {
                var,
                iter,
                body,
                span: NO,
            })
        })
    })
}

pub fn program() -> impl Strategy<Value = Program> {
    let item = prop_oneof![
        2 => let_().prop_map(Item::Let),
        1 => prop::collection::vec(route_item(), 0..5).prop_map(|items| Item::Route(Route { items, span: NO })),
    ];
    prop::collection::vec(item, 0..5).prop_map(|items| Program { items, span: NO })
}

/// Real tokens (and a few near-misses) for token soups.
pub const VOCABULARY: &[&str] = &[
    "let", "route", "go", "as", "pass", "avoid", "prefer", "within", "during", "for", "in", "if",
    "else", "and", "or", "not", "true", "false", "x", "objects", "rooms", "chair", "nearest", "2",
    "0.5", "1.5m", "30cm", "\"s\"", "(", ")", "{", "}", "[", "]", ",", ":", ".", "=", "=>", "==",
    "!=", "<", "<=", ">", ">=", "|", "+", "-", "*", "/", ";", ":=", "&&", "||", "!", "#c\n", "'q'",
    "\"open", "// c\n", "3ft", "@", "\n", "lambda", "def",
];
