//! `eamadm_eval::stats` against independent implementations (scipy 1.17.1, statsmodels 0.15.0,
//! numpy 2.4.6; the values were printed by `stats_reference.py` next to this file), with the
//! retention slope of `scores` and the seed summary's t factor beside them, the laws
//! the statistics obey (proptest), seeded reproducibility, typed errors on bad input, and the
//! worked case of issue 11 (Task II's bimodal final steps).

use eamadm_eval::scores::slope;
use eamadm_eval::stats::{
    Bootstrap, Interval, PermutationTest, Statistic, StatsError, distribution, holm, iqm, mean,
    median, normal_quantile, probability_of_improvement, sample_sd, wilson,
};
use eamadm_eval::summary::{student_t_975, summarise_seeds};
use proptest::prelude::*;

/// EA-MADM's final steps per seed on Task II (issue 11): five seeds at the optimum 73, one at
/// 75, four stuck at the 2000-step cap.
const EA_MADM_TASK2: [f64; 10] = [
    73.0, 73.0, 73.0, 73.0, 73.0, 75.0, 2000.0, 2000.0, 2000.0, 2000.0,
];
/// A competitor of our choosing: half its seeds at the cap, the others between 800 and 1700.
const COMPETITOR_TASK2: [f64; 10] = [
    812.0, 2000.0, 1377.0, 2000.0, 954.0, 2000.0, 1640.0, 2000.0, 1105.0, 2000.0,
];
const ONE: [f64; 1] = [4.25];
const TWO: [f64; 2] = [3.0, -1.5];
const THREE: [f64; 3] = [0.3, 0.1, 0.2];
const FIVE: [f64; 5] = [2.5, -7.25, 3.125, 11.0, 0.0];
const SEVEN: [f64; 7] = [0.1, 0.7, 0.2, 0.35, 0.9, 0.15, 0.6];
const TWELVE: [f64; 12] = [
    5.5, 1.0, 9.25, -3.0, 4.0, 4.0, 12.5, 0.75, 6.0, 2.0, 8.0, -1.25,
];
const THIRTEEN: [f64; 13] = [
    13.0, 1.0, 12.0, 2.0, 11.0, 3.0, 10.0, 4.0, 9.0, 5.0, 8.0, 6.0, 700.0,
];

/// `|actual − expected| ≤ tolerance · max(1, |expected|)`.
fn close(actual: f64, expected: f64, tolerance: f64) -> bool {
    (actual - expected).abs() <= tolerance * expected.abs().max(1.0)
}

#[test]
fn location_and_spread_match_numpy_and_scipy() -> Result<(), StatsError> {
    // (sample, numpy.mean, numpy.median, scipy.stats.trim_mean(x, 0.25), numpy.std(ddof=1)).
    let cases: [(&[f64], f64, f64, f64, f64); 9] = [
        (
            &EA_MADM_TASK2,
            844.0,
            74.0,
            715.6666666666666,
            994.926574621911,
        ),
        (&COMPETITOR_TASK2, 1588.8, 1820.0, 1687.0, 486.8674928104726),
        (&ONE, 4.25, 4.25, 4.25, 0.0),
        (&TWO, 0.75, 0.75, 0.75, 3.181980515339464),
        (
            &THREE,
            0.20000000000000004,
            0.2,
            0.20000000000000004,
            0.09999999999999999,
        ),
        (&FIVE, 1.875, 2.5, 1.875, 6.557438524302),
        (
            &SEVEN,
            0.42857142857142855,
            0.35,
            0.39999999999999997,
            0.30802751886958474,
        ),
        (&TWELVE, 4.0625, 4.0, 3.75, 4.493840481450946),
        (
            &THIRTEEN,
            60.30769230769231,
            8.0,
            7.571428571428571,
            192.2430686290079,
        ),
    ];
    for (x, expected_mean, expected_median, expected_iqm, expected_sd) in cases {
        assert!(close(mean(x)?, expected_mean, 1e-12), "mean of {x:?}");
        assert!(close(median(x)?, expected_median, 1e-12), "median of {x:?}");
        assert!(close(iqm(x)?, expected_iqm, 1e-12), "iqm of {x:?}");
        assert!(close(sample_sd(x)?, expected_sd, 1e-12), "sd of {x:?}");
        assert_eq!(Statistic::Iqm.of(x)?.to_bits(), iqm(x)?.to_bits());
    }
    Ok(())
}

