//! The integration tests of `ea-tree`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

mod common;
mod exact_table;
mod indexed_vs_literal;
mod laws;
mod persistence;
mod snapshots;
