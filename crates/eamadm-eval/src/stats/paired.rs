//! Paired comparisons by seed: runs of one seed share their random streams (every stream is
//! keyed by the seed and its purpose, never by the method), so two methods' scores on one seed
//! form a pair. Here: the sign-flip permutation test of paired differences, its two one-sided
//! tests for equivalence (TOST), the percentile bootstrap of the paired differences' location,
//! and the exact sign test (McNemar's exact test on discordant pairs).
//!
//! # Formulas
//!
//! * **Sign-flip test** ([`SignFlipTest::p_value`]) of `H₀`: the differences `dᵢ` are
//!   symmetric about 0. The statistic is `T = θ(d)` (mean, median or IQM). Under `H₀` every
//!   sign vector `s ∈ {−1, +1}ⁿ` is equally likely; for the mean of at most
//!   [`EXACT_MAX_PAIRS`] differences all are counted by meet in the middle
//!   ([`SignFlipMeans`]), whatever `resamples`; for any statistic with
//!   `2ⁿ ≤ resamples` all are enumerated
//!   and `p_greater = #{s: θ(s·d) ≥ T} / 2ⁿ`, `p_less = #{s: θ(s·d) ≤ T} / 2ⁿ`; otherwise
//!   `B = resamples` random sign vectors are drawn and each count gets `+1` in numerator and
//!   denominator (Phipson & Smyth 2010). Two-sided: `min(1, 2 min(p_less, p_greater))`, as
//!   `scipy.stats.permutation_test(…, permutation_type="samples")` computes it. Comparisons
//!   allow a relative slack of `10⁻¹²` of `max |dᵢ|` (ties in the last bits count as ties).
//! * **TOST** ([`SignFlipTest::equivalence_p_value`], Schuirmann 1987) with margin `δ > 0`:
//!   `p_lower` tests `θ ≤ −δ` against `θ > −δ` (sign-flip, `greater`, on `d + δ`), `p_upper`
//!   tests `θ ≥ δ` against `θ < δ` (`less`, on `d − δ`); `p_TOST = max(p_lower, p_upper)`.
//!   Equivalence within `±δ` is shown at level `α` when `p_TOST ≤ α`.
//! * **Sign test** ([`sign_test`]): with `w` pairs favouring one side and `l` the other (ties
//!   dropped), `p = min(1, 2 P(X ≤ min(w, l)))` for `X ~ Binomial(w + l, ½)` — the exact
//!   two-sided `scipy.stats.binomtest(w, w + l, 0.5)`; on binary outcomes it is McNemar's
//!   exact test. Up to `w + l = 125` the tail is counted in integers, so `p` is the correctly
//!   rounded value of the rational `2 Σ_{i ≤ min(w, l)} C(w + l, i) / 2^(w + l)`; beyond, the
//!   binomial probabilities are summed from logarithms (relative error about `10⁻¹³`).
//!
//! # Random draws
//!
//! Monte-Carlo sign vectors: for `b = 1..=B`, one 32-bit word per block of 32 differences
//! (bit `i mod 32` of word `⌊i/32⌋` set flips `dᵢ`), from `ChaCha8Rng::seed_from_u64(seed)`.

use super::batch::BatchedSubsets;
use super::counted::CountedSample;
use super::location::Statistic;
use super::paired_mean::{EXACT_MAX_PAIRS, SignFlipMeans};
use super::words::Words;
use super::{Bootstrap, Interval, StatsError, check_resamples, check_sample, finite};

/// Which way a one-sided test looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Alternative {
    /// `θ ≠ 0`.
    TwoSided,
    /// `θ > 0`.
    Greater,
    /// `θ < 0`.
    Less,
}

/// Settings of the paired sign-flip permutation test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SignFlipTest {
    /// All `2ⁿ` sign vectors are enumerated when `2ⁿ ≤ resamples`; otherwise this many random
    /// ones are drawn (1 to [`MAX_RESAMPLES`](super::MAX_RESAMPLES)).
    pub resamples: u32,
    /// Seed of the `ChaCha8` generator of the random sign vectors.
    pub seed: u64,
}

impl Default for SignFlipTest {
    /// 10 000 resamples, seed 0.
    fn default() -> Self {
        Self {
            resamples: 10_000,
            seed: 0,
        }
    }
}

