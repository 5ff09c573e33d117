//! The worked examples of the project's paper notes (§5) and Yager (1988), the reference
//! visibility edges, the error cases and the extreme-value behaviour, as plain unit tests.

use madm_owa::{
    MadmDecider, MadmError, OwaWeights, Support, WEIGHT_SUM_TOLERANCE, Weighting, andness,
    is_visible, natural_visibility_graph, orness, owa, owa_sorted, validate_weights,
    visibility_weights_into,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn assert_close(got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "got {got}, want {want} (tolerance {tol})"
    );
}

// ---------------------------------------------------------------- Yager's OWA example

#[test]
fn yager_worked_example_aggregates_to_0_76() {
    assert_close(
        owa(&[0.7, 1.0, 0.3, 0.6], &[0.4, 0.3, 0.2, 0.1]).unwrap(),
        0.76,
        1e-12,
    );
}

#[test]
fn yager_worked_example_has_orness_two_thirds() {
    assert_close(orness(&[0.4, 0.3, 0.2, 0.1]).unwrap(), 2.0 / 3.0, 1e-12);
    assert_close(andness(&[0.4, 0.3, 0.2, 0.1]).unwrap(), 1.0 / 3.0, 1e-12);
}

#[test]
fn orness_of_max_min_and_mean_operators() {
    assert_close(orness(&[1.0, 0.0, 0.0]).unwrap(), 1.0, 0.0);
    assert_close(orness(&[0.0, 0.0, 1.0]).unwrap(), 0.0, 0.0);
    assert_close(orness(&[0.25; 4]).unwrap(), 0.5, 1e-15);
    // One weight: 0/0 in the formula, defined as one half.
    assert_close(orness(&[1.0]).unwrap(), 0.5, 0.0);
}

#[test]
fn owa_sorted_matches_owa_and_rejects_unsorted_input() {
    let w = [0.4, 0.3, 0.2, 0.1];
    assert_close(owa_sorted(&[1.0, 0.7, 0.6, 0.3], &w).unwrap(), 0.76, 1e-12);
    assert_eq!(
        owa_sorted(&[1.0, 0.6, 0.7, 0.3], &w),
        Err(MadmError::NotDescending {
            index: 2,
            value: 0.7,
            previous: 0.6
        })
    );
}

// ---------------------------------------------------------------- maximum-entropy weights

#[test]
fn maximum_entropy_weights_match_the_literature_for_n3_orness_0_7() {
    // Fullér & Majlender (2001), also O'Hagan: (0.554, 0.292, 0.154).
    let w = OwaWeights::maximum_entropy(3, 0.7).unwrap();
    let expected = [0.553_97, 0.292_06, 0.153_97];
    for (got, want) in w.as_slice().iter().zip(expected) {
        assert_close(*got, want, 1e-5);
    }
    assert_close(w.orness(), 0.7, 1e-12);
}

#[test]
fn maximum_entropy_ends_are_exact_operators() {
    assert_eq!(
        OwaWeights::maximum_entropy(4, 1.0).unwrap().as_slice(),
        [1.0, 0.0, 0.0, 0.0]
    );
    assert_eq!(
        OwaWeights::maximum_entropy(4, 0.0).unwrap().as_slice(),
        [0.0, 0.0, 0.0, 1.0]
    );
    assert_eq!(
        OwaWeights::maximum_entropy(4, 0.5).unwrap().as_slice(),
        [0.25; 4]
    );
    assert_eq!(
        OwaWeights::maximum_entropy(1, 0.9).unwrap().as_slice(),
        [1.0]
    );
}

#[test]
fn maximum_entropy_rejects_orness_outside_unit_interval() {
    for bad in [-0.1, 1.1, f64::NAN] {
        assert!(matches!(
            OwaWeights::maximum_entropy(3, bad),
            Err(MadmError::InvalidParameter { name: "orness", .. })
        ));
    }
    assert_eq!(
        OwaWeights::maximum_entropy(0, 0.5),
        Err(MadmError::Empty { what: "weights" })
    );
}

