//! Exact Euclidean distance fields over the grid (Meijster, Roerdink & Hesselink's separable
//! transform), the primitive behind clearance, erosion by a robot radius, the planner's soft-cost
//! fields and heuristics, and "distance to a footprint" queries.
//!
//! Distances are between cell centres, in cells. Squared distances are exact integers, so the square
//! root is the only rounding: every result equals a brute-force scan bit for bit, whichever entry
//! point computed it.
//!
//! The transform is on the critical path of planning (one per stage heuristic and per soft term), so
//! it is written for speed: both passes walk memory row by row, only the columns between the
//! leftmost and rightmost source take part in the column pass and in the envelopes (other columns
//! hold no source, so their parabolas never reach the lower envelope), and [`EdtScratch`] lets a
//! caller reuse the buffers across transforms.

use crate::grid::Grid;
use std::cell::{Cell, RefCell};

/// The largest side for which every squared distance, `2 (n - 1)²`, fits in a `u32`.
pub const MAX_U32_SIDE: usize = 46_341;

/// Marks "no source at all" in the `u32` outputs.
pub const NO_SOURCE: u32 = u32::MAX;

/// Reusable working memory of the transform (vertical distances and the envelope stacks).
#[derive(Debug, Default, Clone)]
pub struct EdtScratch {
    g: Vec<u32>,
    s: Vec<u32>,
    t: Vec<u32>,
}

/// Squared distance, in cells², from every cell to the nearest source cell; `f64::INFINITY` when
/// there is no source at all.
pub fn squared_distance_field(sources: &Grid<bool>) -> Grid<f64> {
    let n = sources.n();
    let mut out = vec![0.0f64; n * n];
    transform(
        sources.data(),
        n,
        &mut out,
        &mut EdtScratch::default(),
        f64::INFINITY,
        |v| v as f64,
    );
    Grid::from_vec(n, out).unwrap_or_else(|| Grid::new(n, f64::INFINITY))
}

/// Euclidean distance, in cells, from every cell to the nearest source cell (0 on sources,
/// `f64::INFINITY` everywhere when there is no source).
pub fn distance_field(sources: &Grid<bool>) -> Grid<f64> {
    let n = sources.n();
    Grid::from_vec(n, distances(sources.data(), n)).unwrap_or_else(|| Grid::new(n, f64::INFINITY))
}

/// [`distance_field`] over a row-major `n`×`n` mask given as a slice.
pub fn distances(sources: &[bool], n: usize) -> Vec<f64> {
    let mut out = vec![0.0f64; n * n];
    transform(
        sources,
        n,
        &mut out,
        &mut EdtScratch::default(),
        f64::INFINITY,
        |v| (v as f64).sqrt(),
    );
    out
}

/// Squared distances in cells² as `u32` over a row-major `n`×`n` mask, [`NO_SOURCE`] everywhere
/// when there is no source. Half the memory of `f64` and exact for `n ≤` [`MAX_U32_SIDE`]; larger
/// distances saturate at `u32::MAX - 1`.
pub fn squared_distances(sources: &[bool], n: usize) -> Vec<u32> {
    let mut out = Vec::new();
    squared_distances_into(sources, n, &mut out, &mut EdtScratch::default());
    out
}

/// [`squared_distances`] into `out` (resized to `n * n`), reusing `scratch`: a planner computing many
/// fields on one map allocates nothing after the first.
pub fn squared_distances_into(
    sources: &[bool],
    n: usize,
    out: &mut Vec<u32>,
    scratch: &mut EdtScratch,
) {
    out.resize(n * n, 0);
    transform(sources, n, out, scratch, NO_SOURCE, |v| {
        u32::try_from(v).unwrap_or(u32::MAX - 1).min(u32::MAX - 1)
    });
}

/// The separable transform. `sources` and `out` are row-major `n`×`n` (`sources` shorter than that
/// counts as false beyond its end); `convert` maps an exact squared distance to the output type and
/// `none` fills the output when there is no source.
/// The mask cut or padded (with non-sources) to exactly `cells` entries, copying only when short.
fn exactly_cells(sources: &[bool], cells: usize) -> std::borrow::Cow<'_, [bool]> {
    if sources.len() >= cells {
        std::borrow::Cow::Borrowed(&sources[..cells])
    } else {
        let mut padded = sources.to_vec();
        padded.resize(cells, false);
        std::borrow::Cow::Owned(padded)
    }
}

