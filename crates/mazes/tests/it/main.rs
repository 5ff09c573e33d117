//! The integration tests of `mazes`, compiled as one test binary (one module per topic)
//! so that `cargo test` links one executable per crate instead of one per file.

mod bounds;
mod common;
mod env;
mod fixtures;
mod generation;
mod layouts;
mod map_text;
mod model;
mod path;
mod render;
mod subtasks;
