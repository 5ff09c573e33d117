//! Monte-Carlo error of the claims' bootstrap (issue 20): rerun every interval the claims
//! compute (IQM of one method, IQM difference of two, mean paired difference) on fixed
//! hand-made data with other bootstrap seeds, at the claims' resample count, and bound how far
//! each endpoint moves. The tolerance and the measured spread are in docs/paper-notes.md §10.1.

use eamadm_eval::claims::ClaimOptions;
use eamadm_eval::stats::paired::paired_difference;
use eamadm_eval::stats::{Bootstrap, Interval, Statistic};

/// Task-I-like final steps: the optimum 58, detours of 2–6 steps, one seed at the 2000 cap.
const TASK1_X: [f64; 20] = [
    58.0, 58.0, 60.0, 58.0, 2000.0, 58.0, 64.0, 58.0, 58.0, 60.0, 58.0, 62.0, 58.0, 58.0, 60.0,
    58.0, 58.0, 58.0, 64.0, 58.0,
];
const TASK1_Y: [f64; 20] = [
    58.0, 60.0, 58.0, 58.0, 58.0, 58.0, 60.0, 58.0, 62.0, 58.0, 58.0, 58.0, 60.0, 58.0, 58.0, 58.0,
    66.0, 58.0, 58.0, 60.0,
];
/// Task-II-like final steps with many seeds at the cap (the worked case of §10.1, doubled).
const TASK2_X: [f64; 20] = [
    73.0, 73.0, 73.0, 73.0, 73.0, 75.0, 2000.0, 2000.0, 2000.0, 2000.0, 73.0, 77.0, 73.0, 81.0,
    73.0, 75.0, 2000.0, 73.0, 79.0, 73.0,
];
const TASK2_Y: [f64; 20] = [
    812.0, 2000.0, 1377.0, 2000.0, 954.0, 2000.0, 1640.0, 2000.0, 1105.0, 2000.0, 73.0, 2000.0,
    641.0, 2000.0, 1210.0, 98.0, 2000.0, 433.0, 2000.0, 75.0,
];

/// The tolerance of an endpoint, in units of the metric: 1 % of the pooled data's range (20
/// steps on a 58–2000 step scale), and never below the 2-step equivalence margin's tenth.
fn tolerance(x: &[f64], y: &[f64]) -> f64 {
    let (low, high) = x
        .iter()
        .chain(y)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    (0.01 * (high - low)).max(0.2)
}

/// Every interval the claims compute for the pair `(x, y)`.
fn claim_intervals(bootstrap: &Bootstrap, x: &[f64], y: &[f64]) -> [Interval; 4] {
    [
        bootstrap.interval(x, Statistic::Iqm).unwrap(),
        bootstrap.interval(y, Statistic::Iqm).unwrap(),
        bootstrap.difference(x, y, Statistic::Iqm).unwrap(),
        paired_difference(bootstrap, x, y, Statistic::Mean).unwrap(),
    ]
}

#[test]
fn every_claim_endpoint_is_stable_across_bootstrap_seeds() {
    let reference = ClaimOptions::default().bootstrap;
    for (task, x, y) in [("task1", &TASK1_X, &TASK1_Y), ("task2", &TASK2_X, &TASK2_Y)] {
        let tolerance = tolerance(x, y);
        let base = claim_intervals(&reference, x, y);
        for seed in 1..=4 {
            let other = Bootstrap {
                seed: reference.seed + seed,
                ..reference
            };
            for (which, (a, b)) in base.iter().zip(claim_intervals(&other, x, y)).enumerate() {
                assert_eq!(a.estimate, b.estimate, "the estimate does not resample");
                let moved = (a.low - b.low).abs().max((a.high - b.high).abs());
                eprintln!(
                    "{task} interval {which} seed +{seed}: moved {moved:.3} (tolerance {tolerance})"
                );
                assert!(
                    moved < tolerance,
                    "{task}, interval {which}, seed +{seed}: {a:?} vs {b:?} moved {moved} ≥ {tolerance}"
                );
            }
        }
    }
}
