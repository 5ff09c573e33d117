//! Integration tests of `eamadm`, one module per concern.
#![expect(
    clippy::unwrap_used,
    reason = "tests and their helpers unwrap: a failure there is the test failing"
)]

mod bounds;
mod fuzz_inputs;
mod input_files;
mod mutate;
mod names;
