//! Whole claim chains through the public claims API (`claims::judge`, `claims::rows`,
//! `claims::estimates`, `claims::outcome_rows`) against independent implementations: every
//! number of a C3 judgement on Task II (EA-MADM against three competitors: the
//! `stable_reaching` sign tests and the deciding greedy-SD comparisons in one Holm family, the
//! secondary training-curve comparisons in their own), the outcome rows (Wilson, sign test), a
//! C4 judgement on the robot decided by per-seed reaching (sign tests, Holm) and one where every
//! seed reaches (nine metric comparisons, average reward the one oriented higher-is-better, one
//! Holm family).
//!
//! The expected values were printed by `chains_reference.py` next to this file (Python 3.11.7,
//! scipy 1.17.1, statsmodels 0.15.0, numpy 2.4.6): `scipy.stats.trim_mean(x, 0.25)`,
//! `permutation_test` (exact, every sign vector) for the deciding mean paired difference's
//! beyond-margin, within-margin and two-sided p-values, every subset mean listed with numpy
//! for its interval, `mannwhitneyu`, `binomtest`, statsmodels' `multipletests(method="holm")`
//! and `proportion_confint(method="wilson")`. The inputs have ties (greedy SDs of 0, equal
//! values across methods), a competitor with two values (n = 2), a per-seed test with no
//! discordant seed, one with as many wins as losses and one-sided splits. Exact tests' p-values
//! (a count over an enumeration, then Holm) are compared bit for bit; other values to 1e-12.
//! The descriptive IQM bootstrap intervals are pinned too: the script draws the replicates
//! again (`ChaCha8`, Lemire, as `eamadm_eval::stats` documents) and takes
//! `numpy.quantile(…, method="linear")` of them. The last test does the same for the default
//! run's paths (20 seeds: 10 000 random splits and resamples, all 2²⁰ sign vectors).

use eamadm_eval::Role;
use eamadm_eval::claims::{
    self, ClaimOptions, Comparison, Judgement, Margin, Margins, ReachingComparison,
};
use eamadm_eval::scores::{FinalScore, RunOutcome};
use eamadm_eval::stats::paired::{differences, paired_difference};
use eamadm_eval::stats::{
    Alternative, Bootstrap, PermutationTest, SignFlipMeans, SignFlipTest, Statistic,
};

/// One seed of C3: (`stable_reaching`, `fluctuation_greedy_steps`, `fluctuation_greedy_return`,
/// `fluctuation_steps`, `fluctuation_return`); a seed that is not stable-reaching has no greedy SD.
type C3Seed = (bool, Option<f64>, Option<f64>, f64, f64);

const fn stable(greedy_steps: f64, greedy_return: f64, steps: f64, ret: f64) -> C3Seed {
    (true, Some(greedy_steps), Some(greedy_return), steps, ret)
}

const fn stuck(steps: f64, ret: f64) -> C3Seed {
    (false, None, None, steps, ret)
}

/// The C3 scores of `chains_reference.py` (`C3`), method by method: (label, kind, seeds 0–7).
const C3: [(&str, &str, [C3Seed; 8]); 4] = [
    (
        "ea-madm",
        "ea_madm",
        [
            stable(0.0, 0.0, 12.0, 11.0),
            stable(0.0, 0.5, 9.5, 9.0),
            stable(1.5, 1.5, 14.0, 13.5),
            stable(0.0, 0.0, 9.5, 9.0),
            stable(2.5, 3.0, 30.0, 29.0),
            stuck(250.0, 240.0),
            stable(0.0, 0.0, 11.0, 11.0),
            stable(4.0, 4.5, 13.0, 12.5),
        ],
    ),
    (
        "epsilon-greedy",
        "epsilon_greedy",
        [
            stable(2.0, 2.5, 40.0, 39.0),
            stuck(300.0, 290.0),
            stuck(310.0, 300.0),
            stable(3.0, 3.0, 42.5, 41.0),
            stuck(305.0, 295.0),
            stuck(299.0, 290.0),
            stuck(320.0, 310.0),
            stuck(301.0, 292.5),
        ],
    ),
    (
        "epsilon-decreasing",
        "epsilon_decreasing",
        [
            stable(0.0, 0.5, 20.0, 19.0),
            stable(1.0, 1.0, 18.0, 18.0),
            stable(1.5, 1.5, 14.0, 13.5),
            stable(0.0, 0.5, 25.0, 24.0),
            stuck(30.0, 29.0),
            stuck(22.0, 21.0),
            stuck(200.0, 190.0),
            stuck(210.0, 205.0),
        ],
    ),
    (
        "softmax",
        "softmax",
        [
            stable(5.0, 5.0, 35.0, 34.0),
            stable(4.0, 4.5, 33.0, 33.0),
            stuck(280.0, 270.0),
            stable(6.0, 6.0, 36.0, 35.5),
            stable(7.5, 7.0, 40.0, 39.0),
            stable(3.0, 3.0, 31.0, 30.0),
            stable(5.0, 5.0, 35.0, 34.0),
            stable(8.0, 8.5, 38.0, 37.0),
        ],
    ),
];