// ---------------------------------------------------------------- visibility graph

#[test]
fn reference_visibility_edges_from_paper_notes() {
    assert_eq!(
        natural_visibility_graph(&[3.0, 1.0, 2.0, 4.0]).unwrap(),
        [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    );
    assert_eq!(
        natural_visibility_graph(&[4.0, 3.0, 2.0, 1.0]).unwrap(),
        [(0, 1), (1, 2), (2, 3)]
    );
    assert_eq!(
        natural_visibility_graph(&[1.0, 1.0, 1.0]).unwrap(),
        [(0, 1), (1, 2)]
    );
    assert_eq!(
        natural_visibility_graph(&[0.9, 0.7, 0.6, 0.3]).unwrap(),
        [(0, 1), (0, 2), (1, 2), (2, 3)]
    );
}

#[test]
fn visibility_graph_of_short_series() {
    assert!(natural_visibility_graph(&[]).unwrap().is_empty());
    assert!(natural_visibility_graph(&[5.0]).unwrap().is_empty());
    assert_eq!(natural_visibility_graph(&[5.0, -5.0]).unwrap(), [(0, 1)]);
}

#[test]
fn point_exactly_on_the_line_blocks() {
    // (1, 2) lies exactly on the line from (0, 3) to (2, 1).
    assert!(!is_visible(&[3.0, 2.0, 1.0], 0, 2));
    // Nudged below the line it no longer blocks.
    assert!(is_visible(&[3.0, 1.999, 1.0], 0, 2));
}

#[test]
fn is_visible_handles_bad_indices_and_order() {
    let s = [3.0, 1.0, 2.0];
    assert!(!is_visible(&s, 1, 1));
    assert!(!is_visible(&s, 0, 3));
    assert!(is_visible(&s, 2, 0));
}

#[test]
fn visibility_graph_rejects_non_finite_values() {
    let err = natural_visibility_graph(&[1.0, f64::NAN]).unwrap_err();
    assert!(
        matches!(err, MadmError::NonFinite { what: "series", index: 1, value } if value.is_nan())
    );
    assert_eq!(err.to_string(), "`series[1]` is NaN, not a finite number");
    assert!(matches!(
        natural_visibility_graph(&[1.0, f64::INFINITY]),
        Err(MadmError::NonFinite {
            what: "series",
            index: 1,
            ..
        })
    ));
}

#[test]
fn visibility_is_exact_near_f64_max() {
    // Differences overflow here; the scaled re-check must still see the geometry.
    let big = f64::MAX;
    assert_eq!(
        natural_visibility_graph(&[big, -big, big]).unwrap(),
        [(0, 1), (0, 2), (1, 2)]
    );
    assert_eq!(
        natural_visibility_graph(&[-big, big, -big]).unwrap(),
        [(0, 1), (1, 2)]
    );
}

// ---------------------------------------------------------------- visibility weights

#[test]
fn worked_example_supports_weights_and_aggregate() {
    let sorted = [0.9, 0.7, 0.6, 0.3];
    let mut w = [0.0; 4];
    visibility_weights_into(&sorted, Support::default(), &mut w).unwrap();
    let supports = [21.75, 57.75, 50.0, 2.0];
    for (got, s) in w.iter().zip(supports) {
        assert_close(*got, s / 131.5, 1e-7);
    }
    assert_close(w[0], 0.1654, 1e-4);
    assert_close(w[1], 0.4392, 1e-4);
    assert_close(w[2], 0.3802, 1e-4);
    assert_close(w[3], 0.0152, 1e-4);
    let eq = owa_sorted(&sorted, &w).unwrap();
    assert_close(eq, 0.689, 1e-3);
    assert_close(eq, 90.6 / 131.5, 1e-7);
}

#[test]
fn literal_epsilon_zero_falls_back_to_uniform_on_ties() {
    let mut w = [0.0; 3];
    visibility_weights_into(&[2.0, 2.0, 1.0], Support::Paper { epsilon: 0.0 }, &mut w).unwrap();
    assert_eq!(w, [1.0 / 3.0; 3]);
    // Without a tie, epsilon = 0 is the literal Eq. 15.
    visibility_weights_into(&[0.9, 0.7, 0.6], Support::Paper { epsilon: 0.0 }, &mut w).unwrap();
    // Supports: (15.75 + 6, 15.75 + 42, 6 + 42) out of 127.5.
    assert_close(w[0], 21.75 / 127.5, 1e-12);
    assert_close(w[1], 57.75 / 127.5, 1e-12);
    assert_close(w[2], 48.0 / 127.5, 1e-12);
}

#[test]
fn ties_dominate_with_small_epsilon() {
    let mut w = [0.0; 3];
    visibility_weights_into(&[2.0, 2.0, 1.0], Support::default(), &mut w).unwrap();
    // The tie's support 4e9 dwarfs the rest.
    assert_close(w[0], 0.5, 1e-6);
    assert_close(w[1], 0.5, 1e-6);
    assert!(w[2] < 1e-6);
}

#[test]
fn zero_total_support_falls_back_to_uniform() {
    let mut w = [0.0; 2];
    // Opposite signs: the paper support clamps the negative product to 0.
    visibility_weights_into(&[1.0, -1.0], Support::default(), &mut w).unwrap();
    assert_eq!(w, [0.5, 0.5]);
    // Two distinct values are each other's extremes: distance support 0.
    visibility_weights_into(&[3.0, 1.0], Support::Distance, &mut w).unwrap();
    assert_eq!(w, [0.5, 0.5]);
    // A single value always gets weight 1.
    let mut one = [0.0];
    visibility_weights_into(&[7.0], Support::Distance, &mut one).unwrap();
    assert_eq!(one, [1.0]);
}

#[test]
fn distance_support_on_worked_example() {
    let mut w = [0.0; 4];
    visibility_weights_into(&[0.9, 0.7, 0.6, 0.3], Support::Distance, &mut w).unwrap();
    // range 0.6; edges (0,1): 1 - 0.2/0.6, (0,2): 0.5, (1,2): 1 - 0.1/0.6, (2,3): 0.5.
    let (s01, s02, s12, s23) = (2.0 / 3.0, 0.5, 5.0 / 6.0, 0.5);
    let total = 2.0 * (s01 + s02 + s12 + s23);
    let expected = [s01 + s02, s01 + s12, s02 + s12 + s23, s23].map(|s| s / total);
    for (got, want) in w.iter().zip(expected) {
        assert_close(*got, want, 1e-12);
    }
}

#[test]
fn distance_support_with_zero_range_weights_by_degree() {
    let mut w = [0.0; 4];
    visibility_weights_into(&[2.0; 4], Support::Distance, &mut w).unwrap();
    // Only neighbours see each other: degrees (1, 2, 2, 1).
    assert_eq!(w, [1.0 / 6.0, 2.0 / 6.0, 2.0 / 6.0, 1.0 / 6.0]);
}

#[test]
fn visibility_weights_reject_bad_input() {
    let mut w = [0.0; 2];
    assert_eq!(
        visibility_weights_into(&[], Support::default(), &mut []),
        Err(MadmError::Empty { what: "series" })
    );
    assert_eq!(
        visibility_weights_into(&[1.0, 2.0, 3.0], Support::default(), &mut w),
        Err(MadmError::LengthMismatch {
            what: "out",
            expected: 3,
            found: 2
        })
    );
    assert!(matches!(
        visibility_weights_into(&[1.0, f64::NEG_INFINITY], Support::default(), &mut w),
        Err(MadmError::NonFinite {
            what: "series",
            index: 1,
            ..
        })
    ));
    for epsilon in [-1e-9, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            visibility_weights_into(&[1.0, 2.0], Support::Paper { epsilon }, &mut w),
            Err(MadmError::InvalidParameter {
                name: "epsilon",
                ..
            })
        ));
    }
}

