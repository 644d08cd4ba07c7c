//! The core form the automaton is built from: formulas in negation normal form over numbered
//! atoms, hash-consed in an [`Arena`] so that equal formulas are equal ids and conjunctions and
//! disjunctions are flattened, sorted and deduplicated (the ACI normalisation that keeps
//! progression finite).
//!
//! Residual formulas are read over a *suffix* of the route that may be empty (the route has
//! ended). Two constants make that exact: `NonEmpty` (a position remains) and `End` (none does).
//! A literal needs a position, so it is false on the empty suffix; `G φ` and `φ R ψ` are true on
//! it; `F`, `U` and strong `X` are false. Direct evaluation ([`holds`]) is the LTLf semantics on
//! the surface syntax, kept independent of this module so tests can compare the two.

use super::syntax::{Formula, Kind};
use std::collections::HashMap;

pub type Id = u32;

#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Node {
    True,
    False,
    /// A position remains.
    NonEmpty,
    /// No position remains.
    End,
    Lit {
        atom: u32,
        negated: bool,
    },
    And(Vec<Id>),
    Or(Vec<Id>),
    Next(Id),
    WeakNext(Id),
    Until(Id, Id),
    Release(Id, Id),
    Eventually(Id),
    Always(Id),
}

#[derive(Clone, Debug, Default)]
pub struct Arena {
    nodes: Vec<Node>,
    /// Nesting depth of each node (a leaf is 1): what recursion over it costs in stack.
    depths: Vec<u32>,
    index: HashMap<Node, Id>,
}

impl Arena {
    pub fn new() -> Self {
        let mut a = Arena::default();
        a.intern(Node::True);
        a.intern(Node::False);
        a
    }

    pub const TRUE: Id = 0;
    pub const FALSE: Id = 1;

