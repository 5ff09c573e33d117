//! The mean of paired differences judged from its exact sign-flip distribution: the sign-flip
//! p-values, the confidence interval that inverts them, the test that the mean lies beyond an
//! equivalence margin and the test that it lies within it — one distribution, so the interval
//! and every test agree, and no resampling where the distribution can be enumerated.
//!
//! # Formulas
//!
//! With paired differences `d₁ … dₙ` (method − competitor, one per seed) the statistic is
//! their mean `d̄`. A sign vector flips the subset `F` of the differences; the flipped mean is
//! at least the observed one exactly when `Σ_{i∈F} dᵢ ≤ 0`. So, testing the location `c`
//! (the differences `dᵢ − c`),
//!
//! * `p_greater(c) = #{F : Σ_{i∈F} (dᵢ − c) ≤ 0} / 2ⁿ` (evidence that the mean exceeds `c`),
//! * `p_less(c) = #{F : Σ_{i∈F} (dᵢ − c) ≥ 0} / 2ⁿ` (evidence that it is below `c`),
//!
//! the empty `F` (the observed signs) counting in both; `p_greater(0)` and `p_less(0)` are the
//! sign-flip test of [`SignFlipTest`](super::SignFlipTest) with the mean, and two-sided
//! `min(1, 2 min(p_greater, p_less))` as `scipy.stats.permutation_test(…,
//! permutation_type="samples")` gives it. Sums short of 0 by at most `n/2 · 10⁻¹² · max |dᵢ −
//! c|` count as 0 (the crate's tie rule on the mean, `10⁻¹² · max |value|`, written for sums).
//!
//! **The interval** inverts these tests. `Σ_{i∈F} (dᵢ − c) ≤ 0` says that the mean of the
//! subset, `M_F = (1/|F|) Σ_{i∈F} dᵢ`, is at most `c`; so with `M₍₁₎ ≤ … ≤ M₍₂ⁿ₋₁₎` the
//! means of the `2ⁿ − 1` non-empty subsets and `K = ⌊(α/2) 2ⁿ⌋` (`α = 1 − confidence`), the
//! locations not rejected by either one-sided test at `α/2` are `[M₍K₎, M₍₂ⁿ₋K₎]`: Hartigan's
//! subsample means as typical values (Hartigan, *Using subsample values as typical values*,
//! JASA 64, 1969), the confidence set of Fisher's paired randomisation test. It holds the
//! centre of symmetry with probability at least `1 − α` when the differences are symmetric
//! about it — the assumption of the sign-flip test itself. With `K = 0` (fewer than 6 pairs at
//! 95 %) no location can be rejected and the interval is unbounded ([`None`] ends).
//!
//! **Margins.** For a margin `δ > 0`, [`beyond_margin`](SignFlipMeans::beyond_margin) is
//! `min(1, 2 min(p_less(−δ), p_greater(δ)))`: at most `α` exactly when the `1 − α` interval
//! lies wholly below `−δ` or wholly above `δ`. [`within_margin`](SignFlipMeans::within_margin)
//! is `min(1, 2 max(p_greater(−δ), p_less(δ)))`: at most `α` exactly when the `1 − α` interval
//! lies inside `(−δ, δ)` — the two one-sided tests of Schuirmann's TOST each at `α/2` (the
//! 95 % interval inside the margin, not TOST's usual 90 %). With `δ = 0` the first is the
//! two-sided test of `d̄ = 0`.
//!
//! # Enumeration, meet in the middle
//!
//! Up to [`EXACT_MAX_PAIRS`] differences all `2ⁿ` subsets count, without visiting them: the
//! differences are split into two halves; each half's `2^(n/2)` subset sums are listed (each
//! from a smaller one by one addition) and sorted within each subset size; a count over all
//! `2ⁿ` subsets is then, for every pair of sizes `(a, b)`, a two-pointer walk over the two
//! sorted lists counting the pairs with `x + y ≤ c (a + b)` — `O(n 2^(n/2))` per count
//! (about 22 000 steps at `n = 20` instead of 2²⁰ sign vectors). An interval end is found by
//! bisecting `c` until at most 512 subset means lie between the bounds, which are then listed
//! and the one of the wanted rank taken.
//!
//! Beyond [`EXACT_MAX_PAIRS`], [`SignFlipMeans::drawn`] takes `B` random sign vectors (drawn as
//! [`SignFlipTest`](super::SignFlipTest) draws them: one 32-bit word of
//! `ChaCha8Rng::seed_from_u64(seed)` per block of 32 differences, bit `i mod 32` set flips
//! `dᵢ`): each count gets `+1` in numerator and denominator (Phipson & Smyth 2010), and the
//! interval ends are the order statistics `K = ⌊(α/2)(B + 1)⌋` from either end of the `B`
//! subset means (Hartigan's random subsets). [`monte_carlo_se`](SignFlipMeans::monte_carlo_se)
//! gives a p-value's Monte-Carlo standard error `√(p(1 − p)/B)`.

