//! LTLf → minimal DFA by formula progression, with symbolic guards.
//!
//! A state is a residual formula (hash-consed, ACI-normalised, in [`Arena`]). To leave a state,
//! its formula is unfolded once into a propositional part about the current letter and
//! obligations for the rest of the route (`F a` = `a | X F a`, `a U b` = `b | a & X(a U b)`, ...),
//! and the atoms are then decided one at a time (Shannon expansion, ascending atom order) with
//! constant folding after each decision. A branch stops as soon as no atom is left undecided, so
//! a state with a few relevant atoms gets a few cubes, not 2^k letters; each leaf's obligations
//! form the successor formula. A state accepts when its formula holds on the empty suffix.
//!
//! Minimisation is in [`super::minimise`]. Every step of both is paid for in a [`Budget`] as it
//! happens, so a formula too large for a route is refused within a bounded amount of work and
//! memory, not after it.

use super::budget::Budget;
use super::formula::{Arena, Id, Node};
use super::syntax::Formula;
use petgraph::graph::{DiGraph, NodeIndex};
use std::collections::HashMap;

/// A conjunction of literals: atoms in `pos` true, atoms in `neg` false (bit `i` = atom `i`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cube {
    pub pos: u64,
    pub neg: u64,
}

impl Cube {
    pub fn matches(self, letter: u64) -> bool {
        letter & self.pos == self.pos && letter & self.neg == 0
    }

    pub fn intersects(self, o: Cube) -> bool {
        (self.pos | o.pos) & (self.neg | o.neg) == 0
    }
}

/// A propositional guard: a disjunction of cubes (empty = `false`, one empty cube = `true`).
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Guard(pub Vec<Cube>);

impl Guard {
    pub fn matches(&self, letter: u64) -> bool {
        self.0.iter().any(|c| c.matches(letter))
    }

    /// The guard in the formula text syntax over `atoms` (`a & !b | c`).
    pub fn text(&self, atoms: &[String]) -> String {
        if self.0.is_empty() {
            return "false".into();
        }
        let cube = |c: &Cube| {
            let lits: Vec<String> = (0..atoms.len())
                .filter_map(|i| {
                    if c.pos >> i & 1 == 1 {
                        Some(atoms[i].clone())
                    } else if c.neg >> i & 1 == 1 {
                        Some(format!("!{}", atoms[i]))
                    } else {
                        None
                    }
                })
                .collect();
            if lits.is_empty() {
                "true".to_string()
            } else {
                lits.join(" & ")
            }
        };
        self.0.iter().map(cube).collect::<Vec<_>>().join(" | ")
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Edge {
    pub from: usize,
    pub to: usize,
    pub guard: Guard,
}

/// A complete deterministic automaton over the valuations of `atoms`.
#[derive(Clone, Debug, PartialEq)]
pub struct Dfa {
    pub atoms: Vec<String>,
    pub initial: usize,
    pub accepting: Vec<bool>,
    /// Per state, its outgoing edges; the guards of a state are disjoint and cover every letter.
    pub edges: Vec<Vec<Edge>>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BuildError {
    /// More atoms than a letter mask holds.
    TooManyAtoms(usize),
    /// The construction passed its state budget.
    TooManyStates(usize),
    /// The formula names an atom not in the list.
    UnknownAtom(String),
    /// A formula or state nests deeper than the construction recurses.
    TooDeep(u32),
    /// The construction passed its work budget ([`super::budget`]) after `states` states.
    Budget {
        what: &'static str,
        limit: u64,
        states: usize,
    },
}

impl std::fmt::Display for BuildError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BuildError::TooManyAtoms(n) => {
                write!(f, "{n} atoms: at most {MAX_ATOMS} are supported")
            }
            BuildError::TooManyStates(n) => {
                write!(f, "the automaton passed {n} states; simplify the formula")
            }
            BuildError::UnknownAtom(a) => write!(f, "unknown atom `{a}`"),
            BuildError::TooDeep(n) => {
                write!(
                    f,
                    "the formula nests more than {n} levels deep; simplify it"
                )
            }
            BuildError::Budget {
                what,
                limit,
                states,
            } => write!(
                f,
                "the automaton is too large to build: it passed the limit of {limit} {what} \
                 after {states} states"
            ),
        }
    }
}

