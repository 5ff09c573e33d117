//! What a learner learns from, which need not be the task's own reward.

use crate::env::Step;
use crate::error::DqlError;

/// The reward a learner is trained on, computed from each transition.
///
/// Plain agents learn from the task's reward ([`TaskRewardSignal`]); a sub-task learner
/// from one sub-task's reward ([`SubtaskRewardSignal`]); the EA-MADM source task from a
/// standardised combination of all sub-task rewards (Eq. 10–12, implemented by
/// the facade). The episode driver reports the *task* return whatever the signal.
pub trait RewardSignal {
    /// Called once before each episode with the environment's number of sub-tasks
    /// (reset running statistics here; reject an impossible configuration).
    ///
    /// # Errors
    /// Any [`DqlError`] that makes the episode impossible; the driver returns it
    /// before resetting the environment.
    fn begin_episode(&mut self, n_subtasks: usize) -> Result<(), DqlError> {
        let _ = n_subtasks;
        Ok(())
    }

    /// The learning reward for the transition `step`, whose sub-task rewards are
    /// `subtask_rewards` (the environment's
    /// [`subtask_rewards`](crate::Environment::subtask_rewards) for that step).
    /// Should be finite: the driver rejects a non-finite signal with
    /// [`DqlError::NonFiniteReward`]. Should not allocate.
    fn learning_reward(&mut self, step: &Step, subtask_rewards: &[f64]) -> f64;
}

/// Learn from the task's own reward, [`Step::reward`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TaskRewardSignal;

impl RewardSignal for TaskRewardSignal {
    #[inline]
    fn learning_reward(&mut self, step: &Step, _subtask_rewards: &[f64]) -> f64 {
        step.reward
    }
}

/// Learn from sub-task `k`'s reward, `subtask_rewards()[k]` (sub-task pre-training).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SubtaskRewardSignal(pub usize);

impl RewardSignal for SubtaskRewardSignal {
    fn begin_episode(&mut self, n_subtasks: usize) -> Result<(), DqlError> {
        if self.0 < n_subtasks {
            Ok(())
        } else {
            Err(DqlError::SubtaskOutOfRange {
                index: self.0,
                n_subtasks,
            })
        }
    }

    #[inline]
    fn learning_reward(&mut self, _step: &Step, subtask_rewards: &[f64]) -> f64 {
        // An environment that breaks its contract mid-episode (too few sub-task
        // rewards) yields NaN, which the driver reports as an error.
        subtask_rewards.get(self.0).copied().unwrap_or(f64::NAN)
    }
}