impl SignFlipTest {
    /// Checked settings: `resamples` in `1..=MAX_RESAMPLES`.
    ///
    /// # Errors
    /// [`StatsError::InvalidParameter`] for `resamples` out of range.
    pub fn new(resamples: u32, seed: u64) -> Result<Self, StatsError> {
        check_resamples(resamples)?;
        Ok(Self { resamples, seed })
    }

    /// Whether [`p_value`](Self::p_value) enumerates every sign vector for `n` differences of
    /// any statistic: when `2ⁿ ≤ resamples`. The mean is enumerated up to
    /// [`EXACT_MAX_PAIRS`] differences whatever `resamples` ([`is_exact_for`](Self::is_exact_for)).
    #[must_use]
    pub fn is_exact(&self, n: usize) -> bool {
        n < 32 && (1_u64 << n) <= u64::from(self.resamples)
    }

    /// Whether [`p_value`](Self::p_value) enumerates every sign vector for `n` differences and
    /// `statistic`: the mean up to [`EXACT_MAX_PAIRS`] (counted by meet in the middle,
    /// [`SignFlipMeans`]), any statistic when [`is_exact`](Self::is_exact).
    #[must_use]
    pub fn is_exact_for(&self, n: usize, statistic: Statistic) -> bool {
        (statistic == Statistic::Mean && n <= EXACT_MAX_PAIRS) || self.is_exact(n)
    }

    /// The p-value of the paired differences `differences` (method − competitor, one per seed)
    /// under sign flips, for `statistic` and `alternative`.
    ///
    /// # Errors
    /// [`StatsError::Empty`], [`StatsError::NonFinite`], [`StatsError::InvalidParameter`].
    pub fn p_value(
        &self,
        differences: &[f64],
        statistic: Statistic,
        alternative: Alternative,
    ) -> Result<f64, StatsError> {
        check_resamples(self.resamples)?;
        check_sample(differences, "differences")?;
        if statistic == Statistic::Mean && differences.len() <= EXACT_MAX_PAIRS {
            let means = SignFlipMeans::exact(differences)?;
            return Ok(match alternative {
                Alternative::Greater => means.p_greater(0.0),
                Alternative::Less => means.p_less(0.0),
                Alternative::TwoSided => means.p_two_sided(0.0),
            });
        }
        let observed = statistic.of(differences)?;
        let scale = differences.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let slack = 1e-12 * scale;
        let n = differences.len();
        let signed = SignedMagnitudes::new(differences);
        // Each sign vector picks one of the two slots of every difference (a count of 1);
        // the statistic walks the picked slots in ascending order, so nothing is sorted per
        // sign vector and the bits equal those of `statistic.of` on the flipped values. The
        // statistics are computed together afterwards, then compared with the observed value:
        // as bit masks over the slots for up to 32 differences, else counted over the slots
        // (per distinct value for integers).
        let exact = self.is_exact(n);
        let vectors = if exact {
            1_u64 << n
        } else {
            u64::from(self.resamples)
        };
        let replicates = if let Some(mut replicates) =
            BatchedSubsets::new(statistic, &signed.slots, n, vectors as usize)
        {
            let bit = |slot: usize| 1_u64 << slot;
            let unflipped = signed.kept.iter().fold(0, |mask, &slot| mask | bit(slot));
            // Flipping dᵢ moves its bit from its own slot to its negation's.
            let flip: Vec<u64> = signed
                .kept
                .iter()
                .zip(&signed.flipped)
                .map(|(&kept, &flipped)| bit(kept) | bit(flipped))
                .collect();
            self.for_each_sign_vector(n, exact, |words| {
                let mut mask = unflipped;
                for (i, &flip) in flip.iter().enumerate() {
                    let flipped = u64::from(words[i / 32] >> (i % 32) & 1);
                    mask ^= flip & flipped.wrapping_neg();
                }
                replicates.push(mask);
            });
            replicates.finish()
        } else {
            let sample = CountedSample::new(&signed.slots, n);
            let slot = |&position: &usize| sample.slot_of()[position];
            let kept: Vec<u32> = signed.kept.iter().map(slot).collect();
            let flipped: Vec<u32> = signed.flipped.iter().map(slot).collect();
            let mut counts = vec![0_u32; sample.slots()];
            let mut replicates = sample.replicates(statistic, n, vectors as usize);
            self.for_each_sign_vector(n, exact, |words| {
                counts.fill(0);
                for (i, (&kept, &flipped)) in kept.iter().zip(&flipped).enumerate() {
                    let flip = words[i / 32] >> (i % 32) & 1 == 1;
                    counts[(if flip { flipped } else { kept }) as usize] += 1;
                }
                replicates.push(&counts);
            });
            replicates.finish()
        };
        let (mut greater, mut less) = (0_u64, 0_u64);
        for t in replicates {
            let t = finite(t, statistic.name())?;
            if t >= observed - slack {
                greater += 1;
            }
            if t <= observed + slack {
                less += 1;
            }
        }
        let (p_greater, p_less) = if exact {
            (
                greater as f64 / vectors as f64,
                less as f64 / vectors as f64,
            )
        } else {
            let b = f64::from(self.resamples) + 1.0;
            ((greater as f64 + 1.0) / b, (less as f64 + 1.0) / b)
        };
        Ok(match alternative {
            Alternative::Greater => p_greater,
            Alternative::Less => p_less,
            Alternative::TwoSided => (2.0 * p_greater.min(p_less)).min(1.0),
        })
    }

