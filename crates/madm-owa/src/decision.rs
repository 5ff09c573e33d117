//! The multi-attribute decision (Sec. IV.C, Eq. 13–16): the evaluation value of every row of a
//! decision matrix and the best row, allocation-free after the first call.

use rand::{Rng, RngExt};
use serde::{Deserialize, Serialize};

use crate::error::{MadmError, check_len};
use crate::owa::{dot_clamped, sort_descending};
use crate::support::{
    Support, fill_uniform, visibility_owa_sorted_unchecked, visibility_weights_unchecked,
};
use crate::weights::{OwaWeights, maximum_entropy_into};

/// Which OWA weights a [`MadmDecider`] applies to each sorted row: a config value, so that
/// experiments can swap the paper's visibility weights for plain OWA variants (ablations).
///
/// Serialised with a `kind` tag, e.g. in TOML:
///
/// ```toml
/// weighting = { kind = "visibility", support = { kind = "paper", epsilon = 1e-9 } }
/// weighting = { kind = "visibility", support = { kind = "distance" } }
/// weighting = { kind = "uniform" }
/// weighting = { kind = "given", weights = [0.4, 0.3, 0.2, 0.1] }
/// weighting = { kind = "maximum_entropy", orness = 0.7 }
/// ```
///
/// An unknown key is an error that names it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "WeightingRepr", into = "WeightingRepr")]
pub enum Weighting {
    /// Equal weights: every row is valued by the mean of its attributes.
    Uniform,
    /// The same caller-given weights for every row; their length must equal the number of
    /// columns of the matrices evaluated.
    Given {
        /// The weights, position 0 (largest attribute) first.
        weights: OwaWeights,
    },
    /// The same maximum-entropy weights with this orness for every row (see
    /// [`OwaWeights::maximum_entropy`]).
    MaximumEntropy {
        /// Orness in `[0, 1]`: 1 values a row by its best attribute, 0 by its worst.
        orness: f64,
    },
    /// The paper's method (the default): weights computed per row from the visibility graph of
    /// its sorted attributes (Eq. 14–15). The support defaults to [`Support::default`].
    Visibility {
        /// The support function of Eq. 15.
        support: Support,
    },
}

/// The serialised form of a [`Weighting`]: the same shape, but `Uniform` is an empty struct
/// variant, which rejects extra keys (a unit variant of an internally tagged enum would not).
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum WeightingRepr {
    Uniform {},
    Given {
        weights: OwaWeights,
    },
    MaximumEntropy {
        orness: f64,
    },
    Visibility {
        #[serde(default)]
        support: Support,
    },
}

impl From<WeightingRepr> for Weighting {
    fn from(repr: WeightingRepr) -> Self {
        match repr {
            WeightingRepr::Uniform {} => Self::Uniform,
            WeightingRepr::Given { weights } => Self::Given { weights },
            WeightingRepr::MaximumEntropy { orness } => Self::MaximumEntropy { orness },
            WeightingRepr::Visibility { support } => Self::Visibility { support },
        }
    }
}

impl From<Weighting> for WeightingRepr {
    fn from(weighting: Weighting) -> Self {
        match weighting {
            Weighting::Uniform => Self::Uniform {},
            Weighting::Given { weights } => Self::Given { weights },
            Weighting::MaximumEntropy { orness } => Self::MaximumEntropy { orness },
            Weighting::Visibility { support } => Self::Visibility { support },
        }
    }
}

impl Default for Weighting {
    /// [`Weighting::Visibility`] with the repaired paper support ([`Support::default`]).
    fn default() -> Self {
        Self::Visibility {
            support: Support::default(),
        }
    }
}

impl Weighting {
    /// Checks the parameters (the orness range, the support's `ε`; given weights are valid by
    /// construction).
    ///
    /// # Errors
    ///
    /// [`MadmError::InvalidParameter`] naming the parameter.
    pub fn validate(&self) -> Result<(), MadmError> {
        match self {
            Self::Uniform | Self::Given { .. } => Ok(()),
            Self::MaximumEntropy { orness } => {
                if (0.0..=1.0).contains(orness) {
                    Ok(())
                } else {
                    Err(MadmError::InvalidParameter {
                        name: "orness",
                        value: *orness,
                        reason: "must be in [0, 1]",
                    })
                }
            }
            Self::Visibility { support } => support.validate(),
        }
    }
}

