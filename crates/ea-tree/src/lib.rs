//! Experience-aggregation tree: Jaccard-clustered storage of (s, a, Q1, Q2) samples (EA-MADM paper, Sec. IV.B).
//!
//! Not implemented yet: this crate is an empty library until its issue lands.
//! See `docs/ARCHITECTURE.md` for what it will hold.