use super::words::Words;
use super::{StatsError, check_confidence, check_resamples, check_sample, mean};

/// Up to this many paired differences the sign-flip distribution of their mean is enumerated
/// in full (`2²⁴ ≈ 1.7 · 10⁷` sign vectors, counted by meet in the middle).
pub const EXACT_MAX_PAIRS: usize = 24;

/// The most subset means listed at once when an interval end is located.
const LISTED: u64 = 512;

/// The relative tie tolerance of the crate's tests (see [the module docs](self)).
const TIE: f64 = 1e-12;

/// The sign-flip distribution of the mean of paired differences, enumerated or drawn.
#[derive(Debug, Clone)]
pub struct SignFlipMeans {
    n: usize,
    /// The mean of the differences.
    mean: f64,
    /// The smallest and largest difference.
    range: (f64, f64),
    /// The differences, for the tie tolerance at a location.
    differences: Vec<f64>,
    kind: Kind,
}

#[derive(Debug, Clone)]
enum Kind {
    /// Every subset, by meet in the middle: the subset sums of each half, sorted, by size;
    /// and the same for the negated differences (the upper interval end).
    Exact { halves: Halves, negated: Halves },
    /// `B` random subsets: each one's sum and size, and the non-empty subsets' means sorted.
    Drawn {
        subsets: Vec<(f64, u32)>,
        means: Vec<f64>,
    },
}

/// The two halves' subset sums, by subset size, each list ascending.
#[derive(Debug, Clone)]
struct Halves {
    first: Vec<Vec<f64>>,
    second: Vec<Vec<f64>>,
}

impl Halves {
    fn new(values: &[f64]) -> Self {
        let (first, second) = values.split_at(values.len() / 2);
        Self {
            first: subset_sums_by_size(first),
            second: subset_sums_by_size(second),
        }
    }

    /// `#{F : Σ_F vᵢ − c |F| ≤ tol}` over every subset `F` (empty included).
    fn count_at_most(&self, c: f64, tol: f64) -> u64 {
        let mut count = 0;
        for (a, xs) in self.first.iter().enumerate() {
            for (b, ys) in self.second.iter().enumerate() {
                let t = c * (a + b) as f64 + tol;
                // For x ascending, the ys with x + y ≤ t are a prefix that only shrinks.
                let mut j = ys.len();
                for &x in xs {
                    while j > 0 && x + ys[j - 1] > t {
                        j -= 1;
                    }
                    count += j as u64;
                }
            }
        }
        count
    }

    /// `#{F : Σ_F vᵢ − c |F| ≥ −tol}` over every subset `F` (empty included).
    fn count_at_least(&self, c: f64, tol: f64) -> u64 {
        let mut count = 0;
        for (a, xs) in self.first.iter().enumerate() {
            for (b, ys) in self.second.iter().enumerate() {
                let t = c * (a + b) as f64 - tol;
                // For x ascending, the ys with x + y ≥ t are a suffix that only grows.
                let mut j = ys.len();
                for &x in xs {
                    while j > 0 && x + ys[j - 1] >= t {
                        j -= 1;
                    }
                    count += (ys.len() - j) as u64;
                }
            }
        }
        count
    }

