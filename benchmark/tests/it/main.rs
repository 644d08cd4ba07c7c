//! One integration-test binary for the crate: each module was once its own test target.
//! Linking the workspace once instead of once per file is most of a fresh build's time.

mod budget;
mod episode_png;
mod eval_props;
mod formats_doc;
mod grounding2route;
mod ltl_differential;
mod nav2_roundtrip;
mod prompt_lexicon;
mod reference_vectors;
mod report_methods;
mod runner_resume;
mod suite_build;
