//! The exact Map2Route evaluator: HCS, PL, segment-wise SPL and raw soft-constraint values, as
//! the reference's current evaluator computes them, plus the summary aggregation.
//!
//! Entry points: [`EvalMap`] (built once per map), [`evaluate`] / [`evaluate_or_worst_case`]
//! (one route on one episode), [`aggregate`] (many episodes).

pub mod aggregate;
mod context;
pub mod evaluate;
pub mod geometry;
pub mod hcs;
pub mod map;
pub mod ndtw;
mod oracle;
pub mod path_shape;
pub mod pl;
pub mod soft;
pub mod spl;

pub use aggregate::{Aggregate, EpisodeRecord, MetricBlock, aggregate};
pub use context::EvalError;
pub use evaluate::{EpisodeMetrics, evaluate, evaluate_or_worst_case, worst_case_metrics};
pub use map::{EvalMap, MapError};
pub use soft::{EvalOptions, SoftDetail, soft_details};
