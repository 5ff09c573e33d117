//! Integration tests of `ea-tree`, one module per concern.
#![expect(
    clippy::unwrap_used,
    reason = "tests and their helpers unwrap: a failure there is the test failing"
)]

mod fuzz_load;
mod saved_files;
