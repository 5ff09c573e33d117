//! The integration tests of `eamadm`, one test binary with one module per subject.

mod robot_refusals;
mod stats;
