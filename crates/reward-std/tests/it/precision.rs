//! Precision of the cross-sectional standardisation for rewards with a large common offset and
//! a tiny spread (issue 14, item 10): the mean of the z-scores (Eq. 12) stays within 1e-12.

use proptest::prelude::*;
use reward_std::cross_sectional;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Offsets up to 1e9 in magnitude, spreads of ±1e-3: the shift before the sums keeps the
    /// deviations' digits, so Eq. 12's mean is zero to within 1e-12.
    #[test]
    fn mean_of_z_scores_stays_zero_under_a_large_offset(
        offset in -1e9..1e9_f64,
        deviations in prop::collection::vec(-1e-3..1e-3_f64, 2..16),
    ) {
        let rewards: Vec<f64> = deviations.iter().map(|d| offset + d).collect();
        let mut z = vec![0.0; rewards.len()];
        let mean = cross_sectional(&rewards, &mut z).unwrap();
        prop_assert!(mean.abs() <= 1e-12, "mean {mean:e} for offset {offset}, {deviations:?}");
        prop_assert!(z.iter().all(|v| v.is_finite()));
    }
}

/// The example: 1e6 + U(±1e-3) gave a mean of 7e-5 before the fix.
#[test]
fn the_reported_offset_of_a_million_is_exact_enough() {
    let rewards = [
        1e6 + 3.1e-4,
        1e6 - 9.7e-4,
        1e6 + 2.2e-5,
        1e6 - 1.5e-4,
        1e6 + 8.8e-4,
    ];
    let mut z = [0.0; 5];
    let mean = cross_sectional(&rewards, &mut z).unwrap();
    assert!(mean.abs() <= 1e-12, "mean {mean:e}");
}