    /// The means of the non-empty subsets with a mean in `(low, high]`, unsorted.
    fn means_between(&self, low: f64, high: f64) -> Vec<f64> {
        let mut means = Vec::new();
        for (a, xs) in self.first.iter().enumerate() {
            for (b, ys) in self.second.iter().enumerate() {
                let size = a + b;
                if size == 0 {
                    continue;
                }
                let k = size as f64;
                let (from, to) = (low * k, high * k);
                for &x in xs {
                    let start = ys.partition_point(|&y| x + y <= from);
                    for &y in ys[start..].iter().take_while(|&&y| x + y <= to) {
                        means.push((x + y) / k);
                    }
                }
            }
        }
        means
    }
}

/// The subset sums of `values` grouped by subset size, each group ascending (`total_cmp`).
/// Each sum is a smaller subset's sum plus one value: the subset without its lowest member.
fn subset_sums_by_size(values: &[f64]) -> Vec<Vec<f64>> {
    let subsets = 1_usize << values.len();
    let mut sums = vec![0.0_f64; subsets];
    let mut by_size: Vec<Vec<f64>> = vec![Vec::new(); values.len() + 1];
    by_size[0].push(0.0);
    for mask in 1..subsets {
        let lowest = mask.trailing_zeros() as usize;
        sums[mask] = sums[mask & (mask - 1)] + values[lowest];
        by_size[mask.count_ones() as usize].push(sums[mask]);
    }
    for group in &mut by_size {
        group.sort_unstable_by(f64::total_cmp);
    }
    by_size
}

impl SignFlipMeans {
    /// The exact distribution (every sign vector) when `differences` has at most
    /// [`EXACT_MAX_PAIRS`] values, else `resamples` random sign vectors drawn from `seed`
    /// ([`drawn`](Self::drawn)).
    ///
    /// # Errors
    /// [`StatsError::Empty`], [`StatsError::NonFinite`]; [`StatsError::InvalidParameter`] for
    /// `resamples` out of range when the distribution is drawn.
    pub fn new(differences: &[f64], resamples: u32, seed: u64) -> Result<Self, StatsError> {
        if differences.len() <= EXACT_MAX_PAIRS {
            Self::exact(differences)
        } else {
            Self::drawn(differences, resamples, seed)
        }
    }

    /// The exact distribution of at most [`EXACT_MAX_PAIRS`] differences.
    ///
    /// # Errors
    /// [`StatsError::Empty`], [`StatsError::NonFinite`]; [`StatsError::InvalidParameter`] for
    /// more than [`EXACT_MAX_PAIRS`] differences.
    pub fn exact(differences: &[f64]) -> Result<Self, StatsError> {
        check_sample(differences, "differences")?;
        if differences.len() > EXACT_MAX_PAIRS {
            return Err(StatsError::InvalidParameter {
                name: "differences' length",
                value: differences.len().to_string(),
                expected: "at most 24 differences to enumerate (draw them beyond)",
            });
        }
        let negated: Vec<f64> = differences.iter().map(|d| -d).collect();
        Self::with_kind(
            differences,
            Kind::Exact {
                halves: Halves::new(differences),
                negated: Halves::new(&negated),
            },
        )
    }

    /// `resamples` random sign vectors drawn from `seed` (see [the module docs](self)), for any
    /// number of differences.
    ///
    /// # Errors
    /// [`StatsError::Empty`], [`StatsError::NonFinite`], [`StatsError::InvalidParameter`] for
    /// `resamples` out of range.
    pub fn drawn(differences: &[f64], resamples: u32, seed: u64) -> Result<Self, StatsError> {
        check_sample(differences, "differences")?;
        check_resamples(resamples)?;
        let mut rng = Words::seed_from_u64(seed);
        let mut words = vec![0_u32; differences.len().div_ceil(32)];
        let mut subsets = Vec::with_capacity(resamples as usize);
        for _ in 0..resamples {
            for word in &mut words {
                *word = rng.next_u32();
            }
            let (mut sum, mut size) = (0.0, 0_u32);
            for (i, d) in differences.iter().enumerate() {
                if words[i / 32] >> (i % 32) & 1 == 1 {
                    sum += d;
                    size += 1;
                }
            }
            subsets.push((sum, size));
        }
        let mut means: Vec<f64> = subsets
            .iter()
            .filter(|&&(_, size)| size > 0)
            .map(|&(sum, size)| sum / f64::from(size))
            .collect();
        means.sort_unstable_by(f64::total_cmp);
        Self::with_kind(differences, Kind::Drawn { subsets, means })
    }

