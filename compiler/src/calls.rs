//! Checking calls of built-ins: choosing the overload, matching positional and named arguments
//! to parameters, and explaining wrong names, receivers and arities.

use crate::check::{CallInfo, Checker, Resolution};
use crate::diagnostic::{Code, Diagnostic};
use crate::slot::{CatCtx, Slot};
use crate::suggest;
use m2rc_grammar::ast::{Arg, Expr, Ident, Span};
use m2rc_stdlib::builtins::{self, Builtin, Elem, Receiver, Requirement, Ty, Type};
use m2rc_stdlib::vocab::CategoryKind;

impl Checker<'_> {
    /// `f(args)`
    pub(crate) fn call(&mut self, e: &Expr, func: &Ident, args: &[Arg]) -> Type {
        let name = func.name.as_str();
        if let Some(b) = builtins::functions(name).next() {
            return self.apply(e, func, b, Elem::Place, args);
        }
        if let Some(m) = builtins::methods(name).next() {
            // `nearest(objects(chair))`: a method called like a function.
            let mut d = Diagnostic::new(
                Code::MethodAsFunction,
                func.span,
                format!("`{name}` is a method: call it on its receiver"),
            )
            .note(format!("signature: `{}`", m.signature(None)));
            let area = format!("area_{name}");
            if let Some(f) = builtins::functions(&area).next() {
                // `between(a, b)` means the area between them; `s.between(a, b)` would filter `s`.
                d = d
                    .help(format!(
                        "the area {name} places is `{area}(...)`: `{}`",
                        f.signature(None)
                    ))
                    .note(format!(
                        "`s.{name}(...)` keeps the elements of a set `s` that lie {name} the places"
                    ))
                    .suggest(func.span, area.clone());
            } else if let Some((first, rest)) = args.split_first()
                && first.name.is_none()
                && builtins::methods(name).any(|m| {
                    let required = m
                        .params
                        .iter()
                        .filter(|p| p.req == Requirement::Required)
                        .count();
                    rest.len() >= required && rest.len() <= m.params.len()
                })
            {
                // Only offered when the method form has the right number of arguments.
                let recv = self.text(first.value.span);
                let rest: Vec<&str> = rest.iter().map(|a| self.text(a.span)).collect();
                let fixed = format!("{recv}.{name}({})", rest.join(", "));
                d = d.help(format!("write `{fixed}`")).suggest(e.span, fixed);
            }
            self.report(d);
            self.args_unchecked(args);
            return Type::Error;
        }
        let mut d = Diagnostic::new(
            Code::UnknownFunction,
            func.span,
            format!("unknown function `{name}`"),
        );
        let free: Vec<&str> = builtins::BUILTINS
            .iter()
            .filter(|b| !b.is_method())
            .map(|b| b.name)
            .collect();
        let meant = builtins::synonyms::meaning(name);
        if let Some(kw) = meant.filter(|m| builtins::synonyms::KEYWORD_MEANINGS.contains(m)) {
            d = d.help(format!(
                "`{kw}` is a constraint, not a function: write `{kw} <place>` as its own line in the stage"
            ));
        } else if let Some(m) = meant.filter(|m| builtins::functions(m).next().is_some()) {
            let sig = builtins::functions(m)
                .map(|b| b.signature(None))
                .next()
                .unwrap_or_default();
            d = d
                .help(format!("`{name}` means `{m}`: `{sig}`"))
                .suggest(func.span, m);
        } else if let Some(m) = meant {
            d = d.help(format!(
                "`{name}` means the method `.{m}(...)`: call it on a set"
            ));
        } else if let Some(best) = suggest::best(name, free.iter().copied()) {
            d = d
                .help(format!("did you mean `{best}`?"))
                .suggest(func.span, best);
        } else if self.peek_binding(name).is_some() {
            d = d.note(format!("`{name}` is a binding, not a function"));
        }
        self.report(d);
        self.args_unchecked(args);
        Type::Error
    }

    /// `receiver.method(args)`
    pub(crate) fn method(
        &mut self,
        e: &Expr,
        receiver: &Expr,
        method: &Ident,
        args: &[Arg],
    ) -> Type {
        let recv = self.expr(receiver, Slot::Any);
        let name = method.name.as_str();
        if recv == Type::Error {
            self.args_unchecked(args);
            return Type::Error;
        }
        if let Some((b, t)) = builtins::method_for(name, recv) {
            return self.apply(e, method, b, t, args);
        }
        let rows: Vec<&'static Builtin> = builtins::methods(name).collect();
        if !rows.is_empty() {
            let receivers: Vec<String> = rows
                .iter()
                .filter_map(|b| match b.receiver {
                    Receiver::Method(alts) => {
                        Some(builtins::signature::display_alternatives(alts, None))
                    }
                    Receiver::Free => None,
                })
                .collect();
            let mut d = Diagnostic::new(
                Code::WrongReceiver,
                method.span,
                format!(
                    "`{name}` is a method of {}, found `{recv}`",
                    receivers.join(" and ")
                ),
            )
            .label(receiver.span, format!("this is `{recv}`"));
            if let Type::Set(el) = recv
                && builtins::method_for(name, el.ty()).is_some()
            {
                d = d
                    .help(format!("choose one element first, e.g. `.only().{name}(...)` or `.nearest().{name}(...)`"))
                    .suggest(Span::new(receiver.span.end, receiver.span.end), ".only()");
            } else if recv.is_place()
                && let Some(el) = recv.as_place()
                && builtins::method_for(name, Type::Set(el)).is_some()
            {
                d = d.note(format!(
                    "`{name}` works on sets; `{recv}` is a single place"
                ));
            }
            if let Some(def) = self.lambda_param_of(receiver) {
                d = d.label(
                    def,
                    format!("the parameter is a `{recv}`: an element of the set being filtered"),
                );
            }
            self.report(d);
            self.args_unchecked(args);
            return Type::Error;
        }
        if let Some(first) = builtins::functions(name).next() {
            let recv_text = self.text(receiver.span);
            let mut parts = vec![recv_text];
            parts.extend(args.iter().map(|a| self.text(a.span)));
            let fixed = format!("{name}({})", parts.join(", "));
            let mut d = Diagnostic::new(
                Code::FunctionAsMethod,
                method.span,
                format!("`{name}` is a function, not a method"),
            );
            // The rewrite moves the receiver to the first argument: offered only when it fits
            // there, so that applying it never trades this error for a type error.
            let elem = recv.as_place().unwrap_or(Elem::Place);
            if builtins::functions(name).any(|b| {
                b.params
                    .first()
                    .is_some_and(|p| p.ty.iter().any(|t| t.accepts(recv, elem)))
            }) {
                d = d.help(format!("write `{fixed}`")).suggest(e.span, fixed);
            } else {
                d = d
                    .note(format!("signature: `{}`", first.signature(None)))
                    .help(format!(
                        "call it as `{name}(...)`; `{recv}` does not fit its first argument"
                    ));
            }
            self.report(d);
            self.args_unchecked(args);
            return Type::Error;
        }
        // Prefer methods that apply to this receiver in the did-you-mean.
        let applicable: Vec<&str> = builtins::BUILTINS
            .iter()
            .filter(|b| b.is_method() && b.bind_receiver(recv).is_some())
            .map(|b| b.name)
            .collect();
        let all: Vec<&str> = builtins::BUILTINS
            .iter()
            .filter(|b| b.is_method())
            .map(|b| b.name)
            .collect();
        let mut d = Diagnostic::new(
            Code::UnknownMethod,
            method.span,
            format!("no method `{name}` on `{recv}`"),
        );
        if let Some(best) = suggest::best(name, applicable.iter().copied())
            .or_else(|| suggest::best(name, all.iter().copied()))
        {
            d = d
                .help(format!("did you mean `{best}`?"))
                .suggest(method.span, best);
        } else {
            let mut names = applicable.clone();
            names.dedup();
            d = d.note(format!("methods of `{recv}`: {}", names.join(", ")));
        }
        self.report(d);
        self.args_unchecked(args);
        Type::Error
    }

    /// The lambda parameter a receiver names, if any, for "the parameter is a Room" labels.
    fn lambda_param_of(&self, receiver: &Expr) -> Option<Span> {
        let m2rc_grammar::ast::ExprKind::Name(id) = &receiver.kind else {
            return None;
        };
        match self.resolutions.get(&id.span) {
            Some(Resolution::Binding {
                def,
                kind: crate::resolve::BindingKind::LambdaParam,
            }) => Some(*def),
            _ => None,
        }
    }

    /// Checks arguments of a call that could not be resolved, so names inside still resolve.
    /// Category words there are not reported: the call's own error explains the line, and the
    /// word was probably meant as a category of the intended built-in.
    fn args_unchecked(&mut self, args: &[Arg]) {
        let saved = std::mem::replace(&mut self.lenient, true);
        for a in args {
            self.expr(&a.value, Slot::Any);
        }
        self.lenient = saved;
    }

    /// Matches `args` to the parameters of `b`, checks each, and records the call.
    fn apply(
        &mut self,
        e: &Expr,
        func: &Ident,
        b: &'static Builtin,
        t: Elem,
        args: &[Arg],
    ) -> Type {
        self.resolutions
            .insert(func.span, Resolution::Builtin { builtin: b, t });
        let mut filled: Vec<Option<usize>> = vec![None; b.params.len()];
        let mut seen_named = false;
        let mut positional = 0usize;
        let mut extra: Vec<usize> = Vec::new();
        for (i, a) in args.iter().enumerate() {
            match &a.name {
                None => {
                    if seen_named {
                        self.report(
                            Diagnostic::new(
                                Code::PositionalAfterNamed,
                                a.span,
                                "a positional argument cannot follow a named one",
                            )
                            .help(format!(
                                "name it, or move it before the named arguments: `{}`",
                                b.signature(Some(t))
                            )),
                        );
                        self.expr(&a.value, Slot::Any);
                        continue;
                    }
                    if positional < b.params.len() {
                        filled[positional] = Some(i);
                    } else {
                        extra.push(i);
                    }
                    positional += 1;
                }
                Some(n) => {
                    seen_named = true;
                    match b.params.iter().position(|p| p.name == n.name) {
                        Some(p) if filled[p].is_some() => {
                            let prev = filled[p]
                                .and_then(|j| args.get(j))
                                .map_or(a.span, |x| x.span);
                            self.report(
                                Diagnostic::new(
                                    Code::DuplicateArgument,
                                    a.span,
                                    format!("argument `{}` is given twice", n.name),
                                )
                                .label(prev, "first given here")
                                .help("remove one of them"),
                            );
                            self.expr(&a.value, Slot::Any);
                        }
                        Some(p) => filled[p] = Some(i),
                        None => {
                            let names: Vec<&str> = b.params.iter().map(|p| p.name).collect();
                            let mut d = Diagnostic::new(
                                Code::UnknownNamedArgument,
                                n.span,
                                format!("`{}` has no parameter `{}`", b.name, n.name),
                            )
                            .note(format!("signature: `{}`", b.signature(Some(t))));
                            if let Some(best) = suggest::best(&n.name, names.iter().copied()) {
                                d = d
                                    .help(format!("did you mean `{best}`?"))
                                    .suggest(n.span, best);
                            }
                            self.report(d);
                            self.expr(&a.value, Slot::Any);
                        }
                    }
                }
            }
        }
        if !extra.is_empty() {
            let first = &args[extra[0]];
            let last = &args[*extra.last().unwrap_or(&extra[0])];
            // Remove from the end of the last accepted argument, taking the comma with it.
            let from = if extra[0] > 0 {
                args[extra[0] - 1].span.end
            } else {
                first.span.start
            };
            let n = b.params.len();
            let mut d = Diagnostic::new(
                Code::TooManyArguments,
                first.span.to(last.span),
                format!(
                    "`{}` takes {n} argument{}, but {} were given",
                    b.name,
                    if n == 1 { "" } else { "s" },
                    n + extra.len()
                ),
            )
            .note(format!("signature: `{}`", b.signature(Some(t))));
            if b.name == "objects" || b.name == "rooms" {
                let cats: Vec<&str> = std::iter::once(filled[0])
                    .flatten()
                    .chain(extra.iter().copied())
                    .map(|i| self.text(args[i].span))
                    .collect();
                d = d
                    .help(format!(
                        "unite categories with `|`: `{}({})`",
                        b.name,
                        cats.join(" | ")
                    ))
                    .suggest(e.span, format!("{}({})", b.name, cats.join(" | ")));
            } else if b.name == "area_between" && filled.iter().all(Option::is_some) {
                // Three or more places: the enclosed-area variant, not a dropped argument.
                let places: Vec<&str> = filled
                    .iter()
                    .flatten()
                    .chain(extra.iter())
                    .map(|&i| self.text(args[i].value.span))
                    .collect();
                let fixed = format!("area_enclosed([{}])", places.join(", "));
                d = d
                    .help(format!(
                        "for the area enclosed by three or more places write `{fixed}`"
                    ))
                    .suggest(e.span, fixed);
            } else {
                d = d
                    .help("remove the extra arguments")
                    .suggest(Span::new(from, last.span.end), "");
            }
            self.report(d);
            let extra_args: Vec<Arg> = extra.iter().map(|&i| args[i].clone()).collect();
            self.args_unchecked(&extra_args);
        }
        for (p, slot_arg) in b.params.iter().zip(&filled) {
            match slot_arg {
                Some(i) => {
                    let cat = p.ty.contains(&Ty::Is(Type::Category)).then_some(CatCtx {
                        want: match b.name {
                            "objects" => Some(CategoryKind::Object),
                            "rooms" => Some(CategoryKind::Room),
                            _ => None,
                        },
                        func: Some(func.span),
                    });
                    self.check_expr(&args[*i].value, Slot::Alts { alts: p.ty, t, cat });
                }
                None if p.req == Requirement::Required => {
                    let ty = builtins::signature::display_alternatives(p.ty, Some(t));
                    let mut d = Diagnostic::new(
                        Code::MissingArgument,
                        e.span,
                        format!("`{}` is missing its argument `{}: {ty}`", b.name, p.name),
                    )
                    .help(format!("signature: `{}`", b.signature(Some(t))));
                    // `a.between(b)` on one place: the writer meant the area between the two.
                    if b.name == "between"
                        && args.len() == 1
                        && let m2rc_grammar::ast::ExprKind::Method { receiver, .. } = &e.kind
                        && self.types.get(&receiver.span).is_some_and(|t| t.is_place())
                        && self.lambda_param_of(receiver).is_none()
                    {
                        let fixed = format!(
                            "area_between({}, {})",
                            self.text(receiver.span),
                            self.text(args[0].value.span)
                        );
                        d = d
                            .help(format!("for the area between two places write `{fixed}`"))
                            .suggest(e.span, fixed);
                    }
                    // `through(x)` on one place: "pass close by x" is a near preference; the
                    // writer gave one place, so no second one is offered.
                    if b.name == "through" && args.len() == 1 && args[0].name.is_none() {
                        let fixed = format!("near({})", self.text(args[0].value.span));
                        d = d
                            .help(format!(
                                "`through` is a path past two to four places in order; to stay close to one place (\"pass close by x\") write `{fixed}`"
                            ))
                            .suggest(e.span, fixed);
                    }
                    // A word the instruction must choose: offer every one, never pick.
                    let words: Vec<&str> = builtins::ENUM_WORDS
                        .iter()
                        .filter(|w| p.ty.contains(&Ty::Is(w.ty)))
                        .map(|w| w.name)
                        .collect();
                    if !words.is_empty() && self.text(e.span).ends_with(')') {
                        let at = Span::new(e.span.end - 1, e.span.end - 1);
                        let sep = if args.is_empty() { "" } else { ", " };
                        for w in &words {
                            d = d.suggest(at, format!("{sep}{}: {w}", p.name));
                        }
                        d = d.note(format!(
                            "the instruction must decide between {}; none is assumed",
                            words
                                .iter()
                                .map(|w| format!("`{w}`"))
                                .collect::<Vec<_>>()
                                .join(" and ")
                        ));
                    }
                    self.report(d);
                }
                None => {}
            }
        }
        self.check_ranges(b, args, &filled);
        self.calls.insert(
            e.span,
            CallInfo {
                builtin: b,
                t,
                args: filled,
            },
        );
        b.ret.instantiate(t).unwrap_or(Type::Error)
    }
}
