//! Statistics that fit reinforcement-learning results: location statistics over seeds (mean,
//! median, interquartile mean), seeded percentile and stratified bootstrap intervals,
//! permutation tests, Holm's adjustment, the probability of improvement, Wilson intervals for
//! success proportions, the normal quantile and a printable per-seed distribution.
//!
//! This module depends on nothing else of `eamadm-eval` (only `std`, `rand`, `rand_chacha`,
//! `serde` and `thiserror`). One file per topic: [`location`] (mean, median, IQM, SD,
//! quantiles), [`bootstrap`], [`permutation`] (the permutation test and its combinatorics),
//! [`comparison`] (Holm, probability of improvement), [`proportion`] (Wilson), [`normal`]
//! (the normal quantile), [`paired`] (sign-flip test, TOST, paired bootstrap, sign test) and
//! [`distribution`](mod@distribution).
//!
//! # Conventions
//!
//! Every function rejects an empty sample ([`StatsError::Empty`]) and any NaN or infinite value
//! ([`StatsError::NonFinite`], naming the position), and returns finite numbers only; it never
//! panics and never returns NaN.
//!
//! Every location statistic is computed from the **sorted** sample, adding in ascending order.
//! So each is a symmetric function of its input *bit for bit* (permuting the seeds cannot change
//! a single bit), and the bootstrap and the permutation test, which evaluate the statistic of a
//! resample from its multiplicities over the sorted data, give exactly the bits that
//! [`Statistic::of`] gives on the materialised resample. A mean of values that all lie in
//! `[a, b]` is clamped into `[a, b]`, so rounding can never push it outside.
//!
//! # Formulas
//!
//! With `x₍₁₎ ≤ … ≤ x₍ₙ₎` the sorted sample:
//!
//! * **Mean** `x̄ = (1/n) Σ x₍ᵢ₎`.
//! * **Median**: `x₍₍ₙ₊₁₎/₂₎` for odd `n`, `(x₍ₙ/₂₎ + x₍ₙ/₂₊₁₎)/2` for even `n`.
//! * **Interquartile mean** (IQM; Agarwal et al., *Deep reinforcement learning at the edge of
//!   the statistical precipice*, Advances in Neural Information Processing Systems 34, 2021):
//!   with `k = ⌊n/4⌋`, `IQM = (1/(n − 2k)) Σ_{i=k+1}^{n−k} x₍ᵢ₎`, the mean after dropping the `k` smallest and `k`
//!   largest values. This is rliable's definition, `scipy.stats.trim_mean(x, 0.25)`: whole
//!   observations are dropped and the ones at the quartile edges get **no** fractional weight.
//!   For `n ≤ 3` nothing is dropped and the IQM is the mean.
//! * **Sample standard deviation** `s = √(Σ (xᵢ − x̄)² / (n − 1))`, and `0` for `n = 1`.
//! * **Quantile** at level `p` (quartiles of [`distribution()`], bootstrap percentiles): linear
//!   interpolation between order statistics at position `h = (n − 1) p` (Hyndman & Fan type 7,
//!   numpy's default): `x₍⌊h⌋₊₁₎ + (h − ⌊h⌋)(x₍⌊h⌋₊₂₎ − x₍⌊h⌋₊₁₎)`.
//!
//! ## Bootstrap (Efron & Tibshirani, *An Introduction to the Bootstrap*, 1993, ch. 13)
//!
//! [`Bootstrap::interval`]: draw `B` resamples of size `n` with replacement, compute the
//! statistic `θ*_b` of each, and report the **percentile interval**
//! `[q_{α/2}(θ*), q_{1−α/2}(θ*)]` with `α = 1 − confidence` and `q` the type-7 quantile above;
//! the estimate is the statistic of the data itself. [`Bootstrap::difference`] resamples `x`
//! and `y` independently in each round (stratified by method) and takes the percentile interval
//! of `θ(x*) − θ(y*)`. [`Bootstrap::stratified_interval`] is the stratified bootstrap of
//! Agarwal et al. (2021): in each round every group (task) is resampled within itself with its
//! own size, the resampled groups are pooled and the statistic is taken of the pool.
//!
//! ## Permutation test
//!
//! [`PermutationTest::p_value`] tests exchangeability of `x` and `y` with the two-sided
//! statistic `D = |θ(x) − θ(y)|`. Over the `C(n+m, n)` ways to split the pooled sample into
//! groups of sizes `n` and `m`: if `C(n+m, n) ≤ resamples` every split is enumerated and
//! `p = #{splits with D ≥ D_obs} / C(n+m, n)` (the observed split is one of them); otherwise
//! `B = resamples` random splits are drawn and `p = (b + 1)/(B + 1)` with `b` the number of
//! drawn splits with `D ≥ D_obs` (Phipson & Smyth, *Permutation p-values should never be zero*,
//! 2010), so `p` is never 0. Splits whose `D` falls short of `D_obs` by no more than
//! `10⁻¹² · max |pooled value|` count as ties (`≥`): a different set of values can give the
//! same difference mathematically but not in the last bits.
//!
//! ## Multiple comparisons (Holm, *A simple sequentially rejective multiple test procedure*, 1979)
//!
//! [`holm`]: with the `m` p-values sorted ascending `p₍₁₎ ≤ … ≤ p₍ₘ₎`, the adjusted value of
//! the `i`-th is `min(1, max_{j ≤ i} (m − j + 1) p₍ⱼ₎)`, reported in the input order. Rejecting
//! where the adjusted value is `≤ α` controls the family-wise error rate at `α`.
//!
//! ## Probability of improvement (Agarwal et al., 2021)
//!
//! [`probability_of_improvement`] `P(X > Y) = (1/(n m)) Σᵢ Σⱼ [S(xᵢ, yⱼ)]` with `S = 1` when
//! `xᵢ > yⱼ`, `½` on ties and `0` otherwise, the Mann–Whitney `U` statistic of `x` divided by
//! `n m`. Counted in integers, so `P(X > Y) + P(Y > X) = 1`.
//!
//! ## Wilson score interval (Wilson, *Probable inference, the law of succession, and statistical inference*, 1927)
//!
//! [`wilson`]: with `p̂ = s/n` and `z = Φ⁻¹(1 − α/2)`,
//! `centre = (p̂ + z²/(2n)) / (1 + z²/n)` and
//! `half = z/(1 + z²/n) · √(p̂(1 − p̂)/n + z²/(4n²))`; the interval is `centre ± half`, clamped
//! to `[0, p̂]` below and `[p̂, 1]` above (it contains `p̂` exactly; the clamp only removes
//! rounding).
//!
//! ## Normal quantile (Wichura, *Algorithm AS 241: the percentage points of the normal distribution*, 1988)
//!
//! [`normal_quantile`] is `PPND16`: rational approximations of degree 7 in `r = 0.180625 − q²`
//! for `|q| = |p − ½| ≤ 0.425`, and in `r = √(−ln min(p, 1−p))` (shifted by 1.6 or 5) in the
//! tails; relative error about `10⁻¹⁶`.
//!
//! # Random draws (reproducible bit for bit)
//!
//! Every resampling method owns one `ChaCha8Rng::seed_from_u64(seed)`. A draw of an index
//! below `k` takes one 32-bit word `w` and returns `⌊w k / 2³²⌋`, rejecting and redrawing when
//! `(w k) mod 2³² < (2³² − k) mod k` (Lemire, *Fast random integer generation in an interval*,
//! 2019): exactly uniform, and independent of `rand`'s own range algorithm, which may change.
//! An index `i` into a sample selects its `i`-th smallest value (`f64::total_cmp` order), so
//! reordering the input changes no bit of any result. Draw order:
//!
//! * [`Bootstrap::interval`]: for `b = 1..=B`, `n` indices below `n`.
//! * [`Bootstrap::difference`]: for `b = 1..=B`, `n` indices below `n` for `x`, then `m`
//!   indices below `m` for `y`.
//! * [`Bootstrap::stratified_interval`]: for `b = 1..=B`, for each group `g` in the given
//!   order, `n_g` indices below `n_g`.
//! * [`PermutationTest::p_value`] (Monte Carlo): one array of pooled positions `0..n+m` kept
//!   across rounds; for `b = 1..=B`, a partial Fisher–Yates shuffle of its first `n` entries
//!   (for `i = 0..n`, swap entry `i` with entry `i + j`, `j` an index below `n + m − i`); those
//!   `n` positions form `x`'s group. Each round's split is uniform whatever the array held
//!   before.
//!
//! # Example
//!
//! ```
//! use eamadm_eval::stats::{Bootstrap, PermutationTest, Statistic, holm, iqm};
//!
//! // Final steps per seed: EA-MADM is bimodal (most seeds at the optimum, some stuck at the cap).
//! let ea_madm = [73.0, 73.0, 73.0, 73.0, 73.0, 75.0, 2000.0, 2000.0, 2000.0, 2000.0];
//! let other = [812.0, 2000.0, 1377.0, 2000.0, 954.0, 2000.0, 1640.0, 2000.0, 1105.0, 2000.0];
//! // The IQM drops the 2 smallest and 2 largest: (73 + 73 + 73 + 75 + 2000 + 2000) / 6.
//! assert!((iqm(&ea_madm)? - 4294.0 / 6.0).abs() < 1e-9);
//!
//! let bootstrap = Bootstrap::new(10_000, 0.95, 7)?;
//! let difference = bootstrap.difference(&ea_madm, &other, Statistic::Mean)?;
//! assert!(difference.low < difference.estimate && difference.estimate < difference.high);
//! let p = PermutationTest::default().p_value(&ea_madm, &other, Statistic::Mean)?;
//! let adjusted = holm(&[p, 0.2, 0.01])?;
//! assert!(adjusted[0] >= p && adjusted[0] <= 1.0);
//! # Ok::<(), eamadm_eval::stats::StatsError>(())
//! ```

