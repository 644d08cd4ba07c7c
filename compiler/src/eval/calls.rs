//! The built-ins: queries, filters, predicates, measures, rankings, places and preferences.

use super::codes;
use super::value::{Lambda, PlaceVal, Pref, Region, Value};
use super::{Grounder, Problem};
use crate::ir::{BoundAgainst, Construction, Direction, RouteBinding, SourceSpan};
use m2rc_grammar::ast::{Arg, Expr, ExprKind};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{Target, nominal_path};
use std::rc::Rc;

fn region(
    cells: Vec<Cell>,
    kind: &str,
    from: Vec<String>,
    radius_m: Option<f64>,
    label: String,
) -> PlaceVal {
    PlaceVal::Region(Rc::new(Region {
        cells,
        construction: Construction {
            kind: kind.into(),
            from,
            radius_m,
        },
        label,
    }))
}

impl Grounder<'_, '_> {
    pub(super) fn call(
        &mut self,
        e: &Expr,
        name: &str,
        recv: Option<Value>,
        args: &[Arg],
    ) -> Value {
        let Some((row, vals)) = self.bind_args(name, recv.as_ref(), args) else {
            return self.unsupported(e);
        };
        if vals.iter().any(|v| matches!(v, Some(Value::Unknown))) {
            return Value::Unknown;
        }
        let arg = |i: usize| vals.get(i).cloned().flatten();
        let arg_span = |i: usize| args.get(i).map_or(e.span, |a| a.value.span);
        let recv_span = match &e.kind {
            ExprKind::Method { receiver, .. } => receiver.span,
            _ => e.span,
        };
        let _ = row;
        match (name, recv) {
            // --- queries ---------------------------------------------------------------------
            ("objects", None) => {
                let cats = match arg(0) {
                    Some(Value::Category(c)) => Some(c),
                    _ => None,
                };
                Value::Set(
                    self.q
                        .map()
                        .objects
                        .iter()
                        .filter(|o| cats.as_ref().is_none_or(|c| c.contains(&o.category)))
                        .map(|o| PlaceVal::Object(o.id))
                        .collect(),
                )
            }
            ("rooms", None) => {
                let cats = match arg(0) {
                    Some(Value::Category(c)) => Some(c),
                    _ => None,
                };
                Value::Set(
                    self.q
                        .map()
                        .rooms
                        .iter()
                        .filter(|r| cats.as_ref().is_none_or(|c| c.contains(&r.category)))
                        .map(|r| PlaceVal::Room(r.id))
                        .collect(),
                )
            }
            // --- set filters and single-place predicates ---------------------------------------
            (
                "in" | "near" | "on" | "inside" | "under" | "next_to" | "between" | "holding"
                | "containing" | "contains" | "adjacent_to",
                Some(r),
            ) => {
                let (single, items) = match r {
                    Value::Place(p) => (true, vec![p]),
                    Value::Set(s) => (false, s),
                    _ => return self.unsupported(e),
                };
                let xs = arg(0).and_then(|v| v.places()).unwrap_or_default();
                let ys = arg(1).and_then(|v| v.places()).unwrap_or_default();
                let within = arg(1)
                    .and_then(|v| v.number())
                    .unwrap_or(self.q.thresholds.near_m);
                let corridors: Vec<Vec<Cell>> = if name == "between" {
                    let mut v = Vec::new();
                    for a in &xs {
                        for b in &ys {
                            if !a.same(b) {
                                v.push(self.q.hull_between(a.target(self.q), b.target(self.q)));
                            }
                        }
                    }
                    v
                } else {
                    Vec::new()
                };
                let keep: Vec<PlaceVal> = items
                    .into_iter()
                    .filter(|p| self.relation(name, p, &xs, within, &corridors, &ys))
                    .collect();
                if single {
                    Value::Bool(!keep.is_empty())
                } else {
                    Value::Set(keep)
                }
            }
            ("only_reachable_through", Some(Value::Place(PlaceVal::Room(r)))) => {
                let through: Vec<u32> = arg(0)
                    .and_then(|v| v.places())
                    .unwrap_or_default()
                    .iter()
                    .filter_map(|p| {
                        if let PlaceVal::Room(x) = p {
                            Some(*x)
                        } else {
                            None
                        }
                    })
                    .collect();
                Value::Bool(self.q.only_reachable_through(r, &through))
            }
            ("except", Some(Value::Set(s))) => {
                let xs = arg(0).and_then(|v| v.places()).unwrap_or_default();
                Value::Set(
                    s.into_iter()
                        .filter(|p| !xs.iter().any(|x| x.same(p)))
                        .collect(),
                )
            }
            ("where", Some(Value::Set(s))) => {
                let Some(Value::Lambda(f)) = arg(0) else {
                    return self.unsupported(e);
                };
                let mut out = Vec::new();
                for p in s {
                    match self.apply(&f, p.clone()) {
                        Value::Bool(true) => out.push(p),
                        Value::Bool(false) => {}
                        Value::Unknown => return Value::Unknown,
                        _ => return self.unsupported(e),
                    }
                }
                Value::Set(out)
            }
            ("sorted_by", Some(Value::Set(s))) => {
                let Some(Value::Lambda(f)) = arg(0) else {
                    return self.unsupported(e);
                };
                match self.keys(&f, &s) {
                    Some(mut keyed) => {
                        keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
                        Value::Set(keyed.into_iter().map(|(_, p)| p).collect())
                    }
                    None => Value::Unknown,
                }
            }
            ("exists", Some(Value::Set(s))) => Value::Bool(!s.is_empty()),
            ("is_empty", Some(Value::Set(s))) => Value::Bool(s.is_empty()),
            ("count", Some(Value::Set(s))) => Value::Int(s.len() as i64),
            // --- measures ------------------------------------------------------------------------
            ("distance", Some(Value::Place(a))) => {
                let Some(Value::Place(b)) = arg(0) else {
                    return self.unsupported(e);
                };
                let travel = matches!(arg(1), Some(Value::Travel(true)));
                match self.distance(&a, &b, travel) {
                    Some(d) => Value::Distance(d),
                    None => {
                        let (la, lb) = (a.label(self.q), b.label(self.q));
                        let p = if travel {
                            Problem::error(
                                codes::UNREACHABLE,
                                e.span,
                                format!("no traversable path between {la} and {lb}"),
                            )
                        } else {
                            Problem::error(
                                codes::EMPTY_PLACE,
                                e.span,
                                format!("{la} or {lb} covers no cell of the map"),
                            )
                        };
                        self.report(p)
                    }
                }
            }
            ("area", Some(Value::Place(PlaceVal::Room(r)))) => Value::Number(self.q.room_area(r)),
            ("room", Some(Value::Place(p))) => match p.room_of(self.q) {
                Some(r) => Value::Place(PlaceVal::Room(r)),
                None => {
                    let l = p.label(self.q);
                    self.report(Problem::error(
                        codes::NO_ROOM,
                        recv_span,
                        format!("{l} lies in no room"),
                    ))
                }
            },
            // --- rankings --------------------------------------------------------------------------
            ("nearest" | "farthest" | "kth_nearest" | "kth_farthest", Some(Value::Set(s))) => {
                let kth = name.starts_with("kth");
                let off = usize::from(kth);
                let Some(Value::Place(to)) = arg(off) else {
                    return self.unsupported(e);
                };
                let travel = matches!(arg(off + 1), Some(Value::Travel(true)));
                let k = if kth {
                    arg(0).and_then(|v| v.number()).unwrap_or(1.0) as i64
                } else {
                    1
                };
                self.rank_by_distance(e, recv_span, name, s, &to, travel, k, arg_span(0))
            }
            ("largest" | "smallest", Some(Value::Set(s))) => {
                let mut keyed: Vec<(f64, PlaceVal)> = s
                    .into_iter()
                    .map(|p| {
                        let a = match &p {
                            PlaceVal::Room(r) => self.q.room_area(*r),
                            other => self.q.cells(other.target(self.q)).len() as f64,
                        };
                        (a, p)
                    })
                    .collect();
                if name == "largest" {
                    keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
                } else {
                    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
                }
                self.first_ranked(e, recv_span, name, keyed)
            }
            ("max_by" | "min_by", Some(Value::Set(s))) => {
                let Some(Value::Lambda(f)) = arg(0) else {
                    return self.unsupported(e);
                };
                let Some(mut keyed) = self.keys(&f, &s) else {
                    return Value::Unknown;
                };
                if name == "max_by" {
                    keyed.sort_by(|a, b| b.0.total_cmp(&a.0));
                } else {
                    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
                }
                self.first_ranked(e, recv_span, name, keyed)
            }
            ("only", Some(Value::Set(s))) => self.only(e, recv_span, s),
            // --- places ------------------------------------------------------------------------------
            ("corners" | "doorways", Some(r)) => {
                let rooms: Vec<u32> = r
                    .places()
                    .unwrap_or_default()
                    .iter()
                    .filter_map(|p| {
                        if let PlaceVal::Room(x) = p {
                            Some(*x)
                        } else {
                            None
                        }
                    })
                    .collect();
                let mut out = Vec::new();
                for room in rooms {
                    let rl = PlaceVal::Room(room).label(self.q);
                    if name == "corners" {
                        for (i, c) in self.q.corners(room).into_iter().enumerate() {
                            out.push(region(
                                c,
                                "corner",
                                vec![rl.clone()],
                                Some(self.q.thresholds.corner_radius_m),
                                format!("corner {} of {rl}", i + 1),
                            ));
                        }
                    } else {
                        let doors: Vec<(u32, Vec<Cell>)> = self
                            .q
                            .doorways(room)
                            .into_iter()
                            .map(|p| {
                                (
                                    if p.rooms.0 == room {
                                        p.rooms.1
                                    } else {
                                        p.rooms.0
                                    },
                                    p.cells.clone(),
                                )
                            })
                            .collect();
                        for (other, cells) in doors {
                            out.push(self.doorway_region(room, other, cells));
                        }
                    }
                }
                Value::Set(out)
            }
            ("adjacent", Some(Value::Place(PlaceVal::Room(r)))) => Value::Set(
                self.q
                    .adjacent_rooms(r)
                    .into_iter()
                    .map(PlaceVal::Room)
                    .collect(),
            ),
            ("doorways_between", None) => match (arg(0), arg(1)) {
                (Some(Value::Place(PlaceVal::Room(a))), Some(Value::Place(PlaceVal::Room(b)))) => {
                    let doors: Vec<Vec<Cell>> = self
                        .q
                        .doorways_between(a, b)
                        .into_iter()
                        .map(|p| p.cells.clone())
                        .collect();
                    Value::Set(
                        doors
                            .into_iter()
                            .map(|c| self.doorway_region(a, b, c))
                            .collect(),
                    )
                }
                _ => self.unsupported(e),
            },
            ("area_between", None) => {
                let xs = arg(0).and_then(|v| v.places()).unwrap_or_default();
                let ys = arg(1).and_then(|v| v.places()).unwrap_or_default();
                // With sets, the nearest pair.
                let mut best: Option<(f64, PlaceVal, PlaceVal)> = None;
                for a in &xs {
                    for b in &ys {
                        if let Some(d) = self.q.distance(a.target(self.q), b.target(self.q))
                            && best.as_ref().is_none_or(|x| d < x.0)
                        {
                            best = Some((d, a.clone(), b.clone()));
                        }
                    }
                }
                let Some((_, a, b)) = best else {
                    return self.report(Problem::error(
                        codes::EMPTY_PLACE,
                        e.span,
                        "`area_between` needs a place on each side, and one side matched nothing on this map",
                    ));
                };
                let cells = self.q.corridor(a.target(self.q), b.target(self.q));
                let (la, lb) = (a.label(self.q), b.label(self.q));
                self.nonempty_region(
                    e,
                    cells,
                    "area_between",
                    vec![la.clone(), lb.clone()],
                    None,
                    format!("area between {la} and {lb}"),
                )
            }
            ("area_near", None) => {
                let Some(Value::Place(x)) = arg(0) else {
                    return self.unsupported(e);
                };
                let within = arg(1).and_then(|v| v.number()).unwrap_or(0.5);
                let cells = self.q.area_near(x.target(self.q), within);
                let l = x.label(self.q);
                self.nonempty_region(
                    e,
                    cells,
                    "area_near",
                    vec![l.clone()],
                    Some(within),
                    format!("area within {within} m of {l}"),
                )
            }
            ("center", None) => {
                let xs = arg(0).and_then(|v| v.places()).unwrap_or_default();
                let centers: Vec<[f64; 2]> = xs.iter().filter_map(|p| p.center(self.q)).collect();
                let labels: Vec<String> = xs.iter().map(|p| p.label(self.q)).collect();
                let label = format!(
                    "centre of {}",
                    if labels.len() == 1 {
                        labels[0].clone()
                    } else {
                        format!("{} places", labels.len())
                    }
                );
                let cells = self.q.center_of(&centers);
                self.nonempty_region(e, cells, "center", labels, Some(0.3), label)
            }
            // --- route-dependent places -------------------------------------------------------------
            ("room_before_entering" | "doorway_leaving" | "doorway_entering", None) => {
                let Some(Value::Place(PlaceVal::Room(room))) = arg(0) else {
                    return self.unsupported(e);
                };
                self.route_place(e, name, room)
            }
            ("first_entered", None) => {
                let rooms: Vec<u32> = arg(0)
                    .and_then(|v| v.places())
                    .unwrap_or_default()
                    .iter()
                    .filter_map(|p| {
                        if let PlaceVal::Room(x) = p {
                            Some(*x)
                        } else {
                            None
                        }
                    })
                    .collect();
                self.first_entered(e, &rooms)
            }
            // --- preferences ------------------------------------------------------------------------
            ("near" | "far", None) => {
                let xs = arg(0).and_then(|v| v.places()).unwrap_or_default();
                Value::Pref(if name == "near" {
                    Pref::Near(xs)
                } else {
                    Pref::Far(xs)
                })
            }
            ("closer", None) => {
                let a = arg(0).and_then(|v| v.places()).unwrap_or_default();
                let b = arg(1).and_then(|v| v.places()).unwrap_or_default();
                Value::Pref(Pref::Closer(a, b))
            }
            ("circle" | "follow_wall" | "patrol", None) => {
                let dir = match arg(1) {
                    Some(Value::Direction(d)) => d,
                    _ => Direction::Counterclockwise,
                };
                match (name, arg(0)) {
                    ("circle", Some(Value::Place(p))) => Value::Pref(Pref::Circle(p, dir)),
                    ("follow_wall", Some(Value::Place(PlaceVal::Room(r)))) => {
                        Value::Pref(Pref::FollowWall(r, dir))
                    }
                    ("patrol", Some(Value::Place(PlaceVal::Room(r)))) => {
                        Value::Pref(Pref::Patrol(r, dir))
                    }
                    _ => self.unsupported(e),
                }
            }
            ("clearance", None) => Value::Pref(Pref::Clearance(
                arg(0).and_then(|v| v.number()).unwrap_or(0.5),
            )),
            _ => self.unsupported(e),
        }
    }

