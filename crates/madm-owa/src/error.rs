//! The crate's error type.

/// Everything that can be wrong with the input of this crate's functions.
///
/// Every variant names the argument (or matrix entry) at fault and the offending value, so a
/// message such as ``weight 2 is -0.1; OWA weights must be non-negative`` is enough to find
/// the bug.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MadmError {
    /// An input that needs at least one element has none.
    #[error("`{what}` is empty; at least one element is needed")]
    Empty {
        /// Name of the argument.
        what: &'static str,
    },
    /// A decision matrix with no rows (alternatives) or no columns (attributes).
    #[error(
        "decision matrix is {rows} x {cols}: it needs at least one row (alternative) and one column (attribute)"
    )]
    EmptyMatrix {
        /// Number of rows the caller passed.
        rows: usize,
        /// Number of columns the caller passed.
        cols: usize,
    },
    /// Two inputs that must have the same length do not.
    #[error("`{what}` has length {found}, expected {expected}")]
    LengthMismatch {
        /// Name of the argument whose length is wrong.
        what: &'static str,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        found: usize,
    },
    /// A flat, row-major decision matrix does not hold `rows × cols` entries.
    #[error("decision matrix has {len} entries, which is not {rows} rows x {cols} columns")]
    ShapeMismatch {
        /// Number of rows the caller claimed.
        rows: usize,
        /// Number of columns the caller claimed.
        cols: usize,
        /// Length of the slice actually passed.
        len: usize,
    },
    /// An element of a vector is NaN or infinite.
    #[error("`{what}[{index}]` is {value}, not a finite number")]
    NonFinite {
        /// Name of the argument.
        what: &'static str,
        /// Index of the element.
        index: usize,
        /// The element.
        value: f64,
    },
    /// An entry of a decision matrix is NaN or infinite.
    #[error("decision matrix entry (row {row}, column {col}) is {value}, not a finite number")]
    NonFiniteEntry {
        /// Row (action / scheme) of the entry.
        row: usize,
        /// Column (attribute) of the entry.
        col: usize,
        /// The entry.
        value: f64,
    },
    /// An OWA weight is negative.
    #[error("weight {index} is {value}; OWA weights must be non-negative")]
    NegativeWeight {
        /// Index (sorted position) of the weight.
        index: usize,
        /// The weight.
        value: f64,
    },
    /// OWA weights do not sum to 1.
    #[error("weights sum to {sum}; OWA weights must sum to 1 (within {tolerance})")]
    WeightSum {
        /// The sum of the weights.
        sum: f64,
        /// The tolerance allowed, [`WEIGHT_SUM_TOLERANCE`](crate::WEIGHT_SUM_TOLERANCE).
        tolerance: f64,
    },
    /// A series that must be sorted in descending order is not.
    #[error(
        "`sorted` is not in descending order: element {index} ({value}) exceeds its predecessor ({previous})"
    )]
    NotDescending {
        /// Index of the first element larger than its predecessor.
        index: usize,
        /// That element.
        value: f64,
        /// Its predecessor.
        previous: f64,
    },
    /// A scalar parameter is out of its domain.
    #[error("parameter `{name}` is {value}: {reason}")]
    InvalidParameter {
        /// Name of the parameter (as spelled in configs).
        name: &'static str,
        /// The value given.
        value: f64,
        /// What the parameter must satisfy.
        reason: &'static str,
    },
}

/// Checks that every element of `values` is finite.
pub(crate) fn check_finite(what: &'static str, values: &[f64]) -> Result<(), MadmError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(MadmError::NonFinite {
            what,
            index,
            value: values[index],
        }),
    }
}

/// Checks that `values` is not empty.
pub(crate) fn check_non_empty(what: &'static str, values: &[f64]) -> Result<(), MadmError> {
    if values.is_empty() {
        Err(MadmError::Empty { what })
    } else {
        Ok(())
    }
}

/// Checks that `values` has length `expected`.
pub(crate) fn check_len(
    what: &'static str,
    values: &[f64],
    expected: usize,
) -> Result<(), MadmError> {
    if values.len() == expected {
        Ok(())
    } else {
        Err(MadmError::LengthMismatch {
            what,
            expected,
            found: values.len(),
        })
    }
}
