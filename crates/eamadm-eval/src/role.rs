//! Why a method is in an experiment.

use serde::{Deserialize, Serialize};

/// Why a method is in an experiment; reports group methods by it and test the paper's claims
/// only on `Paper` methods (with ablations and controls explaining the result).
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// EA-MADM as the paper describes it, or one of the paper's competitors.
    #[default]
    Paper,
    /// EA-MADM with one of its switches flipped, to see what each part contributes.
    Ablation,
    /// A comparison the paper does not run (equal step budgets, equal reward information,
    /// a sub-task alone, the tree's thresholds), marked so it is never mistaken for the paper's.
    Control,
}

impl Role {
    /// The TOML and CSV name: `paper`, `ablation` or `control`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::Ablation => "ablation",
            Self::Control => "control",
        }
    }
}