use serde::{Deserialize, Serialize};
use thiserror::Error;

mod batch;
pub mod bootstrap;
pub mod comparison;
mod counted;
pub mod distribution;
pub mod hierarchical;
pub mod location;
pub mod normal;
pub mod paired;
pub mod paired_mean;
pub mod permutation;
pub mod proportion;
mod words;

pub use bootstrap::Bootstrap;
pub use comparison::{holm, probability_of_improvement};
pub use distribution::{Distribution, distribution};
pub use location::{Statistic, iqm, mean, median, sample_sd};
pub use normal::normal_quantile;
pub use paired::{Alternative, SignFlipTest, paired_difference, sign_test};
pub use paired_mean::{EXACT_MAX_PAIRS, SignFlipMeans};
pub use permutation::PermutationTest;
pub use proportion::wilson;

/// The most resamples a [`Bootstrap`] or [`PermutationTest`] accepts: the bootstrap keeps one
/// `f64` per resample, so this bounds its memory at 80 MB.
pub const MAX_RESAMPLES: u32 = 10_000_000;

/// Bad input to a statistic: what was wrong and what to fix.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum StatsError {
    /// An empty sample.
    #[error("{what} is empty: need at least one value")]
    Empty {
        /// Which input (for example `"x"`, `"y"`, `"p_values"`).
        what: &'static str,
    },
    /// A NaN or infinite value.
    #[error("{what}[{index}] = {value} is not finite: remove or replace it")]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// Position of the value in that input (0-based).
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A group of a stratified sample with no value.
    #[error("group {group} is empty: every group needs at least one value")]
    EmptyGroup {
        /// Position of the group (0-based).
        group: usize,
    },
    /// A NaN or infinite value in a group of a stratified sample.
    #[error("group {group}, value {index} = {value} is not finite: remove or replace it")]
    NonFiniteInGroup {
        /// Position of the group (0-based).
        group: usize,
        /// Position of the value within its group (0-based).
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A value that should be a probability is outside `[0, 1]` (or not finite).
    #[error("{what}[{index}] = {value} is not a probability: expected a value in [0, 1]")]
    NotAProbability {
        /// Which input.
        what: &'static str,
        /// Position of the value (0-based).
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// A parameter outside its domain.
    #[error("{name} = {value} is invalid: expected {expected}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// Its value, as given.
        value: String,
        /// What it must be.
        expected: &'static str,
    },
    /// No seeds at all (a curve statistic of [`summary`](crate::summary)).
    #[error("no seeds: need at least one curve or value")]
    NoSeeds,
    /// A seed whose curve has no episode.
    #[error("seed {seed} has an empty curve")]
    EmptyCurve {
        /// Index of the seed (position in the input).
        seed: usize,
    },
    /// A NaN or infinite value in a seed's curve.
    #[error("seed {seed}, episode {episode}: value {value} is not finite")]
    NonFiniteInCurve {
        /// Index of the seed (position in the input).
        seed: usize,
        /// Index of the episode within that seed's curve (0-based).
        episode: usize,
        /// The offending value.
        value: f64,
    },
    /// A window of zero episodes.
    #[error("window must be at least 1 episode, got 0")]
    ZeroWindow,
    /// The result is not representable as a finite `f64` (values near `f64::MAX`).
    #[error("{what} overflows f64: rescale the values")]
    Overflow {
        /// Which result.
        what: &'static str,
    },
}

