//! The integration tests of `eamadm`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

mod common;
mod config;
mod run;
