//! LIMP's planner as the adaptation runs it (TPSM-like progression to transition regions): at
//! each stage, every traversable cell's full valuation previews the residual formula; cells that
//! would make it false are forbidden, cells that would change it are goals; A* (forbidden cells
//! masked) goes to the nearest goal, and the residual is progressed by the labels of the end cell.
//! At most [`MAX_STAGES`] stages, or until the residual is accepting.
//!
//! Regions: `near(object)` = the traversable cells within [`NEAR_CELLS`] of its footprint, minus
//! the footprint ([`AVOID_CELLS`] when the predicate appears negated); `near(room)` = the room's
//! traversable cells.

use crate::common::failure::Failure;
use crate::common::grid::{GridSearch, append_path};
use crate::common::prefix_ltl::to_prefix;
use crate::common::progress::{accepting, progress, same};
use m2rc_compiler::ltl::Formula;
use m2rc_compiler::ltl::syntax::Kind;
use m2rc_stdlib::grid::Cell;
use serde::Serialize;
use std::collections::BTreeMap;

pub const MAX_STAGES: usize = 16;
/// 24 cells = 1.2 m.
pub const NEAR_CELLS: f64 = 24.0;
/// 18 cells = 0.9 m.
pub const AVOID_CELLS: f64 = 18.0;

/// Atoms of `f` that occur under a negation.
pub fn negated_atoms(f: &Formula) -> Vec<String> {
    fn go(x: &Formula, neg: bool, out: &mut Vec<String>) {
        match &x.kind {
            Kind::Atom(a) if neg && !out.contains(a) => out.push(a.clone()),
            Kind::Not(a) => go(a, !neg, out),
            Kind::Implies(a, b) => {
                go(a, !neg, out);
                go(b, neg, out)
            }
            Kind::Iff(a, b) => {
                for y in [a, b] {
                    go(y, true, out);
                    go(y, false, out);
                }
            }
            Kind::And(a, b)
            | Kind::Or(a, b)
            | Kind::Until(a, b)
            | Kind::Release(a, b)
            | Kind::WeakUntil(a, b) => {
                go(a, neg, out);
                go(b, neg, out)
            }
            Kind::Next(a) | Kind::WeakNext(a) | Kind::Eventually(a) | Kind::Always(a) => {
                go(a, neg, out)
            }
            _ => {}
        }
    }
    let mut out = vec![];
    go(f, false, &mut out);
    out
}

