//! One integration-test binary for the crate: each module was once its own test target.
//! Linking the workspace once instead of once per file is most of a fresh build's time.

mod ablate_cli;
mod check_cli;
mod common;
mod compile_cli;
mod docs_benchmark;
mod explain_cli;
mod faults_episode;
mod faults_io;
mod faults_lsp;
mod faults_outputs;
mod faults_replies;
mod faults_report;
mod faults_rundir;
mod import_cli;
mod lsp_stdio;
mod ltl_cli;
mod map_cache;
mod nav2_cli;
mod robot_out;
mod run_cli;
mod serve_cli;
mod table1_cli;
mod tools_mcp;
mod usability_cli;
