//! The route block: stages, `for` groups, constraints and their scopes, into RouteIR.

use super::codes;
use super::shapes::LoopAsk;
use super::value::{PlaceVal, Pref, Value};
use super::{Grounder, Problem};
use crate::ir::{
    self, CellSet, Constraint, ConstraintKind, Construction, Direction, Pass, Place, PlaceKind,
    ROUTE_IR_VERSION, RouteIr, Shape, SourceSpan, StageScope,
};
use m2rc_grammar::ast::{self, ConstraintKind as Kind, Item, RouteItem, Scope, Span, StageItem};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target, WaypointShape};

/// A route-level constraint waiting for the stage list, to resolve `during` names.
struct Pending {
    kind: ConstraintKind,
    within: Option<Place>,
    during: Option<Vec<ast::Ident>>,
    /// The stage whose body declared it.
    stage: Option<usize>,
    span: Span,
}

#[derive(Default)]
struct Build {
    stages: Vec<ir::Stage>,
    pending: Vec<Pending>,
}

impl Grounder<'_, '_> {
    pub(super) fn program(&mut self, program: &ast::Program, start: Cell) -> RouteIr {
        let mut b = Build::default();
        for item in &program.items {
            match item {
                Item::Let(l) => self.let_binding(l),
                Item::Route(r) => self.route_items(&r.items, &mut b),
                Item::Error(_) => {}
            }
        }
        let mut constraints = Vec::new();
        for p in b.pending {
            let stage_scope = match (&p.during, p.stage) {
                (_, Some(i)) => StageScope::Stages(vec![i]),
                (None, None) => StageScope::Global,
                (Some(names), None) => {
                    let mut idx = Vec::new();
                    for n in names {
                        let found: Vec<usize> = b
                            .stages
                            .iter()
                            .enumerate()
                            .filter(|(_, s)| s.name == n.name)
                            .map(|(i, _)| i)
                            .collect();
                        if found.is_empty() {
                            self.problems.push(
                                Problem::warning(
                                    codes::UNKNOWN_STAGE,
                                    n.span,
                                    format!("no stage `{}` on this map", n.name),
                                )
                                .note("a `for` loop over an empty set produced none of its stages"),
                            );
                        }
                        idx.extend(found);
                    }
                    idx.sort_unstable();
                    idx.dedup();
                    if idx.is_empty() {
                        continue;
                    }
                    StageScope::Stages(idx)
                }
            };
            constraints.push(Constraint {
                id: format!("c{}", constraints.len()),
                kind: p.kind,
                stage_scope,
                spatial_scope: p.within,
                span: SourceSpan::new(self.source, p.span),
            });
        }
        let map = self.q.map();
        RouteIr {
            version: ROUTE_IR_VERSION,
            map_id: map.map_id.clone(),
            grid_size: map.n(),
            resolution_m: self.q.res(),
            start,
            stages: b.stages,
            constraints,
            route_bindings: std::mem::take(&mut self.bindings),
        }
    }

    fn let_binding(&mut self, l: &ast::Let) {
        let v = self.eval(&l.value);
        self.scopes.push((l.name.name.clone(), v));
    }

    fn route_items(&mut self, items: &[RouteItem], b: &mut Build) {
        let depth = self.scopes.len();
        for item in items {
            match item {
                RouteItem::Let(l) => self.let_binding(l),
                RouteItem::Stage(s) => self.stage(s, b),
                RouteItem::Constraint(c) => self.constraint(c, None, b),
                RouteItem::For(f) => match self.eval(&f.iter) {
                    Value::Set(elems) => {
                        for el in elems {
                            self.scopes.push((f.var.name.clone(), Value::Place(el)));
                            self.route_items(&f.body, b);
                            self.scopes.pop();
                        }
                    }
                    Value::Unknown => {}
                    _ => {
                        self.unsupported(&f.iter);
                    }
                },
                RouteItem::Error(_) => {}
                // Grounded through its atoms: `ltl::program` turns the form into stages first.
                RouteItem::Ltl(_) => {}
            }
        }
        self.scopes.truncate(depth);
    }

