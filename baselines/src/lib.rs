//! `m2rc-baselines`: the adapted methods of Map2Route's Table I, on m2rc's harness. Each method
//! keeps its own representation, map abstraction and planner (the point of the table is what each
//! representation can and cannot say) and reuses m2rc's parts where they compute the same thing.
//! `benchmark` never depends on this crate: the CLI builds a method here and hands it to the
//! runner as a `m2rc_benchmark::methods::Method`.
//!
//! # Adding a method
//!
//! Put it in its own folder `src/<method>/`, add `pub mod <method>;` below and one line to
//! [`registry::BASELINES`]. A method's `predict`:
//!
//! 1. opens a [`calls::Session`] (`Session::new(&setup, NAME, &map.map.map_id, episode)`) and
//!    makes every LLM call through `session.chat(step, messages, &gold)`, where `gold` is the
//!    method's oracle: it builds the perfect reply in the method's own format from
//!    [`common::gold::Gold`] (used only with `--llm gold`). Embeddings go through
//!    `session.embed(step, texts)`. A call returns `Err(Failure)` with status `pending` in a batch
//!    run: return that failure; the next run re-runs the method from its first call, answered
//!    from the cache.
//! 2. grounds into [`common::inventory::Inventory`] APs ([`common::labels`] for where an AP is
//!    true), reads formulas with [`common::prefix_ltl`] into m2rc's LTLf type, advances them with
//!    [`common::progress`], searches the grid with [`common::grid::GridSearch`], starting from
//!    [`common::start_cell`];
//! 3. returns [`common::failure::prediction`] with its route or a [`common::failure::Failure`]
//!    carrying the method's own status string, and a record block (`session.calls` under
//!    `"calls"`, plus the method's trace: grounding, formula, planner figures). The block is what
//!    `m2rc baseline explain` prints.
//!
//! `config()` returns `{"method": NAME, "m2rc": version, "model": setup.config(), ...}` plus the
//! method's own settings (budgets, radii), so a run resumed with other settings is refused.

pub mod calls;
pub mod common;
pub mod grounding;
pub mod iln;
pub mod lang2ltl;
pub mod lang2ltl2;
pub mod limp;
pub mod ltlcodegen;
pub mod osgllm;
pub mod registry;
pub mod sayplan;

pub use calls::{GOLD_LABEL, ModelSetup, Session};
pub use common::failure::Failure;
pub use registry::{
    BASELINES, BaselineArgs, Built, baseline_names, build, is_baseline, uses_embeddings,
};
