//! Typed errors: bad samples and configs, and failed saves and loads.

use std::path::PathBuf;

/// A rejected configuration, sample or table.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EaTreeError {
    /// A threshold is NaN or outside `[0, 1]`.
    #[error("{name} must be a number in [0, 1], got {value}")]
    InvalidThreshold {
        /// `state_threshold` or `action_threshold`.
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// A sample's state has no features (its token set would be empty).
    #[error("a sample's state must have at least one feature, got an empty feature list")]
    EmptyState,
    /// A sample's state has more features than a token can index.
    #[error("a sample's state has {len} features, more than the {max} a tree can encode")]
    TooManyFeatures {
        /// Number of features given.
        len: usize,
        /// [`MAX_FEATURES`](crate::MAX_FEATURES).
        max: usize,
    },
    /// A sample's Q value is NaN or infinite.
    #[error("{name} must be finite, got {value}")]
    NonFiniteQ {
        /// `q1` or `q2`.
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// The tree already holds `u32::MAX` clusters.
    #[error("the tree is full: it already holds {clusters} clusters")]
    TooManyClusters {
        /// Number of clusters held.
        clusters: usize,
    },
    /// A table gave the same (state, action) pair twice.
    #[error("table entry (state {state_id}, action {action}) is given more than once")]
    DuplicateTableEntry {
        /// The repeated state id.
        state_id: usize,
        /// The repeated action.
        action: usize,
    },
    /// A table gave two different feature lists for one state id.
    #[error("table state {state_id} is given with two different feature lists")]
    InconsistentStateFeatures {
        /// The state id.
        state_id: usize,
    },
}

/// Loading a tree failed; every malformed input ends here, never in a panic.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The input ends in the middle of the JSON document.
    #[error("the tree file is truncated: input ends at line {line}, column {column}")]
    Truncated {
        /// Line where the input ended (1-based).
        line: usize,
        /// Column where the input ended.
        column: usize,
    },
    /// The input is not JSON, or not JSON of the tree file's shape.
    #[error("the tree file is corrupt at line {line}, column {column}: {message}")]
    Corrupt {
        /// Line of the error (1-based).
        line: usize,
        /// Column of the error.
        column: usize,
        /// What the parser expected.
        message: String,
    },
    /// The file is not an ea-tree file, or one of a version this build does not read.
    #[error(
        "unsupported tree file: format {format:?} version {version} (expected \"ea-tree\" version 1)"
    )]
    UnsupportedFormat {
        /// The `format` field found.
        format: String,
        /// The `version` field found.
        version: u32,
    },
    /// The tree was built with another similarity than the one it is loaded with.
    #[error("the tree was built with similarity {found:?}, but is loaded with {expected:?}")]
    SimilarityMismatch {
        /// Name of the similarity the caller loads with.
        expected: String,
        /// Name stored in the file.
        found: String,
    },
    /// The stored thresholds are invalid.
    #[error("the tree file's config is invalid: {0}")]
    InvalidConfig(EaTreeError),
    /// The structure parses but is not a tree this crate could have built.
    #[error("the tree file is inconsistent: {location}: {problem}")]
    Inconsistent {
        /// Where: `cluster #i` or `tree`.
        location: String,
        /// What is wrong, with the offending value.
        problem: String,
    },
}