#[test]
fn iqm_drops_whole_values_as_scipy_trim_mean_does() -> Result<(), StatsError> {
    // n = 10: ⌊10/4⌋ = 2 whole values dropped at each end, the middle 6 averaged, as
    // scipy.stats.trim_mean(x, 0.25) does; the mean of the empirical quantile function over
    // [0.25, 0.75] (values 3 and 8 weighted ½) would be 651.5 (stats_reference.py prints both).
    assert!(close(iqm(&EA_MADM_TASK2)?, 4294.0 / 6.0, 1e-12));
    assert!((iqm(&EA_MADM_TASK2)? - 651.5).abs() > 60.0);
    // n = 5: one value dropped each end (the fractional IQM would be 1.9375).
    assert!(close(iqm(&FIVE)?, 1.875, 1e-12));
    // n a multiple of 4: the two conventions agree.
    assert!(close(iqm(&TWELVE)?, 3.75, 1e-12));
    Ok(())
}

#[test]
fn quartiles_match_numpy_percentile() -> Result<(), StatsError> {
    // (sample, numpy.percentile(x, 25), numpy.percentile(x, 75)), linear interpolation.
    let cases: [(&[f64], f64, f64); 9] = [
        (&EA_MADM_TASK2, 73.0, 2000.0),
        (&COMPETITOR_TASK2, 1173.0, 2000.0),
        (&ONE, 4.25, 4.25),
        (&TWO, -0.375, 1.875),
        (&THREE, 0.15000000000000002, 0.25),
        (&FIVE, 0.0, 3.125),
        (&SEVEN, 0.175, 0.6499999999999999),
        (&TWELVE, 0.9375, 6.5),
        (&THIRTEEN, 4.0, 11.0),
    ];
    for (x, q1, q3) in cases {
        let shape = distribution(x, None)?;
        assert!(close(shape.q1, q1, 1e-12), "q1 of {x:?}: {}", shape.q1);
        assert!(close(shape.q3, q3, 1e-12), "q3 of {x:?}: {}", shape.q3);
        assert_eq!(shape.n, x.len());
        assert_eq!(shape.median, median(x)?);
    }
    Ok(())
}

#[test]
fn holm_matches_statsmodels() -> Result<(), StatsError> {
    // multipletests(p, method="holm")[1].
    let cases: [(&[f64], &[f64]); 8] = [
        (&[0.01, 0.04, 0.03, 0.005], &[0.03, 0.06, 0.06, 0.02]),
        // Tied p-values, two of them, and the sign tests of the C3 chain (`chains.rs`).
        (&[0.02, 0.02, 0.02, 0.5], &[0.08, 0.08, 0.08, 0.5]),
        (&[0.04, 0.03], &[0.06, 0.06]),
        (&[0.0625, 0.25, 1.0], &[0.1875, 0.5, 1.0]),
        (
            &[0.2, 0.2, 0.01, 0.6, 0.04],
            &[
                0.6000000000000001,
                0.6000000000000001,
                0.05,
                0.6000000000000001,
                0.16,
            ],
        ),
        (&[0.5], &[0.5]),
        (
            &[0.3, 0.4, 0.9],
            &[0.8999999999999999, 0.8999999999999999, 0.9],
        ),
        (&[0.0, 1.0, 0.011, 0.012], &[0.0, 1.0, 0.033, 0.033]),
    ];
    for (p, expected) in cases {
        let adjusted = holm(p)?;
        assert_eq!(adjusted.len(), expected.len());
        for (a, e) in adjusted.iter().zip(expected) {
            assert!(close(*a, *e, 1e-12), "holm({p:?}) = {adjusted:?}");
        }
    }
    Ok(())
}

