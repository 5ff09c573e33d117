//! The integration tests of `madm-owa`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

mod laws;
mod snapshots;
mod worked_examples;
