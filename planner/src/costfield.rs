//! The per-segment soft cost field Φ (method notes §4.4): the sum of the active soft terms, each
//! multiplied by its spatial-scope mask, plus the always-on clearance term. Φ is charged once per
//! entered cell, independent of step length, as in the reference.
//!
//! Distances are exact Euclidean distances in cells. Each term computes its distance transform only
//! on a window that holds its reference cells and every cell whose value can matter (the scope, or
//! the band within the clipping radius), which is exact and keeps a room-scoped term on a 700×700
//! map to a fraction of a full transform.
//!
//! Φ is written in the padded layout the searches read, and only on traversable cells: a search
//! looks Φ up only on cells it may enter, so the value anywhere else can never matter, and skipping
//! those cells skips most of the `exp` and square roots on a house where most of the grid is wall or
//! outside.

use crate::problem::{Area, CostProfile, RelativeMode, SoftKind, SoftTerm};
use m2rc_stdlib::field::{self, EdtScratch};
use m2rc_stdlib::grid::Cell;

/// Inclusive cell rectangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Rect {
    r0: i64,
    c0: i64,
    r1: i64,
    c1: i64,
}

impl Rect {
    fn full(n: usize) -> Self {
        Rect {
            r0: 0,
            c0: 0,
            r1: n as i64 - 1,
            c1: n as i64 - 1,
        }
    }

    fn of_cells(cells: &[Cell]) -> Option<Self> {
        let first = cells.first()?;
        let mut r = Rect {
            r0: first.row as i64,
            c0: first.col as i64,
            r1: first.row as i64,
            c1: first.col as i64,
        };
        for c in cells {
            r.r0 = r.r0.min(c.row as i64);
            r.r1 = r.r1.max(c.row as i64);
            r.c0 = r.c0.min(c.col as i64);
            r.c1 = r.c1.max(c.col as i64);
        }
        Some(r)
    }

    fn union(self, o: Rect) -> Rect {
        Rect {
            r0: self.r0.min(o.r0),
            c0: self.c0.min(o.c0),
            r1: self.r1.max(o.r1),
            c1: self.c1.max(o.c1),
        }
    }

    fn grow(self, by: i64, n: usize) -> Rect {
        Rect {
            r0: (self.r0 - by).max(0),
            c0: (self.c0 - by).max(0),
            r1: (self.r1 + by).min(n as i64 - 1),
            c1: (self.c1 + by).min(n as i64 - 1),
        }
    }
}

/// Reusable buffers of the windowed transforms.
#[derive(Debug, Default)]
pub struct FieldScratch {
    edt: EdtScratch,
    src: Vec<bool>,
    /// Recent transforms by (sources, hull): a route-level preference is active in every segment
    /// with the same reference and window, so its transform is computed once per plan.
    done: Vec<Transform>,
    /// Memory of forgotten transforms.
    spare: Vec<Vec<u32>>,
}

/// Most transforms kept by [`FieldScratch`] (each up to the map's size in `u32`).
const KEPT_TRANSFORMS: usize = 4;

#[derive(Debug)]
struct Transform {
    sources: Vec<Cell>,
    hull: Rect,
    side: usize,
    sq: Vec<u32>,
}

impl FieldScratch {
    /// The index in `done` of the transform of `sources` over the square hull of `window ∪
    /// sources`, computed unless already there. Indices of earlier calls stay valid until the next
    /// call that has to compute.
    fn transform(&mut self, sources: &[Cell], window: Rect) -> usize {
        let hull = Rect::of_cells(sources).map_or(window, |s| s.union(window));
        if let Some(i) = self
            .done
            .iter()
            .position(|t| t.hull == hull && t.sources == sources)
        {
            return i;
        }
        let side = ((hull.r1 - hull.r0).max(hull.c1 - hull.c0) + 1) as usize;
        self.src.clear();
        self.src.resize(side * side, false);
        for c in sources {
            self.src
                [(c.row as i64 - hull.r0) as usize * side + (c.col as i64 - hull.c0) as usize] =
                true;
        }
        let mut sq = if self.done.len() >= KEPT_TRANSFORMS {
            self.done.remove(0).sq
        } else {
            self.spare.pop().unwrap_or_default()
        };
        field::squared_distances_into(&self.src, side, &mut sq, &mut self.edt);
        self.done.push(Transform {
            sources: sources.to_vec(),
            hull,
            side,
            sq,
        });
        self.done.len() - 1
    }

