//! Eq. 10–12 as printed: standardise the sub-tasks' rewards of one time step against each
//! other, then average.

use crate::error::{RewardStdError, check_rewards};

/// Standardises the `m` sub-task rewards of one time step against their own cross-sectional
/// mean and **population** standard deviation (Eq. 10–11), writes the z-scores
/// `Re_k = (r_k − μ) / σ` into `z_out`, and returns their mean (Eq. 12), the value the paper
/// hands to the source task.
///
/// **That mean is identically 0.** The z-scores of any set of numbers sum to zero, so Eq. 12
/// gives 0 whenever `σ > 0` (up to rounding, about `1e-16`); and when all rewards are equal,
/// `σ = 0` and Eq. 11 is 0/0, which we define as all z-scores 0 (never NaN). Taken literally,
/// the source task therefore learns from a reward of 0 on every step. We ship this literal
/// form so that the degeneracy can be shown (a property test proves it); use
/// [`RunningStandardiser`](crate::RunningStandardiser) for a standardisation that keeps a
/// learning signal.
///
/// Any finite input is accepted: the rewards are first scaled by an exact power of two (which
/// leaves z-scores unchanged, bit for bit, unless values are subnormal) so that huge or tiny
/// rewards neither overflow nor underflow, then shifted by their midrange, so that a large
/// common offset cannot swamp a small spread: for rewards like `1e9 + U(±1e-3)` the mean of
/// the z-scores stays within `1e-12` of 0 (a property test pins this). Allocates nothing.
///
/// # Errors
///
/// [`RewardStdError::Empty`] for no rewards, [`RewardStdError::LengthMismatch`] when `z_out`
/// is not as long as `rewards`, [`RewardStdError::NonFinite`] for a NaN or infinite reward.
/// On error `z_out` is left untouched.
///
/// # Example
///
/// ```
/// let mut z = [0.0; 3];
/// let mean = reward_std::cross_sectional(&[1.0, 2.0, 6.0], &mut z)?;
/// // μ = 3, σ = sqrt((4 + 1 + 9) / 3).
/// let sigma = (14.0_f64 / 3.0).sqrt();
/// assert!((z[0] - (-2.0 / sigma)).abs() < 1e-12);
/// assert!(mean.abs() < 1e-15); // Eq. 12 is always 0
/// # Ok::<(), reward_std::RewardStdError>(())
/// ```
pub fn cross_sectional(rewards: &[f64], z_out: &mut [f64]) -> Result<f64, RewardStdError> {
    check_rewards("rewards", rewards, rewards.len())?;
    if z_out.len() != rewards.len() {
        return Err(RewardStdError::LengthMismatch {
            what: "z_out",
            expected: rewards.len(),
            found: z_out.len(),
        });
    }
    let (lo, hi) = rewards
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &r| {
            (lo.min(r), hi.max(r))
        });
    if lo == hi {
        // σ = 0: all rewards equal, every z-score is 0 (Eq. 11 would be 0/0).
        z_out.fill(0.0);
        return Ok(0.0);
    }
    // Bring the rewards near 1 by an exact power of two, then shift them by their (scaled)
    // midrange. With a large common offset and a tiny spread (1e6 ± 1e-3) the shift is exact
    // (Sterbenz: the values lie within a factor 2 of each other), so every later sum works on
    // the deviations alone and cannot lose their digits to the offset. A second exact power of
    // two brings the deviations near 1 again.
    let (f1, f2) = power_of_two_scale(lo.abs().max(hi.abs()));
    let centre = (lo * f1 * f2) * 0.5 + (hi * f1 * f2) * 0.5;
    let spread = (hi * f1 * f2 - centre)
        .abs()
        .max((lo * f1 * f2 - centre).abs());
    let (g1, g2) = if spread > 0.0 {
        power_of_two_scale(spread)
    } else {
        (1.0, 1.0)
    };
    let scaled = |r: f64| ((r * f1 * f2) - centre) * g1 * g2;
    // sub-task counts are far below 2^53
    let m = rewards.len() as f64;
    // Two-pass mean with a correction pass: exact enough that equal deviations cancel.
    let rough_mean = rewards.iter().map(|&r| scaled(r)).sum::<f64>() / m;
    let mean = rough_mean + rewards.iter().map(|&r| scaled(r) - rough_mean).sum::<f64>() / m;
    let variance = rewards
        .iter()
        .map(|&r| {
            let d = scaled(r) - mean;
            d * d
        })
        .sum::<f64>()
        / m;
    let sigma = variance.sqrt();
    if sigma <= 0.0 || !sigma.is_finite() {
        // Unreachable for distinct normal values after scaling; kept so that no input can
        // produce a division by zero.
        z_out.fill(0.0);
        return Ok(0.0);
    }
    for (z, &r) in z_out.iter_mut().zip(rewards) {
        *z = (scaled(r) - mean) / sigma;
    }
    Ok(z_out.iter().sum::<f64>() / m)
}

/// Two powers of two whose product maps `magnitude` (finite, > 0) to about 1. Two factors,
/// because the full factor can exceed the range of `f64` (for subnormal magnitudes).
fn power_of_two_scale(magnitude: f64) -> (f64, f64) {
    // log2 of a finite positive f64 lies in [-1075, 1024].
    let k = -(magnitude.log2().round() as i32);
    let half = k / 2;
    (power_of_two(half), power_of_two(k - half))
}

/// `2^exponent` for an exponent of a normal `f64`, `[-1022, 1023]` (the scales above need
/// `[-512, 538]`), assembled from its bits: the value `2.0_f64.powi(exponent)` computes by
/// repeated multiplication, exact for powers of two, without the `__powidf2` call.
fn power_of_two(exponent: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&exponent), "normal exponent");
    // the biased exponent lies in [1, 2046]
    f64::from_bits(u64::from((exponent + 1023).unsigned_abs()) << 52)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The assembled powers of two are `powi`'s, bit for bit, over every exponent a normal
    /// `f64` has (a superset of what `power_of_two_scale` asks for).
    #[test]
    fn powers_of_two_are_powis() {
        for exponent in -1022..=1023 {
            assert_eq!(
                power_of_two(exponent).to_bits(),
                2.0_f64.powi(std::hint::black_box(exponent)).to_bits(),
                "2^{exponent}"
            );
        }
    }

    /// Every `k` the scale can produce splits into two normal powers of two.
    #[test]
    fn every_scale_exponent_is_in_range() {
        for magnitude in [f64::MAX, 5e-324, f64::MIN_POSITIVE, 1.0] {
            let k = -(magnitude.log2().round() as i32);
            assert!((-1024..=1075).contains(&k), "{magnitude}: {k}");
            let half = k / 2;
            assert!((-1022..=1023).contains(&half) && (-1022..=1023).contains(&(k - half)));
        }
    }

    #[test]
    fn scale_brings_extremes_near_one() {
        for m in [f64::MAX, 1e300, 1.0, 1e-300, f64::MIN_POSITIVE, 5e-324] {
            let (a, b) = power_of_two_scale(m);
            let s = m * a * b;
            assert!((0.5..=2.0).contains(&s), "{m} -> {s}");
        }
    }
}