#[test]
fn wilson_matches_statsmodels() -> Result<(), StatsError> {
    // proportion_confint(s, n, alpha=1 - confidence, method="wilson").
    let cases = [
        (0, 10, 0.95, 0.0, 0.2775327998628892),
        (10, 10, 0.95, 0.7224672001371107, 0.9999999999999999),
        (7, 10, 0.95, 0.39677814746114537, 0.8922087325936989),
        (62, 100, 0.95, 0.5220975529551107, 0.7090240074752127),
        (1, 3, 0.9, 0.07826572633372836, 0.746466131718776),
        (13, 20, 0.99, 0.3716618210473128, 0.853606558623061),
        (500, 1000, 0.5, 0.4893378056892053, 0.5106621943107947),
    ];
    for (successes, trials, confidence, low, high) in cases {
        let interval = wilson(successes, trials, confidence)?;
        assert_eq!(interval.estimate, successes as f64 / trials as f64);
        assert!(close(interval.low, low, 1e-12), "{interval:?} vs {low}");
        assert!(close(interval.high, high, 1e-12), "{interval:?} vs {high}");
    }
    Ok(())
}

#[test]
fn probability_of_improvement_is_mann_whitney_u_over_nm() -> Result<(), StatsError> {
    // scipy.stats.mannwhitneyu(x, y).statistic / (n m).
    let cases: [(&[f64], &[f64], f64); 4] = [
        (&EA_MADM_TASK2, &COMPETITOR_TASK2, 0.3),
        (&FIVE, &SEVEN, 0.6),
        (&TWELVE, &THIRTEEN, 0.28846153846153844),
        (&TWO, &THREE, 0.5),
    ];
    for (x, y, expected) in cases {
        assert!(close(probability_of_improvement(x, y)?, expected, 1e-12));
    }
    Ok(())
}

#[test]
fn exact_permutation_p_matches_scipy() -> Result<(), StatsError> {
    // scipy.stats.permutation_test((x, y), |T(x) − T(y)|, permutation_type="independent",
    // n_resamples=inf, alternative="greater"): every split enumerated.
    let small_x = [73.0, 73.0, 75.0, 2000.0, 2000.0];
    let small_y = [812.0, 2000.0, 1377.0, 954.0, 1105.0, 2000.0];
    let tiny_x = [1.0, 5.0, 2.0];
    let tiny_y = [9.0, 7.0, 8.0, 6.0];
    let cases: [(Statistic, &[f64], &[f64], f64); 9] = [
        (Statistic::Mean, &small_x, &small_y, 0.3225108225108225),
        (Statistic::Mean, &tiny_x, &tiny_y, 0.02857142857142857),
        (Statistic::Mean, &small_y, &tiny_x, 0.011904761904761904),
        (Statistic::Median, &small_x, &small_y, 0.1406926406926407),
        (Statistic::Median, &tiny_x, &tiny_y, 0.05714285714285714),
        (Statistic::Median, &small_y, &tiny_x, 0.08333333333333333),
        (Statistic::Iqm, &small_x, &small_y, 0.4134199134199134),
        (Statistic::Iqm, &tiny_x, &tiny_y, 0.02857142857142857),
        (Statistic::Iqm, &small_y, &tiny_x, 0.011904761904761904),
    ];
    let test = PermutationTest::default();
    for (statistic, x, y, expected) in cases {
        assert!(test.is_exact(x.len(), y.len()));
        let p = test.p_value(x, y, statistic)?;
        // A count over the enumeration divided by C(n+m, n): scipy's value to the bit.
        assert_eq!(
            p.to_bits(),
            expected.to_bits(),
            "{statistic:?} {x:?} {y:?}: {p}"
        );
        // Exact enumeration draws nothing: the seed cannot matter.
        let other_seed = PermutationTest::new(10_000, 99)?;
        assert_eq!(other_seed.p_value(x, y, statistic)?, p);
    }
    Ok(())
}

