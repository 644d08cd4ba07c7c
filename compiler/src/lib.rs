//! placeholder
mod calls;
mod categories;
pub mod check;
pub mod diagnostic;
pub mod eval;
mod hints;
pub mod ir;
pub mod lower;
mod ranges;
pub mod resolve;
mod scopecheck;
mod slot;
pub mod suggest;
mod typecheck;
pub use check::{CheckResult, check};
pub mod lsp;
pub mod ltl;
pub mod verify;