/// Evaluates decision matrices (Eq. 13–16) and picks their best row.
///
/// A decision matrix is a flat, row-major `&[f64]` of `rows × cols` finite entries: one row
/// per action (scheme), one column per attribute (the sub-tasks' values and the source task's
/// own value). For each row the decider sorts the attributes in descending order (Step 1),
/// weights the sorted positions by its [`Weighting`] (Steps 2–3) and takes the dot product
/// (Step 4, Eq. 16, read with `ω_k`: the printed `ω_j` is a typo). The result always lies
/// between the row's smallest and largest attribute and is never NaN.
///
/// The decider owns its scratch buffers (hence `&mut self`): after the first call with the
/// largest shape it sees, calls allocate nothing. Give each learner its own decider. A 5 × 4
/// decision (the robot task's shape) takes about 120–130 ns (`cargo bench -p madm-owa`).
///
/// # Example
///
/// ```
/// use madm_owa::{MadmDecider, Weighting};
/// use rand::SeedableRng;
///
/// // 3 actions x 4 attributes; action 1 is best on every attribute.
/// let matrix = [
///     0.9, 0.7, 0.6, 0.3, //
///     1.0, 0.8, 0.7, 0.4, //
///     0.1, 0.2, 0.3, 0.4, //
/// ];
/// let mut decider = MadmDecider::new(Weighting::default())?;
/// let mut values = [0.0; 3];
/// decider.evaluate(&matrix, 3, 4, &mut values)?;
/// assert!((values[0] - 0.689).abs() < 1e-3); // the paper-notes' worked example
///
/// let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
/// assert_eq!(decider.best_row(&matrix, 3, 4, &mut rng)?, 1);
/// # Ok::<(), madm_owa::MadmError>(())
/// ```
#[derive(Debug, Clone)]
pub struct MadmDecider {
    weighting: Weighting,
    /// The row being evaluated, sorted in descending order.
    sorted: Vec<f64>,
    /// The weights of the row being evaluated; for row-independent weightings, the weights
    /// for `cached_cols` columns.
    weights: Vec<f64>,
    /// Number of columns the row-independent weights in `weights` were computed for (0: none).
    cached_cols: usize,
    /// The evaluation value of every row of the last [`MadmDecider::best_row`] call.
    values: Vec<f64>,
}

impl Default for MadmDecider {
    /// A decider with [`Weighting::default`] (the paper's visibility weights).
    fn default() -> Self {
        Self {
            weighting: Weighting::default(),
            sorted: Vec::new(),
            weights: Vec::new(),
            cached_cols: 0,
            values: Vec::new(),
        }
    }
}

impl MadmDecider {
    /// A decider applying `weighting`.
    ///
    /// # Errors
    ///
    /// Whatever [`Weighting::validate`] rejects.
    pub fn new(weighting: Weighting) -> Result<Self, MadmError> {
        weighting.validate()?;
        Ok(Self {
            weighting,
            ..Self::default()
        })
    }

    /// The weighting this decider applies.
    #[must_use]
    pub fn weighting(&self) -> &Weighting {
        &self.weighting
    }

    /// Writes the evaluation value `Eq(a_j)` of every row of `matrix` into `out` (Eq. 16).
    ///
    /// # Errors
    ///
    /// [`MadmError::EmptyMatrix`] when `rows` or `cols` is 0, [`MadmError::ShapeMismatch`] when
    /// `matrix.len() != rows × cols`, [`MadmError::LengthMismatch`] when `out.len() != rows`
    /// (or given weights do not have `cols` entries), [`MadmError::NonFiniteEntry`] for a NaN
    /// or infinite entry. On error `out` is left untouched.
    pub fn evaluate(
        &mut self,
        matrix: &[f64],
        rows: usize,
        cols: usize,
        out: &mut [f64],
    ) -> Result<(), MadmError> {
        check_matrix(matrix, rows, cols)?;
        check_len("out", out, rows)?;
        self.prepare(cols)?;
        for (row, value) in matrix.chunks_exact(cols).zip(out.iter_mut()) {
            *value = self.evaluate_row(row);
        }
        Ok(())
    }

