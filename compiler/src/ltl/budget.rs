//! The work budget of the automaton construction.
//!
//! Progression is exponential in the worst case (`F a0 & ... & F a29` has 2^30 states, and its
//! first state alone has 2^30 guard cubes), and the state limit alone is checked too late: a
//! single state can take minutes and gigabytes before it has a successor. So every step that can
//! grow (a node of the Shannon expansion, a residual term, a guard cube, a comparison while
//! minimising) is paid for here as it happens, and the construction stops with an error the
//! moment it is over. The count is of steps, not of time, so the same formula is refused or
//! built the same way on every machine and every run.

use super::dfa::BuildError;

/// Steps the construction may take: a fraction of a second of a development build, a few tens of
/// megabytes at most. A route's formula needs far fewer (four ordered visits, two avoids and an
/// until over 8 atoms: about 14 000; nine unordered visits, 512 states: 7.6 million; ten
/// unordered visits pass the limit). `m2rc ltl --bench 1` prints what a formula takes.
pub const MAX_WORK: u64 = 20_000_000;
/// Guard cubes (edges before merging) of the unminimised automaton: what its edges hold in
/// memory.
pub const MAX_CUBES: u64 = 200_000;

#[derive(Clone, Debug)]
pub struct Budget {
    work: u64,
    cubes: u64,
    max_work: u64,
    max_cubes: u64,
    /// States explored so far, for the message.
    pub states: usize,
}

impl Default for Budget {
    fn default() -> Self {
        Budget::new(MAX_WORK, MAX_CUBES)
    }
}

impl Budget {
    pub fn new(max_work: u64, max_cubes: u64) -> Self {
        Budget {
            work: 0,
            cubes: 0,
            max_work,
            max_cubes,
            states: 0,
        }
    }

    /// Pays `units` steps of work.
    pub fn spend(&mut self, units: u64) -> Result<(), BuildError> {
        self.work = self.work.saturating_add(units);
        if self.work > self.max_work {
            return Err(BuildError::Budget {
                what: "construction steps",
                limit: self.max_work,
                states: self.states,
            });
        }
        Ok(())
    }

    /// Pays one guard cube (and the step that made it).
    pub fn cube(&mut self) -> Result<(), BuildError> {
        self.cubes += 1;
        if self.cubes > self.max_cubes {
            return Err(BuildError::Budget {
                what: "guard cubes",
                limit: self.max_cubes,
                states: self.states,
            });
        }
        self.spend(1)
    }

    /// Steps spent so far (for tests and the benchmark figures).
    pub fn used(&self) -> u64 {
        self.work
    }
}
