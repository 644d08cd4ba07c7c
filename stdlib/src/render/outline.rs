//! Outlines of cell sets as closed rectilinear loops.
//!
//! Drawing a 700×700 map cell by cell would give an SVG of hundreds of thousands of squares; a room,
//! a wall run or a region is instead drawn as one path along its boundary. The boundary is the set of
//! unit cell sides between a member and a non-member, each directed with the member on its right
//! (clockwise on screen, y down). Chaining them gives loops whose winding number is 1 inside the set
//! and 0 elsewhere, holes included, so any fill rule draws the set exactly.

use crate::grid::Cell;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write;

/// A lattice corner: `(x, y)` = (col, row) of the cell whose top-left corner it is.
pub type Pt = (i64, i64);

type Edge = (Pt, Pt);

/// The boundary sides of cell `(row, col)` against non-members, interior on the right.
fn push_cell_edges(row: i64, col: i64, member: impl Fn(i64, i64) -> bool, out: &mut Vec<Edge>) {
    let (x, y) = (col, row);
    if !member(row - 1, col) {
        out.push(((x, y), (x + 1, y)));
    }
    if !member(row, col + 1) {
        out.push(((x + 1, y), (x + 1, y + 1)));
    }
    if !member(row + 1, col) {
        out.push(((x + 1, y + 1), (x, y + 1)));
    }
    if !member(row, col - 1) {
        out.push(((x, y + 1), (x, y)));
    }
}

/// Loops around an arbitrary list of cells (duplicates allowed).
pub fn trace_cells(cells: &[Cell]) -> Vec<Vec<Pt>> {
    let set: HashSet<(i64, i64)> = cells.iter().map(|c| (c.row as i64, c.col as i64)).collect();
    let mut sorted: Vec<(i64, i64)> = set.iter().copied().collect();
    sorted.sort_unstable();
    let mut edges = Vec::new();
    for &(r, c) in &sorted {
        push_cell_edges(r, c, |rr, cc| set.contains(&(rr, cc)), &mut edges);
    }
    chain(edges)
}

/// Loops around every label of a row-major `w`×`h` window whose top-left cell is `origin`
/// (`[row, col]`), except `skip`. Cells outside the window count as a different label.
pub fn trace_labels(
    labels: &[u32],
    w: usize,
    h: usize,
    origin: (i64, i64),
    skip: Option<u32>,
) -> BTreeMap<u32, Vec<Vec<Pt>>> {
    let mut by_label: BTreeMap<u32, Vec<Edge>> = BTreeMap::new();
    let at = |r: i64, c: i64| -> Option<u32> {
        (r >= 0 && c >= 0 && (r as usize) < h && (c as usize) < w)
            .then(|| labels[r as usize * w + c as usize])
    };
    let mut tmp = Vec::with_capacity(4);
    for r in 0..h as i64 {
        for c in 0..w as i64 {
            let l = labels[r as usize * w + c as usize];
            if Some(l) == skip {
                continue;
            }
            tmp.clear();
            push_cell_edges(r, c, |rr, cc| at(rr, cc) == Some(l), &mut tmp);
            if !tmp.is_empty() {
                let v = by_label.entry(l).or_default();
                v.extend(tmp.iter().map(|&((x0, y0), (x1, y1))| {
                    (
                        (x0 + origin.1, y0 + origin.0),
                        (x1 + origin.1, y1 + origin.0),
                    )
                }));
            }
        }
    }
    by_label.into_iter().map(|(l, e)| (l, chain(e))).collect()
}

/// Chains directed unit edges into closed loops, keeping only the corners.
fn chain(mut edges: Vec<Edge>) -> Vec<Vec<Pt>> {
    edges.sort_unstable();
    edges.dedup();
    let mut outgoing: HashMap<Pt, Vec<usize>> = HashMap::with_capacity(edges.len());
    for (i, e) in edges.iter().enumerate() {
        outgoing.entry(e.0).or_default().push(i);
    }
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for start in 0..edges.len() {
        if used[start] {
            continue;
        }
        let origin = edges[start].0;
        let mut pts = vec![origin];
        let mut cur = start;
        loop {
            used[cur] = true;
            let end = edges[cur].1;
            if end == origin {
                break;
            }
            pts.push(end);
            let next = outgoing
                .get(&end)
                .and_then(|v| v.iter().copied().find(|&j| !used[j]));
            match next {
                Some(j) => cur = j,
                // Only reachable on inconsistent input; close what we have rather than fail.
                None => break,
            }
        }
        loops.push(corners(&pts));
    }
    loops
}

