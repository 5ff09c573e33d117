//! The seeded percentile bootstrap: one sample, a difference of two, and the stratified
//! bootstrap over groups (see [the module docs](super) for the formulas and the draw order).

use super::counted::CountedSample;
use super::location::{Statistic, quantile_unsorted};
use super::words::Words;
use super::{
    Interval, StatsError, check_confidence, check_len, check_resamples, check_sample, finite,
    sorted_copy,
};

/// Settings of the seeded percentile bootstrap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bootstrap {
    /// Number of resamples `B` (1 to [`MAX_RESAMPLES`](super::MAX_RESAMPLES)).
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
        check_len(x.len(), "the sample's size")?;
        let sorted = sorted_copy(x);
        let sample = CountedSample::new(&sorted, x.len());
        let estimate = statistic.of(x)?;
        let mut rng = Words::seed_from_u64(self.seed);
        let mut replicates = sample.replicates(statistic, x.len(), self.resamples as usize);
        let mut counts = vec![0; sample.slots()];
        for _ in 0..self.resamples {
            draw(&mut rng, &sample, &mut counts);
            replicates.push(&counts);
        }
        percentile_interval(
            self.confidence,
            estimate,
            &mut replicates.finish(),
            statistic.name(),
        )
    }

    /// [`Self::interval`] of each of `samples`, bit for bit, drawing the resamples once for
    /// all samples of one size: with one seed, `interval` draws the same positions of the
    /// sorted sample for every sample of a size, so here each resample's positions are drawn
    /// once and counted into every such sample (one task × method's metrics, whose values
    /// all come from its seeds). The intervals are in the order of `samples`.
    ///
    /// # Errors
    /// [`StatsError`] as [`Self::interval`] gives for the first sample it fails on.
    pub fn intervals(
        &self,
        samples: &[&[f64]],
        statistic: Statistic,
    ) -> Result<Vec<Interval>, StatsError> {
        self.validate()?;
        for x in samples {
            check_sample(x, "x")?;
            check_len(x.len(), "the sample's size")?;
        }
        let mut intervals = vec![None; samples.len()];
        let mut sizes: Vec<usize> = samples.iter().map(|x| x.len()).collect();
        sizes.sort_unstable();
        sizes.dedup();
        for size in sizes {
            let members: Vec<usize> = (0..samples.len())
                .filter(|&i| samples[i].len() == size)
                .collect();
            let sorted: Vec<Vec<f64>> = members.iter().map(|&i| sorted_copy(samples[i])).collect();
            let counted: Vec<CountedSample<'_>> = sorted
                .iter()
                .map(|sorted| CountedSample::new(sorted, size))
                .collect();
            let estimates = members
                .iter()
                .map(|&i| statistic.of(samples[i]))
                .collect::<Result<Vec<f64>, StatsError>>()?;
            let mut replicates: Vec<_> = counted
                .iter()
                .map(|sample| sample.replicates(statistic, size, self.resamples as usize))
                .collect();
            let mut counts: Vec<Vec<u32>> = counted
                .iter()
                .map(|s| {
                    if s.is_exact() {
                        vec![0; s.slots()]
                    } else {
                        Vec::new()
                    }
                })
                .collect();
            // Every sample counted per position (not per distinct value) has the same counts
            // of a resample: they are counted once, into `per_position`.
            let mut per_position = vec![0; size];
            let mut rng = Words::seed_from_u64(self.seed);
            let mut positions = Vec::with_capacity(size);
            for _ in 0..self.resamples {
                positions.clear();
                rng.uniform_below_each(size as u32, size, |i| positions.push(i));
                let mut counted_per_position = false;
                for ((sample, counts), replicates) in
                    counted.iter().zip(&mut counts).zip(&mut replicates)
                {
                    if sample.is_exact() {
                        count_positions(sample, &positions, counts);
                        replicates.push(counts);
                    } else {
                        if !counted_per_position {
                            count_positions(sample, &positions, &mut per_position);
                            counted_per_position = true;
                        }
                        replicates.push(&per_position);
                    }
                }
            }
            for ((&i, replicates), estimate) in members.iter().zip(replicates).zip(estimates) {
                intervals[i] = Some(percentile_interval(
                    self.confidence,
                    estimate,
                    &mut replicates.finish(),
                    statistic.name(),
                )?);
            }
        }
        Ok(intervals.into_iter().flatten().collect())
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
        check_len(x.len(), "x's size")?;
        check_len(y.len(), "y's size")?;
        let (sorted_x, sorted_y) = (sorted_copy(x), sorted_copy(y));
        let sample_x = CountedSample::new(&sorted_x, x.len());
        let sample_y = CountedSample::new(&sorted_y, y.len());
        let estimate = finite(statistic.of(x)? - statistic.of(y)?, "difference")?;
        let mut rng = Words::seed_from_u64(self.seed);
        let resamples = self.resamples as usize;
        let mut of_x = sample_x.replicates(statistic, x.len(), resamples);
        let mut of_y = sample_y.replicates(statistic, y.len(), resamples);
        let mut counts_x = vec![0; sample_x.slots()];
        let mut counts_y = vec![0; sample_y.slots()];
        // Both resamples are drawn in the documented order; their statistics are computed
        // from the counts, which changes no draw and no bit.
        for _ in 0..self.resamples {
            draw(&mut rng, &sample_x, &mut counts_x);
            of_x.push(&counts_x);
            draw(&mut rng, &sample_y, &mut counts_y);
            of_y.push(&counts_y);
        }
        let mut replicates: Vec<f64> = of_x
            .finish()
            .iter()
            .zip(of_y.finish())
            .map(|(of_x, of_y)| of_x - of_y)
            .collect();
        percentile_interval(self.confidence, estimate, &mut replicates, "difference")
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

        let sample = CountedSample::new(&sorted, total);
        // Each group's draws land in the slots of its positions.
        let slots: Vec<Vec<u32>> = positions
            .iter()
            .map(|group| group.iter().map(|&p| sample.slot_of()[p]).collect())
            .collect();
        let mut rng = Words::seed_from_u64(self.seed);
        let mut replicates = sample.replicates(statistic, total, self.resamples as usize);
        let mut counts = vec![0; sample.slots()];
        for _ in 0..self.resamples {
            counts.fill(0);
            for group in &slots {
                rng.uniform_below_each(group.len() as u32, group.len(), |i| {
                    counts[group[i] as usize] += 1;
                });
            }
            replicates.push(&counts);
        }
        percentile_interval(
            self.confidence,
            estimate,
            &mut replicates.finish(),
            statistic.name(),
        )
    }
}

