//! The grammar crate's integration tests, in one binary (one link, one process): construct-by-
//! construct parses, error messages, the example programs in `tests/programs/`, and the
//! property tests.

mod grammar {
    pub mod comments;
    pub mod constructs;
    pub mod errors;
    pub mod programs;
    pub mod props;
    pub mod strategies;
}
