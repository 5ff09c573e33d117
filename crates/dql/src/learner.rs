//! The interface the episode driver and exploration policies see a learner through.

use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::error::{DqlError, check_index};
use crate::table::QTable;

/// One visited state–action pair with its final estimates: the experience sample
/// `(s, a, Q1(s, a), Q2(s, a))` of the paper's Sec. IV.B, plus how often it was updated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ExperienceSample {
    /// State index.
    pub state: usize,
    /// Action index.
    pub action: usize,
    /// `Q1(state, action)`.
    pub q1: f64,
    /// `Q2(state, action)` (equal to `q1` for a single-estimator learner).
    pub q2: f64,
    /// Number of updates of this pair (at least 1).
    pub updates: u32,
}

/// A tabular value learner: it turns transitions into action values.
///
/// Implemented by [`DoubleQ`](crate::DoubleQ) (Eq. 9, corrected) and
/// [`QLearning`](crate::QLearning) (Eq. 2). The learner owns one or two
/// [`QTable`]s and an update counter per state–action pair, so the pairs an
/// agent has experienced can be exported with [`experience`](Learner::experience).
pub trait Learner {
    /// Number of states.
    fn n_states(&self) -> usize;

    /// Number of actions.
    fn n_actions(&self) -> usize;

    /// Writes the action values that behaviour is derived from for `state` into
    /// `out` (one per action). For double Q this is the mean `(Q1 + Q2) / 2` by
    /// default (see [`BehaviourValues`](crate::BehaviourValues)); for Q-learning, `Q`.
    ///
    /// # Panics
    /// If `state >= n_states()` or `out.len() != n_actions()`.
    fn action_values(&self, state: usize, out: &mut [f64]);

    /// Learns from one transition `(state, action, reward, next_state)`.
    ///
    /// `terminated` means the episode ended inside the task: the target is
    /// `reward` alone, without bootstrapping from `next_state`. A truncated step
    /// (step cap) is passed with `terminated = false` and bootstraps as usual.
    /// Every random draw (which estimator to update, tie-breaks) comes from `rng`.
    /// Updates exactly one cell of exactly one table, and allocates nothing.
    ///
    /// # Panics
    /// If a state or the action is out of range.
    fn update<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action: usize,
        reward: f64,
        next_state: usize,
        terminated: bool,
        rng: &mut R,
    );

    /// [`update`](Learner::update) with its indices checked first: an out-of-range
    /// `state`, `action` or `next_state` is an [`DqlError::IndexOutOfRange`] and
    /// leaves the learner untouched (no random draw is taken either).
    ///
    /// `update` itself panics on such indices because they are a caller bug, and the
    /// training hot path must not pay for a `Result` per step; this variant is for
    /// callers whose indices come from outside (and for tests of the contract).
    ///
    /// # Errors
    /// [`DqlError::IndexOutOfRange`] naming the first argument out of range.
    fn try_update<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action: usize,
        reward: f64,
        next_state: usize,
        terminated: bool,
        rng: &mut R,
    ) -> Result<(), DqlError> {
        check_index("state", state, self.n_states())?;
        check_index("action", action, self.n_actions())?;
        check_index("next_state", next_state, self.n_states())?;
        self.update(state, action, reward, next_state, terminated, rng);
        Ok(())
    }

    /// `Q1(state, ·)`: the first estimator's values in `state`, one per action
    /// (the only estimator of a single-estimator learner).
    ///
    /// # Panics
    /// If `state >= n_states()`.
    fn q1_row(&self, state: usize) -> &[f64];

    /// `Q2(state, ·)` (the same values as [`q1_row`](Learner::q1_row) for a
    /// single-estimator learner).
    ///
    /// # Panics
    /// If `state >= n_states()`.
    fn q2_row(&self, state: usize) -> &[f64];

    /// `Q1(state, action)`.
    ///
    /// # Panics
    /// If a state or the action is out of range.
    fn q1(&self, state: usize, action: usize) -> f64 {
        self.q1_row(state)[action]
    }

    /// `Q2(state, action)`.
    ///
    /// # Panics
    /// If a state or the action is out of range.
    fn q2(&self, state: usize, action: usize) -> f64 {
        self.q2_row(state)[action]
    }

    /// A copy of the whole first estimator as a [`QTable`].
    fn q1_table(&self) -> QTable {
        QTable::from_rows(self.n_states(), self.n_actions(), |s| self.q1_row(s))
    }

    /// A copy of the whole second estimator as a [`QTable`].
    fn q2_table(&self) -> QTable {
        QTable::from_rows(self.n_states(), self.n_actions(), |s| self.q2_row(s))
    }

    /// How many times each state–action pair has been updated, row-major: the count of `(s, a)` is at `s * n_actions() + a`.
    /// Counts saturate at `u32::MAX`.
    fn update_counts(&self) -> &[u32];

    /// How many times `(state, action)` has been updated.
    ///
    /// # Panics
    /// If a state or the action is out of range.
    fn update_count(&self, state: usize, action: usize) -> u32 {
        assert!(action < self.n_actions(), "action {action} out of range");
        self.update_counts()[state * self.n_actions() + action]
    }

    /// Every state–action pair updated at least once, in row-major order, with
    /// its current `Q1`, `Q2` and update count: what the facade stores in an
    /// experience-aggregation tree after training a sub-task.
    fn experience(&self) -> impl Iterator<Item = ExperienceSample> + '_
    where
        Self: Sized,
    {
        let n_actions = self.n_actions();
        self.update_counts()
            .iter()
            .enumerate()
            .filter(|(_, count)| **count > 0)
            .map(move |(index, &updates)| {
                let (state, action) = (index / n_actions, index % n_actions);
                ExperienceSample {
                    state,
                    action,
                    q1: self.q1(state, action),
                    q2: self.q2(state, action),
                    updates,
                }
            })
    }
}
