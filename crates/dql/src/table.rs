//! A dense action-value table and the argmax/max helpers every learner and policy uses.

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::error::{DqlError, check_param};

/// How a fresh table is filled.
///
/// Algorithm 1 says "arbitrarily" and Algorithm 2 "randomly"; both are offered.
/// Serialised as `{"kind": "zero"}`, `{"kind": "constant", "value": 1.0}` or
/// `{"kind": "uniform", "low": -0.01, "high": 0.01}`; an unknown key is an error that names it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(from = "InitialisationRepr", into = "InitialisationRepr")]
pub enum Initialisation {
    /// Every value 0 (every greedy choice starts as a full tie).
    #[default]
    Zero,
    /// Every value `value` (e.g. optimistic initialisation).
    Constant {
        /// The value of every cell.
        value: f64,
    },
    /// Independent draws, uniform in `[low, high)`, from the caller's RNG.
    Uniform {
        /// Lower bound (inclusive).
        low: f64,
        /// Upper bound (exclusive; equal to `low` gives the constant `low`).
        high: f64,
    },
}

/// The serialised form of an [`Initialisation`]: the same shape, but `Zero` is an empty struct
/// variant, which rejects extra keys (a unit variant of an internally tagged enum would not).
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum InitialisationRepr {
    Zero {},
    Constant { value: f64 },
    Uniform { low: f64, high: f64 },
}

impl From<InitialisationRepr> for Initialisation {
    fn from(repr: InitialisationRepr) -> Self {
        match repr {
            InitialisationRepr::Zero {} => Self::Zero,
            InitialisationRepr::Constant { value } => Self::Constant { value },
            InitialisationRepr::Uniform { low, high } => Self::Uniform { low, high },
        }
    }
}

impl From<Initialisation> for InitialisationRepr {
    fn from(init: Initialisation) -> Self {
        match init {
            Initialisation::Zero => Self::Zero {},
            Initialisation::Constant { value } => Self::Constant { value },
            Initialisation::Uniform { low, high } => Self::Uniform { low, high },
        }
    }
}

/// Largest magnitude of an initial action value: `1e9`.
///
/// Initial values (and the tasks' rewards, bounded as tightly by their crates) this small keep
/// every learned value many orders of magnitude below `f64::MAX`: an update moves a value by at
/// most `α · (|r| + |Q|)`, so even the longest validated run cannot overflow, and the sums and
/// products of values that policies and decision rules form stay finite. Optimistic or
/// pessimistic initialisation needs values near the rewards' scale, far below this.
pub const MAX_ABS_INITIAL_VALUE: f64 = 1e9;

impl Initialisation {
    /// Checks the values are finite, at most [`MAX_ABS_INITIAL_VALUE`] in magnitude, and
    /// `low <= high`.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] naming `init.value`, `init.low` or `init.high`.
    pub fn validate(&self) -> Result<(), DqlError> {
        let bounded = |v: f64| v.is_finite() && v.abs() <= MAX_ABS_INITIAL_VALUE;
        match *self {
            Self::Zero => Ok(()),
            Self::Constant { value } => check_param(
                "init.value",
                value,
                bounded(value),
                "a finite value with |value| <= 1e9",
            ),
            Self::Uniform { low, high } => {
                check_param(
                    "init.low",
                    low,
                    bounded(low),
                    "a finite value with |low| <= 1e9",
                )?;
                check_param(
                    "init.high",
                    high,
                    bounded(high) && high >= low,
                    "a finite value >= init.low with |high| <= 1e9",
                )
            }
        }
    }
}

/// Action values `Q(s, a)` for `n_states × n_actions` pairs in one contiguous,
/// row-major buffer (row `s` holds the values of every action in state `s`).
///
/// The shape is fixed at construction and always has at least one state and one
/// action. Indexing methods panic on an out-of-range state or action: indices come
/// from the environment and the policy, whose contracts guarantee the range, so a
/// bad index is a programming error rather than bad input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "QTableRepr", into = "QTableRepr")]
pub struct QTable {
    n_states: usize,
    n_actions: usize,
    values: Vec<f64>,
}

/// The serialised form of a [`QTable`]; deserialising validates shape and values.
#[derive(Serialize, Deserialize)]
struct QTableRepr {
    n_states: usize,
    n_actions: usize,
    values: Vec<f64>,
}