/// An estimate with its confidence interval `[low, high]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    /// The point estimate (the statistic of the data itself).
    pub estimate: f64,
    /// Lower end of the interval.
    pub low: f64,
    /// Upper end of the interval.
    pub high: f64,
}

impl Interval {
    /// Whether `value` lies in `[low, high]`.
    pub fn contains(&self, value: f64) -> bool {
        self.low <= value && value <= self.high
    }

    /// Whether the interval lies entirely above or entirely below `value` (for a difference,
    /// `excludes(0.0)` says its sign is settled at this confidence).
    pub fn excludes(&self, value: f64) -> bool {
        !self.contains(value)
    }
}

/// Rejects an empty sample or a non-finite value.
pub(crate) fn check_sample(x: &[f64], what: &'static str) -> Result<(), StatsError> {
    if x.is_empty() {
        return Err(StatsError::Empty { what });
    }
    if let Some((index, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(StatsError::NonFinite { what, index, value });
    }
    Ok(())
}

/// A sample size as the `u32` the index draws use.
pub(crate) fn check_len(len: usize, what: &'static str) -> Result<u32, StatsError> {
    u32::try_from(len).map_err(|_| StatsError::InvalidParameter {
        name: what,
        value: len.to_string(),
        expected: "at most 4 294 967 295 values",
    })
}

pub(crate) fn check_resamples(resamples: u32) -> Result<(), StatsError> {
    if (1..=MAX_RESAMPLES).contains(&resamples) {
        Ok(())
    } else {
        Err(StatsError::InvalidParameter {
            name: "resamples",
            value: resamples.to_string(),
            expected: "between 1 and 10 000 000",
        })
    }
}

pub(crate) fn check_confidence(confidence: f64) -> Result<(), StatsError> {
    if confidence > 0.0 && confidence < 1.0 {
        Ok(())
    } else {
        Err(StatsError::InvalidParameter {
            name: "confidence",
            value: confidence.to_string(),
            expected: "a level strictly between 0 and 1, such as 0.95",
        })
    }
}

/// `value` if finite, else an overflow error naming `what`.
pub(crate) fn finite(value: f64, what: &'static str) -> Result<f64, StatsError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(StatsError::Overflow { what })
    }
}

/// A sorted copy (`total_cmp`: the sorted output is unique bit for bit).
pub(crate) fn sorted_copy(x: &[f64]) -> Vec<f64> {
    let mut sorted = x.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    sorted
}