    fn with_kind(differences: &[f64], kind: Kind) -> Result<Self, StatsError> {
        let low = differences.iter().copied().fold(f64::INFINITY, f64::min);
        let high = differences
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        Ok(Self {
            n: differences.len(),
            mean: mean(differences)?,
            range: (low, high),
            differences: differences.to_vec(),
            kind,
        })
    }

    /// The number of paired differences.
    #[must_use]
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false: a distribution has at least one difference.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The mean of the differences (added in ascending order, as [`mean`]).
    #[must_use]
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// Whether every sign vector is counted (else they are drawn).
    #[must_use]
    pub fn is_exact(&self) -> bool {
        matches!(self.kind, Kind::Exact { .. })
    }

    /// The sign vectors counted: `2ⁿ` when exact, else the number drawn.
    #[must_use]
    pub fn sign_vectors(&self) -> u64 {
        match &self.kind {
            Kind::Exact { .. } => 1_u64 << self.n,
            Kind::Drawn { subsets, .. } => subsets.len() as u64,
        }
    }

    /// The tie tolerance on a subset sum at location `c`.
    fn tolerance(&self, c: f64) -> f64 {
        let scale = self
            .differences
            .iter()
            .fold(0.0_f64, |m, d| m.max((d - c).abs()));
        0.5 * self.n as f64 * TIE * scale
    }

    /// A count over the sign vectors as a p-value: exact, or `(b + 1)/(B + 1)` when drawn.
    fn p_of(&self, count: u64) -> f64 {
        match &self.kind {
            Kind::Exact { .. } => count as f64 / (1_u64 << self.n) as f64,
            Kind::Drawn { subsets, .. } => (count + 1) as f64 / (subsets.len() + 1) as f64,
        }
    }

    /// `p_greater(c)`: the one-sided p-value of "the mean exceeds `c`" (see [the module
    /// docs](self)).
    #[must_use]
    pub fn p_greater(&self, c: f64) -> f64 {
        let tol = self.tolerance(c);
        let count = match &self.kind {
            Kind::Exact { halves, .. } => halves.count_at_most(c, tol),
            Kind::Drawn { subsets, .. } => subsets
                .iter()
                .filter(|&&(sum, size)| sum - c * f64::from(size) <= tol)
                .count() as u64,
        };
        self.p_of(count)
    }

    /// `p_less(c)`: the one-sided p-value of "the mean is below `c`".
    #[must_use]
    pub fn p_less(&self, c: f64) -> f64 {
        let tol = self.tolerance(c);
        let count = match &self.kind {
            Kind::Exact { halves, .. } => halves.count_at_least(c, tol),
            Kind::Drawn { subsets, .. } => subsets
                .iter()
                .filter(|&&(sum, size)| sum - c * f64::from(size) >= -tol)
                .count() as u64,
        };
        self.p_of(count)
    }

    /// The two-sided p-value of "the mean is `c`": `min(1, 2 min(p_greater, p_less))`.
    #[must_use]
    pub fn p_two_sided(&self, c: f64) -> f64 {
        (2.0 * self.p_greater(c).min(self.p_less(c))).min(1.0)
    }

