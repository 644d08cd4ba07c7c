//! Region membership and segment/region intersection, with the reference evaluator's exact
//! tolerances: every geometric metric (HCS crossing, must-avoid hits, SPL's legal moves, soft
//! region waypoints) is decided here, so tie and touch rules live in one place.
//!
//! A cell is the unit square `[r-0.5, r+0.5] x [c-0.5, c+0.5]` around its integer centre, and a
//! route segment is the straight line between two waypoints. Touching a boundary counts.

use crate::episode::{CellRc, HardConstraint, Shape, SoftConstraint};
use std::collections::HashMap;

/// The reference's `EVALUATION_EPSILON`, used by every geometric tolerance.
pub const EPSILON: f64 = 1e-6;

/// A point `[row, col]` in cell units.
pub type Point = [f64; 2];

/// A validated region. Built from a constraint's `shape` / `center` / `radius` / `width` /
/// `height` / `cells`, with the reference's validation (no defaults: a circle needs a positive
/// radius, a rectangle a positive width and height, a freeform region a cell list).
#[derive(Clone, Debug)]
pub enum Geom {
    Circle {
        center: Point,
        radius: f64,
    },
    /// `height` runs along rows, `width` along cols.
    Rect {
        center: Point,
        width: f64,
        height: f64,
    },
    Freeform(Freeform),
}

/// A freeform region: a union of unit cells, in file order (the order breaks ties between
/// cells a segment enters at the same parameter).
#[derive(Clone, Debug)]
pub struct Freeform {
    pub cells: Vec<CellRc>,
    /// First index of each distinct cell in `cells`.
    index: HashMap<(i64, i64), usize>,
    /// Inclusive bounding box of the cells: `[row_min, row_max, col_min, col_max]`.
    bbox: Option<[i64; 4]>,
}

impl Freeform {
    pub fn new(cells: Vec<CellRc>) -> Self {
        let mut index = HashMap::with_capacity(cells.len());
        let mut bbox: Option<[i64; 4]> = None;
        for (i, c) in cells.iter().enumerate() {
            index.entry((c[0], c[1])).or_insert(i);
            bbox = Some(match bbox {
                None => [c[0], c[0], c[1], c[1]],
                Some([r0, r1, c0, c1]) => [r0.min(c[0]), r1.max(c[0]), c0.min(c[1]), c1.max(c[1])],
            });
        }
        Freeform { cells, index, bbox }
    }

    pub fn contains(&self, row: i64, col: i64) -> bool {
        self.index.contains_key(&(row, col))
    }

    pub fn bbox(&self) -> Option<[i64; 4]> {
        self.bbox
    }
}

/// The raw region fields of a constraint, before validation.
#[derive(Clone, Copy, Debug)]
pub struct RegionSpec<'a> {
    pub shape: Option<Shape>,
    pub center: Option<[f64; 2]>,
    pub radius: Option<f64>,
    pub width: Option<f64>,
    pub height: Option<f64>,
    pub cells: Option<&'a [CellRc]>,
}

impl<'a> RegionSpec<'a> {
    pub fn of_hard(c: &'a HardConstraint) -> Self {
        RegionSpec {
            shape: Some(c.shape),
            center: c.center,
            radius: c.radius,
            width: c.width,
            height: c.height,
            cells: c.cells.as_deref(),
        }
    }

    pub fn of_soft(c: &'a SoftConstraint) -> Self {
        RegionSpec {
            shape: c.shape,
            center: c.center,
            radius: c.radius,
            width: c.width,
            height: c.height,
            cells: c.cells.as_deref(),
        }
    }
}

