//! A location statistic of many resampled multisets at once, bit for bit what
//! [`Statistic::of_counts`] gives for each.
//!
//! Each multiset (`sorted[i]` taken `counts[i]` times) is written out in sorted order, then
//! the trimmed sums of [`LANES`] multisets are added side by side, position by position. Every
//! lane still adds its own values one at a time in ascending order, exactly as
//! [`trimmed_mean_of_counts`](super::location::trimmed_mean_of_counts) does, so each sum has the
//! same bits; but the lanes' additions are independent, so they overlap instead of waiting on
//! one another, and writing a multiset out needs no branch per value (most counts are 0, 1 or
//! 2, at random, which a branch predictor cannot learn).

use super::location::Statistic;

/// How many multisets are summed side by side.
const LANES: usize = 8;

/// Room past the end of a written-out multiset: a value is written [`UNROLL`] times before
/// its count is looked at.
const UNROLL: usize = 4;

/// Collects resampled multisets of one sorted sample and computes `statistic` of each, in the
/// order they were given.
pub(crate) struct BatchedStatistic<'a> {
    statistic: Statistic,
    sorted: &'a [f64],
    /// The sorted positions `start..end` of a multiset the statistic reads (the IQM's middle,
    /// the median's one or two, the mean's all); only those are written out.
    start: usize,
    end: usize,
    /// Length of one lane: the window's size plus [`UNROLL`] slots of room.
    stride: usize,
    /// Up to [`LANES`] written-out windows, lane `l` at `l * stride..`.
    lanes: Vec<f64>,
    /// How many lanes hold a multiset not yet computed.
    filled: usize,
    replicates: Vec<f64>,
}

impl<'a> BatchedStatistic<'a> {
    /// For multisets of `total ≥ 1` values of `sorted` (ascending, non-empty); `capacity` is
    /// how many will be given.
    pub(crate) fn new(
        statistic: Statistic,
        sorted: &'a [f64],
        total: usize,
        capacity: usize,
    ) -> Self {
        let (start, end) = match statistic {
            Statistic::Mean => (0, total),
            Statistic::Iqm => (total / 4, total - total / 4),
            Statistic::Median => ((total - 1) / 2, total / 2 + 1),
        };
        let stride = end - start + UNROLL;
        Self {
            statistic,
            sorted,
            start,
            end,
            stride,
            lanes: vec![0.0; stride * LANES],
            filled: 0,
            replicates: Vec::with_capacity(capacity),
        }
    }

    /// Adds the multiset holding `sorted[i]` `counts[i]` times; the counts must add up to the
    /// `total` given to [`new`](Self::new).
    pub(crate) fn push(&mut self, counts: &[u32]) {
        let (start, end) = (self.start, self.end);
        let window = end - start;
        let stride = self.stride;
        let lane = &mut self.lanes[self.filled * stride..(self.filled + 1) * stride];
        let mut values = self.sorted.iter().zip(counts);
        // The values below the window are only counted; the first value reaching into it
        // fills its positions from `start` on. `written` counts the window's positions
        // filled so far.
        let mut below = 0;
        let mut written = 0;
        for (&value, &count) in values.by_ref() {
            let next = below + count as usize;
            if next > start {
                written = next.min(end) - start;
                if let Some(copies) = lane.get_mut(..written) {
                    copies.fill(value);
                }
                break;
            }
            below = next;
        }
        let mut position = written;
        for (&value, &count) in values {
            if position >= window {
                break;
            }
            let count = count as usize;
            // Written UNROLL times whatever the count, in one store of adjacent slots (the
            // extra copies are overwritten by the next values or lie past the window), so the
            // common small counts take no branch.
            if let Some(slots) = lane.get_mut(position..position + UNROLL) {
                slots.copy_from_slice(&[value; UNROLL]);
            }
            if count > UNROLL
                && let Some(slots) = lane.get_mut(position..(position + count).min(window))
            {
                slots.fill(value);
            }
            position += count;
        }
        self.filled += 1;
        if self.filled == LANES {
            self.compute();
        }
    }

    /// The statistic of every multiset given, in order.
    pub(crate) fn finish(mut self) -> Vec<f64> {
        if self.filled > 0 {
            self.compute();
        }
        self.replicates
    }

