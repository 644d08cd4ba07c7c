//! Grounding: evaluates a checked `.m2r` program over a map and builds its [`RouteIr`].
//!
//! The evaluator runs after the checker has accepted the program, so it dispatches on the runtime
//! values and the built-in table (`m2rc_stdlib::builtins`) and never re-checks types. What can
//! still go wrong is a fact about the map (no such object here, two candidates where one was
//! meant, a route that never enters the room it should have entered before); each such failure is
//! recorded as a [`Problem`] with the span of the expression responsible and its evidence, and the
//! failing expression evaluates to [`Value::Unknown`], which silently propagates. So all runtime
//! errors of a program are reported at once, never only the first.
//!
//! Route-dependent places (`room_before_entering`, `doorway_leaving`, `doorway_entering`,
//! `first_entered`) are read off [`GroundOptions::route`] when a planned route is given, else off
//! the shortest traversable path; the pipeline re-grounds against each planned route until the
//! binding is stable. A set destination (`go S`) is grounded as all its members, and the member the
//! planned route reached is handed back the same way ([`GroundOptions::chosen`]).

mod any_of;
pub mod codes;
mod expr;
mod ground;
mod memo;
mod problem;
mod route;
mod shapes;
mod value;

pub use any_of::Chosen;
pub use problem::{Level, Problem};
pub use route::{ir_place, union_place};
pub use shapes::THROUGH_REACH_M;
pub use value::{PlaceVal, Pref, Region, Value, WallFollow, room_name};

use crate::check::{CheckResult, Resolution};
use crate::ir::{Construction, RouteBinding, RouteIr};
use m2rc_grammar::ast::{Program, Span};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, TravelField};
use std::collections::HashMap;
use std::rc::Rc;

/// What grounding needs besides the program and the map.
#[derive(Clone, Debug, Default)]
pub struct GroundOptions {
    /// Start cell; the map's own start when `None`.
    pub start: Option<Cell>,
    /// A planned route (from the start) to bind route-dependent places against.
    pub route: Option<Vec<Cell>>,
    /// The members of set destinations and passes (`go S`, `pass S`) that route reached.
    pub chosen: Vec<Chosen>,
}

/// The result of grounding: the IR when no error occurred, and every finding.
#[derive(Debug)]
pub struct Grounded {
    pub ir: Option<RouteIr>,
    pub problems: Vec<Problem>,
}

/// Grounds a program the checker accepted, using its canonical category names (`tv` is
/// `television`).
pub fn ground_checked(
    checked: &CheckResult,
    source: &str,
    q: &MapQuery,
    opts: &GroundOptions,
) -> Grounded {
    ground_with(
        &checked.program,
        Some(&checked.resolutions),
        source,
        q,
        opts,
    )
}

/// Grounds `program` (already accepted by the checker) over the map behind `q`, taking category
/// names as written.
pub fn ground(program: &Program, source: &str, q: &MapQuery, opts: &GroundOptions) -> Grounded {
    ground_with(program, None, source, q, opts)
}

fn ground_with(
    program: &Program,
    resolutions: Option<&HashMap<Span, Resolution>>,
    source: &str,
    q: &MapQuery,
    opts: &GroundOptions,
) -> Grounded {
    let (mut g, start) = match Grounder::start(q, resolutions, source, opts) {
        Ok(x) => x,
        Err(p) => {
            return Grounded {
                ir: None,
                problems: vec![*p],
            };
        }
    };
    let ir = g.program(program, start);
    let failed = g.problems.iter().any(Problem::is_error);
    Grounded {
        ir: if failed { None } else { Some(ir) },
        problems: g.problems,
    }
}

/// Evaluates only the top-level `let` bindings of a checked program, in order: each one's value
/// and every finding. A tool call (`crate::tools`) is answered this way, so a query means exactly
/// what the same expression means in a program.
pub fn evaluate_lets(
    checked: &CheckResult,
    source: &str,
    q: &MapQuery,
    opts: &GroundOptions,
) -> (Vec<(String, Value)>, Vec<Problem>) {
    let (mut g, _) = match Grounder::start(q, Some(&checked.resolutions), source, opts) {
        Ok(x) => x,
        Err(p) => return (Vec::new(), vec![*p]),
    };
    for item in &checked.program.items {
        if let m2rc_grammar::ast::Item::Let(l) = item {
            let v = g.eval(&l.value);
            g.scopes.push((l.name.name.clone(), v));
        }
    }
    (g.scopes, g.problems)
}

impl<'q, 'm> Grounder<'q, 'm> {
    /// A grounder at the start of a program, or why the start is unusable.
    fn start(
        q: &'q MapQuery<'m>,
        resolutions: Option<&'q HashMap<Span, Resolution>>,
        source: &'q str,
        opts: &'q GroundOptions,
    ) -> Result<(Self, Cell), Box<Problem>> {
        let Some(start) = resolve_start(q, opts.start) else {
            return Err(Box::new(Problem::error(
                codes::NO_START,
                Span::new(0, 0),
                match opts.start.or(q.map().start) {
                    Some(c) => format!(
                        "the start cell [{}, {}] is not traversable and no free cell is near it",
                        c.row, c.col
                    ),
                    None => format!("map `{}` has no start position", q.map().map_id),
                },
            )
            .help("give a start cell (`--start-cell row,col` or `--start x,y` in metres) on a free cell of the map")));
        };
        let start_place = PlaceVal::Region(Rc::new(Region {
            cells: vec![start],
            construction: Construction {
                kind: "start".into(),
                from: vec![],
                radius_m: None,
            },
            label: "start".into(),
        }));
        let g = Grounder {
            q,
            source,
            route: opts.route.as_deref(),
            chosen: &opts.chosen,
            problems: start_moved(q, opts.start, start).into_iter().collect(),
            scopes: Vec::new(),
            start: start_place.clone(),
            here: start_place,
            stage_target: None,
            bindings: Vec::new(),
            travel: Vec::new(),
            resolutions,
            memo: memo::Memo::default(),
            reached: Vec::new(),
        };
        Ok((g, start))
    }
}