    fn stage(&mut self, s: &ast::Stage, b: &mut Build) {
        let index = b.stages.len();
        let goal = match self.eval(&s.target) {
            Value::Place(p) => self.set_goal("go", s.target.span, vec![p], index, None),
            Value::Set(ps) => self.set_goal("go", s.target.span, ps, index, None),
            Value::Unknown => None,
            _ => {
                self.unsupported(&s.target);
                None
            }
        };
        let name = s
            .name
            .as_ref()
            .map_or(format!("stage{}", index + 1), |n| n.name.clone());
        let (target, ir_target) = match goal {
            Some(g) => (Some(g.value), g.ir),
            None => (
                None,
                Place {
                    kind: PlaceKind::Region {
                        construction: Construction {
                            kind: "unresolved".into(),
                            from: vec![],
                            radius_m: None,
                        },
                    },
                    label: "unresolved".into(),
                    cells: CellSet::default(),
                },
            ),
        };
        b.stages.push(ir::Stage {
            name,
            target: ir_target,
            passes: vec![],
            span: SourceSpan::new(self.source, s.span),
        });
        let depth = self.scopes.len();
        let outer_target = self
            .stage_target
            .replace(target.clone().unwrap_or(PlaceVal::Room(0)));
        for item in &s.body {
            match item {
                StageItem::Let(l) => self.let_binding(l),
                StageItem::Constraint(c) => self.constraint(c, Some(index), b),
                StageItem::Error(_) => {}
            }
        }
        self.stage_target = outer_target;
        self.scopes.truncate(depth);
        if let Some(t) = target {
            self.reached.push(t.clone());
            self.here = t;
        }
    }

    fn constraint(&mut self, c: &ast::Constraint, stage: Option<usize>, b: &mut Build) {
        let value = self.eval(&c.value);
        let mut within: Option<Place> = None;
        let mut during = None;
        for s in &c.scopes {
            match s {
                Scope::Within { place, .. } => match self.eval(place).places() {
                    Some(ps) if !ps.is_empty() => within = Some(self.union_place(&ps)),
                    Some(_) => {
                        self.problems.push(Problem::error(
                            codes::EMPTY_REFERENCE,
                            place.span,
                            "this scope matches nothing on this map",
                        ));
                        return;
                    }
                    None => return,
                },
                Scope::During { stages, .. } => during = Some(stages.clone()),
            }
        }
        let kind = match (c.kind, value) {
            (_, Value::Unknown) => return,
            (Kind::Pass, v) => {
                let Some(places) = v.places() else { return };
                match stage.and_then(|i| b.stages.get_mut(i).map(|_| i)) {
                    Some(i) => {
                        let at = b.stages[i].passes.len();
                        let Some(goal) = self.set_goal("pass", c.value.span, places, i, Some(at))
                        else {
                            return;
                        };
                        b.stages[i].passes.push(Pass {
                            place: goal.ir,
                            span: SourceSpan::new(self.source, c.span),
                        });
                    }
                    None => {
                        self.problems.push(
                            Problem::error(
                                codes::UNSUPPORTED,
                                c.span,
                                "`pass` outside a stage has no order to be passed in",
                            )
                            .help("put `pass` inside the stage it belongs to"),
                        );
                    }
                }
                return;
            }
            (Kind::Avoid, v) => {
                let Some(places) = v.places() else { return };
                if places.is_empty() {
                    self.problems.push(Problem::warning(
                        codes::EMPTY_CONSTRAINT,
                        c.value.span,
                        "`avoid` matches nothing on this map; the constraint is dropped",
                    ));
                    return;
                }
                ConstraintKind::Avoid {
                    place: self.union_place(&places),
                }
            }
            // "Stay close to all the dressers": one near term per member, same scopes.
            (Kind::Prefer, Value::Pref(Pref::NearEach(xs))) => {
                if xs.is_empty() {
                    self.problems.push(Problem::warning(
                        codes::EMPTY_CONSTRAINT,
                        c.value.span,
                        "`near_each` refers to nothing on this map; the preference is dropped",
                    ));
                }
                for x in &xs {
                    b.pending.push(Pending {
                        kind: ConstraintKind::Near {
                            reference: self.ir_place(x),
                        },
                        within: within.clone(),
                        during: during.clone(),
                        stage,
                        span: c.span,
                    });
                }
                return;
            }
            (Kind::Prefer, Value::Pref(p)) => match self.preference(c, p, stage) {
                Some(k) => k,
                None => return,
            },
            (Kind::Prefer, _) => {
                self.unsupported(&c.value);
                return;
            }
        };
        b.pending.push(Pending {
            kind,
            within,
            during,
            stage,
            span: c.span,
        });
    }