    /// Drops the remembered transforms, keeping their memory: a new plan starts from nothing
    /// known but allocates nothing.
    pub fn forget(&mut self) {
        self.spare.extend(self.done.drain(..).map(|t| t.sq));
    }

    fn distance(&self, i: usize) -> WindowDistance<'_> {
        let t = &self.done[i];
        WindowDistance {
            origin: (t.hull.r0, t.hull.c0),
            side: t.side,
            sq: &t.sq,
        }
    }
}

/// Exact distances from some sources for the cells of a window, as a closure over map cells. The
/// transform runs on the square hull of the window and the sources; squared distances are kept and
/// the root taken only where a value is read (the same `f64` as a full distance field).
struct WindowDistance<'s> {
    origin: (i64, i64),
    side: usize,
    sq: &'s [u32],
}

impl WindowDistance<'_> {
    fn at(&self, r: i64, c: i64) -> f64 {
        let v = self.sq[(r - self.origin.0) as usize * self.side + (c - self.origin.1) as usize];
        if v == field::NO_SOURCE {
            f64::INFINITY
        } else {
            (v as f64).sqrt()
        }
    }
}

/// Source cells of an area, restricted to the grid.
fn sources(area: &Area, n: usize) -> Vec<Cell> {
    area.cells()
        .into_iter()
        .filter(|c| (c.row as usize) < n && (c.col as usize) < n)
        .collect()
}

/// The scope's mask and bounding rectangle, or `None` for "everywhere".
fn scope_of(scope: &Option<Area>, n: usize) -> Option<(Vec<bool>, Option<Rect>)> {
    scope.as_ref().map(|a| {
        let m = a.to_mask(n);
        let mut rect: Option<Rect> = None;
        for (r, row) in m.chunks_exact(n.max(1)).enumerate() {
            if let (Some(c0), Some(c1)) =
                (row.iter().position(|v| *v), row.iter().rposition(|v| *v))
            {
                let line = Rect {
                    r0: r as i64,
                    c0: c0 as i64,
                    r1: r as i64,
                    c1: c1 as i64,
                };
                rect = Some(rect.map_or(line, |b| b.union(line)));
            }
        }
        (m, rect)
    })
}

/// Adds `weight · value(d)` over the scope (or the whole map) to Φ, where `d` is the distance to
/// `reference`. `clip` is the distance beyond which `value` is constant (lets an unscoped term
/// transform only a band around the reference).
#[allow(clippy::too_many_arguments)]
fn add_distance_term(
    phi: &mut [f64],
    ctx: &FieldContext<'_>,
    scratch: &mut FieldScratch,
    reference: &Area,
    scope: &Option<Area>,
    weight: f64,
    clip: Option<f64>,
    value: impl Fn(f64) -> f64,
) {
    let n = ctx.n;
    let src = sources(reference, n);
    if src.is_empty() || weight == 0.0 {
        return;
    }
    let Some(src_rect) = Rect::of_cells(&src) else {
        return;
    };
    match scope_of(scope, n) {
        Some((_, None)) => {}
        Some((mask, Some(rect))) => {
            let i = scratch.transform(&src, rect);
            let wd = scratch.distance(i);
            for_traversable(ctx, rect, |r, c, i, pi| {
                if mask[i] {
                    phi[pi] += weight * value(wd.at(r, c));
                }
            });
        }
        None => {
            let window = match clip {
                Some(radius) => src_rect.grow(radius.ceil() as i64 + 1, n),
                None => Rect::full(n),
            };
            let i = scratch.transform(&src, window);
            let wd = scratch.distance(i);
            let outside = clip
                .map(|radius| weight * value(radius + 1.0))
                .unwrap_or(0.0);
            for_traversable(ctx, Rect::full(n), |r, c, _, pi| {
                if r >= window.r0 && r <= window.r1 && c >= window.c0 && c <= window.c1 {
                    phi[pi] += weight * value(wd.at(r, c));
                } else {
                    phi[pi] += outside;
                }
            });
        }
    }
}

