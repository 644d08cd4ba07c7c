//! Exact Euclidean distance transform in integer arithmetic (Meijster, Roerdink & Hesselink 2000),
//! tuned for the planner: the heuristic of every stage and every soft term needs one, so the
//! transform is on the critical path of a plan. It returns the same values as
//! `m2rc_stdlib::field::distance_field` (tested bit for bit) but walks memory row by row in both
//! passes, which is several times faster on a 700×700 map.

/// Squared distance, in cells², from every cell of the row-major `n`×`n` grid to the nearest source
/// cell; `u32::MAX` everywhere when there is no source.
pub fn squared(sources: &[bool], n: usize) -> Vec<u32> {
    debug_assert_eq!(sources.len(), n * n);
    let inf = (2 * n + 2) as u32; // larger than any vertical distance
    // Phase 1: vertical distance to the nearest source in the same column, two sweeps over rows.
    let mut g = vec![inf; n * n];
    for r in 0..n {
        let (prev, cur) = g.split_at_mut(r * n);
        let cur = &mut cur[..n];
        let src = &sources[r * n..(r + 1) * n];
        if r == 0 {
            for (g, &s) in cur.iter_mut().zip(src) {
                *g = if s { 0 } else { inf };
            }
        } else {
            let above = &prev[(r - 1) * n..r * n];
            for ((g, &s), &a) in cur.iter_mut().zip(src).zip(above) {
                *g = if s { 0 } else { (a + 1).min(inf) };
            }
        }
    }
    for r in (0..n.saturating_sub(1)).rev() {
        let (cur, next) = g.split_at_mut((r + 1) * n);
        let cur = &mut cur[r * n..];
        for (g, &b) in cur[..n].iter_mut().zip(&next[..n]) {
            if b + 1 < *g {
                *g = b + 1;
            }
        }
    }
    // Phase 2: per row, lower envelope of the parabolas (x - i)² + g(i)².
    let mut out = vec![u32::MAX; n * n];
    let mut s = vec![0usize; n];
    let mut t = vec![0i64; n];
    let big = (inf as i64) * (inf as i64);
    for r in 0..n {
        let row = &g[r * n..(r + 1) * n];
        if row.iter().all(|&v| v >= inf) {
            continue;
        }
        let gi = |i: usize| -> i64 { row[i] as i64 };
        let f = |x: usize, i: usize| -> i64 {
            let d = x as i64 - i as i64;
            d * d + gi(i) * gi(i)
        };
        let sep = |i: usize, u: usize| -> i64 {
            let (ii, uu) = (i as i64, u as i64);
            (uu * uu - ii * ii + gi(u) * gi(u) - gi(i) * gi(i)).div_euclid(2 * (uu - ii))
        };
        let mut q: isize = 0;
        s[0] = 0;
        t[0] = 0;
        for u in 1..n {
            while q >= 0 && f(t[q as usize] as usize, s[q as usize]) > f(t[q as usize] as usize, u)
            {
                q -= 1;
            }
            if q < 0 {
                q = 0;
                s[0] = u;
            } else {
                let wv = 1 + sep(s[q as usize], u);
                if wv < n as i64 {
                    q += 1;
                    s[q as usize] = u;
                    t[q as usize] = wv;
                }
            }
        }
        let dst = &mut out[r * n..(r + 1) * n];
        for u in (0..n).rev() {
            let v = f(u, s[q as usize]);
            dst[u] = if v >= big { u32::MAX } else { v as u32 };
            if u as i64 == t[q as usize] {
                q -= 1;
            }
        }
    }
    out
}

/// Euclidean distance in cells (`f64::INFINITY` when there is no source).
pub fn distance(sources: &[bool], n: usize) -> Vec<f64> {
    squared(sources, n)
        .into_iter()
        .map(|v| {
            if v == u32::MAX {
                f64::INFINITY
            } else {
                (v as f64).sqrt()
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use m2rc_stdlib::field::distance_field;
    use m2rc_stdlib::grid::Grid;
    use proptest::prelude::*;

    #[test]
    fn no_sources_is_infinite() {
        assert!(distance(&[false; 9], 3).iter().all(|v| v.is_infinite()));
        assert!(distance(&[], 0).is_empty());
    }

    proptest! {
        #[test]
        fn equals_stdlib_transform(n in 1usize..40, bits in proptest::collection::vec(any::<u8>(), 1600), density in 1u8..120) {
            let src: Vec<bool> = (0..n * n).map(|i| bits[i] < density).collect();
            let ours = distance(&src, n);
            let theirs = distance_field(&Grid::from_vec(n, src).unwrap());
            prop_assert_eq!(ours, theirs.into_vec());
        }
    }
}
