//! The bootstrap and the permutation test against the plainest implementations of their
//! documented draws (the module docs of `eamadm_eval::stats`, "Random draws"): every resample or
//! split materialised and its statistic taken by [`Statistic::of`], which sorts it. The library
//! counts resamples per sorted slot, per distinct value for integer samples, or as bit masks;
//! these laws say that none of it changes a bit, on integer samples with many ties, on values
//! that round differently in another order, and on pooled samples over 64 values.

use eamadm_eval::stats::{Bootstrap, Interval, PermutationTest, Statistic};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Lemire's index below `k`, one word of `rng` at a time.
fn below(rng: &mut ChaCha8Rng, k: usize) -> usize {
    let k = k as u64;
    loop {
        let product = u64::from(rng.next_u32()) * k;
        // Keep the word unless the low half falls below (2³² − k) mod k.
        if (product as u32 as u64) >= ((1_u64 << 32) - k) % k {
            return (product >> 32) as usize;
        }
    }
}

fn sorted(x: &[f64]) -> Vec<f64> {
    let mut sorted = x.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted
}

/// The type-7 quantile of ascending `v`.
fn quantile(v: &[f64], p: f64) -> f64 {
    let h = (v.len() - 1) as f64 * p;
    let below = h.floor();
    let i = below as usize;
    match v.get(i + 1) {
        Some(&next) if h > below => (v[i] + (h - below) * (next - v[i])).clamp(v[i], next),
        _ => v[i],
    }
}

fn percentile_interval(estimate: f64, mut replicates: Vec<f64>, confidence: f64) -> Interval {
    replicates.sort_by(f64::total_cmp);
    let alpha = 1.0 - confidence;
    Interval {
        estimate,
        low: quantile(&replicates, alpha / 2.0),
        high: quantile(&replicates, 1.0 - alpha / 2.0),
    }
}

/// One resample of `x`: index `i` takes the `i`-th smallest value.
fn resample(rng: &mut ChaCha8Rng, x: &[f64]) -> Vec<f64> {
    let ascending = sorted(x);
    (0..x.len())
        .map(|_| ascending[below(rng, x.len())])
        .collect()
}

fn interval_by_materialising(b: &Bootstrap, x: &[f64], statistic: Statistic) -> Interval {
    let mut rng = ChaCha8Rng::seed_from_u64(b.seed);
    let replicates = (0..b.resamples)
        .map(|_| statistic.of(&resample(&mut rng, x)).unwrap())
        .collect();
    percentile_interval(statistic.of(x).unwrap(), replicates, b.confidence)
}

fn difference_by_materialising(
    b: &Bootstrap,
    x: &[f64],
    y: &[f64],
    statistic: Statistic,
) -> Interval {
    let mut rng = ChaCha8Rng::seed_from_u64(b.seed);
    let replicates = (0..b.resamples)
        .map(|_| {
            let of_x = statistic.of(&resample(&mut rng, x)).unwrap();
            of_x - statistic.of(&resample(&mut rng, y)).unwrap()
        })
        .collect();
    let estimate = statistic.of(x).unwrap() - statistic.of(y).unwrap();
    percentile_interval(estimate, replicates, b.confidence)
}

fn stratified_by_materialising(b: &Bootstrap, groups: &[&[f64]], statistic: Statistic) -> Interval {
    let mut rng = ChaCha8Rng::seed_from_u64(b.seed);
    let replicates = (0..b.resamples)
        .map(|_| {
            let pool: Vec<f64> = groups.iter().flat_map(|g| resample(&mut rng, g)).collect();
            statistic.of(&pool).unwrap()
        })
        .collect();
    let all: Vec<f64> = groups.iter().flat_map(|g| g.iter().copied()).collect();
    percentile_interval(statistic.of(&all).unwrap(), replicates, b.confidence)
}

