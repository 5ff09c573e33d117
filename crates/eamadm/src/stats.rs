//! Statistics that fit reinforcement-learning results: location statistics over seeds (mean,
//! median, interquartile mean), seeded percentile and stratified bootstrap intervals,
//! permutation tests, Holm's adjustment, the probability of improvement, Wilson intervals for
//! success proportions, the normal quantile and a printable per-seed distribution.
//!
//! This module depends on no other module of `eamadm` (only `std`, `rand`, `rand_chacha`,
//! `serde` and `thiserror`), so it can be lifted into a crate of its own.
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
//! * **Quantile** at level `p` (quartiles of [`distribution`], bootstrap percentiles): linear
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
//! use eamadm::stats::{Bootstrap, PermutationTest, Statistic, holm, iqm};
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
//! # Ok::<(), eamadm::stats::StatsError>(())
//! ```

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use thiserror::Error;

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

/// A location statistic over seeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Statistic {
    /// The arithmetic mean ([`mean`]).
    Mean,
    /// The median ([`median`]).
    Median,
    /// The interquartile mean ([`iqm`]).
    Iqm,
}

impl Statistic {
    /// Every statistic, in a fixed order.
    pub const ALL: [Self; 3] = [Self::Mean, Self::Median, Self::Iqm];

    /// The statistic of `x`.
    pub fn of(self, x: &[f64]) -> Result<f64, StatsError> {
        check_sample(x, "x")?;
        let sorted = sorted_copy(x);
        let ones = vec![1; sorted.len()];
        finite(self.of_counts(&sorted, &ones, sorted.len()), self.name())
    }

    /// The statistic's short name: `"mean"`, `"median"` or `"iqm"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Mean => "mean",
            Self::Median => "median",
            Self::Iqm => "iqm",
        }
    }

    /// The statistic of the multiset holding `sorted[i]` `counts[i]` times (`total` values in
    /// all, `total ≥ 1`), with `sorted` ascending. Adds in ascending order, so the bits equal
    /// those of the statistic of the materialised multiset.
    fn of_counts(self, sorted: &[f64], counts: &[u32], total: usize) -> f64 {
        match self {
            Self::Mean => trimmed_mean_of_counts(sorted, counts, 0, total),
            Self::Iqm => {
                let k = total / 4;
                trimmed_mean_of_counts(sorted, counts, k, total - k)
            }
            Self::Median => {
                let lower = value_at_position(sorted, counts, (total - 1) / 2);
                let upper = value_at_position(sorted, counts, total / 2);
                // Halving is exact, so this equals (lower + upper) / 2 but cannot overflow.
                lower / 2.0 + upper / 2.0
            }
        }
    }
}

/// The arithmetic mean `(1/n) Σ xᵢ`, added in ascending order.
pub fn mean(x: &[f64]) -> Result<f64, StatsError> {
    Statistic::Mean.of(x)
}

/// The median: the middle value, or the mean of the two middle values for even `n`.
pub fn median(x: &[f64]) -> Result<f64, StatsError> {
    Statistic::Median.of(x)
}

/// Interquartile mean: the mean of the middle 50 %, rliable's definition — the mean after
/// dropping the `⌊n/4⌋` smallest and the `⌊n/4⌋` largest values, with no fractional weight at
/// the quartile edges (= `scipy.stats.trim_mean(x, 0.25)`). For `n ≤ 3` it is the mean.
pub fn iqm(x: &[f64]) -> Result<f64, StatsError> {
    Statistic::Iqm.of(x)
}

/// Sample standard deviation (divisor `n − 1`; `0` for `n = 1`).
pub fn sample_sd(x: &[f64]) -> Result<f64, StatsError> {
    check_sample(x, "x")?;
    let n = x.len();
    if n == 1 {
        return Ok(0.0);
    }
    let centre = mean(x)?;
    // Scale by the largest deviation so that squaring cannot overflow.
    let scale = x.iter().map(|v| (v - centre).abs()).fold(0.0, f64::max);
    if scale == 0.0 {
        return Ok(0.0);
    }
    if !scale.is_finite() {
        return Err(StatsError::Overflow {
            what: "sample standard deviation",
        });
    }
    let squares: f64 = x.iter().map(|v| ((v - centre) / scale).powi(2)).sum();
    finite(
        scale * (squares / (n - 1) as f64).sqrt(),
        "sample standard deviation",
    )
}