/// A run with the given label, kind and seed; every column the chains do not read is fixed.
fn run(task: &str, method: &str, kind: &str, seed: u64) -> FinalScore {
    FinalScore {
        task: task.to_owned(),
        layout: String::new(),
        method: method.to_owned(),
        role: Role::Paper,
        kind: kind.to_owned(),
        seed,
        episodes: 200,
        final_window: 20,
        final_steps: 100.0,
        final_return: -100.0,
        success_rate: 1.0,
        greedy_reached: true,
        greedy_steps: 73,
        outcome: RunOutcome::Converged,
        collapse_episode: None,
        fluctuation_steps: 0.0,
        fluctuation_return: 0.0,
        greedy_evaluations: 10,
        stable_reaching: Some(true),
        fluctuation_greedy_steps: Some(0.0),
        fluctuation_greedy_return: Some(0.0),
        env_steps_total: 20_000,
        pretrain_env_steps: 0,
        step_cap: 2000,
        optimum_steps: Some(73),
        reaching_episodes: 100,
        reach_average_reward: None,
        reach_time: None,
        reach_retention_time: None,
        retention_decay: None,
    }
}

/// The C3 scores as `final-scores.csv` rows of Task II; a run is `converged` exactly when it
/// is stable-reaching (for the outcome rows).
fn c3_scores() -> Vec<FinalScore> {
    let mut rows = Vec::new();
    for (method, kind, seeds) in C3 {
        for (seed, (is_stable, greedy_steps, greedy_return, steps, ret)) in (0_u64..).zip(seeds) {
            rows.push(FinalScore {
                stable_reaching: Some(is_stable),
                fluctuation_greedy_steps: greedy_steps,
                fluctuation_greedy_return: greedy_return,
                fluctuation_steps: steps,
                fluctuation_return: ret,
                outcome: if is_stable {
                    RunOutcome::Converged
                } else {
                    RunOutcome::Collapsed
                },
                collapse_episode: (!is_stable).then_some(150),
                ..run("task2", method, kind, seed)
            });
        }
    }
    rows
}

/// Exact enumeration everywhere: C(16, 8) = 12 870 splits ≤ 20 000, 2⁸ sign vectors ≤ 2 000.
/// Margins as the reference script judged: 2 steps on Task II's step metrics, none on the
/// return metrics nor on the robot's (their TOST p-values are then blank).
fn options() -> ClaimOptions {
    let mut margins = Margins::new();
    let steps = |column: &str| Margin {
        column: column.to_owned(),
        value: 2.0,
        reason: "the shortest detour on a grid".to_owned(),
    };
    margins
        .insert(
            "task2",
            &[
                steps("final_steps"),
                steps("fluctuation_steps"),
                steps("fluctuation_greedy_steps"),
            ],
        )
        .unwrap();
    ClaimOptions {
        margins,
        bootstrap: Bootstrap::new(2_000, 0.95, 7).unwrap(),
        sign_flip: SignFlipTest::new(2_000, 7).unwrap(),
        alpha: 0.05,
    }
}

/// `|actual − expected| ≤ 1e-12 · max(1, |expected|)`.
fn close(actual: f64, expected: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= 1e-12 * expected.abs().max(1.0),
        "{what}: {actual} vs {expected}"
    );
}

/// Bit-for-bit equality (a p-value of an exact test: a count over the enumeration).
fn exact(actual: f64, expected: f64, what: &str) {
    assert_eq!(
        actual.to_bits(),
        expected.to_bits(),
        "{what}: {actual} vs {expected}"
    );
}

/// What `chains_reference.py` prints for one comparison.
struct Expected {
    metric: &'static str,
    versus: &'static str,
    n: (usize, usize),
    paired_n: usize,
    /// `numpy.mean(d)` of the paired differences.
    estimate: f64,
    /// Every non-empty subset's mean of `d` listed with numpy and ranked: the one at rank
    /// ⌊0.025 · 2ⁿ⌋ from each end (`None`: too few pairs).
    interval: Option<(f64, f64)>,
    /// `min(1, 2 min(p_less(−m), p_greater(m)))` of exact sign-flip
    /// `permutation_test(permutation_type="samples")` p-values (m = 0 without a margin).
    p_value: f64,
    /// `multipletests(method="holm")` over the family (the informative comparisons, and C3's
    /// sign tests); `None` for an uninformative comparison.
    p_holm: Option<f64>,
    /// Exact sign-flip two-sided p of the mean.
    paired_p_value: f64,
    margin: Option<f64>,
    /// `min(1, 2 max(p_greater(−m), p_less(m)))`.
    p_equivalence: Option<f64>,
    /// Holm over the informative comparisons' equivalence p-values (1 without a margin).
    p_equivalence_holm: Option<f64>,
    informative: bool,
    /// `mannwhitneyu(y, x).statistic / (n m)` (lower is better).
    p_improvement: f64,
    /// `trim_mean(x, 0.25) − trim_mean(y, 0.25)`.
    iqm_difference: f64,
    /// The IQM difference's percentile interval: the replicates drawn again in Python by the
    /// documented draw order, `numpy.quantile(…, method="linear")` of them.
    iqm_ci: (f64, f64),
}

