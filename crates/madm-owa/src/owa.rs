//! The OWA operator itself (Yager 1988; Eq. 3 of the paper) and the orness of its weights.

use crate::error::{MadmError, check_finite, check_len, check_non_empty};

/// How far the sum of OWA weights may stray from 1 and still be accepted.
///
/// Loose enough for weights written with a few decimals (`0.1 + 0.2 + 0.3 + 0.4` is
/// `1.0000000000000002`), tight enough to catch real mistakes.
pub const WEIGHT_SUM_TOLERANCE: f64 = 1e-9;

/// Checks that `weights` is a valid OWA weight vector: non-empty, finite, each weight `≥ 0`,
/// summing to 1 within [`WEIGHT_SUM_TOLERANCE`].
///
/// # Errors
///
/// [`MadmError::Empty`], [`MadmError::NonFinite`], [`MadmError::NegativeWeight`] or
/// [`MadmError::WeightSum`], checked in that order.
pub fn validate_weights(weights: &[f64]) -> Result<(), MadmError> {
    check_non_empty("weights", weights)?;
    check_finite("weights", weights)?;
    if let Some(index) = weights.iter().position(|&w| w < 0.0) {
        return Err(MadmError::NegativeWeight {
            index,
            value: weights[index],
        });
    }
    let sum: f64 = weights.iter().sum();
    if (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
        return Err(MadmError::WeightSum {
            sum,
            tolerance: WEIGHT_SUM_TOLERANCE,
        });
    }
    Ok(())
}

/// The OWA aggregate of `values` (Eq. 3): sort the values in descending order and take the
/// dot product with `weights`, whose `i`-th entry weights the `i`-th *largest* value.
///
/// The result always lies in `[min(values), max(values)]` (it is clamped there, so rounding
/// cannot push it out and huge values cannot overflow it), does not depend on the order of
/// `values`, and equals `c` for a constant vector `c`. Allocates one sorted copy of `values`;
/// on a hot path use [`owa_sorted`] or [`MadmDecider`](crate::MadmDecider).
///
/// # Errors
///
/// Everything [`validate_weights`] rejects, [`MadmError::LengthMismatch`] when `values` and
/// `weights` differ in length, and [`MadmError::NonFinite`] for a NaN or infinite value.
///
/// # Example
///
/// Yager's worked example:
///
/// ```
/// let v = madm_owa::owa(&[0.7, 1.0, 0.3, 0.6], &[0.4, 0.3, 0.2, 0.1])?;
/// assert!((v - 0.76).abs() < 1e-12);
/// # Ok::<(), madm_owa::MadmError>(())
/// ```
pub fn owa(values: &[f64], weights: &[f64]) -> Result<f64, MadmError> {
    validate_weights(weights)?;
    check_len("values", values, weights.len())?;
    check_finite("values", values)?;
    let mut sorted = values.to_vec();
    sort_descending(&mut sorted);
    Ok(dot_clamped(&sorted, weights))
}

/// [`owa`] for values already sorted in descending order. Allocates nothing.
///
/// # Errors
///
/// As [`owa`], plus [`MadmError::NotDescending`] when `sorted` is not in descending order.
pub fn owa_sorted(sorted: &[f64], weights: &[f64]) -> Result<f64, MadmError> {
    validate_weights(weights)?;
    check_len("sorted", sorted, weights.len())?;
    check_finite("sorted", sorted)?;
    if let Some(index) = (1..sorted.len()).find(|&i| sorted[i] > sorted[i - 1]) {
        return Err(MadmError::NotDescending {
            index,
            value: sorted[index],
            previous: sorted[index - 1],
        });
    }
    Ok(dot_clamped(sorted, weights))
}

/// Yager's orness of a weight vector: `Σ_i (n − 1 − i) · w_i / (n − 1)` with 0-based `i`.
///
/// 1 for the max operator `(1, 0, …, 0)`, 0 for the min operator `(0, …, 0, 1)`, ½ for the
/// mean; reversing the vector turns orness `θ` into `1 − θ`. For a single weight (`n = 1`) the
/// formula is 0/0; we return ½: the one-element OWA is max and min at once, and ½ is the only
/// value that the reversal law allows for a vector equal to its own reverse.
///
/// # Errors
///
/// Everything [`validate_weights`] rejects.
///
/// # Example
///
/// ```
/// let o = madm_owa::orness(&[0.4, 0.3, 0.2, 0.1])?;
/// assert!((o - 2.0 / 3.0).abs() < 1e-12);
/// # Ok::<(), madm_owa::MadmError>(())
/// ```
pub fn orness(weights: &[f64]) -> Result<f64, MadmError> {
    validate_weights(weights)?;
    Ok(orness_unchecked(weights))
}

/// Yager's andness, `1 − orness` (see [`orness`]).
///
/// # Errors
///
/// Everything [`validate_weights`] rejects.
pub fn andness(weights: &[f64]) -> Result<f64, MadmError> {
    orness(weights).map(|o| 1.0 - o)
}

/// [`orness`] of a non-empty vector, without validation.
// lengths are far below 2^53
pub(crate) fn orness_unchecked(weights: &[f64]) -> f64 {
    let n = weights.len();
    if n <= 1 {
        return 0.5;
    }
    let sum: f64 = weights
        .iter()
        .enumerate()
        .map(|(i, &w)| (n - 1 - i) as f64 * w)
        .sum();
    sum / (n - 1) as f64
}

/// Sorts finite values in descending order, in place (insertion sort: the rows we sort have a
/// handful of elements, where it beats the general-purpose sort; inlined so that fixed-size
/// rows unroll).
#[inline(always)]
pub(crate) fn sort_descending(values: &mut [f64]) {
    for i in 1..values.len() {
        let v = values[i];
        let mut j = i;
        while j > 0 && values[j - 1] < v {
            values[j] = values[j - 1];
            j -= 1;
        }
        values[j] = v;
    }
}

/// `Σ sorted_k · w_k`, clamped to `[last, first]` of the descending `sorted` slice. With finite
/// values and weights in `[0, 1]` the sum cannot be NaN; the clamp turns the (only
/// theoretically possible) overflow into the maximum and absorbs rounding.
#[inline]
pub(crate) fn dot_clamped(sorted: &[f64], weights: &[f64]) -> f64 {
    let sum: f64 = sorted.iter().zip(weights).map(|(y, w)| y * w).sum();
    let (max, min) = (sorted[0], sorted[sorted.len() - 1]);
    sum.max(min).min(max)
}
