//! Route structure and scopes: one `route` block with at least one stage; `pass` only inside a
//! stage; `during` only outside stages, naming declared stages in route order; `within` a place;
//! `prefer` a preference; `avoid` and `pass` places; `go` a single place.

use crate::check::{Checker, Ctx, Resolution, StageInfo};
use crate::diagnostic::{Code, Diagnostic};
use crate::resolve::{BindingKind, FrameKind};
use crate::slot::Slot;
use crate::suggest;
use m2rc_grammar::ast::{
    Constraint, ConstraintKind, ExprKind, ForStages, Item, Let, Program, Route, RouteItem, Scope,
    Span, Stage, StageItem,
};
use m2rc_stdlib::builtins::{Elem, Ty, Type, statements};
use m2rc_stdlib::vocab::{CategoryKind, Lookup};

const PLACES: &[Ty] = &[Ty::PLACE, Ty::SET_PLACE];
const PREFERENCE: &[Ty] = &[Ty::Is(Type::Preference)];

impl Checker<'_> {
    pub(crate) fn program(&mut self, p: &Program) {
        self.push_frame(FrameKind::Program);
        let mut first_route: Option<Span> = None;
        for item in &p.items {
            match item {
                Item::Let(l) => self.let_binding(l),
                Item::Route(r) => {
                    if let Some(first) = first_route {
                        self.report(
                            Diagnostic::new(
                                Code::MultipleRoutes,
                                Span::new(r.span.start, (r.span.start + 5).min(r.span.end)),
                                "a program has exactly one `route` block",
                            )
                            .label(first, "the first `route` block")
                            .help("merge the stages of both blocks into one `route { ... }`"),
                        );
                    } else {
                        first_route =
                            Some(Span::new(r.span.start, (r.span.start + 5).min(r.span.end)));
                    }
                    self.route(r);
                }
                Item::Error(_) => {}
            }
        }
        if first_route.is_none() && !self.had_parse_errors {
            let end = self.src.len();
            self.report(
                Diagnostic::new(
                    Code::MissingRoute,
                    Span::new(end, end),
                    "the program has no `route` block",
                )
                .help("add a route, e.g. `route { go objects(bed).nearest() }`"),
            );
        }
        self.pop_frame();
    }

    fn let_binding(&mut self, l: &Let) {
        let ty = self.expr(&l.value, Slot::Any);
        self.resolutions.insert(
            l.name.span,
            Resolution::Binding {
                def: l.name.span,
                kind: BindingKind::Let,
            },
        );
        self.bind(&l.name, l.span, ty, BindingKind::Let);
    }

    fn route(&mut self, r: &Route) {
        let base = self.stages.len();
        self.collect_stages(&r.items, false);
        let names: Vec<(usize, String, Span)> = self.stages[base..]
            .iter()
            .enumerate()
            .filter_map(|(i, s)| Some((base + i, s.name.clone()?, s.name_span?)))
            .collect();
        for (k, (i, name, span)) in names.iter().enumerate() {
            self.resolutions.insert(*span, Resolution::Stage(*i));
            if let Some((_, _, first)) = names[..k].iter().find(|(_, n, _)| n == name) {
                self.report(
                    Diagnostic::new(
                        Code::DuplicateStage,
                        *span,
                        format!("stage `{name}` is declared twice"),
                    )
                    .label(*first, "first declared here")
                    .help("give every stage its own name")
                    .suggest(*span, format!("{name}_2")),
                );
            }
        }
        let ltl = r.items.iter().any(|i| matches!(i, RouteItem::Ltl(_)));
        if self.stages.len() == base && !self.had_parse_errors && !ltl {
            self.report(
                Diagnostic::new(
                    Code::EmptyRoute,
                    Span::new(r.span.start, (r.span.start + 5).min(r.span.end)),
                    "the route has no stage",
                )
                .note("a route is a sequence of `go <place>` stages")
                .help("add a stage, e.g. `go objects(bed).nearest()`"),
            );
        }
        self.push_frame(FrameKind::Route);
        self.route_items(&r.items, base);
        self.pop_frame();
    }

    /// Lists every stage in route order before checking, so that `during` may name later stages.
    fn collect_stages(&mut self, items: &[RouteItem], in_for: bool) {
        for it in items {
            match it {
                RouteItem::Stage(s) => self.stages.push(StageInfo {
                    name: s.name.as_ref().map(|n| n.name.clone()),
                    name_span: s.name.as_ref().map(|n| n.span),
                    span: s.span,
                    target: s.target.span,
                    in_for,
                }),
                RouteItem::For(f) => self.collect_stages(&f.body, true),
                _ => {}
            }
        }
    }

    fn route_items(&mut self, items: &[RouteItem], base: usize) {
        for it in items {
            match it {
                RouteItem::Let(l) => self.let_binding(l),
                RouteItem::Stage(s) => self.stage(s),
                RouteItem::Constraint(c) => {
                    let saved = self.ctx;
                    self.ctx = Ctx {
                        in_stage: false,
                        route_wide: true,
                    };
                    self.constraint(c, base);
                    self.ctx = saved;
                }
                RouteItem::For(f) => self.for_stages(f, base),
                RouteItem::Error(_) => {}
                RouteItem::Ltl(f) => self.ltl_form(f, items),
            }
        }
    }

    fn stage(&mut self, s: &Stage) {
        // A set is "any one of them": the planner reaches the member cheapest by route.
        let slot = self.operand_slot("go", &s.target);
        let ty = self.expr(&s.target, slot);
        if !slot.accepts(ty) {
            self.report(
                Diagnostic::new(
                    Code::GoTargetNotPlace,
                    s.target.span,
                    format!(
                        "`go` needs a place (an Object, Room or Region) or a set of places, found `{ty}`"
                    ),
                )
                .help(match ty {
                    Type::Preference => "preferences go in the stage body: `go x { prefer ... }`",
                    _ => "write an object, room or region, e.g. `objects(bed).nearest()`",
                }),
            );
        }
        self.push_frame(FrameKind::Stage);
        let saved = self.ctx;
        self.ctx = Ctx {
            in_stage: true,
            route_wide: false,
        };
        for it in &s.body {
            match it {
                StageItem::Let(l) => self.let_binding(l),
                StageItem::Constraint(c) => self.constraint(c, 0),
                StageItem::Error(_) => {}
            }
        }
        self.ctx = saved;
        self.pop_frame();
    }

    fn for_stages(&mut self, f: &ForStages, base: usize) {
        let ty = self.expr(&f.iter, Slot::Any);
        let elem = match ty {
            Type::Set(e) => e,
            Type::Error => Elem::Place,
            other => {
                let mut d = Diagnostic::new(
                    Code::ForOverNonSet,
                    f.iter.span,
                    format!("`for` runs over a set, found `{other}`"),
                );
                if other.is_place() {
                    d = d.help("for a single place, write the stages without `for`");
                }
                self.report(d);
                Elem::Place
            }
        };
        self.push_frame(FrameKind::For);
        let var_ty = if ty == Type::Error || !ty.is_set() {
            Type::Error
        } else {
            elem.ty()
        };
        self.resolutions.insert(
            f.var.span,
            Resolution::Binding {
                def: f.var.span,
                kind: BindingKind::ForVar,
            },
        );
        self.bind(&f.var, f.var.span, var_ty, BindingKind::ForVar);
        self.route_items(&f.body, base);
        self.pop_frame();
    }

    fn constraint(&mut self, c: &Constraint, base: usize) {
        let word = match c.kind {
            ConstraintKind::Pass => "pass",
            ConstraintKind::Avoid => "avoid",
            ConstraintKind::Prefer => "prefer",
        };
        if c.kind == ConstraintKind::Pass && !self.ctx.in_stage {
            self.report(
                Diagnostic::new(Code::PassOutsideStage, c.kind_span, "`pass` must be inside a stage")
                    .note("`pass` orders waypoints before a stage's destination; outside stages it has no order")
                    .help("put `pass` inside the stage it belongs to: `go x { pass y }`"),
            );
        }
        self.constraint_value(c, word);
        let mut within: Option<Span> = None;
        let mut during: Option<Span> = None;
        for s in &c.scopes {
            match s {
                Scope::Within { place, span } => {
                    if let Some(first) = within {
                        self.duplicate_scope(*span, first, "within");
                    }
                    within = Some(*span);
                    let ty = self.expr(place, Slot::alts(PLACES));
                    if !Slot::alts(PLACES).accepts(ty) {
                        let mut d = Diagnostic::new(
                            Code::WithinNotPlace,
                            place.span,
                            format!(
                                "`within` needs a place (a room, region or object area), found `{ty}`"
                            ),
                        );
                        if ty == Type::Distance {
                            d = d.help("to stay within a distance of something, use `near(x)` or `area_near(x, within: d)`");
                        }
                        self.report(d);
                    }
                }
                Scope::During { stages, span } => {
                    if let Some(first) = during {
                        self.duplicate_scope(*span, first, "during");
                    }
                    during = Some(*span);
                    self.during(stages, *span, base);
                }
            }
        }
    }

    fn duplicate_scope(&mut self, span: Span, first: Span, word: &str) {
        self.report(
            Diagnostic::new(
                Code::DuplicateScope,
                span,
                format!("`{word}` is given twice for one constraint"),
            )
            .label(first, "first given here")
            .help(format!(
                "keep one `{word}`; for several places or stages write one constraint each"
            ))
            .suggest(span, ""),
        );
    }

    fn constraint_value(&mut self, c: &Constraint, word: &str) {
        let v = &c.value;
        match c.kind {
            ConstraintKind::Prefer => {
                if self.prefer_category_word(v) {
                    return;
                }
                let ty = self.expr(v, Slot::alts(PREFERENCE));
                if ty == Type::Preference || ty == Type::Error {
                    return;
                }
                let mut d = Diagnostic::new(
                    Code::PreferNotPreference,
                    v.span,
                    format!("`prefer` needs a preference, found `{ty}`"),
                )
                .note("preferences: near(x), far(x), closer(a, b), circle(x), follow_wall(room, dir), patrol(room, dir), clearance(d)");
                if ty.is_place() || ty.is_set() {
                    let t = self.text(v.span);
                    d = d
                        .help(format!("to stay close to it, write `prefer near({t})`"))
                        .suggest(v.span, format!("near({t})"));
                }
                self.report(d);
            }
            ConstraintKind::Pass | ConstraintKind::Avoid => {
                // `pass S` is any one member, `avoid S` every member.
                let slot = self.operand_slot(word, v);
                let ty = self.expr(v, slot);
                if slot.accepts(ty) {
                    return;
                }
                if ty == Type::Preference {
                    let mut d = Diagnostic::new(
                        Code::AvoidPreference,
                        v.span,
                        format!("`{word}` takes a place, not a preference"),
                    )
                    .note("`pass` and `avoid` are hard constraints on places; preferences go after `prefer`");
                    if let ExprKind::Call { func, args } = &v.kind
                        && args.len() == 1
                        && (func.name == "near" || func.name == "far")
                    {
                        let inner = self.text(args[0].value.span);
                        if c.kind == ConstraintKind::Avoid {
                            d = d
                                .help(format!("to keep away softly, write `prefer far({inner})`; to never enter it, `avoid {inner}`"))
                                .suggest(c.kind_span.to(v.span), format!("prefer far({inner})"))
                                .suggest(v.span, inner.to_string());
                        } else {
                            d = d
                                .help(format!("write `{word} {inner}`"))
                                .suggest(v.span, inner.to_string());
                        }
                    } else {
                        let t = self.text(v.span);
                        d = d
                            .help(format!("write `prefer {t}`"))
                            .suggest(c.kind_span, "prefer");
                    }
                    self.report(d);
                } else {
                    self.report(Diagnostic::new(
                        Code::ConstraintNotPlace,
                        v.span,
                        format!("`{word}` needs a place or a set of places, found `{ty}`"),
                    ));
                }
            }
        }
    }

    /// The slot of a `go`/`pass`/`avoid` operand, from the statement table. A bare category word
    /// after `go` or `pass` (`go kitchen`) names one thing, so it is read in a one-place slot and
    /// its fix picks one (`.only()`, `.nearest()`) instead of offering the set, which would mean
    /// "any kitchen".
    fn operand_slot(&self, keyword: &str, e: &m2rc_grammar::ast::Expr) -> Slot {
        if keyword != "avoid"
            && let ExprKind::Name(id) = &e.kind
            && self.peek_binding(&id.name).is_none()
            && m2rc_stdlib::builtins::constant(&id.name).is_none()
        {
            return Slot::alts(&[Ty::PLACE]);
        }
        Slot::alts(statements::operand(keyword))
    }

    /// `prefer kitchen`: a bare category word where a preference goes. Reported as E0309 with
    /// the `near(...)` fix rather than as a category used as a value.
    fn prefer_category_word(&mut self, v: &m2rc_grammar::ast::Expr) -> bool {
        let ExprKind::Name(id) = &v.kind else {
            return false;
        };
        if self.peek_binding(&id.name).is_some() {
            return false;
        }
        let (cat, kind) = match self.vocab.lookup(&id.name) {
            Lookup::Found(k) => (id.name.clone(), k),
            Lookup::Synonym(c, k) | Lookup::NotInMap(c, k) => (c, k),
            _ => return false,
        };
        let query = match kind {
            CategoryKind::Object => "objects",
            CategoryKind::Room => "rooms",
        };
        let fixed = format!("near({query}({cat}))");
        self.types.insert(v.span, Type::Error);
        self.report(
            Diagnostic::new(
                Code::PreferNotPreference,
                v.span,
                format!(
                    "`prefer` needs a preference, found the category `{}`",
                    id.name
                ),
            )
            .help(format!("to stay close to it, write `prefer {fixed}`"))
            .suggest(v.span, fixed),
        );
        true
    }

    fn during(&mut self, stages: &[m2rc_grammar::ast::Ident], span: Span, base: usize) {
        if self.ctx.in_stage {
            let remove = if span.start > 0 && self.src.as_bytes().get(span.start - 1) == Some(&b' ')
            {
                Span::new(span.start - 1, span.end)
            } else {
                span
            };
            self.report(
                Diagnostic::new(
                    Code::DuringInsideStage,
                    span,
                    "`during` is not allowed inside a stage",
                )
                .note("inside a stage body, the stage itself is the constraint's scope")
                .help("remove `during`, or move the constraint out of the stage body")
                .suggest(remove, ""),
            );
        }
        let known: Vec<(usize, String)> = self.stages[base..]
            .iter()
            .enumerate()
            .filter_map(|(i, s)| Some((base + i, s.name.clone()?)))
            .collect();
        let mut indices: Vec<(usize, &str)> = Vec::new();
        for id in stages {
            match known.iter().find(|(_, n)| *n == id.name) {
                Some((i, _)) => {
                    self.resolutions.insert(id.span, Resolution::Stage(*i));
                    indices.push((*i, &id.name));
                }
                None => {
                    let mut d = Diagnostic::new(
                        Code::UnknownStage,
                        id.span,
                        format!("no stage is named `{}`", id.name),
                    );
                    if let Some(best) =
                        suggest::best(&id.name, known.iter().map(|(_, n)| n.as_str()))
                    {
                        d = d
                            .help(format!("did you mean `{best}`?"))
                            .suggest(id.span, best);
                    } else if known.is_empty() {
                        d = d.help("name a stage with `go <place> as <name>`");
                    } else {
                        let names: Vec<&str> = known.iter().map(|(_, n)| n.as_str()).collect();
                        d = d.note(format!("stages: {}", names.join(", ")));
                    }
                    self.report(d);
                }
            }
        }
        if indices.windows(2).any(|w| w[0].0 >= w[1].0)
            && let (Some(first), Some(last)) = (stages.first(), stages.last())
        {
            let mut sorted = indices.clone();
            sorted.sort();
            sorted.dedup();
            let fixed: Vec<&str> = sorted.iter().map(|(_, n)| *n).collect();
            self.report(
                Diagnostic::new(
                    Code::StagesOutOfOrder,
                    first.span.to(last.span),
                    "stages after `during` must be listed once each, in route order",
                )
                .help(format!("write `during {}`", fixed.join(", ")))
                .suggest(first.span.to(last.span), fixed.join(", ")),
            );
        }
    }
}