fn check_comparison(actual: &Comparison, expected: &Expected) {
    let what = format!("{} vs {}", expected.metric, expected.versus);
    assert_eq!(
        (actual.metric.column, actual.versus.as_str(), actual.n),
        (expected.metric, expected.versus, expected.n),
        "{what}"
    );
    let paired = &actual.paired;
    assert_eq!(paired.n, expected.paired_n, "{what}");
    close(paired.estimate, expected.estimate, &what);
    match expected.interval {
        Some((low, high)) => {
            close(paired.low.unwrap(), low, &what);
            close(paired.high.unwrap(), high, &what);
        }
        None => assert_eq!((paired.low, paired.high), (None, None), "{what}"),
    }
    exact(actual.p_value, expected.p_value, &what);
    exact(paired.p_beyond, expected.p_value, &what);
    assert_eq!(actual.informative, expected.informative, "{what}");
    match expected.p_holm {
        Some(p) => exact(actual.p_holm, p, &what),
        None => exact(actual.p_holm, actual.p_value, &what),
    }
    exact(paired.p_value, expected.paired_p_value, &what);
    assert!(paired.exact, "{what}");
    assert_eq!(actual.margin, expected.margin, "{what}");
    assert_eq!(
        paired.p_equivalence.map(f64::to_bits),
        expected.p_equivalence.map(f64::to_bits),
        "{what}"
    );
    assert_eq!(
        paired.p_equivalence_holm.map(f64::to_bits),
        expected.p_equivalence_holm.map(f64::to_bits),
        "{what}"
    );
    close(actual.p_improvement, expected.p_improvement, &what);
    close(
        actual.iqm_difference.estimate,
        expected.iqm_difference,
        &what,
    );
    close(actual.iqm_difference.low, expected.iqm_ci.0, &what);
    close(actual.iqm_difference.high, expected.iqm_ci.1, &what);
}

