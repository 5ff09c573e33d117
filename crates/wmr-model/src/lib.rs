//! A 2D wheeled mobile robot (e-puck class) and its obstacle-avoidance task for tabular reinforcement learning.
//!
//! Not implemented yet: this crate is an empty library until its issue lands.
//! See `docs/ARCHITECTURE.md` for what it will hold.