    /// The value at `position` of the window of `lane`.
    fn at(&self, position: usize, lane: usize) -> f64 {
        self.lanes[lane * self.stride + position]
    }

    /// Appends the statistic of the filled lanes.
    fn compute(&mut self) {
        let window = self.end - self.start;
        match self.statistic {
            Statistic::Mean | Statistic::Iqm => self.trimmed_means(window),
            Statistic::Median => {
                for lane in 0..self.filled {
                    let lower = self.at(0, lane);
                    let upper = self.at(window - 1, lane);
                    // As in `Statistic::of_counts`.
                    self.replicates.push(lower / 2.0 + upper / 2.0);
                }
            }
        }
        self.filled = 0;
    }

    /// Appends the mean of the `window` values of each filled lane.
    fn trimmed_means(&mut self, window: usize) {
        let lanes: [&[f64]; LANES] = std::array::from_fn(|lane| {
            &self.lanes[lane * self.stride..lane * self.stride + window]
        });
        let mut sums = [0.0_f64; LANES];
        for position in 0..window {
            for (sum, lane) in sums.iter_mut().zip(&lanes) {
                *sum += lane[position];
            }
        }
        let taken = window as f64;
        for (lane, &sum) in sums.iter().enumerate().take(self.filled) {
            let lowest = lanes[lane][0];
            let highest = lanes[lane][window - 1];
            let mean = if sum.is_finite() {
                sum / taken
            } else {
                // Values near f64::MAX: divide first, as `trimmed_mean_of_counts` does.
                let mut scaled = 0.0;
                for &value in lanes[lane] {
                    scaled += value / taken;
                }
                scaled
            };
            self.replicates.push(mean.clamp(lowest, highest));
        }
    }
}

/// The most sorted values [`BatchedSubsets`] takes: one bit each in a `u64`.
pub(crate) const MAX_SUBSET_SLOTS: usize = 64;

/// Collects subsets of one sorted sample of at most [`MAX_SUBSET_SLOTS`] values, each a bit
/// mask (bit `i` takes `sorted[i]`), and computes `statistic` of each, in the order they were
/// given: the splits of the permutation test and the sign vectors of the sign-flip test.
///
/// Bit for bit [`Statistic::of_counts`] with counts of 0 and 1: each lane walks its mask's set
/// bits upward (lowest first, so ascending values) and adds the values of the trimmed window
/// one at a time. Nothing is written out; the [`LANES`] lanes take one value each per step, so
/// their chains of additions overlap.
pub(crate) struct BatchedSubsets {
    statistic: Statistic,
    /// The sorted values, padded to 64 (the padding is never selected).
    sorted: [f64; MAX_SUBSET_SLOTS],
    /// How many bits each mask has set.
    total: usize,
    /// Up to [`LANES`] masks not yet computed.
    masks: [u64; LANES],
    filled: usize,
    replicates: Vec<f64>,
}

impl BatchedSubsets {
    /// For subsets of `total ≥ 1` values of `sorted` (ascending, at most [`MAX_SUBSET_SLOTS`]
    /// values, else `None`); `capacity` is how many will be given.
    pub(crate) fn new(
        statistic: Statistic,
        sorted: &[f64],
        total: usize,
        capacity: usize,
    ) -> Option<Self> {
        let mut padded = [0.0; MAX_SUBSET_SLOTS];
        padded.get_mut(..sorted.len())?.copy_from_slice(sorted);
        Some(Self {
            statistic,
            sorted: padded,
            total,
            masks: [0; LANES],
            filled: 0,
            replicates: Vec::with_capacity(capacity),
        })
    }

    /// Adds the subset of the values whose bits `mask` sets (`total` of them).
    pub(crate) fn push(&mut self, mask: u64) {
        debug_assert_eq!(mask.count_ones() as usize, self.total);
        self.masks[self.filled] = mask;
        self.filled += 1;
        if self.filled == LANES {
            self.compute();
        }
    }

    /// The statistic of every subset given, in order.
    pub(crate) fn finish(mut self) -> Vec<f64> {
        if self.filled > 0 {
            self.compute();
        }
        self.replicates
    }

