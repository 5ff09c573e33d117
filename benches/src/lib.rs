//! Criterion benchmarks of the eamadm crates; the code is in `benches/benches/*.rs`, one file per
//! measured crate (`<crate>_<what>.rs`), run with `cargo bench -p eamadm-benches`.
//!
//! They live in their own package so that `cargo test` and `cargo test -p <crate>` never compile
//! criterion: a dev-dependency is built for every test target of the crate that declares it.
//! This library is empty on purpose.