impl TryFrom<QTableRepr> for QTable {
    type Error = DqlError;
    fn try_from(repr: QTableRepr) -> Result<Self, DqlError> {
        Self::from_values(repr.n_states, repr.n_actions, repr.values)
    }
}

impl From<QTable> for QTableRepr {
    fn from(table: QTable) -> Self {
        Self {
            n_states: table.n_states,
            n_actions: table.n_actions,
            values: table.values,
        }
    }
}

/// `n_states * n_actions`, or an error if either is 0 or the product overflows.
fn cell_count(n_states: usize, n_actions: usize) -> Result<usize, DqlError> {
    match n_states.checked_mul(n_actions) {
        Some(cells) if cells > 0 => Ok(cells),
        _ => Err(DqlError::InvalidShape {
            n_states,
            n_actions,
        }),
    }
}

impl QTable {
    /// A table of zeros.
    ///
    /// # Errors
    /// [`DqlError::InvalidShape`] when a dimension is 0 or the size overflows.
    pub fn zeros(n_states: usize, n_actions: usize) -> Result<Self, DqlError> {
        Self::filled(n_states, n_actions, 0.0)
    }

    /// A table with every cell equal to `value`.
    ///
    /// # Errors
    /// [`DqlError::InvalidShape`] as for [`zeros`](Self::zeros);
    /// [`DqlError::InvalidParameter`] when `value` is not finite.
    pub fn filled(n_states: usize, n_actions: usize, value: f64) -> Result<Self, DqlError> {
        check_param("value", value, value.is_finite(), "a finite value")?;
        let cells = cell_count(n_states, n_actions)?;
        Ok(Self {
            n_states,
            n_actions,
            values: vec![value; cells],
        })
    }

    /// A table filled according to `init`, drawing from `rng` for
    /// [`Initialisation::Uniform`] (cells in row-major order, one `f64` draw each).
    ///
    /// # Errors
    /// [`DqlError::InvalidShape`], or [`DqlError::InvalidParameter`] for a bad `init`.
    pub fn initialised<R: Rng + ?Sized>(
        n_states: usize,
        n_actions: usize,
        init: &Initialisation,
        rng: &mut R,
    ) -> Result<Self, DqlError> {
        init.validate()?;
        match *init {
            Initialisation::Zero => Self::zeros(n_states, n_actions),
            Initialisation::Constant { value } => Self::filled(n_states, n_actions, value),
            Initialisation::Uniform { low, high } => {
                let mut table = Self::zeros(n_states, n_actions)?;
                let width = high - low;
                for cell in &mut table.values {
                    // `low + width * u` with u in [0, 1) can round up to `high`;
                    // clamping keeps the documented half-open range.
                    let drawn = low + width * rng.random::<f64>();
                    *cell = if drawn < high { drawn } else { low };
                }
                Ok(table)
            }
        }
    }