    /// The p-value that the mean lies beyond `±margin` on one side (`margin ≥ 0`; with 0, the
    /// two-sided test of 0): at most `α` exactly when the `1 − α` [`interval`](Self::interval)
    /// lies wholly below `−margin` or wholly above `margin`.
    ///
    /// # Errors
    /// [`StatsError::InvalidParameter`] for a margin that is negative or not finite.
    pub fn beyond_margin(&self, margin: f64) -> Result<f64, StatsError> {
        check_margin(margin, "a finite number ≥ 0")?;
        Ok((2.0 * self.p_less(-margin).min(self.p_greater(margin))).min(1.0))
    }

    /// The p-value that the mean lies within `(−margin, margin)` (`margin > 0`): at most `α`
    /// exactly when the `1 − α` [`interval`](Self::interval) lies inside the margin (two
    /// one-sided tests, each at `α/2`).
    ///
    /// # Errors
    /// [`StatsError::InvalidParameter`] for a margin that is not finite and positive.
    pub fn within_margin(&self, margin: f64) -> Result<f64, StatsError> {
        if margin == 0.0 {
            return Err(StatsError::InvalidParameter {
                name: "margin",
                value: "0".to_owned(),
                expected: "a finite positive number",
            });
        }
        check_margin(margin, "a finite positive number")?;
        Ok((2.0 * self.p_greater(-margin).max(self.p_less(margin))).min(1.0))
    }

    /// The Monte-Carlo standard error `√(p(1 − p)/B)` of a p-value `p` of this distribution:
    /// `None` when it is exact.
    #[must_use]
    pub fn monte_carlo_se(&self, p: f64) -> Option<f64> {
        match &self.kind {
            Kind::Exact { .. } => None,
            Kind::Drawn { subsets, .. } => {
                let p = p.clamp(0.0, 1.0);
                Some((p * (1.0 - p) / subsets.len() as f64).sqrt())
            }
        }
    }

    /// The `confidence` interval of the mean that inverts the sign-flip tests (see [the
    /// module docs](self)); an end is `None` when no location on that side can be rejected
    /// (too few differences for the level).
    ///
    /// # Errors
    /// [`StatsError::InvalidParameter`] for a confidence outside `(0, 1)`.
    pub fn interval(&self, confidence: f64) -> Result<(Option<f64>, Option<f64>), StatsError> {
        check_confidence(confidence)?;
        let tail = (1.0 - confidence) / 2.0;
        Ok(match &self.kind {
            Kind::Exact { halves, negated } => {
                // `⌊tail · 2ⁿ⌋`; the product is exact (a power of two).
                let rank = (tail * (1_u64 << self.n) as f64).floor() as u64;
                if rank == 0 {
                    (None, None)
                } else {
                    let (low, high) = self.range;
                    (
                        Some(smallest_mean(halves, rank, low, high)),
                        Some(-smallest_mean(negated, rank, -high, -low)),
                    )
                }
            }
            Kind::Drawn { means, subsets } => {
                let rank = (tail * (subsets.len() + 1) as f64).floor() as usize;
                if rank == 0 || rank > means.len() {
                    (None, None)
                } else {
                    (Some(means[rank - 1]), Some(means[means.len() - rank]))
                }
            }
        })
    }
}

/// Rejects a margin that is negative or not finite.
fn check_margin(margin: f64, expected: &'static str) -> Result<(), StatsError> {
    if margin.is_finite() && margin >= 0.0 {
        Ok(())
    } else {
        Err(StatsError::InvalidParameter {
            name: "margin",
            value: margin.to_string(),
            expected,
        })
    }
}