    /// The evaluation value `Eq` of the single `row` (Eq. 16): what
    /// [`evaluate`](Self::evaluate) writes for a one-row matrix, bit for bit, without its
    /// output slice. The per-decision path of a caller that evaluates rows one at a time (the
    /// facade's EA-MADM policy recomputes only the rows whose attributes changed).
    ///
    /// # Errors
    ///
    /// As [`evaluate`](Self::evaluate) for a matrix of one row of `row.len()` columns.
    #[inline]
    pub fn evaluate_one(&mut self, row: &[f64]) -> Result<f64, MadmError> {
        check_matrix(row, 1, row.len())?;
        self.prepare(row.len())?;
        Ok(self.evaluate_row(row))
    }

    /// The index of the row with the largest evaluation value; when several rows share the
    /// largest value exactly, one of them uniformly at random from `rng`. The generator is
    /// drawn from only when there is a tie, so a decision without ties consumes no randomness.
    /// The values themselves are then available from [`MadmDecider::last_values`].
    ///
    /// Exact equality is the right notion of a tie here: rows holding the same attributes (in
    /// any order) get bit-identical values, since their sorted rows are identical.
    ///
    /// # Errors
    ///
    /// As [`MadmDecider::evaluate`] (without the `out` check).
    pub fn best_row<R: Rng + ?Sized>(
        &mut self,
        matrix: &[f64],
        rows: usize,
        cols: usize,
        rng: &mut R,
    ) -> Result<usize, MadmError> {
        // Take the buffer out so that `evaluate` can borrow `self`; put it back whatever
        // happens, so its capacity is kept.
        let mut values = std::mem::take(&mut self.values);
        values.resize(rows, 0.0);
        let result = self.evaluate(matrix, rows, cols, &mut values);
        self.values = values;
        result?;
        Ok(argmax_random_tie(&self.values, rng))
    }

    /// The evaluation values computed by the last successful [`MadmDecider::best_row`] call,
    /// one per row (empty before the first call; unspecified after a failed call).
    #[must_use]
    pub fn last_values(&self) -> &[f64] {
        &self.values
    }

    /// The OWA weights this decider attaches to the sorted positions of one `row` (largest
    /// attribute first) written into `weights_out`; returns the row's evaluation value. For
    /// inspection and tests; [`MadmDecider::evaluate`] is the fast path.
    ///
    /// # Errors
    ///
    /// As [`MadmDecider::evaluate`] for a one-row matrix, with `weights_out` needing
    /// `row.len()` entries.
    pub fn row_weights(&mut self, row: &[f64], weights_out: &mut [f64]) -> Result<f64, MadmError> {
        check_matrix(row, 1, row.len())?;
        check_len("weights_out", weights_out, row.len())?;
        self.prepare(row.len())?;
        let value = self.evaluate_row(row);
        let weights = match &self.weighting {
            Weighting::Given { weights } => weights.as_slice(),
            Weighting::Visibility { support } => {
                // The fused evaluation did not materialise the weights: compute them.
                self.sorted.copy_from_slice(row);
                sort_descending(&mut self.sorted);
                visibility_weights_unchecked(&self.sorted, *support, &mut self.weights);
                &self.weights
            }
            Weighting::Uniform | Weighting::MaximumEntropy { .. } => &self.weights,
        };
        weights_out.copy_from_slice(weights);
        Ok(value)
    }

