//! The integration tests of `wmr-model`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

mod default_scenario;
mod properties;
mod refusals;
mod scenarios;
mod snapshot;
mod snapshots;