/// Validates a region the way the reference's point and segment tests do; the message names
/// the offending key.
pub fn compile(spec: RegionSpec<'_>) -> Result<Geom, String> {
    match spec.shape {
        Some(Shape::Freeform) => match spec.cells {
            Some(cells) => Ok(Geom::Freeform(Freeform::new(cells.to_vec()))),
            None => Err("freeform constraint cells must be a list".into()),
        },
        Some(Shape::Circle) => {
            let center = spec.center.ok_or("constraint center must be [row, col]")?;
            match spec.radius {
                Some(r) if r > 0.0 && r.is_finite() => Ok(Geom::Circle { center, radius: r }),
                _ => Err("circle constraint radius must be positive".into()),
            }
        }
        Some(Shape::Rectangle) => {
            let center = spec.center.ok_or("constraint center must be [row, col]")?;
            match (spec.width, spec.height) {
                (Some(w), Some(h)) if w > 0.0 && h > 0.0 && w.is_finite() && h.is_finite() => {
                    Ok(Geom::Rect {
                        center,
                        width: w,
                        height: h,
                    })
                }
                _ => Err("rectangle constraint width and height must be positive".into()),
            }
        }
        None => Err("unknown constraint shape: none given".into()),
    }
}

impl Geom {
    /// Inclusive membership of a point (cell centre).
    pub fn contains(&self, p: Point) -> bool {
        match self {
            Geom::Circle { center, radius } => {
                (p[0] - center[0]).hypot(p[1] - center[1]) <= *radius
            }
            Geom::Rect {
                center,
                width,
                height,
            } => {
                (p[0] - center[0]).abs() <= height / 2.0 && (p[1] - center[1]).abs() <= width / 2.0
            }
            Geom::Freeform(f) => {
                p[0].fract() == 0.0
                    && p[1].fract() == 0.0
                    && p[0].abs() < 9.0e15
                    && p[1].abs() < 9.0e15
                    && f.contains(p[0] as i64, p[1] as i64)
            }
        }
    }

    pub fn contains_cell(&self, row: i64, col: i64) -> bool {
        match self {
            Geom::Freeform(f) => f.contains(row, col),
            _ => self.contains([row as f64, col as f64]),
        }
    }

    /// Bounding box `[row_min, row_max, col_min, col_max]` in continuous coordinates (freeform
    /// cells contribute their centres); `None` for an empty freeform region.
    pub fn bbox(&self) -> Option<[f64; 4]> {
        match self {
            Geom::Circle { center, radius } => Some([
                center[0] - radius,
                center[0] + radius,
                center[1] - radius,
                center[1] + radius,
            ]),
            Geom::Rect {
                center,
                width,
                height,
            } => Some([
                center[0] - height / 2.0,
                center[0] + height / 2.0,
                center[1] - width / 2.0,
                center[1] + width / 2.0,
            ]),
            Geom::Freeform(f) => f
                .bbox()
                .map(|[r0, r1, c0, c1]| [r0 as f64, r1 as f64, c0 as f64, c1 as f64]),
        }
    }

    /// The parameter interval `[t_enter, t_exit]` within `[0, 1]` where segment `a -> b` meets
    /// the region, or `None`. For a freeform region, the interval of the cell entered first
    /// (the earliest cell in file order on ties), as the reference returns.
    pub fn segment_interval(&self, a: Point, b: Point) -> Option<(f64, f64)> {
        match self {
            Geom::Circle { center, radius } => circle_interval(a, b, *center, *radius),
            Geom::Rect {
                center,
                width,
                height,
            } => rect_interval(
                a,
                b,
                center[0] - height / 2.0,
                center[0] + height / 2.0,
                center[1] - width / 2.0,
                center[1] + width / 2.0,
            ),
            Geom::Freeform(f) => freeform_interval(f, a, b),
        }
    }

    pub fn segment_intersects(&self, a: Point, b: Point) -> bool {
        self.segment_interval(a, b).is_some()
    }
}