/// Settings of the seeded percentile bootstrap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bootstrap {
    /// Number of resamples `B` (1 to [`MAX_RESAMPLES`]).
    pub resamples: u32,
    /// Confidence level of the interval, in `(0, 1)`.
    pub confidence: f64,
    /// Seed of the `ChaCha8` generator the resamples are drawn from.
    pub seed: u64,
}

impl Default for Bootstrap {
    /// 10 000 resamples, 95 % confidence, seed 0.
    fn default() -> Self {
        Self {
            resamples: 10_000,
            confidence: 0.95,
            seed: 0,
        }
    }
}

impl Bootstrap {
    /// Checked settings: `resamples` in `1..=MAX_RESAMPLES`, `confidence` in `(0, 1)`.
    pub fn new(resamples: u32, confidence: f64, seed: u64) -> Result<Self, StatsError> {
        let bootstrap = Self {
            resamples,
            confidence,
            seed,
        };
        bootstrap.validate()?;
        Ok(bootstrap)
    }

    /// Checks the settings (the fields are public, so [`Bootstrap::new`] may have been
    /// bypassed).
    fn validate(&self) -> Result<(), StatsError> {
        check_resamples(self.resamples)?;
        check_confidence(self.confidence)
    }

    /// Percentile interval of `statistic` over seeds; estimate = statistic of the data.
    pub fn interval(&self, x: &[f64], statistic: Statistic) -> Result<Interval, StatsError> {
        self.validate()?;
        check_sample(x, "x")?;
        let sample = Resampler::new(x)?;
        let estimate = statistic.of(x)?;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let mut replicates = Vec::with_capacity(self.resamples as usize);
        let mut counts = vec![0; x.len()];
        for _ in 0..self.resamples {
            let value = sample.draw(&mut rng, &mut counts, statistic);
            replicates.push(value);
        }
        self.percentile_interval(estimate, &mut replicates, statistic.name())
    }

    /// Interval of statistic(x) − statistic(y), x and y resampled independently (stratified by
    /// method).
    pub fn difference(
        &self,
        x: &[f64],
        y: &[f64],
        statistic: Statistic,
    ) -> Result<Interval, StatsError> {
        self.validate()?;
        check_sample(x, "x")?;
        check_sample(y, "y")?;
        let sample_x = Resampler::new(x)?;
        let sample_y = Resampler::new(y)?;
        let estimate = finite(statistic.of(x)? - statistic.of(y)?, "difference")?;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let mut replicates = Vec::with_capacity(self.resamples as usize);
        let mut counts_x = vec![0; x.len()];
        let mut counts_y = vec![0; y.len()];
        for _ in 0..self.resamples {
            let of_x = sample_x.draw(&mut rng, &mut counts_x, statistic);
            let of_y = sample_y.draw(&mut rng, &mut counts_y, statistic);
            replicates.push(of_x - of_y);
        }
        self.percentile_interval(estimate, &mut replicates, "difference")
    }