    fn relation(
        &self,
        name: &str,
        p: &PlaceVal,
        xs: &[PlaceVal],
        within: f64,
        corridors: &[Vec<Cell>],
        ys: &[PlaceVal],
    ) -> bool {
        let q = self.q;
        let obj = |x: &PlaceVal| match x {
            PlaceVal::Object(id) => q.map().object(*id),
            _ => None,
        };
        let room_ids = || {
            xs.iter().filter_map(|x| {
                if let PlaceVal::Room(r) = x {
                    Some(*r)
                } else {
                    None
                }
            })
        };
        match name {
            "in" => p.room_of(q).is_some_and(|r| room_ids().any(|x| x == r)),
            "near" => xs
                .iter()
                .any(|x| !x.same(p) && q.near(p.target(q), x.target(q), within)),
            "containing" | "contains" => {
                let PlaceVal::Room(r) = p else { return false };
                xs.iter().any(|x| x.room_of(q) == Some(*r))
            }
            "adjacent_to" => {
                let PlaceVal::Room(r) = p else { return false };
                room_ids().any(|x| q.adjacent(*r, x))
            }
            "between" => {
                let Some(o) = obj(p) else { return false };
                if xs.iter().chain(ys).any(|x| x.same(p)) {
                    return false;
                }
                let c = Cell::new(
                    o.center[0].round().max(0.0) as u32,
                    o.center[1].round().max(0.0) as u32,
                );
                corridors.iter().any(|cor| cor.binary_search(&c).is_ok())
            }
            _ => {
                let Some(o) = obj(p) else { return false };
                xs.iter().filter_map(obj).any(|x| match name {
                    "on" => q.on(o, x),
                    "inside" => q.inside(o, x),
                    "under" => q.under(o, x),
                    "next_to" => q.next_to(o, x),
                    "holding" => q.on(x, o) || q.inside(x, o),
                    _ => false,
                })
            }
        }
    }