fn transform<T: Copy>(
    sources: &[bool],
    n: usize,
    out: &mut [T],
    scratch: &mut EdtScratch,
    none: T,
    convert: impl Fn(u64) -> T,
) {
    let cells = n * n;
    let out = &mut out[..cells];
    let sources = exactly_cells(sources, cells);
    let Some(cols) = columns(&sources, n, &mut scratch.g) else {
        out.fill(none);
        return;
    };
    scratch.s.resize(cols.w, 0);
    scratch.t.resize(cols.w, 0);
    for (r, dst) in out.chunks_exact_mut(n).enumerate() {
        cols.row(
            &scratch.g,
            r,
            &mut scratch.s,
            &mut scratch.t,
            dst,
            none,
            &convert,
        );
    }
}

/// The column window of a transform and its vertical distances.
#[derive(Clone, Copy, Debug)]
struct Columns {
    n: usize,
    /// First column holding a source, and the window's width (up to the last one).
    c0: usize,
    w: usize,
    /// Larger than any vertical distance: "no source in this column".
    inf: u32,
}

/// Phase 1: the columns between the leftmost and rightmost source, and in `g` (rows × width,
/// row-major) each cell's vertical distance to the nearest source of its column, by a downward
/// then an upward sweep. `None` when there is no source.
fn columns(sources: &[bool], n: usize, g: &mut Vec<u32>) -> Option<Columns> {
    let (mut c0, mut c1) = (usize::MAX, 0usize);
    for row in sources.chunks(n.max(1)) {
        if let Some(first) = row.iter().position(|s| *s) {
            c0 = c0.min(first);
            let last = row.iter().rposition(|s| *s).unwrap_or(first);
            c1 = c1.max(last);
        }
    }
    if c0 == usize::MAX {
        return None;
    }
    let w = c1 - c0 + 1;
    let inf = u32::try_from(n + 1).unwrap_or(u32::MAX);
    g.clear();
    g.resize(n * w, inf);
    for r in 0..n {
        let src = &sources[r * n + c0..r * n + c0 + w];
        let (prev, cur) = g.split_at_mut(r * w);
        let cur = &mut cur[..w];
        if r == 0 {
            for (g, &s) in cur.iter_mut().zip(src) {
                *g = if s { 0 } else { inf };
            }
        } else {
            let above = &prev[(r - 1) * w..];
            for ((g, &s), &a) in cur.iter_mut().zip(src).zip(above) {
                *g = if s { 0 } else { a.saturating_add(1).min(inf) };
            }
        }
    }
    for r in (0..n.saturating_sub(1)).rev() {
        let (cur, next) = g.split_at_mut((r + 1) * w);
        for (g, &b) in cur[r * w..].iter_mut().zip(&next[..w]) {
            *g = (*g).min(b.saturating_add(1));
        }
    }
    Some(Columns { n, c0, w, inf })
}

impl Columns {
    /// Phase 2 for row `r`: the lower envelope of the parabolas `(x - i)² + g(i)²` of the columns
    /// with a finite `g`, written out into `dst` segment by segment. `s` and `t` hold `w` entries.
    #[allow(clippy::too_many_arguments)]
    fn row<T: Copy>(
        &self,
        g: &[u32],
        r: usize,
        s: &mut [u32],
        t: &mut [u32],
        dst: &mut [T],
        none: T,
        convert: &impl Fn(u64) -> T,
    ) {
        let (n, w, c0) = (self.n, self.w, self.c0);
        let row = &g[r * w..(r + 1) * w];
        let h = |j: u32| -> i64 {
            let v = row[j as usize] as i64;
            v * v
        };
        let col = |j: u32| -> i64 { (c0 + j as usize) as i64 };
        let f = |x: i64, j: u32| -> i64 {
            let d = x - col(j);
            d * d + h(j)
        };
        // Last x where parabola i is at most parabola u (i left of u).
        let sep = |i: u32, u: u32| -> i64 {
            let (ci, cu) = (col(i), col(u));
            (cu * cu - ci * ci + h(u) - h(i)).div_euclid(2 * (cu - ci))
        };
        let mut q: isize = -1;
        for u in 0..w as u32 {
            if row[u as usize] >= self.inf {
                continue;
            }
            while q >= 0 && f(t[q as usize] as i64, s[q as usize]) > f(t[q as usize] as i64, u) {
                q -= 1;
            }
            if q < 0 {
                q = 0;
                s[0] = u;
                t[0] = 0;
            } else {
                let start = 1 + sep(s[q as usize], u);
                if start < n as i64 {
                    q += 1;
                    s[q as usize] = u;
                    t[q as usize] = start as u32;
                }
            }
        }
        if q < 0 {
            // No column of this row reaches a source: impossible when a source exists, kept safe.
            dst.fill(none);
            return;
        }
        let q = q as usize;
        for k in 0..=q {
            let from = t[k] as usize;
            let to = if k == q { n } else { t[k + 1] as usize };
            let (cj, hj) = (col(s[k]), h(s[k]));
            for (x, o) in dst[from..to].iter_mut().enumerate() {
                let d = (from + x) as i64 - cj;
                *o = convert((d * d + hj) as u64);
            }
        }
    }
}

