//! Reward schemes as data: what each kind of transition pays, for the task and its sub-tasks.
//!
//! Every transition of a maze falls into exactly one [`Event`]; a [`RewardScheme`] maps
//! events to rewards. A [`TaskSpec`] bundles the task's own scheme, one scheme per
//! sub-task and the step cap. The presets ([`TaskSpec::task1`], [`TaskSpec::task2`])
//! are the paper's Sec. VI.A tasks; the crate docs explain the sub-task definitions.

use std::fmt;

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// What a transition did, judged by the squared Euclidean distance between tile centres.
///
/// Classified in this order: reaching the target is [`Event::Target`]; a blocked move
/// (obstacle or outer wall; the agent stays) is [`Event::Bump`]; otherwise the move is
/// [`Event::Closer`] if the Euclidean distance to the target shrank and [`Event::Farther`]
/// if not. (A move of one tile always changes the distance, so "not closer" is "farther".)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Event {
    /// A move that shrank the Euclidean distance to the target (without reaching it).
    Closer = 0,
    /// A move that did not shrink the Euclidean distance to the target.
    Farther = 1,
    /// A move into an obstacle or the outer wall; the agent stays where it was.
    Bump = 2,
    /// A move onto the target; the episode terminates.
    Target = 3,
}

impl Event {
    /// Number of events.
    pub const COUNT: usize = 4;
    /// All events, in index order.
    pub const ALL: [Self; Self::COUNT] = [Self::Closer, Self::Farther, Self::Bump, Self::Target];

    /// The event's index in `0..4` (the order of [`Event::ALL`]).
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Lower-case name, as in the serialised form.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Closer => "closer",
            Self::Farther => "farther",
            Self::Bump => "bump",
            Self::Target => "target",
        }
    }
}

impl fmt::Display for Event {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The reward paid for each [`Event`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RewardScheme {
    /// Reward for a move that shrinks the Euclidean distance to the target.
    pub closer: f64,
    /// Reward for a move that does not shrink it.
    pub farther: f64,
    /// Reward for bumping into an obstacle or the outer wall (the agent stays).
    pub bump: f64,
    /// Reward for reaching the target (paid instead of `closer`).
    pub target: f64,
}

impl RewardScheme {
    /// Task I's reward (Sec. VI.A): +1 closer, −1 otherwise, −100 for a bump, +100 at the target.
    pub const TASK_I: Self = Self {
        closer: 1.0,
        farther: -1.0,
        bump: -100.0,
        target: 100.0,
    };

    /// Task II's reward (Sec. VI.A): +10 at the target, −1 for every other step. Read
    /// literally, a bump is one of those "other" steps and also pays −1.
    pub const TASK_II: Self = Self {
        closer: -1.0,
        farther: -1.0,
        bump: -1.0,
        target: 10.0,
    };

    /// Sub-task "reach the target faster" of Task I: the distance shaping of
    /// [`TASK_I`](Self::TASK_I) without the bump penalty (a bump does not shrink the
    /// distance, so it pays the "otherwise" −1).
    pub const REACH_FASTER_TASK_I: Self = Self {
        closer: 1.0,
        farther: -1.0,
        bump: -1.0,
        target: 100.0,
    };

    /// Sub-task "reach the target faster" of Task II: the same distance shaping (+1 / −1)
    /// with Task II's target bonus (+10).
    pub const REACH_FASTER_TASK_II: Self = Self {
        closer: 1.0,
        farther: -1.0,
        bump: -1.0,
        target: 10.0,
    };

    /// Sub-task "do not hit obstacles" (both tasks): −100 for a bump (Task I's bump
    /// penalty, the paper's only one), 0 for everything else.
    pub const DO_NOT_HIT: Self = Self {
        closer: 0.0,
        farther: 0.0,
        bump: -100.0,
        target: 0.0,
    };

    /// The reward for `event`.
    #[must_use]
    pub const fn reward(&self, event: Event) -> f64 {
        match event {
            Event::Closer => self.closer,
            Event::Farther => self.farther,
            Event::Bump => self.bump,
            Event::Target => self.target,
        }
    }

    /// The rewards in [`Event::ALL`] order.
    #[must_use]
    pub const fn by_event(&self) -> [f64; Event::COUNT] {
        [self.closer, self.farther, self.bump, self.target]
    }

    /// Checks that every reward is finite and at most [`MAX_ABS_REWARD`] in magnitude; `field`
    /// prefixes the field names in the error.
    ///
    /// # Errors
    ///
    /// [`SpecError::NonFiniteReward`] or [`SpecError::RewardOutOfRange`] naming the first bad
    /// field.
    pub fn validate(&self, field: &str) -> Result<(), SpecError> {
        for event in Event::ALL {
            let value = self.reward(event);
            if !value.is_finite() {
                return Err(SpecError::NonFiniteReward {
                    field: format!("{field}.{}", event.name()),
                    value,
                });
            }
            if value.abs() > MAX_ABS_REWARD {
                return Err(SpecError::RewardOutOfRange {
                    field: format!("{field}.{}", event.name()),
                    value,
                    limit: MAX_ABS_REWARD,
                });
            }
        }
        Ok(())
    }
}

/// Largest `step_cap`: 100 000 steps. A run keeps whole episodes' trajectories (8 bytes a
/// step), so an unbounded cap could exhaust memory long after the spec was accepted; the
/// presets use 2000.
pub const MAX_STEP_CAP: u32 = 100_000;

/// Largest magnitude of a reward constant: `1e9`.
///
/// The presets use rewards of magnitude at most 10. Bounding them (with the learners' initial
/// values, see `dql::MAX_ABS_INITIAL_VALUE`) keeps every Q-value and learning signal of a
/// validated run finite: a value moves by at most `α · (|r| + |Q|)` per update, and no
/// validated run is long enough to carry a 1e9 reward anywhere near `f64::MAX`.
pub const MAX_ABS_REWARD: f64 = 1e9;

/// A named sub-task: one reward scheme over the same maze and dynamics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Subtask {
    /// Human-readable name, e.g. `"reach the target faster"`.
    pub name: String,
    /// What the sub-task's learner is paid.
    pub reward: RewardScheme,
}

/// Name of the first sub-task of the presets.
pub const REACH_FASTER_NAME: &str = "reach the target faster";
/// Name of the second sub-task of the presets.
pub const DO_NOT_HIT_NAME: &str = "do not hit obstacles";

/// The default episode length limit (Sec. VI.A: "exceeds 2000").
pub const DEFAULT_STEP_CAP: u32 = 2000;

/// Everything about a maze task except the layout: rewards, sub-tasks and the step cap.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskSpec {
    /// The task's own reward (what learning curves plot).
    pub reward: RewardScheme,
    /// The decomposition into sub-tasks, in the order of `subtask_rewards()`.
    pub subtasks: Vec<Subtask>,
    /// Episodes are truncated after this many steps.
    pub step_cap: u32,
}

