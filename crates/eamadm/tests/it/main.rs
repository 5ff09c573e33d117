//! The eamadm integration tests in one binary; each module is one topic.

#![expect(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

#[path = "../common/mod.rs"]
mod common;

mod behaviour;
mod bounds;
mod claims;
mod controls;
mod fuzz_inputs;
mod input_files;
mod mutate;
mod names;
mod robot_refusals;
mod stats;