pub const MAX_ATOMS: usize = 64;
/// States explored before giving up (the formula is then far larger than a route needs).
pub const MAX_STATES: usize = 20_000;
/// Deepest formula or state the construction takes; it recurses over them, and this keeps it well
/// inside a thread's stack (a 2 MB worker thread's too). A chain of visits nests two levels per
/// visit, so `--planner ltl` takes routes of up to about 490 stages; a written formula nests at
/// most `syntax::MAX_NESTING` levels.
pub const MAX_STATE_DEPTH: u32 = 1000;

/// The unfolded form of a state: the current letter's part and the obligations for the rest.
#[derive(Clone, Debug, PartialEq)]
enum Now {
    T,
    F,
    Lit(u32, bool),
    Obl(Id),
    And(Vec<Now>),
    Or(Vec<Now>),
}

fn unfold(a: &mut Arena, id: Id, b: &mut Budget) -> Result<Now, BuildError> {
    b.spend(1)?;
    Ok(match a.node(id).clone() {
        Node::True | Node::NonEmpty => Now::T,
        Node::False | Node::End => Now::F,
        Node::Lit { atom, negated } => Now::Lit(atom, negated),
        Node::And(c) => Now::And(unfold_all(a, &c, b)?),
        Node::Or(c) => Now::Or(unfold_all(a, &c, b)?),
        Node::Next(x) => {
            let ne = a.non_empty();
            Now::Obl(a.and([ne, x]))
        }
        Node::WeakNext(x) => {
            let end = a.end();
            Now::Obl(a.or([end, x]))
        }
        Node::Until(x, y) => Now::Or(vec![
            unfold(a, y, b)?,
            Now::And(vec![unfold(a, x, b)?, Now::Obl(id)]),
        ]),
        Node::Release(x, y) => Now::And(vec![
            unfold(a, y, b)?,
            Now::Or(vec![unfold(a, x, b)?, Now::Obl(id)]),
        ]),
        Node::Eventually(x) => Now::Or(vec![unfold(a, x, b)?, Now::Obl(id)]),
        Node::Always(x) => Now::And(vec![unfold(a, x, b)?, Now::Obl(id)]),
    })
}

fn unfold_all(a: &mut Arena, ids: &[Id], b: &mut Budget) -> Result<Vec<Now>, BuildError> {
    ids.iter().map(|&x| unfold(a, x, b)).collect()
}

/// `now` with `atom` set to `value`, constant-folded; `steps` counts the nodes visited.
fn assign(now: &Now, atom: u32, value: bool, steps: &mut u64) -> Now {
    *steps += 1;
    match now {
        Now::Lit(x, neg) if *x == atom => {
            if value != *neg {
                Now::T
            } else {
                Now::F
            }
        }
        Now::And(c) => {
            let mut out = Vec::new();
            for p in c {
                match assign(p, atom, value, steps) {
                    Now::T => {}
                    Now::F => return Now::F,
                    q => out.push(q),
                }
            }
            match out.len() {
                0 => Now::T,
                1 => out.pop().unwrap_or(Now::T),
                _ => Now::And(out),
            }
        }
        Now::Or(c) => {
            let mut out = Vec::new();
            for p in c {
                match assign(p, atom, value, steps) {
                    Now::F => {}
                    Now::T => return Now::T,
                    q => out.push(q),
                }
            }
            match out.len() {
                0 => Now::F,
                1 => out.pop().unwrap_or(Now::F),
                _ => Now::Or(out),
            }
        }
        other => other.clone(),
    }
}

