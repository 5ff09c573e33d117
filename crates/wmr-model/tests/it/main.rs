//! The `wmr-model` integration tests gathered into one test binary (one module per topic).

mod refusals;
