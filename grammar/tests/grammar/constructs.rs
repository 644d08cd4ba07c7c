//! One test per construct: the tree the parser builds, checked through a compact S-expression
//! rendering (structure) and through spans where they matter.

use m2rc_grammar::ast::*;
use m2rc_grammar::{parse, parse_expr};

/// `(op lhs rhs)`, `(. recv method args..)`, `(call f args..)`, `(=> x body)`, `(if c a b)`.
fn sx(e: &Expr) -> String {
    let args = |a: &[Arg]| {
        a.iter()
            .map(|a| match &a.name {
                Some(n) => format!(" {}:{}", n.name, sx(&a.value)),
                None => format!(" {}", sx(&a.value)),
            })
            .collect::<String>()
    };
    match &e.kind {
        ExprKind::Name(i) => i.name.clone(),
        ExprKind::Int(v) => format!("{v}i"),
        ExprKind::Number(v) => format!("{v}f"),
        ExprKind::Distance { value, unit } => format!("{value}{unit:?}"),
        ExprKind::Bool(b) => b.to_string(),
        ExprKind::Str(s) => format!("{s:?}"),
        ExprKind::Call { func, args: a } => format!("(call {}{})", func.name, args(a)),
        ExprKind::Method {
            receiver,
            method,
            args: a,
            parens,
        } => {
            format!(
                "(.{} {} {}{})",
                if *parens { "" } else { "field" },
                sx(receiver),
                method.name,
                args(a)
            )
        }
        ExprKind::Lambda { param, body } => format!("(=> {} {})", param.name, sx(body)),
        ExprKind::Binary { op, lhs, rhs, .. } => format!("({op:?} {} {})", sx(lhs), sx(rhs)),
        ExprKind::Unary { op, operand, .. } => format!("({op:?} {})", sx(operand)),
        ExprKind::If {
            cond,
            then,
            otherwise,
        } => format!("(if {} {} {})", sx(cond), sx(then), sx(otherwise)),
        ExprKind::Error => "ERROR".to_string(),
    }
}

fn e(src: &str) -> String {
    match parse_expr(src) {
        Ok(expr) => sx(&expr),
        Err(errors) => panic!("{src}: {errors:?}"),
    }
}

fn clean(src: &str) -> Program {
    let parsed = parse(src);
    assert!(parsed.errors.is_empty(), "{src}: {:?}", parsed.errors);
    parsed.program
}

fn route_items(src: &str) -> Vec<RouteItem> {
    match clean(src).items.into_iter().next() {
        Some(Item::Route(r)) => r.items,
        other => panic!("expected a route, got {other:?}"),
    }
}

