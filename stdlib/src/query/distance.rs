//! Distances between places: straight-line between footprints, and travel (geodesic) distance over
//! the traversable grid.

use super::{MapQuery, Target};
use crate::grid::{Cell, Grid};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// How far from a place its travel band reaches (the planner's goal band around objects), metres.
const APPROACH_M: f64 = 0.3;
/// How far the band may reach when no free cell lies that close, metres.
const BAND_SEARCH_M: f64 = 0.6;

impl MapQuery<'_> {
    /// Shortest straight-line distance between the cells of `a` and `b`, metres (0 when they share
    /// a cell); `None` when either has no cells.
    pub fn distance(&self, a: Target, b: Target) -> Option<f64> {
        self.distance_cells(a, b).map(|d| d * self.res())
    }

    /// [`MapQuery::distance`] in cells.
    pub fn distance_cells(&self, a: Target, b: Target) -> Option<f64> {
        let (ca, cb) = (self.cells(a), self.cells(b));
        if ca.is_empty() || cb.is_empty() {
            return None;
        }
        if self.overlap(a, b) {
            return Some(0.0);
        }
        // Scan the smaller rim; search the larger, sorted one by rows.
        let (oa, ob) = match (self.rim(a), self.rim(b)) {
            (x, y) if x.len() <= y.len() => (x, y),
            (x, y) => (y, x),
        };
        let bb = bbox(ob);
        let sorted = ob.is_sorted();
        let mut best = f64::INFINITY;
        for &p in oa {
            // The bounding box of `ob` bounds every distance from `p` from below.
            if bbox_dist2(p, bb) >= best {
                continue;
            }
            best = if sorted {
                nearest_sq_sorted(p, ob, best)
            } else {
                nearest_sq(p, ob, best)
            };
        }
        Some(best.sqrt())
    }

    /// Where travel to or from a place starts: its own traversable cells; for a place with none
    /// (furniture), the free cells within 0.3 m of it (Chebyshev), else those within 0.6 m; for an
    /// object with neither (a card on a sofa), the planner's goal fallback
    /// ([`MapQuery::room_fallback`]), so that a stage starting at it has somewhere to start from.
    pub fn band(&self, t: Target) -> Vec<Cell> {
        let cells = self.cells(t);
        let mut out: Vec<Cell> = cells
            .iter()
            .copied()
            .filter(|&c| self.is_traversable(c))
            .collect();
        let n = self.map.n() as i64;
        let reach = [
            (APPROACH_M / self.res()).ceil().max(1.0) as i64,
            (BAND_SEARCH_M / self.res()).ceil().max(1.0) as i64,
        ];
        for r in reach {
            if !out.is_empty() {
                break;
            }
            for &c in self.outline(t) {
                for dr in -r..=r {
                    for dc in -r..=r {
                        let (y, x) = (c.row as i64 + dr, c.col as i64 + dc);
                        if y < 0 || x < 0 || y >= n || x >= n {
                            continue;
                        }
                        let q = Cell::new(y as u32, x as u32);
                        if self.is_traversable(q) {
                            out.push(q);
                        }
                    }
                }
            }
        }
        if out.is_empty()
            && let Target::Object(o) = t
            && let Some(c) = o.room.and_then(|r| self.room_fallback(r, o.center))
        {
            out.push(c);
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The planner's goal for an object with no free cell near it, as the reference plans it
    /// (method notes §4.2): the traversable cell of `room` nearest `center` (ties: lower row, then
    /// lower column). The verifier and the band of an object share it, so a destination the
    /// planner reaches is also a place the next stage can start from.
    pub fn room_fallback(&self, room: u32, center: [f64; 2]) -> Option<Cell> {
        self.room_cells(room)
            .iter()
            .copied()
            .filter(|&c| self.is_traversable(c))
            .min_by(|a, b| {
                let d = |c: Cell| {
                    let (dr, dc) = (c.row as f64 - center[0], c.col as f64 - center[1]);
                    dr * dr + dc * dc
                };
                d(*a).total_cmp(&d(*b)).then_with(|| a.cmp(b))
            })
    }

    /// Travel distances from the band of `from` to every cell.
    pub fn travel_field(&self, from: Target) -> TravelField {
        TravelField::new(&self.traversable, &self.band(from), self.res())
    }

    /// Travel distance between two places, metres; `None` when there is no traversable path.
    pub fn travel_distance(&self, a: Target, b: Target) -> Option<f64> {
        self.travel_field(a).to(&self.band(b))
    }
}

/// Geodesic distances over the traversable grid: 8-connected, diagonal steps √2, no corner cutting
/// (a diagonal step needs both orthogonal neighbours traversable), as the planner moves.
pub struct TravelField {
    dist: Grid<f64>,
    res: f64,
}

#[derive(PartialEq)]
struct Item(f64, usize);
impl Eq for Item {}
impl Ord for Item {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then_with(|| o.1.cmp(&self.1))
    }
}
impl PartialOrd for Item {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl TravelField {
    /// Dijkstra from every source cell (distance 0).
    pub fn new(traversable: &Grid<bool>, sources: &[Cell], res: f64) -> Self {
        let n = traversable.n();
        let mut dist = Grid::new(n, f64::INFINITY);
        let mut heap = BinaryHeap::new();
        for &s in sources {
            if traversable.get(s) == Some(&true) {
                dist.set(s, 0.0);
                heap.push(Item(0.0, traversable.index(s)));
            }
        }
        let free = traversable.data();
        while let Some(Item(d, i)) = heap.pop() {
            if d > dist.data()[i] {
                continue;
            }
            for (j, diagonal) in steps_from(free, n, i) {
                let nd = d + if diagonal {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                };
                if nd < dist.data()[j] {
                    dist.data_mut()[j] = nd;
                    heap.push(Item(nd, j));
                }
            }
        }
        TravelField { dist, res }
    }

