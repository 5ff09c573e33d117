//! The environment interface for discrete tasks, in Gymnasium's shape.

use crate::error::{DqlError, check_index};

/// What one call to [`Environment::step`] observed.
///
/// `terminated` and `truncated` follow Gymnasium's convention: a *terminated* step
/// ended the episode inside the task (goal reached, obstacle hit, target lost), so
/// its successor has no value and learners must not bootstrap from it; a
/// *truncated* step was cut by something outside the task (the step cap), so the
/// successor still has a value and learners bootstrap as usual. At most one of the
/// two is `true`; when both would apply, `terminated` wins and `truncated` is `false`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// Index of the state the action led to, in `0..n_states()`.
    pub next_state: usize,
    /// The task's own reward for this transition (the one learning curves plot).
    pub reward: f64,
    /// The episode ended inside the task: do not bootstrap from `next_state`.
    pub terminated: bool,
    /// The episode was cut by the step cap: bootstrap from `next_state` as usual.
    pub truncated: bool,
}

impl Step {
    /// `true` when the episode is over, for either reason.
    #[must_use]
    pub fn done(&self) -> bool {
        self.terminated || self.truncated
    }
}

/// A discrete, episodic task: finitely many states and actions, indexed from 0.
///
/// [`run_episode`](crate::run_episode) drives one episode of a learner on it;
/// what the learner learns from is chosen by a [`RewardSignal`](crate::RewardSignal)
/// ([`Step::reward`] for plain agents, one entry of
/// [`subtask_rewards`](Environment::subtask_rewards) for a sub-task learner),
/// while the episode's reported return is always the sum of [`Step::reward`].
///
/// # Contract
///
/// * [`reset`](Environment::reset) starts an episode and returns its initial state.
///   `Some(seed)` re-seeds the environment's own random stream (sensor noise,
///   random starts, …) so that everything after it is a function of the seed;
///   `None` continues the current stream. A fresh environment behaves as if it was
///   reset with some fixed seed documented by the implementation.
/// * [`step`](Environment::step) must only be called after `reset` and before the
///   step that returned `done()`; the result of stepping a finished episode is
///   unspecified but must not panic or produce non-finite rewards. An action
///   outside `0..n_actions()` may panic (it is a caller bug, not bad input);
///   [`try_step`](Environment::try_step) checks it and returns an error instead.
/// * Every state index returned is in `0..n_states()`; every reward is finite.
/// * After each `step`, [`subtask_rewards`](Environment::subtask_rewards) holds one
///   reward per sub-task for that same transition (the decomposition of the task
///   that EA-MADM trains sub-task learners on). Tasks without a decomposition
///   return an empty slice. Implementations keep these in a buffer they own, so
///   stepping allocates nothing.
/// * [`state_features`](Environment::state_features) describes a state by small
///   discrete features (for a grid: its column and row) so that state similarity
///   can be measured (the experience-aggregation tree does). It is not called on
///   the hot path; the default is the single feature `[state]`.
/// * Everything random in an environment comes from its own seeded generator;
///   an implementation never touches a global or thread-local RNG.
pub trait Environment {
    /// Number of states; state indices are `0..n_states()`.
    fn n_states(&self) -> usize;

    /// Number of actions; action indices are `0..n_actions()`.
    fn n_actions(&self) -> usize;

    /// Number of sub-tasks the task is decomposed into (0 when it is not).
    fn n_subtasks(&self) -> usize {
        0
    }

    /// Names of the sub-tasks, in the order of [`subtask_rewards`](Environment::subtask_rewards).
    fn subtask_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// Starts an episode and returns the initial state (see the trait docs for `seed`).
    fn reset(&mut self, seed: Option<u64>) -> usize;

    /// Applies `action` and returns what happened.
    fn step(&mut self, action: usize) -> Step;

    /// [`step`](Environment::step) with the action checked first: an action outside
    /// `0..n_actions()` is an [`DqlError::IndexOutOfRange`] and the environment is
    /// not stepped.
    ///
    /// `step` may panic on such an action (a caller bug; the hot path does not pay
    /// for a check); this variant is for callers whose actions come from outside.
    ///
    /// # Errors
    /// [`DqlError::IndexOutOfRange`] with `argument = "action"`.
    fn try_step(&mut self, action: usize) -> Result<Step, DqlError> {
        check_index("action", action, self.n_actions())?;
        Ok(self.step(action))
    }

    /// The sub-task rewards of the last transition, one per sub-task.
    fn subtask_rewards(&self) -> &[f64] {
        &[]
    }

    /// Discrete features of `state` (one bin index per feature).
    fn state_features(&self, state: usize) -> Vec<u32> {
        vec![u32::try_from(state).unwrap_or(u32::MAX)]
    }
}

/// A picture of an environment's state, as Gymnasium's `rgb_array` render mode returns it:
/// `height` rows of `width` pixels, each three bytes (red, green, blue), row by row from the
/// top. Environments draw their own (`mazes::render_rgb`, `wmr_model::render_rgb`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbFrame {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `height · width · 3` bytes.
    pub pixels: Vec<u8>,
}

impl RgbFrame {
    /// A frame of one colour.
    #[must_use]
    pub fn filled(width: usize, height: usize, colour: [u8; 3]) -> Self {
        Self {
            width,
            height,
            pixels: colour.repeat(width * height),
        }
    }

    /// Paints the pixel at column `x`, row `y` (from the top); a pixel outside the frame is
    /// ignored.
    pub fn set(&mut self, x: usize, y: usize, colour: [u8; 3]) {
        if x < self.width && y < self.height {
            let at = (y * self.width + x) * 3;
            self.pixels[at..at + 3].copy_from_slice(&colour);
        }
    }

    /// The colour of the pixel at column `x`, row `y`, if inside the frame.
    #[must_use]
    pub fn get(&self, x: usize, y: usize) -> Option<[u8; 3]> {
        (x < self.width && y < self.height).then(|| {
            let at = (y * self.width + x) * 3;
            [self.pixels[at], self.pixels[at + 1], self.pixels[at + 2]]
        })
    }
}
