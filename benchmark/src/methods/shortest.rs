//! The `shortest` baseline: the shortest legal route through the ground-truth targets, in order,
//! that never touches an active must-avoid. It reads only the annotation (no language, no
//! preferences), so it bounds what hard constraints alone buy: HCS = 1 on every feasible episode,
//! soft metrics left to chance.

use super::{Method, MethodError, Prediction, PreparedMap, start_cell};
use crate::episode::{CellRc, ConstraintKind, Episode, HardConstraint, Shape, SoftConstraint};
use crate::suite::paths::{Leg, PassMask, chain_legs};
use m2rc_stdlib::map::FREE;

pub struct Shortest;

impl Method for Shortest {
    fn name(&self) -> &str {
        "shortest"
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let map = &map.map;
        let start = start_cell(map, episode)?;
        let n = map.n();
        let free = PassMask::new(n, map.occupancy.data().iter().map(|&v| v == FREE).collect());
        let plan = TransitionPlan::new(episode, n);
        if plan.targets.is_empty() {
            return Err(MethodError(
                "the episode has fewer than two must-pass constraints".into(),
            ));
        }
        let mut legs_goal = Vec::new();
        let mut legs_forbidden = Vec::new();
        for k in 0..plan.targets.len() {
            let goal = plan.targets[k].clone();
            let mut forbidden = plan.active_avoid_cells(k);
            // Keep the next leg's avoids away from where this leg ends (the evaluator charges an
            // avoid whose exit coincides with the goal entry to the next leg).
            if k + 1 < plan.targets.len() {
                let near = dilate(n, &goal, 2);
                forbidden.extend(
                    plan.active_avoid_cells(k + 1)
                        .into_iter()
                        .filter(|&i| near[i]),
                );
            }
            legs_goal.push(goal);
            legs_forbidden.push(forbidden);
        }
        // Legs are chained greedily; when a leg is infeasible the route so far is returned.
        let mut route = vec![start];
        for k in 0..legs_goal.len() {
            let at = *route.last().expect("non-empty");
            let leg = [Leg {
                goal: &legs_goal[k],
                forbidden: &legs_forbidden[k],
            }];
            match chain_legs(&free, at, &leg) {
                Some((path, _)) => route.extend(path.into_iter().skip(1)),
                None => {
                    return Ok(Prediction {
                        trajectory: route,
                        program: None,
                        notes: vec![format!(
                            "target {} is unreachable without touching an active must-avoid",
                            k + 1
                        )],
                        ..Prediction::default()
                    });
                }
            }
        }
        Ok(Prediction {
            trajectory: route,
            program: None,
            notes: vec![],
            ..Prediction::default()
        })
    }
}

/// The ordered targets and the avoids active on each transition, as cell masks, following the
/// evaluator's rules (record region first and never scored; scoped avoids match (from, to) orders).
pub struct TransitionPlan {
    /// Goal masks of targets 1..m (the record region excluded).
    pub targets: Vec<Vec<bool>>,
    /// For each target k: the cells of avoids active while heading to it.
    avoids: Vec<Vec<usize>>,
}

impl TransitionPlan {
    pub fn new(episode: &Episode, n: usize) -> Self {
        let mut passes: Vec<(f64, usize, &HardConstraint)> = episode
            .hard_constraints
            .iter()
            .enumerate()
            .filter(|(_, c)| c.kind == ConstraintKind::MustPass)
            .map(|(i, c)| (c.order.map(|o| o as f64).unwrap_or(i as f64 + 1.0), i, c))
            .collect();
        passes.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut targets = Vec::new();
        let mut avoids = Vec::new();
        for k in 1..passes.len() {
            let (to, _, target) = passes[k];
            let (from, _, _) = passes[k - 1];
            targets.push(inside_mask(&RegionView::of_hard(target), n));
            let mut cells = Vec::new();
            for c in episode
                .hard_constraints
                .iter()
                .filter(|c| c.kind == ConstraintKind::MustAvoid)
            {
                let active = match c.scope.as_ref().filter(|s| s.is_between()) {
                    None => true,
                    Some(s) => {
                        s.to_order.map(|o| o as f64) == Some(to)
                            && s.from_order.map(|o| o as f64) == Some(from)
                    }
                };
                if active {
                    cells.extend(touch_cells(&RegionView::of_hard(c), n));
                }
            }
            avoids.push(cells);
        }
        TransitionPlan { targets, avoids }
    }

    pub fn active_avoid_cells(&self, k: usize) -> Vec<usize> {
        self.avoids.get(k).cloned().unwrap_or_default()
    }
}

/// The region fields of a hard or soft constraint, with the reference's defaults for absent keys
/// (radius 6, width and height 12).
pub struct RegionView<'a> {
    pub shape: Option<Shape>,
    pub center: [f64; 2],
    pub radius: f64,
    pub width: f64,
    pub height: f64,
    pub cells: &'a [CellRc],
}

