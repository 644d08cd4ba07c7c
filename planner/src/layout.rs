//! Padded flat indexing: the N×N grid is stored inside an (N+2)×(N+2) array whose border is never
//! traversable, so the search loop can step to all eight neighbours without bounds checks.

use m2rc_stdlib::grid::Cell;

/// Row/column offsets of the eight moves, in the reference order: up, down, left, right, up-left,
/// up-right, down-left, down-right. The order decides which of several equal-cost paths is found.
pub const MOVES: [(i32, i32); 8] = [
    (-1, 0),
    (1, 0),
    (0, -1),
    (0, 1),
    (-1, -1),
    (-1, 1),
    (1, -1),
    (1, 1),
];

/// Whether the diagonal move `k` (4..8 in [`MOVES`]) from padded index `u` keeps off the corners
/// of cells outside `free`: both orthogonal neighbours it passes between must be in `free`. Every
/// search applies this one rule; `free` is the base traversability for the reference's corner
/// rule (walls only), or the allowed cells when an avoided cell's corner counts too, as the
/// evaluator's segment test counts a touched corner (`m2rc_benchmark::route::validity` checks
/// routes with the same rule). Straight moves (`k < 4`) pass no corner.
#[inline]
pub fn corners_free(free: &[bool], u: usize, k: usize, w: usize) -> bool {
    if k < 4 {
        return true;
    }
    let (dr, dc) = MOVES[k];
    free[(u as isize + dr as isize * w as isize) as usize]
        && free[(u as isize + dc as isize) as usize]
}

/// Heading slot meaning "no previous move" (the start of a search).
pub const NO_HEADING: u8 = 8;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Side of the map grid.
    pub n: usize,
    /// Side of the padded array, `n + 2`.
    pub w: usize,
}

impl Layout {
    pub fn new(n: usize) -> Self {
        Layout { n, w: n + 2 }
    }

    /// Number of padded slots.
    pub fn len(&self) -> usize {
        self.w * self.w
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    pub fn idx(&self, c: Cell) -> usize {
        (c.row as usize + 1) * self.w + c.col as usize + 1
    }

    /// Padded index of the row-major map index `i`.
    pub fn idx_of_plain(&self, i: usize) -> usize {
        (i / self.n + 1) * self.w + i % self.n + 1
    }

    /// The cell of a padded index inside the map.
    pub fn cell(&self, idx: usize) -> Cell {
        Cell::new((idx / self.w - 1) as u32, (idx % self.w - 1) as u32)
    }

    pub fn contains(&self, c: Cell) -> bool {
        (c.row as usize) < self.n && (c.col as usize) < self.n
    }

    /// Signed padded-index offsets of [`MOVES`].
    pub fn offsets(&self) -> [isize; 8] {
        let w = self.w as isize;
        MOVES.map(|(dr, dc)| dr as isize * w + dc as isize)
    }

    /// A row-major N×N array copied into the padded layout, with `fill` on the border.
    pub fn pad<T: Copy>(&self, plain: &[T], fill: T) -> Vec<T> {
        let mut out = vec![fill; self.len()];
        for r in 0..self.n {
            let dst = (r + 1) * self.w + 1;
            out[dst..dst + self.n].copy_from_slice(&plain[r * self.n..(r + 1) * self.n]);
        }
        out
    }

    /// The padded array's interior, row-major N×N.
    pub fn unpad<T: Copy>(&self, padded: &[T]) -> Vec<T> {
        let mut out = Vec::with_capacity(self.n * self.n);
        for r in 0..self.n {
            let src = (r + 1) * self.w + 1;
            out.extend_from_slice(&padded[src..src + self.n]);
        }
        out
    }
}

/// Turn penalty `S = (|wrap(θ' - θ)| / π)²` between an incoming heading slot (0..8, 8 = none) and
/// a move, with θ = atan2(dr, dc). With 45° moves it takes the values 0, 1/16, 1/4, 9/16, 1.
pub fn turn_table() -> [[f64; 8]; 9] {
    let mut t = [[0.0; 8]; 9];
    for (h, row) in t.iter_mut().enumerate().take(8) {
        let a = (MOVES[h].0 as f64).atan2(MOVES[h].1 as f64);
        for (m, slot) in row.iter_mut().enumerate() {
            let b = (MOVES[m].0 as f64).atan2(MOVES[m].1 as f64);
            let mut d = b - a;
            while d > std::f64::consts::PI {
                d -= 2.0 * std::f64::consts::PI;
            }
            while d < -std::f64::consts::PI {
                d += 2.0 * std::f64::consts::PI;
            }
            // Snap to the exact multiple of 45° so table values do not carry atan2 rounding.
            let steps = (d.abs() / std::f64::consts::FRAC_PI_4).round();
            *slot = (steps / 4.0).powi(2);
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pad_round_trips_and_indexes() {
        let l = Layout::new(3);
        let plain: Vec<u32> = (0..9).collect();
        let p = l.pad(&plain, 99);
        assert_eq!(p.len(), 25);
        assert_eq!(p[l.idx(Cell::new(1, 2))], 5);
        assert_eq!(p[0], 99);
        assert_eq!(l.unpad(&p), plain);
        assert_eq!(l.cell(l.idx(Cell::new(2, 1))), Cell::new(2, 1));
        assert_eq!(l.idx_of_plain(5), l.idx(Cell::new(1, 2)));
    }

    #[test]
    fn turn_penalties() {
        let t = turn_table();
        assert_eq!(t[3][3], 0.0); // right, right
        assert_eq!(t[3][2], 1.0); // right then left: U-turn
        assert_eq!(t[3][1], 0.25); // right then down: 90°
        assert_eq!(t[3][7], 0.0625); // right then down-right: 45°
        assert_eq!(t[NO_HEADING as usize], [0.0; 8]);
    }
}
