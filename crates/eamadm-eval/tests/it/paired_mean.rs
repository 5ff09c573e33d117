//! `eamadm_eval::stats::SignFlipMeans` (issue 34): the exact sign-flip distribution of the mean
//! of paired differences against independent implementations (scipy 1.17.1's
//! `permutation_test` enumerating every sign vector, and every subset mean listed with numpy;
//! printed by `paired_mean_reference.py` next to this file), with the laws that tie the
//! interval to the tests.

use eamadm_eval::claims::stream_seed;
use eamadm_eval::stats::{
    Alternative, EXACT_MAX_PAIRS, SignFlipMeans, SignFlipTest, Statistic, StatsError,
};
use proptest::prelude::*;

const TASK2: [f64; 20] = [
    -1235.65, 567.2, 507.4, 449.45, -1400.0, 496.95, -1417.55, -1502.75, -1406.9, -1528.7, -1333.6,
    551.7, -1408.2, -1485.3, -1470.2, -1357.4, -1428.75, 637.05, -1385.65, -1353.75,
];
const TASK1: [f64; 20] = [
    0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.25, 0.0, 1942.0, 0.0, 1940.0,
    0.0, -4.0, 0.0,
];
const D12: [f64; 12] = [
    1.5, -0.5, 2.0, 0.25, -1.0, 3.0, 0.75, -0.25, 1.25, 0.5, -2.0, 1.0,
];
const D7: [f64; 7] = [3.0, 1.0, 4.0, 1.5, 5.0, 9.0, 2.5];
const D5: [f64; 5] = [3.0, 1.0, 4.0, 1.5, 5.0];

/// Bit-for-bit: an exact p-value is a count over the 2ⁿ sign vectors divided by 2ⁿ.
fn exact(a: f64, b: f64) {
    assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
}

/// An interval end found by bisection and listing: to 1e-12 relative.
fn close(a: f64, b: f64) {
    assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} vs {b}");
}

struct Reference {
    d: &'static [f64],
    margin: f64,
    /// `p_greater(0)`, `p_less(0)`, two-sided.
    at_zero: [f64; 3],
    /// beyond, within.
    margin_tests: [f64; 2],
    /// `p_greater(−m)`, `p_less(m)`, `p_less(−m)`, `p_greater(m)`.
    one_sided: [f64; 4],
    interval: Option<(f64, f64)>,
}

const REFERENCES: [Reference; 5] = [
    Reference {
        d: &TASK2,
        margin: 2.0,
        at_zero: [
            0.999241828918457,
            0.0007600784301757812,
            0.0015201568603515625,
        ],
        margin_tests: [0.0015506744384765625, 1.0],
        one_sided: [
            0.9992256164550781,
            0.0007495880126953125,
            0.0007753372192382812,
            0.9992513656616211,
        ],
        interval: Some((-1225.7099999999998, -414.46999999999997)),
    },
    Reference {
        d: &TASK1,
        margin: 2.0,
        at_zero: [0.234375, 0.78125, 0.46875],
        margin_tests: [0.5, 1.0],
        one_sided: [
            6.103515625e-05,
            0.7500009536743164,
            0.9999961853027344,
            0.25,
        ],
        interval: Some((-0.775, 484.78125)),
    },
    Reference {
        d: &D12,
        margin: 0.5,
        at_zero: [0.107666015625, 0.9111328125, 0.21533203125],
        margin_tests: [0.9609375, 1.0],
        one_sided: [0.013671875, 0.5625, 0.98974609375, 0.48046875],
        interval: Some((-0.3333333333333333, 1.4166666666666667)),
    },
    Reference {
        d: &D7,
        margin: 1.0,
        at_zero: [0.0078125, 1.0, 0.015625],
        margin_tests: [0.03125, 1.0],
        one_sided: [0.0078125, 1.0, 1.0, 0.015625],
        interval: Some((1.5, 6.5)),
    },
    Reference {
        d: &D5,
        margin: 1.0,
        at_zero: [0.03125, 1.0, 0.0625],
        margin_tests: [0.125, 1.0],
        one_sided: [0.03125, 1.0, 1.0, 0.0625],
        interval: None,
    },
];

#[test]
fn exact_p_values_and_intervals_equal_scipy_and_listed_subset_means() {
    for r in &REFERENCES {
        let means = SignFlipMeans::exact(r.d).unwrap();
        assert!(means.is_exact());
        assert_eq!(means.sign_vectors(), 1 << r.d.len());
        exact(means.p_greater(0.0), r.at_zero[0]);
        exact(means.p_less(0.0), r.at_zero[1]);
        exact(means.p_two_sided(0.0), r.at_zero[2]);
        exact(means.beyond_margin(r.margin).unwrap(), r.margin_tests[0]);
        exact(means.within_margin(r.margin).unwrap(), r.margin_tests[1]);
        exact(means.p_greater(-r.margin), r.one_sided[0]);
        exact(means.p_less(r.margin), r.one_sided[1]);
        exact(means.p_less(-r.margin), r.one_sided[2]);
        exact(means.p_greater(r.margin), r.one_sided[3]);
        match (means.interval(0.95).unwrap(), r.interval) {
            ((Some(low), Some(high)), Some((want_low, want_high))) => {
                close(low, want_low);
                close(high, want_high);
            }
            (got, want) => assert!(want.is_none() && got == (None, None), "{got:?}"),
        }
        assert_eq!(means.monte_carlo_se(0.5), None);
    }
    let d12 = SignFlipMeans::exact(&D12).unwrap();
    for (confidence, (low, high)) in [
        (0.5, (0.25, 0.8125)),
        (0.9, (-0.16666666666666666, 1.25)),
        (0.99, (-0.7, 1.75)),
    ] {
        let (got_low, got_high) = d12.interval(confidence).unwrap();
        close(got_low.unwrap(), low);
        close(got_high.unwrap(), high);
    }
}