    fn preference(
        &mut self,
        c: &ast::Constraint,
        p: Pref,
        _stage: Option<usize>,
    ) -> Option<ConstraintKind> {
        let empty = |g: &mut Self, what: &str| {
            g.problems.push(Problem::warning(
                codes::EMPTY_CONSTRAINT,
                c.value.span,
                format!("`{what}` refers to nothing on this map; the preference is dropped"),
            ));
            None
        };
        // Where the loop starts from: the free cell of the stage start nearest its centre.
        let centre = self.here.center(self.q).unwrap_or([0.0, 0.0]);
        let from = self
            .q
            .band(self.here.target(self.q))
            .into_iter()
            .min_by(|a, b| {
                let d = |c: &Cell| (c.row as f64 - centre[0]).hypot(c.col as f64 - centre[1]);
                d(a).total_cmp(&d(b)).then(a.cmp(b))
            });
        let patrol = matches!(p, Pref::Patrol(..));
        Some(match p {
            Pref::Near(xs) if xs.is_empty() => return empty(self, "near"),
            Pref::NearEach(_) => return None,
            Pref::Far(xs) if xs.is_empty() => return empty(self, "far"),
            Pref::Near(xs) => ConstraintKind::Near {
                reference: self.union_place(&xs),
            },
            Pref::Far(xs) => ConstraintKind::Far {
                reference: self.union_place(&xs),
            },
            Pref::Closer(a, b) if a.is_empty() || b.is_empty() => return empty(self, "closer"),
            Pref::Closer(a, b) => ConstraintKind::Relative {
                closer: self.union_place(&a),
                farther: self.union_place(&b),
            },
            Pref::Clearance(d) => ConstraintKind::Clearance { distance_m: d },
            Pref::Circle(x, dir) => {
                let room = x.room_of(self.q);
                let ask = LoopAsk {
                    name: "circle",
                    shape: WaypointShape::Circle,
                    around: &x,
                    room,
                    from,
                    direction: dir,
                    until: None,
                    passing: None,
                    avoiding: None,
                    end: None,
                };
                let (dir, wps) = self.loop_shape(&c.value, ask);
                self.shape(c, Shape::Circle, dir, &x, wps)?
            }
            Pref::Through(xs) => self.through(c, &xs)?,
            Pref::FollowWall(w) | Pref::Patrol(w) => {
                let x = PlaceVal::Room(w.room);
                // A patrol ends at the doorway used to leave the room.
                let end = if patrol {
                    let door = self.route_leaving_doorway(w.room);
                    if door.is_some() {
                        let rl = x.label(self.q);
                        self.bind(&c.value, "patrol", format!("doorway leaving {rl}"));
                    }
                    door
                } else {
                    None
                };
                let ask = LoopAsk {
                    name: if patrol { "patrol" } else { "follow_wall" },
                    shape: WaypointShape::Walls,
                    around: &x,
                    room: Some(w.room),
                    from,
                    direction: w.direction,
                    until: w.until.as_ref(),
                    passing: w.passing.as_ref(),
                    avoiding: w.avoiding.as_ref(),
                    end,
                };
                let (dir, wps) = self.loop_shape(&c.value, ask);
                self.shape(
                    c,
                    if patrol {
                        Shape::Patrol
                    } else {
                        Shape::FollowWall
                    },
                    dir,
                    &x,
                    wps,
                )?
            }
        })
    }

