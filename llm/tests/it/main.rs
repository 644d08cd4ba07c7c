//! One integration-test binary for the crate: each module was once its own test target.
//! Linking the workspace once instead of once per file is most of a fresh build's time.

mod mock_server;
mod replies;