#[test]
fn literals() {
    assert_eq!(e("2"), "2i");
    assert_eq!(e("0.5"), "0.5f");
    assert_eq!(e("1.5m"), "1.5M");
    assert_eq!(e("30cm"), "30Cm");
    assert_eq!(e("true"), "true");
    assert_eq!(e("false"), "false");
    assert_eq!(e(r#""a\tb""#), r#""a\tb""#);
    assert_eq!(e("kitchen"), "kitchen");
}

#[test]
fn calls_and_named_arguments() {
    assert_eq!(e("objects()"), "(call objects)");
    assert_eq!(e("objects(chair)"), "(call objects chair)");
    assert_eq!(
        e("nearest(to: bed, by: travel)"),
        "(call nearest to:bed by:travel)"
    );
    assert_eq!(
        e("area_near(x, within: 0.5m,)"),
        "(call area_near x within:0.5M)"
    );
}

#[test]
fn method_chains_with_and_without_parentheses() {
    assert_eq!(
        e("rooms(bathroom).smallest()"),
        "(. (call rooms bathroom) smallest)"
    );
    assert_eq!(e("x.room"), "(.field x room)");
    assert_eq!(e("a.b().c(1).d"), "(.field (. (. a b) c 1i) d)");
    assert_eq!(
        e("objects(can)\n  .in(kitchen)\n  .only()"),
        "(. (. (call objects can) in kitchen) only)"
    );
}

#[test]
fn keywords_are_method_and_argument_names() {
    assert_eq!(e("o.in(room)"), "(. o in room)");
    assert_eq!(e("o.near(x, within: 1.5m)"), "(. o near x within:1.5M)");
    assert_eq!(e("o.not.and()"), "(. (.field o not) and)");
}

#[test]
fn lambdas() {
    assert_eq!(e("o => o.in(k)"), "(=> o (. o in k))");
    assert_eq!(
        e("s.where(r => r.area() > 2.0 and r.exists())"),
        "(. s where (=> r (And (Gt (. r area) 2f) (. r exists))))"
    );
    assert_eq!(e("x => y => x"), "(=> x (=> y x))");
}

#[test]
fn if_expressions() {
    assert_eq!(e("if a { b } else { c }"), "(if a b c)");
    assert_eq!(
        e("if a { b } else if c { d } else { e }"),
        "(if a b (if c d e))"
    );
    assert_eq!(e("if a { b } else { c }.count()"), "(. (if a b c) count)");
}

#[test]
fn precedence_loosest_to_tightest() {
    assert_eq!(e("a or b and c"), "(Or a (And b c))");
    assert_eq!(e("a and b or c"), "(Or (And a b) c)");
    assert_eq!(e("not a and b"), "(And (Not a) b)");
    assert_eq!(e("not a == b"), "(Not (Eq a b))");
    assert_eq!(e("a == b | c"), "(Eq a (Union b c))");
    assert_eq!(e("a | b + c"), "(Union a (Add b c))");
    assert_eq!(e("a + b * c"), "(Add a (Mul b c))");
    assert_eq!(e("-a * b"), "(Mul (Neg a) b)");
    assert_eq!(e("-a.b()"), "(Neg (. a b))");
    assert_eq!(e("(a + b) * c"), "(Mul (Add a b) c)");
}

#[test]
fn associativity() {
    assert_eq!(e("a - b - c"), "(Sub (Sub a b) c)");
    assert_eq!(e("a | b | c"), "(Union (Union a b) c)");
    assert_eq!(e("a or b or c"), "(Or (Or a b) c)");
    assert_eq!(e("not not a"), "(Not (Not a))");
    assert_eq!(e("- -a"), "(Neg (Neg a))");
    assert!(
        parse_expr("a < b < c").is_err(),
        "comparisons are non-associative"
    );
}

#[test]
fn all_comparison_operators() {
    for (src, op) in [
        ("==", "Eq"),
        ("!=", "Ne"),
        ("<", "Lt"),
        ("<=", "Le"),
        (">", "Gt"),
        (">=", "Ge"),
    ] {
        assert_eq!(e(&format!("a {src} b")), format!("({op} a b)"));
    }
}

#[test]
fn top_level_lets_and_route() {
    let p = clean("let a = 1\nlet b = a\nroute {}");
    assert_eq!(p.items.len(), 3);
    let Item::Let(l) = &p.items[1] else { panic!() };
    assert_eq!(l.name.name, "b");
    assert_eq!(l.span, Span::new(10, 19));
    assert_eq!(l.name.span, Span::new(14, 15));
    assert!(
        matches!(&p.items[2], Item::Route(r) if r.items.is_empty() && r.span == Span::new(20, 28))
    );
}

#[test]
fn stages_with_names_and_bodies() {
    let items =
        route_items("route {\n go a\n go b as second\n go c { pass d\n avoid e }\n go f as g {} }");
    let stages: Vec<&Stage> = items
        .iter()
        .map(|i| match i {
            RouteItem::Stage(s) => s,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(stages.len(), 4);
    assert!(stages[0].name.is_none() && stages[0].body.is_empty());
    assert_eq!(
        stages[1].name.as_ref().map(|n| n.name.as_str()),
        Some("second")
    );
    assert_eq!(stages[2].body.len(), 2);
    assert!(stages[3].body.is_empty());
    assert_eq!(stages[3].name.as_ref().map(|n| n.name.as_str()), Some("g"));
}

#[test]
fn constraints_and_scopes() {
    let items = route_items(
        "route { go a as s1\n go b as s2\n avoid x during s1, s2\n prefer near(y) within k\n prefer far(z) during s1 within k }",
    );
    let cs: Vec<&Constraint> = items
        .iter()
        .filter_map(|i| match i {
            RouteItem::Constraint(c) => Some(c),
            _ => None,
        })
        .collect();
    assert_eq!(cs.len(), 3);
    assert_eq!(cs[0].kind, ConstraintKind::Avoid);
    assert!(matches!(&cs[0].scopes[..], [Scope::During { stages, .. }] if stages.len() == 2));
    assert_eq!(cs[1].kind, ConstraintKind::Prefer);
    assert!(matches!(&cs[1].scopes[..], [Scope::Within { .. }]));
    assert!(matches!(
        &cs[2].scopes[..],
        [Scope::During { .. }, Scope::Within { .. }]
    ));
    let src = "route { go a { pass b } }";
    let items = route_items(src);
    let RouteItem::Stage(s) = &items[0] else {
        panic!()
    };
    let StageItem::Constraint(c) = &s.body[0] else {
        panic!()
    };
    assert_eq!(c.kind, ConstraintKind::Pass);
    assert_eq!(&src[c.kind_span.start..c.kind_span.end], "pass");
    assert_eq!(&src[c.span.start..c.span.end], "pass b");
}

#[test]
fn during_accepts_a_trailing_comma() {
    let items = route_items("route { go a as s\n avoid x during s,\n go b }");
    assert_eq!(items.len(), 3);
}

#[test]
fn for_stages_and_lets_in_blocks() {
    let items =
        route_items("route { let k = 2\n for r in rs { go r { let d = r.doorways()\n pass d } } }");
    assert!(matches!(&items[0], RouteItem::Let(l) if l.name.name == "k"));
    let RouteItem::For(f) = &items[1] else {
        panic!("{:?}", items[1])
    };
    assert_eq!(f.var.name, "r");
    let RouteItem::Stage(s) = &f.body[0] else {
        panic!()
    };
    assert!(matches!(&s.body[0], StageItem::Let(_)));
}

#[test]
fn spans_cover_the_source_of_each_node() {
    let src = "let x = objects(chair).in(kitchen).nearest(by: travel)";
    let p = clean(src);
    let Item::Let(l) = &p.items[0] else { panic!() };
    assert_eq!(
        &src[l.value.span.start..l.value.span.end],
        "objects(chair).in(kitchen).nearest(by: travel)"
    );
    let ExprKind::Method {
        receiver,
        method,
        args,
        ..
    } = &l.value.kind
    else {
        panic!()
    };
    assert_eq!(
        &src[receiver.span.start..receiver.span.end],
        "objects(chair).in(kitchen)"
    );
    assert_eq!(&src[method.span.start..method.span.end], "nearest");
    assert_eq!(&src[args[0].span.start..args[0].span.end], "by: travel");
    let src2 = "let y = a + b";
    let Item::Let(l) = &clean(src2).items[0] else {
        panic!()
    };
    let ExprKind::Binary { op_span, .. } = &l.value.kind else {
        panic!()
    };
    assert_eq!(&src2[op_span.start..op_span.end], "+");
}

#[test]
fn program_span_is_the_whole_file_and_comments_are_collected() {
    let src = "// map: demo\nlet a = 1 // one\n";
    let parsed = parse(src);
    assert_eq!(parsed.program.span, Span::new(0, src.len()));
    assert_eq!(parsed.comments.len(), 2);
    assert_eq!(parsed.comments[1].1, "// one");
}

#[test]
fn empty_and_comment_only_files() {
    assert!(clean("").items.is_empty());
    assert!(clean("// nothing here\n").items.is_empty());
}