impl TaskSpec {
    /// Task I: [`RewardScheme::TASK_I`], sub-tasks "reach the target faster"
    /// ([`RewardScheme::REACH_FASTER_TASK_I`]) and "do not hit obstacles"
    /// ([`RewardScheme::DO_NOT_HIT`]), step cap 2000.
    #[must_use]
    pub fn task1() -> Self {
        Self {
            reward: RewardScheme::TASK_I,
            subtasks: vec![
                Subtask {
                    name: REACH_FASTER_NAME.to_owned(),
                    reward: RewardScheme::REACH_FASTER_TASK_I,
                },
                Subtask {
                    name: DO_NOT_HIT_NAME.to_owned(),
                    reward: RewardScheme::DO_NOT_HIT,
                },
            ],
            step_cap: DEFAULT_STEP_CAP,
        }
    }

    /// Task II: [`RewardScheme::TASK_II`], sub-tasks "reach the target faster"
    /// ([`RewardScheme::REACH_FASTER_TASK_II`]) and "do not hit obstacles"
    /// ([`RewardScheme::DO_NOT_HIT`]), step cap 2000.
    #[must_use]
    pub fn task2() -> Self {
        Self {
            reward: RewardScheme::TASK_II,
            subtasks: vec![
                Subtask {
                    name: REACH_FASTER_NAME.to_owned(),
                    reward: RewardScheme::REACH_FASTER_TASK_II,
                },
                Subtask {
                    name: DO_NOT_HIT_NAME.to_owned(),
                    reward: RewardScheme::DO_NOT_HIT,
                },
            ],
            step_cap: DEFAULT_STEP_CAP,
        }
    }

    /// Checks the spec: finite rewards, a step cap in `1..=`[`MAX_STEP_CAP`], non-empty
    /// distinct names.
    ///
    /// # Errors
    ///
    /// The first problem found, as a [`SpecError`] naming the field.
    pub fn validate(&self) -> Result<(), SpecError> {
        if !(1..=MAX_STEP_CAP).contains(&self.step_cap) {
            return Err(SpecError::StepCapOutOfRange {
                value: self.step_cap,
            });
        }
        self.reward.validate("reward")?;
        for (index, subtask) in self.subtasks.iter().enumerate() {
            subtask
                .reward
                .validate(&format!("subtasks[{index}].reward"))?;
            if subtask.name.trim().is_empty() {
                return Err(SpecError::EmptySubtaskName { index });
            }
            if let Some(first) = self.subtasks[..index]
                .iter()
                .position(|other| other.name == subtask.name)
            {
                return Err(SpecError::DuplicateSubtaskName {
                    name: subtask.name.clone(),
                    first,
                    index,
                });
            }
        }
        Ok(())
    }
}

/// A [`TaskSpec`] that cannot be used.
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum SpecError {
    /// A reward is NaN or infinite.
    #[error("`{field}` must be a finite number, got {value}")]
    NonFiniteReward {
        /// Path of the offending field, e.g. `subtasks[1].reward.bump`.
        field: String,
        /// The value found.
        value: f64,
    },
    /// A reward's magnitude exceeds [`MAX_ABS_REWARD`].
    #[error("`{field}` must lie in [-{limit:e}, {limit:e}], got {value}")]
    RewardOutOfRange {
        /// Path of the offending field, e.g. `reward.target`.
        field: String,
        /// The value found.
        value: f64,
        /// The largest magnitude accepted.
        limit: f64,
    },
    /// `step_cap` is 0 (no episode could take a single step) or above [`MAX_STEP_CAP`].
    #[error("`step_cap` must be in [1, {MAX_STEP_CAP}], got {value}")]
    StepCapOutOfRange {
        /// The value found.
        value: u32,
    },
    /// A sub-task has an empty (or all-blank) name.
    #[error("`subtasks[{index}].name` must not be empty")]
    EmptySubtaskName {
        /// Index of the sub-task.
        index: usize,
    },
    /// Two sub-tasks share a name.
    #[error("`subtasks[{index}].name` repeats the name {name:?} of `subtasks[{first}]`")]
    DuplicateSubtaskName {
        /// The repeated name.
        name: String,
        /// Index of the first sub-task with that name.
        first: usize,
        /// Index of the repeat.
        index: usize,
    },
}