fn first_atom(now: &Now) -> Option<u32> {
    match now {
        Now::Lit(x, _) => Some(*x),
        Now::And(c) | Now::Or(c) => c.iter().filter_map(first_atom).min(),
        _ => None,
    }
}

/// The state after a letter: the residual obligations in disjunctive normal form, each term a
/// sorted set of obligation nodes, with duplicates and supersets dropped, then rebuilt as one
/// node. The terms range over a finite set (the formula's temporal subformulas and their
/// `X`/`WX` wrappers), so this is what makes progression close: ACI and absorption on the nested
/// form alone still let some formulas grow equivalent states without end.
fn residual(a: &mut Arena, now: &Now, b: &mut Budget) -> Result<Id, BuildError> {
    let terms = dnf_now(a, now, b)?;
    let mut parts = Vec::with_capacity(terms.len());
    for t in terms {
        b.spend(1 + t.len() as u64)?;
        parts.push(a.and(t));
    }
    // Absorption in `or` compares the terms pairwise.
    b.spend((parts.len() * parts.len()) as u64)?;
    Ok(a.or(parts))
}

/// Terms of a disjunctive normal form: each a sorted, duplicate-free conjunction of node ids.
type Terms = Vec<Vec<Id>>;

/// Terms a residual may have before the construction gives up (the formula is then far larger
/// than a route needs).
const MAX_TERMS: usize = 4096;

fn dnf_now(a: &Arena, now: &Now, b: &mut Budget) -> Result<Terms, BuildError> {
    b.spend(1)?;
    match now {
        Now::T => Ok(vec![vec![]]),
        Now::F | Now::Lit(..) => Ok(vec![]),
        Now::Obl(x) => dnf_id(a, *x, b),
        Now::And(c) => {
            let mut acc: Terms = vec![vec![]];
            for p in c {
                acc = product(a, acc, dnf_now(a, p, b)?, b)?;
            }
            Ok(acc)
        }
        Now::Or(c) => {
            let mut acc: Terms = Vec::new();
            for p in c {
                acc.extend(dnf_now(a, p, b)?);
            }
            minimal(a, acc, b)
        }
    }
}

fn dnf_id(a: &Arena, id: Id, b: &mut Budget) -> Result<Terms, BuildError> {
    b.spend(1)?;
    match a.node(id) {
        Node::True => Ok(vec![vec![]]),
        Node::False => Ok(vec![]),
        Node::And(c) => {
            let mut acc: Terms = vec![vec![]];
            for &p in c {
                acc = product(a, acc, dnf_id(a, p, b)?, b)?;
            }
            Ok(acc)
        }
        Node::Or(c) => {
            let mut acc: Terms = Vec::new();
            for &p in c {
                acc.extend(dnf_id(a, p, b)?);
            }
            minimal(a, acc, b)
        }
        _ => Ok(vec![vec![id]]),
    }
}

fn too_many_terms(b: &Budget) -> BuildError {
    BuildError::Budget {
        what: "terms in one state",
        limit: MAX_TERMS as u64,
        states: b.states,
    }
}

fn product(a: &Arena, xs: Terms, ys: Terms, b: &mut Budget) -> Result<Terms, BuildError> {
    if xs.len().saturating_mul(ys.len()) > MAX_TERMS * 4 {
        return Err(too_many_terms(b));
    }
    let mut out = Vec::with_capacity(xs.len() * ys.len());
    for x in &xs {
        for y in &ys {
            b.spend(1 + (x.len() + y.len()) as u64)?;
            let mut t: Vec<Id> = x.iter().chain(y).copied().collect();
            t.sort_unstable();
            t.dedup();
            out.push(t);
        }
    }
    minimal(a, out, b)
}

