//! `eamadm_eval::stats::paired` against independent implementations (scipy 1.17.1,
//! statsmodels 0.15.0; the values were printed by `paired_reference.py` next to this file),
//! with the laws the paired statistics obey and a rerun with another seed.

use eamadm_eval::stats::paired::{differences, paired_difference};
use eamadm_eval::stats::{Alternative, Bootstrap, SignFlipTest, Statistic, StatsError, sign_test};
use proptest::prelude::*;

const X: [f64; 10] = [58.0, 58.0, 60.0, 58.0, 2000.0, 58.0, 64.0, 58.0, 58.0, 60.0];
const Y: [f64; 10] = [58.0, 60.0, 58.0, 58.0, 58.0, 58.0, 60.0, 58.0, 62.0, 58.0];
const D12: [f64; 12] = [
    1.5, -0.5, 2.0, 0.25, -1.0, 3.0, 0.75, -0.25, 1.25, 0.5, -2.0, 1.0,
];

fn close(a: f64, b: f64) {
    assert!((a - b).abs() < 1e-12, "{a} vs {b}");
}

#[test]
fn sign_flip_p_values_equal_scipy_permutation_test() {
    let test = SignFlipTest::default();
    let d10 = differences(&X, &Y).unwrap();
    assert!(test.is_exact(10) && test.is_exact(12) && !test.is_exact(14));
    let cases: [(&[f64], Statistic, [f64; 3]); 4] = [
        (&d10, Statistic::Mean, [0.5, 0.25, 0.859375]),
        (&d10, Statistic::Iqm, [0.6875, 0.34375, 0.84375]),
        (
            &D12,
            Statistic::Mean,
            [0.21533203125, 0.107666015625, 0.9111328125],
        ),
        (
            &D12,
            Statistic::Iqm,
            [0.208984375, 0.1044921875, 0.91259765625],
        ),
    ];
    for (d, statistic, [two, greater, less]) in cases {
        close(
            test.p_value(d, statistic, Alternative::TwoSided).unwrap(),
            two,
        );
        close(
            test.p_value(d, statistic, Alternative::Greater).unwrap(),
            greater,
        );
        close(test.p_value(d, statistic, Alternative::Less).unwrap(), less);
    }
}

#[test]
fn tost_equals_the_two_one_sided_scipy_tests() {
    let test = SignFlipTest::default();
    let d10 = differences(&X, &Y).unwrap();
    let cases: [(&[f64], Statistic, f64, f64); 6] = [
        (&d10, Statistic::Mean, 2.0, 0.5234375),
        (&d10, Statistic::Iqm, 2.0, 0.14453125),
        (&D12, Statistic::Mean, 2.0, 0.00244140625),
        (&D12, Statistic::Iqm, 2.0, 0.00390625),
        (&D12, Statistic::Mean, 1.0, 0.14697265625),
        (&D12, Statistic::Iqm, 1.0, 0.15673828125),
    ];
    for (d, statistic, margin, expected) in cases {
        close(
            test.equivalence_p_value(d, statistic, margin).unwrap(),
            expected,
        );
    }
}

#[test]
fn sign_test_equals_scipy_binomtest_and_statsmodels_mcnemar() {
    for (wins, losses, expected) in [
        (2, 0, 0.5),
        (0, 5, 0.0625),
        (3, 14, 0.012725830078125),
        (10, 10, 1.0),
        (1, 19, 4.00543212890625e-05),
        (0, 0, 1.0),
    ] {
        let p = sign_test(wins, losses);
        assert!(
            (p - expected).abs() <= 1e-12 * expected.max(1e-300),
            "{wins} {losses}: {p}"
        );
    }
}

#[test]
fn monte_carlo_sign_flip_is_close_to_exact_and_seeded() {
    // 14 differences: 16 384 sign vectors; 10 000 random ones give p within 4 standard errors.
    let d: Vec<f64> = D12.iter().chain(&[0.8, -0.6]).copied().collect();
    let exact = SignFlipTest::new(1 << 14, 0).unwrap();
    let drawn = SignFlipTest::new(10_000, 3).unwrap();
    let p_exact = exact
        .p_value(&d, Statistic::Mean, Alternative::TwoSided)
        .unwrap();
    let p_drawn = drawn
        .p_value(&d, Statistic::Mean, Alternative::TwoSided)
        .unwrap();
    let se = (p_exact * (1.0 - p_exact) / 10_000.0).sqrt() * 2.0;
    assert!(
        (p_drawn - p_exact).abs() < 4.0 * se,
        "{p_drawn} vs {p_exact}"
    );
    assert_eq!(
        drawn.p_value(&d, Statistic::Mean, Alternative::TwoSided),
        Ok(p_drawn)
    );
}

#[test]
fn paired_bootstrap_is_the_bootstrap_of_the_differences() {
    let bootstrap = Bootstrap::default();
    let interval = paired_difference(&bootstrap, &X, &Y, Statistic::Mean).unwrap();
    let direct = bootstrap
        .interval(&differences(&X, &Y).unwrap(), Statistic::Mean)
        .unwrap();
    assert_eq!(interval, direct);
    close(interval.estimate, 194.4); // (0 − 2 + 2 + 0 + 1942 + 0 + 4 + 0 − 4 + 2) / 10
}

#[test]
fn bad_paired_input_is_a_typed_error() {
    assert!(matches!(
        differences(&X, &Y[..9]),
        Err(StatsError::InvalidParameter { .. })
    ));
    assert!(matches!(
        SignFlipTest::default().equivalence_p_value(&D12, Statistic::Mean, 0.0),
        Err(StatsError::InvalidParameter { name: "margin", .. })
    ));
    assert!(matches!(
        SignFlipTest::default().p_value(&[], Statistic::Mean, Alternative::Less),
        Err(StatsError::Empty { .. })
    ));
}

proptest! {
    /// Swapping the methods mirrors the one-sided p-values and keeps the two-sided one.
    #[test]
    fn swapping_the_pair_mirrors_the_test(d in prop::collection::vec(-50.0_f64..50.0, 1..9)) {
        let test = SignFlipTest::default();
        let negated: Vec<f64> = d.iter().map(|v| -v).collect();
        let p = |d: &[f64], a| test.p_value(d, Statistic::Mean, a).unwrap();
        prop_assert_eq!(p(&d, Alternative::Greater), p(&negated, Alternative::Less));
        prop_assert_eq!(p(&d, Alternative::TwoSided), p(&negated, Alternative::TwoSided));
    }

    /// The sign test is symmetric and a probability; more lopsided splits are more significant.
    #[test]
    fn sign_test_laws(w in 0_u64..60, l in 0_u64..60) {
        let p = sign_test(w, l);
        prop_assert!((0.0..=1.0).contains(&p));
        prop_assert_eq!(p, sign_test(l, w));
        if w > l {
            prop_assert!(sign_test(w + 1, l) <= p + 1e-15);
        }
    }

    /// Equivalence within a wider margin is never harder to show.
    #[test]
    fn a_wider_margin_never_raises_the_tost_p(d in prop::collection::vec(-5.0_f64..5.0, 2..9), m in 0.1_f64..4.0) {
        let test = SignFlipTest::default();
        let narrow = test.equivalence_p_value(&d, Statistic::Mean, m).unwrap();
        let wide = test.equivalence_p_value(&d, Statistic::Mean, 2.0 * m).unwrap();
        prop_assert!(wide <= narrow + 1e-15);
    }
}
