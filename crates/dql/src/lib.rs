//! Tabular double Q-learning (work in progress: only the environment interface is in place).
//!
//! This crate will hold the learning core of the EA-MADM paper (Sec. III.C, Eq. 9,
//! Algorithm 1). Today it defines the [`Environment`] interface that the task crates
//! (`mazes`, `wmr-model`) implement.

pub mod env;

pub use env::{Environment, Step};