    /// Evaluates a ranking key per element; `None` (with the error already reported) on failure.
    fn keys(&mut self, f: &Lambda, s: &[PlaceVal]) -> Option<Vec<(f64, PlaceVal)>> {
        let mut out = Vec::with_capacity(s.len());
        for p in s {
            match self.apply(f, p.clone()).number() {
                Some(k) => out.push((k, p.clone())),
                None => return None,
            }
        }
        Some(out)
    }

    fn first_ranked(
        &mut self,
        e: &Expr,
        recv_span: m2rc_grammar::ast::Span,
        name: &str,
        keyed: Vec<(f64, PlaceVal)>,
    ) -> Value {
        match keyed.into_iter().next() {
            Some((_, p)) => Value::Place(p),
            None => self.report(
                Problem::error(
                    codes::EMPTY_RANKING,
                    e.span,
                    format!("`.{name}()` of an empty selection"),
                )
                .label(recv_span, "this selection has no element on this map"),
            ),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn rank_by_distance(
        &mut self,
        e: &Expr,
        recv_span: m2rc_grammar::ast::Span,
        name: &str,
        s: Vec<PlaceVal>,
        to: &PlaceVal,
        travel: bool,
        k: i64,
        k_span: m2rc_grammar::ast::Span,
    ) -> Value {
        if s.is_empty() {
            return self.first_ranked(e, recv_span, name, Vec::new());
        }
        let mut keyed: Vec<(f64, PlaceVal)> = s
            .into_iter()
            .map(|p| (self.distance(&p, to, travel).unwrap_or(f64::INFINITY), p))
            .collect();
        let far = name.contains("farthest");
        // Unreachable candidates rank last either way.
        keyed.sort_by(|a, b| match (a.0.is_finite(), b.0.is_finite(), far) {
            (true, false, _) => std::cmp::Ordering::Less,
            (false, true, _) => std::cmp::Ordering::Greater,
            (_, _, true) => b.0.total_cmp(&a.0),
            _ => a.0.total_cmp(&b.0),
        });
        let n = keyed.len() as i64;
        if k < 1 || k > n {
            return self.report(
                Problem::error(
                    codes::ORDINAL_OUT_OF_RANGE,
                    k_span,
                    format!("k = {k}, but the selection has {n} element(s)"),
                )
                .label(recv_span, format!("{n} candidate(s) on this map")),
            );
        }
        let (d, p) = keyed.swap_remove(k as usize - 1);
        if !d.is_finite() {
            let l = to.label(self.q);
            return self.report(Problem::error(
                codes::UNREACHABLE,
                e.span,
                format!("no candidate can be reached from {l} (travel distance undefined)"),
            ));
        }
        Value::Place(p)
    }

    fn only(&mut self, e: &Expr, recv_span: m2rc_grammar::ast::Span, s: Vec<PlaceVal>) -> Value {
        match s.len() {
            1 => Value::Place(s.into_iter().next().unwrap_or(PlaceVal::Room(0))),
            0 => {
                let mut p = Problem::error(
                    codes::EMPTY_SELECTION,
                    e.span,
                    "`.only()` found no candidate on this map",
                )
                .label(recv_span, "this selection is empty here");
                if let Some(note) = self.missing_category_note(recv_span) {
                    p = p.note(note);
                }
                self.report(p.help("check the category and filters, or guard the choice with `if s.exists() { ... } else { ... }`"))
            }
            n => {
                let notes: Vec<String> = s.iter().map(|p| self.describe(p)).collect();
                self.report(
                    Problem::error(codes::AMBIGUOUS_SELECTION, e.span, format!("`.only()` found {n} candidates on this map"))
                        .label(recv_span, format!("{n} candidates here"))
                        .notes(notes)
                        .help("pick one with a ranking (`.nearest()`, `.farthest()`, `.largest()`, `.min_by(...)`) or narrow it (`.in(room)`, `.near(x)`)"),
                )
            }
        }
    }

    /// "this map has no `toilet` at all", when the selection starts from a category the map lacks.
    fn missing_category_note(&self, span: m2rc_grammar::ast::Span) -> Option<String> {
        let text = self.source.get(span.start..span.end)?;
        let inner = text
            .split("objects(")
            .nth(1)
            .or_else(|| text.split("rooms(").nth(1))?;
        let cats: Vec<&str> = inner
            .split(')')
            .next()?
            .split('|')
            .map(str::trim)
            .filter(|c| !c.is_empty())
            .collect();
        let map = self.q.map();
        let missing: Vec<&str> = cats
            .into_iter()
            .filter(|c| {
                !map.objects.iter().any(|o| o.category == *c)
                    && !map.rooms.iter().any(|r| r.category == *c)
            })
            .collect();
        (!missing.is_empty()).then(|| format!("this map has no `{}` at all", missing.join("`, `")))
    }

    fn doorway_region(&self, a: u32, b: u32, cells: Vec<Cell>) -> PlaceVal {
        let (la, lb) = (
            PlaceVal::Room(a).label(self.q),
            PlaceVal::Room(b).label(self.q),
        );
        region(
            cells,
            "doorway",
            vec![la.clone(), lb.clone()],
            None,
            format!("doorway {la} / {lb}"),
        )
    }

    fn nonempty_region(
        &mut self,
        e: &Expr,
        cells: Vec<Cell>,
        kind: &str,
        from: Vec<String>,
        r: Option<f64>,
        label: String,
    ) -> Value {
        if cells.is_empty() {
            return self.report(Problem::error(
                codes::EMPTY_PLACE,
                e.span,
                format!("{label} covers no cell of the map"),
            ));
        }
        Value::Place(region(cells, kind, from, r, label))
    }

    pub(super) fn bind(&mut self, e: &Expr, function: &str, resolved: String) {
        let against = if self.route.is_some() {
            BoundAgainst::Planned
        } else {
            BoundAgainst::Nominal
        };
        self.bindings.push(RouteBinding {
            function: function.into(),
            resolved,
            against,
            span: SourceSpan::new(self.source, e.span),
        });
    }

    /// The path a route-dependent place is read from: the planned route, or the shortest path
    /// from the current stage's start into `room`.
    fn path_into(&mut self, room: u32) -> Option<Vec<Cell>> {
        if let Some(r) = self.route {
            return Some(r.to_vec());
        }
        let cells = self.q.room_cells(room).to_vec();
        nominal_path(self.q, self.here.target(self.q), &cells)
    }

    fn route_place(&mut self, e: &Expr, name: &str, room: u32) -> Value {
        let rl = PlaceVal::Room(room).label(self.q);
        let planned = self.route.is_some();
        let path = self.path_into(room).unwrap_or_default();
        let result: Option<PlaceVal> = match name {
            "room_before_entering" => self.q.room_before_entering(&path, room).map(PlaceVal::Room),
            "doorway_entering" => self
                .q
                .doorway_entering(&path, room)
                .map(|c| self.entering_region(&path, room, c)),
            _ => {
                if planned {
                    self.q
                        .doorway_leaving(&path, room)
                        .map(|c| self.leaving_region(&path, room, c))
                } else {
                    // Before planning: the doorway of the room nearest the stage's start.
                    let here = self.here.clone();
                    let doors: Vec<(u32, Vec<Cell>)> = self
                        .q
                        .doorways(room)
                        .into_iter()
                        .map(|p| {
                            (
                                if p.rooms.0 == room {
                                    p.rooms.1
                                } else {
                                    p.rooms.0
                                },
                                p.cells.clone(),
                            )
                        })
                        .collect();
                    let mut best: Option<(f64, u32, Vec<Cell>)> = None;
                    for (other, cells) in doors {
                        let d = self
                            .q
                            .distance(Target::Cells(&cells), here.target(self.q))
                            .unwrap_or(f64::INFINITY);
                        if best.as_ref().is_none_or(|b| d < b.0) {
                            best = Some((d, other, cells));
                        }
                    }
                    best.map(|(_, other, cells)| self.doorway_region(room, other, cells))
                }
            }
        };
        match result {
            Some(p) => {
                let l = p.label(self.q);
                self.bind(e, name, l);
                Value::Place(p)
            }
            None => {
                let why = match name {
                    "doorway_leaving" => format!("the route never leaves {rl}"),
                    _ if path.is_empty() => format!("{rl} cannot be reached"),
                    _ => format!(
                        "the route never enters {rl} from another room (it starts there, or the room has no doorway)"
                    ),
                };
                self.report(
                    Problem::error(
                        codes::ROUTE_PLACE_UNDEFINED,
                        e.span,
                        format!("`{name}` is undefined here: {why}"),
                    )
                    .note(format!(
                        "read off {}",
                        if planned {
                            "the planned route"
                        } else {
                            "the shortest path from the stage start"
                        }
                    )),
                )
            }
        }
    }

    fn entering_region(&self, path: &[Cell], room: u32, cells: Vec<Cell>) -> PlaceVal {
        let v = m2rc_stdlib::query::room_visits(self.q, path);
        let other = v
            .iter()
            .zip(v.iter().skip(1))
            .find(|(_, b)| b.room == room)
            .map_or(0, |(a, _)| a.room);
        self.doorway_region(other, room, cells)
    }

    fn leaving_region(&self, path: &[Cell], room: u32, cells: Vec<Cell>) -> PlaceVal {
        let v = m2rc_stdlib::query::room_visits(self.q, path);
        let other = v
            .iter()
            .zip(v.iter().skip(1))
            .find(|(a, _)| a.room == room)
            .map_or(0, |(_, b)| b.room);
        self.doorway_region(room, other, cells)
    }

    fn first_entered(&mut self, e: &Expr, rooms: &[u32]) -> Value {
        let found = if let Some(r) = self.route {
            self.q.first_entered(r, rooms)
        } else {
            // Before planning: the room of the set with the shortest travel from the stage start.
            let here = self.here.clone();
            let f = self.travel_from(&here);
            let mut best: Option<(f64, u32)> = None;
            for &r in rooms {
                let d = f.to(self.q.room_cells(r)).unwrap_or(f64::INFINITY);
                if d.is_finite() && best.is_none_or(|b| d < b.0) {
                    best = Some((d, r));
                }
            }
            best.map(|b| b.1)
        };
        match found {
            Some(r) => {
                let l = PlaceVal::Room(r).label(self.q);
                self.bind(e, "first_entered", l);
                Value::Place(PlaceVal::Room(r))
            }
            None => self.report(Problem::error(
                codes::ROUTE_PLACE_UNDEFINED,
                e.span,
                if rooms.is_empty() {
                    "`first_entered` of an empty set of rooms".to_string()
                } else {
                    "`first_entered` is undefined here: the route enters none of these rooms"
                        .to_string()
                },
            )),
        }
    }
}
