//! Errors of a run.

use dql::DqlError;
use ea_tree::EaTreeError;
use madm_owa::MadmError;
use reward_std::RewardStdError;
use thiserror::Error;

use crate::agent::PolicyError;
use crate::config::ConfigError;

/// A run that could not complete, with the method and seed it belongs to.
#[derive(Debug, Error)]
#[error("method `{method}`, seed {seed}: {source}")]
pub struct RunError {
    /// The method's label.
    pub method: String,
    /// The run's seed.
    pub seed: u64,
    /// What went wrong (boxed: runs return `Result<RunRecord, RunError>` and the failure
    /// is the rare path).
    #[source]
    pub source: Box<RunFailure>,
}

impl RunError {
    pub(crate) fn new(method: &str, seed: u64, source: impl Into<RunFailure>) -> Self {
        Self {
            method: method.to_owned(),
            seed,
            source: Box::new(source.into()),
        }
    }
}

/// What went wrong in a run.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RunFailure {
    /// The config or the task cannot be used.
    #[error(transparent)]
    Config(Box<ConfigError>),
    /// Invalid learning parameters, or an environment that broke its contract.
    #[error("learning: {0}")]
    Learning(#[from] DqlError),
    /// An experience tree could not be built.
    #[error("experience tree: {0}")]
    Tree(#[from] EaTreeError),
    /// The EA-MADM policy could not be built.
    #[error("EA-MADM policy: {0}")]
    Policy(#[from] PolicyError),
    /// The reward standardisation could not be set up.
    #[error("reward standardisation: {0}")]
    Standardisation(#[from] RewardStdError),
    /// An EA-MADM decision could not be made: a value of the decision matrix was not finite.
    #[error(
        "EA-MADM decision: {0} (a learned value overflowed; bound the learner's `init` and the \
         task's rewards)"
    )]
    Decision(#[source] MadmError),
}

impl From<ConfigError> for RunFailure {
    fn from(error: ConfigError) -> Self {
        Self::Config(Box::new(error))
    }
}
