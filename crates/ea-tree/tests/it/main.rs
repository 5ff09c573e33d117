//! The integration tests of `ea-tree`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

#![expect(
    clippy::unwrap_used,
    reason = "tests and their helpers unwrap: a failure there is the test failing"
)]

mod common;
mod exact_table;
mod fuzz_load;
mod indexed_vs_literal;
mod laws;
mod persistence;
mod snapshots;
