//! Path shapes (`circle`, `follow_wall`, `patrol`, `through`): their waypoints, how far round
//! they go, and which way round when the instruction does not say.
//!
//! A direction the writer left out is never guessed: both ways are built and the shorter one is
//! taken (for `follow_wall(..., passing: x)`, the way whose waypoints come nearest `x`; with
//! `avoiding: x`, the way whose waypoints keep farthest from it); the
//! choice is recorded as a route binding (`follow_wall` -> `clockwise (shorter: 7.9 m vs 9.4 m)`),
//! so the IR and `m2rc compile` say which was picked.

use super::value::PlaceVal;
use super::{Grounder, Problem, codes};
use crate::ir::{CellSet, ConstraintKind, Construction, Direction, Place, PlaceKind, Shape};
use m2rc_grammar::ast::{self, Expr};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::{MapQuery, Target, WaypointShape, loop_waypoints};

/// What a loop shape is asked to do.
pub(super) struct LoopAsk<'a> {
    pub name: &'static str,
    pub shape: WaypointShape,
    pub around: &'a PlaceVal,
    pub room: Option<u32>,
    pub from: Option<Cell>,
    pub direction: Option<Direction>,
    /// Stop at the waypoint nearest this place, then end on it (`until: doorway`).
    pub until: Option<&'a PlaceVal>,
    /// Choose the side whose waypoints pass nearest this place.
    pub passing: Option<&'a PlaceVal>,
    /// Choose the side whose waypoints keep farthest from this place (chosen by exclusion: "the
    /// side that does not pass by the dresser").
    pub avoiding: Option<&'a PlaceVal>,
    /// A final waypoint after the loop (the doorway a patrol leaves by).
    pub end: Option<Vec<Cell>>,
}

fn centre(w: &[Cell]) -> Option<[f64; 2]> {
    MapQuery::centroid(w)
}

impl Grounder<'_, '_> {
    /// The waypoints of the loop in the chosen direction, and that direction.
    pub(super) fn loop_shape(&mut self, e: &Expr, ask: LoopAsk) -> (Direction, Vec<Vec<Cell>>) {
        let dirs: Vec<Direction> = match ask.direction {
            Some(d) => vec![d],
            None => vec![Direction::Clockwise, Direction::Counterclockwise],
        };
        let mut options: Vec<(Direction, Vec<Vec<Cell>>, f64, f64)> = Vec::new();
        for d in dirs {
            let mut wps = loop_waypoints(
                self.q,
                ask.shape,
                ask.around.target(self.q),
                ask.room,
                d == Direction::Clockwise,
                ask.from,
            );
            if let Some(u) = ask.until {
                self.truncate_at(&mut wps, u);
            }
            if let Some(end) = &ask.end {
                wps.push(end.clone());
            }
            let len = self.polyline_m(ask.from, &wps);
            // One score, lower is better: the approach to `passing`, or minus the approach to
            // `avoiding`.
            let pass = match (ask.passing, ask.avoiding) {
                (Some(p), _) => self.nearest_approach_m(&wps, p),
                (None, Some(x)) => -self.nearest_approach_m(&wps, x),
                (None, None) => 0.0,
            };
            options.push((d, wps, len, pass));
        }
        if options.len() == 1 {
            let (d, w, _, _) = options.swap_remove(0);
            return (d, w);
        }
        // Passing side first, then length; exact ties keep counterclockwise, and say so.
        let (a, b) = (&options[0], &options[1]);
        let sided = ask.passing.is_some() || ask.avoiding.is_some();
        let first_wins = if sided && (a.3 - b.3).abs() > 1e-9 {
            a.3 < b.3
        } else {
            a.2 < b.2 - 1e-9
        };
        let (win, lose) = if first_wins { (0, 1) } else { (1, 0) };
        let differ = (options[0].3 - options[1].3).abs() > 1e-9;
        let reason = match (ask.passing, ask.avoiding) {
            (Some(p), _) if differ => format!(
                "the side passing {} ({:.1} m from it vs {:.1} m)",
                p.label(self.q),
                options[win].3,
                options[lose].3
            ),
            (None, Some(x)) if differ => format!(
                "the side avoiding {} ({:.1} m from it vs {:.1} m)",
                x.label(self.q),
                -options[win].3,
                -options[lose].3
            ),
            _ if (options[0].2 - options[1].2).abs() <= 1e-9 => {
                "both ways are equally long".to_string()
            }
            _ => format!(
                "shorter: {:.1} m vs {:.1} m",
                options[win].2, options[lose].2
            ),
        };
        let (d, w, _, _) = options.swap_remove(win);
        self.bind(e, ask.name, format!("{} ({reason})", d.word()));
        (d, w)
    }