// ---------------------------------------------------------------- extreme values

#[test]
fn huge_values_give_finite_valid_results() {
    for support in [
        Support::default(),
        Support::Paper { epsilon: 0.0 },
        Support::Distance,
    ] {
        for row in [
            [1e300, 1e300, -1e300, 5.0],
            [f64::MAX, -f64::MAX, f64::MAX, 0.0],
            [1e300, 9e299, 8e299, 1e-300],
            [1e-300, 2e-300, 0.0, -1e-300],
        ] {
            let w = OwaWeights::visibility_of_values(&row, support).unwrap();
            validate_weights(w.as_slice()).unwrap();
            let eq = w.aggregate(&row).unwrap();
            assert!(eq.is_finite(), "{support:?} {row:?} -> {eq}");
            let (lo, hi) = row
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
            assert!(lo <= eq && eq <= hi, "{support:?} {row:?} -> {eq}");
        }
    }
}

#[test]
fn overflowing_products_fall_back_to_uniform() {
    // 1e300 * 9e299 overflows: the paper support's total is infinite, weights are uniform.
    let w = OwaWeights::visibility_of_values(&[1e300, 9e299, 8e299], Support::default()).unwrap();
    assert_eq!(w.as_slice(), [1.0 / 3.0; 3]);
    // The distance support works on halved values and never overflows.
    let w =
        OwaWeights::visibility_of_values(&[f64::MAX, 0.0, -f64::MAX], Support::Distance).unwrap();
    assert_eq!(w.as_slice(), [0.25, 0.5, 0.25]);
}