    /// The value of the lowest bit set in `mask` (not 0).
    fn lowest(&self, mask: u64) -> f64 {
        self.sorted[(mask.trailing_zeros() as usize) % MAX_SUBSET_SLOTS]
    }

    /// Appends the statistic of the filled lanes.
    fn compute(&mut self) {
        // Unfilled lanes repeat the first mask, so that every lane has `total` bits set.
        let first = self.masks[0];
        for mask in &mut self.masks[self.filled..] {
            *mask = first;
        }
        let total = self.total;
        match self.statistic {
            Statistic::Mean => self.trimmed_means(0, total),
            Statistic::Iqm => {
                let k = total / 4;
                self.trimmed_means(k, total - k);
            }
            Statistic::Median => {
                for lane in 0..self.filled {
                    let mut mask = self.masks[lane];
                    for _ in 0..(total - 1) / 2 {
                        mask = without_lowest(mask);
                    }
                    let lower = self.lowest(mask);
                    if total.is_multiple_of(2) {
                        mask = without_lowest(mask);
                    }
                    let upper = self.lowest(mask);
                    // As in `Statistic::of_counts`.
                    self.replicates.push(lower / 2.0 + upper / 2.0);
                }
            }
        }
        self.filled = 0;
    }

    /// Appends the mean of the `start..end`-th set values of each filled lane.
    fn trimmed_means(&mut self, start: usize, end: usize) {
        let mut masks = self.masks;
        for mask in &mut masks {
            for _ in 0..start {
                *mask = without_lowest(*mask);
            }
        }
        let window = masks;
        let lowest: [f64; LANES] = std::array::from_fn(|lane| self.lowest(window[lane]));
        let mut sums = [0.0_f64; LANES];
        let mut highest = [0.0_f64; LANES];
        for _ in start..end {
            for lane in 0..LANES {
                let value = self.lowest(masks[lane]);
                sums[lane] += value;
                highest[lane] = value;
                masks[lane] = without_lowest(masks[lane]);
            }
        }
        let taken = (end - start) as f64;
        for lane in 0..self.filled {
            let mean = if sums[lane].is_finite() {
                sums[lane] / taken
            } else {
                // Values near f64::MAX: divide first, as `trimmed_mean_of_counts` does.
                let mut mask = window[lane];
                let mut scaled = 0.0;
                for _ in start..end {
                    scaled += self.lowest(mask) / taken;
                    mask = without_lowest(mask);
                }
                scaled
            };
            self.replicates
                .push(mean.clamp(lowest[lane], highest[lane]));
        }
    }
}

