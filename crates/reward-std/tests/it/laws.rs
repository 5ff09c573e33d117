//! Mathematical laws of both standardisations, as property tests.

use proptest::prelude::*;
use reward_std::{RunningStandardiser, cross_sectional};

/// Any finite `f64`, from subnormals to `±f64::MAX`.
fn any_finite() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

/// Reward-like values: the tasks' continuous and discrete rewards, and ties.
fn reward() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -100.0..100.0_f64,
        2 => prop::sample::select(vec![-100.0, -10.0, -1.0, 0.0, 1.0, 2.0, 10.0, 100.0]),
        1 => -1e6..1e6_f64,
    ]
}

/// Two-pass mean and population variance (with a correction pass for the mean).
fn two_pass(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let rough = xs.iter().sum::<f64>() / n;
    let mean = rough + xs.iter().map(|x| x - rough).sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    (mean, var)
}

proptest! {
    /// Eq. 12 is identically zero: the mean of cross-sectional z-scores vanishes for any
    /// finite input (and the z-scores have population variance 1 unless all are 0).
    #[test]
    fn cross_sectional_mean_is_always_zero(
        rewards in prop::collection::vec(prop_oneof![3 => reward(), 1 => any_finite()], 1..16),
    ) {
        let mut z = vec![0.0; rewards.len()];
        let mean = cross_sectional(&rewards, &mut z).unwrap();
        prop_assert!(mean.abs() < 1e-14, "Eq. 12 gave {mean} for {rewards:?}");
        prop_assert!(z.iter().all(|v| v.is_finite()));
        let m = z.len() as f64;
        let var = z.iter().map(|v| v * v).sum::<f64>() / m;
        let all_zero = z.iter().all(|&v| v == 0.0);
        prop_assert!(all_zero || (var - 1.0).abs() < 1e-12, "variance of z-scores {var}");
        // Samuelson: no z-score exceeds sqrt(m - 1).
        prop_assert!(z.iter().all(|v| v.abs() <= (m - 1.0).sqrt() + 1e-12));
    }

    /// z-scores do not change under a positive affine change of the rewards' units.
    #[test]
    fn cross_sectional_ignores_units(
        rewards in prop::collection::vec(-100.0..100.0_f64, 2..8),
        scale in 0.01..100.0_f64,
        shift in -100.0..100.0_f64,
    ) {
        let moved: Vec<f64> = rewards.iter().map(|r| scale * r + shift).collect();
        let (mut z, mut zm) = (vec![0.0; rewards.len()], vec![0.0; rewards.len()]);
        cross_sectional(&rewards, &mut z).unwrap();
        cross_sectional(&moved, &mut zm).unwrap();
        let (lo, hi) = rewards.iter().fold((f64::MAX, f64::MIN), |(l, h), &r| (l.min(r), h.max(r)));
        // Well-conditioned inputs only: a relative spread of 1e-6 at least.
        prop_assume!(hi - lo > 1e-6 * (1.0 + lo.abs().max(hi.abs())));
        for (a, b) in z.iter().zip(&zm) {
            prop_assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
    }

    /// The running standardisation equals the two-pass computation over the episode so far,
    /// at every step, for every sub-task.
    #[test]
    fn running_equals_two_pass(
        steps in (1_usize..4).prop_flat_map(|m| {
            prop::collection::vec(prop::collection::vec(reward(), m), 1..60)
        }),
    ) {
        let m = steps[0].len();
        let mut running = RunningStandardiser::new(m).unwrap();
        let mut history: Vec<Vec<f64>> = vec![Vec::new(); m];
        for step in &steps {
            let signal = running.push(step).unwrap();
            for k in 0..m {
                history[k].push(step[k]);
                let (mean, var) = two_pass(&history[k]);
                let scale = 1.0 + mean.abs() + var.sqrt();
                prop_assert!((running.means()[k] - mean).abs() <= 1e-12 * scale);
                prop_assert!((running.variances()[k] - var).abs() <= 1e-10 * scale * scale);
                // Compare z only where it is well-conditioned (σ not tiny against the values).
                let z = if var > 0.0 { (step[k] - mean) / var.sqrt() } else { 0.0 };
                if var == 0.0 || var.sqrt() > 1e-6 * scale {
                    prop_assert!((running.z_scores()[k] - z).abs() <= 1e-6, "{} vs {z}", running.z_scores()[k]);
                }
            }
            let n = history[0].len() as f64;
            prop_assert!(running.z_scores().iter().all(|z| z.abs() <= (n - 1.0).sqrt() + 1e-9));
            // The signal is the mean over sub-tasks of the z-scores.
            prop_assert_eq!(signal, running.z_scores().iter().sum::<f64>() / m as f64);
        }
    }

    /// A reset makes the standardiser indistinguishable from a fresh one.
    #[test]
    fn reset_equals_fresh(
        before in prop::collection::vec(prop::collection::vec(reward(), 2), 0..20),
        after in prop::collection::vec(prop::collection::vec(reward(), 2), 1..20),
    ) {
        let mut used = RunningStandardiser::new(2).unwrap();
        for step in &before {
            used.push(step).unwrap();
        }
        used.reset();
        let mut fresh = RunningStandardiser::new(2).unwrap();
        for step in &after {
            prop_assert_eq!(used.push(step).unwrap(), fresh.push(step).unwrap());
        }
        prop_assert_eq!(used, fresh);
    }
}
