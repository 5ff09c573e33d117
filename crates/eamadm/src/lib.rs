//! Experience-aggregative RL with multi-attribute decision-making (EA-MADM): the method, its competitors and the experiment runner.
//!
//! Not implemented yet: this crate is an empty library until its issue lands.
//! See `docs/ARCHITECTURE.md` for what it will hold.
