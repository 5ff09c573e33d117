//! Validated OWA weight vectors and the generators that produce them.

use serde::{Deserialize, Serialize};

use crate::error::{MadmError, check_finite, check_non_empty};
use crate::owa::{dot_clamped, orness_unchecked, owa, sort_descending, validate_weights};
use crate::support::{Support, fill_uniform, visibility_weights_unchecked};

/// A valid OWA weight vector: non-empty, every weight finite and in `[0, 1]`, summing to 1
/// within [`WEIGHT_SUM_TOLERANCE`](crate::WEIGHT_SUM_TOLERANCE). Weight `i` applies to the
/// `i`-th largest value.
///
/// Serialises as a plain list of numbers and validates when deserialised.
///
/// # Example
///
/// ```
/// use madm_owa::OwaWeights;
///
/// let w = OwaWeights::new(vec![0.4, 0.3, 0.2, 0.1])?;
/// assert!((w.aggregate(&[0.7, 1.0, 0.3, 0.6])? - 0.76).abs() < 1e-12);
/// assert!((w.orness() - 2.0 / 3.0).abs() < 1e-12);
///
/// let me = OwaWeights::maximum_entropy(3, 0.7)?;
/// assert!((me.orness() - 0.7).abs() < 1e-12);
/// # Ok::<(), madm_owa::MadmError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<f64>", into = "Vec<f64>")]
pub struct OwaWeights(Vec<f64>);

impl OwaWeights {
    /// Validates caller-given weights.
    ///
    /// # Errors
    ///
    /// Everything [`validate_weights`] rejects.
    pub fn new(weights: Vec<f64>) -> Result<Self, MadmError> {
        validate_weights(&weights)?;
        Ok(Self(weights))
    }

    /// `n` equal weights `1/n`: the OWA becomes the arithmetic mean (orness ½).
    ///
    /// # Errors
    ///
    /// [`MadmError::Empty`] when `n = 0`.
    pub fn uniform(n: usize) -> Result<Self, MadmError> {
        if n == 0 {
            return Err(MadmError::Empty { what: "weights" });
        }
        let mut weights = vec![0.0; n];
        fill_uniform(&mut weights);
        Ok(Self(weights))
    }

    /// O'Hagan's maximum-entropy weights of length `n` with the given `orness` (in `[0, 1]`):
    /// the most even weights whose orness is `orness`.
    ///
    /// Fullér and Majlender (2001) showed these weights form a geometric progression
    /// `w_i ∝ q^i`; we find `q` by bisection (`orness` is monotone in `q`). Orness 1 gives the
    /// max operator `(1, 0, …, 0)`, orness 0 the min operator, orness ½ the uniform weights.
    /// For `n = 1` the only weight vector is `(1)`, whatever `orness`.
    ///
    /// # Errors
    ///
    /// [`MadmError::Empty`] when `n = 0`; [`MadmError::InvalidParameter`] naming `orness` when
    /// it is not in `[0, 1]`.
    pub fn maximum_entropy(n: usize, orness: f64) -> Result<Self, MadmError> {
        let mut weights = vec![0.0; n];
        maximum_entropy_into(orness, &mut weights)?;
        Ok(Self(weights))
    }

    /// Visibility-based weights of the positions of `series` (Eq. 15); see
    /// [`visibility_weights_into`](crate::visibility_weights_into), which this wraps. For OWA
    /// weights in the paper's sense pass the values sorted in descending order, or use
    /// [`OwaWeights::visibility_of_values`].
    ///
    /// # Errors
    ///
    /// As [`visibility_weights_into`](crate::visibility_weights_into).
    pub fn visibility(series: &[f64], support: Support) -> Result<Self, MadmError> {
        support.validate()?;
        check_non_empty("series", series)?;
        check_finite("series", series)?;
        let mut weights = vec![0.0; series.len()];
        visibility_weights_unchecked(series, support, &mut weights);
        Ok(Self(weights))
    }

