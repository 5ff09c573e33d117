//! The natural visibility graph of a series (Lacasa et al., PNAS 2008): Step 2 of the paper's
//! MADM procedure (Eq. 14, which OCR garbled; this is the criterion it encodes).

use crate::error::{MadmError, check_finite};

/// `true` when positions `i` and `k` of `series` see each other in the natural visibility graph.
///
/// Plot each element as the bar `(position, value)`. Two positions `a < b` see each other when
/// every position `f` strictly between them lies strictly below the straight line joining the
/// tops of their bars:
///
/// ```text
/// y_f < y_b + (y_a - y_b) * (b - f) / (b - a)      for every a < f < b
/// ```
///
/// The criterion is *strict*: a point exactly on the line of sight blocks it, so a run of equal
/// values or a straight-line run connects only neighbours. Adjacent positions always see each
/// other. Visibility is symmetric, so `i` and `k` may come in either order.
///
/// The test is evaluated in the multiplied-out form `(y_f - y_b)(b - a) < (y_a - y_b)(b - f)`,
/// which is exact for integer-valued series and for ties; when a product overflows (values
/// within a factor of about `2n` of `f64::MAX`) the values are scaled by an exact power of two
/// and compared again.
///
/// Returns `false` when `i == k` (no self-loops) or either index is out of range. A NaN in the
/// series makes every comparison through it false (it blocks); [`natural_visibility_graph`]
/// rejects non-finite series instead.
#[must_use]
pub fn is_visible(series: &[f64], i: usize, k: usize) -> bool {
    let (a, b) = if i < k { (i, k) } else { (k, i) };
    if a == b || b >= series.len() {
        return false;
    }
    sees(series, a, b)
}

/// [`is_visible`] for `a < b < series.len()`. Inlined into the weight loops so that, for the
/// fixed row lengths of the decider, the whole check unrolls.
#[inline(always)]
pub(crate) fn sees(series: &[f64], a: usize, b: usize) -> bool {
    let (y_a, y_b) = (series[a], series[b]);
    // positions are far below 2^53
    let span = (b - a) as f64;
    ((a + 1)..b).all(|f| {
        let to_b = (b - f) as f64;
        strictly_below_line(series[f], y_a, y_b, span, to_b)
    })
}

/// Exactly 2^-64 (biased exponent 1023 - 64 = 959 = 0x3BF, zero mantissa).
const SCALE: f64 = f64::from_bits(0x3BF0_0000_0000_0000);

/// `y_f < y_b + (y_a - y_b) * to_b / span`, multiplied out and safe from overflow.
#[inline(always)]
fn strictly_below_line(y_f: f64, y_a: f64, y_b: f64, span: f64, to_b: f64) -> bool {
    let lhs = (y_f - y_b) * span;
    let rhs = (y_a - y_b) * to_b;
    if lhs.is_finite() && rhs.is_finite() {
        return lhs < rhs;
    }
    // Only reached for values near f64::MAX: scaling by 2^-64 is exact for such magnitudes and
    // leaves ample head-room for the differences and products.
    let (y_f, y_a, y_b) = (y_f * SCALE, y_a * SCALE, y_b * SCALE);
    (y_f - y_b) * span < (y_a - y_b) * to_b
}

/// The edges of the natural visibility graph of `series` (see [`is_visible`]), as pairs
/// `(i, k)` of 0-based positions with `i < k`, in lexicographic order.
///
/// An empty or one-element series has no edges. The direct check costs `O(n³)`, which is what
/// the MADM decision needs (`n` = number of attributes, a handful).
///
/// # Errors
///
/// [`MadmError::NonFinite`] if an element is NaN or infinite.
///
/// # Example
///
/// ```
/// use madm_owa::natural_visibility_graph;
///
/// let edges = natural_visibility_graph(&[0.9, 0.7, 0.6, 0.3])?;
/// assert_eq!(edges, [(0, 1), (0, 2), (1, 2), (2, 3)]);
/// // Ties and straight lines block: only neighbours connect.
/// assert_eq!(natural_visibility_graph(&[1.0, 1.0, 1.0])?, [(0, 1), (1, 2)]);
/// # Ok::<(), madm_owa::MadmError>(())
/// ```
pub fn natural_visibility_graph(series: &[f64]) -> Result<Vec<(usize, usize)>, MadmError> {
    check_finite("series", series)?;
    let n = series.len();
    let mut edges = Vec::new();
    for i in 0..n {
        for k in (i + 1)..n {
            if is_visible(series, i, k) {
                edges.push((i, k));
            }
        }
    }
    Ok(edges)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_is_two_to_the_minus_64() {
        assert_eq!(SCALE, 0.5_f64.powi(64));
    }
}
