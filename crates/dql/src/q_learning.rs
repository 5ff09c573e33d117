//! Single-estimator Q-learning (Watkins; the paper's Eq. 2), for comparison with double Q.

use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::double_q::validate_alpha_gamma;
use crate::error::DqlError;
use crate::learner::Learner;
use crate::table::{Initialisation, QTable};

/// Hyper-parameters of [`QLearning`]. The default is Table 1's α = 0.1, γ = 0.95
/// with zero initialisation; a missing `init` deserialises to zero, an unknown field is an error
/// that names it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QLearningParams {
    /// Learning rate α ∈ (0, 1].
    pub alpha: f64,
    /// Discount factor γ ∈ [0, 1].
    pub gamma: f64,
    /// How the table is initialised.
    #[serde(default)]
    pub init: Initialisation,
}

impl Default for QLearningParams {
    fn default() -> Self {
        Self {
            alpha: 0.1,
            gamma: 0.95,
            init: Initialisation::Zero,
        }
    }
}

impl QLearningParams {
    /// Parameters with the given α and γ and zero initialisation.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] naming `alpha` or `gamma`.
    pub fn new(alpha: f64, gamma: f64) -> Result<Self, DqlError> {
        let params = Self {
            alpha,
            gamma,
            init: Initialisation::Zero,
        };
        params.validate()?;
        Ok(params)
    }

    /// Checks α ∈ (0, 1], γ ∈ [0, 1] and a valid `init`.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] naming the first invalid field and its value.
    pub fn validate(&self) -> Result<(), DqlError> {
        validate_alpha_gamma(self.alpha, self.gamma)?;
        self.init.validate()
    }
}

/// Tabular Q-learning (Eq. 2):
/// `Q(s, a) ← (1 − α) · Q(s, a) + α · (r + γ · max_a' Q(s', a'))`, without the
/// bootstrap term on a terminated step.
///
/// It has the same interface as [`DoubleQ`](crate::DoubleQ); [`Learner::q1`] and
/// [`Learner::q2`] (and their row and table forms) both read its single table. Its update draws nothing from the
/// RNG. Its `max` over noisy estimates is biased upwards (the maximisation bias
/// double Q removes).
///
/// Serialisable (parameters, table, update counts); deserialising validates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "QLearningRepr", into = "QLearningRepr")]
pub struct QLearning {
    params: QLearningParams,
    q: QTable,
    update_counts: Vec<u32>,
}

impl QLearning {
    /// A learner for `n_states × n_actions` with validated `params`; `rng` is drawn
    /// from only for a uniform `init`.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] or [`DqlError::InvalidShape`].
    pub fn new<R: Rng + ?Sized>(
        n_states: usize,
        n_actions: usize,
        params: QLearningParams,
        rng: &mut R,
    ) -> Result<Self, DqlError> {
        params.validate()?;
        let q = QTable::initialised(n_states, n_actions, &params.init, rng)?;
        let update_counts = vec![0; q.as_slice().len()];
        Ok(Self {
            params,
            q,
            update_counts,
        })
    }

    /// The hyper-parameters.
    #[must_use]
    pub fn params(&self) -> &QLearningParams {
        &self.params
    }

    /// The table.
    #[must_use]
    pub fn q(&self) -> &QTable {
        &self.q
    }

    /// Mutable access to the table. Keep the values finite.
    pub fn q_mut(&mut self) -> &mut QTable {
        &mut self.q
    }

    /// Sets every update count back to 0 (the table is kept).
    pub fn clear_update_counts(&mut self) {
        self.update_counts.fill(0);
    }
}

/// The serialised form of a [`QLearning`].
#[derive(Serialize, Deserialize)]
struct QLearningRepr {
    params: QLearningParams,
    q: QTable,
    update_counts: Vec<u32>,
}

impl TryFrom<QLearningRepr> for QLearning {
    type Error = DqlError;
    fn try_from(repr: QLearningRepr) -> Result<Self, DqlError> {
        repr.params.validate()?;
        let cells = repr.q.as_slice().len();
        if repr.update_counts.len() != cells {
            return Err(DqlError::UpdateCountLength {
                len: repr.update_counts.len(),
                cells,
            });
        }
        Ok(Self {
            params: repr.params,
            q: repr.q,
            update_counts: repr.update_counts,
        })
    }
}

impl From<QLearning> for QLearningRepr {
    fn from(learner: QLearning) -> Self {
        Self {
            params: learner.params,
            q: learner.q,
            update_counts: learner.update_counts,
        }
    }
}

impl Learner for QLearning {
    #[inline]
    fn n_states(&self) -> usize {
        self.q.n_states()
    }

    #[inline]
    fn n_actions(&self) -> usize {
        self.q.n_actions()
    }

    #[inline]
    fn action_values(&self, state: usize, out: &mut [f64]) {
        out.copy_from_slice(self.q.row(state));
    }

    #[inline]
    fn update<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action: usize,
        reward: f64,
        next_state: usize,
        terminated: bool,
        _rng: &mut R,
    ) {
        let target = if terminated {
            reward
        } else {
            reward + self.params.gamma * self.q.max(next_state)
        };
        let alpha = self.params.alpha;
        let cell = &mut self.q.row_mut(state)[action];
        *cell = (1.0 - alpha) * *cell + alpha * target;
        let count = &mut self.update_counts[state * self.q.n_actions() + action];
        *count = count.saturating_add(1);
    }

    #[inline]
    fn q1_row(&self, state: usize) -> &[f64] {
        self.q.row(state)
    }

    #[inline]
    fn q2_row(&self, state: usize) -> &[f64] {
        self.q.row(state)
    }

    #[inline]
    fn update_counts(&self) -> &[u32] {
        &self.update_counts
    }
}
