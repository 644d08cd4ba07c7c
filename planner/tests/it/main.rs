//! One integration-test binary for the crate: each module was once its own test target.
//! Linking the workspace once instead of once per file is most of a fresh build's time.

mod fixture;
mod fixture_route;
mod lower;
mod planners;
mod properties;
mod set_goals;