/// The requested (or the map's) start, snapped to the nearest free cell within 4 m.
fn resolve_start(q: &MapQuery, start: Option<Cell>) -> Option<Cell> {
    let s = start.or(q.map().start)?;
    if q.is_traversable(s) {
        return Some(s);
    }
    let c = q.nearest_traversable([s.row as f64, s.col as f64], None)?;
    (c.dist(s) * q.res() <= 4.0).then_some(c)
}

/// A warning when the route will not start where it was asked to (a start on a wall or on
/// furniture is moved silently otherwise, and the route then seems to begin in the wrong place).
fn start_moved(q: &MapQuery, asked: Option<Cell>, used: Cell) -> Option<Problem> {
    let s = asked.or(q.map().start)?;
    (s != used).then(|| {
        Problem::warning(
            codes::START_MOVED,
            Span::new(0, 0),
            format!(
                "the start cell [{}, {}] is not traversable; the route starts at [{}, {}], {:.2} m away",
                s.row,
                s.col,
                used.row,
                used.col,
                s.dist(used) * q.res()
            ),
        )
        .help("give a start cell (`--start-cell row,col` or `--start x,y` in metres) on a free cell of the map")
    })
}

pub(crate) struct Grounder<'q, 'm> {
    q: &'q MapQuery<'m>,
    source: &'q str,
    route: Option<&'q [Cell]>,
    /// Members of set goals reached by the planned route (see `any_of.rs`).
    chosen: &'q [Chosen],
    problems: Vec<Problem>,
    /// Bindings in scope, innermost last.
    scopes: Vec<(String, Value)>,
    start: PlaceVal,
    /// Where the current stage starts.
    here: PlaceVal,
    /// The destination of the stage whose body is being evaluated.
    stage_target: Option<PlaceVal>,
    bindings: Vec<RouteBinding>,
    /// Travel fields already computed, by source place.
    travel: Vec<(PlaceVal, Rc<TravelField>)>,
    /// The checker's name resolutions, for canonical category names.
    resolutions: Option<&'q HashMap<Span, Resolution>>,
    /// Cached sub-expressions of lambda bodies (see `memo.rs` for the bound).
    memo: memo::Memo,
    /// Destinations of the stages evaluated so far, in route order (for `visited()`).
    reached: Vec<PlaceVal>,
}

impl Grounder<'_, '_> {
    fn report(&mut self, p: Problem) -> Value {
        self.problems.push(p);
        Value::Unknown
    }

    fn lookup(&self, name: &str) -> Option<&Value> {
        self.scopes
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v)
    }

    fn travel_from(&mut self, p: &PlaceVal) -> Rc<TravelField> {
        if let Some((_, f)) = self.travel.iter().find(|(k, _)| k.same(p)) {
            return f.clone();
        }
        let f = Rc::new(self.q.travel_field(p.target(self.q)));
        self.travel.push((p.clone(), f.clone()));
        f
    }

    /// Distance between two places in metres, straight or travel; `None` when undefined.
    fn distance(&mut self, a: &PlaceVal, b: &PlaceVal, travel: bool) -> Option<f64> {
        if travel {
            let f = self.travel_from(b);
            f.to(&self.q.band(a.target(self.q)))
        } else {
            self.q.distance(a.target(self.q), b.target(self.q))
        }
    }

    /// One line of evidence about a candidate: id, category, room, distance from here.
    fn describe(&mut self, p: &PlaceVal) -> String {
        let here = self.here.clone();
        let d = self
            .distance(p, &here, false)
            .map_or("unknown distance".to_string(), |d| {
                format!("{:.2} m", if d.abs() < 0.005 { 0.0 } else { d })
            });
        let what = match p {
            PlaceVal::Object(id) => match self.q.map().object(*id) {
                Some(o) => {
                    let room = o
                        .room
                        .and_then(|r| self.q.map().room(r))
                        .map_or("no room".to_string(), value::room_name);
                    format!("object {} `{}` in {room}", o.id, o.category)
                }
                None => format!("object {id}"),
            },
            PlaceVal::Room(id) => match self.q.map().room(*id) {
                Some(r) => format!(
                    "room `{}` ({}, {:.1} m²)",
                    value::room_name(r),
                    r.category,
                    self.q.room_area(r.id)
                ),
                None => format!("room {id}"),
            },
            PlaceVal::Region(r) => format!("region `{}`", r.label),
        };
        format!(
            "candidate: {what}, {d} from {}",
            if self.stage_target.is_some() {
                "the stage start"
            } else {
                "here"
            }
        )
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_relations;
#[cfg(test)]
mod tests_route_places;