    /// Stratified bootstrap (rliable): resample within each group (task), pool, take the
    /// statistic. The estimate is the statistic of all groups pooled.
    pub fn stratified_interval(
        &self,
        groups: &[&[f64]],
        statistic: Statistic,
    ) -> Result<Interval, StatsError> {
        self.validate()?;
        if groups.is_empty() {
            return Err(StatsError::Empty { what: "groups" });
        }
        for (group, values) in groups.iter().enumerate() {
            if values.is_empty() {
                return Err(StatsError::EmptyGroup { group });
            }
            if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(StatsError::NonFiniteInGroup {
                    group,
                    index,
                    value,
                });
            }
            check_len(values.len(), "a group's size")?;
        }
        // The pool, sorted once; `positions[g][i]` is where group g's i-th smallest value sits.
        let pooled: Vec<f64> = groups.iter().flat_map(|g| g.iter().copied()).collect();
        let total = pooled.len();
        check_len(total, "the pooled sample's size")?;
        let estimate = statistic.of(&pooled)?;
        let mut order: Vec<usize> = (0..total).collect();
        order.sort_by(|&a, &b| pooled[a].total_cmp(&pooled[b]).then(a.cmp(&b)));
        let sorted: Vec<f64> = order.iter().map(|&i| pooled[i]).collect();
        let mut rank = vec![0; total];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r;
        }
        let mut positions = Vec::with_capacity(groups.len());
        let mut offset = 0;
        for values in groups {
            // Ascending ranks: index i of a group draws the group's i-th smallest value, as
            // in `interval`, so a single group gives exactly the plain bootstrap.
            let mut group = rank[offset..offset + values.len()].to_vec();
            group.sort_unstable();
            positions.push(group);
            offset += values.len();
        }

        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let mut replicates = Vec::with_capacity(self.resamples as usize);
        let mut counts = vec![0; total];
        for _ in 0..self.resamples {
            counts.fill(0);
            for group in &positions {
                let size = group.len() as u32;
                for _ in 0..group.len() {
                    counts[group[uniform_below(&mut rng, size) as usize]] += 1;
                }
            }
            replicates.push(statistic.of_counts(&sorted, &counts, total));
        }
        self.percentile_interval(estimate, &mut replicates, statistic.name())
    }

    /// The percentile interval of `replicates` (sorted in place) around `estimate`.
    fn percentile_interval(
        &self,
        estimate: f64,
        replicates: &mut [f64],
        what: &'static str,
    ) -> Result<Interval, StatsError> {
        if replicates.iter().any(|v| !v.is_finite()) {
            return Err(StatsError::Overflow { what });
        }
        replicates.sort_unstable_by(f64::total_cmp);
        let alpha = 1.0 - self.confidence;
        Ok(Interval {
            estimate,
            low: quantile_sorted(replicates, alpha / 2.0),
            high: quantile_sorted(replicates, 1.0 - alpha / 2.0),
        })
    }
}

/// Settings of the permutation test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PermutationTest {
    /// The largest number of splits enumerated exactly, and the number of random splits drawn
    /// otherwise (1 to [`MAX_RESAMPLES`]).
    pub resamples: u32,
    /// Seed of the `ChaCha8` generator of the random splits.
    pub seed: u64,
}

impl Default for PermutationTest {
    /// 10 000 resamples, seed 0.
    fn default() -> Self {
        Self {
            resamples: 10_000,
            seed: 0,
        }
    }
}

impl PermutationTest {
    /// Checked settings: `resamples` in `1..=MAX_RESAMPLES`.
    pub fn new(resamples: u32, seed: u64) -> Result<Self, StatsError> {
        check_resamples(resamples)?;
        Ok(Self { resamples, seed })
    }

    /// Whether [`p_value`](Self::p_value) enumerates every split for samples of sizes `n` and
    /// `m` (`C(n+m, n) ≤ resamples`) rather than drawing random ones.
    pub fn is_exact(&self, n: usize, m: usize) -> bool {
        binomial_at_most(n + m, n, u64::from(self.resamples)).is_some()
    }