    /// A table over the given row-major values.
    ///
    /// # Errors
    /// [`DqlError::InvalidShape`], [`DqlError::DataLength`] when
    /// `values.len() != n_states * n_actions`, [`DqlError::NonFiniteValue`] for a
    /// NaN or infinite value.
    pub fn from_values(
        n_states: usize,
        n_actions: usize,
        values: Vec<f64>,
    ) -> Result<Self, DqlError> {
        let cells = cell_count(n_states, n_actions)?;
        if values.len() != cells {
            return Err(DqlError::DataLength {
                len: values.len(),
                n_states,
                n_actions,
            });
        }
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(DqlError::NonFiniteValue {
                state: index / n_actions,
                action: index % n_actions,
                value: values[index],
            });
        }
        Ok(Self {
            n_states,
            n_actions,
            values,
        })
    }

    /// A table assembled row by row from `row(s)` (each of length `n_actions`),
    /// for learners that store their estimators in another layout. The shape is
    /// the learner's, hence valid.
    pub(crate) fn from_rows<'a>(
        n_states: usize,
        n_actions: usize,
        row: impl Fn(usize) -> &'a [f64],
    ) -> Self {
        let mut values = Vec::with_capacity(n_states * n_actions);
        for state in 0..n_states {
            values.extend_from_slice(row(state));
        }
        debug_assert_eq!(values.len(), n_states * n_actions);
        Self {
            n_states,
            n_actions,
            values,
        }
    }

    /// Number of states (rows).
    #[must_use]
    #[inline]
    pub fn n_states(&self) -> usize {
        self.n_states
    }

    /// Number of actions (columns).
    #[must_use]
    #[inline]
    pub fn n_actions(&self) -> usize {
        self.n_actions
    }

    /// `Q(state, action)`.
    ///
    /// # Panics
    /// If `state >= n_states()` or `action >= n_actions()`.
    #[must_use]
    #[inline]
    pub fn get(&self, state: usize, action: usize) -> f64 {
        self.row(state)[action]
    }

    /// Sets `Q(state, action)`. The value should be finite: learners rely on it.
    ///
    /// # Panics
    /// If `state >= n_states()` or `action >= n_actions()`.
    #[inline]
    pub fn set(&mut self, state: usize, action: usize, value: f64) {
        self.row_mut(state)[action] = value;
    }

    /// The values of every action in `state`.
    ///
    /// # Panics
    /// If `state >= n_states()`.
    #[must_use]
    #[inline]
    pub fn row(&self, state: usize) -> &[f64] {
        let start = state * self.n_actions;
        &self.values[start..start + self.n_actions]
    }

    /// The values of every action in `state`, mutably.
    ///
    /// # Panics
    /// If `state >= n_states()`.
    #[must_use]
    #[inline]
    pub fn row_mut(&mut self, state: usize) -> &mut [f64] {
        let start = state * self.n_actions;
        &mut self.values[start..start + self.n_actions]
    }

    /// All values, row-major: `Q(s, a)` is at `s * n_actions() + a`.
    #[must_use]
    #[inline]
    pub fn as_slice(&self) -> &[f64] {
        &self.values
    }

    /// `max_a Q(state, a)`.
    ///
    /// # Panics
    /// If `state >= n_states()`.
    #[must_use]
    #[inline]
    pub fn max(&self, state: usize) -> f64 {
        max_value(self.row(state))
    }

    /// `argmax_a Q(state, a)`, ties broken uniformly at random with `rng` (see
    /// [`argmax_random_tie`] for how many draws that takes).
    ///
    /// # Panics
    /// If `state >= n_states()`.
    #[must_use]
    #[inline]
    pub fn argmax<R: Rng + ?Sized>(&self, state: usize, rng: &mut R) -> usize {
        argmax_random_tie(self.row(state), rng)
    }
}

/// The largest value of `values`; NaNs are ignored, and an empty or all-NaN slice
/// gives `-inf`.
#[must_use]
#[inline]
pub fn max_value(values: &[f64]) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for &value in values {
        if value > best {
            best = value;
        }
    }
    best
}

/// The index of the largest value of `values`, ties broken uniformly at random.
///
/// One pass finds the maximum and counts how many entries equal it; only when
/// there is more than one does it draw (once, `rng.random_range(0..ties)`, which
/// `rand` takes from one `u32`) which of the tied indices to return. A unique maximum therefore consumes no randomness.
/// NaNs never win; if every value is NaN the result is 0.
///
/// # Panics
/// If `values` is empty.
#[must_use]
#[inline(always)]
pub fn argmax_random_tie<R: Rng + ?Sized>(values: &[f64], rng: &mut R) -> usize {
    // The mazes' four actions: the same code on a slice whose length the compiler knows, so
    // both passes are unrolled and unchecked (the robot's five take the general path).
    if let Ok(four) = <&[f64; 4]>::try_from(values) {
        return argmax_random_tie_of(four.as_slice(), rng);
    }
    argmax_random_tie_of(values, rng)
}

/// [`argmax_random_tie`]'s body, inlined into each call so that a known length unrolls it.
#[inline(always)]
fn argmax_random_tie_of<R: Rng + ?Sized>(values: &[f64], rng: &mut R) -> usize {
    assert!(!values.is_empty(), "argmax of an empty slice");
    let mut best = f64::NEG_INFINITY;
    let mut best_index = 0;
    let mut ties = 0_usize;
    // Written as selects rather than branches: on learned values the comparisons
    // are unpredictable, and conditional moves avoid the mispredictions.
    for (index, &value) in values.iter().enumerate() {
        let better = value > best;
        ties = if better {
            1
        } else {
            ties + usize::from(value == best)
        };
        best_index = if better { index } else { best_index };
        best = if better { value } else { best };
    }
    if ties <= 1 {
        return best_index;
    }
    let mut remaining = rng.random_range(0..ties);
    for (index, &value) in values.iter().enumerate().skip(best_index) {
        if value == best {
            if remaining == 0 {
                return index;
            }
            remaining -= 1;
        }
    }
    // The second pass visits exactly `ties` equal values, and `remaining < ties`.
    best_index
}
