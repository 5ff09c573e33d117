//! The laws of the streaming per-episode band (`eamadm_eval::summary::BandAccumulator`, which
//! `mean_band` is built on): it equals a two-pass computation (mean first, then squared
//! deviations) up to rounding, the order of the seeds changes it only at rounding level, bad
//! curves are refused with `mean_band`'s error values, and what it holds does not grow with the
//! number of seeds.

use eamadm_eval::summary::{BandAccumulator, BandPoint, StatsError, mean_band, student_t_975};
use proptest::prelude::*;

/// The band of `runs` computed in two passes per episode: the mean, then the sample variance
/// from the deviations to it.
fn two_pass_band(runs: &[Vec<f64>]) -> Vec<BandPoint> {
    let longest = runs.iter().map(Vec::len).max().unwrap_or(0);
    (0..longest)
        .map(|episode| {
            let column: Vec<f64> = runs
                .iter()
                .filter_map(|c| c.get(episode).copied())
                .collect();
            let n = column.len();
            let count = n as f64;
            let mean = column.iter().sum::<f64>() / count;
            let half_width = student_t_975(n - 1).map_or(0.0, |t| {
                let variance =
                    column.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0);
                t * variance.sqrt() / count.sqrt()
            });
            BandPoint {
                n,
                mean,
                lower: mean - half_width,
                upper: mean + half_width,
            }
        })
        .collect()
}

/// Whether two bands agree to `1e-9` relative to the size of the data (`scale`, the largest
/// magnitude of any value): a mean near zero of large values is a difference of large numbers,
/// so its rounding is relative to them.
fn agree(a: &[BandPoint], b: &[BandPoint], scale: f64) -> bool {
    let tolerance = 1e-9 * scale.max(1e-300);
    a.len() == b.len()
        && a.iter().zip(b).all(|(p, q)| {
            p.n == q.n
                && (p.mean - q.mean).abs() <= tolerance
                && (p.lower - q.lower).abs() <= tolerance
                && (p.upper - q.upper).abs() <= tolerance
        })
}

fn scale(runs: &[Vec<f64>]) -> f64 {
    runs.iter().flatten().fold(0.0, |m: f64, v| m.max(v.abs()))
}

/// Ragged curves of 1 to 12 seeds, 1 to 40 episodes each, values of very different sizes.
fn curves() -> impl Strategy<Value = Vec<Vec<f64>>> {
    let value = prop_oneof![-1e6..1e6_f64, -1.0..1.0_f64, 1e5..1e5 + 1.0];
    prop::collection::vec(prop::collection::vec(value, 1..40), 1..12)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn streaming_band_equals_the_two_pass_band(runs in curves()) {
        let mut accumulator = BandAccumulator::new();
        for curve in &runs {
            accumulator.push(curve)?;
        }
        let streamed = accumulator.band();
        prop_assert!(
            agree(&streamed, &two_pass_band(&runs), scale(&runs)),
            "{streamed:?}"
        );
        prop_assert_eq!(&mean_band(&runs)?, &streamed);
        prop_assert_eq!(accumulator.seeds(), runs.len());
        prop_assert_eq!(accumulator.episodes(), runs.iter().map(Vec::len).max().unwrap_or(0));
    }

    #[test]
    fn the_order_of_seeds_changes_the_band_only_by_rounding(
        (runs, shuffled) in curves().prop_flat_map(|runs| {
            let shuffled = Just(runs.clone()).prop_shuffle();
            (Just(runs), shuffled)
        }),
    ) {
        prop_assert!(agree(&mean_band(&runs)?, &mean_band(&shuffled)?, scale(&runs)));
    }

    #[test]
    fn the_held_state_depends_on_episodes_not_on_seeds(
        curve in prop::collection::vec(-100.0..100.0_f64, 1..30),
        seeds in 1_usize..200,
    ) {
        let mut accumulator = BandAccumulator::new();
        for seed in 0..seeds {
            let shifted: Vec<f64> = curve.iter().map(|v| v + seed as f64).collect();
            accumulator.push(&shifted)?;
        }
        // Per episode one count, one mean and one sum of squares, whatever the seeds.
        prop_assert_eq!(accumulator.episodes(), curve.len());
        prop_assert_eq!(accumulator.seeds(), seeds);
        prop_assert!(accumulator.band().iter().all(|p| p.n == seeds));
    }
}

#[test]
fn identical_seeds_give_a_band_of_width_zero() {
    let runs = vec![vec![0.1, 0.7, 1e6 + 0.3]; 7];
    for point in mean_band(&runs).unwrap() {
        assert_eq!(point.lower, point.mean);
        assert_eq!(point.upper, point.mean);
    }
}

#[test]
fn bad_curves_are_refused_with_mean_bands_errors_and_change_nothing() {
    let mut accumulator = BandAccumulator::new();
    accumulator.push(&[1.0, 2.0]).unwrap();
    let before = accumulator.clone();
    assert_eq!(
        accumulator.push(&[]),
        Err(StatsError::EmptyCurve { seed: 1 })
    );
    assert_eq!(
        accumulator
            .push(&[3.0, 4.0, f64::NAN])
            .unwrap_err()
            .to_string(),
        "seed 1, episode 2: value NaN is not finite"
    );
    assert_eq!(accumulator, before);
    let runs = vec![vec![1.0, 2.0], vec![3.0, 4.0, f64::NEG_INFINITY]];
    assert_eq!(
        mean_band(&runs),
        Err(StatsError::NonFiniteInCurve {
            seed: 1,
            episode: 2,
            value: f64::NEG_INFINITY
        })
    );
    assert_eq!(mean_band(&[]), Err(StatsError::NoSeeds));
    assert!(BandAccumulator::new().band().is_empty());
}