    /// Two-sided p-value of |statistic(x) − statistic(y)| under exchangeability: exact
    /// enumeration of all splits when C(n+m, n) ≤ resamples, else Monte Carlo with
    /// (b+1)/(B+1).
    pub fn p_value(&self, x: &[f64], y: &[f64], statistic: Statistic) -> Result<f64, StatsError> {
        check_resamples(self.resamples)?;
        check_sample(x, "x")?;
        check_sample(y, "y")?;
        let (n, m) = (x.len(), y.len());
        let total = n + m;
        check_len(total, "the pooled sample's size")?;
        let mut pooled: Vec<f64> = x.iter().chain(y).copied().collect();
        pooled.sort_unstable_by(f64::total_cmp);
        let scale = pooled.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let observed = (statistic.of(x)? - statistic.of(y)?).abs();
        // Ties within rounding count as at least as extreme (see the module docs).
        let threshold = observed - 1e-12 * scale;
        let mut in_x = vec![0_u32; total];
        let mut in_y = vec![0_u32; total];
        let as_extreme = |in_x: &[u32], in_y: &mut [u32]| {
            for (to_y, &to_x) in in_y.iter_mut().zip(in_x) {
                *to_y = 1 - to_x;
            }
            let difference =
                statistic.of_counts(&pooled, in_x, n) - statistic.of_counts(&pooled, in_y, m);
            difference.abs() >= threshold
        };

        if let Some(splits) = binomial_at_most(total, n, u64::from(self.resamples)) {
            // Every n-subset of the pooled positions, in lexicographic order.
            let mut chosen: Vec<usize> = (0..n).collect();
            let mut hits = 0_u64;
            loop {
                in_x.fill(0);
                for &i in &chosen {
                    in_x[i] = 1;
                }
                if as_extreme(&in_x, &mut in_y) {
                    hits += 1;
                }
                if !next_combination(&mut chosen, total) {
                    break;
                }
            }
            Ok(hits as f64 / splits as f64)
        } else {
            let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
            let mut permutation: Vec<usize> = (0..total).collect();
            let mut hits = 0_u64;
            for _ in 0..self.resamples {
                for i in 0..n {
                    let j = i + uniform_below(&mut rng, (total - i) as u32) as usize;
                    permutation.swap(i, j);
                }
                in_x.fill(0);
                for &i in &permutation[..n] {
                    in_x[i] = 1;
                }
                if as_extreme(&in_x, &mut in_y) {
                    hits += 1;
                }
            }
            Ok((hits + 1) as f64 / (f64::from(self.resamples) + 1.0))
        }
    }
}

/// Holm–Bonferroni step-down adjusted p-values, in the input order, monotone, capped at 1.
pub fn holm(p_values: &[f64]) -> Result<Vec<f64>, StatsError> {
    if p_values.is_empty() {
        return Err(StatsError::Empty { what: "p_values" });
    }
    if let Some((index, &value)) = p_values
        .iter()
        .enumerate()
        .find(|(_, p)| !(0.0..=1.0).contains(*p))
    {
        return Err(StatsError::NotAProbability {
            what: "p_values",
            index,
            value,
        });
    }
    let m = p_values.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p_values[a].total_cmp(&p_values[b]).then(a.cmp(&b)));
    let mut adjusted = vec![0.0; m];
    let mut running = 0.0_f64;
    for (rank, &i) in order.iter().enumerate() {
        running = running.max(((m - rank) as f64 * p_values[i]).min(1.0));
        adjusted[i] = running;
    }
    Ok(adjusted)
}

/// P(X > Y) + ½ P(X = Y) over all pairs (Mann–Whitney U / (n m)).
pub fn probability_of_improvement(x: &[f64], y: &[f64]) -> Result<f64, StatsError> {
    check_sample(x, "x")?;
    check_sample(y, "y")?;
    // Twice the U statistic, in integers: 2 per win, 1 per tie.
    let mut doubled_u = 0_u128;
    for a in x {
        for b in y {
            doubled_u += match a.partial_cmp(b) {
                Some(std::cmp::Ordering::Greater) => 2,
                Some(std::cmp::Ordering::Equal) => 1,
                _ => 0,
            };
        }
    }
    let pairs = x.len() as u128 * y.len() as u128;
    Ok(doubled_u as f64 / (2 * pairs) as f64)
}

