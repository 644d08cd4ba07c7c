//! Rasterization by the reference's cell-centre rule: a cell belongs to a shape when its centre
//! lies inside it or on its boundary (tolerance 1e-9 m). Every routine scans only the shape's
//! bounding box, which keeps a whole-house import in the low milliseconds.

use crate::grid::Cell;

const EPS: f64 = 1e-9;

/// Where an N×N grid sits in the world: cell `(r, c)` has its centre at
/// `(x_min + c * res, z_min + r * res)`.
#[derive(Clone, Copy, Debug)]
pub struct Raster {
    pub x_min: f64,
    pub z_min: f64,
    pub res: f64,
    pub n: usize,
}

impl Raster {
    /// Index range of cell centres within `[lo, hi]` along one axis starting at `origin`.
    fn range(&self, origin: f64, lo: f64, hi: f64) -> Option<(usize, usize)> {
        let a = ((lo - origin) / self.res - EPS).ceil().max(0.0);
        let b = ((hi - origin) / self.res + EPS)
            .floor()
            .min(self.n as f64 - 1.0);
        (a <= b && b >= 0.0).then_some((a as usize, b as usize))
    }

    pub fn centre(&self, row: usize, col: usize) -> [f64; 2] {
        [
            self.x_min + col as f64 * self.res,
            self.z_min + row as f64 * self.res,
        ]
    }

    /// The cell containing world `(x, z)`, rounding half to even like Python's `round`.
    pub fn cell_of(&self, x: f64, z: f64) -> Option<Cell> {
        let c = ((x - self.x_min) / self.res).round_ties_even();
        let r = ((z - self.z_min) / self.res).round_ties_even();
        let n = self.n as f64;
        (r >= 0.0 && c >= 0.0 && r < n && c < n).then(|| Cell::new(r as u32, c as u32))
    }

    /// Nearest in-grid cell to world `(x, z)`, clamping points outside the grid.
    pub fn clamp_cell(&self, x: f64, z: f64) -> Cell {
        let hi = self.n.saturating_sub(1) as f64;
        let c = ((x - self.x_min) / self.res)
            .round_ties_even()
            .clamp(0.0, hi);
        let r = ((z - self.z_min) / self.res)
            .round_ties_even()
            .clamp(0.0, hi);
        Cell::new(r as u32, c as u32)
    }

    /// Cells whose centre is inside `poly` (`(x, z)` vertices) or on its boundary.
    pub fn polygon_cells(&self, poly: &[[f64; 2]]) -> Vec<Cell> {
        let mut out = Vec::new();
        if poly.len() < 3 {
            return out;
        }
        let (mut x0, mut x1, mut z0, mut z1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for p in poly {
            x0 = x0.min(p[0]);
            x1 = x1.max(p[0]);
            z0 = z0.min(p[1]);
            z1 = z1.max(p[1]);
        }
        let (Some((c0, c1)), Some((r0, r1))) = (
            self.range(self.x_min, x0, x1),
            self.range(self.z_min, z0, z1),
        ) else {
            return out;
        };
        for r in r0..=r1 {
            for c in c0..=c1 {
                if inside_or_on(self.centre(r, c), poly) {
                    out.push(Cell::new(r as u32, c as u32));
                }
            }
        }
        out
    }

    /// Cells whose centre lies within `half_width` of segment `a-b`, each with its position along
    /// the segment (metres from `a`, clamped to the segment).
    pub fn segment_cells(&self, a: [f64; 2], b: [f64; 2], half_width: f64) -> Vec<(Cell, f64)> {
        let mut out = Vec::new();
        let hw = half_width + EPS;
        let (Some((c0, c1)), Some((r0, r1))) = (
            self.range(self.x_min, a[0].min(b[0]) - hw, a[0].max(b[0]) + hw),
            self.range(self.z_min, a[1].min(b[1]) - hw, a[1].max(b[1]) + hw),
        ) else {
            return out;
        };
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let len = len2.sqrt();
        for r in r0..=r1 {
            for c in c0..=c1 {
                let p = self.centre(r, c);
                let t = if len2 > 0.0 {
                    (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let q = [a[0] + t * d[0], a[1] + t * d[1]];
                if (p[0] - q[0]).hypot(p[1] - q[1]) <= hw {
                    out.push((Cell::new(r as u32, c as u32), t * len));
                }
            }
        }
        out
    }
}

fn on_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + t * d[0], a[1] + t * d[1]];
    (p[0] - q[0]).hypot(p[1] - q[1]) <= EPS
}

/// Point in polygon by ray casting, counting the boundary as inside.
pub fn inside_or_on(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if on_segment(p, a, b) {
            return true;
        }
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1] + 1e-12) + a[0];
            if p[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Shoelace area of a polygon, m².
pub fn polygon_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    let mut s = 0.0;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        s += a[0] * b[1] - b[0] * a[1];
    }
    (s / 2.0).abs()
}

/// Corners `(x, z)` of an asset's footprint: the box `size_x` by `size_z` centred on `(cx, cz)`,
/// rotated by `yaw_deg` about the vertical axis in Unity's left-handed convention
/// (`x' = x cos t + z sin t`, `z' = -x sin t + z cos t`).
pub fn box_corners(cx: f64, cz: f64, size_x: f64, size_z: f64, yaw_deg: f64) -> [[f64; 2]; 4] {
    let t = yaw_deg.to_radians();
    let (s, c) = t.sin_cos();
    let (hx, hz) = (size_x / 2.0, size_z / 2.0);
    [[-hx, -hz], [hx, -hz], [hx, hz], [-hx, hz]]
        .map(|[x, z]| [cx + x * c + z * s, cz - x * s + z * c])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raster(n: usize) -> Raster {
        Raster {
            x_min: 0.0,
            z_min: 0.0,
            res: 1.0,
            n,
        }
    }

    #[test]
    fn square_room_covers_boundary_centres() {
        // The reference's 4x4 m room at 1 m resolution covers all 25 centres of a 5x5 grid.
        let cells = raster(5).polygon_cells(&[[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]]);
        assert_eq!(cells.len(), 25);
    }

    #[test]
    fn wall_segment_is_one_row() {
        // wall|0|0.0|2.0|4.0|2.0 on a 5x5 grid at 1 m covers exactly row 2.
        let cells = raster(5).segment_cells([0.0, 2.0], [4.0, 2.0], 0.5);
        let rows: Vec<u32> = cells.iter().map(|(c, _)| c.row).collect();
        assert_eq!(rows, vec![2; 5]);
        assert_eq!(cells.last().unwrap().1, 4.0);
    }

    #[test]
    fn rotation_follows_unity() {
        // A 2 m (x) by 1 m (z) box turned 90 degrees spans 1 m in x and 2 m in z.
        let c = box_corners(0.0, 0.0, 2.0, 1.0, 90.0);
        let xs: Vec<f64> = c.iter().map(|p| p[0]).collect();
        let zs: Vec<f64> = c.iter().map(|p| p[1]).collect();
        let span = |v: &[f64]| {
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        assert!((span(&xs) - 1.0).abs() < 1e-9 && (span(&zs) - 2.0).abs() < 1e-9);
        // Unity: local +x turned by +90 degrees points to world -z.
        let p = box_corners(0.0, 0.0, 2.0, 0.0, 90.0)[1];
        assert!(p[0].abs() < 1e-9 && (p[1] + 1.0).abs() < 1e-9);
    }

    #[test]
    fn area_of_l_shape() {
        let l = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        assert_eq!(polygon_area(&l), 3.0);
        assert!(inside_or_on([0.5, 1.5], &l) && !inside_or_on([1.5, 1.5], &l));
    }
}