/// Drops the vertices where the boundary goes straight on.
fn corners(pts: &[Pt]) -> Vec<Pt> {
    let n = pts.len();
    if n < 3 {
        return pts.to_vec();
    }
    (0..n)
        .filter(|&i| {
            let p = pts[(i + n - 1) % n];
            let q = pts[i];
            let r = pts[(i + 1) % n];
            let d1 = ((q.0 - p.0).signum(), (q.1 - p.1).signum());
            let d2 = ((r.0 - q.0).signum(), (r.1 - q.1).signum());
            d1 != d2
        })
        .map(|i| pts[i])
        .collect()
}

/// SVG path data for the loops, mapping lattice corners to pixels with `to_px`.
pub fn path_data(loops: &[Vec<Pt>], to_px: impl Fn(Pt) -> (f64, f64)) -> String {
    use super::svg::num;
    let mut d = String::new();
    for lp in loops {
        let Some(&first) = lp.first() else { continue };
        let (x0, y0) = to_px(first);
        let _ = write!(d, "M{} {}", num(x0), num(y0));
        let mut prev = first;
        for &p in &lp[1..] {
            let (x, y) = to_px(p);
            if p.1 == prev.1 {
                let _ = write!(d, "H{}", num(x));
            } else if p.0 == prev.0 {
                let _ = write!(d, "V{}", num(y));
            } else {
                let _ = write!(d, "L{} {}", num(x), num(y));
            }
            prev = p;
        }
        d.push('Z');
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of a loop (shoelace); positive for clockwise on screen (y down).
    fn area2(lp: &[Pt]) -> i64 {
        let n = lp.len();
        (0..n)
            .map(|i| {
                let (x0, y0) = lp[i];
                let (x1, y1) = lp[(i + 1) % n];
                x0 * y1 - x1 * y0
            })
            .sum()
    }

    #[test]
    fn single_cell_is_a_unit_square() {
        let loops = trace_cells(&[Cell::new(2, 3)]);
        assert_eq!(loops, vec![vec![(3, 2), (4, 2), (4, 3), (3, 3)]]);
        assert_eq!(area2(&loops[0]), 2);
    }

    #[test]
    fn ring_has_outer_loop_and_reversed_hole() {
        let mut cells = Vec::new();
        for r in 0..3 {
            for c in 0..3 {
                if (r, c) != (1, 1) {
                    cells.push(Cell::new(r, c));
                }
            }
        }
        let loops = trace_cells(&cells);
        assert_eq!(loops.len(), 2);
        let total: i64 = loops.iter().map(|l| area2(l)).sum();
        assert_eq!(total, 2 * 8, "net area equals the 8 member cells");
        assert!(loops.iter().all(|l| l.len() == 4));
    }

    #[test]
    fn labels_get_one_region_each_and_skip_is_skipped() {
        // 1 1 2
        // 1 0 2
        let labels = [1, 1, 2, 1, 0, 2];
        let out = trace_labels(&labels, 3, 2, (10, 20), Some(0));
        assert_eq!(out.keys().copied().collect::<Vec<_>>(), vec![1, 2]);
        let a1: i64 = out[&1].iter().map(|l| area2(l)).sum();
        let a2: i64 = out[&2].iter().map(|l| area2(l)).sum();
        assert_eq!((a1, a2), (6, 4));
        assert!(
            out[&2][0].contains(&(23, 10)),
            "origin offsets x by col and y by row"
        );
    }

    #[test]
    fn diagonal_touch_keeps_all_cells() {
        let loops = trace_cells(&[Cell::new(0, 0), Cell::new(1, 1)]);
        let total: i64 = loops.iter().map(|l| area2(l)).sum();
        assert_eq!(total, 4);
    }

    #[test]
    fn path_uses_axis_commands() {
        let loops = trace_cells(&[Cell::new(0, 0), Cell::new(0, 1)]);
        let d = path_data(&loops, |(x, y)| (x as f64 * 2.0, y as f64 * 2.0));
        assert_eq!(d, "M0 0H4V2H0Z");
    }
}