/// Wilson score interval for a proportion; estimate = successes / trials.
pub fn wilson(successes: u64, trials: u64, confidence: f64) -> Result<Interval, StatsError> {
    if trials == 0 {
        return Err(StatsError::InvalidParameter {
            name: "trials",
            value: "0".to_owned(),
            expected: "at least 1 trial",
        });
    }
    if successes > trials {
        return Err(StatsError::InvalidParameter {
            name: "successes",
            value: successes.to_string(),
            expected: "at most the number of trials",
        });
    }
    check_confidence(confidence)?;
    let z = normal_quantile(1.0 - (1.0 - confidence) / 2.0)?;
    let n = trials as f64;
    let proportion = successes as f64 / n;
    let z2 = z * z;
    let denominator = 1.0 + z2 / n;
    let centre = (proportion + z2 / (2.0 * n)) / denominator;
    let half = z * (proportion * (1.0 - proportion) / n + z2 / (4.0 * n * n)).sqrt() / denominator;
    Ok(Interval {
        estimate: proportion,
        low: (centre - half).clamp(0.0, proportion),
        high: (centre + half).clamp(proportion, 1.0),
    })
}

/// The per-seed distribution in a form a report prints.
///
/// `bimodal` is true when either rule holds:
/// * **cap rule** (with a cap): at least 2 values at or above the cap and at least 2 below it
///   — some seeds are stuck at the step cap while others are not;
/// * **gap rule**: the sorted values split at one place into a lower and an upper group of at
///   least 2 values each, and the gap between the groups is wider than the two groups' ranges
///   added together — two clusters further apart than either is wide.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Distribution {
    /// Number of values.
    pub n: usize,
    /// Smallest value.
    pub min: f64,
    /// First quartile (type 7).
    pub q1: f64,
    /// Median.
    pub median: f64,
    /// Third quartile (type 7).
    pub q3: f64,
    /// Largest value.
    pub max: f64,
    /// How many values are at or above the cap (0 without a cap).
    pub at_cap: usize,
    /// Whether the values form two separated groups (see the type's docs).
    pub bimodal: bool,
}

/// The per-seed distribution of `x`; `cap` is the step cap, if the values have one.
pub fn distribution(x: &[f64], cap: Option<f64>) -> Result<Distribution, StatsError> {
    check_sample(x, "x")?;
    if let Some(cap) = cap.filter(|c| !c.is_finite()) {
        return Err(StatsError::InvalidParameter {
            name: "cap",
            value: cap.to_string(),
            expected: "a finite number",
        });
    }
    let sorted = sorted_copy(x);
    let n = sorted.len();
    let at_cap = cap.map_or(0, |cap| sorted.iter().filter(|&&v| v >= cap).count());
    let cap_rule = cap.is_some() && at_cap >= 2 && n - at_cap >= 2;
    let gap_rule = (2..=n.saturating_sub(2)).any(|k| {
        let gap = sorted[k] - sorted[k - 1];
        let spread = (sorted[k - 1] - sorted[0]) + (sorted[n - 1] - sorted[k]);
        gap > spread
    });
    Ok(Distribution {
        n,
        min: sorted[0],
        q1: quantile_sorted(&sorted, 0.25),
        median: median(x)?,
        q3: quantile_sorted(&sorted, 0.75),
        max: sorted[n - 1],
        at_cap,
        bimodal: cap_rule || gap_rule,
    })
}

/// Normal quantile (inverse CDF) needed by Wilson for any confidence (Wichura's AS 241
/// `PPND16`, relative error about 1e-16). `p` must lie in `(0, 1)`.
pub fn normal_quantile(p: f64) -> Result<f64, StatsError> {
    if !(p > 0.0 && p < 1.0) {
        return Err(StatsError::InvalidParameter {
            name: "p",
            value: p.to_string(),
            expected: "a probability strictly between 0 and 1",
        });
    }
    let q = p - 0.5;
    if q.abs() <= 0.425 {
        let r = 0.180_625 - q * q;
        return Ok(q * polynomial(&AS241_A, r) / polynomial(&AS241_B, r));
    }
    let tail = if q < 0.0 { p } else { 1.0 - p };
    let r = (-tail.ln()).sqrt();
    let magnitude = if r <= 5.0 {
        let r = r - 1.6;
        polynomial(&AS241_C, r) / polynomial(&AS241_D, r)
    } else {
        let r = r - 5.0;
        polynomial(&AS241_E, r) / polynomial(&AS241_F, r)
    };
    Ok(if q < 0.0 { -magnitude } else { magnitude })
}