/// A maximal horizontal run of traversable cells: its row and first and last column, inclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Run {
    pub row: u32,
    pub c0: u32,
    pub c1: u32,
}

/// The runs of a row-major `n`×`n` traversable mask, by row then column. A few thousand runs stand
/// for the hundred thousand free cells of a house, and walking them skips walls and the outside
/// without testing each cell.
pub fn traversable_runs(traversable: &[bool], n: usize) -> Vec<Run> {
    let mut runs = Vec::new();
    for (r, row) in traversable.chunks_exact(n.max(1)).enumerate() {
        let mut c = 0;
        while let Some(start) = row[c..].iter().position(|t| *t) {
            let c0 = c + start;
            let len = row[c0..].iter().position(|t| !*t).unwrap_or(n - c0);
            runs.push(Run {
                row: r as u32,
                c0: c0 as u32,
                c1: (c0 + len - 1) as u32,
            });
            c = c0 + len;
            if c >= n {
                break;
            }
        }
    }
    runs
}

/// Calls `f(row, col, row-major index, padded index)` on every traversable cell of `rect`.
fn for_traversable(ctx: &FieldContext<'_>, rect: Rect, mut f: impl FnMut(i64, i64, usize, usize)) {
    let n = ctx.n;
    let w = n + 2;
    let first = ctx.runs.partition_point(|run| (run.row as i64) < rect.r0);
    for run in &ctx.runs[first..] {
        let r = run.row as i64;
        if r > rect.r1 {
            break;
        }
        let (c0, c1) = ((run.c0 as i64).max(rect.c0), (run.c1 as i64).min(rect.c1));
        let (row, prow) = (r as usize * n, (r as usize + 1) * w + 1);
        for c in c0..=c1 {
            f(r, c, row + c as usize, prow + c as usize);
        }
    }
}

/// Per-map inputs shared by every segment's field.
pub struct FieldContext<'a> {
    pub n: usize,
    pub resolution: f64,
    pub profile: &'a CostProfile,
    /// Squared distance to the nearest clearance obstacle, in cells² (row-major; `u32::MAX` =
    /// none). Squared, because the clearance terms only need a square root within their radius.
    pub obstacle_sq: &'a [u32],
    /// The traversable cells, by runs ([`traversable_runs`]): Φ is only written on them.
    pub runs: &'a [Run],
}

/// The clearance penalty `λ · ((max(0, R − d)) / R)²` at obstacle distance `d`.
pub fn clearance_cost(d: f64, radius: f64, weight: f64) -> f64 {
    let x = (radius - d).max(0.0) / radius;
    weight * x * x
}

/// The always-on clearance field, row-major over every cell (zero when the profile turns it off).
pub fn clearance_field(ctx: &FieldContext<'_>) -> Vec<f64> {
    let p = ctx.profile;
    if !p.clearance || p.clearance_weight == 0.0 {
        return vec![0.0; ctx.n * ctx.n];
    }
    let radius = p.cells(p.clearance_radius_m, ctx.resolution);
    let r2 = radius * radius;
    ctx.obstacle_sq
        .iter()
        .map(|&sq| {
            if (sq as f64) < r2 {
                clearance_cost((sq as f64).sqrt(), radius, p.clearance_weight)
            } else {
                0.0
            }
        })
        .collect()
}

