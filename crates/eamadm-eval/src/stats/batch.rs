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
    /// How many values each multiset holds.
    total: usize,
    /// Length of one lane: the multiset's size plus [`UNROLL`] slots of room.
    stride: usize,
    /// Up to [`LANES`] written-out multisets, lane `l` at `l * stride..`.
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
        let stride = total + UNROLL;
        Self {
            statistic,
            sorted,
            total,
            stride,
            lanes: vec![0.0; stride * LANES],
            filled: 0,
            replicates: Vec::with_capacity(capacity),
        }
    }

    /// Adds the multiset holding `sorted[i]` `counts[i]` times; the counts must add up to the
    /// `total` given to [`new`](Self::new).
    pub(crate) fn push(&mut self, counts: &[u32]) {
        let stride = self.stride;
        let lane = &mut self.lanes[self.filled * stride..(self.filled + 1) * stride];
        let mut position = 0;
        for (&value, &count) in self.sorted.iter().zip(counts) {
            let count = count as usize;
            // Written UNROLL times whatever the count, in one store of adjacent slots (the
            // extra copies are overwritten by the next values or lie past the end), so the
            // common small counts take no branch.
            if let Some(slots) = lane.get_mut(position..position + UNROLL) {
                slots.copy_from_slice(&[value; UNROLL]);
            }
            if count > UNROLL
                && let Some(slots) = lane.get_mut(position..position + count)
            {
                slots.fill(value);
            }
            position += count;
        }
        debug_assert_eq!(position, self.total);
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

    /// The value at `position` of `lane`.
    fn at(&self, position: usize, lane: usize) -> f64 {
        self.lanes[lane * self.stride + position]
    }

    /// Appends the statistic of the filled lanes.
    fn compute(&mut self) {
        let total = self.total;
        match self.statistic {
            Statistic::Mean => self.trimmed_means(0, total),
            Statistic::Iqm => {
                let k = total / 4;
                self.trimmed_means(k, total - k);
            }
            Statistic::Median => {
                for lane in 0..self.filled {
                    let lower = self.at((total - 1) / 2, lane);
                    let upper = self.at(total / 2, lane);
                    // As in `Statistic::of_counts`.
                    self.replicates.push(lower / 2.0 + upper / 2.0);
                }
            }
        }
        self.filled = 0;
    }

    /// Appends the mean of positions `start..end` of each filled lane.
    fn trimmed_means(&mut self, start: usize, end: usize) {
        let window: [&[f64]; LANES] = std::array::from_fn(|lane| {
            &self.lanes[lane * self.stride + start..lane * self.stride + end]
        });
        let mut sums = [0.0_f64; LANES];
        for position in 0..end - start {
            for (sum, lane) in sums.iter_mut().zip(&window) {
                *sum += lane[position];
            }
        }
        let taken = (end - start) as f64;
        for (lane, &sum) in sums.iter().enumerate().take(self.filled) {
            let lowest = window[lane][0];
            let highest = window[lane][end - start - 1];
            let mean = if sum.is_finite() {
                sum / taken
            } else {
                // Values near f64::MAX: divide first, as `trimmed_mean_of_counts` does.
                let mut scaled = 0.0;
                for &value in window[lane] {
                    scaled += value / taken;
                }
                scaled
            };
            self.replicates.push(mean.clamp(lowest, highest));
        }
    }
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

    #[test]
    fn a_count_above_the_unroll_is_written_in_full() {
        let sorted = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        let counts = [0, 7, 0, 0, 0, 0, 0];
        let mut batch = BatchedStatistic::new(Statistic::Mean, &sorted, 7, 1);
        batch.push(&counts);
        assert_eq!(batch.finish(), vec![2.0]);
    }
}