#[test]
fn monte_carlo_permutation_p_is_close_to_the_exact_one() -> Result<(), StatsError> {
    // C(11, 5) = 462 splits: with 400 resamples the test draws, with 462 it enumerates.
    let x = [73.0, 73.0, 75.0, 2000.0, 2000.0];
    let y = [812.0, 2000.0, 1377.0, 954.0, 1105.0, 2000.0];
    let drawn = PermutationTest::new(400, 3)?;
    assert!(!drawn.is_exact(5, 6));
    assert!(PermutationTest::new(462, 3)?.is_exact(5, 6));
    let p = drawn.p_value(&x, &y, Statistic::Mean)?;
    // Exact 0.3225; (b + 1)/(B + 1) with B = 400 has a standard error of about 0.023.
    assert!((p - 0.3225108225108225).abs() < 0.08, "{p}");
    // The smallest possible Monte-Carlo p is 1/(B + 1), never 0.
    let separated = drawn.p_value(&[0.0; 12], &[1.0; 12], Statistic::Mean)?;
    assert!((1.0 / 401.0..0.01).contains(&separated), "{separated}");
    Ok(())
}

#[test]
fn normal_quantile_matches_scipy_norm_ppf() -> Result<(), StatsError> {
    let cases = [
        (1e-300, -37.0470962993612),
        (1e-20, -9.262340089798409),
        (1e-10, -6.361340902404056),
        (1e-05, -4.264890793922825),
        (0.001, -3.090232306167813),
        (0.025, -1.9599639845400545),
        (0.07, -1.4757910281791706),
        (0.3, -0.5244005127080409),
        (0.5, 0.0),
        (0.6, 0.2533471031357997),
        (0.8, 0.8416212335729143),
        (0.975, 1.959963984540054),
        (0.999, 3.090232306167813),
        (0.9999999999, 6.361340889697422),
    ];
    for (p, expected) in cases {
        let z = normal_quantile(p)?;
        assert!(
            close(z, expected, 1e-13),
            "Φ⁻¹({p}) = {z}, scipy {expected}"
        );
    }
    Ok(())
}

#[test]
fn retention_slope_matches_scipy_linregress() {
    // scipy.stats.linregress(range(n), y).slope: `retention_decay` of final-scores.csv.
    let cases: [(&[f64], f64); 4] = [
        (&[5.0, 3.0, 1.0], -2.0),
        (&[1.0, 1.6, 1.9, 2.5], 0.48),
        (&[2.0, 2.0], 0.0),
        (
            &[
                0.8, 0.75, 0.9, 0.6, 0.55, 0.7, 0.4, 0.45, 0.5, 0.3, 0.35, 0.2,
            ],
            -0.0541958041958042,
        ),
    ];
    for (y, expected) in cases {
        let slope = slope(y).unwrap();
        assert!(close(slope, expected, 1e-12), "{y:?}: {slope}");
    }
}

#[test]
fn student_t_matches_scipy_and_the_seed_summary_numpy() -> Result<(), StatsError> {
    // scipy.stats.t.ppf(0.975, df): a 6-decimal table up to df = 30, Cornish–Fisher beyond
    // (documented error below 1e-6).
    for (df, expected) in [
        (1, 12.706204736174694),
        (2, 4.302652729749462),
        (5, 2.5705818356363146),
        (19, 2.0930240544083087),
        (30, 2.0422724563012378),
        (31, 2.039513446396408),
        (50, 2.008559112100761),
        (100, 1.9839715185235518),
        (1000, 1.9623390808264083),
    ] {
        let t = student_t_975(df).unwrap();
        assert!((t - expected).abs() < 1e-6, "df {df}: {t} vs {expected}");
    }
    assert_eq!(student_t_975(0), None);
    // numpy.mean, numpy.std(ddof=1) and t.ppf(0.975, 9) · sd / √10.
    let x = [3.0, 9.5, 4.25, 7.0, 1.0, 12.0, 6.5, 8.0, 2.0, 5.0];
    let summary = summarise_seeds(&x)?;
    assert!(close(summary.mean, 5.825, 1e-12));
    assert!(close(summary.sd.unwrap(), 3.452153112350481, 1e-12));
    assert!(close(
        summary.ci95_half_width.unwrap(),
        2.4695215693880406,
        1e-6
    ));
    Ok(())
}

#[test]
fn bootstrap_matches_the_exact_bootstrap_distribution() -> Result<(), StatsError> {
    // All 6⁶ = 46 656 resamples of x enumerated in Python: the 2.5 % and 97.5 % percentiles
    // of their means are 3.0 and 20.0.
    let x = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
    let interval = Bootstrap::new(50_000, 0.95, 11)?.interval(&x, Statistic::Mean)?;
    assert_eq!(interval.estimate, 10.5);
    // The bootstrap distribution's sd is about 4.4 and its atoms lie 1/6 apart.
    assert!((interval.low - 3.0).abs() <= 0.34, "{interval:?}");
    assert!((interval.high - 20.0).abs() <= 0.5, "{interval:?}");
    Ok(())
}

