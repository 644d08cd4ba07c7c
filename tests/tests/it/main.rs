//! One integration-test binary for the end-to-end tests (docs, examples, UI).

mod docs;
mod examples;
mod ui;