/// Slab test against an axis-aligned box; touching counts.
pub fn rect_interval(
    a: Point,
    b: Point,
    row_min: f64,
    row_max: f64,
    col_min: f64,
    col_max: f64,
) -> Option<(f64, f64)> {
    let mut t_min = 0.0f64;
    let mut t_max = 1.0f64;
    for (start, delta, low, high) in [
        (a[0], b[0] - a[0], row_min, row_max),
        (a[1], b[1] - a[1], col_min, col_max),
    ] {
        if delta.abs() <= EPSILON {
            if start < low || start > high {
                return None;
            }
            continue;
        }
        let first = (low - start) / delta;
        let second = (high - start) / delta;
        t_min = t_min.max(first.min(second));
        t_max = t_max.min(first.max(second));
        if t_min - t_max > EPSILON {
            return None;
        }
    }
    Some((t_min.max(0.0), t_max.min(1.0)))
}

/// Segment against a disc, by the quadratic in the segment parameter.
pub fn circle_interval(a: Point, b: Point, center: Point, radius: f64) -> Option<(f64, f64)> {
    let dr = b[0] - a[0];
    let dc = b[1] - a[1];
    let sr = a[0] - center[0];
    let sc = a[1] - center[1];
    let qa = dr * dr + dc * dc;
    let qc = sr * sr + sc * sc - radius * radius;
    if qa <= EPSILON {
        return if qc <= EPSILON {
            Some((0.0, 1.0))
        } else {
            None
        };
    }
    let qb = 2.0 * (sr * dr + sc * dc);
    let mut disc = qb * qb - 4.0 * qa * qc;
    if disc < -EPSILON {
        return None;
    }
    if disc < 0.0 {
        disc = 0.0;
    }
    let root = disc.sqrt();
    let first = (-qb - root) / (2.0 * qa);
    let second = (-qb + root) / (2.0 * qa);
    let enter = first.min(second).max(0.0);
    let exit = first.max(second).min(1.0);
    if enter - exit > EPSILON || exit < -EPSILON || enter > 1.0 + EPSILON {
        return None;
    }
    Some((enter, exit))
}

fn cell_interval(a: Point, b: Point, row: i64, col: i64) -> Option<(f64, f64)> {
    let (r, c) = (row as f64, col as f64);
    rect_interval(a, b, r - 0.5, r + 0.5, c - 0.5, c + 0.5)
}

/// Earliest-entered cell of a freeform region. Only cells near the segment can meet it, so a
/// short segment looks up the cells around it instead of scanning the whole region.
fn freeform_interval(f: &Freeform, a: Point, b: Point) -> Option<(f64, f64)> {
    if f.cells.is_empty() {
        return None;
    }
    // Cells whose square comes within one cell of the segment's bounding box.
    let r0 = (a[0].min(b[0]) - 1.5).floor();
    let r1 = (a[0].max(b[0]) + 1.5).ceil();
    let c0 = (a[1].min(b[1]) - 1.5).floor();
    let c1 = (a[1].max(b[1]) + 1.5).ceil();
    let area = (r1 - r0 + 1.0) * (c1 - c0 + 1.0);
    let mut best: Option<(f64, usize, (f64, f64))> = None;
    let mut consider = |idx: usize, row: i64, col: i64| {
        if let Some(iv) = cell_interval(a, b, row, col) {
            let better = match best {
                None => true,
                Some((enter, bi, _)) => iv.0 < enter || (iv.0 == enter && idx < bi),
            };
            if better {
                best = Some((iv.0, idx, iv));
            }
        }
    };
    if area.is_finite() && area < f.index.len() as f64 {
        for row in r0 as i64..=r1 as i64 {
            for col in c0 as i64..=c1 as i64 {
                if let Some(&idx) = f.index.get(&(row, col)) {
                    consider(idx, row, col);
                }
            }
        }
    } else {
        for (idx, cell) in f.cells.iter().enumerate() {
            consider(idx, cell[0], cell[1]);
        }
    }
    best.map(|(_, _, iv)| iv)
}

/// Whether a polyline touches a region: a waypoint inside, or a segment meeting it.
pub fn polyline_hits(points: &[Point], g: &Geom) -> bool {
    points.iter().any(|&p| g.contains(p))
        || points.windows(2).any(|w| g.segment_intersects(w[0], w[1]))
}

