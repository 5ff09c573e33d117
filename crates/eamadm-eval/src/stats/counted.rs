//! A location statistic of many multisets of one sorted sample, each given by its counts, bit
//! for bit what [`Statistic::of_counts`] gives for each: the resamples of the bootstrap, the
//! splits of the permutation test and the sign vectors of the sign-flip test.
//!
//! **Integer samples** (step counts, and differences of them) take a shortcut. When every value
//! is an integer and `max |value| · (values in a multiset) < 2⁵³`, every partial sum of a
//! multiset's values is an integer below 2⁵³ in magnitude, so every `f64` addition in
//! [`trimmed_mean_of_counts`](super::location::trimmed_mean_of_counts) is exact: its sum is the
//! exact integer sum (`+0.0` when it is zero, since the sum starts at `+0.0`) whatever the order
//! of addition. The values are then counted per *distinct* value (a position → slot table), and
//! a trimmed sum is `Σ value × (its copies inside the trimmed window)` in `i64`, `O(distinct)`
//! per multiset instead of `O(values)`. The clamp of the one-at-a-time definition is then a
//! no-op (the exact mean lies between the smallest and the largest value taken, and rounding to
//! nearest is monotone), and the median reads the same value, so the bits are equal; the law
//! `counted_equals_one_at_a_time` checks it. Any other sample is counted per position and
//! computed by [`BatchedStatistic`].

use super::batch::BatchedStatistic;
use super::location::Statistic;

/// `2⁵³`: every integer of smaller magnitude is an `f64`.
const EXACT_LIMIT: u64 = 1 << 53;

/// The slots a multiset of one sorted sample is counted in: one per distinct value when its sums
/// are exact (see [the module docs](self)), else one per position.
pub(crate) struct CountedSample<'a> {
    sorted: &'a [f64],
    /// `slot_of[position]`: the slot counting `sorted[position]`.
    slot_of: Vec<u32>,
    /// `Some` when counting per distinct value.
    exact: Option<DistinctValues>,
}

/// The distinct values of an integer sample (distinct under `f64::total_cmp`, so `−0.0` and
/// `0.0` keep their own slots and the median keeps its sign bit).
pub(crate) struct DistinctValues {
    /// Ascending.
    values: Vec<f64>,
    /// `values` as integers.
    integers: Vec<i64>,
}

impl<'a> CountedSample<'a> {
    /// For multisets of `sorted` (ascending under `f64::total_cmp`, finite, non-empty) holding at
    /// most `most_taken` values each.
    pub(crate) fn new(sorted: &'a [f64], most_taken: usize) -> Self {
        match DistinctValues::exact(sorted, most_taken) {
            Some((exact, slot_of)) => Self {
                sorted,
                slot_of,
                exact: Some(exact),
            },
            None => Self {
                sorted,
                slot_of: (0..sorted.len() as u32).collect(),
                exact: None,
            },
        }
    }

    /// How many slots a count vector has.
    pub(crate) fn slots(&self) -> usize {
        self.exact
            .as_ref()
            .map_or(self.sorted.len(), |exact| exact.values.len())
    }

    /// `slot_of()[position]` is the slot that counts `sorted[position]`.
    pub(crate) fn slot_of(&self) -> &[u32] {
        &self.slot_of
    }

    /// Whether the multisets are counted per distinct value (the exact-integer shortcut);
    /// otherwise `slot_of` is the identity.
    pub(crate) fn is_exact(&self) -> bool {
        self.exact.is_some()
    }

    /// Collects `capacity` multisets of `total` values each (`1 ≤ total ≤ most_taken`).
    pub(crate) fn replicates(
        &self,
        statistic: Statistic,
        total: usize,
        capacity: usize,
    ) -> Replicates<'_> {
        match &self.exact {
            Some(distinct) => Replicates::Exact {
                distinct,
                statistic,
                total,
                values: Vec::with_capacity(capacity),
            },
            None => Replicates::Batched(BatchedStatistic::new(
                statistic,
                self.sorted,
                total,
                capacity,
            )),
        }
    }
}

