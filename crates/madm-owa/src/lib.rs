//! OWA aggregation, natural visibility graphs and visibility-weighted multi-attribute decisions (EA-MADM paper, Eq. 3, 13-16).
//!
//! Not implemented yet: this crate is an empty library until its issue lands.
//! See `docs/ARCHITECTURE.md` for what it will hold.