/// Converts integer waypoints to points.
pub fn to_points(cells: &[[i64; 2]]) -> Vec<Point> {
    cells.iter().map(|c| [c[0] as f64, c[1] as f64]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ff(cells: &[[i64; 2]]) -> Geom {
        Geom::Freeform(Freeform::new(cells.to_vec()))
    }

    #[test]
    fn diagonal_touches_corner_cells_at_half() {
        assert_eq!(
            ff(&[[0, 1]]).segment_interval([0.0, 0.0], [1.0, 1.0]),
            Some((0.5, 0.5))
        );
        assert_eq!(
            ff(&[[1, 0]]).segment_interval([0.0, 0.0], [1.0, 1.0]),
            Some((0.5, 0.5))
        );
    }

    #[test]
    fn straight_move_only_touches_entered_cells() {
        let g = ff(&[[1, 1]]);
        assert!(g.segment_interval([0.0, 0.0], [0.0, 1.0]).is_none());
        assert!(
            ff(&[[0, 2]])
                .segment_interval([0.0, 0.0], [0.0, 1.0])
                .is_none()
        );
        assert_eq!(
            ff(&[[0, 1]]).segment_interval([0.0, 0.0], [0.0, 2.0]),
            Some((0.25, 0.75))
        );
    }

    #[test]
    fn freeform_ties_take_the_first_cell_in_file_order() {
        // Both cells are entered at t = 0.5; the first listed decides the exit.
        let g = ff(&[[0, 1], [1, 1]]);
        assert_eq!(g.segment_interval([0.0, 0.0], [1.0, 1.0]), Some((0.5, 0.5)));
        let g = ff(&[[1, 1], [0, 1]]);
        assert_eq!(g.segment_interval([0.0, 0.0], [1.0, 1.0]), Some((0.5, 1.0)));
    }

    #[test]
    fn long_segments_scan_all_cells_and_short_ones_look_up() {
        let cells: Vec<[i64; 2]> = (0..50).map(|c| [3, c]).collect();
        let g = ff(&cells);
        let iv = g.segment_interval([3.0, 60.0], [3.0, 0.0]).unwrap();
        assert!((iv.0 - 10.5 / 60.0).abs() < 1e-12);
        assert!(g.segment_interval([0.0, 0.0], [1.0, 1.0]).is_none());
        assert!(g.segment_interval([2.0, 0.0], [2.0, 1.0]).is_none());
    }

    #[test]
    fn circle_interval_and_degenerate_segment() {
        let iv = circle_interval([0.0, -2.0], [0.0, 2.0], [0.0, 0.0], 1.0).unwrap();
        assert!((iv.0 - 0.25).abs() < 1e-12 && (iv.1 - 0.75).abs() < 1e-12);
        assert_eq!(
            circle_interval([0.0, 0.5], [0.0, 0.5], [0.0, 0.0], 1.0),
            Some((0.0, 1.0))
        );
        assert_eq!(
            circle_interval([0.0, 2.0], [0.0, 2.0], [0.0, 0.0], 1.0),
            None
        );
        // Tangent touch counts.
        assert!(circle_interval([1.0, -2.0], [1.0, 2.0], [0.0, 0.0], 1.0).is_some());
        assert!(circle_interval([0.0, 2.0], [0.0, 3.0], [0.0, 0.0], 1.0).is_none());
    }

    #[test]
    fn rectangle_membership_is_inclusive() {
        let g = Geom::Rect {
            center: [2.0, 2.0],
            width: 2.0,
            height: 4.0,
        };
        assert!(g.contains([0.0, 1.0]));
        assert!(!g.contains([0.0, 0.0]));
        assert!(g.segment_intersects([0.0, 0.0], [0.0, 1.0]));
    }

    #[test]
    fn compile_rejects_missing_radius() {
        let spec = RegionSpec {
            shape: Some(Shape::Circle),
            center: Some([1.0, 1.0]),
            radius: None,
            width: None,
            height: None,
            cells: None,
        };
        assert!(compile(spec).unwrap_err().contains("radius"));
    }
}
