//! The source task's learning signal: the sub-task rewards of each step, standardised and
//! averaged (Sec. IV.A, Eq. 10–12).

use dql::{DqlError, RewardSignal, Step};
use reward_std::{RewardStandardiser, RewardStdError, Standardisation};

/// [`RewardSignal`] of the EA-MADM source task: each step's sub-task rewards
/// (`env.subtask_rewards()`) go through a [`RewardStandardiser`], and the source task learns
/// from the result; the task's own reward is only reported.
///
/// * [`Standardisation::CrossSectional`] is Eq. 10–12 as printed: the mean of the z-scores of
///   one step's rewards, **identically 0** (exactly 0.0 on the mazes, whose two sub-task
///   rewards give z-scores ±1). The source task then learns nothing and its own values stay
///   at their initial values; EA-MADM decides on the sub-tasks' experience alone.
/// * [`Standardisation::Running`] (our repair, the default) standardises each sub-task's
///   reward against its own running statistics over the episode, then averages.
///
/// The statistics restart at every episode. Nothing is allocated per step.
#[derive(Debug, Clone)]
pub struct StandardisedReward {
    standardiser: RewardStandardiser,
}

impl StandardisedReward {
    /// A signal over `subtasks` sub-task rewards per step.
    ///
    /// # Errors
    /// [`RewardStdError::Empty`] when `subtasks` is 0.
    pub fn new(mode: Standardisation, subtasks: usize) -> Result<Self, RewardStdError> {
        Ok(Self {
            standardiser: RewardStandardiser::new(mode, subtasks)?,
        })
    }

    /// The standardisation in use.
    #[must_use]
    pub fn mode(&self) -> Standardisation {
        self.standardiser.mode()
    }
}

impl RewardSignal for StandardisedReward {
    fn begin_episode(&mut self, n_subtasks: usize) -> Result<(), DqlError> {
        if n_subtasks != self.standardiser.subtasks() {
            return Err(DqlError::ShapeMismatch {
                what: "sub-task count",
                environment: n_subtasks,
                learner: self.standardiser.subtasks(),
            });
        }
        self.standardiser.reset();
        Ok(())
    }

    #[inline]
    fn learning_reward(&mut self, _step: &Step, subtask_rewards: &[f64]) -> f64 {
        // A rejected input (wrong length, non-finite) becomes NaN, which the episode driver
        // reports as `DqlError::NonFiniteReward`.
        self.standardiser.push(subtask_rewards).unwrap_or(f64::NAN)
    }
}
