//! Arguments whose value is known before grounding and can be wrong whatever the map: a negative
//! distance (`clearance(-5m)`, `near(x, within: -1m)`) or an ordinal below 1
//! (`kth_nearest(-1)`, `kth(0)`). Reported here (E0216) rather than as a grounding failure, so
//! the repair loop sees them without a map.

use crate::check::Checker;
use crate::diagnostic::{Code, Diagnostic};
use m2rc_grammar::ast::{Arg, DistanceUnit, Expr, ExprKind, UnOp};
use m2rc_stdlib::builtins::{Builtin, Ty, Type};

/// A literal's value in metres or as a count, seeing through unary minus.
fn literal(e: &Expr) -> Option<f64> {
    match &e.kind {
        ExprKind::Int(i) => Some(*i as f64),
        ExprKind::Number(x) => Some(*x),
        ExprKind::Distance { value, unit } => Some(match unit {
            DistanceUnit::M => *value,
            DistanceUnit::Cm => *value / 100.0,
        }),
        ExprKind::Unary {
            op: UnOp::Neg,
            operand,
            ..
        } => literal(operand).map(|v| -v),
        _ => None,
    }
}

impl Checker<'_> {
    pub(crate) fn check_ranges(&mut self, b: &Builtin, args: &[Arg], filled: &[Option<usize>]) {
        for (p, slot) in b.params.iter().zip(filled) {
            let Some(arg) = slot.and_then(|i| args.get(i)) else {
                continue;
            };
            let Some(v) = literal(&arg.value) else {
                continue;
            };
            let text = self.text(arg.value.span).to_string();
            if p.ty.contains(&Ty::Is(Type::Distance)) && v < 0.0 {
                self.report(
                    Diagnostic::new(
                        Code::ArgumentOutOfRange,
                        arg.value.span,
                        format!(
                            "`{}` of `{}` cannot be negative, found `{text}`",
                            p.name, b.name
                        ),
                    )
                    .note("distances are lengths: 0 or more")
                    .help(format!(
                        "give the distance the instruction states, e.g. `{}: 0.5m`",
                        p.name
                    )),
                );
            } else if p.ty.contains(&Ty::Is(Type::Int)) && p.name == "k" && v < 1.0 {
                // `tour(k)` counts rooms; every other `k` is a position.
                let d = if b.name == "tour" {
                    Diagnostic::new(
                        Code::ArgumentOutOfRange,
                        arg.value.span,
                        format!("`k` of `tour` is how many rooms to pass, at least 1, found `{text}`"),
                    )
                    .help("give the number of rooms the instruction names, e.g. `tour(2)` for \"two bedrooms\"")
                } else {
                    Diagnostic::new(
                        Code::ArgumentOutOfRange,
                        arg.value.span,
                        format!("`k` of `{}` counts from 1, found `{text}`", b.name),
                    )
                    .note(if b.name.contains("farthest") {
                        "k = 1 is the farthest, k = 2 the second farthest"
                    } else {
                        "k = 1 is the first, k = 2 the second"
                    })
                    .help("give the position the instruction names: `1` for the first")
                };
                self.report(d);
            }
        }
    }
}