/// Wichura (1988), AS 241 `PPND16`: numerator for `|p − ½| ≤ 0.425`, lowest power first.
#[expect(
    clippy::excessive_precision,
    reason = "the published AS 241 coefficients, kept digit for digit"
)]
const AS241_A: [f64; 8] = [
    3.387_132_872_796_366_608,
    1.331_416_678_917_843_774_5e2,
    1.971_590_950_306_551_442_7e3,
    1.373_169_376_550_946_112_5e4,
    4.592_195_393_154_987_145_7e4,
    6.726_577_092_700_870_085_3e4,
    3.343_057_558_358_812_810_5e4,
    2.509_080_928_730_122_672_7e3,
];
/// Denominator for `|p − ½| ≤ 0.425`.
#[expect(
    clippy::excessive_precision,
    reason = "the published AS 241 coefficients, kept digit for digit"
)]
const AS241_B: [f64; 8] = [
    1.0,
    4.231_333_070_160_091_125_2e1,
    6.871_870_074_920_579_083e2,
    5.394_196_021_424_751_107_7e3,
    2.121_379_430_158_659_586_7e4,
    3.930_789_580_009_271_061e4,
    2.872_908_573_572_194_267_4e4,
    5.226_495_278_852_854_561e3,
];
/// Numerator for the tail with `r = √(−ln min(p, 1−p)) ≤ 5` (in `r − 1.6`).
#[expect(
    clippy::excessive_precision,
    reason = "the published AS 241 coefficients, kept digit for digit"
)]
const AS241_C: [f64; 8] = [
    1.423_437_110_749_683_577_34,
    4.630_337_846_156_545_295_9,
    5.769_497_221_460_691_405_5,
    3.647_848_324_763_204_605_04,
    1.270_458_252_452_368_382_58,
    2.417_807_251_774_506_117_7e-1,
    2.272_384_498_926_918_458_33e-2,
    7.745_450_142_783_414_076_4e-4,
];
/// Denominator for the tail with `r ≤ 5`.
#[expect(
    clippy::excessive_precision,
    reason = "the published AS 241 coefficients, kept digit for digit"
)]
const AS241_D: [f64; 8] = [
    1.0,
    2.053_191_626_637_758_821_87,
    1.676_384_830_183_803_849_4,
    6.897_673_349_851_000_045_5e-1,
    1.481_039_764_274_800_745_9e-1,
    1.519_866_656_361_645_719_66e-2,
    5.475_938_084_995_344_946e-4,
    1.050_750_071_644_416_843_24e-9,
];
/// Numerator for the far tail, `r > 5` (in `r − 5`).
#[expect(
    clippy::excessive_precision,
    reason = "the published AS 241 coefficients, kept digit for digit"
)]
const AS241_E: [f64; 8] = [
    6.657_904_643_501_103_777_2,
    5.463_784_911_164_114_369_9,
    1.784_826_539_917_291_335_8,
    2.965_605_718_285_048_912_3e-1,
    2.653_218_952_657_612_309_3e-2,
    1.242_660_947_388_078_438_6e-3,
    2.711_555_568_743_487_578_15e-5,
    2.010_334_399_292_288_132_65e-7,
];
/// Denominator for the far tail.
#[expect(
    clippy::excessive_precision,
    reason = "the published AS 241 coefficients, kept digit for digit"
)]
const AS241_F: [f64; 8] = [
    1.0,
    5.998_322_065_558_879_376_9e-1,
    1.369_298_809_227_358_053_1e-1,
    1.487_536_129_085_061_485_25e-2,
    7.868_691_311_456_132_591e-4,
    1.846_318_317_510_054_681_8e-5,
    1.421_511_758_316_445_888_7e-7,
    2.044_263_103_389_939_785_64e-15,
];