/// The percentile interval at `confidence` of `replicates` (reordered in place) around
/// `estimate`: one implementation for the one-level and the two-level bootstrap.
pub(super) fn percentile_interval(
    confidence: f64,
    estimate: f64,
    replicates: &mut [f64],
    what: &'static str,
) -> Result<Interval, StatsError> {
    if replicates.iter().any(|v| !v.is_finite()) {
        return Err(StatsError::Overflow { what });
    }
    let alpha = 1.0 - confidence;
    Ok(Interval {
        estimate,
        low: quantile_unsorted(replicates, alpha / 2.0),
        high: quantile_unsorted(replicates, 1.0 - alpha / 2.0),
    })
}

/// Counts the resample at `positions` (of the sorted sample) into `counts`, as [`draw`] does.
fn count_positions(sample: &CountedSample<'_>, positions: &[usize], counts: &mut [u32]) {
    counts.fill(0);
    if sample.is_exact() {
        let slot_of = sample.slot_of();
        for &i in positions {
            counts[slot_of[i] as usize] += 1;
        }
    } else {
        for &i in positions {
            counts[i] += 1;
        }
    }
}

/// Draws one resample with replacement of the sorted sample of `sample` (`n` indices below `n`):
/// its multiplicities per slot, into `counts`.
fn draw(rng: &mut Words, sample: &CountedSample<'_>, counts: &mut [u32]) {
    counts.fill(0);
    let slot_of = sample.slot_of();
    let size = slot_of.len();
    if sample.is_exact() {
        rng.uniform_below_each(size as u32, size, |i| counts[slot_of[i] as usize] += 1);
    } else {
        // One slot per position: no table to look up.
        rng.uniform_below_each(size as u32, size, |i| counts[i] += 1);
    }
}
