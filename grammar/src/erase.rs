//! Span erasure, for comparing trees that came from different texts of the same program (the
//! round-trip property `parse(print(p)) == p`, checker tests that build trees by hand).

use crate::ast::*;

/// Whether two programs are the same tree, ignoring every span.
pub fn same_modulo_spans(a: &Program, b: &Program) -> bool {
    erase_spans(a) == erase_spans(b)
}

/// A copy of `program` with every span set to `0..0`.
pub fn erase_spans(program: &Program) -> Program {
    Program {
        items: program.items.iter().map(item).collect(),
        span: Span::default(),
    }
}

/// A copy of `e` with every span set to `0..0`.
pub fn erase_expr_spans(e: &Expr) -> Expr {
    expr(e)
}

fn id(i: &Ident) -> Ident {
    Ident {
        name: i.name.clone(),
        span: Span::default(),
    }
}

fn item(i: &Item) -> Item {
    match i {
        Item::Let(l) => Item::Let(let_(l)),
        Item::Route(r) => Item::Route(Route {
            items: r.items.iter().map(route_item).collect(),
            span: Span::default(),
        }),
        Item::Error(_) => Item::Error(Span::default()),
    }
}

fn let_(l: &Let) -> Let {
    Let {
        name: id(&l.name),
        value: expr(&l.value),
        span: Span::default(),
    }
}

fn route_item(i: &RouteItem) -> RouteItem {
    match i {
        RouteItem::Stage(s) => RouteItem::Stage(Stage {
            target: expr(&s.target),
            name: s.name.as_ref().map(id),
            body: s.body.iter().map(stage_item).collect(),
            span: Span::default(),
        }),
        RouteItem::Constraint(c) => RouteItem::Constraint(constraint(c)),
        RouteItem::Let(l) => RouteItem::Let(let_(l)),
        RouteItem::For(f) => RouteItem::For(ForStages {
            var: id(&f.var),
            iter: expr(&f.iter),
            body: f.body.iter().map(route_item).collect(),
            span: Span::default(),
        }),
        RouteItem::Error(_) => RouteItem::Error(Span::default()),
        RouteItem::Ltl(f) => RouteItem::Ltl(LtlForm {
            keyword: id(&f.keyword),
            formula: f.formula.clone(),
            formula_span: Span::default(),
            span: Span::default(),
        }),
    }
}

fn stage_item(i: &StageItem) -> StageItem {
    match i {
        StageItem::Constraint(c) => StageItem::Constraint(constraint(c)),
        StageItem::Let(l) => StageItem::Let(let_(l)),
        StageItem::Error(_) => StageItem::Error(Span::default()),
    }
}

fn constraint(c: &Constraint) -> Constraint {
    Constraint {
        kind: c.kind,
        kind_span: Span::default(),
        value: expr(&c.value),
        scopes: c
            .scopes
            .iter()
            .map(|s| match s {
                Scope::Within { place, .. } => Scope::Within {
                    place: expr(place),
                    span: Span::default(),
                },
                Scope::During { stages, .. } => Scope::During {
                    stages: stages.iter().map(id).collect(),
                    span: Span::default(),
                },
            })
            .collect(),
        span: Span::default(),
    }
}

fn args(a: &[Arg]) -> Vec<Arg> {
    a.iter()
        .map(|a| Arg {
            name: a.name.as_ref().map(id),
            value: expr(&a.value),
            span: Span::default(),
        })
        .collect()
}

fn expr(e: &Expr) -> Expr {
    let kind = match &e.kind {
        ExprKind::Name(i) => ExprKind::Name(id(i)),
        ExprKind::Call { func, args: a } => ExprKind::Call {
            func: id(func),
            args: args(a),
        },
        ExprKind::Method {
            receiver,
            method,
            args: a,
            parens,
        } => ExprKind::Method {
            receiver: Box::new(expr(receiver)),
            method: id(method),
            args: args(a),
            parens: *parens,
        },
        ExprKind::Lambda { param, body } => ExprKind::Lambda {
            param: id(param),
            body: Box::new(expr(body)),
        },
        ExprKind::Binary { op, lhs, rhs, .. } => ExprKind::Binary {
            op: *op,
            op_span: Span::default(),
            lhs: Box::new(expr(lhs)),
            rhs: Box::new(expr(rhs)),
        },
        ExprKind::Unary { op, operand, .. } => ExprKind::Unary {
            op: *op,
            op_span: Span::default(),
            operand: Box::new(expr(operand)),
        },
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => ExprKind::If {
            cond: Box::new(expr(cond)),
            then: Box::new(expr(then)),
            otherwise: Box::new(expr(otherwise)),
        },
        other @ (ExprKind::Int(_)
        | ExprKind::Number(_)
        | ExprKind::Distance { .. }
        | ExprKind::Bool(_)
        | ExprKind::Str(_)
        | ExprKind::Error) => other.clone(),
    };
    Expr {
        kind,
        span: Span::default(),
    }
}
