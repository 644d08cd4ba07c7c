//! Path-shape similarity: normalized dynamic time warping with a dead-band tolerance.
//!
//! Local costs are `max(0, distance - tolerance)`; the predecessor of each cell is the minimum
//! by (cost, steps) over up, left, diagonal, first option winning ties; the score is
//! `exp(-cost / (success_distance * max(m, 1)))` for a reference of m points. All in cells.

use super::geometry::Point;

/// δ, in grid cells (0.5 m at 0.05 m per cell).
pub const PATH_SHAPE_TOLERANCE_GRID: f64 = 10.0;
/// d_succ, in grid cells (0.2 m at 0.05 m per cell).
pub const PATH_SHAPE_NDTW_SUCCESS_DISTANCE: f64 = 4.0;

/// `(nDTW, cost, mean cost per alignment step, alignment steps)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ndtw {
    pub score: f64,
    pub cost: f64,
    pub mean: f64,
    pub steps: usize,
}

/// nDTW with the benchmark's constants.
pub fn ndtw(local: &[Point], reference: &[Point]) -> Ndtw {
    ndtw_with(
        local,
        reference,
        PATH_SHAPE_NDTW_SUCCESS_DISTANCE,
        PATH_SHAPE_TOLERANCE_GRID,
    )
}

pub fn ndtw_with(
    local: &[Point],
    reference: &[Point],
    success_distance: f64,
    tolerance: f64,
) -> Ndtw {
    let (cost, steps) = dtw_cost_and_steps(local, reference, tolerance);
    if cost.is_infinite() {
        return Ndtw {
            score: 0.0,
            cost,
            mean: cost,
            steps,
        };
    }
    if steps == 0 {
        return Ndtw {
            score: 1.0,
            cost: 0.0,
            mean: 0.0,
            steps: 0,
        };
    }
    let denom = success_distance * reference.len().max(1) as f64;
    Ndtw {
        score: (-cost / denom).exp(),
        cost,
        mean: cost / steps as f64,
        steps,
    }
}

fn dtw_cost_and_steps(local: &[Point], reference: &[Point], tolerance: f64) -> (f64, usize) {
    if local.is_empty() || reference.is_empty() {
        let cost = if local.is_empty() && reference.is_empty() {
            0.0
        } else {
            f64::INFINITY
        };
        return (cost, 0);
    }
    let (n, m) = (local.len(), reference.len());
    let w = m + 1;
    let mut cost = vec![f64::INFINITY; (n + 1) * w];
    let mut steps = vec![0usize; (n + 1) * w];
    cost[0] = 0.0;
    for i in 1..=n {
        let p = local[i - 1];
        for j in 1..=m {
            let q = reference[j - 1];
            let options = [(i - 1) * w + j, i * w + j - 1, (i - 1) * w + j - 1];
            let mut best = options[0];
            for &o in &options[1..] {
                if cost[o] < cost[best] || (cost[o] == cost[best] && steps[o] < steps[best]) {
                    best = o;
                }
            }
            let local_cost = (p[0] - q[0]).hypot(p[1] - q[1]);
            cost[i * w + j] = cost[best] + (local_cost - tolerance).max(0.0);
            steps[i * w + j] = steps[best] + 1;
        }
    }
    let s = steps[n * w + m];
    if s == 0 {
        return (f64::INFINITY, 0);
    }
    (cost[n * w + m], s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1.0)
    }

    /// D.4 vector V8.
    #[test]
    fn reference_vectors_v8() {
        let r = ndtw(&[[0.0, 0.0], [0.0, 5.0]], &[[0.0, 0.0], [0.0, 5.0]]);
        assert_eq!(
            r,
            Ndtw {
                score: 1.0,
                cost: 0.0,
                mean: 0.0,
                steps: 2
            }
        );
        let r = ndtw(&[[12.0, 0.0], [12.0, 5.0]], &[[0.0, 0.0], [0.0, 5.0]]);
        assert!(close(r.score, 0.6065306597126334) && close(r.cost, 4.0) && close(r.mean, 2.0));
        assert_eq!(r.steps, 2);
        let r = ndtw(&[[20.0, 0.0]], &[[0.0, 0.0], [0.0, 1.0], [0.0, 2.0]]);
        assert!(close(r.score, 0.08123617416335172), "{r:?}");
        assert!(close(r.cost, 30.124735636742567) && close(r.mean, 10.041578545580856));
        assert_eq!(r.steps, 3);
    }

    #[test]
    fn empty_sides() {
        assert_eq!(ndtw(&[], &[]).score, 1.0);
        let r = ndtw(&[[1.0, 1.0]], &[]);
        assert_eq!(r.score, 0.0);
        assert!(r.cost.is_infinite());
    }
}