#[test]
fn bootstrap_matches_scipy_within_monte_carlo_error() -> Result<(), StatsError> {
    // scipy.stats.bootstrap(method="percentile", n_resamples=200_000): (statistic, one sample
    // low/high, difference low/high).
    let cases = [
        (
            Statistic::Mean,
            (265.9, 1422.1),
            (-1379.1999999999998, -77.39999999999986),
        ),
        (Statistic::Iqm, (73.0, 1679.1666666666667), (-1807.0, 139.5)),
    ];
    let bootstrap = Bootstrap::new(100_000, 0.95, 5)?;
    // The data span 1927 steps; a percentile of 100 000 resamples moves by a few steps between
    // seeds, the IQM's lumpy distribution (atoms 1/6 of a gap apart) by up to about 60.
    let tolerance = 80.0;
    for (statistic, (low, high), (difference_low, difference_high)) in cases {
        let one = bootstrap.interval(&EA_MADM_TASK2, statistic)?;
        assert!((one.low - low).abs() < tolerance, "{statistic:?} {one:?}");
        assert!((one.high - high).abs() < tolerance, "{statistic:?} {one:?}");
        let two = bootstrap.difference(&EA_MADM_TASK2, &COMPETITOR_TASK2, statistic)?;
        assert!(
            (two.low - difference_low).abs() < tolerance,
            "{statistic:?} {two:?}"
        );
        assert!(
            (two.high - difference_high).abs() < tolerance,
            "{statistic:?} {two:?}"
        );
    }
    Ok(())
}

#[test]
fn bootstrap_is_reproducible_bit_for_bit_and_seed_dependent() -> Result<(), StatsError> {
    let x = [3.0, 9.5, 4.25, 7.0, 1.0, 12.0, 6.5, 8.0, 2.0, 5.0];
    for statistic in Statistic::ALL {
        let a = Bootstrap::new(2_000, 0.9, 1)?.interval(&x, statistic)?;
        let again = Bootstrap::new(2_000, 0.9, 1)?.interval(&x, statistic)?;
        assert_eq!(a.low.to_bits(), again.low.to_bits());
        assert_eq!(a.high.to_bits(), again.high.to_bits());
        let other = Bootstrap::new(2_000, 0.9, 2)?.interval(&x, statistic)?;
        assert_eq!(other.estimate, a.estimate);
        assert!((a.low - other.low).abs() < 1.0 && (a.high - other.high).abs() < 1.0);
        // The mean's bootstrap distribution has thousands of distinct values, so another
        // seed moves its percentiles (the median's has few atoms and may not move).
        if statistic == Statistic::Mean {
            assert!((a.low, a.high) != (other.low, other.high));
        }
        // Permuting the seeds' order changes nothing, to the bit: the statistics are
        // computed from the sorted sample.
        let mut reversed = x;
        reversed.reverse();
        let permuted = Bootstrap::new(2_000, 0.9, 1)?.interval(&reversed, statistic)?;
        assert_eq!(permuted, a);
    }
    Ok(())
}

#[test]
fn more_resamples_narrow_the_monte_carlo_noise() -> Result<(), StatsError> {
    // Twenty seeds of low-resample intervals scatter more than twenty of high-resample ones.
    let x = [3.0, 9.5, 4.25, 7.0, 1.0, 12.0, 6.5, 8.0, 2.0, 5.0];
    let spread = |resamples: u32| -> Result<f64, StatsError> {
        let lows = (0..20)
            .map(|seed| {
                Ok(Bootstrap::new(resamples, 0.95, seed)?
                    .interval(&x, Statistic::Mean)?
                    .low)
            })
            .collect::<Result<Vec<f64>, StatsError>>()?;
        sample_sd(&lows)
    };
    assert!(spread(100)? > 2.0 * spread(10_000)?);
    Ok(())
}