    /// The cells [`TravelField::new`] gives a finite distance, by a flood fill: what a check
    /// that only asks "can it be reached" needs, at a fraction of the cost of the distances.
    pub fn reachable(traversable: &Grid<bool>, sources: &[Cell]) -> Grid<bool> {
        let n = traversable.n();
        let free = traversable.data();
        let mut seen = Grid::new(n, false);
        let mut stack = Vec::new();
        for &s in sources {
            if traversable.get(s) == Some(&true) && seen.get(s) == Some(&false) {
                seen.set(s, true);
                stack.push(traversable.index(s));
            }
        }
        while let Some(i) = stack.pop() {
            for (j, _) in steps_from(free, n, i) {
                if !seen.data()[j] {
                    seen.data_mut()[j] = true;
                    stack.push(j);
                }
            }
        }
        seen
    }

    /// Distance in cells to one cell (`INFINITY` when unreachable or outside the grid).
    pub fn cells_to(&self, cell: Cell) -> f64 {
        self.dist.get(cell).copied().unwrap_or(f64::INFINITY)
    }

    /// Shortest travel distance to any of `cells`, metres; `None` when none is reachable.
    pub fn to(&self, cells: &[Cell]) -> Option<f64> {
        let d = cells
            .iter()
            .map(|&c| self.cells_to(c))
            .fold(f64::INFINITY, f64::min);
        d.is_finite().then_some(d * self.res)
    }