    /// Calls `signs` with every sign vector of `n` differences (`exact`: `0..2ⁿ` in order,
    /// bit `i` flipping `dᵢ`), or with `resamples` random ones drawn in the documented order;
    /// a vector is given as words, bit `i mod 32` of word `⌊i/32⌋` flipping `dᵢ`.
    fn for_each_sign_vector(&self, n: usize, exact: bool, mut signs: impl FnMut(&[u32])) {
        if exact {
            // `is_exact` holds only for n < 32: one word.
            for vector in 0..1_u32 << n {
                signs(&[vector]);
            }
        } else {
            let mut rng = Words::seed_from_u64(self.seed);
            let mut words = vec![0_u32; n.div_ceil(32)];
            for _ in 0..self.resamples {
                for word in &mut words {
                    *word = rng.next_u32();
                }
                signs(&words);
            }
        }
    }

    /// The TOST p-value that the location `statistic` of the paired `differences` lies within
    /// `±margin`: `max(p_lower, p_upper)` (see [the module docs](self)).
    ///
    /// # Errors
    /// As [`p_value`](Self::p_value); [`StatsError::InvalidParameter`] for a margin that is
    /// not finite and positive.
    pub fn equivalence_p_value(
        &self,
        differences: &[f64],
        statistic: Statistic,
        margin: f64,
    ) -> Result<f64, StatsError> {
        if !(margin.is_finite() && margin > 0.0) {
            return Err(StatsError::InvalidParameter {
                name: "margin",
                value: margin.to_string(),
                expected: "a finite positive number",
            });
        }
        let shifted = |by: f64| -> Vec<f64> { differences.iter().map(|d| d + by).collect() };
        let lower = self.p_value(&shifted(margin), statistic, Alternative::Greater)?;
        let upper = self.p_value(&shifted(-margin), statistic, Alternative::Less)?;
        Ok(lower.max(upper))
    }
}

/// The values `±dᵢ` that sign flips can give, laid out once in ascending order (`f64::total_cmp`):
/// with `a₍₀₎ ≤ … ≤ a₍ₙ₋₁₎` the sorted magnitudes `|dᵢ|`, `slots = [−a₍ₙ₋₁₎, …, −a₍₀₎, a₍₀₎, …,
/// a₍ₙ₋₁₎]`. A sign vector's values are then a multiset over `slots` with one count per
/// difference, and the location statistic of those counts is the statistic of the flipped
/// sample bit for bit (values equal under `total_cmp` are equal bit for bit, so the sorted
/// flipped sample is exactly the counted slots in order).
struct SignedMagnitudes {
    /// The `2n` signed magnitudes, ascending.
    slots: Vec<f64>,
    /// `kept[i]`: the slot holding `dᵢ` itself.
    kept: Vec<usize>,
    /// `flipped[i]`: the slot holding `−dᵢ`.
    flipped: Vec<usize>,
}