/// (versus, n, reached, discordant, `binomtest` p, Holm p) of a per-seed test.
type ExpectedTest = (&'static str, usize, (usize, usize), (u64, u64), f64, f64);

fn check_tests(actual: &[ReachingComparison], metric: &str, expected: &[ExpectedTest]) {
    assert_eq!(actual.len(), expected.len());
    for (test, &(versus, n, reached, discordant, p, p_holm)) in actual.iter().zip(expected) {
        assert_eq!(
            (
                test.metric,
                test.versus.as_str(),
                test.n,
                test.reached,
                test.discordant
            ),
            (metric, versus, n, reached, discordant)
        );
        exact(test.p_value, p, versus);
        exact(test.p_holm, p_holm, versus);
    }
}

fn c3_judgement(scores: &[FinalScore]) -> Judgement {
    claims::judge(scores, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C3" && j.method == "ea-madm")
        .unwrap()
}

#[test]
fn c3_stable_reaching_sign_tests_and_holm_match_scipy_and_statsmodels() {
    let judgement = c3_judgement(&c3_scores());
    // binomtest(5, 5), binomtest(3, 3), binomtest(1, 2): a one-sided split, another, and as
    // many wins as losses; Holm in one family with C3's informative greedy-SD comparisons
    // (issue 34: C3 gets one family), multipletests(…, method="holm").
    check_tests(
        &judgement.reaching,
        claims::STABLE_REACHING,
        &[
            ("epsilon-greedy", 8, (7, 2), (5, 0), 0.0625, 0.4375),
            ("epsilon-decreasing", 8, (7, 4), (3, 0), 0.25, 1.0),
            ("softmax", 8, (7, 7), (1, 1), 1.0, 1.0),
        ],
    );
    // claims.csv carries each as a `stable_reaching` row: the share of seeds EA-MADM is
    // stable-reaching on minus the competitor's, the raw and the Holm p.
    let rows = claims::rows(std::slice::from_ref(&judgement), &[]);
    let stable_rows: Vec<_> = rows
        .iter()
        .filter(|r| r.metric == claims::STABLE_REACHING)
        .collect();
    let expected = [(0.625, 0.0625, 0.4375), (0.375, 0.25, 1.0), (0.0, 1.0, 1.0)];
    assert_eq!(stable_rows.len(), expected.len());
    for (row, (estimate, p, p_holm)) in stable_rows.iter().zip(expected) {
        close(row.estimate.unwrap(), estimate, &row.versus);
        exact(row.p_value.unwrap(), p, &row.versus);
        exact(row.p_holm.unwrap(), p_holm, &row.versus);
        assert_eq!(row.n, 8);
    }
}

#[test]
fn c3_greedy_sd_comparisons_match_scipy_and_statsmodels() {
    let options = options();
    assert!(options.sign_flip.is_exact_for(8, Statistic::Mean));
    let judgement = c3_judgement(&c3_scores());
    let expected = [
        Expected {
            metric: "fluctuation_greedy_steps",
            versus: "epsilon-greedy",
            n: (7, 2),
            paired_n: 2,
            estimate: -2.5,
            interval: None,
            p_value: 1.0,
            p_holm: Some(1.0),
            paired_p_value: 0.5,
            margin: Some(2.0),
            p_equivalence: Some(1.0),
            p_equivalence_holm: Some(1.0),
            informative: true,
            p_improvement: 0.7857142857142857,
            iqm_difference: -1.7,
            iqm_ci: (-3.0, -0.10000000000000009),
        },
        Expected {
            metric: "fluctuation_greedy_steps",
            versus: "epsilon-decreasing",
            n: (7, 4),
            paired_n: 4,
            estimate: -0.25,
            interval: None,
            p_value: 1.0,
            p_holm: Some(1.0),
            paired_p_value: 1.0,
            margin: Some(2.0),
            p_equivalence: Some(0.125),
            p_equivalence_holm: Some(0.75),
            informative: true,
            p_improvement: 0.44642857142857145,
            iqm_difference: 0.30000000000000004,
            iqm_ci: (-1.0, 2.1),
        },
        Expected {
            metric: "fluctuation_greedy_steps",
            versus: "softmax",
            n: (7, 7),
            paired_n: 6,
            estimate: -4.833333333333333,
            interval: Some((-6.0, -4.0)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: Some(2.0),
            p_equivalence: Some(1.0),
            p_equivalence_holm: Some(1.0),
            informative: true,
            p_improvement: 0.9693877551020408,
            iqm_difference: -4.7,
            iqm_ci: (-6.4, -2.5000000000000004),
        },
        Expected {
            metric: "fluctuation_greedy_return",
            versus: "epsilon-greedy",
            n: (7, 2),
            paired_n: 2,
            estimate: -2.75,
            interval: None,
            p_value: 0.5,
            p_holm: Some(1.0),
            paired_p_value: 0.5,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.75,
            iqm_difference: -1.75,
            iqm_ci: (-2.8, 0.0),
        },
        Expected {
            metric: "fluctuation_greedy_return",
            versus: "epsilon-decreasing",
            n: (7, 4),
            paired_n: 4,
            estimate: -0.375,
            interval: None,
            p_value: 0.25,
            p_holm: Some(1.0),
            paired_p_value: 0.25,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.5535714285714286,
            iqm_difference: 0.25,
            iqm_ci: (-0.95, 2.0),
        },
        Expected {
            metric: "fluctuation_greedy_return",
            versus: "softmax",
            n: (7, 7),
            paired_n: 6,
            estimate: -4.666666666666667,
            interval: Some((-6.0, -4.0)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.9591836734693877,
            iqm_difference: -4.5,
            iqm_ci: (-6.3, -2.4),
        },
    ];
    assert_eq!(judgement.comparisons.len(), expected.len());
    for (actual, expected) in judgement.comparisons.iter().zip(&expected) {
        check_comparison(actual, expected);
    }
    // claims.csv's comparison rows carry the same numbers.
    let rows = claims::rows(std::slice::from_ref(&judgement), &[]);
    for expected in &expected {
        let row = rows
            .iter()
            .find(|r| r.metric == expected.metric && r.versus == expected.versus)
            .unwrap();
        close(row.estimate.unwrap(), expected.estimate, expected.metric);
        assert_eq!(
            row.ci_low.zip(row.ci_high).is_some(),
            expected.interval.is_some()
        );
        exact(row.p_value.unwrap(), expected.p_value, expected.metric);
        assert_eq!(
            row.p_holm.map(f64::to_bits),
            expected.p_holm.map(f64::to_bits)
        );
        close(
            row.p_improvement.unwrap(),
            expected.p_improvement,
            expected.metric,
        );
        assert_eq!(row.paired_n, Some(expected.paired_n));
        exact(
            row.paired_p_value.unwrap(),
            expected.paired_p_value,
            expected.metric,
        );
        assert_eq!(
            row.p_equivalence_holm.map(f64::to_bits),
            expected.p_equivalence_holm.map(f64::to_bits)
        );
        assert_eq!(row.informative, Some(expected.informative));
        close(
            row.iqm_difference.unwrap(),
            expected.iqm_difference,
            expected.metric,
        );
    }
}

#[test]
fn c3_secondary_curve_sd_comparisons_match_scipy_and_statsmodels() {
    let judgement = c3_judgement(&c3_scores());
    let expected = [
        Expected {
            metric: "fluctuation_steps",
            versus: "epsilon-greedy",
            n: (8, 8),
            paired_n: 8,
            estimate: -196.0625,
            interval: Some((-297.6666666666667, -41.0)),
            p_value: 0.0078125,
            p_holm: Some(0.046875),
            paired_p_value: 0.0078125,
            margin: Some(2.0),
            p_equivalence: Some(1.0),
            p_equivalence_holm: Some(1.0),
            informative: true,
            p_improvement: 0.96875,
            iqm_difference: -288.75,
            iqm_ci: (-295.753125, -94.87187500000002),
        },
        Expected {
            metric: "fluctuation_steps",
            versus: "epsilon-decreasing",
            n: (8, 8),
            paired_n: 8,
            estimate: -23.75,
            interval: Some((-131.33333333333334, 106.25)),
            p_value: 0.78125,
            p_holm: Some(1.0),
            paired_p_value: 0.75,
            margin: Some(2.0),
            p_equivalence: Some(1.0),
            p_equivalence_holm: Some(1.0),
            informative: true,
            p_improvement: 0.78125,
            iqm_difference: -11.75,
            iqm_ci: (-104.878125, 52.256249999999966),
        },
        Expected {
            metric: "fluctuation_steps",
            versus: "softmax",
            n: (8, 8),
            paired_n: 8,
            estimate: -22.375,
            interval: Some((-144.5, 97.0)),
            p_value: 0.5078125,
            p_holm: Some(1.0),
            paired_p_value: 0.5078125,
            margin: Some(2.0),
            p_equivalence: Some(1.0),
            p_equivalence_holm: Some(1.0),
            informative: true,
            p_improvement: 0.890625,
            iqm_difference: -23.5,
            iqm_ci: (-85.628125, 40.75),
        },
        Expected {
            metric: "fluctuation_return",
            versus: "epsilon-greedy",
            n: (8, 8),
            paired_n: 8,
            estimate: -190.3125,
            interval: Some((-288.5, -41.0)),
            p_value: 0.0078125,
            p_holm: Some(0.046875),
            paired_p_value: 0.0078125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.96875,
            iqm_difference: -279.875,
            iqm_ci: (-286.503125, -92.12187500000002),
        },
        Expected {
            metric: "fluctuation_return",
            versus: "epsilon-decreasing",
            n: (8, 8),
            paired_n: 8,
            estimate: -23.0625,
            interval: Some((-126.5, 102.0)),
            p_value: 0.75,
            p_holm: Some(1.0),
            paired_p_value: 0.75,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.78125,
            iqm_difference: -11.25,
            iqm_ci: (-100.64687499999997, 50.13437499999995),
        },
        Expected {
            metric: "fluctuation_return",
            versus: "softmax",
            n: (8, 8),
            paired_n: 8,
            estimate: -22.1875,
            interval: Some((-139.75, 92.75)),
            p_value: 0.5078125,
            p_holm: Some(1.0),
            paired_p_value: 0.5078125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.890625,
            iqm_difference: -23.125,
            iqm_ci: (-83.0, 38.25),
        },
    ];
    assert_eq!(judgement.secondary.len(), expected.len());
    for (actual, expected) in judgement.secondary.iter().zip(&expected) {
        check_comparison(actual, expected);
    }
}

#[test]
fn c3_single_method_iqms_and_intervals_match_scipy_trim_mean_and_numpy_quantile() {
    let scores = c3_scores();
    let estimates = claims::estimates(&scores, &options()).unwrap();
    // (method, metric, trim_mean(x, 0.25), seeds with a value, the percentile interval of
    // the replicates drawn again in Python).
    let expected = [
        ("ea-madm", "fluctuation_greedy_steps", 0.8, 7, (0.0, 2.4)),
        (
            "ea-madm",
            "fluctuation_greedy_return",
            1.0,
            7,
            (0.09750000000000442, 2.8),
        ),
        (
            "ea-madm",
            "fluctuation_steps",
            12.5,
            8,
            (10.25, 76.25624999999997),
        ),
        ("ea-madm", "fluctuation_return", 12.0, 8, (10.0, 73.375)),
        (
            "epsilon-greedy",
            "fluctuation_greedy_steps",
            2.5,
            2,
            (2.0, 3.0),
        ),
        (
            "epsilon-greedy",
            "fluctuation_greedy_return",
            2.75,
            2,
            (2.5, 3.0),
        ),
        (
            "epsilon-greedy",
            "fluctuation_steps",
            301.25,
            8,
            (170.0, 308.75),
        ),
        (
            "epsilon-greedy",
            "fluctuation_return",
            291.875,
            8,
            (164.9875, 298.75),
        ),
        (
            "epsilon-decreasing",
            "fluctuation_greedy_steps",
            0.5,
            4,
            (0.0, 1.5),
        ),
        (
            "epsilon-decreasing",
            "fluctuation_greedy_return",
            0.75,
            4,
            (0.5, 1.5),
        ),
        (
            "epsilon-decreasing",
            "fluctuation_steps",
            24.25,
            8,
            (18.75, 117.51249999999993),
        ),
        (
            "epsilon-decreasing",
            "fluctuation_return",
            23.25,
            8,
            (18.25, 114.51249999999993),
        ),
        ("softmax", "fluctuation_greedy_steps", 5.5, 7, (4.2, 7.0)),
        (
            "softmax",
            "fluctuation_greedy_return",
            5.5,
            7,
            (4.297500000000004, 7.0),
        ),
        ("softmax", "fluctuation_steps", 36.0, 8, (33.5, 98.25)),
        ("softmax", "fluctuation_return", 35.125, 8, (32.875, 95.0)),
    ];
    for (method, metric, iqm, n, (low, high)) in expected {
        let estimate = estimates
            .iter()
            .find(|e| e.method == method && e.metric == metric)
            .unwrap();
        assert_eq!((estimate.n, estimate.seeds), (n, 8), "{method} {metric}");
        let interval = estimate.iqm.unwrap();
        close(interval.estimate, iqm, metric);
        close(interval.low, low, metric);
        close(interval.high, high, metric);
    }
}

#[test]
fn outcome_rows_match_statsmodels_wilson_and_scipy_binomtest() {
    let rows = claims::outcome_rows(&c3_scores()).unwrap();
    // proportion_confint(k, 8, alpha=0.05, method="wilson").
    let shares = [
        ("ea-madm", 0.875, 0.5291118177871466, 0.9775825085499434),
        (
            "epsilon-greedy",
            0.25,
            0.071479212752109,
            0.5907245696898311,
        ),
        (
            "epsilon-decreasing",
            0.5,
            0.2152160622138775,
            0.7847839377861225,
        ),
        ("softmax", 0.875, 0.5291118177871466, 0.9775825085499434),
    ];
    for (method, share, low, high) in shares {
        let row = rows
            .iter()
            .find(|r| r.method == method && r.versus.is_empty())
            .unwrap();
        assert_eq!((row.n, row.estimate), (8, Some(share)));
        close(row.ci_low.unwrap(), low, method);
        close(row.ci_high.unwrap(), high, method);
    }
    // Paired by seed, not adjusted: binomtest on the discordant seeds.
    for (versus, estimate, p) in [
        ("epsilon-greedy", 0.625, 0.0625),
        ("epsilon-decreasing", 0.375, 0.25),
        ("softmax", 0.0, 1.0),
    ] {
        let row = rows
            .iter()
            .find(|r| r.method == "ea-madm" && r.versus == versus)
            .unwrap();
        close(row.estimate.unwrap(), estimate, versus);
        exact(row.p_value.unwrap(), p, versus);
        assert_eq!((row.n, row.p_holm), (8, None));
    }
}

/// The seeds (of 0–9) each method reaches the target on: `C4_REACHES` of the script.
const C4: [(&str, &str, &[u64]); 4] = [
    ("ea-madm", "ea_madm", &[9]),
    ("epsilon-greedy", "epsilon_greedy", &[0, 1, 2, 3, 4, 5, 6]),
    ("epsilon-decreasing", "epsilon_decreasing", &[9]),
    ("softmax", "softmax", &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]),
];

#[test]
fn c4_reached_sign_tests_and_holm_match_scipy_and_statsmodels() {
    let mut scores = Vec::new();
    for (method, kind, reaching) in C4 {
        for seed in 0..10 {
            let reaches = reaching.contains(&seed);
            let value = reaches.then_some(1.0 + seed as f64);
            scores.push(FinalScore {
                greedy_reached: reaches,
                reaching_episodes: if reaches { 10 } else { 0 },
                reach_average_reward: value,
                reach_time: value,
                reach_retention_time: value,
                retention_decay: value.map(|v| -v),
                ..run("robot", method, kind, seed)
            });
        }
    }
    let judgement = claims::judge(&scores, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C4" && j.method == "ea-madm")
        .unwrap();
    // EA-MADM has one seed with a C4 value: judged on per-seed reaching. binomtest(1, 8),
    // no discordant seed (p = 1), binomtest(0, 9); multipletests([0.0703125, 1, 0.00390625],
    // method="holm") = [0.140625, 1, 0.01171875].
    assert!(judgement.comparisons.is_empty());
    check_tests(
        &judgement.reaching,
        claims::REACHED,
        &[
            ("epsilon-greedy", 10, (1, 7), (1, 7), 0.0703125, 0.140625),
            ("epsilon-decreasing", 10, (1, 1), (0, 0), 1.0, 1.0),
            ("softmax", 10, (1, 10), (0, 9), 0.00390625, 0.01171875),
        ],
    );
    let rows = claims::rows(std::slice::from_ref(&judgement), &[]);
    let reached: Vec<_> = rows
        .iter()
        .filter(|r| r.metric == claims::REACHED)
        .collect();
    for (row, (estimate, p_holm)) in
        reached
            .iter()
            .zip([(-0.6, 0.140625), (0.0, 1.0), (-0.9, 0.01171875)])
    {
        close(row.estimate.unwrap(), estimate, &row.versus);
        exact(row.p_holm.unwrap(), p_holm, &row.versus);
    }
    assert_eq!(reached.len(), 3);
}

/// C4 per seed when every method reaches on every seed: (`reach_average_reward`,
/// `reach_time`, `retention_decay`), `C4_ALL_REACH` of the script.
type C4Seed = (f64, f64, f64);

const C4_ALL_REACH: [(&str, &str, [C4Seed; 6]); 4] = [
    (
        "ea-madm",
        "ea_madm",
        [
            (0.52, 41.0, -0.012),
            (0.61, 35.5, -0.020),
            (0.48, 44.0, -0.008),
            (0.61, 36.0, -0.015),
            (0.55, 39.5, -0.020),
            (0.70, 31.0, -0.025),
        ],
    ),
    (
        "epsilon-greedy",
        "epsilon_greedy",
        [
            (0.40, 52.0, -0.004),
            (0.45, 47.5, 0.001),
            (0.38, 55.0, -0.006),
            (0.52, 41.0, -0.010),
            (0.41, 50.0, 0.002),
            (0.44, 49.0, -0.003),
        ],
    ),
    (
        "epsilon-decreasing",
        "epsilon_decreasing",
        [
            (0.50, 42.0, -0.010),
            (0.58, 37.0, -0.018),
            (0.47, 45.5, -0.009),
            (0.60, 36.0, -0.012),
            (0.55, 39.5, -0.021),
            (0.66, 33.0, -0.019),
        ],
    ),
    (
        "softmax",
        "softmax",
        [
            (0.45, 47.0, -0.007),
            (0.49, 45.0, -0.011),
            (0.43, 49.5, -0.002),
            (0.51, 42.5, -0.009),
            (0.47, 46.0, -0.005),
            (0.53, 40.0, -0.013),
        ],
    ),
];

#[test]
fn c4_metric_comparisons_when_every_seed_reaches_match_scipy_and_statsmodels() {
    let mut scores = Vec::new();
    for (method, kind, seeds) in C4_ALL_REACH {
        for (seed, (reward, time, decay)) in (0_u64..).zip(seeds) {
            scores.push(FinalScore {
                reach_average_reward: Some(reward),
                reach_time: Some(time),
                reach_retention_time: Some(time / 10.0),
                retention_decay: Some(decay),
                ..run("robot", method, kind, seed)
            });
        }
    }
    let judgement = claims::judge(&scores, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C4" && j.method == "ea-madm")
        .unwrap();
    // Every method reaches on every seed: no per-seed test, nine metric comparisons (average
    // reward oriented higher-is-better, the other two lower), one Holm family, no margins.
    assert!(judgement.reaching.is_empty());
    let expected = [
        Expected {
            metric: "reach_average_reward",
            versus: "epsilon-greedy",
            n: (6, 6),
            paired_n: 6,
            estimate: 0.145,
            interval: Some((0.08999999999999997, 0.25999999999999995)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.9583333333333334,
            iqm_difference: 0.14750000000000002,
            iqm_ci: (0.0675, 0.23000000000000004),
        },
        Expected {
            metric: "reach_average_reward",
            versus: "epsilon-decreasing",
            n: (6, 6),
            paired_n: 6,
            estimate: 0.01833333333333333,
            interval: Some((0.0, 0.039999999999999925)),
            p_value: 0.0625,
            p_holm: Some(0.28125),
            paired_p_value: 0.0625,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.5972222222222222,
            iqm_difference: 0.015000000000000013,
            iqm_ci: (-0.07000000000000006, 0.1100624999999997),
        },
        Expected {
            metric: "reach_average_reward",
            versus: "softmax",
            n: (6, 6),
            paired_n: 6,
            estimate: 0.09833333333333333,
            interval: Some((0.04999999999999999, 0.16999999999999993)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.8888888888888888,
            iqm_difference: 0.09250000000000003,
            iqm_ci: (0.025000000000000022, 0.1750624999999997),
        },
        Expected {
            metric: "reach_time",
            versus: "epsilon-greedy",
            n: (6, 6),
            paired_n: 6,
            estimate: -11.25,
            interval: Some((-18.0, -5.0)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.9583333333333334,
            iqm_difference: -11.625,
            iqm_ci: (-16.628124999999994, -5.5),
        },
        Expected {
            metric: "reach_time",
            versus: "epsilon-decreasing",
            n: (6, 6),
            paired_n: 6,
            estimate: -1.0,
            interval: Some((-2.0, 0.0)),
            p_value: 0.125,
            p_holm: Some(0.28125),
            paired_p_value: 0.125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.5833333333333334,
            iqm_difference: -0.625,
            iqm_ci: (-6.375, 4.875),
        },
        Expected {
            metric: "reach_time",
            versus: "softmax",
            n: (6, 6),
            paired_n: 6,
            estimate: -7.166666666666667,
            interval: Some((-9.5, -5.5)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.9166666666666666,
            iqm_difference: -7.125,
            iqm_ci: (-12.003124999999994, -2.0),
        },
        Expected {
            metric: "retention_decay",
            versus: "epsilon-greedy",
            n: (6, 6),
            paired_n: 6,
            estimate: -0.013333333333333334,
            interval: Some((-0.022000000000000002, -0.002)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.9722222222222222,
            iqm_difference: -0.013750000000000002,
            iqm_ci: (-0.02, -0.0065),
        },
        Expected {
            metric: "retention_decay",
            versus: "epsilon-decreasing",
            n: (6, 6),
            paired_n: 6,
            estimate: -0.0018333333333333337,
            interval: Some((-0.006000000000000002, 0.0010000000000000009)),
            p_value: 0.1875,
            p_holm: Some(0.28125),
            paired_p_value: 0.1875,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.5972222222222222,
            iqm_difference: -0.002,
            iqm_ci: (-0.009000000000000001, 0.0055),
        },
        Expected {
            metric: "retention_decay",
            versus: "softmax",
            n: (6, 6),
            paired_n: 6,
            estimate: -0.008833333333333334,
            interval: Some((-0.015, -0.005)),
            p_value: 0.03125,
            p_holm: Some(0.28125),
            paired_p_value: 0.03125,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: true,
            p_improvement: 0.8888888888888888,
            iqm_difference: -0.008750000000000003,
            iqm_ci: (-0.015000000000000003, -0.002),
        },
    ];
    assert_eq!(judgement.comparisons.len(), expected.len());
    for (actual, expected) in judgement.comparisons.iter().zip(&expected) {
        check_comparison(actual, expected);
    }
}

/// The default run's case (`DEFAULT_X`, `DEFAULT_Y` of the script): 20 seeds per method.
const DEFAULT_X: [f64; 20] = [
    73.0, 73.0, 75.0, 73.0, 2000.0, 73.0, 77.0, 73.0, 73.0, 2000.0, 75.0, 73.0, 73.0, 2000.0, 73.0,
    79.0, 73.0, 73.0, 75.0, 73.0,
];
const DEFAULT_Y: [f64; 20] = [
    73.0, 2000.0, 75.0, 73.0, 954.0, 2000.0, 73.0, 2000.0, 77.0, 73.0, 73.0, 75.0, 2000.0, 1233.0,
    73.0, 990.0, 73.0, 1502.0, 2000.0, 88.0,
];

#[test]
fn the_default_runs_monte_carlo_paths_match_the_redrawn_python() {
    // At 20 seeds C(40, 20) splits and 2²⁰ sign vectors are too many: the claims' defaults
    // (10 000 resamples, seed 0) draw at random. The script draws the same splits, sign
    // vectors and resamples again (ChaCha8, Lemire, partial Fisher–Yates, one word per 32
    // signs, as the stats module documents), evaluates them with scipy/numpy and counts with
    // the same tie rule: the p-values, (b + 1)/(B + 1), agree to the bit.
    let permutation = PermutationTest::default();
    let sign_flip = SignFlipTest::default();
    assert!(!permutation.is_exact(20, 20) && !sign_flip.is_exact(20));
    let (x, y) = (DEFAULT_X, DEFAULT_Y);
    exact(
        permutation.p_value(&x, &y, Statistic::Iqm).unwrap(),
        0.10028997100289971,
        "permutation, IQM",
    );
    exact(
        permutation.p_value(&x, &y, Statistic::Mean).unwrap(),
        0.10028997100289971,
        "permutation, mean",
    );
    // Issue 34: the sign-flip test of the mean counts all 2²⁰ sign vectors at 20 pairs
    // (scipy's `permutation_test(…, n_resamples=inf)` enumerates them too), whatever its
    // `resamples`: no Monte-Carlo error, no floor at 1/(B + 1).
    assert!(sign_flip.is_exact_for(20, Statistic::Mean));
    let d = differences(&x, &y).unwrap();
    for (alternative, expected) in [
        (Alternative::TwoSided, 0.10345458984375),
        (Alternative::Greater, 0.948974609375),
        (Alternative::Less, 0.051727294921875),
    ] {
        exact(
            sign_flip.p_value(&d, Statistic::Mean, alternative).unwrap(),
            expected,
            "sign flip",
        );
    }
    exact(
        sign_flip
            .equivalence_p_value(&d, Statistic::Mean, 2.0)
            .unwrap(),
        0.9458827972412109,
        "TOST",
    );
    let (low, high) = SignFlipMeans::exact(&d).unwrap().interval(0.95).unwrap();
    close(low.unwrap(), -928.3, "sign-flip interval");
    close(high.unwrap(), 112.25, "sign-flip interval");
    // numpy.quantile of the redrawn replicates (10 000 of them, 95 %).
    let bootstrap = Bootstrap::default();
    let one = bootstrap.interval(&x, Statistic::Iqm).unwrap();
    close(one.low, 73.0, "IQM interval");
    close(one.high, 268.1, "IQM interval");
    let two = bootstrap.difference(&x, &y, Statistic::Iqm).unwrap();
    close(two.low, -1170.8025, "IQM difference interval");
    close(two.high, -0.20000000000000284, "IQM difference interval");
    let paired = paired_difference(&bootstrap, &x, &y, Statistic::Mean).unwrap();
    close(paired.low, -886.0074999999999, "paired interval");
    close(paired.high, 70.01999999999971, "paired interval");
}