impl DistinctValues {
    /// The distinct values of `sorted` and the position → slot table, when every value is an
    /// integer and `max |value| · most_taken < 2⁵³`.
    fn exact(sorted: &[f64], most_taken: usize) -> Option<(Self, Vec<u32>)> {
        let largest = sorted.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        if largest >= EXACT_LIMIT as f64 || sorted.iter().any(|v| v.fract() != 0.0) {
            return None;
        }
        // `largest` is an integer below 2⁵³, so the conversion is exact.
        let bound = (largest as u64).checked_mul(u64::try_from(most_taken).ok()?)?;
        if bound >= EXACT_LIMIT {
            return None;
        }
        let mut values: Vec<f64> = Vec::new();
        let mut slot_of = Vec::with_capacity(sorted.len());
        for &value in sorted {
            if values
                .last()
                .is_none_or(|last| last.to_bits() != value.to_bits())
            {
                values.push(value);
            }
            slot_of.push(u32::try_from(values.len() - 1).ok()?);
        }
        // Exact: each is an integer of magnitude below 2⁵³.
        let integers = values.iter().map(|&v| v as i64).collect();
        Some((Self { values, integers }, slot_of))
    }

    /// The statistic of the multiset holding `values[j]` `counts[j]` times, `total` in all.
    fn of_counts(&self, statistic: Statistic, counts: &[u32], total: usize) -> f64 {
        match statistic {
            Statistic::Mean => {
                let sum: i64 = self
                    .integers
                    .iter()
                    .zip(counts)
                    .map(|(&value, &count)| value * i64::from(count))
                    .sum();
                sum as f64 / total as f64
            }
            Statistic::Iqm => {
                let k = total / 4;
                self.trimmed_sum(counts, k, total - k) as f64 / (total - 2 * k) as f64
            }
            Statistic::Median => {
                let lower = self.value_at_position(counts, (total - 1) / 2);
                let upper = self.value_at_position(counts, total / 2);
                // As in `Statistic::of_counts`.
                lower / 2.0 + upper / 2.0
            }
        }
    }

    /// The exact sum of the values at sorted positions `start..end` of the multiset.
    fn trimmed_sum(&self, counts: &[u32], start: usize, end: usize) -> i64 {
        let mut sum = 0;
        let mut position = 0;
        for (&value, &count) in self.integers.iter().zip(counts) {
            let next = position + count as usize;
            let copies = next.min(end).saturating_sub(position.max(start));
            sum += value * copies as i64;
            if next >= end {
                break;
            }
            position = next;
        }
        sum
    }

    /// The value at 0-based `position` of the sorted multiset.
    fn value_at_position(&self, counts: &[u32], position: usize) -> f64 {
        let mut seen = 0;
        for (&value, &count) in self.values.iter().zip(counts) {
            seen += count as usize;
            if seen > position {
                return value;
            }
        }
        // Unreachable for position < total; the largest value is the right answer at the end.
        self.values.last().copied().unwrap_or(0.0)
    }
}

/// The statistic of multisets of a [`CountedSample`], in the order they were given.
pub(crate) enum Replicates<'a> {
    /// Computed at once per distinct value, exactly.
    Exact {
        distinct: &'a DistinctValues,
        statistic: Statistic,
        total: usize,
        /// The statistics so far.
        values: Vec<f64>,
    },
    /// Counted per position and computed in batches.
    Batched(BatchedStatistic<'a>),
}

