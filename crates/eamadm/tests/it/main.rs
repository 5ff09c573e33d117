//! The eamadm integration tests in one binary; each module is one topic.

#![expect(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

#[path = "../common/mod.rs"]
mod common;

mod behaviour;
mod claims;
mod controls;
mod robot_refusals;
mod stats;