/// Squared distances computed a row at a time, on first read. An A* heuristic reads the distance to
/// the goal only on the cells the search pushes, usually a fraction of the rows of a large map, so
/// the per-row envelope pass (most of a transform's cost) is skipped for the rest. Values are the
/// same as [`squared_distances`]. Not `Sync`: one search reads it at a time.
#[derive(Debug, Default)]
pub struct LazySquaredDistances {
    cols: Option<Columns>,
    g: Vec<u32>,
    /// Value + 1 once its row is computed; 0 = not yet.
    table: Vec<Cell<u32>>,
    /// Envelope stacks and one row of output.
    stacks: RefCell<(Vec<u32>, Vec<u32>, Vec<u32>)>,
}

impl LazySquaredDistances {
    /// Runs the column pass over the row-major `n`×`n` mask (side at most [`MAX_U32_SIDE`] for
    /// exact values); rows come later.
    pub fn new(sources: &[bool], n: usize) -> Self {
        let mut lazy = LazySquaredDistances::default();
        lazy.reset(sources, n);
        lazy
    }

    /// Starts over on another mask, keeping the memory (a planner reuses one per stage).
    pub fn reset(&mut self, sources: &[bool], n: usize) {
        let cells = n * n;
        let sources = exactly_cells(sources, cells);
        self.cols = columns(&sources, n, &mut self.g);
        let w = self.cols.map_or(0, |c| c.w);
        let len = if self.cols.is_some() { cells } else { 0 };
        self.table.truncate(len);
        self.table.iter().for_each(|c| c.set(0));
        self.table.resize(len, Cell::new(0));
        let stacks = self.stacks.get_mut();
        stacks.0.resize(w, 0);
        stacks.1.resize(w, 0);
        stacks.2.resize(n, 0);
    }

    /// The squared distance of row-major cell `i`, [`NO_SOURCE`] when there is no source (or `i` is
    /// outside the grid).
    pub fn get(&self, i: usize) -> u32 {
        let Some(cols) = &self.cols else {
            return NO_SOURCE;
        };
        match self.table.get(i).map(Cell::get) {
            None => NO_SOURCE,
            Some(0) => {
                self.fill_row(cols, i / cols.n);
                self.table[i].get() - 1
            }
            Some(v) => v - 1,
        }
    }

