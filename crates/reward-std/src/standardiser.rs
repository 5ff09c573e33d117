//! One switchable standardiser for the source task's learning signal, chosen by config.

use serde::{Deserialize, Serialize};

use crate::cross_sectional::cross_sectional;
use crate::error::{RewardStdError, check_rewards};
use crate::running::RunningStandardiser;

/// Which standardisation turns the sub-task rewards of a time step into the source task's
/// reward. Serialised as a string: `"running"` or `"cross_sectional"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Standardisation {
    /// Eq. 10–12 as printed ([`cross_sectional`]): identically 0, kept to show the degeneracy.
    CrossSectional,
    /// Our repair ([`RunningStandardiser`]), the default: each sub-task against its own
    /// running statistics over the episode.
    #[default]
    Running,
}

/// The source task's reward from the sub-task rewards, by the configured [`Standardisation`].
/// Owns its buffers: [`push`](RewardStandardiser::push) allocates nothing.
///
/// # Example
///
/// ```
/// use reward_std::{RewardStandardiser, Standardisation};
///
/// let mut literal = RewardStandardiser::new(Standardisation::CrossSectional, 3)?;
/// let mut running = RewardStandardiser::new(Standardisation::Running, 3)?;
/// for step in [[1.0, -1.0, 100.0], [1.0, -100.0, 2.0], [-1.0, 1.0, 2.0]] {
///     assert!(literal.push(&step)?.abs() < 1e-15); // always 0
///     running.push(&step)?;
/// }
/// assert_eq!(running.z_scores().len(), 3);
/// # Ok::<(), reward_std::RewardStdError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RewardStandardiser {
    mode: Standardisation,
    running: RunningStandardiser,
    /// z-scores of the last cross-sectional push.
    z: Vec<f64>,
}

impl RewardStandardiser {
    /// A standardiser of `subtasks` rewards per step, at the start of an episode.
    ///
    /// # Errors
    ///
    /// [`RewardStdError::Empty`] when `subtasks` is 0.
    pub fn new(mode: Standardisation, subtasks: usize) -> Result<Self, RewardStdError> {
        Ok(Self {
            mode,
            running: RunningStandardiser::new(subtasks)?,
            z: vec![0.0; subtasks],
        })
    }

    /// The configured standardisation.
    #[must_use]
    pub fn mode(&self) -> Standardisation {
        self.mode
    }

    /// Number of sub-tasks.
    #[must_use]
    pub fn subtasks(&self) -> usize {
        self.z.len()
    }

    /// Call at every episode start (forgets the running statistics; harmless for the
    /// cross-sectional mode, which has none).
    pub fn reset(&mut self) {
        self.running.reset();
        self.z.fill(0.0);
    }

    /// The source task's reward for one time step's sub-task rewards.
    ///
    /// # Errors
    ///
    /// [`RewardStdError::Empty`], [`RewardStdError::LengthMismatch`] (not one reward per
    /// sub-task), [`RewardStdError::NonFinite`], and in running mode
    /// [`RewardStdError::OutOfRange`].
    pub fn push(&mut self, rewards: &[f64]) -> Result<f64, RewardStdError> {
        match self.mode {
            Standardisation::Running => self.running.push(rewards),
            Standardisation::CrossSectional => {
                check_rewards("rewards", rewards, self.z.len())?;
                cross_sectional(rewards, &mut self.z)
            }
        }
    }

    /// The per-sub-task z-scores of the last push (zeros after a reset).
    #[must_use]
    pub fn z_scores(&self) -> &[f64] {
        match self.mode {
            Standardisation::Running => self.running.z_scores(),
            Standardisation::CrossSectional => &self.z,
        }
    }
}
