//! The tree's thresholds τₛ and τₐ.

use serde::{Deserialize, Serialize};

use crate::error::EaTreeError;

/// Similarity thresholds of the tree (Sec. IV.B): a sample's state is *similar* to a
/// centre when `state_similarity >= state_threshold` (τₛ), its action when
/// `action_similarity >= action_threshold` (τₐ). Both must lie in `[0, 1]`.
///
/// The paper gives no values. The default is `τₛ = τₐ = 1` (exact match), where the tree
/// answers exactly like a table of per-(s, a) means.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EaTreeConfig {
    /// τₛ, in `[0, 1]`.
    pub state_threshold: f64,
    /// τₐ, in `[0, 1]`.
    pub action_threshold: f64,
}

impl EaTreeConfig {
    /// Exact matching: `τₛ = τₐ = 1`.
    pub const EXACT: Self = Self {
        state_threshold: 1.0,
        action_threshold: 1.0,
    };

    /// A validated configuration.
    ///
    /// # Errors
    /// [`EaTreeError::InvalidThreshold`] if a threshold is not a number in `[0, 1]`.
    pub fn new(state_threshold: f64, action_threshold: f64) -> Result<Self, EaTreeError> {
        let config = Self {
            state_threshold,
            action_threshold,
        };
        config.validate()?;
        Ok(config)
    }

    /// Checks both thresholds (useful after deserialising a config).
    ///
    /// # Errors
    /// [`EaTreeError::InvalidThreshold`] naming the first threshold outside `[0, 1]` (or NaN).
    pub fn validate(&self) -> Result<(), EaTreeError> {
        for (name, value) in [
            ("state_threshold", self.state_threshold),
            ("action_threshold", self.action_threshold),
        ] {
            if !(0.0..=1.0).contains(&value) {
                return Err(EaTreeError::InvalidThreshold { name, value });
            }
        }
        Ok(())
    }
}

impl Default for EaTreeConfig {
    fn default() -> Self {
        Self::EXACT
    }
}