    /// One shortest path from the sources to `goal` (inclusive), following decreasing distance;
    /// `None` when `goal` is unreachable.
    pub fn path_to(&self, traversable: &Grid<bool>, goal: Cell) -> Option<Vec<Cell>> {
        let n = self.dist.n();
        if !self.cells_to(goal).is_finite() {
            return None;
        }
        let mut path = vec![goal];
        let mut cur = goal;
        while self.cells_to(cur) > 0.0 {
            let (r, c) = (cur.row as i64, cur.col as i64);
            let mut best: Option<(f64, Cell)> = None;
            for (dr, dc) in STEPS {
                let (y, x) = (r + dr, c + dc);
                if !traversable.contains(y, x) {
                    continue;
                }
                let q = Cell::new(y as u32, x as u32);
                let diagonal = dr != 0 && dc != 0;
                let free = |yy: i64, xx: i64| traversable.data()[yy as usize * n + xx as usize];
                if diagonal && !(free(r, x) && free(y, c)) {
                    continue;
                }
                let step = if diagonal {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                };
                let dq = self.cells_to(q);
                if (dq + step - self.cells_to(cur)).abs() < 1e-9
                    && best.is_none_or(|(bd, _)| dq < bd)
                {
                    best = Some((dq, q));
                }
            }
            let (_, next) = best?;
            path.push(next);
            cur = next;
            if path.len() > n * n {
                return None;
            }
        }
        path.reverse();
        Some(path)
    }
}

/// 8-neighbour steps: orthogonal first, then diagonal, so ties are broken the same way everywhere.
pub(crate) const STEPS: [(i64, i64); 8] = [
    (-1, 0),
    (1, 0),
    (0, -1),
    (0, 1),
    (-1, -1),
    (-1, 1),
    (1, -1),
    (1, 1),
];

/// The cells one step from row-major cell `i` of an `n` x `n` grid with free cells `free`, and
/// whether the step is diagonal: 8-connected, a diagonal only when both orthogonal neighbours it
/// passes are free (the planner's no-corner-cutting rule).
fn steps_from(free: &[bool], n: usize, i: usize) -> impl Iterator<Item = (usize, bool)> + '_ {
    let (r, c) = ((i / n) as i64, (i % n) as i64);
    let side = n as i64;
    STEPS.iter().filter_map(move |&(dr, dc)| {
        let (y, x) = (r + dr, c + dc);
        if y < 0 || x < 0 || y >= side || x >= side {
            return None;
        }
        let j = y as usize * n + x as usize;
        let diagonal = dr != 0 && dc != 0;
        let corners_free =
            || free[r as usize * n + x as usize] && free[y as usize * n + c as usize];
        (free[j] && (!diagonal || corners_free())).then_some((j, diagonal))
    })
}

/// `(min_row, min_col, max_row, max_col)`.
/// The smaller of `best` and the least squared distance from `p` to a cell of `cells`.
fn nearest_sq(p: Cell, cells: &[Cell], mut best: f64) -> f64 {
    for &q in cells {
        let dr = p.row as f64 - q.row as f64;
        let dc = p.col as f64 - q.col as f64;
        best = best.min(dr * dr + dc * dc);
    }
    best
}

/// [`nearest_sq`] over cells sorted row-major: rows are visited outward from `p`'s row and the
/// scan stops once the row gap alone reaches `best`, so only the rows near `p` are read. Exact:
/// the same minimum as the full scan.
fn nearest_sq_sorted(p: Cell, cells: &[Cell], mut best: f64) -> f64 {
    let split = cells.partition_point(|q| q.row < p.row);
    let (r, c) = (p.row as f64, p.col as f64);
    for q in &cells[split..] {
        let dr = q.row as f64 - r;
        if dr * dr >= best {
            break;
        }
        let dc = q.col as f64 - c;
        best = best.min(dr * dr + dc * dc);
    }
    for q in cells[..split].iter().rev() {
        let dr = r - q.row as f64;
        if dr * dr >= best {
            break;
        }
        let dc = q.col as f64 - c;
        best = best.min(dr * dr + dc * dc);
    }
    best
}

fn bbox(cells: &[Cell]) -> (f64, f64, f64, f64) {
    let mut b = (
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    );
    for c in cells {
        let (r, k) = (c.row as f64, c.col as f64);
        b = (b.0.min(r), b.1.min(k), b.2.max(r), b.3.max(k));
    }
    b
}

fn bbox_dist2(p: Cell, b: (f64, f64, f64, f64)) -> f64 {
    let (r, c) = (p.row as f64, p.col as f64);
    let dr = (b.0 - r).max(0.0).max(r - b.2);
    let dc = (b.1 - c).max(0.0).max(c - b.3);
    dr * dr + dc * dc
}

#[cfg(test)]
mod tests {
    use super::super::fixture::two_rooms;
    use super::*;

