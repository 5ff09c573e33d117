//! Integration tests of `dql`, one module per concern.

mod bounds;