    pub fn node(&self, id: Id) -> &Node {
        &self.nodes[id as usize]
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    fn intern(&mut self, n: Node) -> Id {
        if let Some(&id) = self.index.get(&n) {
            return id;
        }
        let id = self.nodes.len() as Id;
        let d = |x: &Id| self.depths[*x as usize];
        let depth = 1 + match &n {
            Node::And(c) | Node::Or(c) => c.iter().map(d).max().unwrap_or(0),
            Node::Next(x) | Node::WeakNext(x) | Node::Eventually(x) | Node::Always(x) => d(x),
            Node::Until(x, y) | Node::Release(x, y) => d(x).max(d(y)),
            _ => 0,
        };
        self.nodes.push(n.clone());
        self.depths.push(depth);
        self.index.insert(n, id);
        id
    }

    /// How deeply `id` nests (a leaf is 1).
    pub fn depth(&self, id: Id) -> u32 {
        self.depths[id as usize]
    }

    pub fn lit(&mut self, atom: u32, negated: bool) -> Id {
        self.intern(Node::Lit { atom, negated })
    }

    pub fn non_empty(&mut self) -> Id {
        self.intern(Node::NonEmpty)
    }

    pub fn end(&mut self) -> Id {
        self.intern(Node::End)
    }

    pub fn and(&mut self, parts: impl IntoIterator<Item = Id>) -> Id {
        self.junction(parts, true)
    }

    pub fn or(&mut self, parts: impl IntoIterator<Item = Id>) -> Id {
        self.junction(parts, false)
    }

    fn junction(&mut self, parts: impl IntoIterator<Item = Id>, conj: bool) -> Id {
        let (unit, zero) = if conj {
            (Arena::TRUE, Arena::FALSE)
        } else {
            (Arena::FALSE, Arena::TRUE)
        };
        let mut flat: Vec<Id> = Vec::new();
        for p in parts {
            match self.node(p) {
                Node::And(c) if conj => flat.extend(c.iter().copied()),
                Node::Or(c) if !conj => flat.extend(c.iter().copied()),
                _ if p == unit => {}
                _ if p == zero => return zero,
                _ => flat.push(p),
            }
        }
        flat.sort_unstable();
        flat.dedup();
        // Complementary literals; `NonEmpty` against `End`; `NonEmpty` is implied by a literal.
        let mut has_lit = false;
        let (mut ne, mut end) = (false, false);
        for &p in &flat {
            match *self.node(p) {
                Node::Lit { atom, negated } => {
                    has_lit = true;
                    let other = Node::Lit {
                        atom,
                        negated: !negated,
                    };
                    if let Some(&o) = self.index.get(&other).filter(|o| flat.contains(o)) {
                        // p & !p is false everywhere; p | !p holds wherever a position remains,
                        // so the pair becomes `NonEmpty` (which leaves fewer literals: this ends).
                        if conj {
                            return zero;
                        }
                        let ne_id = self.non_empty();
                        let rest: Vec<Id> = flat
                            .iter()
                            .copied()
                            .filter(|&x| x != p && x != o)
                            .chain([ne_id])
                            .collect();
                        return self.junction(rest, conj);
                    }
                }
                Node::NonEmpty => ne = true,
                Node::End => end = true,
                _ => {}
            }
        }
        if ne && end {
            return zero;
        }
        if conj && ne && has_lit {
            let ne_id = self.non_empty();
            flat.retain(|p| *p != ne_id);
        }
        self.absorb(&mut flat, conj);
        match flat.len() {
            0 => unit,
            1 => flat[0],
            _ => self.intern(if conj {
                Node::And(flat)
            } else {
                Node::Or(flat)
            }),
        }
    }

    /// Absorption, `x & (x | y) = x` and `x | (x & y) = x`, and of an inner junction by one with
    /// fewer children (`(x | y) & (x | y | z) = x | y`). Without it, progression of formulas
    /// such as `F false W F WX false` builds ever deeper equivalent states and never closes.
    fn absorb(&self, flat: &mut Vec<Id>, conj: bool) {
        let inner = |q: Id| -> Option<&[Id]> {
            match self.node(q) {
                Node::Or(c) if conj => Some(c),
                Node::And(c) if !conj => Some(c),
                _ => None,
            }
        };
        let subset = |a: &[Id], b: &[Id]| a.iter().all(|x| b.binary_search(x).is_ok());
        let drop: Vec<Id> = flat
            .iter()
            .copied()
            .filter(|&q| {
                let Some(c) = inner(q) else { return false };
                c.iter().any(|x| flat.contains(x))
                    || flat.iter().any(|&o| {
                        o != q && inner(o).is_some_and(|d| d.len() < c.len() && subset(d, c))
                    })
            })
            .collect();
        flat.retain(|q| !drop.contains(q));
    }

    pub fn next(&mut self, a: Id) -> Id {
        if a == Arena::FALSE {
            return a;
        }
        self.intern(Node::Next(a))
    }

    pub fn weak_next(&mut self, a: Id) -> Id {
        if a == Arena::TRUE {
            return a;
        }
        self.intern(Node::WeakNext(a))
    }

    pub fn eventually(&mut self, a: Id) -> Id {
        match a {
            Arena::FALSE => a,
            Arena::TRUE => self.non_empty(),
            _ => self.intern(Node::Eventually(a)),
        }
    }

    pub fn always(&mut self, a: Id) -> Id {
        if a == Arena::TRUE {
            return a;
        }
        self.intern(Node::Always(a))
    }

    pub fn until(&mut self, a: Id, b: Id) -> Id {
        match (a, b) {
            (_, Arena::FALSE) => Arena::FALSE,
            (Arena::FALSE, _) => b,
            (Arena::TRUE, _) => self.eventually(b),
            _ => self.intern(Node::Until(a, b)),
        }
    }

    pub fn release(&mut self, a: Id, b: Id) -> Id {
        match (a, b) {
            (_, Arena::TRUE) => Arena::TRUE,
            (Arena::FALSE, _) => self.always(b),
            _ => self.intern(Node::Release(a, b)),
        }
    }

    /// The negation normal form of `f`, negated when `neg`; atoms by `atom_index`.
    pub fn from_formula(
        &mut self,
        f: &Formula,
        neg: bool,
        atom_index: &dyn Fn(&str) -> Option<u32>,
    ) -> Result<Id, String> {
        let mut go = |g: &Formula, n: bool| self.from_formula(g, n, atom_index);
        Ok(match (&f.kind, neg) {
            (Kind::True, false) | (Kind::False, true) => Arena::TRUE,
            (Kind::False, false) | (Kind::True, true) => Arena::FALSE,
            (Kind::Atom(name), n) => {
                let i = atom_index(name).ok_or_else(|| format!("unknown atom `{name}`"))?;
                self.lit(i, n)
            }
            (Kind::Not(a), n) => go(a, !n)?,
            (Kind::And(a, b), false) | (Kind::Or(a, b), true) => {
                let (x, y) = (go(a, neg)?, go(b, neg)?);
                self.and([x, y])
            }
            (Kind::Or(a, b), false) | (Kind::And(a, b), true) => {
                let (x, y) = (go(a, neg)?, go(b, neg)?);
                self.or([x, y])
            }
            (Kind::Implies(a, b), false) => {
                let (x, y) = (go(a, true)?, go(b, false)?);
                self.or([x, y])
            }
            (Kind::Implies(a, b), true) => {
                let (x, y) = (go(a, false)?, go(b, true)?);
                self.and([x, y])
            }
            (Kind::Iff(a, b), n) => {
                // a <-> b = (a & b) | (!a & !b); negated: (a & !b) | (!a & b).
                let (pa, na) = (go(a, false)?, go(a, true)?);
                let (pb, nb) = (go(b, false)?, go(b, true)?);
                let (l, r) = if n {
                    (self.and([pa, nb]), self.and([na, pb]))
                } else {
                    (self.and([pa, pb]), self.and([na, nb]))
                };
                self.or([l, r])
            }
            (Kind::Next(a), false) | (Kind::WeakNext(a), true) => {
                let x = go(a, neg)?;
                self.next(x)
            }
            (Kind::WeakNext(a), false) | (Kind::Next(a), true) => {
                let x = go(a, neg)?;
                self.weak_next(x)
            }
            (Kind::Eventually(a), false) | (Kind::Always(a), true) => {
                let x = go(a, neg)?;
                self.eventually(x)
            }
            (Kind::Always(a), false) | (Kind::Eventually(a), true) => {
                let x = go(a, neg)?;
                self.always(x)
            }
            (Kind::Until(a, b), false) | (Kind::Release(a, b), true) => {
                let (x, y) = (go(a, neg)?, go(b, neg)?);
                self.until(x, y)
            }
            (Kind::Release(a, b), false) | (Kind::Until(a, b), true) => {
                let (x, y) = (go(a, neg)?, go(b, neg)?);
                self.release(x, y)
            }
            (Kind::WeakUntil(a, b), false) => {
                // a W b = b R (a | b).
                let (x, y) = (go(a, false)?, go(b, false)?);
                let ab = self.or([x, y]);
                self.release(y, ab)
            }
            (Kind::WeakUntil(a, b), true) => {
                // !(a W b) = !b U (!a & !b).
                let (x, y) = (go(a, true)?, go(b, true)?);
                let ab = self.and([x, y]);
                self.until(y, ab)
            }
        })
    }

    /// Whether `id` holds on the empty suffix (the route has ended): the acceptance of a state.
    pub fn accepts_empty(&self, id: Id) -> bool {
        match self.node(id) {
            Node::True | Node::End | Node::WeakNext(_) | Node::Release(..) | Node::Always(_) => {
                true
            }
            Node::False
            | Node::NonEmpty
            | Node::Lit { .. }
            | Node::Next(_)
            | Node::Until(..)
            | Node::Eventually(_) => false,
            Node::And(c) => c.iter().all(|&x| self.accepts_empty(x)),
            Node::Or(c) => c.iter().any(|&x| self.accepts_empty(x)),
        }
    }

    /// Atoms occurring in `id`, ascending.
    pub fn atoms_of(&self, id: Id, out: &mut Vec<u32>) {
        match self.node(id) {
            Node::Lit { atom, .. } => {
                if let Err(at) = out.binary_search(atom) {
                    out.insert(at, *atom);
                }
            }
            Node::And(c) | Node::Or(c) => {
                for &x in c.clone().iter() {
                    self.atoms_of(x, out);
                }
            }
            Node::Next(a) | Node::WeakNext(a) | Node::Eventually(a) | Node::Always(a) => {
                self.atoms_of(*a, out)
            }
            Node::Until(a, b) | Node::Release(a, b) => {
                self.atoms_of(*a, out);
                self.atoms_of(*b, out);
            }
            _ => {}
        }
    }
}

/// Direct LTLf semantics: does `f` hold at position `i` of `trace` (each letter the set of atom
/// indices true there, as a bit mask)? `i < trace.len()` is required for atoms to hold.
pub fn holds(f: &Formula, trace: &[u64], i: usize, atom: &dyn Fn(&str) -> Option<u32>) -> bool {
    let n = trace.len();
    let at = |g: &Formula, j: usize| holds(g, trace, j, atom);
    match &f.kind {
        Kind::True => true,
        Kind::False => false,
        Kind::Atom(a) => i < n && atom(a).is_some_and(|k| trace[i] >> k & 1 == 1),
        Kind::Not(a) => !at(a, i),
        Kind::And(a, b) => at(a, i) && at(b, i),
        Kind::Or(a, b) => at(a, i) || at(b, i),
        Kind::Implies(a, b) => !at(a, i) || at(b, i),
        Kind::Iff(a, b) => at(a, i) == at(b, i),
        Kind::Next(a) => i + 1 < n && at(a, i + 1),
        Kind::WeakNext(a) => i + 1 >= n || at(a, i + 1),
        Kind::Eventually(a) => (i..n).any(|j| at(a, j)),
        Kind::Always(a) => (i..n).all(|j| at(a, j)),
        Kind::Until(a, b) => (i..n).any(|j| at(b, j) && (i..j).all(|k| at(a, k))),
        Kind::Release(a, b) => (i..n).all(|j| at(b, j) || (i..j).any(|k| at(a, k))),
        Kind::WeakUntil(a, b) => {
            (i..n).any(|j| at(b, j) && (i..j).all(|k| at(a, k))) || (i..n).all(|j| at(a, j))
        }
    }
}