/// Sorted terms without duplicates and without any term that implies another (absorption: `t | k`
/// is `k` when `t` implies `k`). Implication is read syntactically: `t` implies `k` when each
/// conjunct of `k` is a conjunct of `t` or, for an eventuality, implied by one ([`reaches`]).
/// The second case is what keeps a chain of visits linear: after entering `b` in
/// `F(b & F(k & F(b & ...)))` the state is `F(k & F(b & ...)) | F(b & F(k & F(b & ...)))`, whose
/// second term implies the first; without it, every state would keep every earlier position.
fn minimal(a: &Arena, mut terms: Terms, b: &mut Budget) -> Result<Terms, BuildError> {
    b.spend(terms.len() as u64)?;
    terms.sort_by(|x, y| x.len().cmp(&y.len()).then_with(|| x.cmp(y)));
    terms.dedup();
    let mut keep: Terms = Vec::with_capacity(terms.len());
    for t in terms {
        b.spend(1 + keep.len() as u64)?;
        let mut absorbed = false;
        for k in &keep {
            if term_implies(a, &t, k, b)? {
                absorbed = true;
                break;
            }
        }
        if absorbed {
            continue;
        }
        let mut kept = Vec::with_capacity(keep.len() + 1);
        for k in keep {
            if !term_implies(a, &k, &t, b)? {
                kept.push(k);
            }
        }
        kept.push(t);
        keep = kept;
    }
    if keep.len() > MAX_TERMS {
        return Err(too_many_terms(b));
    }
    keep.sort();
    Ok(keep)
}

/// Whether the conjunction `t` implies the conjunction `k`, on every suffix, the empty one
/// included.
fn term_implies(a: &Arena, t: &[Id], k: &[Id], b: &mut Budget) -> Result<bool, BuildError> {
    b.spend((t.len() * k.len()) as u64)?;
    'each: for &x in k {
        if t.binary_search(&x).is_ok() {
            continue;
        }
        if matches!(a.node(x), Node::Eventually(_)) {
            for &y in t {
                // `F α` implies `F β` when α implies `F β` wherever it holds; both are false on
                // the empty suffix.
                if let Node::Eventually(alpha) = *a.node(y)
                    && reaches(a, alpha, x, b)?
                {
                    continue 'each;
                }
            }
        }
        return Ok(false);
    }
    Ok(true)
}

/// Whether `p`, holding at a position of the route, implies the eventuality `x` = `F β` there: `p`
/// is `x` or `β`, or requires something later that does (`F q`, `q'  U q`, `X q`), or is a
/// conjunction with such a conjunct, or a disjunction of such parts.
fn reaches(a: &Arena, p: Id, x: Id, b: &mut Budget) -> Result<bool, BuildError> {
    b.spend(1)?;
    let Node::Eventually(beta) = *a.node(x) else {
        return Ok(false);
    };
    if p == x || p == beta {
        return Ok(true);
    }
    Ok(match a.node(p) {
        Node::Eventually(q) | Node::Until(_, q) | Node::Next(q) => reaches(a, *q, x, b)?,
        Node::And(c) => {
            let mut any = false;
            for &q in c {
                if reaches(a, q, x, b)? {
                    any = true;
                    break;
                }
            }
            any
        }
        Node::Or(c) => {
            let mut all = !c.is_empty();
            for &q in c {
                if !reaches(a, q, x, b)? {
                    all = false;
                    break;
                }
            }
            all
        }
        _ => false,
    })
}