/// The `rank`-th smallest mean (`rank ≥ 1`) of the non-empty subsets of the values whose
/// halves are `halves`, all of which lie in `[low, high]`.
fn smallest_mean(halves: &Halves, rank: u64, low: f64, high: f64) -> f64 {
    // Non-empty subsets with a mean at most `c` (the empty subset always counts).
    let at_most = |c: f64| halves.count_at_most(c, 0.0) - 1;
    if at_most(low) >= rank {
        return low;
    }
    // Invariant: at_most(lo) < rank ≤ at_most(hi).
    let (mut lo, mut hi) = (low, high);
    let (mut below, mut up_to_hi) = (at_most(lo), at_most(high));
    loop {
        if up_to_hi - below <= LISTED {
            let mut means = halves.means_between(lo, hi);
            means.sort_unstable_by(f64::total_cmp);
            let index = (rank - below - 1) as usize;
            // Rounding may list a mean twice or miss one at a bound; the bound then stands.
            return means.get(index).map_or(hi, |m| m.clamp(lo, hi));
        }
        // Halving the order of the floats between the bounds, not their distance: at most 64
        // steps, even when many subset means tie at the wanted one (next to 0 the floats are
        // dense).
        let (lo_key, hi_key) = (order_key(lo), order_key(hi));
        if hi_key - lo_key <= 1 {
            // Adjacent floats: the wanted mean is `hi` to the last bit.
            return hi;
        }
        let mid = from_order_key(lo_key + (hi_key - lo_key) / 2);
        let count = at_most(mid);
        if count >= rank {
            hi = mid;
            up_to_hi = count;
        } else {
            lo = mid;
            below = count;
        }
    }
}

/// A key whose unsigned order is the order of the finite floats (`−0.0` just below `+0.0`).
fn order_key(x: f64) -> u64 {
    let bits = x.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | 1 << 63
    }
}

/// The float of an [`order_key`].
fn from_order_key(key: u64) -> f64 {
    f64::from_bits(if key >> 63 == 1 {
        key & !(1 << 63)
    } else {
        !key
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every subset's sum and size, visited one by one (the oracle).
    fn brute(d: &[f64]) -> Vec<(f64, usize)> {
        (0..1_usize << d.len())
            .map(|mask| {
                let members: Vec<f64> = (0..d.len())
                    .filter(|i| mask >> i & 1 == 1)
                    .map(|i| d[i])
                    .collect();
                (members.iter().sum(), members.len())
            })
            .collect()
    }

    #[test]
    fn counts_equal_visiting_every_subset() {
        let d = [3.0, -1.0, 4.0, -1.5, 5.0, -9.0, 2.0, 6.0, -5.0, 3.5, 0.0];
        let exact = SignFlipMeans::exact(&d).unwrap();
        let all = brute(&d);
        for c in [-9.5, -2.0, -0.5, 0.0, 0.7, 1.0, 3.25, 6.5] {
            let le = all.iter().filter(|(s, k)| s - c * *k as f64 <= 0.0).count();
            let ge = all.iter().filter(|(s, k)| s - c * *k as f64 >= 0.0).count();
            let Kind::Exact { halves, .. } = &exact.kind else {
                unreachable!()
            };
            assert_eq!(halves.count_at_most(c, 0.0), le as u64, "c = {c}");
            assert_eq!(halves.count_at_least(c, 0.0), ge as u64, "c = {c}");
        }
    }

    #[test]
    fn interval_ends_are_the_ranked_subset_means() {
        let d = [
            1.0, -2.5, 7.0, 0.5, 3.0, -1.0, 4.5, 2.0, 9.0, -3.0, 6.0, 0.25,
        ];
        let exact = SignFlipMeans::exact(&d).unwrap();
        let mut means: Vec<f64> = brute(&d)
            .into_iter()
            .filter(|&(_, k)| k > 0)
            .map(|(s, k)| s / k as f64)
            .collect();
        means.sort_unstable_by(f64::total_cmp);
        for confidence in [0.5, 0.9, 0.95, 0.99] {
            let rank = ((1.0 - confidence) / 2.0 * 4096.0_f64).floor() as usize;
            let (low, high) = exact.interval(confidence).unwrap();
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
            assert!(close(low.unwrap(), means[rank - 1]), "{confidence}");
            assert!(
                close(high.unwrap(), means[means.len() - rank]),
                "{confidence}"
            );
        }
        // Five pairs cannot reach 95 %: the smallest one-sided p is 1/32.
        let five = SignFlipMeans::exact(&d[..5]).unwrap();
        assert_eq!(five.interval(0.95).unwrap(), (None, None));
    }
}
