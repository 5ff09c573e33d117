//! The repaired standardisation: each sub-task's reward against its own running statistics
//! over the episode (Welford), averaged over sub-tasks.

use crate::error::{RewardStdError, check_rewards};

/// Largest reward magnitude [`RunningStandardiser::push`] accepts: `1e150`.
///
/// Squared deviations of rewards this large stay below `f64::MAX` (`(2e150)² = 4e300`), so the
/// running statistics can never overflow, however long the episode. No task produces rewards
/// anywhere near this; a larger one is a bug upstream.
pub const MAX_ABS_REWARD: f64 = 1e150;

/// Running standardisation of `m` sub-task rewards (our repair of Eq. 10–12, whose literal form
/// is identically 0; see [`cross_sectional`](crate::cross_sectional)).
///
/// Each sub-task `k` keeps the running mean `μ_k` and **population** variance `σ_k²` of the
/// rewards it received since the episode started (Fig. 3 of the paper draws rewards along time
/// from the episode start `t₁`). Each [`push`](RunningStandardiser::push) of one time step's
/// rewards:
///
/// 1. **includes the new reward in the statistics first**, then
/// 2. standardises it, `z_k = (r_k − μ_k) / σ_k`, with `z_k = 0` when `σ_k = 0`, and
/// 3. returns the mean of the `z_k` over the sub-tasks.
///
/// Consequences of (1): the first step of an episode always yields 0 (one sample, `σ = 0`), a
/// sub-task whose reward never changes contributes 0, and every `z_k` is bounded by
/// `sqrt(n − 1)` after `n` steps (a new reward cannot be arbitrarily far from a mean that
/// includes it), so a single outlier cannot blow up the source task's reward.
///
/// The statistics use Welford's update in the form that stores the variance itself
/// (`σ² += (δ·δ′ − σ²) / n`), which is stable for long episodes and for rewards with a large
/// common offset, where `E[r²] − E[r]²` would cancel catastrophically. Call
/// [`reset`](RunningStandardiser::reset) at every episode start. Allocates nothing after
/// construction.
///
/// # Example
///
/// ```
/// use reward_std::RunningStandardiser;
///
/// let mut std = RunningStandardiser::new(2)?;
/// assert_eq!(std.push(&[-1.0, 5.0])?, 0.0); // first step of an episode: always 0
/// // Sub-task 0 improves (+1 against a mean of 0 and σ of 1); sub-task 1 is constant.
/// let signal = std.push(&[1.0, 5.0])?;
/// assert_eq!(std.z_scores(), [1.0, 0.0]);
/// assert_eq!(signal, 0.5);
/// std.reset();
/// assert_eq!(std.push(&[100.0, -3.0])?, 0.0);
/// # Ok::<(), reward_std::RewardStdError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RunningStandardiser {
    /// Time steps pushed since the last reset.
    count: u64,
    /// Running mean of each sub-task's rewards.
    mean: Vec<f64>,
    /// Running population variance of each sub-task's rewards.
    variance: Vec<f64>,
    /// z-score of each sub-task's latest reward.
    z: Vec<f64>,
    /// `1 / m` when the sub-task count `m` is a power of two (then exact), else `None`.
    power_of_two_reciprocal: Option<f64>,
}

impl RunningStandardiser {
    /// A standardiser for `subtasks` sub-tasks, at the start of an episode.
    ///
    /// # Errors
    ///
    /// [`RewardStdError::Empty`] when `subtasks` is 0.
    pub fn new(subtasks: usize) -> Result<Self, RewardStdError> {
        if subtasks == 0 {
            return Err(RewardStdError::Empty { what: "subtasks" });
        }
        Ok(Self {
            count: 0,
            mean: vec![0.0; subtasks],
            variance: vec![0.0; subtasks],
            z: vec![0.0; subtasks],
            // sub-task counts are far below 2^53
            power_of_two_reciprocal: subtasks.is_power_of_two().then(|| 1.0 / subtasks as f64),
        })
    }

    /// Forgets the episode's statistics: call at every episode start.
    pub fn reset(&mut self) {
        self.count = 0;
        self.mean.fill(0.0);
        self.variance.fill(0.0);
        self.z.fill(0.0);
    }

    /// Adds one time step's rewards (one per sub-task) to the statistics and returns the mean
    /// over sub-tasks of their z-scores against the updated statistics (see the type's docs).
    ///
    /// # Errors
    ///
    /// [`RewardStdError::Empty`], [`RewardStdError::LengthMismatch`] (not one reward per
    /// sub-task), [`RewardStdError::NonFinite`], or [`RewardStdError::OutOfRange`] (a reward
    /// beyond [`MAX_ABS_REWARD`]). The input is checked before anything changes, so on error
    /// the statistics are as before the call.
    pub fn push(&mut self, rewards: &[f64]) -> Result<f64, RewardStdError> {
        // One branch-free pass decides the common case (`|r| <= limit` is false for NaN and
        // the infinities too, and `new` refused 0 sub-tasks); only a bad input takes the
        // checks that find the error to report.
        let valid = rewards.len() == self.mean.len()
            && rewards
                .iter()
                .fold(true, |ok, r| ok & (r.abs() <= MAX_ABS_REWARD));
        if !valid {
            reject(rewards, self.mean.len())?;
        }
        self.count += 1;
        // exact below 2^53 steps
        let n = self.count as f64;
        let mut z_sum = 0.0;
        for (((&r, mean), variance), z) in rewards
            .iter()
            .zip(&mut self.mean)
            .zip(&mut self.variance)
            .zip(&mut self.z)
        {
            let delta = r - *mean;
            *mean += delta / n;
            let delta_after = r - *mean;
            // δ and δ′ never differ in sign (the new mean lies between the old one and r), so
            // the variance stays >= 0; the `max` only guards against the last rounding bit.
            *variance = (*variance + (delta * delta_after - *variance) / n).max(0.0);
            *z = if *variance > 0.0 {
                delta_after / variance.sqrt()
            } else {
                0.0
            };
            z_sum += *z;
        }
        Ok(mean_over_subtasks(
            z_sum,
            self.z.len(),
            self.power_of_two_reciprocal,
        ))
    }