impl<'a> RegionView<'a> {
    pub fn of_hard(c: &'a HardConstraint) -> Self {
        RegionView {
            shape: Some(c.shape),
            center: c.center.unwrap_or([0.0, 0.0]),
            radius: c.radius.unwrap_or(6.0),
            width: c.width.unwrap_or(12.0),
            height: c.height.unwrap_or(12.0),
            cells: c.cells.as_deref().unwrap_or(&[]),
        }
    }

    pub fn of_soft(c: &'a SoftConstraint) -> Self {
        RegionView {
            shape: c.shape,
            center: c.center.unwrap_or([0.0, 0.0]),
            radius: c.radius.unwrap_or(6.0),
            width: c.width.unwrap_or(12.0),
            height: c.height.unwrap_or(12.0),
            cells: c.cells.as_deref().unwrap_or(&[]),
        }
    }

    fn shape(&self) -> Option<Shape> {
        self.shape
    }
    fn center(&self) -> [f64; 2] {
        self.center
    }
    fn radius(&self) -> f64 {
        self.radius
    }
    fn width(&self) -> f64 {
        self.width
    }
    fn height(&self) -> f64 {
        self.height
    }
    fn cells(&self) -> &[CellRc] {
        self.cells
    }
}

/// Cells whose centre lies inside the region (the evaluator's point test).
pub fn inside_mask(c: &RegionView<'_>, n: usize) -> Vec<bool> {
    let mut mask = vec![false; n * n];
    match c.shape().unwrap_or(Shape::Circle) {
        Shape::Freeform => {
            for cell in c.cells() {
                if cell[0] >= 0 && cell[1] >= 0 && (cell[0] as usize) < n && (cell[1] as usize) < n
                {
                    mask[cell[0] as usize * n + cell[1] as usize] = true;
                }
            }
        }
        shape => {
            let [cr, cc] = c.center();
            let (hr, hc) = match shape {
                Shape::Rectangle => (c.height() / 2.0, c.width() / 2.0),
                _ => (c.radius(), c.radius()),
            };
            for_box(n, cr, cc, hr, hc, |r, col| {
                let (dr, dc) = (r as f64 - cr, col as f64 - cc);
                let inside = match shape {
                    Shape::Rectangle => dr.abs() <= hr && dc.abs() <= hc,
                    _ => dr.hypot(dc) <= c.radius(),
                };
                if inside {
                    mask[r * n + col] = true;
                }
            });
        }
    }
    mask
}

/// Cells a move must not enter for the route to stay clear of the region: every cell whose unit
/// square meets it (conservative for circles and rectangles, exact for freeform cells).
pub fn touch_cells(c: &RegionView<'_>, n: usize) -> Vec<usize> {
    match c.shape().unwrap_or(Shape::Circle) {
        Shape::Freeform => c
            .cells()
            .iter()
            .filter(|cell| {
                cell[0] >= 0 && cell[1] >= 0 && (cell[0] as usize) < n && (cell[1] as usize) < n
            })
            .map(|cell| cell[0] as usize * n + cell[1] as usize)
            .collect(),
        shape => {
            let [cr, cc] = c.center();
            let (hr, hc) = match shape {
                Shape::Rectangle => (c.height() / 2.0 + 0.5, c.width() / 2.0 + 0.5),
                _ => (c.radius() + 0.5, c.radius() + 0.5),
            };
            let mut out = Vec::new();
            for_box(n, cr, cc, hr, hc, |r, col| {
                let meets = match shape {
                    Shape::Rectangle => true,
                    _ => {
                        // Distance from the circle centre to the cell's square.
                        let dr = ((r as f64 - cr).abs() - 0.5).max(0.0);
                        let dc = ((col as f64 - cc).abs() - 0.5).max(0.0);
                        dr.hypot(dc) <= c.radius() + 1e-6
                    }
                };
                if meets {
                    out.push(r * n + col);
                }
            });
            out
        }
    }
}

fn for_box(n: usize, cr: f64, cc: f64, hr: f64, hc: f64, mut f: impl FnMut(usize, usize)) {
    if !(cr.is_finite() && cc.is_finite() && hr.is_finite() && hc.is_finite()) || n == 0 {
        return;
    }
    let lo = |x: f64| (x.floor().max(0.0) as usize).min(n - 1);
    let (r0, r1) = (lo(cr - hr), lo(cr + hr + 1.0));
    let (c0, c1) = (lo(cc - hc), lo(cc + hc + 1.0));
    for r in r0..=r1 {
        for c in c0..=c1 {
            f(r, c);
        }
    }
}

fn dilate(n: usize, mask: &[bool], by: i64) -> Vec<bool> {
    let mut out = vec![false; n * n];
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        let (r, c) = ((i / n) as i64, (i % n) as i64);
        for dr in -by..=by {
            for dc in -by..=by {
                let (rr, cc) = (r + dr, c + dc);
                if rr >= 0 && cc >= 0 && (rr as usize) < n && (cc as usize) < n {
                    out[rr as usize * n + cc as usize] = true;
                }
            }
        }
    }
    out
}
