//! One module per subcommand.

pub mod ablate;
pub mod ablate_grounding;
pub mod baseline;
pub mod bench;
pub mod bench_import;
pub mod bench_table1;
pub mod check;
pub mod compile;
pub mod eval;
pub mod fmt;
pub mod lsp;
pub mod ltl;
pub mod map;
pub mod map_check;
pub mod prompt;
pub mod route_out;
pub mod run;
pub mod serve;
pub mod serve_route;
pub mod suite;
pub mod tools;