    /// Number of sub-tasks.
    #[must_use]
    pub fn subtasks(&self) -> usize {
        self.mean.len()
    }

    /// Time steps pushed since the last reset.
    #[must_use]
    pub fn count(&self) -> u64 {
        self.count
    }

    /// The running mean of each sub-task's rewards (zeros right after a reset).
    #[must_use]
    pub fn means(&self) -> &[f64] {
        &self.mean
    }

    /// The running population variance of each sub-task's rewards (zeros right after a reset).
    #[must_use]
    pub fn variances(&self) -> &[f64] {
        &self.variance
    }

    /// The z-score of each sub-task's latest reward (zeros right after a reset).
    #[must_use]
    pub fn z_scores(&self) -> &[f64] {
        &self.z
    }
}

/// `z_sum / subtasks`, as a multiplication when `reciprocal` is the exact `1 / subtasks` of a
/// power of two: both then round the same real number `z_sum · 2⁻ᵏ` once, so the bits are the
/// same, and the step's learning update, which waits on the result, waits on a multiplication
/// rather than a division.
#[inline]
fn mean_over_subtasks(z_sum: f64, subtasks: usize, reciprocal: Option<f64>) -> f64 {
    match reciprocal {
        Some(reciprocal) => z_sum * reciprocal,
        // sub-task counts are far below 2^53
        None => z_sum / subtasks as f64,
    }
}

/// The error for `rewards` given to a standardiser of `subtasks` sub-tasks: empty, not one
/// reward per sub-task, non-finite, or beyond [`MAX_ABS_REWARD`], checked in that order.
/// `Ok` only for valid rewards.
fn reject(rewards: &[f64], subtasks: usize) -> Result<(), RewardStdError> {
    check_rewards("rewards", rewards, subtasks)?;
    if let Some(index) = rewards.iter().position(|r| r.abs() > MAX_ABS_REWARD) {
        return Err(RewardStdError::OutOfRange {
            index,
            value: rewards[index],
            limit: MAX_ABS_REWARD,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Dividing by a power of two and multiplying by its exact reciprocal give the same
        /// bits for every `f64` (subnormal results, both zeros, infinities and NaN included),
        /// for every sub-task count up to 2^10; other counts keep the division.
        #[test]
        fn the_mean_over_subtasks_is_the_division(
            bits in any::<u64>(),
            subtasks in 1..=1024_usize,
        ) {
            let z_sum = f64::from_bits(bits);
            let reciprocal = subtasks.is_power_of_two().then(|| 1.0 / subtasks as f64);
            let divided = z_sum / subtasks as f64;
            let mean = mean_over_subtasks(z_sum, subtasks, reciprocal);
            if divided.is_nan() {
                prop_assert!(mean.is_nan());
            } else {
                prop_assert_eq!(mean.to_bits(), divided.to_bits());
            }
        }

        /// The same law at the smallest magnitudes, where a multiplication's result is
        /// subnormal and rounding is coarsest.
        #[test]
        fn the_mean_over_subtasks_is_the_division_for_subnormals(
            mantissa in 0..(1_u64 << 54),
            exponent in 0..2_u32,
            negative in any::<bool>(),
            k in 0..=10_u32,
        ) {
            let z_sum = f64::from_bits(
                (u64::from(negative) << 63) | (u64::from(exponent) << 52) | (mantissa >> 2),
            );
            let subtasks = 1_usize << k;
            let mean = mean_over_subtasks(z_sum, subtasks, Some(1.0 / subtasks as f64));
            prop_assert_eq!(mean.to_bits(), (z_sum / subtasks as f64).to_bits());
        }

        /// The single-pass check accepts exactly the rewards the full checks accept, and a
        /// rejected push reports their error and changes nothing: bad pushes mixed into an
        /// episode leave it as if they had not been made.
        #[test]
        fn the_fast_check_accepts_what_the_full_checks_accept(
            pushes in proptest::collection::vec(
                proptest::collection::vec(
                    prop_oneof![
                        8 => -10.0..10.0_f64,
                        1 => proptest::sample::select(vec![
                            f64::NAN, f64::INFINITY, f64::NEG_INFINITY, MAX_ABS_REWARD,
                            -MAX_ABS_REWARD, 2.0 * MAX_ABS_REWARD, 0.0,
                        ]),
                    ],
                    0..4,
                ),
                0..20,
            ),
        ) {
            let mut checked = RunningStandardiser::new(2).expect("2 sub-tasks");
            let mut clean = checked.clone();
            for rewards in &pushes {
                let before = checked.clone();
                let got = checked.push(rewards);
                match reject(rewards, 2) {
                    Ok(()) => {
                        let expected = clean.push(rewards).expect("valid rewards");
                        prop_assert_eq!(got.map(f64::to_bits), Ok(expected.to_bits()));
                    }
                    Err(error) => {
                        // errors compared by their text: a NaN makes them unequal under `==`
                        prop_assert_eq!(format!("{:?}", got), format!("{:?}", Err::<f64, _>(error)));
                        prop_assert_eq!(&checked, &before);
                    }
                }
                prop_assert_eq!(&checked, &clean);
            }
        }
    }
}
