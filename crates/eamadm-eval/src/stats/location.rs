//! Location statistics over seeds (mean, median, interquartile mean), the sample standard
//! deviation, and the type-7 quantile; each computed from the sorted sample, so symmetric bit
//! for bit (see [the module docs](super)).

use serde::{Deserialize, Serialize};

use super::{StatsError, check_sample, finite, sorted_copy};

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
    pub(crate) fn of_counts(self, sorted: &[f64], counts: &[u32], total: usize) -> f64 {
        let trimmed_mean = |start, end| trimmed_mean_of_counts(sorted, counts, start, end);
        match self {
            Self::Mean => trimmed_mean(0, total),
            Self::Iqm => {
                let k = total / 4;
                trimmed_mean(k, total - k)
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

/// The mean of the values at sorted positions `start..end` of the multiset holding `sorted[i]`
/// `counts[i]` times, added one by one in ascending order and clamped into the range of the
/// values added. `sorted` is ascending, so that range is the first and the last value taken
/// (no min/max per value; the hot loop of the bootstrap is the chain of additions alone).
pub(crate) fn trimmed_mean_of_counts(
    sorted: &[f64],
    counts: &[u32],
    start: usize,
    end: usize,
) -> f64 {
    let mut sum = 0.0;
    let mut lowest = None;
    let mut highest = f64::NEG_INFINITY;
    let mut position = 0;
    for (&value, &count) in sorted.iter().zip(counts) {
        let next = position + count as usize;
        // `position < end` here (the loop stops at `end`), so this value is taken at least
        // once exactly when its positions reach past `start`.
        if next > start && count > 0 {
            lowest.get_or_insert(value);
            highest = value;
            for _ in position.max(start)..next.min(end) {
                sum += value;
            }
            if next >= end {
                break;
            }
        }
        position = next;
    }
    let lowest = lowest.unwrap_or(highest);
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
pub(crate) fn value_at_position(sorted: &[f64], counts: &[u32], position: usize) -> f64 {
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
pub(crate) fn quantile_sorted(sorted: &[f64], p: f64) -> f64 {
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

/// The type-7 quantile at level `p ∈ [0, 1]` of a non-empty slice, by selection in `O(len)`
/// instead of a sort (`values` is reordered). The two order statistics it interpolates are
/// unique values under `f64::total_cmp`, so the result equals [`quantile_sorted`]'s bit for
/// bit whatever the selection algorithm.
pub(crate) fn quantile_unsorted(values: &mut [f64], p: f64) -> f64 {
    let h = (values.len() - 1) as f64 * p;
    let below = h.floor();
    let i = (below as usize).min(values.len() - 1);
    let (_, &mut at, above) = values.select_nth_unstable_by(i, f64::total_cmp);
    match above.iter().copied().min_by(f64::total_cmp) {
        Some(next) if h > below => (at + (h - below) * (next - at)).clamp(at, next),
        _ => at,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The implementation before the first and last value replaced min/max per value, kept as
    /// the oracle: the mean of the values at sorted positions `start..end` of the multiset holding `sorted[i]`
    /// `counts[i]` times, added one by one in ascending order and clamped into the range of the
    /// values added.
    fn trimmed_mean_of_counts_reference(
        sorted: &[f64],
        counts: &[u32],
        start: usize,
        end: usize,
    ) -> f64 {
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

    proptest! {
        /// The walk gives the reference's bits for every multiset and trimmed range, signed
        /// zeros and ties included.
        #[test]
        fn walk_equals_the_reference_bit_for_bit(
            values in prop::collection::vec(prop_oneof![
                Just(-0.0), Just(0.0), Just(0.1), Just(-0.3), -1e3_f64..1e3,
                Just(f64::MAX), Just(-f64::MAX)
            ], 1..40),
            draws in prop::collection::vec(0_usize..1000, 1..64),
            trim in 0_usize..20,
        ) {
            let mut sorted = values;
            sorted.sort_unstable_by(f64::total_cmp);
            let total = draws.len();
            let mut counts = vec![0_u32; sorted.len()];
            for d in &draws {
                counts[d % sorted.len()] += 1;
            }
            let start = trim.min((total - 1) / 2);
            let end = total - start;
            prop_assert_eq!(
                trimmed_mean_of_counts(&sorted, &counts, start, end).to_bits(),
                trimmed_mean_of_counts_reference(&sorted, &counts, start, end).to_bits()
            );
        }
    }

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
    fn selection_gives_the_sorted_quantile_bit_for_bit() {
        let values = [5.5, -1.0, 3.25, 9.0, 0.0, 3.25, 7.75, -4.5, 2.0];
        let mut sorted = values;
        sorted.sort_unstable_by(f64::total_cmp);
        for p in [0.0, 0.025, 0.1, 0.25, 0.5, 0.8, 0.975, 1.0] {
            let mut scratch = values;
            assert_eq!(
                quantile_unsorted(&mut scratch, p).to_bits(),
                quantile_sorted(&sorted, p).to_bits(),
                "{p}"
            );
        }
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
