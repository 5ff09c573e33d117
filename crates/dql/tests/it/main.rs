//! The integration tests of `dql`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

mod bounds;
mod common;
mod convergence;
mod driver;
mod laws;
mod learners;
mod maximisation_bias;
mod pinned;
mod serde_forms;
mod value_iteration;