#[test]
fn decider_survives_supports_whose_products_with_values_overflow() {
    // The tie's support is about 1e289 (finite), but support x value overflows: the decider
    // must take its normalise-first path and still agree with the standalone weights.
    let row = [1e140, 5e139, 1e140];
    let mut d = MadmDecider::default();
    let mut out = [0.0];
    d.evaluate(&row, 1, 3, &mut out).unwrap();
    let standalone = OwaWeights::visibility_of_values(&row, Support::default())
        .unwrap()
        .aggregate(&row)
        .unwrap();
    assert!(out[0].is_finite());
    assert_close(out[0] / 1e140, 1.0, 1e-9);
    assert_eq!(out[0], standalone);
}

#[test]
fn owa_of_values_near_f64_max_stays_finite() {
    let v = owa(&[f64::MAX, f64::MAX, f64::MAX], &[0.2, 0.3, 0.5]).unwrap();
    assert_eq!(v, f64::MAX);
    let v = owa(&[f64::MAX, -f64::MAX], &[0.5, 0.5]).unwrap();
    assert_eq!(v, 0.0);
}

// ---------------------------------------------------------------- weight validation

#[test]
fn weight_validation_names_the_problem() {
    assert_eq!(
        validate_weights(&[]),
        Err(MadmError::Empty { what: "weights" })
    );
    assert_eq!(
        validate_weights(&[0.6, -0.1, 0.5]),
        Err(MadmError::NegativeWeight {
            index: 1,
            value: -0.1
        })
    );
    assert_eq!(
        validate_weights(&[0.5, 0.4]),
        Err(MadmError::WeightSum {
            sum: 0.9,
            tolerance: WEIGHT_SUM_TOLERANCE
        })
    );
    assert!(matches!(
        validate_weights(&[0.5, f64::NAN]),
        Err(MadmError::NonFinite {
            what: "weights",
            index: 1,
            ..
        })
    ));
    // Sums off by rounding are accepted.
    validate_weights(&[0.1, 0.2, 0.3, 0.4]).unwrap();
    assert_eq!(
        owa(&[1.0], &[0.5, 0.5]),
        Err(MadmError::LengthMismatch {
            what: "values",
            expected: 2,
            found: 1
        })
    );
    assert!(matches!(
        owa(&[1.0, f64::NAN], &[0.5, 0.5]),
        Err(MadmError::NonFinite {
            what: "values",
            index: 1,
            ..
        })
    ));
}

