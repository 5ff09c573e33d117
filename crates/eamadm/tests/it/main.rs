//! The integration tests of `eamadm`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

#![expect(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

mod behaviour;
mod bounds;
mod common;
mod config;
mod controls;
mod family;
mod fuzz_inputs;
mod input_files;
mod mutate;
mod names;
mod oracle;
mod pairing;
mod readings;
mod robot_refusals;
mod run;
mod shared;
mod tuning;
