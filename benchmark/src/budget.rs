//! The per-episode budget: whatever a program does (a model's reply is untrusted), one episode
//! cannot stop a benchmark run or `m2rc run`. Every compile and plan of an episode (all repair
//! rounds, all re-binding plans) draws on one [`Meter`], checked cooperatively as the pipeline
//! goes:
//!
//! * **work**: planner expansions summed over the episode. Each plan is given what is left as its
//!   expansion budget, so the planner's own loops stop at it; reproducible (same inputs, same
//!   verdict on any machine).
//! * **memory estimate**: before a product-graph (LTL) search, its size (grid cells × automaton
//!   states × bytes a state) is compared with the budget, and the search is refused instead of
//!   run; reproducible too.
//! * **wall time** (off by default): checked between phases (before checking, grounding and every
//!   plan). Not reproducible, so an episode stopped by it says "wall time" in its reason.
//!
//! The automaton construction of a `route ltl` formula carries its own work limit (E0810) in the
//! compiler. An episode over its budget is recorded with status `budget_exceeded` and the reason,
//! and the run goes on.

use m2rc_compiler::diagnostic::{Code, Diagnostic};
use m2rc_grammar::ast::Span;
use serde::{Deserialize, Serialize};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Limits of one episode. The reproducible parts belong to a method's configuration (and so to
/// a run's fingerprint) when they differ from the defaults; the wall time never does.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct EpisodeBudget {
    /// Planner expansions over all of the episode's plans; 0 = unlimited.
    pub max_expansions: u64,
    /// Estimated memory of one product-graph search, in MiB; 0 = unlimited.
    pub max_product_mb: u64,
    /// Wall time of the whole episode's compiling and planning; `None` = unlimited.
    #[serde(skip)]
    pub max_wall: Option<Duration>,
}

impl EpisodeBudget {
    /// Whether the reproducible limits are the defaults (left out of a configuration, so runs
    /// made before the budget existed keep their fingerprint).
    pub fn is_default(&self) -> bool {
        let d = EpisodeBudget::default();
        self.max_expansions == d.max_expansions && self.max_product_mb == d.max_product_mb
    }

    /// From the `--episode-*` flags.
    pub fn from_args(a: &m2rc_llm::args::BudgetArgs) -> Result<Self, String> {
        let max_wall = match a.episode_max_seconds {
            None => None,
            Some(s) if s.is_finite() && s > 0.0 => Some(Duration::from_secs_f64(s)),
            Some(s) => {
                return Err(format!(
                    "--episode-max-seconds {s} must be a positive number of seconds"
                ));
            }
        };
        Ok(EpisodeBudget {
            max_expansions: a.episode_max_expansions,
            max_product_mb: a.episode_max_product_mb,
            max_wall,
        })
    }
}

/// Default work budget: 20 plans' worth of the reference profile's one million expansions per
/// segment, far above any suite episode (a Hard episode takes well under a million).
pub const DEFAULT_MAX_EXPANSIONS: u64 = 20_000_000;
/// Default memory estimate for one product-graph search: 2 GiB.
pub const DEFAULT_MAX_PRODUCT_MB: u64 = 2048;
/// Bytes a product state takes in the estimate (cost, predecessor, heap entry, visited bit).
pub const PRODUCT_STATE_BYTES: u64 = 24;

impl Default for EpisodeBudget {
    fn default() -> Self {
        EpisodeBudget {
            max_expansions: DEFAULT_MAX_EXPANSIONS,
            max_product_mb: DEFAULT_MAX_PRODUCT_MB,
            max_wall: None,
        }
    }
}

/// What one episode has spent of its budget. Shared by its compiles (and safe across threads).
#[derive(Debug)]
pub struct Meter {
    pub budget: EpisodeBudget,
    started: Instant,
    expansions: AtomicU64,
    exceeded: Mutex<Option<String>>,
}

impl Meter {
    pub fn new(budget: EpisodeBudget) -> Self {
        Meter {
            budget,
            started: Instant::now(),
            expansions: AtomicU64::new(0),
            exceeded: Mutex::new(None),
        }
    }

    /// Why the episode went over its budget, once it has.
    pub fn exceeded(&self) -> Option<String> {
        self.exceeded
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }

    /// Planner expansions spent so far.
    pub fn expansions(&self) -> u64 {
        self.expansions.load(Ordering::Relaxed)
    }