/// [`clearance_field`] written straight into the padded layout (zero on the border): the planner's
/// form, without a second full-grid array to copy from.
pub fn clearance_field_padded(ctx: &FieldContext<'_>, layout: &crate::layout::Layout) -> Vec<f64> {
    let mut out = vec![0.0; layout.len()];
    let p = ctx.profile;
    if !p.clearance || p.clearance_weight == 0.0 || ctx.n == 0 {
        return out;
    }
    let radius = p.cells(p.clearance_radius_m, ctx.resolution);
    let r2 = radius * radius;
    for (r, row) in ctx.obstacle_sq.chunks_exact(ctx.n).enumerate() {
        let start = (r + 1) * layout.w + 1;
        for (o, &sq) in out[start..start + ctx.n].iter_mut().zip(row) {
            if (sq as f64) < r2 {
                *o = clearance_cost((sq as f64).sqrt(), radius, p.clearance_weight);
            }
        }
    }
    out
}

/// Adds one soft term to Φ (padded layout of side `n + 2`), on traversable cells.
pub fn add_term(
    phi: &mut [f64],
    ctx: &FieldContext<'_>,
    scratch: &mut FieldScratch,
    term: &SoftTerm,
) {
    let p = ctx.profile;
    let n = ctx.n;
    let res = ctx.resolution;
    let scale = p.soft_scale;
    match &term.kind {
        SoftKind::Near { reference } => {
            let radius = p.cells(p.near_radius_m, res);
            let w = term.weight.unwrap_or(p.near_weight) * scale;
            add_distance_term(
                phi,
                ctx,
                scratch,
                reference,
                &term.scope,
                w,
                Some(radius),
                |d| (d / radius).clamp(0.0, 1.0),
            );
        }
        SoftKind::Far { reference } => {
            let sigma = p.cells(p.far_sigma_m, res);
            let w = term.weight.unwrap_or(p.far_weight) * scale;
            add_distance_term(phi, ctx, scratch, reference, &term.scope, w, None, |d| {
                (-d / sigma).exp()
            });
        }
        SoftKind::PathShape { waypoints } => {
            let radius = p.cells(p.path_shape_radius_m, res);
            let w = term.weight.unwrap_or(p.path_shape_weight) * scale;
            add_distance_term(
                phi,
                ctx,
                scratch,
                waypoints,
                &term.scope,
                w,
                Some(radius),
                |d| (d / radius).clamp(0.0, 1.0),
            );
        }
        SoftKind::Relative {
            closer,
            farther,
            mode,
        } => {
            let w = term.weight.unwrap_or(p.relative_weight) * scale;
            add_relative(phi, ctx, scratch, closer, farther, *mode, &term.scope, w);
        }
        SoftKind::Clearance { radius_m } => {
            let radius = p.cells(*radius_m, res);
            let w = term.weight.unwrap_or(p.clearance_weight) * scale;
            if w == 0.0 {
                return;
            }
            let mask = term.scope.as_ref().map(|a| a.to_mask(n));
            let r2 = radius * radius;
            let sq_of = ctx.obstacle_sq;
            for_traversable(ctx, Rect::full(n), |_, _, i, pi| {
                let sq = sq_of[i];
                if (sq as f64) < r2 && mask.as_ref().is_none_or(|m| m[i]) {
                    phi[pi] += clearance_cost((sq as f64).sqrt(), radius, w);
                }
            });
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn add_relative(
    phi: &mut [f64],
    ctx: &FieldContext<'_>,
    scratch: &mut FieldScratch,
    closer: &Area,
    farther: &Area,
    mode: RelativeMode,
    scope: &Option<Area>,
    weight: f64,
) {
    let n = ctx.n;
    let (a, b) = (sources(closer, n), sources(farther, n));
    if a.is_empty() || b.is_empty() || weight == 0.0 {
        return;
    }
    let scope = scope_of(scope, n);
    let window = match &scope {
        Some((_, None)) => return,
        Some((_, Some(r))) => *r,
        None => Rect::full(n),
    };
    // After a, b, the second round computes at most one of them and the last call finds its
    // transform, so both indices are valid together.
    scratch.transform(&a, window);
    scratch.transform(&b, window);
    let ia = scratch.transform(&a, window);
    let ib = scratch.transform(&b, window);
    let (da, db) = (scratch.distance(ia), scratch.distance(ib));
    let radius = ctx
        .profile
        .cells(ctx.profile.relative_radius_m, ctx.resolution);
    for_traversable(ctx, window, |r, c, i, pi| {
        if scope.as_ref().is_none_or(|(m, _)| m[i]) {
            phi[pi] += weight * relative_value(da.at(r, c), db.at(r, c), mode, radius);
        }
    });
}

/// The relative term's per-cell value before λ, from the distances to the place to be closer to
/// and the place to be farther from.
pub fn relative_value(d_close: f64, d_far: f64, mode: RelativeMode, radius: f64) -> f64 {
    match mode {
        RelativeMode::Ratio => {
            let sum = d_close + d_far;
            if sum <= 1e-6 { 0.5 } else { d_close / sum }
        }
        RelativeMode::Difference => ((d_close - d_far).max(0.0) / radius).clamp(0.0, 1.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::Layout;
    use crate::problem::Origin;
    use m2rc_stdlib::grid::Grid;

    fn ctx_profile() -> CostProfile {
        CostProfile {
            clearance: false,
            ..CostProfile::reference()
        }
    }

    fn term(kind: SoftKind, scope: Option<Area>) -> SoftTerm {
        SoftTerm {
            kind,
            weight: None,
            scope,
            origin: Origin::Unknown,
        }
    }

    /// Φ of one term, row-major, with every cell traversable except `blocked`.
    fn field_blocked(n: usize, res: f64, t: &SoftTerm, blocked: &[usize]) -> Vec<f64> {
        let p = ctx_profile();
        let od = vec![u32::MAX; n * n];
        let l = Layout::new(n);
        let mut trav = vec![true; n * n];
        blocked.iter().for_each(|&i| trav[i] = false);
        let runs = traversable_runs(&trav, n);
        let ctx = FieldContext {
            n,
            resolution: res,
            profile: &p,
            obstacle_sq: &od,
            runs: &runs,
        };
        let mut phi = vec![0.0; l.len()];
        add_term(&mut phi, &ctx, &mut FieldScratch::default(), t);
        l.unpad(&phi)
    }

    fn field(n: usize, res: f64, t: &SoftTerm) -> Vec<f64> {
        field_blocked(n, res, t, &[])
    }

    #[test]
    fn the_padded_clearance_field_is_the_plain_one_padded() {
        let n = 9;
        let p = CostProfile::reference();
        // Squared distances to a wall along row 0 and one obstacle in the middle.
        let od: Vec<u32> = (0..n * n)
            .map(|i| {
                let (r, c) = ((i / n) as i64, (i % n) as i64);
                let mid = (r - 4).pow(2) + (c - 4).pow(2);
                (r * r).min(mid) as u32
            })
            .collect();
        for res in [0.05, 0.1, 0.5] {
            let ctx = FieldContext {
                n,
                resolution: res,
                profile: &p,
                obstacle_sq: &od,
                runs: &[],
            };
            let l = Layout::new(n);
            let padded = clearance_field_padded(&ctx, &l);
            let plain = clearance_field(&ctx);
            assert!(plain.iter().any(|&v| v > 0.0), "resolution {res}");
            assert_eq!(padded, l.pad(&plain, 0.0), "resolution {res}");
        }
    }

    #[test]
    fn a_busy_transform_cache_gives_the_same_field() {
        let n = 12;
        let p = ctx_profile();
        let od = vec![u32::MAX; n * n];
        let runs = traversable_runs(&vec![true; n * n], n);
        let ctx = FieldContext {
            n,
            resolution: 0.5,
            profile: &p,
            obstacle_sq: &od,
            runs: &runs,
        };
        let cell = |r, c| Area::Cells(vec![Cell::new(r, c)]);
        let relative = term(
            SoftKind::Relative {
                closer: cell(1, 1),
                farther: cell(9, 10),
                mode: RelativeMode::Ratio,
            },
            None,
        );
        let len = (n + 2) * (n + 2);
        let mut fresh = vec![0.0; len];
        add_term(&mut fresh, &ctx, &mut FieldScratch::default(), &relative);
        let mut scratch = FieldScratch::default();
        for k in 0..2 * KEPT_TRANSFORMS as u32 {
            let far = term(
                SoftKind::Far {
                    reference: cell(k, 3),
                },
                None,
            );
            add_term(&mut vec![0.0; len], &ctx, &mut scratch, &far);
            let mut busy = vec![0.0; len];
            add_term(&mut busy, &ctx, &mut scratch, &relative);
            assert_eq!(busy, fresh, "after {k} other transforms");
        }
    }

    #[test]
    fn runs_cover_exactly_the_traversable_cells() {
        let n = 7;
        let trav: Vec<bool> = (0..n * n).map(|i| (i * 7 + i / 3) % 5 != 0).collect();
        let runs = traversable_runs(&trav, n);
        let mut seen = vec![false; n * n];
        for w in runs.windows(2) {
            assert!((w[0].row, w[0].c1 + 1) < (w[1].row, w[1].c0), "{w:?}");
        }
        for run in &runs {
            for c in run.c0..=run.c1 {
                seen[run.row as usize * n + c as usize] = true;
            }
        }
        assert_eq!(seen, trav);
        assert!(traversable_runs(&[], 0).is_empty());
    }

    #[test]
    fn untraversable_cells_are_left_alone() {
        let n = 6;
        let t = term(
            SoftKind::Far {
                reference: Area::Cells(vec![Cell::new(0, 0)]),
            },
            None,
        );
        let open = field(n, 0.5, &t);
        let phi = field_blocked(n, 0.5, &t, &[3, 20]);
        for i in 0..n * n {
            let want = if i == 3 || i == 20 { 0.0 } else { open[i] };
            assert_eq!(phi[i].to_bits(), want.to_bits(), "cell {i}");
        }
    }

    #[test]
    fn near_term_hand_values() {
        // Resolution 0.5 m: R_near = 1.5 / 0.5 = 3 cells, λ = 8. Reference at (0, 0).
        let n = 8;
        let t = term(
            SoftKind::Near {
                reference: Area::Cells(vec![Cell::new(0, 0)]),
            },
            None,
        );
        let phi = field(n, 0.5, &t);
        assert_eq!(phi[0], 0.0);
        assert!((phi[2] - 8.0 * 2.0 / 3.0).abs() < 1e-12); // (0, 2): d = 2
        assert!((phi[n + 1] - 8.0 * 2f64.sqrt() / 3.0).abs() < 1e-12); // (1, 1)
        assert_eq!(phi[7 * n + 7], 8.0); // far outside the clipping band
        assert_eq!(phi[5], 8.0); // d = 5 > 3
    }

    #[test]
    fn far_term_hand_values() {
        // σ_far = 3 cells, λ = 96.
        let n = 6;
        let t = term(
            SoftKind::Far {
                reference: Area::Cells(vec![Cell::new(0, 0)]),
            },
            None,
        );
        let phi = field(n, 0.5, &t);
        assert!((phi[0] - 96.0).abs() < 1e-12);
        assert!((phi[3] - 96.0 * (-1.0f64).exp()).abs() < 1e-12); // (0, 3)
        assert!((phi[4 * n] - 96.0 * (-4.0f64 / 3.0).exp()).abs() < 1e-12); // (4, 0)
    }

    #[test]
    fn scope_masks_the_term() {
        let n = 6;
        let mut m = Grid::new(n, false);
        m.set(Cell::new(0, 3), true);
        m.set(Cell::new(5, 5), true);
        let t = term(
            SoftKind::Far {
                reference: Area::Cells(vec![Cell::new(0, 0)]),
            },
            Some(Area::mask(m)),
        );
        let phi = field(n, 0.5, &t);
        assert!((phi[3] - 96.0 * (-1.0f64).exp()).abs() < 1e-12);
        let d = (50.0f64).sqrt();
        assert!((phi[5 * n + 5] - 96.0 * (-d / 3.0).exp()).abs() < 1e-12);
        assert_eq!(phi.iter().filter(|v| **v != 0.0).count(), 2);
    }

    #[test]
    fn relative_ratio_and_difference() {
        assert_eq!(relative_value(0.0, 0.0, RelativeMode::Ratio, 30.0), 0.5);
        assert_eq!(relative_value(1.0, 3.0, RelativeMode::Ratio, 30.0), 0.25);
        assert_eq!(
            relative_value(10.0, 4.0, RelativeMode::Difference, 30.0),
            0.2
        );
        assert_eq!(
            relative_value(4.0, 10.0, RelativeMode::Difference, 30.0),
            0.0
        );
        assert_eq!(
            relative_value(100.0, 0.0, RelativeMode::Difference, 30.0),
            1.0
        );
        // Closer to (0,0) than to (0,4): cell (0,1) has d_close 1, d_far 3.
        let n = 5;
        let t = term(
            SoftKind::Relative {
                closer: Area::Cells(vec![Cell::new(0, 0)]),
                farther: Area::Cells(vec![Cell::new(0, 4)]),
                mode: RelativeMode::Ratio,
            },
            None,
        );
        let phi = field(n, 0.05, &t);
        assert!((phi[1] - 64.0 * 0.25).abs() < 1e-12);
        assert!((phi[2] - 32.0).abs() < 1e-12);
    }

    #[test]
    fn path_shape_hand_values() {
        // R_ps = 0.9 / 0.3 = 3 cells, λ = 18.
        let n = 6;
        let t = term(
            SoftKind::PathShape {
                waypoints: Area::Cells(vec![Cell::new(2, 2)]),
            },
            None,
        );
        let phi = field(n, 0.3, &t);
        assert_eq!(phi[2 * n + 2], 0.0);
        assert!((phi[2 * n + 3] - 6.0).abs() < 1e-12);
        assert_eq!(phi[5 * n + 5], 18.0);
    }

    #[test]
    fn clearance_hand_values() {
        // R_c = 0.75 / 0.05 = 15 cells; λ = 36.
        assert_eq!(clearance_cost(0.0, 15.0, 36.0), 36.0);
        assert_eq!(clearance_cost(15.0, 15.0, 36.0), 0.0);
        assert!((clearance_cost(5.0, 15.0, 36.0) - 36.0 * 4.0 / 9.0).abs() < 1e-12);
        assert_eq!(clearance_cost(40.0, 15.0, 36.0), 0.0);
    }

    #[test]
    fn windowed_unscoped_near_equals_full_transform() {
        let n = 40;
        let reference = Area::Cells(vec![Cell::new(10, 12), Cell::new(11, 12), Cell::new(30, 2)]);
        let t = term(
            SoftKind::Near {
                reference: reference.clone(),
            },
            None,
        );
        let phi = field(n, 0.05, &t);
        let full = field::distances(&reference.to_mask(n), n);
        for i in 0..n * n {
            let want = 8.0 * (full[i] / 30.0).clamp(0.0, 1.0);
            assert!((phi[i] - want).abs() < 1e-12, "cell {i}");
        }
    }
}