/// `mask` without its lowest set bit.
fn without_lowest(mask: u64) -> u64 {
    mask & mask.wrapping_sub(1)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    /// Sorted values (with repeats and extremes) and several count vectors over them, each
    /// adding up to the number of values.
    fn multisets() -> impl Strategy<Value = (Vec<f64>, Vec<Vec<u32>>)> {
        let value = prop_oneof![
            4 => -1e3..1e3_f64,
            1 => (-50_i32..50).prop_map(f64::from),
            1 => Just(0.1),
            1 => Just(-0.0),
            1 => Just(f64::MAX / 2.0),
            1 => Just(-f64::MAX / 3.0),
        ];
        prop::collection::vec(value, 1..40).prop_flat_map(|mut values| {
            values.sort_by(f64::total_cmp);
            let n = values.len();
            let counts = prop::collection::vec(
                prop::collection::vec(0..n, n).prop_map(move |draws| {
                    let mut counts = vec![0_u32; n];
                    for i in draws {
                        counts[i] += 1;
                    }
                    counts
                }),
                0..20,
            );
            (Just(values), counts)
        })
    }

    proptest! {
        /// Law: the batch gives, for every multiset and in order, the bits of
        /// `Statistic::of_counts` (the one-at-a-time definition).
        #[test]
        fn batch_equals_one_at_a_time((sorted, draws) in multisets()) {
            for statistic in Statistic::ALL {
                let mut batch = BatchedStatistic::new(statistic, &sorted, sorted.len(), draws.len());
                for counts in &draws {
                    batch.push(counts);
                }
                let got: Vec<u64> = batch.finish().iter().map(|v| v.to_bits()).collect();
                let want: Vec<u64> = draws
                    .iter()
                    .map(|counts| statistic.of_counts(&sorted, counts, sorted.len()).to_bits())
                    .collect();
                prop_assert_eq!(got, want);
            }
        }
    }

    /// Sorted values (at most 64) and subsets of a size `total` of them, as masks.
    fn subsets() -> impl Strategy<Value = (Vec<f64>, usize, Vec<u64>)> {
        let value = prop_oneof![
            4 => -1e3..1e3_f64,
            2 => (-5_i32..5).prop_map(f64::from),
            1 => Just(-0.0),
            1 => Just(f64::MAX / 2.0),
            1 => Just(-f64::MAX / 3.0),
        ];
        prop::collection::vec(value, 1..=MAX_SUBSET_SLOTS).prop_flat_map(|mut values| {
            values.sort_by(f64::total_cmp);
            let n = values.len();
            (1..=n).prop_flat_map(move |total| {
                let mask = Just((0..n).collect::<Vec<usize>>())
                    .prop_shuffle()
                    .prop_map(move |order| order[..total].iter().fold(0_u64, |m, &i| m | 1 << i));
                (
                    Just(values.clone()),
                    Just(total),
                    prop::collection::vec(mask, 0..20),
                )
            })
        })
    }

    proptest! {
        /// Law: each subset's statistic has the bits of `Statistic::of_counts` with 0/1 counts
        /// (the one-at-a-time definition), in order.
        #[test]
        fn subsets_equal_one_at_a_time((sorted, total, masks) in subsets()) {
            for statistic in Statistic::ALL {
                let mut batch = BatchedSubsets::new(statistic, &sorted, total, masks.len())
                    .ok_or_else(|| TestCaseError::fail("at most 64 values"))?;
                for &mask in &masks {
                    batch.push(mask);
                }
                let got: Vec<u64> = batch.finish().iter().map(|v| v.to_bits()).collect();
                let want: Vec<u64> = masks
                    .iter()
                    .map(|&mask| {
                        let counts: Vec<u32> =
                            (0..sorted.len()).map(|i| (mask >> i & 1) as u32).collect();
                        statistic.of_counts(&sorted, &counts, total).to_bits()
                    })
                    .collect();
                prop_assert_eq!(got, want);
            }
        }
    }

    #[test]
    fn more_than_64_values_are_refused() {
        assert!(BatchedSubsets::new(Statistic::Mean, &[0.0; 65], 1, 1).is_none());
        assert!(BatchedSubsets::new(Statistic::Mean, &[0.0; 64], 1, 1).is_some());
    }

    #[test]
    fn long_runs_across_the_window_edges_keep_their_bits() {
        let sorted = [0.1, 0.2, 0.3, 0.7, 1.1, 1.3, 1.7, 1.9, 2.3, 2.9, 3.1, 3.7];
        let draws = [
            [0, 0, 9, 0, 0, 0, 0, 0, 0, 0, 3, 0],
            [5, 0, 0, 0, 0, 0, 6, 0, 0, 0, 0, 1],
            [1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 11],
            [0, 0, 0, 0, 0, 12, 0, 0, 0, 0, 0, 0],
            [2, 1, 0, 0, 2, 0, 0, 7, 0, 0, 0, 0],
        ];
        for statistic in Statistic::ALL {
            let mut batch = BatchedStatistic::new(statistic, &sorted, 12, draws.len());
            for counts in &draws {
                batch.push(counts);
            }
            let got: Vec<u64> = batch.finish().iter().map(|v| v.to_bits()).collect();
            let want: Vec<u64> = draws
                .iter()
                .map(|counts| statistic.of_counts(&sorted, counts, 12).to_bits())
                .collect();
            assert_eq!(got, want, "{statistic:?}");
        }
    }

    #[test]
    fn a_count_above_the_unroll_is_written_in_full() {
        let sorted = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        let counts = [0, 7, 0, 0, 0, 0, 0];
        let mut batch = BatchedStatistic::new(Statistic::Mean, &sorted, 7, 1);
        batch.push(&counts);
        assert_eq!(batch.finish(), vec![2.0]);
    }
}
