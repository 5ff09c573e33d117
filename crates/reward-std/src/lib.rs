//! Cross-sectional and running standardisation of sub-task rewards (EA-MADM paper, Eq. 10-12).
//!
//! Not implemented yet: this crate is an empty library until its issue lands.
//! See `docs/ARCHITECTURE.md` for what it will hold.
