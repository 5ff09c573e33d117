//! Visibility-based OWA weights (Step 3 of the MADM procedure, Eq. 15) and the support
//! functions they are built from.

use serde::{Deserialize, Serialize};

use crate::error::{MadmError, check_finite, check_len, check_non_empty};
use crate::visibility::sees;

/// Default `ε` of [`Support::Paper`]: small enough that it changes the weights of the paper's
/// worked example by less than `1e-6`, large enough that a tie between attributes `x` of order 1
/// gets a large but finite support (about `x² · 1e9`) instead of a division by zero.
pub const DEFAULT_EPSILON: f64 = 1e-9;

/// How much two mutually visible values `x` and `y` support each other in Eq. 15.
///
/// The weight of sorted position `k` is the total support it receives from the positions it
/// sees, divided by the total over all positions. When that total is 0 or not finite the
/// weights fall back to uniform (see [`visibility_weights_into`]).
///
/// Serialised with a `kind` tag, e.g. `{ kind = "paper", epsilon = 1e-9 }` or
/// `{ kind = "distance" }` in TOML; an unknown key is an error that names it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "SupportRepr", into = "SupportRepr")]
pub enum Support {
    /// The paper's support, repaired: `S(x, y) = max(0, x·y) / (|x − y|² + ε)`.
    ///
    /// The printed `x·y / |x − y|²` divides by zero on ties (and ties are always adjacent,
    /// hence always visible), is negative for values of opposite sign and is unbounded; `ε`
    /// and the clamp at 0 repair the first two. `ε = 0` is the literal form: then any visible
    /// tie of non-zero values makes the total support infinite and the row's weights uniform.
    /// Roughly scale-invariant while `ε` is small against the squared gaps.
    Paper {
        /// Added to the squared gap; finite and `≥ 0`. Defaults to [`DEFAULT_EPSILON`].
        epsilon: f64,
    },
    /// A bounded support, as in Yager's power average: `S(x, y) = 1 − |x − y| / range`, where
    /// `range = max − min` of the series being weighted. It lies in `[0, 1]`, is 1 for equal
    /// values and 0 for the two extremes. When `range = 0` (all values equal) every support
    /// is 1, so the weights are proportional to the visibility degree of each position.
    Distance,
}

/// The serialised form of a [`Support`]: the same shape, but `Distance` is an empty struct
/// variant, which rejects extra keys (a unit variant of an internally tagged enum would not).
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum SupportRepr {
    Paper {
        #[serde(default = "default_epsilon")]
        epsilon: f64,
    },
    Distance {},
}

fn default_epsilon() -> f64 {
    DEFAULT_EPSILON
}

impl From<SupportRepr> for Support {
    fn from(repr: SupportRepr) -> Self {
        match repr {
            SupportRepr::Paper { epsilon } => Self::Paper { epsilon },
            SupportRepr::Distance {} => Self::Distance,
        }
    }
}

impl From<Support> for SupportRepr {
    fn from(support: Support) -> Self {
        match support {
            Support::Paper { epsilon } => Self::Paper { epsilon },
            Support::Distance => Self::Distance {},
        }
    }
}

impl Default for Support {
    /// [`Support::Paper`] with [`DEFAULT_EPSILON`].
    fn default() -> Self {
        Self::Paper {
            epsilon: DEFAULT_EPSILON,
        }
    }
}

impl Support {
    /// Checks the parameters: `epsilon` must be finite and non-negative.
    ///
    /// # Errors
    ///
    /// [`MadmError::InvalidParameter`] naming `epsilon`.
    pub fn validate(&self) -> Result<(), MadmError> {
        match *self {
            Self::Paper { epsilon } if !(epsilon.is_finite() && epsilon >= 0.0) => {
                Err(MadmError::InvalidParameter {
                    name: "epsilon",
                    value: epsilon,
                    reason: "must be finite and >= 0",
                })
            }
            _ => Ok(()),
        }
    }
}

/// Writes into `out` the visibility-based OWA weights of the positions of `series` (Eq. 15).
///
/// For the MADM decision `series` is one row of attributes sorted in descending order (the
/// weights then attach to sorted positions, as OWA weights do); the function itself weights
/// the positions as given. Every pair `(i, k)` that sees each other in the natural visibility
/// graph ([`is_visible`](crate::is_visible)) adds `S(y_i, y_k)` to the support of both `i` and `k`; the weights are
/// the supports divided by their total.
///
/// **Fallback:** when the total support is 0 (no visible pair supports another, e.g. a single
/// value, or values of alternating sign) or not finite (literal `ε = 0` with a tie, or products
/// overflowing for values beyond about `1e154`), the weights are uniform, `1/n` each. The
/// result is therefore always a valid OWA weight vector (each weight in `[0, 1]`, summing to 1)
/// and never NaN. Allocates nothing.
///
/// # Errors
///
/// [`MadmError::Empty`] for an empty series, [`MadmError::LengthMismatch`] if `out` is not as
/// long as `series`, [`MadmError::NonFinite`] for a NaN or infinite value, and
/// [`MadmError::InvalidParameter`] for a bad `ε`.
///
/// # Example
///
/// The paper-notes' worked example: supports (21.75, 57.75, 50, 2) out of 131.5.
///
/// ```
/// use madm_owa::{Support, visibility_weights_into};
///
/// let mut w = [0.0; 4];
/// visibility_weights_into(&[0.9, 0.7, 0.6, 0.3], Support::default(), &mut w)?;
/// let expected = [21.75 / 131.5, 57.75 / 131.5, 50.0 / 131.5, 2.0 / 131.5];
/// for (got, want) in w.iter().zip(expected) {
///     assert!((got - want).abs() < 1e-6);
/// }
/// # Ok::<(), madm_owa::MadmError>(())
/// ```
pub fn visibility_weights_into(
    series: &[f64],
    support: Support,
    out: &mut [f64],
) -> Result<(), MadmError> {
    support.validate()?;
    check_non_empty("series", series)?;
    check_len("out", out, series.len())?;
    check_finite("series", series)?;
    visibility_weights_unchecked(series, support, out);
    Ok(())
}

