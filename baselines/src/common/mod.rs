//! The pieces every baseline shares, written once: the instance inventory of atomic propositions,
//! the 1 m object-label radius, prefix-LTL text, LTLf progression on m2rc's formula type, masked
//! grid search over m2rc's A*, the gold annotations an oracle may read, and failure records.

pub mod failure;
pub mod gold;
pub mod grid;
pub mod inventory;
pub mod labels;
pub mod prefix_ltl;
pub mod progress;

/// The start cell of every baseline: the benchmark's rule (`start_pose`, else the first expert
/// waypoint), so every method and the scorer start from the same cell.
pub use m2rc_benchmark::methods::start_cell;
