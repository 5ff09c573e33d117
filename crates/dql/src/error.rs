//! The crate's error type.

use thiserror::Error;

/// Everything that can go wrong in this crate: invalid hyper-parameters, mismatched
/// shapes, and environments or policies that break their contracts at run time.
///
/// Every variant names the offending parameter or quantity and carries its value.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DqlError {
    /// A hyper-parameter is outside its domain (or not finite).
    #[error("invalid hyper-parameter `{name}` = {value}: expected {expected}")]
    InvalidParameter {
        /// The parameter's name, e.g. `alpha` or `epsilon.floor`.
        name: String,
        /// The rejected value.
        value: f64,
        /// The domain it must lie in, in words.
        expected: &'static str,
    },

    /// A table would have no states, no actions, or more cells than fit in memory.
    #[error(
        "invalid table shape {n_states} states x {n_actions} actions: both must be at least 1 and their product must fit in usize"
    )]
    InvalidShape {
        /// Requested number of states.
        n_states: usize,
        /// Requested number of actions.
        n_actions: usize,
    },

    /// A table's value buffer does not have `n_states * n_actions` entries.
    #[error("table data has {len} values, expected {n_states} x {n_actions}")]
    DataLength {
        /// Number of values supplied.
        len: usize,
        /// Number of states of the table.
        n_states: usize,
        /// Number of actions of the table.
        n_actions: usize,
    },

    /// A table value is NaN or infinite.
    #[error("table value at state {state}, action {action} is not finite: {value}")]
    NonFiniteValue {
        /// State index of the offending cell.
        state: usize,
        /// Action index of the offending cell.
        action: usize,
        /// The value.
        value: f64,
    },

    /// The environment and the learner disagree on the number of states or actions.
    #[error("{what} mismatch: environment has {environment}, learner has {learner}")]
    ShapeMismatch {
        /// `"state count"` or `"action count"`.
        what: &'static str,
        /// The environment's count.
        environment: usize,
        /// The learner's count.
        learner: usize,
    },

    /// Two tables that must have the same shape do not (e.g. `Q1` and `Q2`).
    #[error(
        "table shapes differ: {first_states} x {first_actions} versus {second_states} x {second_actions}"
    )]
    TableShapeMismatch {
        /// States of the first table.
        first_states: usize,
        /// Actions of the first table.
        first_actions: usize,
        /// States of the second table.
        second_states: usize,
        /// Actions of the second table.
        second_actions: usize,
    },

    /// Saved update counts do not have one entry per state–action pair.
    #[error("{len} update counts for a table with {cells} cells")]
    UpdateCountLength {
        /// Number of counts supplied.
        len: usize,
        /// Number of state–action pairs.
        cells: usize,
    },

    /// The environment returned a state index outside `0..n_states`.
    #[error("environment returned state {state} at step {step}, but it has only {n_states} states")]
    StateOutOfRange {
        /// The offending state index.
        state: usize,
        /// Number of states.
        n_states: usize,
        /// Step of the episode (0 = the state returned by `reset`).
        step: u64,
    },

    /// The exploration policy chose an action index outside `0..n_actions`.
    #[error("policy chose action {action} at step {step}, but there are only {n_actions} actions")]
    ActionOutOfRange {
        /// The offending action index.
        action: usize,
        /// Number of actions.
        n_actions: usize,
        /// Step of the episode at which it was chosen.
        step: u64,
    },

    /// A reward (the task's or the learning signal's) is NaN or infinite.
    #[error("{which} reward at step {step} is not finite: {value}")]
    NonFiniteReward {
        /// `"task"` or `"learning signal"`.
        which: &'static str,
        /// Step of the episode (1-based: the first transition is step 1).
        step: u64,
        /// The value.
        value: f64,
    },

    /// A state or action index handed to a checked call
    /// ([`Learner::try_update`](crate::Learner::try_update),
    /// [`Environment::try_step`](crate::Environment::try_step)) is out of range.
    #[error("{argument} {index} is out of range: expected an index below {len}")]
    IndexOutOfRange {
        /// The argument's name: `state`, `action` or `next_state`.
        argument: &'static str,
        /// The rejected index.
        index: usize,
        /// The number of valid indices.
        len: usize,
    },

    /// A sub-task reward was requested from a task that has fewer sub-tasks.
    #[error("sub-task {index} requested, but the environment has {n_subtasks} sub-tasks")]
    SubtaskOutOfRange {
        /// The requested sub-task index.
        index: usize,
        /// Number of sub-tasks the environment reports.
        n_subtasks: usize,
    },
}

/// Checks one hyper-parameter: `Ok` when `ok`, otherwise an error naming it.
pub(crate) fn check_param(
    name: &str,
    value: f64,
    ok: bool,
    expected: &'static str,
) -> Result<(), DqlError> {
    if ok {
        Ok(())
    } else {
        Err(DqlError::InvalidParameter {
            name: name.to_owned(),
            value,
            expected,
        })
    }
}

/// Checks one index argument: `Ok` when `index < len`, otherwise an error naming it.
pub(crate) fn check_index(
    argument: &'static str,
    index: usize,
    len: usize,
) -> Result<(), DqlError> {
    if index < len {
        Ok(())
    } else {
        Err(DqlError::IndexOutOfRange {
            argument,
            index,
            len,
        })
    }
}