#[test]
fn error_messages_name_parameter_and_value() {
    let e = validate_weights(&[0.6, -0.1, 0.5]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "weight 1 is -0.1; OWA weights must be non-negative"
    );
    let e = MadmDecider::new(Weighting::MaximumEntropy { orness: 1.5 }).unwrap_err();
    assert_eq!(
        e.to_string(),
        "parameter `orness` is 1.5: must be in [0, 1]"
    );
}

// ---------------------------------------------------------------- the decider

#[test]
fn decider_rejects_bad_matrices() {
    let mut d = MadmDecider::default();
    let mut out = [0.0; 2];
    assert_eq!(
        d.evaluate(&[], 0, 2, &mut []),
        Err(MadmError::EmptyMatrix { rows: 0, cols: 2 })
    );
    assert_eq!(
        d.evaluate(&[], 2, 0, &mut out),
        Err(MadmError::EmptyMatrix { rows: 2, cols: 0 })
    );
    assert_eq!(
        d.evaluate(&[1.0; 5], 2, 3, &mut out),
        Err(MadmError::ShapeMismatch {
            rows: 2,
            cols: 3,
            len: 5
        })
    );
    assert_eq!(
        d.evaluate(&[1.0; 6], 2, 3, &mut [0.0; 3]),
        Err(MadmError::LengthMismatch {
            what: "out",
            expected: 2,
            found: 3
        })
    );
    let mut m = [1.0; 6];
    m[4] = f64::INFINITY;
    assert_eq!(
        d.evaluate(&m, 2, 3, &mut out),
        Err(MadmError::NonFiniteEntry {
            row: 1,
            col: 1,
            value: f64::INFINITY
        })
    );
    assert_eq!(out, [0.0; 2], "out is untouched on error");
    assert_eq!(
        d.evaluate(&[1.0; 4], usize::MAX, 2, &mut out),
        Err(MadmError::ShapeMismatch {
            rows: usize::MAX,
            cols: 2,
            len: 4
        })
    );
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    assert!(d.best_row(&m, 2, 3, &mut rng).is_err());
    // The decider still works after errors.
    assert_eq!(d.best_row(&[1.0, 2.0, 3.0, 4.0], 2, 2, &mut rng), Ok(1));
}

#[test]
fn decider_with_given_weights_checks_the_column_count() {
    let weights = OwaWeights::new(vec![0.4, 0.3, 0.2, 0.1]).unwrap();
    let mut d = MadmDecider::new(Weighting::Given { weights }).unwrap();
    let mut out = [0.0; 1];
    d.evaluate(&[0.7, 1.0, 0.3, 0.6], 1, 4, &mut out).unwrap();
    assert_close(out[0], 0.76, 1e-12);
    assert!(matches!(
        d.evaluate(&[0.7, 1.0, 0.3], 1, 3, &mut out),
        Err(MadmError::LengthMismatch {
            expected: 3,
            found: 4,
            ..
        })
    ));
}

#[test]
fn decider_switches_shapes_and_weightings() {
    let mut out = [0.0; 2];
    let mut uniform = MadmDecider::new(Weighting::Uniform).unwrap();
    uniform
        .evaluate(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 2, 3, &mut out)
        .unwrap();
    assert_close(out[0], 2.0, 1e-15);
    assert_close(out[1], 5.0, 1e-15);
    uniform
        .evaluate(&[1.0, 3.0, 5.0, 7.0], 2, 2, &mut out)
        .unwrap();
    assert_eq!(out, [2.0, 6.0]);

    let mut max = MadmDecider::new(Weighting::MaximumEntropy { orness: 1.0 }).unwrap();
    max.evaluate(&[1.0, 2.0, 3.0, 6.0, 5.0, 4.0], 2, 3, &mut out)
        .unwrap();
    assert_eq!(out, [3.0, 6.0]);
    let mut min = MadmDecider::new(Weighting::MaximumEntropy { orness: 0.0 }).unwrap();
    min.evaluate(&[1.0, 2.0, 3.0, 6.0, 5.0, 4.0], 2, 3, &mut out)
        .unwrap();
    assert_eq!(out, [1.0, 4.0]);
    min.evaluate(&[1.0, 2.0, 6.0, 5.0], 2, 2, &mut out).unwrap();
    assert_eq!(out, [1.0, 5.0]);
}

