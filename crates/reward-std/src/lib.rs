//! Standardisation of sub-task rewards into the source task's reward, from the EA-MADM paper
//! (*An Experience Aggregative Reinforcement Learning With Multi-Attribute Decision-Making for
//! Obstacle Avoidance of Wheeled Mobile Robot*, Sec. IV.A, Eq. 10–12).
//!
//! The source task learns from one reward per step, computed from the `m` rewards its
//! sub-tasks receive for the same transition.
//!
//! * [`cross_sectional`]: **Eq. 10–12 exactly as printed.** Standardise the `m` rewards of one
//!   step against their own mean and population standard deviation, then average the
//!   z-scores. **The average is identically 0** (z-scores always sum to zero), and Eq. 11 is
//!   0/0 when all rewards are equal, which we define as all z-scores 0. Taken literally, the
//!   source task learns from a reward of 0 on every step; this crate ships the literal form
//!   and a property test proving the degeneracy.
//! * [`RunningStandardiser`]: **our repair.** Each sub-task's reward is standardised against
//!   *its own* running mean and population standard deviation over the episode (Welford,
//!   [`reset`](RunningStandardiser::reset) at episode start), the current reward included;
//!   the z-scores are averaged over sub-tasks. `σ = 0` (e.g. the first step) gives 0.
//! * [`RewardStandardiser`] switches between them by a serde config value,
//!   [`Standardisation`] (`"running"`, the default, or `"cross_sectional"`).
//!
//! Nothing here returns NaN for finite input: NaN, infinite, empty or mis-sized input is a
//! typed [`RewardStdError`]. Nothing allocates per step.
//!
//! # Example
//!
//! ```
//! use reward_std::{RunningStandardiser, cross_sectional};
//!
//! // One step, three sub-tasks ("reach faster", "do not hit", "keep the target in view").
//! let rewards = [1.0, -0.3, 2.0];
//! let mut z = [0.0; 3];
//! let literal = cross_sectional(&rewards, &mut z)?;
//! assert!(literal.abs() < 1e-15); // Eq. 12: always 0
//!
//! let mut running = RunningStandardiser::new(3)?;
//! running.reset(); // episode start
//! assert_eq!(running.push(&rewards)?, 0.0); // the first step has nothing to compare with
//! let signal = running.push(&[-1.0, -0.3, 2.0])?; // "reach faster" got worse
//! assert!(signal < 0.0);
//! # Ok::<(), reward_std::RewardStdError>(())
//! ```

mod cross_sectional;
mod error;
mod running;
mod standardiser;

pub use cross_sectional::cross_sectional;
pub use error::RewardStdError;
pub use running::{MAX_ABS_REWARD, RunningStandardiser};
pub use standardiser::{RewardStandardiser, Standardisation};
