//! Double Q-learning (van Hasselt 2010; the paper's Eq. 9 and Algorithm 1, corrected).

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::error::{DqlError, check_param};
use crate::learner::Learner;
use crate::table::{Initialisation, QTable};

/// Which combination of the two estimators behaviour is derived from.
///
/// Both give the same greedy action (and the same ties); they differ for
/// scale-sensitive policies such as softmax, whose temperature applies to these
/// values, and for the facade's multi-attribute decision, which compares them
/// with other tasks' values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BehaviourValues {
    /// `(Q1 + Q2) / 2`: on the scale of a single estimate (Algorithm 2, line 20),
    /// comparable with [`QLearning`](crate::QLearning)'s `Q`.
    #[default]
    Mean,
    /// `Q1 + Q2`, as in van Hasselt's pseudo-code.
    Sum,
}

/// Hyper-parameters of [`DoubleQ`].
///
/// The default is Table 1's α = 0.1, γ = 0.95, with ξ = 0.5 and zero
/// initialisation. Missing `xi`, `init` and `behaviour` fields deserialise to
/// their defaults. [`DoubleQ::new`] validates; so does [`validate`](Self::validate).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DoubleQParams {
    /// Learning rate α ∈ (0, 1].
    pub alpha: f64,
    /// Discount factor γ ∈ [0, 1].
    pub gamma: f64,
    /// Probability ξ ∈ [0, 1] that a step updates `Q1` (otherwise `Q2`).
    /// The paper's estimators are symmetric (0.5); Algorithm 2 sets 0.9.
    #[serde(default = "default_xi")]
    pub xi: f64,
    /// How both tables are initialised (each from its own draws).
    #[serde(default)]
    pub init: Initialisation,
    /// What [`Learner::action_values`] reports.
    #[serde(default)]
    pub behaviour: BehaviourValues,
}

fn default_xi() -> f64 {
    0.5
}

impl Default for DoubleQParams {
    fn default() -> Self {
        Self {
            alpha: 0.1,
            gamma: 0.95,
            xi: default_xi(),
            init: Initialisation::Zero,
            behaviour: BehaviourValues::Mean,
        }
    }
}

/// Checks α ∈ (0, 1] and γ ∈ [0, 1] (shared with Q-learning).
pub(crate) fn validate_alpha_gamma(alpha: f64, gamma: f64) -> Result<(), DqlError> {
    check_param(
        "alpha",
        alpha,
        alpha > 0.0 && alpha <= 1.0,
        "a learning rate in (0, 1]",
    )?;
    check_param(
        "gamma",
        gamma,
        (0.0..=1.0).contains(&gamma),
        "a discount factor in [0, 1]",
    )
}

impl DoubleQParams {
    /// Parameters with the given α and γ and every other field at its default.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] naming `alpha` or `gamma`.
    pub fn new(alpha: f64, gamma: f64) -> Result<Self, DqlError> {
        let params = Self {
            alpha,
            gamma,
            ..Self::default()
        };
        params.validate()?;
        Ok(params)
    }

    /// Checks every field: α ∈ (0, 1], γ ∈ [0, 1], ξ ∈ [0, 1], a valid `init`.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] naming the first invalid field and its value.
    pub fn validate(&self) -> Result<(), DqlError> {
        validate_alpha_gamma(self.alpha, self.gamma)?;
        check_param(
            "xi",
            self.xi,
            (0.0..=1.0).contains(&self.xi),
            "a probability in [0, 1]",
        )?;
        self.init.validate()
    }
}

