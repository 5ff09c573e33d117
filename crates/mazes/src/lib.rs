//! Grid-maze tasks (Task I and Task II of the EA-MADM paper) for tabular reinforcement learning.
//!
//! Not implemented yet: this crate is an empty library until its issue lands.
//! See `docs/ARCHITECTURE.md` for what it will hold.
