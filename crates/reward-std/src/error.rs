//! The crate's error type.

/// Everything that can be wrong with the input of this crate's functions. Every variant names
/// the argument at fault and the offending value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RewardStdError {
    /// An input that needs at least one element has none.
    #[error("`{what}` is empty; at least one sub-task reward is needed")]
    Empty {
        /// Name of the argument.
        what: &'static str,
    },
    /// An input does not have the length it must have.
    #[error("`{what}` has length {found}, expected {expected}")]
    LengthMismatch {
        /// Name of the argument whose length is wrong.
        what: &'static str,
        /// The length it must have (the number of sub-tasks).
        expected: usize,
        /// The length it has.
        found: usize,
    },
    /// A reward is NaN or infinite.
    #[error("`{what}[{index}]` is {value}, not a finite number")]
    NonFinite {
        /// Name of the argument.
        what: &'static str,
        /// Index of the sub-task.
        index: usize,
        /// The reward.
        value: f64,
    },
    /// A reward is too large in magnitude for the running statistics.
    #[error("`rewards[{index}]` is {value}; running standardisation accepts |reward| <= {limit}")]
    OutOfRange {
        /// Index of the sub-task.
        index: usize,
        /// The reward.
        value: f64,
        /// The largest magnitude accepted, [`MAX_ABS_REWARD`](crate::MAX_ABS_REWARD).
        limit: f64,
    },
}

/// Checks that `values` is non-empty, has length `expected` and is finite.
pub(crate) fn check_rewards(
    what: &'static str,
    values: &[f64],
    expected: usize,
) -> Result<(), RewardStdError> {
    if values.is_empty() {
        return Err(RewardStdError::Empty { what });
    }
    if values.len() != expected {
        return Err(RewardStdError::LengthMismatch {
            what,
            expected,
            found: values.len(),
        });
    }
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(RewardStdError::NonFinite {
            what,
            index,
            value: values[index],
        }),
    }
}