    fn route_leaving_doorway(&mut self, room: u32) -> Option<Vec<Cell>> {
        if let Some(r) = self.route
            && let Some(d) = self.q.doorway_leaving(r, room)
        {
            return Some(d);
        }
        // Before planning (or when the route stays): the doorway nearest the stage's destination.
        let t = self.stage_target.clone()?;
        let doors: Vec<Vec<Cell>> = self
            .q
            .doorways(room)
            .into_iter()
            .map(|p| p.cells.clone())
            .collect();
        doors.into_iter().min_by(|a, b| {
            let da = self
                .q
                .distance(Target::Cells(a), t.target(self.q))
                .unwrap_or(f64::INFINITY);
            let db = self
                .q
                .distance(Target::Cells(b), t.target(self.q))
                .unwrap_or(f64::INFINITY);
            da.total_cmp(&db)
        })
    }

    fn shape(
        &mut self,
        c: &ast::Constraint,
        shape: Shape,
        direction: Direction,
        around: &PlaceVal,
        wps: Vec<Vec<Cell>>,
    ) -> Option<ConstraintKind> {
        let wps: Vec<Vec<Cell>> = wps.into_iter().filter(|w| !w.is_empty()).collect();
        if wps.len() < 2 {
            let l = around.label(self.q);
            self.problems.push(Problem::error(
                codes::EMPTY_PLACE,
                c.value.span,
                format!("no room to move around {l}: fewer than two free waypoints"),
            ));
            return None;
        }
        let al = around.label(self.q);
        let waypoints = wps
            .into_iter()
            .enumerate()
            .map(|(i, cells)| Place {
                kind: PlaceKind::Region {
                    construction: Construction {
                        kind: "waypoint".into(),
                        from: vec![al.clone()],
                        radius_m: Some(0.25),
                    },
                },
                label: format!("waypoint {} around {al}", i + 1),
                cells: CellSet::new(cells),
            })
            .collect();
        Some(ConstraintKind::PathShape {
            shape,
            direction: Some(direction),
            around: self.ir_place(around),
            waypoints,
        })
    }

    pub(super) fn ir_place(&self, p: &PlaceVal) -> Place {
        ir_place(self.q, p)
    }

    /// One place for a non-empty list: itself when single, else a union region.
    pub(super) fn union_place(&self, ps: &[PlaceVal]) -> Place {
        union_place(self.q, ps)
    }
}

/// A place of the RouteIR as the compiler writes it (public so that a grounding that does not
/// go through `.m2r`, such as Direct ID's catalog ids, writes the very same places).
pub fn ir_place(q: &MapQuery, p: &PlaceVal) -> Place {
    let kind = match p {
        PlaceVal::Object(id) => {
            let o = q.map().object(*id);
            PlaceKind::Object {
                id: *id,
                category: o.map_or(String::new(), |o| o.category.clone()),
                room: o.and_then(|o| o.room),
            }
        }
        PlaceVal::Room(id) => PlaceKind::Room {
            id: *id,
            category: q
                .map()
                .room(*id)
                .map_or(String::new(), |r| r.category.clone()),
        },
        PlaceVal::Region(r) => PlaceKind::Region {
            construction: r.construction.clone(),
        },
    };
    Place {
        kind,
        label: p.label(q),
        cells: CellSet::new(q.cells(p.target(q)).to_vec()),
    }
}

/// One place for a non-empty list: itself when single, else a union region (the rule for a set).
pub fn union_place(q: &MapQuery, ps: &[PlaceVal]) -> Place {
    if ps.len() == 1 {
        return ir_place(q, &ps[0]);
    }
    let labels: Vec<String> = ps.iter().map(|p| p.label(q)).collect();
    let mut cells = Vec::new();
    for p in ps {
        cells.extend_from_slice(q.cells(p.target(q)));
    }
    Place {
        kind: PlaceKind::Region {
            construction: Construction {
                kind: "union".into(),
                from: labels.clone(),
                radius_m: None,
            },
        },
        label: if labels.len() <= 3 {
            labels.join(" + ")
        } else {
            format!("{} + {} more", labels[0], labels.len() - 1)
        },
        cells: CellSet::new(cells),
    }
}