/// `Σ cᵢ rⁱ` by Horner's rule, `coefficients` lowest power first.
fn polynomial(coefficients: &[f64], r: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |acc, &c| acc * r + c)
}

/// A sample sorted once, ready to be resampled with replacement.
struct Resampler {
    sorted: Vec<f64>,
    size: u32,
}

impl Resampler {
    /// `x` must be non-empty and finite.
    fn new(x: &[f64]) -> Result<Self, StatsError> {
        let size = check_len(x.len(), "the sample's size")?;
        Ok(Self {
            sorted: sorted_copy(x),
            size,
        })
    }

    /// Draws one resample (its multiplicities into `counts`) and returns its statistic.
    fn draw(&self, rng: &mut ChaCha8Rng, counts: &mut [u32], statistic: Statistic) -> f64 {
        counts.fill(0);
        for _ in 0..self.size {
            counts[uniform_below(rng, self.size) as usize] += 1;
        }
        statistic.of_counts(&self.sorted, counts, self.sorted.len())
    }
}

/// An index uniform on `0..k` (`k ≥ 1`) by Lemire's multiply-and-reject method: exactly
/// uniform, one 32-bit word per draw except on the rare rejection.
fn uniform_below(rng: &mut ChaCha8Rng, k: u32) -> u32 {
    let bound = u64::from(k);
    let mut product = u64::from(rng.next_u32()) * bound;
    if (product as u32) < k {
        let threshold = k.wrapping_neg() % k;
        while (product as u32) < threshold {
            product = u64::from(rng.next_u32()) * bound;
        }
    }
    (product >> 32) as u32
}

/// The mean of the values at sorted positions `start..end` of the multiset holding `sorted[i]`
/// `counts[i]` times, added one by one in ascending order and clamped into the range of the
/// values added.
fn trimmed_mean_of_counts(sorted: &[f64], counts: &[u32], start: usize, end: usize) -> f64 {
    let mut sum = 0.0;
    let mut lowest = f64::INFINITY;
    let mut highest = f64::NEG_INFINITY;
    let mut position = 0;
    for (&value, &count) in sorted.iter().zip(counts) {
        let next = position + count as usize;
        let taken = next.min(end).saturating_sub(position.max(start));
        if taken > 0 {
            lowest = lowest.min(value);
            highest = highest.max(value);
            for _ in 0..taken {
                sum += value;
            }
        }
        position = next;
        if position >= end {
            break;
        }
    }
    let taken = (end - start) as f64;
    let mean = if sum.is_finite() {
        sum / taken
    } else {
        // Values near f64::MAX: divide first (rare; the result is clamped anyway).
        let mut scaled = 0.0;
        let mut position = 0;
        for (&value, &count) in sorted.iter().zip(counts) {
            let next = position + count as usize;
            for _ in 0..next.min(end).saturating_sub(position.max(start)) {
                scaled += value / taken;
            }
            position = next;
        }
        scaled
    };
    mean.clamp(lowest, highest)
}

/// The value at 0-based `position` of the sorted multiset holding `sorted[i]` `counts[i]`
/// times.
fn value_at_position(sorted: &[f64], counts: &[u32], position: usize) -> f64 {
    let mut seen = 0;
    for (&value, &count) in sorted.iter().zip(counts) {
        seen += count as usize;
        if seen > position {
            return value;
        }
    }
    // Unreachable for position < total; the largest value is the right answer at the end.
    sorted.last().copied().unwrap_or(0.0)
}

/// The type-7 quantile at level `p ∈ [0, 1]` of a non-empty ascending slice.
fn quantile_sorted(sorted: &[f64], p: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * p;
    let below = h.floor();
    let i = below as usize;
    match sorted.get(i + 1) {
        Some(&next) if h > below => {
            let value = sorted[i] + (h - below) * (next - sorted[i]);
            value.clamp(sorted[i], next)
        }
        _ => sorted[i.min(sorted.len() - 1)],
    }
}