    fn fill_row(&self, cols: &Columns, r: usize) {
        let n = cols.n;
        let mut stacks = self.stacks.borrow_mut();
        let (s, t, row) = &mut *stacks;
        cols.row(&self.g, r, s, t, row, NO_SOURCE - 1, &|v| {
            u32::try_from(v).unwrap_or(u32::MAX - 2).min(u32::MAX - 2) + 1
        });
        for (cell, &v) in self.table[r * n..(r + 1) * n].iter().zip(row.iter()) {
            cell.set(v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Cell;
    use proptest::prelude::*;

    fn brute_sq(sources: &[bool], n: usize) -> Vec<Option<u64>> {
        let pts: Vec<(i64, i64)> = (0..n * n)
            .filter(|&i| sources[i])
            .map(|i| ((i / n) as i64, (i % n) as i64))
            .collect();
        (0..n * n)
            .map(|i| {
                let (r, c) = ((i / n) as i64, (i % n) as i64);
                pts.iter()
                    .map(|(pr, pc)| ((r - pr).pow(2) + (c - pc).pow(2)) as u64)
                    .min()
            })
            .collect()
    }

    fn brute(sources: &Grid<bool>) -> Grid<f64> {
        let data = brute_sq(sources.data(), sources.n())
            .into_iter()
            .map(|v| v.map_or(f64::INFINITY, |v| (v as f64).sqrt()))
            .collect();
        Grid::from_vec(sources.n(), data).unwrap()
    }

    #[test]
    fn empty_source_set_is_infinite() {
        let g = distance_field(&Grid::new(4, false));
        assert!(g.data().iter().all(|v| v.is_infinite()));
        assert!(
            squared_distances(&[false; 9], 3)
                .iter()
                .all(|v| *v == NO_SOURCE)
        );
        assert!(distances(&[], 0).is_empty());
        assert!(
            squared_distance_field(&Grid::new(0, false))
                .data()
                .is_empty()
        );
    }

    #[test]
    fn single_source() {
        let mut s = Grid::new(5, false);
        s.set(Cell::new(0, 0), true);
        let g = distance_field(&s);
        assert_eq!(*g.get(Cell::new(0, 2)).unwrap(), 2.0);
        assert_eq!(*g.get(Cell::new(3, 4)).unwrap(), 5.0);
        let sq = squared_distance_field(&s);
        assert_eq!(*sq.get(Cell::new(4, 4)).unwrap(), 32.0);
    }

    #[test]
    fn scratch_is_reusable_across_sizes_and_sparsity() {
        let mut scratch = EdtScratch::default();
        let mut out = Vec::new();
        for (n, density) in [(30usize, 3u32), (7, 50), (30, 90), (1, 100), (12, 0)] {
            let src: Vec<bool> = (0..n * n)
                .map(|i| (i as u32).wrapping_mul(2_654_435_761) % 100 < density)
                .collect();
            squared_distances_into(&src, n, &mut out, &mut scratch);
            let want: Vec<u32> = brute_sq(&src, n)
                .into_iter()
                .map(|v| v.map_or(NO_SOURCE, |v| v as u32))
                .collect();
            assert_eq!(out, want, "n = {n}, density {density}");
        }
    }

    #[test]
    fn lazy_without_sources_or_out_of_range() {
        let mut lazy = LazySquaredDistances::new(&[false; 16], 4);
        assert_eq!(lazy.get(5), NO_SOURCE);
        lazy.reset(&[true], 1);
        assert_eq!(lazy.get(0), 0);
        assert_eq!(lazy.get(1), NO_SOURCE);
        // Reset after use forgets the rows computed for the previous mask.
        let mut src = vec![false; 25];
        src[0] = true;
        lazy.reset(&src, 5);
        assert_eq!(lazy.get(24), 32);
        src[0] = false;
        src[24] = true;
        lazy.reset(&src, 5);
        assert_eq!(lazy.get(24), 0);
        assert_eq!(lazy.get(0), 32);
    }

    proptest! {
        /// Read in a scrambled order, so rows are filled in any order and some twice over.
        #[test]
        fn lazy_equals_eager(
            n in 1usize..40,
            bits in proptest::collection::vec(any::<u8>(), 1600),
            density in 1u8..60,
            stride in 1usize..97,
        ) {
            let data: Vec<bool> = (0..n * n).map(|i| bits[i] < density).collect();
            let eager = squared_distances(&data, n);
            let lazy = LazySquaredDistances::new(&data, n);
            for k in 0..n * n {
                let i = (k * stride + k / 3) % (n * n);
                prop_assert_eq!(lazy.get(i), eager[i]);
            }
        }

        #[test]
        fn matches_brute_force(n in 1usize..24, bits in proptest::collection::vec(any::<u8>(), 576)) {
            let data: Vec<bool> = (0..n * n).map(|i| bits[i] < 20).collect();
            let s = Grid::from_vec(n, data).unwrap();
            let fast = distance_field(&s);
            let slow = brute(&s);
            prop_assert_eq!(fast.data(), slow.data());
        }

        /// Sparse and dense masks, including sources confined to a few columns (the column window).
        #[test]
        fn squared_matches_brute_force(
            n in 1usize..40,
            bits in proptest::collection::vec(any::<u8>(), 1600),
            density in 1u8..255,
            band in 0usize..40,
        ) {
            let data: Vec<bool> = (0..n * n)
                .map(|i| bits[i] < density && (i % n) >= band.min(n - 1) / 2 && (i % n) <= band)
                .collect();
            let want = brute_sq(&data, n);
            let sq = squared_distances(&data, n);
            let as_f64 = squared_distance_field(&Grid::from_vec(n, data).unwrap());
            for i in 0..n * n {
                prop_assert_eq!(sq[i], want[i].map_or(NO_SOURCE, |v| v as u32));
                prop_assert_eq!(as_f64.data()[i], want[i].map_or(f64::INFINITY, |v| v as f64));
            }
        }
    }
}