/// The traversable cells within `radius` of `footprint`, minus the footprint (row-major mask).
pub fn near_region(search: &GridSearch<'_>, footprint: &[Cell], radius: f64) -> Vec<bool> {
    let n = search.n();
    let mut fp = vec![false; n * n];
    for c in footprint
        .iter()
        .filter(|c| (c.row as usize) < n && (c.col as usize) < n)
    {
        fp[c.row as usize * n + c.col as usize] = true;
    }
    let r = radius.floor() as i64;
    let offsets: Vec<(i64, i64)> = (-r..=r)
        .flat_map(|dr| (-r..=r).map(move |dc| (dr, dc)))
        .filter(|(dr, dc)| ((dr * dr + dc * dc) as f64).sqrt() <= radius)
        .collect();
    let mut out = vec![false; n * n];
    let is_fp = |r: i64, c: i64| {
        r >= 0 && c >= 0 && (r as usize) < n && (c as usize) < n && fp[r as usize * n + c as usize]
    };
    for c in footprint {
        let (r0, c0) = (c.row as i64, c.col as i64);
        // Only border cells of the footprint can be nearest to an outside cell.
        if [(-1, 0), (1, 0), (0, -1), (0, 1)]
            .iter()
            .all(|(dr, dc)| is_fp(r0 + dr, c0 + dc))
        {
            continue;
        }
        for (dr, dc) in &offsets {
            let (rr, cc) = (r0 + dr, c0 + dc);
            if rr < 0 || cc < 0 || rr as usize >= n || cc as usize >= n {
                continue;
            }
            let cell = Cell::new(rr as u32, cc as u32);
            let i = rr as usize * n + cc as usize;
            if !fp[i] && search.is_free(cell) {
                out[i] = true;
            }
        }
    }
    out
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct StageTrace {
    pub residual_before: String,
    pub goal_cells: usize,
    pub forbidden_cells: usize,
    pub end: [u32; 2],
    pub residual_after: String,
}

/// Plans `formula` over the atoms' regions (row-major masks).
pub fn plan(
    search: &mut GridSearch<'_>,
    start: Cell,
    formula: &Formula,
    regions: &[(String, Vec<bool>)],
) -> Result<(Vec<Cell>, Vec<StageTrace>), Failure> {
    let n = search.n();
    let atoms: Vec<&str> = regions.iter().map(|(a, _)| a.as_str()).collect();
    if atoms.len() > 32 {
        return Err(Failure::new("planner_limit", "more than 32 regions"));
    }
    // Each traversable cell's valuation as a bit set over `atoms`.
    let mut val = vec![0u32; n * n];
    for (k, (_, m)) in regions.iter().enumerate() {
        for (v, &inside) in val.iter_mut().zip(m) {
            if inside {
                *v |= 1 << k;
            }
        }
    }
    let atoms = &atoms;
    let holds = |bits: u32| {
        move |a: &str| {
            atoms
                .iter()
                .position(|x| *x == a)
                .is_some_and(|k| bits >> k & 1 == 1)
        }
    };
    let mut residual = formula.clone();
    let mut route = vec![start];
    let mut cur = start;
    let mut stages = vec![];
    for _ in 0..MAX_STAGES {
        if accepting(&residual) {
            break;
        }
        let mut effect: BTreeMap<u32, u8> = BTreeMap::new(); // 0 same, 1 goal, 2 forbidden
        let (mut goals, mut forbidden) = (vec![], vec![false; n * n]);
        let mut n_forbidden = 0;
        for i in 0..n * n {
            let cell = Cell::new((i / n) as u32, (i % n) as u32);
            if !search.is_free(cell) {
                continue;
            }
            let e = *effect.entry(val[i]).or_insert_with(|| {
                let next = progress(&residual, &holds(val[i]));
                if next.kind == Kind::False {
                    2
                } else if !same(&next, &residual) {
                    1
                } else {
                    0
                }
            });
            match e {
                1 => goals.push(cell),
                2 => {
                    forbidden[i] = true;
                    n_forbidden += 1;
                }
                _ => {}
            }
        }
        if goals.is_empty() {
            return Err(Failure::new(
                "no_goal_region",
                format!("no cell advances the residual `{}`", to_prefix(&residual)),
            ));
        }
        let path = search
            .path_to_any(cur, &goals, Some(&forbidden))
            .map_err(|e| {
                Failure::new(
                    "no_path",
                    format!(
                        "no path to a goal region of `{}`: {e:?}",
                        to_prefix(&residual)
                    ),
                )
            })?;
        let end = *path.cells.last().unwrap_or(&cur);
        let before = to_prefix(&residual);
        residual = progress(
            &residual,
            &holds(val[end.row as usize * n + end.col as usize]),
        );
        append_path(&mut route, &path.cells);
        stages.push(StageTrace {
            residual_before: before,
            goal_cells: goals.len(),
            forbidden_cells: n_forbidden,
            end: [end.row, end.col],
            residual_after: to_prefix(&residual),
        });
        cur = end;
        if residual.kind == Kind::False {
            return Err(Failure::new("no_path", "the residual became false"));
        }
    }
    if !accepting(&residual) {
        return Err(Failure::new(
            "stage_limit",
            format!(
                "not accepted after {MAX_STAGES} stages; residual `{}`",
                to_prefix(&residual)
            ),
        ));
    }
    Ok((route, stages))
}