impl SignedMagnitudes {
    fn new(differences: &[f64]) -> Self {
        let n = differences.len();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| differences[a].abs().total_cmp(&differences[b].abs()));
        let mut slots = vec![0.0; 2 * n];
        let mut kept = vec![0; n];
        let mut flipped = vec![0; n];
        for (rank, &i) in order.iter().enumerate() {
            let magnitude = differences[i].abs();
            let (negative, positive) = (n - 1 - rank, n + rank);
            slots[negative] = -magnitude;
            slots[positive] = magnitude;
            // The sign bit decides (−0.0 sits in the negative slot, as `total_cmp` orders it).
            if differences[i].is_sign_negative() {
                (kept[i], flipped[i]) = (negative, positive);
            } else {
                (kept[i], flipped[i]) = (positive, negative);
            }
        }
        Self {
            slots,
            kept,
            flipped,
        }
    }
}

/// The percentile bootstrap interval of `statistic` of the paired differences `x[i] − y[i]`
/// (resampling seeds, each seed's pair together).
///
/// # Errors
/// [`StatsError::InvalidParameter`] when `x` and `y` differ in length; as
/// [`Bootstrap::interval`] otherwise.
pub fn paired_difference(
    bootstrap: &Bootstrap,
    x: &[f64],
    y: &[f64],
    statistic: Statistic,
) -> Result<Interval, StatsError> {
    bootstrap.interval(&differences(x, y)?, statistic)
}

/// The paired differences `x[i] − y[i]`.
///
/// # Errors
/// [`StatsError::InvalidParameter`] when `x` and `y` differ in length; [`StatsError::Empty`]
/// or [`StatsError::NonFinite`] for bad values.
pub fn differences(x: &[f64], y: &[f64]) -> Result<Vec<f64>, StatsError> {
    check_sample(x, "x")?;
    check_sample(y, "y")?;
    if x.len() != y.len() {
        return Err(StatsError::InvalidParameter {
            name: "y's length",
            value: y.len().to_string(),
            expected: "as many values as x: one per seed, in the same seed order",
        });
    }
    Ok(x.iter().zip(y).map(|(a, b)| a - b).collect())
}

/// The exact two-sided sign test of `wins` against `losses` (ties dropped): `1` when both are
/// 0. On paired binary outcomes (reached / did not), `wins` and `losses` are the discordant
/// pairs and this is McNemar's exact test.
#[must_use]
pub fn sign_test(wins: u64, losses: u64) -> f64 {
    let n = wins + losses;
    if n == 0 {
        return 1.0;
    }
    let k = wins.min(losses);
    if let Some(p) = sign_test_by_counting(n, k) {
        return p;
    }
    // P(X ≤ k) for X ~ Binomial(n, ½), summing pmf(i) = C(n, i) / 2ⁿ from logarithms.
    let ln_half_n = n as f64 * std::f64::consts::LN_2;
    let mut ln_choose = 0.0_f64;
    let mut tail = 0.0_f64;
    for i in 0..=k {
        if i > 0 {
            ln_choose += ((n - i + 1) as f64).ln() - (i as f64).ln();
        }
        tail += (ln_choose - ln_half_n).exp();
    }
    (2.0 * tail).min(1.0)
}

/// `min(1, 2 Σ_{i ≤ k} C(n, i) / 2ⁿ)` counted in integers, so the p-value of the exact test is
/// the correctly rounded `f64` of its rational value (as `scipy.stats.binomtest` gives it:
/// `binomtest(3, 3).pvalue` is exactly `0.25`, where summing the pmf from logarithms gave
/// `0.25000000000000006`). `None` above `n = 125`, where a count can overflow `u128`: the
/// caller then sums from logarithms.
fn sign_test_by_counting(n: u64, k: u64) -> Option<f64> {
    let n_bits = u32::try_from(n).ok().filter(|&bits| bits <= 125)?;
    let mut choose: u128 = 1;
    let mut tail: u128 = 1;
    for i in 1..=u128::from(k) {
        // C(n, i) = C(n, i − 1) (n − i + 1) / i, exact: i divides the product.
        choose = choose.checked_mul(u128::from(n) - i + 1)? / i;
        tail = tail.checked_add(choose)?;
    }
    let doubled = tail.checked_mul(2)?;
    // One rounding (the conversion); dividing by a power of two is exact.
    Some((doubled as f64 / (1_u128 << n_bits) as f64).min(1.0))
}