/// Shannon expansion of `now` below `cube`: one leaf per cube of the state's guards, each with
/// its successor. Each node pays for the literals it decides and for its constant folding.
fn split(
    a: &mut Arena,
    now: Now,
    cube: Cube,
    out: &mut Vec<(Cube, Id)>,
    b: &mut Budget,
) -> Result<(), BuildError> {
    match first_atom(&now) {
        None => {
            b.cube()?;
            let r = residual(a, &now, b)?;
            out.push((cube, r));
        }
        Some(x) => {
            let bit = 1u64 << x;
            let mut steps = 0u64;
            let t = assign(&now, x, true, &mut steps);
            let f = assign(&now, x, false, &mut steps);
            // `first_atom` walked it too.
            b.spend(steps + steps / 2)?;
            drop(now);
            let pos = Cube {
                pos: cube.pos | bit,
                ..cube
            };
            split(a, t, pos, out, b)?;
            let neg = Cube {
                neg: cube.neg | bit,
                ..cube
            };
            split(a, f, neg, out, b)?;
        }
    }
    Ok(())
}

impl Dfa {
    /// The automaton of `formula` over `atoms` (every atom of the formula must be listed; atoms
    /// not in the formula are allowed and simply never constrain a guard), within the default
    /// [`Budget`].
    pub fn build(formula: &Formula, atoms: &[String], minimise: bool) -> Result<Dfa, BuildError> {
        build_with(formula, atoms, minimise, &mut Budget::default())
    }

    pub fn states(&self) -> usize {
        self.accepting.len()
    }

    /// The state after reading `letter` in state `q`.
    pub fn step(&self, q: usize, letter: u64) -> usize {
        self.edges[q]
            .iter()
            .find(|e| e.guard.matches(letter))
            .map_or(q, |e| e.to)
    }

    /// Whether the automaton accepts `trace` (letters as atom bit masks).
    pub fn accepts(&self, trace: &[u64]) -> bool {
        let q = trace.iter().fold(self.initial, |q, &l| self.step(q, l));
        self.accepting[q]
    }

    /// The automaton as a petgraph graph (node weight: accepting; edge weight: guard).
    pub fn graph(&self) -> (DiGraph<bool, Guard>, Vec<NodeIndex>) {
        let mut g = DiGraph::new();
        let nodes: Vec<NodeIndex> = self.accepting.iter().map(|&a| g.add_node(a)).collect();
        for e in self.edges.iter().flatten() {
            g.add_edge(nodes[e.from], nodes[e.to], e.guard.clone());
        }
        (g, nodes)
    }

    /// States from which an accepting state is reachable (a state that is not live is a sink).
    pub fn live(&self) -> Vec<bool> {
        let (mut g, nodes) = self.graph();
        g.reverse();
        let mut live = vec![false; self.states()];
        for (q, &acc) in self.accepting.iter().enumerate() {
            if acc && !live[q] {
                let mut dfs = petgraph::visit::Dfs::new(&g, nodes[q]);
                while let Some(n) = dfs.next(&g) {
                    live[n.index()] = true;
                }
            }
        }
        live
    }

    /// Whether some finite non-empty trace is accepted.
    pub fn is_satisfiable(&self) -> bool {
        let live = self.live();
        // The empty trace does not count: some edge out of the initial state must stay live.
        self.edges[self.initial].iter().any(|e| live[e.to])
    }
}

/// [`Dfa::build`] within `budget`.
pub fn build_with(
    formula: &Formula,
    atoms: &[String],
    minimise: bool,
    budget: &mut Budget,
) -> Result<Dfa, BuildError> {
    if atoms.len() > MAX_ATOMS {
        return Err(BuildError::TooManyAtoms(atoms.len()));
    }
    let index: HashMap<&str, u32> = atoms
        .iter()
        .enumerate()
        .map(|(i, a)| (a.as_str(), i as u32))
        .collect();
    let mut arena = Arena::new();
    let root = arena
        .from_formula(formula, false, &|n| index.get(n).copied())
        .map_err(|_| {
            BuildError::UnknownAtom(
                formula
                    .atoms()
                    .into_iter()
                    .find(|a| !index.contains_key(a))
                    .unwrap_or_default()
                    .to_string(),
            )
        })?;
    if arena.depth(root) > MAX_STATE_DEPTH {
        return Err(BuildError::TooDeep(MAX_STATE_DEPTH));
    }
    let raw = explore(&mut arena, root, atoms, budget)?;
    if minimise {
        super::minimise::minimised(&raw, budget)
    } else {
        Ok(raw)
    }
}