/// Monte Carlo only (the caller picks sizes with more splits than resamples).
fn permutation_by_materialising(
    t: &PermutationTest,
    x: &[f64],
    y: &[f64],
    statistic: Statistic,
) -> f64 {
    let pooled = sorted(&[x, y].concat());
    let scale = pooled.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let observed = (statistic.of(x).unwrap() - statistic.of(y).unwrap()).abs();
    let threshold = observed - 1e-12 * scale;
    let mut rng = ChaCha8Rng::seed_from_u64(t.seed);
    let mut permutation: Vec<usize> = (0..pooled.len()).collect();
    let mut hits = 0_u64;
    for _ in 0..t.resamples {
        for i in 0..x.len() {
            let j = i + below(&mut rng, pooled.len() - i);
            permutation.swap(i, j);
        }
        let (in_x, in_y) = permutation.split_at(x.len());
        let group =
            |positions: &[usize]| -> Vec<f64> { positions.iter().map(|&p| pooled[p]).collect() };
        let difference = statistic.of(&group(in_x)).unwrap() - statistic.of(&group(in_y)).unwrap();
        hits += u64::from(difference.abs() >= threshold);
    }
    (hits + 1) as f64 / (f64::from(t.resamples) + 1.0)
}

fn bits(i: Interval) -> [u64; 3] {
    [i.estimate.to_bits(), i.low.to_bits(), i.high.to_bits()]
}

/// Integer samples with many ties (the exact path), or values that round differently when
/// added in another order (the batched path).
fn sample(sizes: std::ops::Range<usize>) -> impl Strategy<Value = Vec<f64>> {
    prop_oneof![
        prop::collection::vec(
            prop_oneof![
                4 => (0_i32..6).prop_map(f64::from),
                1 => Just(2000.0),
                1 => Just(-0.0),
                1 => (-3000_i32..3000).prop_map(f64::from),
            ],
            sizes.clone()
        ),
        prop::collection::vec(
            prop_oneof![Just(0.1), Just(0.7), Just(1e16), Just(3.0), -1e3..1e3_f64],
            sizes
        ),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn bootstrap_equals_materialised_resamples_bit_for_bit(
        x in sample(1..30),
        y in sample(1..30),
        seed in 0_u64..1000,
    ) {
        let b = Bootstrap::new(101, 0.9, seed).unwrap();
        for statistic in Statistic::ALL {
            prop_assert_eq!(
                bits(b.interval(&x, statistic).unwrap()),
                bits(interval_by_materialising(&b, &x, statistic))
            );
            prop_assert_eq!(
                bits(b.difference(&x, &y, statistic).unwrap()),
                bits(difference_by_materialising(&b, &x, &y, statistic))
            );
            prop_assert_eq!(
                bits(b.stratified_interval(&[&x, &y], statistic).unwrap()),
                bits(stratified_by_materialising(&b, &[&x, &y], statistic))
            );
        }
    }

    /// The shared draws of `Bootstrap::intervals` give each sample's own `interval`, bit
    /// for bit, whatever the mix of sizes and of integer and real samples.
    #[test]
    fn intervals_of_many_samples_equal_each_interval_bit_for_bit(
        samples in prop::collection::vec(sample(1..12), 1..6),
        seed in 0_u64..1000,
    ) {
        let b = Bootstrap::new(101, 0.9, seed).unwrap();
        let views: Vec<&[f64]> = samples.iter().map(Vec::as_slice).collect();
        for statistic in Statistic::ALL {
            let together = b.intervals(&views, statistic).unwrap();
            prop_assert_eq!(together.len(), samples.len());
            for (x, interval) in samples.iter().zip(together) {
                prop_assert_eq!(bits(interval), bits(b.interval(x, statistic).unwrap()));
            }
        }
    }

    #[test]
    fn permutation_equals_materialised_splits_bit_for_bit(
        x in sample(8..45),
        y in sample(8..45),
        seed in 0_u64..1000,
    ) {
        // At least 16 values pooled: C(16, 8) = 12 870 splits, more than the resamples.
        let t = PermutationTest::new(200, seed).unwrap();
        prop_assume!(!t.is_exact(x.len(), y.len()));
        for statistic in Statistic::ALL {
            prop_assert_eq!(
                t.p_value(&x, &y, statistic).unwrap().to_bits(),
                permutation_by_materialising(&t, &x, &y, statistic).to_bits()
            );
        }
    }
}