    #[test]
    fn footprint_distance_is_gap_not_centre_distance() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let bed = map.object(1).unwrap();
        let lamp = map.object(2).unwrap();
        // bed cols 2..=5, lamp col 7: gap of 2 cells between col 5 and col 7.
        let d = q
            .distance_cells(Target::Object(bed), Target::Object(lamp))
            .unwrap();
        assert!((d - 2.0).abs() < 1e-9, "{d}");
        assert_eq!(q.distance(Target::Object(bed), Target::Room(1)), Some(0.0));
    }

    #[test]
    fn distances_equal_the_all_pairs_minimum() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let regions = [
            vec![Cell::new(0, 0)],
            vec![Cell::new(5, 9), Cell::new(6, 9)],
        ];
        let mut targets: Vec<Target> = map.objects.iter().map(Target::Object).collect();
        targets.extend(map.rooms.iter().map(|r| Target::Room(r.id)));
        targets.extend(regions.iter().map(|c| Target::Cells(c)));
        for &a in &targets {
            for &b in &targets {
                let mut best = f64::INFINITY;
                for p in q.cells(a) {
                    for r in q.cells(b) {
                        let (dr, dc) = (p.row as f64 - r.row as f64, p.col as f64 - r.col as f64);
                        best = best.min(dr * dr + dc * dc);
                    }
                }
                let want = best.is_finite().then(|| best.sqrt());
                assert_eq!(q.distance_cells(a, b), want, "{a:?} {b:?}");
            }
        }
    }

    proptest::proptest! {
        /// The row-pruned scan finds the same minimum as the full one, from any starting bound.
        #[test]
        fn sorted_scan_equals_full_scan(
            pts in proptest::collection::vec((0u32..40, 0u32..40), 1..60),
            p in (0u32..40, 0u32..40),
            bound in proptest::prop_oneof![proptest::strategy::Just(f64::INFINITY), 0.0f64..900.0],
        ) {
            let mut cells: Vec<Cell> = pts.iter().map(|&(r, c)| Cell::new(r, c)).collect();
            cells.sort();
            cells.dedup();
            let p = Cell::new(p.0, p.1);
            proptest::prop_assert_eq!(
                nearest_sq_sorted(p, &cells, bound).to_bits(),
                nearest_sq(p, &cells, bound).to_bits()
            );
        }
    }

    #[test]
    fn travel_distance_goes_around_walls() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let a = [Cell::new(2, 2)];
        let b = [Cell::new(2, 12)];
        let straight = q
            .distance_cells(Target::Cells(&a), Target::Cells(&b))
            .unwrap();
        let travel = q
            .travel_distance(Target::Cells(&a), Target::Cells(&b))
            .unwrap()
            / q.res();
        // The wall at col 9 has its only door at row 8, so travel is longer than 10 cells.
        assert!(
            travel > straight + 3.0,
            "travel {travel} straight {straight}"
        );
        let field = q.travel_field(Target::Cells(&a));
        let path = field.path_to(q.traversable(), Cell::new(2, 12)).unwrap();
        assert!(path.contains(&Cell::new(8, 9)));
        for w in path.windows(2) {
            assert!(w[0].dist(w[1]) < 1.5);
        }
    }

    proptest::proptest! {
        /// The flood fill reaches exactly the cells the distance field gives a finite distance,
        /// corner rule included.
        #[test]
        fn reachable_is_where_the_travel_distance_is_finite(
            n in 1usize..12,
            bits in proptest::collection::vec(proptest::bool::weighted(0.7), 144),
            sources in proptest::collection::vec((0u32..12, 0u32..12), 0..3),
        ) {
            let t = Grid::from_vec(n, bits[..n * n].to_vec()).unwrap();
            let sources: Vec<Cell> = sources.into_iter().map(|(r, c)| Cell::new(r, c)).collect();
            let field = TravelField::new(&t, &sources, 1.0);
            let reach = TravelField::reachable(&t, &sources);
            for (cell, &seen) in reach.iter_cells() {
                proptest::prop_assert_eq!(seen, field.cells_to(cell).is_finite(), "{:?}", cell);
            }
        }
    }
}
