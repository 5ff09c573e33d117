//! Integration tests of `reward-std`, one module per concern.

mod precision;
