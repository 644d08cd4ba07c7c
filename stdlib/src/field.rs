//! Exact Euclidean distance fields over the grid (Felzenszwalb & Huttenlocher's separable lower
//! envelope of parabolas), the primitive behind clearance, erosion by a robot radius, soft-cost
//! fields and "distance to a footprint" queries.
//!
//! Distances are between cell centres, in cells. Squared distances are computed in exact integer
//! arithmetic (as `f64`, which is exact below 2^53), so the square root is the only rounding: the
//! result equals a brute-force scan bit for bit.

use crate::grid::Grid;

/// Squared distance, in cells², from every cell to the nearest source cell; `f64::INFINITY` when
/// there is no source at all.
pub fn squared_distance_field(sources: &Grid<bool>) -> Grid<f64> {
    let n = sources.n();
    let mut out = sources.map(|&s| if s { 0.0 } else { f64::INFINITY });
    if n == 0 {
        return out;
    }
    let mut f = vec![0.0f64; n];
    let mut d = vec![0.0f64; n];
    let mut v = vec![0usize; n];
    let mut z = vec![0.0f64; n + 1];
    // Columns first (1-D transform along rows of each column), then rows.
    {
        let data = out.data_mut();
        for col in 0..n {
            for row in 0..n {
                f[row] = data[row * n + col];
            }
            transform_1d(&f, &mut d, &mut v, &mut z);
            for row in 0..n {
                data[row * n + col] = d[row];
            }
        }
        for row in 0..n {
            let line = &mut data[row * n..(row + 1) * n];
            f.copy_from_slice(line);
            transform_1d(&f, &mut d, &mut v, &mut z);
            line.copy_from_slice(&d);
        }
    }
    out
}

/// Euclidean distance, in cells, from every cell to the nearest source cell (0 on sources,
/// `f64::INFINITY` everywhere when there is no source).
pub fn distance_field(sources: &Grid<bool>) -> Grid<f64> {
    let mut g = squared_distance_field(sources);
    for v in g.data_mut() {
        *v = v.sqrt();
    }
    g
}

/// One-dimensional squared-distance transform of `f` (sampled function, `INFINITY` = no source).
fn transform_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    // Find the first finite sample; with none, the whole line stays infinite.
    let Some(first) = f.iter().position(|x| x.is_finite()) else {
        d.copy_from_slice(f);
        return;
    };
    let mut k = 0usize;
    v[0] = first;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in first + 1..n {
        if !f[q].is_finite() {
            continue;
        }
        let qf = q as f64;
        loop {
            let p = v[k];
            let pf = p as f64;
            let s = ((f[q] + qf * qf) - (f[p] + pf * pf)) / (2.0 * qf - 2.0 * pf);
            if s <= z[k] && k > 0 {
                k -= 1;
                continue;
            }
            if s <= z[k] {
                // k == 0 and the new parabola dominates from -inf: replace it.
                v[0] = q;
                z[0] = f64::NEG_INFINITY;
                z[1] = f64::INFINITY;
                break;
            }
            k += 1;
            v[k] = q;
            z[k] = s;
            z[k + 1] = f64::INFINITY;
            break;
        }
    }
    k = 0;
    for (q, out) in d.iter_mut().enumerate().take(n) {
        let qf = q as f64;
        while z[k + 1] < qf {
            k += 1;
        }
        let p = v[k];
        let dq = qf - p as f64;
        *out = dq * dq + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Cell;
    use proptest::prelude::*;

    fn brute(sources: &Grid<bool>) -> Grid<f64> {
        let pts: Vec<Cell> = sources
            .iter_cells()
            .filter(|(_, s)| **s)
            .map(|(c, _)| c)
            .collect();
        let data = sources
            .iter_cells()
            .map(|(c, _)| {
                pts.iter()
                    .map(|p| {
                        let dr = c.row as f64 - p.row as f64;
                        let dc = c.col as f64 - p.col as f64;
                        (dr * dr + dc * dc).sqrt()
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        Grid::from_vec(sources.n(), data).unwrap()
    }

    #[test]
    fn empty_source_set_is_infinite() {
        let g = distance_field(&Grid::new(4, false));
        assert!(g.data().iter().all(|v| v.is_infinite()));
    }

    #[test]
    fn single_source() {
        let mut s = Grid::new(5, false);
        s.set(Cell::new(0, 0), true);
        let g = distance_field(&s);
        assert_eq!(*g.get(Cell::new(0, 2)).unwrap(), 2.0);
        assert_eq!(*g.get(Cell::new(3, 4)).unwrap(), 5.0);
    }

    proptest! {
        #[test]
        fn matches_brute_force(n in 1usize..24, bits in proptest::collection::vec(any::<u8>(), 576)) {
            let data: Vec<bool> = (0..n * n).map(|i| bits[i] < 20).collect();
            let s = Grid::from_vec(n, data).unwrap();
            let fast = distance_field(&s);
            let slow = brute(&s);
            prop_assert_eq!(fast.data(), slow.data());
        }
    }
}