/// Whether `n` choose `k` is at most `limit`, and if so its value.
fn binomial_at_most(n: usize, k: usize, limit: u64) -> Option<u64> {
    let k = k.min(n - k);
    let mut value = 1_u128;
    for i in 0..k {
        // value · (n − i) / (i + 1) is C(n, i + 1), an integer at every step.
        value = value * (n - i) as u128 / (i + 1) as u128;
        if value > u128::from(limit) {
            return None;
        }
    }
    u64::try_from(value).ok()
}

/// Advances `chosen` (ascending indices below `n`) to the next combination in lexicographic
/// order; false after the last.
fn next_combination(chosen: &mut [usize], n: usize) -> bool {
    let k = chosen.len();
    let Some(i) = (0..k).rev().find(|&i| chosen[i] < n - k + i) else {
        return false;
    };
    chosen[i] += 1;
    for j in i + 1..k {
        chosen[j] = chosen[j - 1] + 1;
    }
    true
}

/// Rejects an empty sample or a non-finite value.
fn check_sample(x: &[f64], what: &'static str) -> Result<(), StatsError> {
    if x.is_empty() {
        return Err(StatsError::Empty { what });
    }
    if let Some((index, &value)) = x.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(StatsError::NonFinite { what, index, value });
    }
    Ok(())
}

/// A sample size as the `u32` the index draws use.
fn check_len(len: usize, what: &'static str) -> Result<u32, StatsError> {
    u32::try_from(len).map_err(|_| StatsError::InvalidParameter {
        name: what,
        value: len.to_string(),
        expected: "at most 4 294 967 295 values",
    })
}

fn check_resamples(resamples: u32) -> Result<(), StatsError> {
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

fn check_confidence(confidence: f64) -> Result<(), StatsError> {
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
fn finite(value: f64, what: &'static str) -> Result<f64, StatsError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(StatsError::Overflow { what })
    }
}

/// A sorted copy (`total_cmp`: the sorted output is unique bit for bit).
fn sorted_copy(x: &[f64]) -> Vec<f64> {
    let mut sorted = x.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    sorted
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_match_the_materialised_resample() {
        let sorted = [1.0, 2.0, 2.5, 7.0, 9.0];
        let counts = [0, 3, 1, 0, 2];
        let materialised = [2.0, 2.0, 2.0, 2.5, 9.0, 9.0];
        for statistic in Statistic::ALL {
            assert_eq!(
                Ok(statistic.of_counts(&sorted, &counts, 6).to_bits()),
                statistic.of(&materialised).map(f64::to_bits),
                "{statistic:?}"
            );
        }
    }

    #[test]
    fn lemire_draw_covers_the_range_uniformly() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let mut seen = [0_u32; 7];
        for _ in 0..70_000 {
            seen[uniform_below(&mut rng, 7) as usize] += 1;
        }
        assert!(
            seen.iter().all(|&c| (9_500..10_500).contains(&c)),
            "{seen:?}"
        );
        assert_eq!(uniform_below(&mut rng, 1), 0);
    }

    #[test]
    fn combinations_are_all_enumerated() {
        let mut chosen = vec![0, 1, 2];
        let mut count = 1;
        while next_combination(&mut chosen, 6) {
            count += 1;
        }
        assert_eq!(count, 20);
        assert_eq!(binomial_at_most(6, 3, 20), Some(20));
        assert_eq!(binomial_at_most(6, 3, 19), None);
        assert_eq!(binomial_at_most(40, 20, 10_000), None);
        assert_eq!(binomial_at_most(5, 0, 1), Some(1));
    }

    #[test]
    fn quantile_interpolates_linearly() {
        let sorted = [1.0, 2.0, 4.0, 8.0];
        assert_eq!(quantile_sorted(&sorted, 0.0), 1.0);
        assert_eq!(quantile_sorted(&sorted, 1.0), 8.0);
        assert_eq!(quantile_sorted(&sorted, 0.5), 3.0);
        assert_eq!(quantile_sorted(&[5.0], 0.3), 5.0);
    }
}