/// Tabular double Q-learning: two estimators, one updated per step.
///
/// With probability ξ the step updates `Q1`, otherwise `Q2` (one `f64` draw from
/// the caller's RNG per update). Updating `Q1` (mirror image for `Q2`):
///
/// ```text
/// a*        = argmax_a' Q1(s', a')                  (ties at random)
/// target    = r + γ · Q2(s', a*)                    (just r when terminated)
/// Q1(s, a) ← (1 − α) · Q1(s, a) + α · target
/// ```
///
/// This is van Hasselt's update; the paper's Eq. 9 prints `argmax_a Q1(s_t, a)`,
/// a typo for the successor state `s_{t+1}`. The update is written in Eq. 9's
/// `(1 − α) Q + α target` form, so α = 1 sets the cell to the target exactly.
#[derive(Debug, Clone, PartialEq)]
pub struct DoubleQ {
    params: DoubleQParams,
    q1: QTable,
    q2: QTable,
    update_counts: Vec<u32>,
}

impl DoubleQ {
    /// A learner for `n_states × n_actions` with validated `params`. `Q1` is
    /// initialised first, then `Q2`, drawing from `rng` only for a uniform `init`.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] for a bad parameter,
    /// [`DqlError::InvalidShape`] for a bad shape.
    pub fn new<R: Rng + ?Sized>(
        n_states: usize,
        n_actions: usize,
        params: DoubleQParams,
        rng: &mut R,
    ) -> Result<Self, DqlError> {
        params.validate()?;
        let q1 = QTable::initialised(n_states, n_actions, &params.init, rng)?;
        let q2 = QTable::initialised(n_states, n_actions, &params.init, rng)?;
        let update_counts = vec![0; q1.as_slice().len()];
        Ok(Self {
            params,
            q1,
            q2,
            update_counts,
        })
    }

    /// The hyper-parameters.
    #[must_use]
    pub fn params(&self) -> &DoubleQParams {
        &self.params
    }

    /// Mutable access to `Q1` (e.g. to seed it from prior experience).
    /// Keep the values finite.
    pub fn q1_mut(&mut self) -> &mut QTable {
        &mut self.q1
    }

    /// Mutable access to `Q2`. Keep the values finite.
    pub fn q2_mut(&mut self) -> &mut QTable {
        &mut self.q2
    }

    /// Sets every update count back to 0 (the tables are kept).
    pub fn clear_update_counts(&mut self) {
        self.update_counts.fill(0);
    }
}

impl Learner for DoubleQ {
    #[inline]
    fn n_states(&self) -> usize {
        self.q1.n_states()
    }

    #[inline]
    fn n_actions(&self) -> usize {
        self.q1.n_actions()
    }

    #[inline]
    fn action_values(&self, state: usize, out: &mut [f64]) {
        let row1 = self.q1.row(state);
        let row2 = self.q2.row(state);
        assert_eq!(out.len(), row1.len(), "action value buffer length");
        match self.params.behaviour {
            BehaviourValues::Mean => {
                for ((value, &a), &b) in out.iter_mut().zip(row1).zip(row2) {
                    *value = 0.5 * (a + b);
                }
            }
            BehaviourValues::Sum => {
                for ((value, &a), &b) in out.iter_mut().zip(row1).zip(row2) {
                    *value = a + b;
                }
            }
        }
    }

    #[inline]
    fn update<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action: usize,
        reward: f64,
        next_state: usize,
        terminated: bool,
        rng: &mut R,
    ) {
        let update_first = rng.random::<f64>() < self.params.xi;
        let (updated, evaluator) = if update_first {
            (&mut self.q1, &self.q2)
        } else {
            (&mut self.q2, &self.q1)
        };
        let target = if terminated {
            reward
        } else {
            // The updated table selects the successor's action, the other evaluates it.
            let best_next = updated.argmax(next_state, rng);
            reward + self.params.gamma * evaluator.get(next_state, best_next)
        };
        let alpha = self.params.alpha;
        let cell = &mut updated.row_mut(state)[action];
        *cell = (1.0 - alpha) * *cell + alpha * target;
        let count = &mut self.update_counts[state * self.q1.n_actions() + action];
        *count = count.saturating_add(1);
    }

    #[inline]
    fn q1(&self) -> &QTable {
        &self.q1
    }

    #[inline]
    fn q2(&self) -> &QTable {
        &self.q2
    }

    #[inline]
    fn update_counts(&self) -> &[u32] {
        &self.update_counts
    }
}
