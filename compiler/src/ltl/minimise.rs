//! Minimisation of the progression automaton: Moore partition refinement on the symbolic edges.
//! Two states stay together while their acceptance agrees and, for every pair of their edges
//! whose cubes intersect, the targets are in the same block. Edges of a state cover the alphabet
//! exactly once, so this is the usual letter-by-letter refinement without enumerating letters.
//!
//! Equivalent states reach the same set of blocks (every edge has a non-empty guard, so each of
//! one state's edges meets some edge of the other), so states are first bucketed by (block, set
//! of target blocks) and compared edge by edge only within a bucket; each comparison is paid for
//! in the construction's [`Budget`].

use super::budget::Budget;
use super::dfa::{BuildError, Cube, Dfa, Edge, Guard};
use std::collections::{HashMap, VecDeque};

/// Representatives of a bucket: (state, its new block).
type Reps = Vec<(usize, usize)>;

/// Whether states `q` and `r` send every letter to the same block.
fn same(d: &Dfa, block: &[usize], q: usize, r: usize, b: &mut Budget) -> Result<bool, BuildError> {
    for e1 in &d.edges[q] {
        b.spend(d.edges[r].len() as u64)?;
        for e2 in &d.edges[r] {
            if block[e1.to] == block[e2.to] {
                continue;
            }
            b.spend((e1.guard.0.len() * e2.guard.0.len()) as u64)?;
            if e1
                .guard
                .0
                .iter()
                .any(|c1| e2.guard.0.iter().any(|c2| c1.intersects(*c2)))
            {
                return Ok(false);
            }
        }
    }
    Ok(true)
}

/// The minimal automaton of `d`, states numbered breadth-first from the initial one.
pub(super) fn minimised(d: &Dfa, b: &mut Budget) -> Result<Dfa, BuildError> {
    let n = d.states();
    let mut block: Vec<usize> = d.accepting.iter().map(|&a| a as usize).collect();
    let mut blocks = {
        let mut distinct = block.clone();
        distinct.sort_unstable();
        distinct.dedup();
        distinct.len()
    };
    loop {
        // Per bucket, the representatives found so far and their new block.
        let mut buckets: HashMap<(usize, Vec<usize>), Reps> = HashMap::new();
        let mut next = vec![0usize; n];
        let mut made = 0usize;
        for q in 0..n {
            let mut targets: Vec<usize> = d.edges[q].iter().map(|e| block[e.to]).collect();
            targets.sort_unstable();
            targets.dedup();
            b.spend(1 + targets.len() as u64)?;
            let reps = buckets.entry((block[q], targets)).or_default();
            let mut found = None;
            for &(r, id) in reps.iter() {
                if same(d, &block, q, r, b)? {
                    found = Some(id);
                    break;
                }
            }
            next[q] = match found {
                Some(id) => id,
                None => {
                    reps.push((q, made));
                    made += 1;
                    made - 1
                }
            };
        }
        block = next;
        if made == blocks {
            break;
        }
        blocks = made;
    }
    // Renumber blocks in breadth-first order from the initial state.
    let mut order: HashMap<usize, usize> = HashMap::new();
    let mut queue = VecDeque::from([d.initial]);
    let mut seen = vec![false; n];
    seen[d.initial] = true;
    let mut rep_of: Vec<usize> = Vec::new();
    while let Some(q) = queue.pop_front() {
        if let std::collections::hash_map::Entry::Vacant(slot) = order.entry(block[q]) {
            slot.insert(rep_of.len());
            rep_of.push(q);
        }
        for e in &d.edges[q] {
            if !seen[e.to] {
                seen[e.to] = true;
                queue.push_back(e.to);
            }
        }
    }
    let mut edges = Vec::with_capacity(rep_of.len());
    for (k, &q) in rep_of.iter().enumerate() {
        let mut by_target: Vec<(usize, Vec<Cube>)> = Vec::new();
        for e in &d.edges[q] {
            let to = order[&block[e.to]];
            b.spend(1 + by_target.len() as u64)?;
            match by_target.iter_mut().find(|(t, _)| *t == to) {
                Some((_, c)) => c.extend(e.guard.0.iter().copied()),
                None => by_target.push((to, e.guard.0.clone())),
            }
        }
        let mut out = Vec::with_capacity(by_target.len());
        for (to, cubes) in by_target {
            out.push(Edge {
                from: k,
                to,
                guard: simplify(cubes, b)?,
            });
        }
        edges.push(out);
    }
    Ok(Dfa {
        atoms: d.atoms.clone(),
        initial: 0,
        accepting: rep_of.iter().map(|&q| d.accepting[q]).collect(),
        edges,
    })
}

/// Merges cubes that differ in one literal and drops subsumed ones, until nothing changes.
fn simplify(mut cubes: Vec<Cube>, b: &mut Budget) -> Result<Guard, BuildError> {
    loop {
        cubes.sort();
        cubes.dedup();
        let mut changed = false;
        'outer: for i in 0..cubes.len() {
            b.spend(cubes.len() as u64)?;
            for j in 0..cubes.len() {
                if i == j {
                    continue;
                }
                let (x, y) = (cubes[i], cubes[j]);
                // x subsumes y when x's literals are a subset of y's.
                if x.pos & y.pos == x.pos && x.neg & y.neg == x.neg {
                    cubes.remove(j);
                    changed = true;
                    break 'outer;
                }
                let (dx, dy) = (x.pos ^ y.pos, x.neg ^ y.neg);
                if dx == dy && dx.count_ones() == 1 && (x.pos | x.neg) == (y.pos | y.neg) {
                    let merged = Cube {
                        pos: x.pos & !dx,
                        neg: x.neg & !dx,
                    };
                    cubes[i] = merged;
                    cubes.remove(j);
                    changed = true;
                    break 'outer;
                }
            }
        }
        if !changed {
            return Ok(Guard(cubes));
        }
    }
}