#[test]
fn stratified_bootstrap_with_one_group_is_the_plain_bootstrap() -> Result<(), StatsError> {
    let bootstrap = Bootstrap::new(3_000, 0.95, 8)?;
    for statistic in Statistic::ALL {
        let plain = bootstrap.interval(&TWELVE, statistic)?;
        let stratified = bootstrap.stratified_interval(&[&TWELVE], statistic)?;
        assert_eq!(plain, stratified, "{statistic:?}");
    }
    Ok(())
}

#[test]
fn stratified_bootstrap_keeps_each_group_whole() -> Result<(), StatsError> {
    // Two tasks on very different scales. Resampling within each task keeps five values from
    // each in every round, so the pooled median is always the mean of the largest small value
    // and the smallest large one, in [51, 55]; a pooled (unstratified) resample would often
    // draw six or more from one task and put the median near 3 or 103.
    let small = [1.0, 2.0, 3.0, 4.0, 5.0];
    let large = [101.0, 102.0, 103.0, 104.0, 105.0];
    let interval =
        Bootstrap::default().stratified_interval(&[&small, &large], Statistic::Median)?;
    assert_eq!(interval.estimate, 53.0);
    assert!(interval.low >= (1.0 + 101.0) / 2.0 && interval.high <= (5.0 + 105.0) / 2.0);
    let pooled = [small, large].concat();
    assert_eq!(Statistic::Median.of(&pooled)?, interval.estimate);
    Ok(())
}

#[test]
fn worked_case_task2_final_steps() -> Result<(), StatsError> {
    // Issue 11's worked case: EA-MADM's bimodal Task II final steps against a competitor.
    let bootstrap = Bootstrap::default();
    let test = PermutationTest::default();
    let shape = distribution(&EA_MADM_TASK2, Some(2000.0))?;
    assert_eq!(shape.at_cap, 4);
    assert!(shape.bimodal);
    let round = |v: f64| (v * 1000.0).round() / 1000.0;
    let rounded = |i: Interval| [round(i.estimate), round(i.low), round(i.high)];
    let report = serde_json::json!({
        "ea_madm": shape,
        "competitor": distribution(&COMPETITOR_TASK2, Some(2000.0))?,
        "mean_difference": rounded(bootstrap.difference(&EA_MADM_TASK2, &COMPETITOR_TASK2, Statistic::Mean)?),
        "iqm_difference": rounded(bootstrap.difference(&EA_MADM_TASK2, &COMPETITOR_TASK2, Statistic::Iqm)?),
        "median_difference": rounded(bootstrap.difference(&EA_MADM_TASK2, &COMPETITOR_TASK2, Statistic::Median)?),
        "p_mean": round(test.p_value(&EA_MADM_TASK2, &COMPETITOR_TASK2, Statistic::Mean)?),
        "p_iqm": round(test.p_value(&EA_MADM_TASK2, &COMPETITOR_TASK2, Statistic::Iqm)?),
        "p_median": round(test.p_value(&EA_MADM_TASK2, &COMPETITOR_TASK2, Statistic::Median)?),
        "probability_of_improvement": round(probability_of_improvement(&EA_MADM_TASK2, &COMPETITOR_TASK2)?),
        "ea_madm_iqm": rounded(bootstrap.interval(&EA_MADM_TASK2, Statistic::Iqm)?),
    });
    insta::assert_json_snapshot!(report);
    Ok(())
}

#[test]
fn distribution_flags_two_separated_groups() -> Result<(), StatsError> {
    // A cap reached by at least 2 seeds while at least 2 are below it.
    assert!(distribution(&[73.0, 73.0, 2000.0, 2000.0], Some(2000.0))?.bimodal);
    assert!(!distribution(&[73.0, 74.0, 75.0, 2000.0], Some(2000.0))?.bimodal);
    assert!(!distribution(&[2000.0; 6], Some(2000.0))?.bimodal);
    // Without a cap, a gap wider than both groups' ranges together.
    assert!(distribution(&[1.0, 2.0, 3.0, 50.0, 51.0], None)?.bimodal);
    assert!(!distribution(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], None)?.bimodal);
    assert!(!distribution(&THIRTEEN, None)?.bimodal); // one outlier is not a second mode
    assert!(!distribution(&ONE, Some(4.25))?.bimodal);
    assert_eq!(distribution(&ONE, Some(4.25))?.at_cap, 1);
    assert_eq!(distribution(&EA_MADM_TASK2, None)?.at_cap, 0);
    Ok(())
}

