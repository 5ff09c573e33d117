//! The integration tests of `eamadm-eval`, compiled as one test binary (one module per topic).

#![expect(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

mod band;
mod chains;
mod claims;
mod family;
mod findings;
mod hierarchical;
mod margins;
mod monte_carlo;
mod paired;
mod paired_mean;
mod resampling;
mod sensitivity;
mod stats;