fn explore(
    arena: &mut Arena,
    root: Id,
    atoms: &[String],
    b: &mut Budget,
) -> Result<Dfa, BuildError> {
    let mut states: Vec<Id> = vec![root];
    let mut index: HashMap<Id, usize> = HashMap::from([(root, 0)]);
    let mut edges: Vec<Vec<Edge>> = Vec::new();
    let mut q = 0;
    while q < states.len() {
        b.states = states.len();
        let now = unfold(arena, states[q], b)?;
        let mut leaves = Vec::new();
        split(arena, now, Cube::default(), &mut leaves, b)?;
        let mut out: Vec<(usize, Vec<Cube>)> = Vec::new();
        // Position in `out` of each target.
        let mut slot: HashMap<usize, usize> = HashMap::new();
        for (cube, succ) in leaves {
            let to = match index.get(&succ) {
                Some(&t) => t,
                None => {
                    if states.len() >= MAX_STATES {
                        return Err(BuildError::TooManyStates(MAX_STATES));
                    }
                    if arena.depth(succ) > MAX_STATE_DEPTH {
                        return Err(BuildError::TooDeep(MAX_STATE_DEPTH));
                    }
                    states.push(succ);
                    index.insert(succ, states.len() - 1);
                    states.len() - 1
                }
            };
            match slot.get(&to) {
                Some(&k) => out[k].1.push(cube),
                None => {
                    slot.insert(to, out.len());
                    out.push((to, vec![cube]));
                }
            }
        }
        edges.push(
            out.into_iter()
                .map(|(to, cubes)| Edge {
                    from: q,
                    to,
                    guard: Guard(cubes),
                })
                .collect(),
        );
        q += 1;
    }
    Ok(Dfa {
        atoms: atoms.to_vec(),
        initial: 0,
        accepting: states.iter().map(|&s| arena.accepts_empty(s)).collect(),
        edges,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::syntax::parse;

    fn dfa(s: &str, atoms: &[&str]) -> Dfa {
        let atoms: Vec<String> = atoms.iter().map(|a| a.to_string()).collect();
        Dfa::build(&parse(s).unwrap(), &atoms, true).unwrap()
    }

    #[test]
    fn sequenced_visit_with_avoid_is_small() {
        let d = dfa("F(a & F b) & G !c", &["a", "b", "c"]);
        // waiting for a, waiting for b, done, sink.
        assert_eq!(d.states(), 4);
        assert!(d.accepts(&[0b001, 0b010]));
        assert!(d.accepts(&[0b011]));
        assert!(!d.accepts(&[0b010, 0b001]));
        assert!(!d.accepts(&[0b001, 0b110]));
        assert!(d.is_satisfiable());
    }

    #[test]
    fn unsatisfiable_and_next() {
        assert!(!dfa("F a & G !a", &["a"]).is_satisfiable());
        let d = dfa("X a", &["a"]);
        assert!(!d.accepts(&[1]));
        assert!(d.accepts(&[0, 1]));
        let d = dfa("WX a", &["a"]);
        assert!(d.accepts(&[0]));
        assert!(!d.accepts(&[0, 0]));
        let d = dfa("G a", &["a"]);
        assert!(d.accepts(&[1, 1]));
        assert!(!d.accepts(&[1, 0]));
    }

    #[test]
    fn guards_print_in_the_formula_syntax() {
        let d = dfa("F(a & b)", &["a", "b"]);
        let texts: Vec<String> = d.edges[d.initial]
            .iter()
            .map(|e| e.guard.text(&d.atoms))
            .collect();
        assert!(texts.contains(&"a & b".to_string()), "{texts:?}");
        for t in texts {
            parse(&t).unwrap();
        }
    }
}
