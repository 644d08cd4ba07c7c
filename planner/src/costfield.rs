//! The per-segment soft cost field Φ (method notes §4.4): the sum of the active soft terms, each
//! multiplied by its spatial-scope mask, plus the always-on clearance term. Φ is charged once per
//! entered cell, independent of step length, as in the reference.
//!
//! Distances are exact Euclidean distances in cells. Each term computes its distance transform only
//! on a window that holds its reference cells and every cell whose value can matter (the scope, or
//! the band within the clipping radius), which is exact and keeps a room-scoped term on a 700×700
//! map to a fraction of a full transform.

use crate::edt;
use crate::problem::{Area, CostProfile, RelativeMode, SoftKind, SoftTerm};
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

/// Exact distances from `sources` for the cells of `window`, as a closure over map cells. The
/// transform runs on the square hull of `window ∪ sources`.
struct WindowDistance {
    origin: (i64, i64),
    side: usize,
    d: Vec<f64>,
}

impl WindowDistance {
    fn new(sources: &[Cell], window: Rect) -> Self {
        let hull = Rect::of_cells(sources).map_or(window, |s| s.union(window));
        let side = ((hull.r1 - hull.r0).max(hull.c1 - hull.c0) + 1) as usize;
        let mut src = vec![false; side * side];
        for c in sources {
            src[(c.row as i64 - hull.r0) as usize * side + (c.col as i64 - hull.c0) as usize] =
                true;
        }
        WindowDistance {
            origin: (hull.r0, hull.c0),
            side,
            d: edt::distance(&src, side),
        }
    }

    fn at(&self, r: i64, c: i64) -> f64 {
        self.d[(r - self.origin.0) as usize * self.side + (c - self.origin.1) as usize]
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
        let cells: Vec<Cell> = m
            .iter()
            .enumerate()
            .filter(|(_, v)| **v)
            .map(|(i, _)| Cell::new((i / n) as u32, (i % n) as u32))
            .collect();
        (m, Rect::of_cells(&cells))
    })
}

/// Adds `weight · value(d)` over the scope (or the whole map) to `phi`, where `d` is the distance to
/// `reference`. `clip` is the distance beyond which `value` is constant (lets an unscoped term
/// transform only a band around the reference).
fn add_distance_term(
    phi: &mut [f64],
    n: usize,
    reference: &Area,
    scope: &Option<Area>,
    weight: f64,
    clip: Option<f64>,
    value: impl Fn(f64) -> f64,
) {
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
            let wd = WindowDistance::new(&src, rect);
            for r in rect.r0..=rect.r1 {
                for c in rect.c0..=rect.c1 {
                    let i = r as usize * n + c as usize;
                    if mask[i] {
                        phi[i] += weight * value(wd.at(r, c));
                    }
                }
            }
        }
        None => {
            let window = match clip {
                Some(radius) => src_rect.grow(radius.ceil() as i64 + 1, n),
                None => Rect::full(n),
            };
            let wd = WindowDistance::new(&src, window);
            let outside = clip
                .map(|radius| weight * value(radius + 1.0))
                .unwrap_or(0.0);
            for r in 0..n as i64 {
                let inside_rows = r >= window.r0 && r <= window.r1;
                for c in 0..n as i64 {
                    let i = r as usize * n + c as usize;
                    if inside_rows && c >= window.c0 && c <= window.c1 {
                        phi[i] += weight * value(wd.at(r, c));
                    } else {
                        phi[i] += outside;
                    }
                }
            }
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
}

/// The clearance penalty `λ · ((max(0, R − d)) / R)²` at obstacle distance `d`.
pub fn clearance_cost(d: f64, radius: f64, weight: f64) -> f64 {
    let x = (radius - d).max(0.0) / radius;
    weight * x * x
}

/// The always-on clearance field (zero when the profile turns it off).
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

/// Adds one soft term to `phi` (row-major `n`×`n`).
pub fn add_term(phi: &mut [f64], ctx: &FieldContext<'_>, term: &SoftTerm) {
    let p = ctx.profile;
    let n = ctx.n;
    let res = ctx.resolution;
    let scale = p.soft_scale;
    match &term.kind {
        SoftKind::Near { reference } => {
            let radius = p.cells(p.near_radius_m, res);
            let w = term.weight.unwrap_or(p.near_weight) * scale;
            add_distance_term(phi, n, reference, &term.scope, w, Some(radius), |d| {
                (d / radius).clamp(0.0, 1.0)
            });
        }
        SoftKind::Far { reference } => {
            let sigma = p.cells(p.far_sigma_m, res);
            let w = term.weight.unwrap_or(p.far_weight) * scale;
            add_distance_term(phi, n, reference, &term.scope, w, None, |d| {
                (-d / sigma).exp()
            });
        }
        SoftKind::PathShape { waypoints } => {
            let radius = p.cells(p.path_shape_radius_m, res);
            let w = term.weight.unwrap_or(p.path_shape_weight) * scale;
            add_distance_term(phi, n, waypoints, &term.scope, w, Some(radius), |d| {
                (d / radius).clamp(0.0, 1.0)
            });
        }
        SoftKind::Relative {
            closer,
            farther,
            mode,
        } => {
            let w = term.weight.unwrap_or(p.relative_weight) * scale;
            add_relative(phi, ctx, closer, farther, *mode, &term.scope, w);
        }
        SoftKind::Clearance { radius_m } => {
            let radius = p.cells(*radius_m, res);
            let w = term.weight.unwrap_or(p.clearance_weight) * scale;
            if w == 0.0 {
                return;
            }
            let mask = term.scope.as_ref().map(|a| a.to_mask(n));
            let r2 = radius * radius;
            for (i, &sq) in ctx.obstacle_sq.iter().enumerate() {
                if (sq as f64) < r2 && mask.as_ref().is_none_or(|m| m[i]) {
                    phi[i] += clearance_cost((sq as f64).sqrt(), radius, w);
                }
            }
        }
    }
}

fn add_relative(
    phi: &mut [f64],
    ctx: &FieldContext<'_>,
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
    let da = WindowDistance::new(&a, window);
    let db = WindowDistance::new(&b, window);
    let radius = ctx
        .profile
        .cells(ctx.profile.relative_radius_m, ctx.resolution);
    for r in window.r0..=window.r1 {
        for c in window.c0..=window.c1 {
            let i = r as usize * n + c as usize;
            if scope.as_ref().is_some_and(|(m, _)| !m[i]) {
                continue;
            }
            phi[i] += weight * relative_value(da.at(r, c), db.at(r, c), mode, radius);
        }
    }
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

    fn field(n: usize, res: f64, t: &SoftTerm) -> Vec<f64> {
        let p = ctx_profile();
        let od = vec![u32::MAX; n * n];
        let ctx = FieldContext {
            n,
            resolution: res,
            profile: &p,
            obstacle_sq: &od,
        };
        let mut phi = vec![0.0; n * n];
        add_term(&mut phi, &ctx, t);
        phi
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
            Some(Area::Mask(m)),
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
        let full = edt::distance(&reference.to_mask(n), n);
        for i in 0..n * n {
            let want = 8.0 * (full[i] / 30.0).clamp(0.0, 1.0);
            assert!((phi[i] - want).abs() < 1e-12, "cell {i}");
        }
    }
}
