//! Integration tests of `mazes`, one module per concern.

mod bounds;