    fn over(&self, reason: String) -> Box<Diagnostic> {
        let mut slot = self.exceeded.lock().unwrap_or_else(|p| p.into_inner());
        let reason = slot.get_or_insert(reason).clone();
        Box::new(Diagnostic::new(Code::BudgetExceeded, Span::default(), reason).help("the episode is recorded as `budget_exceeded`; raise the budget (`--episode-max-expansions`, `--episode-max-product-mb`, `--episode-max-seconds`) if the program is meant to be this large"))
    }

    /// Ends the episode for `reason` (a program past the size limits of `crate::limits`, whose
    /// plans the per-plan budgets would not bound: they are per segment).
    pub fn refuse(&self, reason: String) -> Box<Diagnostic> {
        self.over(reason)
    }

    /// Before a phase: an error once any part of the budget is spent.
    pub fn check(&self) -> Result<(), Box<Diagnostic>> {
        if let Some(r) = self.exceeded() {
            return Err(self.over(r));
        }
        let b = &self.budget;
        if b.max_expansions > 0 && self.expansions() >= b.max_expansions {
            return Err(self.over(format!(
                "the episode's work budget of {} planner expansions is spent",
                b.max_expansions
            )));
        }
        if let Some(limit) = b.max_wall
            && self.started.elapsed() > limit
        {
            return Err(self.over(format!(
                "the episode's time budget of {:.1} s (wall time, not reproducible) ran out",
                limit.as_secs_f64()
            )));
        }
        Ok(())
    }

    /// The expansion budget for the next plan: what is left, within `own` (the profile's budget;
    /// 0 = unlimited).
    pub fn plan_budget(&self, own: u64) -> u64 {
        if self.budget.max_expansions == 0 {
            return own;
        }
        let left = self
            .budget
            .max_expansions
            .saturating_sub(self.expansions())
            .max(1);
        if own == 0 { left } else { own.min(left) }
    }

    /// Counts a plan's expansions; an error when they used up the work budget.
    pub fn spend(&self, expansions: u64) -> Result<(), Box<Diagnostic>> {
        let _ = self
            .expansions
            .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |e| {
                Some(e.saturating_add(expansions))
            });
        self.check()
    }

    /// Refuses a product-graph search whose estimated size is past the memory budget.
    pub fn check_product(&self, cells: u64, states: u64) -> Result<(), Box<Diagnostic>> {
        let mb = self.budget.max_product_mb;
        let bytes = cells
            .saturating_mul(states)
            .saturating_mul(PRODUCT_STATE_BYTES);
        if mb > 0 && bytes > mb.saturating_mul(1 << 20) {
            return Err(self.over(format!(
                "the route's product graph ({cells} cells × {states} automaton states) would \
                 take about {} MiB, more than the episode's memory budget of {mb} MiB",
                bytes >> 20
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_and_memory_are_metered_and_the_first_reason_is_kept() {
        let m = Meter::new(EpisodeBudget {
            max_expansions: 100,
            max_product_mb: 1,
            max_wall: None,
        });
        assert!(m.check().is_ok());
        assert_eq!(m.plan_budget(0), 100);
        assert_eq!(m.plan_budget(30), 30);
        assert!(m.spend(60).is_ok());
        assert_eq!(m.plan_budget(1_000_000), 40);
        assert!(m.check_product(1000, 40).is_ok());
        let e = m.check_product(250_000, 16).unwrap_err();
        assert_eq!(e.code, Code::BudgetExceeded);
        assert!(
            e.message.contains("memory budget of 1 MiB"),
            "{}",
            e.message
        );
        // Spent work after that: the first reason stays the episode's reason.
        assert!(m.spend(60).is_err());
        assert!(m.exceeded().unwrap().contains("product graph"));
        let unlimited = Meter::new(EpisodeBudget {
            max_expansions: 0,
            max_product_mb: 0,
            max_wall: None,
        });
        assert!(unlimited.spend(u64::MAX / 2).is_ok());
        assert_eq!(unlimited.plan_budget(7), 7);
        assert!(unlimited.check_product(u64::MAX, 2).is_ok());
    }

    #[test]
    fn a_spent_wall_time_budget_says_so() {
        let m = Meter::new(EpisodeBudget {
            max_wall: Some(Duration::ZERO),
            ..EpisodeBudget::default()
        });
        std::thread::sleep(Duration::from_millis(2));
        let e = m.check().unwrap_err();
        assert!(e.message.contains("wall time"), "{}", e.message);
    }
}