impl Replicates<'_> {
    /// Adds the multiset with `counts[slot]` values in each slot of the sample (adding up to
    /// `total`).
    pub(crate) fn push(&mut self, counts: &[u32]) {
        match self {
            Self::Exact {
                distinct,
                statistic,
                total,
                values,
            } => values.push(distinct.of_counts(*statistic, counts, *total)),
            Self::Batched(batch) => batch.push(counts),
        }
    }

    /// The statistic of every multiset given, in order.
    pub(crate) fn finish(self) -> Vec<f64> {
        match self {
            Self::Exact { values, .. } => values,
            Self::Batched(batch) => batch.finish(),
        }
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// Sorted integer values with many ties (and `±0.0`, and values whose sums come near 2⁵³), or
    /// any values; and multisets of a size `total ≤ n` over them, each given by its counts per
    /// position.
    fn multisets() -> impl Strategy<Value = (Vec<f64>, usize, Vec<Vec<u32>>)> {
        // Integers with many ties: the exact path (unless a value near 2⁵² rules it out).
        let integer = prop_oneof![
            6 => (-3_i32..4).prop_map(f64::from),
            3 => (-2000_i64..2000).prop_map(|v| v as f64),
            1 => Just(-0.0),
            1 => Just(0.0),
            1 => Just(2000.0),
            1 => Just((1_u64 << 47) as f64),
            1 => Just(-((1_u64 << 52) as f64)),
        ];
        let any = prop_oneof![3 => integer.clone(), 1 => -1e3..1e3_f64];
        let sample = prop_oneof![
            prop::collection::vec(integer, 1..40),
            prop::collection::vec(any, 1..40),
        ];
        sample.prop_flat_map(|mut values| {
            values.sort_by(f64::total_cmp);
            let n = values.len();
            (1..=n).prop_flat_map(move |total| {
                let counts = prop::collection::vec(
                    prop::collection::vec(0..n, total).prop_map(move |draws| {
                        let mut counts = vec![0_u32; n];
                        for i in draws {
                            counts[i] += 1;
                        }
                        counts
                    }),
                    0..20,
                );
                (Just(values.clone()), Just(total), counts)
            })
        })
    }

    /// The counts per slot of counts per position.
    fn per_slot(sample: &CountedSample<'_>, counts: &[u32]) -> Vec<u32> {
        let mut slots = vec![0; sample.slots()];
        for (&slot, &count) in sample.slot_of().iter().zip(counts) {
            slots[slot as usize] += count;
        }
        slots
    }

    /// Bits of each multiset's statistic through a [`CountedSample`] and by the definition.
    fn both(
        sorted: &[f64],
        total: usize,
        draws: &[Vec<u32>],
        statistic: Statistic,
    ) -> (Vec<u64>, Vec<u64>, bool) {
        let sample = CountedSample::new(sorted, total);
        let mut replicates = sample.replicates(statistic, total, draws.len());
        for counts in draws {
            replicates.push(&per_slot(&sample, counts));
        }
        let got = replicates.finish().iter().map(|v| v.to_bits()).collect();
        let want = draws
            .iter()
            .map(|counts| statistic.of_counts(sorted, counts, total).to_bits())
            .collect();
        (got, want, sample.is_exact())
    }

    proptest! {
        /// Law: the statistic of a counted multiset has the bits of `Statistic::of_counts` (the
        /// one-at-a-time definition), on the exact-integer path and off it.
        #[test]
        fn counted_equals_one_at_a_time((sorted, total, draws) in multisets()) {
            for statistic in Statistic::ALL {
                let (got, want, _) = both(&sorted, total, &draws, statistic);
                prop_assert_eq!(got, want);
            }
        }
    }

    #[test]
    fn integers_are_counted_per_distinct_value() {
        let sorted = [-0.0, 0.0, 0.0, 3.0, 3.0, 3.0, 7.0];
        let sample = CountedSample::new(&sorted, 7);
        assert!(sample.is_exact());
        assert_eq!(sample.slots(), 4);
        assert_eq!(sample.slot_of(), &[0, 1, 1, 2, 2, 2, 3]);
        assert!(!CountedSample::new(&[1.0, 1.5], 2).is_exact());
    }

    #[test]
    fn the_guard_stops_at_two_to_the_53() {
        // 2⁵¹ · 4 = 2⁵³: a sum of four could round, so not exact; three are.
        let big = (1_u64 << 51) as f64;
        let sorted = [-big, 1.0, big];
        assert!(!CountedSample::new(&sorted, 4).is_exact());
        assert!(CountedSample::new(&sorted, 3).is_exact());
        // Near the limit both paths still agree bit for bit, rounding or not.
        let near = [
            (1_u64 << 52) as f64,
            (1_u64 << 52) as f64 + 2.0,
            (1_u64 << 52) as f64 + 4.0,
        ];
        let draws = vec![vec![1, 1, 1], vec![0, 0, 3], vec![2, 1, 0]];
        for statistic in Statistic::ALL {
            let (got, want, exact) = both(&near, 3, &draws, statistic);
            assert!(!exact);
            assert_eq!(got, want);
        }
    }

    #[test]
    fn small_samples_and_signed_zeros_keep_their_bits() {
        for sorted in [
            vec![-0.0],
            vec![-0.0, -0.0],
            vec![-0.0, 0.0, 5.0],
            vec![-4.0, -0.0, 0.0],
        ] {
            let n = sorted.len();
            let mut draws = Vec::new();
            // Every multiset of n values over n positions (n ≤ 3: at most 27 draws).
            for code in 0..n.pow(n as u32) {
                let mut counts = vec![0; n];
                let mut rest = code;
                for _ in 0..n {
                    counts[rest % n] += 1;
                    rest /= n;
                }
                draws.push(counts);
            }
            for statistic in Statistic::ALL {
                let (got, want, exact) = both(&sorted, n, &draws, statistic);
                assert!(exact);
                assert_eq!(got, want, "{sorted:?} {statistic:?}");
            }
        }
    }
}
