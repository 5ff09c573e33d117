//! The integration tests of `eamadm`, one test binary with one module per subject.

mod stats;