    /// Cuts a loop after the waypoint nearest `until` (never the first) and ends it on `until`'s
    /// free cells.
    fn truncate_at(&self, wps: &mut Vec<Vec<Cell>>, until: &PlaceVal) {
        let q = self.q;
        let best = (1..wps.len())
            .filter_map(|i| {
                q.distance(Target::Cells(&wps[i]), until.target(q))
                    .map(|d| (d, i))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        if let Some((_, i)) = best {
            wps.truncate(i + 1);
        }
        let free: Vec<Cell> = q
            .band(until.target(q))
            .into_iter()
            .filter(|&c| q.is_traversable(c))
            .collect();
        if !free.is_empty() {
            wps.push(free);
        }
    }

    /// Length in metres of the polyline from `from` through the waypoint centres.
    fn polyline_m(&self, from: Option<Cell>, wps: &[Vec<Cell>]) -> f64 {
        let mut pts: Vec<[f64; 2]> = from
            .map(|c| [c.row as f64, c.col as f64])
            .into_iter()
            .collect();
        pts.extend(wps.iter().filter_map(|w| centre(w)));
        pts.windows(2)
            .map(|w| (w[0][0] - w[1][0]).hypot(w[0][1] - w[1][1]))
            .sum::<f64>()
            * self.q.res()
    }

    /// How close the loop's waypoints come to `p`, in metres.
    fn nearest_approach_m(&self, wps: &[Vec<Cell>], p: &PlaceVal) -> f64 {
        wps.iter()
            .filter_map(|w| self.q.distance(Target::Cells(w), p.target(self.q)))
            .fold(f64::INFINITY, f64::min)
    }
}

impl Direction {
    pub fn word(self) -> &'static str {
        match self {
            Direction::Clockwise => "clockwise",
            Direction::Counterclockwise => "counterclockwise",
        }
    }
}

/// How close `through` passes an object or a region (the reach of "pass by").
pub const THROUGH_REACH_M: f64 = 0.5;

impl Grounder<'_, '_> {
    /// `through(a, b, ...)`: one waypoint per place, in the writer's order. An object or a region
    /// is passed within [`THROUGH_REACH_M`] of it, a room by entering its floor; only free floor
    /// counts, since a waypoint nobody can stand on could never be passed.
    pub(super) fn through(
        &mut self,
        c: &ast::Constraint,
        places: &[PlaceVal],
    ) -> Option<ConstraintKind> {
        let q = self.q;
        let mut waypoints = Vec::with_capacity(places.len());
        for (i, p) in places.iter().enumerate() {
            let t = p.target(q);
            let mut cells: Vec<Cell> = match p {
                PlaceVal::Room(_) => q.cells(t).to_vec(),
                _ => q.area_near(t, THROUGH_REACH_M),
            };
            cells.retain(|&x| q.is_traversable(x));
            let label = p.label(q);
            if cells.is_empty() {
                self.problems.push(Problem::error(
                    codes::EMPTY_PLACE,
                    c.value.span,
                    match p {
                        PlaceVal::Room(_) => format!("{label} has no free floor to pass through"),
                        _ => format!(
                            "no free floor within {THROUGH_REACH_M} m of {label} to pass by"
                        ),
                    },
                ));
                return None;
            }
            waypoints.push(Place {
                kind: PlaceKind::Region {
                    construction: Construction {
                        kind: "waypoint".into(),
                        from: vec![label.clone()],
                        radius_m: (!matches!(p, PlaceVal::Room(_))).then_some(THROUGH_REACH_M),
                    },
                },
                label: format!("waypoint {}: by {label}", i + 1),
                cells: CellSet::new(cells),
            });
        }
        Some(ConstraintKind::PathShape {
            shape: Shape::Through,
            direction: None,
            around: self.union_place(places),
            waypoints,
        })
    }
}