#[test]
fn decider_row_weights_expose_the_worked_example() {
    let mut d = MadmDecider::default();
    let mut w = [0.0; 4];
    // Unsorted on purpose: the decider sorts.
    let eq = d.row_weights(&[0.3, 0.9, 0.6, 0.7], &mut w).unwrap();
    assert_close(eq, 90.6 / 131.5, 1e-7);
    assert_close(w[1], 57.75 / 131.5, 1e-7);
}

#[test]
fn best_row_ties_are_broken_by_the_rng_and_values_are_kept() {
    // Rows 0, 2 and 3 hold the same attributes in different orders: an exact tie.
    let matrix = [0.2, 0.5, 0.1, 0.0, 0.0, 0.0, 0.1, 0.2, 0.5, 0.5, 0.1, 0.2];
    let mut d = MadmDecider::default();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut counts = [0_u32; 4];
    for _ in 0..300 {
        counts[d.best_row(&matrix, 4, 3, &mut rng).unwrap()] += 1;
    }
    assert_eq!(counts[1], 0);
    assert!(
        counts[0] > 60 && counts[2] > 60 && counts[3] > 60,
        "{counts:?}"
    );
    let values = d.last_values();
    assert_eq!(values.len(), 4);
    assert_eq!(values[0], values[2]);
    assert_eq!(values[0], values[3]);

    // Same seed, same choices.
    let mut a = ChaCha8Rng::seed_from_u64(5);
    let mut b = ChaCha8Rng::seed_from_u64(5);
    let picks_a: Vec<_> = (0..20)
        .map(|_| d.best_row(&matrix, 4, 3, &mut a).unwrap())
        .collect();
    let picks_b: Vec<_> = (0..20)
        .map(|_| d.best_row(&matrix, 4, 3, &mut b).unwrap())
        .collect();
    assert_eq!(picks_a, picks_b);
}

// ---------------------------------------------------------------- configuration