    /// Visibility-based weights for `values` in any order: sorts a copy in descending order
    /// (Step 1) and weights its positions (Steps 2–3). `aggregate(values)` with the result is
    /// the paper's `Eq` of a row (Step 4).
    ///
    /// # Errors
    ///
    /// As [`visibility_weights_into`](crate::visibility_weights_into).
    pub fn visibility_of_values(values: &[f64], support: Support) -> Result<Self, MadmError> {
        check_finite("values", values)?;
        let mut sorted = values.to_vec();
        sort_descending(&mut sorted);
        Self::visibility(&sorted, support)
    }

    /// The weights, position 0 (largest value) first.
    #[must_use]
    pub fn as_slice(&self) -> &[f64] {
        &self.0
    }

    /// Number of weights (never 0).
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Always `false`: a valid weight vector has at least one weight.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Yager's orness (see [`orness`](crate::orness)).
    #[must_use]
    pub fn orness(&self) -> f64 {
        orness_unchecked(&self.0)
    }

    /// Yager's andness, `1 − orness`.
    #[must_use]
    pub fn andness(&self) -> f64 {
        1.0 - self.orness()
    }

    /// The OWA aggregate of `values` with these weights (see [`owa`](crate::owa)).
    ///
    /// # Errors
    ///
    /// [`MadmError::LengthMismatch`] or [`MadmError::NonFinite`] for bad `values`.
    pub fn aggregate(&self, values: &[f64]) -> Result<f64, MadmError> {
        owa(values, &self.0)
    }

    /// The OWA aggregate of values already sorted in descending order (unchecked order is the
    /// caller's promise; see [`owa_sorted`](crate::owa_sorted) for the checked form).
    pub(crate) fn aggregate_sorted_unchecked(&self, sorted: &[f64]) -> f64 {
        dot_clamped(sorted, &self.0)
    }

    /// The weights as a vector.
    #[must_use]
    pub fn into_vec(self) -> Vec<f64> {
        self.0
    }
}

impl AsRef<[f64]> for OwaWeights {
    fn as_ref(&self) -> &[f64] {
        &self.0
    }
}

impl TryFrom<Vec<f64>> for OwaWeights {
    type Error = MadmError;

    fn try_from(weights: Vec<f64>) -> Result<Self, Self::Error> {
        Self::new(weights)
    }
}

impl From<OwaWeights> for Vec<f64> {
    fn from(weights: OwaWeights) -> Self {
        weights.0
    }
}

/// Writes maximum-entropy weights with the given orness into `out` (see
/// [`OwaWeights::maximum_entropy`]).
pub(crate) fn maximum_entropy_into(orness: f64, out: &mut [f64]) -> Result<(), MadmError> {
    if out.is_empty() {
        return Err(MadmError::Empty { what: "weights" });
    }
    if !(0.0..=1.0).contains(&orness) {
        return Err(MadmError::InvalidParameter {
            name: "orness",
            value: orness,
            reason: "must be in [0, 1]",
        });
    }
    if out.len() == 1 {
        out[0] = 1.0;
        return Ok(());
    }
    // Reversing a weight vector maps orness θ to 1 − θ, so solve for θ ≥ ½ (ratio q in [0, 1],
    // no overflow in q^i) and mirror.
    let target = orness.max(1.0 - orness);
    // The ends of the range are exact: q = 0 is the max operator, q = 1 the mean.
    if target >= 1.0 || target <= 0.5 {
        geometric_into(if target >= 1.0 { 0.0 } else { 1.0 }, out);
        if orness < 0.5 {
            out.reverse();
        }
        return Ok(());
    }
    // orness(q) falls from 1 at q = 0 to ½ at q = 1.
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        geometric_into(mid, out);
        if orness_unchecked(out) > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    geometric_into(0.5 * (lo + hi), out);
    if orness < 0.5 {
        out.reverse();
    }
    Ok(())
}

/// `out[i] = q^i / Σ_j q^j` for `q` in `[0, 1]`.
fn geometric_into(q: f64, out: &mut [f64]) {
    let mut term = 1.0;
    let mut sum = 0.0;
    for w in out.iter_mut() {
        *w = term;
        sum += term;
        term *= q;
    }
    for w in out.iter_mut() {
        *w /= sum;
    }
}
