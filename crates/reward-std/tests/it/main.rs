//! The integration tests of `reward-std`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

mod examples;
mod laws;
mod precision;
mod snapshots;