    /// Sizes the scratch buffers for `cols` columns and computes row-independent weights.
    #[inline]
    fn prepare(&mut self, cols: usize) -> Result<(), MadmError> {
        if self.sorted.len() != cols {
            // `resize` only allocates when growing past the capacity: once per largest shape.
            self.sorted.resize(cols, 0.0);
            self.weights.resize(cols, 0.0);
            self.cached_cols = 0;
        }
        match &self.weighting {
            Weighting::Uniform if self.cached_cols != cols => {
                fill_uniform(&mut self.weights);
                self.cached_cols = cols;
            }
            Weighting::MaximumEntropy { orness } if self.cached_cols != cols => {
                maximum_entropy_into(*orness, &mut self.weights)?;
                self.cached_cols = cols;
            }
            Weighting::Given { weights } if weights.len() != cols => {
                return Err(MadmError::LengthMismatch {
                    what: "weighting.weights",
                    expected: cols,
                    found: weights.len(),
                });
            }
            _ => {}
        }
        Ok(())
    }

    /// `Eq` of one validated row of `self.sorted.len()` entries. With visibility weighting
    /// neither `self.sorted` nor `self.weights` holds anything meaningful afterwards (the
    /// fused path sorts on the stack and does not materialise the weights).
    fn evaluate_row(&mut self, row: &[f64]) -> f64 {
        if let Weighting::Visibility { support } = self.weighting {
            return visibility_row_value(row, support, &mut self.sorted, &mut self.weights);
        }
        self.sorted.copy_from_slice(row);
        sort_descending(&mut self.sorted);
        match &self.weighting {
            Weighting::Given { weights } => weights.aggregate_sorted_unchecked(&self.sorted),
            _ => dot_clamped(&self.sorted, &self.weights),
        }
    }
}

/// `Eq` of one finite row with visibility weights. Rows of 2 to 8 attributes are sorted in a
/// stack array of their exact length, so the compiler unrolls the sort and the visibility
/// loops (the facade's rows have 3 or 4; this halves the cost of a 5 x 4 decision); longer
/// rows use the heap scratch `sorted`. Both paths sort into the same sequence and then run the
/// same code, so they agree bit for bit (up to the sign of a zero result).
fn visibility_row_value(
    row: &[f64],
    support: Support,
    sorted: &mut [f64],
    scratch: &mut [f64],
) -> f64 {
    match row.len() {
        2 => visibility_row_value_fixed::<2>(row, support, scratch),
        3 => visibility_row_value_fixed::<3>(row, support, scratch),
        4 => visibility_row_value_fixed::<4>(row, support, scratch),
        5 => visibility_row_value_fixed::<5>(row, support, scratch),
        6 => visibility_row_value_fixed::<6>(row, support, scratch),
        7 => visibility_row_value_fixed::<7>(row, support, scratch),
        8 => visibility_row_value_fixed::<8>(row, support, scratch),
        _ => {
            sorted.copy_from_slice(row);
            sort_descending(sorted);
            visibility_owa_sorted_unchecked(sorted, support, scratch)
        }
    }
}

/// [`visibility_row_value`] for rows of exactly `N` attributes.
fn visibility_row_value_fixed<const N: usize>(
    row: &[f64],
    support: Support,
    scratch: &mut [f64],
) -> f64 {
    let mut sorted = [0.0; N];
    sorted.copy_from_slice(row);
    // Bubble sort as a sorting network: N(N-1)/2 branch-free compare-exchanges, fully
    // unrolled for a constant N (cheaper than the data-dependent branches of insertion sort).
    for pass in 0..N {
        for j in 0..N - 1 - pass.min(N - 1) {
            let (a, b) = (sorted[j], sorted[j + 1]);
            let swap = a < b;
            sorted[j] = if swap { b } else { a };
            sorted[j + 1] = if swap { a } else { b };
        }
    }
    visibility_owa_sorted_unchecked(&sorted, support, scratch)
}