/// Issue 34 item 3: at n ≤ 24 the sign-flip test of the mean enumerates every sign vector
/// whatever its `resamples` (the pinned 20-pair values are the full enumeration, not a
/// Monte-Carlo estimate), and its seed changes nothing.
#[test]
fn the_sign_flip_test_of_the_mean_enumerates_up_to_24_pairs() {
    for seed in [0, 1, 2, 3] {
        let test = SignFlipTest::new(10_000, seed).unwrap();
        assert!(test.is_exact_for(20, Statistic::Mean) && !test.is_exact(20));
        exact(
            test.p_value(&TASK2, Statistic::Mean, Alternative::TwoSided)
                .unwrap(),
            0.0015201568603515625,
        );
        exact(
            test.p_value(&TASK1, Statistic::Mean, Alternative::Greater)
                .unwrap(),
            0.234375,
        );
    }
    assert!(SignFlipTest::default().is_exact_for(EXACT_MAX_PAIRS, Statistic::Mean));
    assert!(!SignFlipTest::default().is_exact_for(EXACT_MAX_PAIRS + 1, Statistic::Mean));
    // 24 pairs count in well under a second (2²⁴ sign vectors by meet in the middle).
    let d24: Vec<f64> = (0..24).map(|i| f64::from(i * 7 % 11) - 4.5).collect();
    let means = SignFlipMeans::exact(&d24).unwrap();
    assert_eq!(means.sign_vectors(), 1 << 24);
    let (low, high) = means.interval(0.95).unwrap();
    assert!(low.unwrap() < means.mean() && means.mean() < high.unwrap());
}

#[test]
fn beyond_24_pairs_the_sign_vectors_are_drawn_with_their_error() {
    let d: Vec<f64> = (0..30).map(|i| f64::from(i % 7) - 2.0).collect();
    let means = SignFlipMeans::new(&d, 20_000, 5).unwrap();
    assert!(!means.is_exact());
    assert_eq!(means.sign_vectors(), 20_000);
    let p = means.p_two_sided(0.0);
    let se = means.monte_carlo_se(p).unwrap();
    assert!(se > 0.0 && se < 0.004, "{se}");
    // The drawn p agrees with the generic sign-flip test's draws from the same seed (the
    // same sign vectors, counted the same way up to the tie rule).
    let generic = SignFlipTest::new(20_000, 5)
        .unwrap()
        .p_value(&d, Statistic::Mean, Alternative::TwoSided)
        .unwrap();
    assert!((p - generic).abs() < 1e-12, "{p} vs {generic}");
    let (low, high) = means.interval(0.95).unwrap();
    assert!(low.unwrap() < means.mean() && means.mean() < high.unwrap());
    // Each comparison draws from a stream of its own.
    assert_ne!(stream_seed(0, &d), stream_seed(0, &d[1..]));
    assert_ne!(stream_seed(0, &d), stream_seed(1, &d));
    assert_eq!(stream_seed(7, &d), stream_seed(7, &d));
}

#[test]
fn bad_input_is_named() {
    assert!(matches!(
        SignFlipMeans::exact(&[]),
        Err(StatsError::Empty { .. })
    ));
    assert!(matches!(
        SignFlipMeans::exact(&[1.0, f64::NAN]),
        Err(StatsError::NonFinite { index: 1, .. })
    ));
    let means = SignFlipMeans::exact(&D7).unwrap();
    assert!(means.within_margin(0.0).is_err());
    assert!(means.beyond_margin(-1.0).is_err());
    assert!(means.beyond_margin(f64::INFINITY).is_err());
    assert!(means.interval(1.0).is_err());
    assert!(SignFlipMeans::exact(&[0.0; 25]).is_err());
    assert!(SignFlipMeans::drawn(&D7, 0, 0).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The interval and the margin tests come from one distribution: the beyond-margin p is at
    /// most α exactly when the 1 − α interval lies wholly beyond the margin, and the
    /// within-margin p exactly when it lies inside (α = 0.05, 0.1, 0.2); the two-sided test of
    /// 0 equals the beyond-margin test with margin 0, and the generic sign-flip test.
    #[test]
    fn tests_and_interval_agree(
        d in prop::collection::vec((-40_i32..40).prop_map(|v| f64::from(v) / 4.0), 6..14),
        margin in (1_i32..12).prop_map(|m| f64::from(m) / 4.0 + 0.125),
    ) {
        let means = SignFlipMeans::exact(&d).unwrap();
        for alpha in [0.05, 0.1, 0.2] {
            let (low, high) = means.interval(1.0 - alpha).unwrap();
            let beyond = means.beyond_margin(margin).unwrap();
            let within = means.within_margin(margin).unwrap();
            let lies_beyond = high.is_some_and(|h| h < -margin) || low.is_some_and(|l| l > margin);
            let lies_within = low.is_some_and(|l| l > -margin) && high.is_some_and(|h| h < margin);
            prop_assert_eq!(beyond <= alpha, lies_beyond, "beyond {} at {}", beyond, alpha);
            prop_assert_eq!(within <= alpha, lies_within, "within {} at {}", within, alpha);
            if let (Some(low), Some(high)) = (low, high) {
                prop_assert!(low <= means.mean() && means.mean() <= high);
            }
        }
        prop_assert_eq!(means.beyond_margin(0.0).unwrap(), means.p_two_sided(0.0));
        let generic = SignFlipTest::default()
            .p_value(&d, Statistic::Mean, Alternative::TwoSided)
            .unwrap();
        prop_assert_eq!(means.p_two_sided(0.0), generic);
    }
}
