//! Thinning a route to waypoints: the start, every stage goal, and every turn where the route
//! strays from the straight line between kept points by more than a tolerance
//! (Ramer-Douglas-Peucker within each stage, so a stage goal is never smoothed away).

use crate::grid::Cell;

/// Indices into `cells` to keep, ascending: 0, every index of `stage_ends` (clamped to the
/// route), the last cell, and the turns beyond `tolerance_cells` in between.
pub fn waypoint_indices(cells: &[Cell], stage_ends: &[usize], tolerance_cells: f64) -> Vec<usize> {
    if cells.is_empty() {
        return Vec::new();
    }
    let last = cells.len() - 1;
    let mut anchors: Vec<usize> = std::iter::once(0)
        .chain(stage_ends.iter().map(|&e| e.min(last)))
        .chain(std::iter::once(last))
        .collect();
    anchors.sort_unstable();
    anchors.dedup();
    let mut keep = vec![false; cells.len()];
    for &a in &anchors {
        keep[a] = true;
    }
    for w in anchors.windows(2) {
        simplify(cells, w[0], w[1], tolerance_cells, &mut keep);
    }
    keep.iter()
        .enumerate()
        .filter_map(|(i, &k)| k.then_some(i))
        .collect()
}

/// Ramer-Douglas-Peucker between `a` and `b` (both kept), with an explicit stack: a route is up
/// to N² cells long and recursion would follow its length.
fn simplify(cells: &[Cell], a: usize, b: usize, tol: f64, keep: &mut [bool]) {
    let mut stack = vec![(a, b)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (mut far, mut far_d) = (a, 0.0f64);
        for i in a + 1..b {
            let d = distance_to_segment(cells[i], cells[a], cells[b]);
            if d > far_d {
                far_d = d;
                far = i;
            }
        }
        if far_d > tol {
            keep[far] = true;
            stack.push((a, far));
            stack.push((far, b));
        }
    }
}

/// Distance in cells from `p` to the segment `a`-`b`.
fn distance_to_segment(p: Cell, a: Cell, b: Cell) -> f64 {
    let (px, py) = (p.col as f64, p.row as f64);
    let (ax, ay) = (a.col as f64, a.row as f64);
    let (bx, by) = (b.col as f64, b.row as f64);
    let (dx, dy) = (bx - ax, by - ay);
    let len2 = dx * dx + dy * dy;
    if len2 == 0.0 {
        return (px - ax).hypot(py - ay);
    }
    let t = (((px - ax) * dx + (py - ay) * dy) / len2).clamp(0.0, 1.0);
    (px - (ax + t * dx)).hypot(py - (ay + t * dy))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(r: u32, col: u32) -> Cell {
        Cell::new(r, col)
    }

    #[test]
    fn a_straight_line_keeps_only_its_ends_and_an_l_keeps_its_corner() {
        let line: Vec<Cell> = (0..10).map(|i| c(0, i)).collect();
        assert_eq!(waypoint_indices(&line, &[9], 1.0), vec![0, 9]);
        let mut l: Vec<Cell> = (0..5).map(|i| c(0, i)).collect();
        l.extend((1..5).map(|i| c(i, 4)));
        assert_eq!(waypoint_indices(&l, &[8], 1.0), vec![0, 4, 8]);
    }

    #[test]
    fn stage_goals_are_kept_even_on_a_straight_line() {
        let line: Vec<Cell> = (0..10).map(|i| c(0, i)).collect();
        assert_eq!(waypoint_indices(&line, &[3, 9], 1.0), vec![0, 3, 9]);
    }

    #[test]
    fn stair_steps_within_the_tolerance_are_not_turns() {
        let stairs: Vec<Cell> = (0..10).flat_map(|i| [c(i, i), c(i, i + 1)]).collect();
        let n = stairs.len() - 1;
        assert_eq!(waypoint_indices(&stairs, &[n], 2.0), vec![0, n]);
    }
}