/// Checks a flat row-major matrix: non-empty shape, matching length, finite entries.
#[inline]
fn check_matrix(matrix: &[f64], rows: usize, cols: usize) -> Result<(), MadmError> {
    if rows == 0 || cols == 0 {
        return Err(MadmError::EmptyMatrix { rows, cols });
    }
    if rows.checked_mul(cols) != Some(matrix.len()) {
        return Err(MadmError::ShapeMismatch {
            rows,
            cols,
            len: matrix.len(),
        });
    }
    // A branch-free pass (which the compiler vectorises) first; the search only on failure.
    if matrix.iter().fold(true, |ok, v| ok & v.is_finite()) {
        return Ok(());
    }
    let index = matrix
        .iter()
        .position(|v| !v.is_finite())
        .expect("the pass above found a non-finite entry");
    Err(MadmError::NonFiniteEntry {
        row: index / cols,
        col: index % cols,
        value: matrix[index],
    })
}

/// Index of the largest of the non-empty, finite `values`, ties broken uniformly at random
/// (one draw, and only when there is a tie).
fn argmax_random_tie<R: Rng + ?Sized>(values: &[f64], rng: &mut R) -> usize {
    let mut best = f64::NEG_INFINITY;
    let mut first = 0;
    let mut ties = 0_usize;
    for (i, &v) in values.iter().enumerate() {
        if v > best {
            best = v;
            first = i;
            ties = 1;
        } else if v == best {
            ties += 1;
        }
    }
    if ties <= 1 {
        return first;
    }
    let chosen = rng.random_range(0..ties);
    values
        .iter()
        .enumerate()
        .filter(|&(_, &v)| v == best)
        .nth(chosen)
        .map_or(first, |(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn any_weighting() -> impl proptest::strategy::Strategy<Value = Weighting> {
        use proptest::prelude::*;
        prop_oneof![
            Just(Weighting::default()),
            Just(Weighting::Visibility {
                support: Support::Distance
            }),
            Just(Weighting::Visibility {
                support: Support::Paper { epsilon: 0.0 }
            }),
            Just(Weighting::Uniform),
            (0.0..=1.0_f64).prop_map(|orness| Weighting::MaximumEntropy { orness }),
            Just(Weighting::Given {
                weights: OwaWeights::uniform(3).expect("3 uniform weights are valid")
            }),
        ]
    }

    proptest::proptest! {
        /// `evaluate_one` is `evaluate` of a one-row matrix: the same value bit for bit, or
        /// the same error (non-finite entries, an empty row, given weights of another length),
        /// whatever rows the decider saw before (its scratch buffers change size with them).
        #[test]
        fn evaluate_one_equals_a_one_row_evaluate(
            weighting in any_weighting(),
            rows in proptest::collection::vec(
                proptest::collection::vec(
                    proptest::prop_oneof![
                        8 => -100.0..100.0_f64,
                        1 => proptest::sample::select(vec![0.0, -0.0, 1.0, f64::NAN, f64::INFINITY]),
                    ],
                    0..12,
                ),
                1..8,
            ),
        ) {
            let mut one = MadmDecider::new(weighting.clone()).expect("valid weighting");
            let mut whole = MadmDecider::new(weighting).expect("valid weighting");
            for row in &rows {
                let mut out = [0.0];
                let expected = whole.evaluate(row, 1, row.len(), &mut out).map(|()| out[0]);
                let got = one.evaluate_one(row);
                // errors compared by their text: a NaN entry makes them unequal under `==`
                let bits = |r: Result<f64, MadmError>| r.map(f64::to_bits).map_err(|e| format!("{e:?}"));
                proptest::prop_assert_eq!(bits(got), bits(expected));
            }
        }
    }

    #[test]
    fn argmax_without_tie_consumes_no_randomness() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let before = rng.clone();
        assert_eq!(argmax_random_tie(&[0.1, 0.5, 0.2], &mut rng), 1);
        assert_eq!(rng, before);
    }

    #[test]
    fn argmax_ties_pick_only_tied_indices() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let mut seen = [0_u32; 4];
        for _ in 0..400 {
            seen[argmax_random_tie(&[0.5, 0.1, 0.5, 0.5], &mut rng)] += 1;
        }
        assert_eq!(seen[1], 0);
        assert!(seen[0] > 80 && seen[2] > 80 && seen[3] > 80, "{seen:?}");
    }
}