#[test]
fn weighting_reads_from_toml_as_documented() {
    #[derive(serde::Deserialize)]
    struct Config {
        weighting: Weighting,
    }
    let parse = |text: &str| toml::from_str::<Config>(text).map(|c| c.weighting);
    assert_eq!(
        parse(
            r#"weighting = { kind = "visibility", support = { kind = "paper", epsilon = 1e-6 } }"#
        )
        .unwrap(),
        Weighting::Visibility {
            support: Support::Paper { epsilon: 1e-6 }
        }
    );
    assert_eq!(
        parse(r#"weighting = { kind = "visibility", support = { kind = "distance" } }"#).unwrap(),
        Weighting::Visibility {
            support: Support::Distance
        }
    );
    assert_eq!(
        parse(r#"weighting = { kind = "visibility" }"#).unwrap(),
        Weighting::default()
    );
    assert_eq!(
        parse(r#"weighting = { kind = "visibility", support = { kind = "paper" } }"#).unwrap(),
        Weighting::default()
    );
    assert_eq!(
        parse(r#"weighting = { kind = "uniform" }"#).unwrap(),
        Weighting::Uniform
    );
    assert_eq!(
        parse(r#"weighting = { kind = "maximum_entropy", orness = 0.7 }"#).unwrap(),
        Weighting::MaximumEntropy { orness: 0.7 }
    );
    assert_eq!(
        parse(r#"weighting = { kind = "given", weights = [0.4, 0.3, 0.2, 0.1] }"#).unwrap(),
        Weighting::Given {
            weights: OwaWeights::new(vec![0.4, 0.3, 0.2, 0.1]).unwrap()
        }
    );
    // Invalid weights, unknown kinds and misspelt fields are rejected.
    let err = parse(r#"weighting = { kind = "given", weights = [0.5, 0.4] }"#).unwrap_err();
    assert!(err.to_string().contains("weights sum to 0.9"), "{err}");
    assert!(parse(r#"weighting = { kind = "softmax" }"#).is_err());
    assert!(
        parse(r#"weighting = { kind = "visibility", support = { kind = "paper", epsion = 1.0 } }"#)
            .is_err()
    );
}

#[test]
fn weighting_round_trips_through_json() {
    for w in [
        Weighting::default(),
        Weighting::Uniform,
        Weighting::Visibility {
            support: Support::Distance,
        },
        Weighting::MaximumEntropy { orness: 0.25 },
        Weighting::Given {
            weights: OwaWeights::new(vec![0.5, 0.5]).unwrap(),
        },
    ] {
        let json = serde_json::to_string(&w).unwrap();
        assert_eq!(
            serde_json::from_str::<Weighting>(&json).unwrap(),
            w,
            "{json}"
        );
    }
    assert_eq!(
        serde_json::to_string(&Weighting::default()).unwrap(),
        r#"{"kind":"visibility","support":{"kind":"paper","epsilon":1e-9}}"#
    );
}

#[test]
fn misspelt_keys_are_rejected_and_named_even_beside_field_less_kinds() {
    #[derive(serde::Deserialize)]
    struct Config {
        weighting: Weighting,
    }
    let rejects = |text: &str, key: &str| {
        let err = toml::from_str::<Config>(text)
            .map(|c| c.weighting)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!("unknown field `{key}`")),
            "{text}: {err}"
        );
    };
    // Field-less kinds: plain unit variants would ignore the extra key.
    rejects(
        r#"weighting = { kind = "uniform", orness = 0.7 }"#,
        "orness",
    );
    rejects(
        r#"weighting = { kind = "visibility", support = { kind = "distance", epsilon = 0.1 } }"#,
        "epsilon",
    );
    rejects(
        r#"weighting = { kind = "visibility", suport = { kind = "distance" } }"#,
        "suport",
    );
    rejects(
        r#"weighting = { kind = "maximum_entropy", ornes = 0.7 }"#,
        "ornes",
    );
    rejects(
        r#"weighting = { kind = "given", weight = [1.0] }"#,
        "weight",
    );
    rejects(
        r#"weighting = { kind = "visibility", support = { kind = "paper", epsion = 1.0 } }"#,
        "epsion",
    );
    let err = serde_json::from_str::<Support>(r#"{"kind":"distance","range":1.0}"#).unwrap_err();
    assert!(err.to_string().contains("unknown field `range`"), "{err}");
}

#[test]
fn serialised_forms_are_the_documented_ones() {
    for (support, json) in [
        (Support::default(), r#"{"kind":"paper","epsilon":1e-9}"#),
        (Support::Distance, r#"{"kind":"distance"}"#),
    ] {
        assert_eq!(serde_json::to_string(&support).unwrap(), json);
        assert_eq!(serde_json::from_str::<Support>(json).unwrap(), support);
    }
    for (weighting, json) in [
        (Weighting::Uniform, r#"{"kind":"uniform"}"#),
        (
            Weighting::Visibility {
                support: Support::Distance,
            },
            r#"{"kind":"visibility","support":{"kind":"distance"}}"#,
        ),
        (
            Weighting::MaximumEntropy { orness: 0.25 },
            r#"{"kind":"maximum_entropy","orness":0.25}"#,
        ),
        (
            Weighting::Given {
                weights: OwaWeights::new(vec![0.75, 0.25]).unwrap(),
            },
            r#"{"kind":"given","weights":[0.75,0.25]}"#,
        ),
    ] {
        assert_eq!(serde_json::to_string(&weighting).unwrap(), json);
        assert_eq!(serde_json::from_str::<Weighting>(json).unwrap(), weighting);
    }
    // TOML writes the same tables.
    assert_eq!(
        toml::to_string(&Weighting::Uniform).unwrap().trim(),
        r#"kind = "uniform""#
    );
}