#[test]
fn bad_input_is_a_typed_error() {
    let nan = [1.0, f64::NAN];
    assert_eq!(mean(&[]), Err(StatsError::Empty { what: "x" }));
    assert!(matches!(
        iqm(&nan),
        Err(StatsError::NonFinite { what: "x", index: 1, value }) if value.is_nan()
    ));
    assert!(matches!(
        median(&[f64::INFINITY]),
        Err(StatsError::NonFinite { index: 0, .. })
    ));
    assert!(matches!(
        Bootstrap::new(0, 0.95, 0),
        Err(StatsError::InvalidParameter {
            name: "resamples",
            ..
        })
    ));
    assert!(matches!(
        Bootstrap::new(10, 1.0, 0),
        Err(StatsError::InvalidParameter {
            name: "confidence",
            ..
        })
    ));
    assert!(matches!(
        Bootstrap::new(10, f64::NAN, 0),
        Err(StatsError::InvalidParameter {
            name: "confidence",
            ..
        })
    ));
    // Fields set directly are checked too.
    let unchecked = Bootstrap {
        resamples: 0,
        confidence: 0.95,
        seed: 0,
    };
    assert!(matches!(
        unchecked.interval(&ONE, Statistic::Mean),
        Err(StatsError::InvalidParameter {
            name: "resamples",
            ..
        })
    ));
    assert_eq!(
        Bootstrap::default().difference(&ONE, &[], Statistic::Mean),
        Err(StatsError::Empty { what: "y" })
    );
    assert_eq!(
        Bootstrap::default().stratified_interval(&[], Statistic::Mean),
        Err(StatsError::Empty { what: "groups" })
    );
    assert_eq!(
        Bootstrap::default().stratified_interval(&[&ONE, &[]], Statistic::Mean),
        Err(StatsError::EmptyGroup { group: 1 })
    );
    assert!(matches!(
        Bootstrap::default().stratified_interval(&[&ONE, &nan], Statistic::Mean),
        Err(StatsError::NonFiniteInGroup {
            group: 1,
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        PermutationTest::new(0, 0),
        Err(StatsError::InvalidParameter {
            name: "resamples",
            ..
        })
    ));
    assert_eq!(
        PermutationTest::default().p_value(&[], &ONE, Statistic::Iqm),
        Err(StatsError::Empty { what: "x" })
    );
    assert_eq!(holm(&[]), Err(StatsError::Empty { what: "p_values" }));
    assert!(matches!(
        holm(&[0.5, 1.5]),
        Err(StatsError::NotAProbability { index: 1, .. })
    ));
    assert!(matches!(
        holm(&[f64::NAN]),
        Err(StatsError::NotAProbability { index: 0, .. })
    ));
    assert_eq!(
        probability_of_improvement(&ONE, &[]),
        Err(StatsError::Empty { what: "y" })
    );
    assert!(matches!(
        wilson(1, 0, 0.95),
        Err(StatsError::InvalidParameter { name: "trials", .. })
    ));
    assert!(matches!(
        wilson(3, 2, 0.95),
        Err(StatsError::InvalidParameter {
            name: "successes",
            ..
        })
    ));
    assert!(matches!(
        wilson(1, 2, 0.0),
        Err(StatsError::InvalidParameter {
            name: "confidence",
            ..
        })
    ));
    for p in [0.0, 1.0, -0.5, f64::NAN] {
        assert!(matches!(
            normal_quantile(p),
            Err(StatsError::InvalidParameter { name: "p", .. })
        ));
    }
    assert!(matches!(
        distribution(&ONE, Some(f64::INFINITY)),
        Err(StatsError::InvalidParameter { name: "cap", .. })
    ));
    // Values near f64::MAX: a finite mean, and an error where the result cannot be finite.
    assert_eq!(mean(&[f64::MAX, f64::MAX]), Ok(f64::MAX));
    assert!(matches!(
        sample_sd(&[-f64::MAX, f64::MAX]),
        Err(StatsError::Overflow { .. })
    ));
    let message = iqm(&nan).map_err(|e| e.to_string());
    assert_eq!(
        message,
        Err("x[1] = NaN is not finite: remove or replace it".to_owned())
    );
}

fn sample() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1e6..1e6_f64, 1..25)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn holm_is_monotone_at_least_raw_and_at_most_one(
        p in prop::collection::vec(0.0..=1.0_f64, 1..15),
    ) {
        let adjusted = holm(&p)?;
        for (raw, adj) in p.iter().zip(&adjusted) {
            prop_assert!(adj >= raw && *adj <= 1.0);
        }
        // Monotone: a smaller raw p never gets a larger adjusted one.
        for i in 0..p.len() {
            for j in 0..p.len() {
                if p[i] < p[j] {
                    prop_assert!(adjusted[i] <= adjusted[j]);
                }
            }
        }
    }

    #[test]
    fn improvement_and_its_converse_add_to_one(x in sample(), y in sample()) {
        let forward = probability_of_improvement(&x, &y)?;
        let backward = probability_of_improvement(&y, &x)?;
        prop_assert!((forward + backward - 1.0).abs() < 1e-12);
        prop_assert!((0.0..=1.0).contains(&forward));
    }

    #[test]
    fn location_statistics_lie_between_min_and_max(x in sample()) {
        let lowest = x.iter().copied().fold(f64::INFINITY, f64::min);
        let highest = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        for statistic in Statistic::ALL {
            let value = statistic.of(&x)?;
            prop_assert!(lowest <= value && value <= highest, "{:?} = {}", statistic, value);
        }
        let shape = distribution(&x, None)?;
        prop_assert!(shape.min <= shape.q1 && shape.q1 <= shape.median);
        prop_assert!(shape.median <= shape.q3 && shape.q3 <= shape.max);
    }

    #[test]
    fn iqm_of_a_constant_shift_shifts(x in sample(), shift in -100.0..100.0_f64) {
        let shifted: Vec<f64> = x.iter().map(|v| v + shift).collect();
        prop_assert!((iqm(&shifted)? - iqm(&x)? - shift).abs() < 1e-6);
    }

    #[test]
    fn wilson_lies_in_the_unit_interval_around_the_estimate(
        trials in 1..5_000_u64,
        fraction in 0.0..=1.0_f64,
        confidence in 0.5..0.999_f64,
    ) {
        let successes = (fraction * trials as f64).round() as u64;
        let interval = wilson(successes, trials, confidence)?;
        prop_assert!(0.0 <= interval.low && interval.low <= interval.estimate);
        prop_assert!(interval.estimate <= interval.high && interval.high <= 1.0);
    }

    #[test]
    fn permutation_p_lies_in_zero_one(
        x in prop::collection::vec(-50.0..50.0_f64, 1..9),
        y in prop::collection::vec(-50.0..50.0_f64, 1..9),
        seed in any::<u64>(),
    ) {
        let test = PermutationTest::new(500, seed)?;
        for statistic in Statistic::ALL {
            let p = test.p_value(&x, &y, statistic)?;
            prop_assert!(p > 0.0 && p <= 1.0, "{:?}: {}", statistic, p);
        }
        // Identical samples: every split is at least as extreme as a zero difference.
        prop_assert_eq!(test.p_value(&x, &x, Statistic::Mean)?, 1.0);
    }

    #[test]
    fn symmetric_data_has_an_interval_around_its_estimate(
        half in prop::collection::vec(0.0..100.0_f64, 2..10),
        centre in -1e3..1e3_f64,
        seed in any::<u64>(),
    ) {
        // Values mirrored around `centre`: the bootstrap distribution is symmetric about it.
        let x: Vec<f64> = half.iter().flat_map(|d| [centre - d, centre + d]).collect();
        let bootstrap = Bootstrap::new(1_000, 0.95, seed)?;
        for statistic in Statistic::ALL {
            let interval = bootstrap.interval(&x, statistic)?;
            prop_assert!(interval.contains(interval.estimate), "{:?} {:?}", statistic, interval);
            prop_assert!(interval.low <= interval.high);
        }
    }
}