/// [`visibility_weights_into`] without validation: `series` non-empty and finite, `out` of the
/// same length, `support` valid.
pub(crate) fn visibility_weights_unchecked(series: &[f64], support: Support, out: &mut [f64]) {
    out.fill(0.0);
    let total = for_each_visible_support(series, support, |i, k, s| {
        out[i] += s;
        out[k] += s;
    });
    if total_is_usable(total) {
        for w in out.iter_mut() {
            *w /= total;
        }
    } else {
        fill_uniform(out);
    }
}

/// The OWA aggregate of the finite, non-empty, descending `sorted` with its own visibility
/// weights, without materialising the weights: `Σ_k y_k·support_k / total`, one division per
/// row. Equal to aggregating with [`visibility_weights_unchecked`] up to rounding, and like it
/// clamped to `[min, max]`; falls back to that slower path (writing the weights into `scratch`,
/// as long as `sorted`) if the fused sum overflows. Always inlined, so that callers passing
/// fixed-size arrays get a fully unrolled loop.
#[inline(always)]
pub(crate) fn visibility_owa_sorted_unchecked(
    sorted: &[f64],
    support: Support,
    scratch: &mut [f64],
) -> f64 {
    let mut weighted = 0.0;
    let total = for_each_visible_support(sorted, support, |i, k, s| {
        // Overflows to infinity only for values near f64::MAX; then the slow path below runs.
        weighted += s * (sorted[i] + sorted[k]);
    });
    let (max, min) = (sorted[0], sorted[sorted.len() - 1]);
    let value = if total_is_usable(total) {
        weighted / total
    } else {
        // Uniform weights: the mean, computed without overflow.
        // lengths are far below 2^53
        let n = sorted.len() as f64;
        sorted.iter().map(|y| y / n).sum()
    };
    if value.is_finite() {
        value.max(min).min(max)
    } else {
        // Only for products beyond f64's range: normalise first, then multiply.
        visibility_weights_unchecked(sorted, support, scratch);
        crate::owa::dot_clamped(sorted, scratch)
    }
}

/// Calls `visit(i, k, S(y_i, y_k))` for every visible pair `i < k` of `series` and returns the
/// total support `2 Σ S` (each pair supports both ends). The support is chosen outside the
/// loop, so each support gets its own loop.
#[inline(always)]
fn for_each_visible_support(
    series: &[f64],
    support: Support,
    visit: impl FnMut(usize, usize, f64),
) -> f64 {
    match support {
        Support::Paper { epsilon } => {
            for_each_visible_pair(series, visit, |x, y| paper_support(x, y, epsilon))
        }
        Support::Distance => {
            // Distance support works on halved values: halving is exact (barring subnormals)
            // and makes `max - min` immune to overflow.
            let (lo, hi) = series
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &y| {
                    (lo.min(y), hi.max(y))
                });
            let half_range = 0.5 * hi - 0.5 * lo;
            for_each_visible_pair(series, visit, |x, y| distance_support(x, y, half_range))
        }
    }
}

/// The loop of [`for_each_visible_support`] for one support function.
#[inline(always)]
fn for_each_visible_pair(
    series: &[f64],
    mut visit: impl FnMut(usize, usize, f64),
    support: impl Fn(f64, f64) -> f64,
) -> f64 {
    let n = series.len();
    let mut pair_total = 0.0;
    for i in 0..n {
        for k in (i + 1)..n {
            if sees(series, i, k) {
                let s = support(series[i], series[k]);
                visit(i, k, s);
                pair_total += s;
            }
        }
    }
    // Doubling is exact: the same bits as summing `2 s` pair by pair.
    2.0 * pair_total
}

/// `true` when a total support can normalise: positive and finite. (`total > 0.0` is false
/// for NaN as well, so every non-finite support ends up in the uniform fallback.)
#[inline]
fn total_is_usable(total: f64) -> bool {
    total > 0.0 && total.is_finite()
}

/// `max(0, x·y) / (|x − y|² + ε)`; may be infinite or NaN on overflow (the caller falls back).
#[inline(always)]
fn paper_support(x: f64, y: f64, epsilon: f64) -> f64 {
    let product = x * y;
    let gap = x - y;
    // Divide unconditionally and select afterwards: branch-free, and the NaN of a discarded
    // 0/0 (a tie at 0 with ε = 0) never escapes.
    let support = product / (gap * gap + epsilon);
    if product > 0.0 { support } else { 0.0 }
}

/// `1 − |x − y| / range`, computed on halved values; 1 when the range is 0. Always in `[0, 1]`.
#[inline(always)]
fn distance_support(x: f64, y: f64, half_range: f64) -> f64 {
    if half_range > 0.0 {
        // |x/2 - y/2| <= half_range because rounding is monotone and x, y lie in [min, max].
        (1.0 - (0.5 * x - 0.5 * y).abs() / half_range).max(0.0)
    } else {
        1.0
    }
}

/// Fills `out` with `1 / out.len()`.
// lengths are far below 2^53
pub(crate) fn fill_uniform(out: &mut [f64]) {
    let w = 1.0 / out.len() as f64;
    out.fill(w);
}
