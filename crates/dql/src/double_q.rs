//! Double Q-learning (van Hasselt 2010; the paper's Eq. 9 and Algorithm 1, corrected).

use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::draw::Coin;
use crate::error::{DqlError, check_param};
use crate::learner::Learner;
use crate::table::{Initialisation, QTable, argmax_random_tie};

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
/// their defaults; an unknown field is an error that names it. [`DoubleQ::new`] validates; so
/// does [`validate`](Self::validate).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
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
/// With probability ξ the step updates `Q1`, otherwise `Q2` (one [`Coin`] flip,
/// i.e. one `u32` from the caller's RNG, per update). Updating `Q1` (mirror image for `Q2`):
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
///
/// Storage: one buffer in which state `s` holds `Q1(s, ·)` followed by
/// `Q2(s, ·)`, so everything a step reads about one state shares cache lines
/// (about 20 % faster than two separate tables on Task I's 900 × 4). Read the
/// estimators with [`Learner::q1_row`], [`Learner::q1`] or [`Learner::q1_table`].
///
/// Serialisable (parameters, both tables and the update counts), so a trained
/// learner can be saved and resumed; deserialising validates everything.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "DoubleQRepr", into = "DoubleQRepr")]
pub struct DoubleQ {
    params: DoubleQParams,
    n_states: usize,
    n_actions: usize,
    /// `[Q1(s, ·), Q2(s, ·)]` for s = 0, 1, …: `2 · n_actions` values per state.
    values: Vec<f64>,
    /// Heads (update Q1) with probability ξ.
    update_first: Coin,
    update_counts: Vec<u32>,
}

impl DoubleQ {
    /// A learner for `n_states × n_actions` with validated `params`. `Q1` is
    /// initialised first (all cells, row-major), then `Q2`, drawing from `rng` only
    /// for a uniform `init`.
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
        Self::from_tables(params, &q1, &q2)
    }

    /// A learner starting from the given estimators (e.g. restored or seeded from
    /// prior experience); `params.init` is not used. Update counts start at 0.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] for a bad parameter;
    /// [`DqlError::TableShapeMismatch`] when the tables' shapes differ.
    pub fn from_tables(params: DoubleQParams, q1: &QTable, q2: &QTable) -> Result<Self, DqlError> {
        params.validate()?;
        if (q1.n_states(), q1.n_actions()) != (q2.n_states(), q2.n_actions()) {
            return Err(DqlError::TableShapeMismatch {
                first_states: q1.n_states(),
                first_actions: q1.n_actions(),
                second_states: q2.n_states(),
                second_actions: q2.n_actions(),
            });
        }
        let (n_states, n_actions) = (q1.n_states(), q1.n_actions());
        let mut values = Vec::with_capacity(2 * q1.as_slice().len());
        for state in 0..n_states {
            values.extend_from_slice(q1.row(state));
            values.extend_from_slice(q2.row(state));
        }
        Ok(Self {
            update_first: Coin::new(params.xi),
            params,
            n_states,
            n_actions,
            values,
            update_counts: vec![0; n_states * n_actions],
        })
    }

    /// The hyper-parameters.
    #[must_use]
    pub fn params(&self) -> &DoubleQParams {
        &self.params
    }

    /// `Q1(state, ·)`, mutably (e.g. to seed it from prior experience).
    /// Keep the values finite.
    ///
    /// # Panics
    /// If `state >= n_states()`.
    pub fn q1_row_mut(&mut self, state: usize) -> &mut [f64] {
        let start = 2 * self.n_actions * state;
        &mut self.values[start..start + self.n_actions]
    }

    /// `Q2(state, ·)`, mutably. Keep the values finite.
    ///
    /// # Panics
    /// If `state >= n_states()`.
    pub fn q2_row_mut(&mut self, state: usize) -> &mut [f64] {
        let start = 2 * self.n_actions * state + self.n_actions;
        &mut self.values[start..start + self.n_actions]
    }

    /// Sets every update count back to 0 (the estimators are kept).
    pub fn clear_update_counts(&mut self) {
        self.update_counts.fill(0);
    }

    /// `[Q1(state, ·), Q2(state, ·)]`.
    #[inline]
    fn block(&self, state: usize) -> &[f64] {
        let width = 2 * self.n_actions;
        &self.values[width * state..width * state + width]
    }
}

/// The serialised form of a [`DoubleQ`].
#[derive(Serialize, Deserialize)]
struct DoubleQRepr {
    params: DoubleQParams,
    q1: QTable,
    q2: QTable,
    update_counts: Vec<u32>,
}

impl TryFrom<DoubleQRepr> for DoubleQ {
    type Error = DqlError;
    fn try_from(repr: DoubleQRepr) -> Result<Self, DqlError> {
        let mut learner = Self::from_tables(repr.params, &repr.q1, &repr.q2)?;
        if repr.update_counts.len() != learner.update_counts.len() {
            return Err(DqlError::UpdateCountLength {
                len: repr.update_counts.len(),
                cells: learner.update_counts.len(),
            });
        }
        learner.update_counts = repr.update_counts;
        Ok(learner)
    }
}

impl From<DoubleQ> for DoubleQRepr {
    fn from(learner: DoubleQ) -> Self {
        Self {
            params: learner.params,
            q1: learner.q1_table(),
            q2: learner.q2_table(),
            update_counts: learner.update_counts,
        }
    }
}

impl Learner for DoubleQ {
    #[inline]
    fn n_states(&self) -> usize {
        self.n_states
    }

    #[inline]
    fn n_actions(&self) -> usize {
        self.n_actions
    }

    #[inline(always)]
    fn action_values(&self, state: usize, out: &mut [f64]) {
        let (row1, row2) = self.block(state).split_at(self.n_actions);
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

    // `always`: with a plain hint the release build kept `update` (and ε-greedy's `select`)
    // out of line, a call per step on the hot path of `run_episode`; inlined, a Task I step
    // took about 15–20 % less time (docs/paper-notes.md §16). The arithmetic is the same.
    #[inline(always)]
    fn update<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action: usize,
        reward: f64,
        next_state: usize,
        terminated: bool,
        rng: &mut R,
    ) {
        let n = self.n_actions;
        assert!(action < n, "action {action} out of range");
        // 0 updates Q1 (probability ξ), 1 updates Q2. An index rather than a
        // branch: the coin is unpredictable by design.
        let updated = usize::from(!self.update_first.flip(rng));
        let target = if terminated {
            reward
        } else {
            // The updated estimator selects the successor's action, the other
            // one evaluates it.
            let successor = self.block(next_state);
            let selector = &successor[updated * n..updated * n + n];
            let evaluator = &successor[(1 - updated) * n..(1 - updated) * n + n];
            let best_next = argmax_random_tie(selector, rng);
            reward + self.params.gamma * evaluator[best_next]
        };
        let alpha = self.params.alpha;
        let cell = &mut self.values[2 * n * state + updated * n + action];
        *cell = (1.0 - alpha) * *cell + alpha * target;
        let count = &mut self.update_counts[n * state + action];
        *count = count.saturating_add(1);
    }

    #[inline]
    fn q1_row(&self, state: usize) -> &[f64] {
        &self.block(state)[..self.n_actions]
    }

    #[inline]
    fn q2_row(&self, state: usize) -> &[f64] {
        &self.block(state)[self.n_actions..]
    }

    #[inline]
    fn update_counts(&self) -> &[u32] {
        &self.update_counts
    }
}
