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

#[cfg(test)]
mod tests {
    use super::*;
    use mazes::{Event, TaskSpec};
    use proptest::prelude::*;

    const STEP: Step = Step {
        next_state: 0,
        reward: 0.0,
        terminated: false,
        truncated: false,
    };

    /// The sub-task reward rows of every maze event, Task I and Task II.
    fn maze_rows() -> Vec<[f64; 2]> {
        [TaskSpec::task1(), TaskSpec::task2()]
            .iter()
            .flat_map(|spec| {
                Event::ALL.map(|event| {
                    [
                        spec.subtasks[0].reward.reward(event),
                        spec.subtasks[1].reward.reward(event),
                    ]
                })
            })
            .collect()
    }

    #[test]
    fn literal_signal_is_exactly_zero_on_every_maze_event() {
        let mut signal = StandardisedReward::new(Standardisation::CrossSectional, 2).unwrap();
        signal.begin_episode(2).unwrap();
        for row in maze_rows() {
            assert_eq!(signal.learning_reward(&STEP, &row), 0.0, "{row:?}");
        }
    }

    #[test]
    fn running_signal_is_not_zero() {
        let mut signal = StandardisedReward::new(Standardisation::Running, 2).unwrap();
        signal.begin_episode(2).unwrap();
        let rewards: Vec<f64> = maze_rows()
            .iter()
            .map(|row| signal.learning_reward(&STEP, row))
            .collect();
        assert!(rewards.iter().any(|r| *r != 0.0), "{rewards:?}");
        assert!(rewards.iter().all(|r| r.is_finite()));
    }

    #[test]
    fn sub_task_count_must_match() {
        let mut signal = StandardisedReward::new(Standardisation::Running, 3).unwrap();
        assert!(matches!(
            signal.begin_episode(2),
            Err(DqlError::ShapeMismatch { .. })
        ));
        assert!(StandardisedReward::new(Standardisation::Running, 0).is_err());
        // A contract breach mid-episode becomes NaN, which the driver rejects.
        signal.begin_episode(3).unwrap();
        assert!(signal.learning_reward(&STEP, &[1.0]).is_nan());
    }

    proptest! {
        /// Eq. 12 is identically zero: whatever the sub-task rewards, the literal signal is 0
        /// up to rounding.
        #[test]
        fn literal_signal_vanishes(rewards in proptest::collection::vec(-1e3..1e3_f64, 1..6)) {
            let mut signal = StandardisedReward::new(Standardisation::CrossSectional, rewards.len()).unwrap();
            signal.begin_episode(rewards.len()).unwrap();
            prop_assert!(signal.learning_reward(&STEP, &rewards).abs() < 1e-12);
        }
    }
}
