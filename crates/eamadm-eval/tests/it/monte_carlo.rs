//! Monte-Carlo error of the claims (issue 34 item 4): the claims are judged again with three
//! other seeds for every random draw (the bootstrap's and the sign vectors'), and no verdict
//! and no endpoint of a deciding interval may move by a tenth of its margin or more — at most
//! 24 paired seeds they are exact (every sign vector counted, nothing resampled), so none moves
//! at all. The descriptive IQM intervals are bootstrap intervals; their endpoints are bounded
//! by 1 % of the data's range (issue 20). docs/paper-notes.md §10.1 and §10.5.

use eamadm_eval::Role;
use eamadm_eval::claims::{self, ClaimOptions, Judgement};
use eamadm_eval::scores::{FinalScore, RunOutcome};
use eamadm_eval::stats::paired::paired_difference;
use eamadm_eval::stats::{Bootstrap, Interval, SignFlipTest, Statistic};

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

/// One seed of `method` on `task` with these final steps (return −steps; a seed below the cap
/// is stable-reaching with a greedy SD that grows with the steps).
fn row(task: &str, method: &str, kind: &str, seed: u64, steps: f64) -> FinalScore {
    let reaches = steps < 2000.0;
    FinalScore {
        task: task.to_owned(),
        layout: String::new(),
        method: method.to_owned(),
        role: Role::Paper,
        kind: kind.to_owned(),
        seed,
        episodes: 200,
        final_window: 20,
        final_steps: steps,
        final_return: -steps,
        success_rate: if reaches { 1.0 } else { 0.0 },
        greedy_reached: reaches,
        greedy_steps: if reaches { steps as u64 } else { 2000 },
        outcome: if reaches {
            RunOutcome::Converged
        } else {
            RunOutcome::Collapsed
        },
        collapse_episode: (!reaches).then_some(150),
        fluctuation_steps: steps / 4.0,
        fluctuation_return: steps / 4.0,
        greedy_evaluations: 10,
        stable_reaching: Some(reaches),
        fluctuation_greedy_steps: reaches.then_some((steps - 50.0) / 10.0),
        fluctuation_greedy_return: reaches.then_some((steps - 50.0) / 10.0),
        env_steps_total: 1000,
        pretrain_env_steps: 0,
        step_cap: 2000,
        optimum_steps: Some(58),
        reaching_episodes: 10,
        reach_average_reward: None,
        reach_time: None,
        reach_retention_time: None,
        retention_decay: None,
    }
}

/// Both tasks: EA-MADM at `x`, three competitors at `y` shifted by 0, +3 and −1 steps a seed.
fn scores() -> Vec<FinalScore> {
    let mut rows = Vec::new();
    for (task, x, y) in [("task1", &TASK1_X, &TASK1_Y), ("task2", &TASK2_X, &TASK2_Y)] {
        for (seed, &steps) in x.iter().enumerate() {
            rows.push(row(task, "ea-madm", "ea_madm", seed as u64, steps));
        }
        for (method, kind, shift) in [
            ("epsilon-greedy", "epsilon_greedy", 0.0),
            ("epsilon-decreasing", "epsilon_decreasing", 3.0),
            ("softmax", "softmax", -1.0),
        ] {
            for (seed, &steps) in y.iter().enumerate() {
                let steps = if steps < 2000.0 { steps + shift } else { steps };
                rows.push(row(task, method, kind, seed as u64, steps));
            }
        }
    }
    rows
}

/// The claims' options with every random draw seeded by `seed`.
fn options(seed: u64) -> ClaimOptions {
    let defaults = ClaimOptions::default();
    ClaimOptions {
        bootstrap: Bootstrap {
            seed,
            ..defaults.bootstrap
        },
        sign_flip: SignFlipTest {
            seed,
            ..defaults.sign_flip
        },
        margins: crate::margins::maze_margins(&["task1", "task2"]),
        ..defaults
    }
}

fn judge(seed: u64) -> Vec<Judgement> {
    claims::judge(&scores(), &options(seed)).unwrap()
}

#[test]
fn no_verdict_or_deciding_endpoint_moves_with_three_other_seeds() {
    let base = judge(0);
    assert!(base.len() >= 6, "{}", base.len());
    for seed in [1, 2, 3] {
        let other = judge(seed);
        assert_eq!(base.len(), other.len());
        for (a, b) in base.iter().zip(&other) {
            let what = format!("{} {} seed {seed}", a.claim.id, a.task);
            assert_eq!(a.verdict, b.verdict, "{what}");
            assert_eq!(a.deciding, b.deciding, "{what}");
            for (ca, cb) in a.comparisons.iter().zip(&b.comparisons) {
                // A tenth of the margin (of 2 steps or 2 reward where there is none).
                let tenth = ca.margin.unwrap_or(2.0) / 10.0;
                let ends = |c: &claims::Comparison| [c.paired.low, c.paired.high];
                for (ea, eb) in ends(ca).into_iter().zip(ends(cb)) {
                    let moved = match (ea, eb) {
                        (Some(x), Some(y)) => (x - y).abs(),
                        (None, None) => 0.0,
                        _ => f64::INFINITY,
                    };
                    assert!(moved < tenth, "{what} {}: moved {moved}", ca.metric.column);
                    // Exact at 20 pairs: not a bit moves.
                    assert_eq!(moved, 0.0, "{what}");
                }
                assert!(ca.paired.exact, "{what}");
                assert_eq!(ca.p_value.to_bits(), cb.p_value.to_bits(), "{what}");
                assert_eq!(ca.p_holm.to_bits(), cb.p_holm.to_bits(), "{what}");
            }
        }
    }
}

/// The tolerance of a descriptive bootstrap endpoint, in units of the metric: 1 % of the
/// pooled data's range (20 steps on a 58–2000 step scale), and never below 0.2.
fn tolerance(x: &[f64], y: &[f64]) -> f64 {
    let (low, high) = x
        .iter()
        .chain(y)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    (0.01 * (high - low)).max(0.2)
}

/// Every bootstrap interval the claims compute for the pair `(x, y)` (descriptive now), and
/// the paired bootstrap the verdicts used before issue 34.
fn bootstrap_intervals(bootstrap: &Bootstrap, x: &[f64], y: &[f64]) -> [Interval; 4] {
    [
        bootstrap.interval(x, Statistic::Iqm).unwrap(),
        bootstrap.interval(y, Statistic::Iqm).unwrap(),
        bootstrap.difference(x, y, Statistic::Iqm).unwrap(),
        paired_difference(bootstrap, x, y, Statistic::Mean).unwrap(),
    ]
}

#[test]
fn descriptive_bootstrap_endpoints_stay_within_one_percent_of_the_range() {
    let reference = ClaimOptions::default().bootstrap;
    for (task, x, y) in [("task1", &TASK1_X, &TASK1_Y), ("task2", &TASK2_X, &TASK2_Y)] {
        let tolerance = tolerance(x, y);
        let base = bootstrap_intervals(&reference, x, y);
        for seed in 1..=4 {
            let other = Bootstrap {
                seed: reference.seed + seed,
                ..reference
            };
            for (which, (a, b)) in base
                .iter()
                .zip(bootstrap_intervals(&other, x, y))
                .enumerate()
            {
                assert_eq!(a.estimate, b.estimate, "the estimate does not resample");
                let moved = (a.low - b.low).abs().max((a.high - b.high).abs());
                assert!(
                    moved < tolerance,
                    "{task}, interval {which}, seed +{seed}: {a:?} vs {b:?} moved {moved} ≥ {tolerance}"
                );
            }
        }
    }
}
