//! The two-sample permutation test: exact enumeration of every split when there are few,
//! Monte Carlo with `(b + 1)/(B + 1)` otherwise (see [the module docs](super)).

use super::batch::BatchedSubsets;
use super::counted::CountedSample;
use super::location::Statistic;
use super::words::Words;
use super::{StatsError, check_len, check_resamples, check_sample};

/// Settings of the permutation test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PermutationTest {
    /// The largest number of splits enumerated exactly, and the number of random splits drawn
    /// otherwise (1 to [`MAX_RESAMPLES`](super::MAX_RESAMPLES)).
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
        let exact = binomial_at_most(total, n, u64::from(self.resamples));
        let splits = exact.map_or(self.resamples as usize, |splits| splits as usize);
        // Each split's two groups' statistics are computed together afterwards, the same
        // bits as one split at a time: as bit masks over the pooled sample when it has at most
        // 64 values, else counted over its slots (per distinct value for integers).
        let (of_x, of_y) = if let (Some(mut of_x), Some(mut of_y)) = (
            BatchedSubsets::new(statistic, &pooled, n, splits),
            BatchedSubsets::new(statistic, &pooled, m, splits),
        ) {
            let everything = u64::MAX >> (64 - total);
            self.for_each_split(n, total, exact.is_some(), |positions| {
                let in_x = positions.iter().fold(0_u64, |mask, &i| mask | 1 << i);
                of_x.push(in_x);
                of_y.push(everything ^ in_x);
            });
            (of_x.finish(), of_y.finish())
        } else {
            let sample = CountedSample::new(&pooled, n.max(m));
            let mut everything = vec![0_u32; sample.slots()];
            for &slot in sample.slot_of() {
                everything[slot as usize] += 1;
            }
            let mut in_x = vec![0_u32; sample.slots()];
            let mut in_y = vec![0_u32; sample.slots()];
            let mut of_x = sample.replicates(statistic, n, splits);
            let mut of_y = sample.replicates(statistic, m, splits);
            self.for_each_split(n, total, exact.is_some(), |positions| {
                in_x.fill(0);
                for &i in positions {
                    in_x[sample.slot_of()[i] as usize] += 1;
                }
                for ((to_y, &to_x), &all) in in_y.iter_mut().zip(&in_x).zip(&everything) {
                    *to_y = all - to_x;
                }
                of_x.push(&in_x);
                of_y.push(&in_y);
            });
            (of_x.finish(), of_y.finish())
        };
        let hits = of_x
            .iter()
            .zip(of_y)
            .filter(|&(of_x, of_y)| (of_x - of_y).abs() >= threshold)
            .count() as u64;
        Ok(match exact {
            Some(splits) => hits as f64 / splits as f64,
            None => (hits + 1) as f64 / (f64::from(self.resamples) + 1.0),
        })
    }

    /// Calls `split` with the pooled positions of `x`'s group of every split of `total`
    /// positions into `n` and `total − n` (`exact`), in lexicographic order, or of
    /// `resamples` random splits drawn in the documented order.
    fn for_each_split(&self, n: usize, total: usize, exact: bool, mut split: impl FnMut(&[usize])) {
        if exact {
            let mut chosen: Vec<usize> = (0..n).collect();
            loop {
                split(&chosen);
                if !next_combination(&mut chosen, total) {
                    break;
                }
            }
        } else {
            let mut rng = Words::seed_from_u64(self.seed);
            let mut permutation: Vec<usize> = (0..total).collect();
            for _ in 0..self.resamples {
                for i in 0..n {
                    let j = i + rng.uniform_below((total - i) as u32) as usize;
                    permutation.swap(i, j);
                }
                split(&permutation[..n]);
            }
        }
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
