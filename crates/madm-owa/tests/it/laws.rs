//! Mathematical laws of the OWA operator, its weight generators, the natural visibility graph
//! and the MADM decider, as property tests.

use madm_owa::{
    MadmDecider, OwaWeights, Support, Weighting, is_visible, natural_visibility_graph, orness, owa,
    validate_weights,
};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Any finite `f64`, from subnormals to `±f64::MAX`.
fn any_finite() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

/// Values like Q-values, plus small integers (which produce ties and straight lines), plus the
/// occasional extreme value.
fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -100.0..100.0_f64,
        3 => (-3_i32..=3).prop_map(f64::from),
        1 => any_finite(),
    ]
}

fn series(max_len: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(value(), 1..=max_len)
}

fn support() -> impl Strategy<Value = Support> {
    prop_oneof![
        Just(Support::default()),
        Just(Support::Paper { epsilon: 0.0 }),
        Just(Support::Paper { epsilon: 1e-3 }),
        Just(Support::Paper { epsilon: 1.0 }),
        Just(Support::Distance),
    ]
}

fn weighting() -> impl Strategy<Value = Weighting> {
    prop_oneof![
        support().prop_map(|support| Weighting::Visibility { support }),
        Just(Weighting::Uniform),
        (0.0..=1.0_f64).prop_map(|orness| Weighting::MaximumEntropy { orness }),
    ]
}

/// A valid weight vector of length `n` (random non-negative masses, normalised).
fn weights(n: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(0.0..1.0_f64, n).prop_map(|raw| {
        let total: f64 = raw.iter().sum();
        if total > 0.0 {
            raw.iter().map(|w| w / total).collect()
        } else {
            vec![1.0 / raw.len() as f64; raw.len()]
        }
    })
}

fn values_and_weights() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    series(10).prop_flat_map(|v| {
        let n = v.len();
        (Just(v), weights(n))
    })
}

fn min_max(values: &[f64]) -> (f64, f64) {
    values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
}

fn sorted_desc(values: &[f64]) -> Vec<f64> {
    let mut s = values.to_vec();
    s.sort_by(|a, b| b.total_cmp(a));
    s
}

/// The visibility criterion by a second, independent formulation: `a` sees `b` iff every
/// intermediate bar's slope from `a` is strictly below the slope from `a` to `b`, in exact
/// integer arithmetic.
fn brute_force_visible(series: &[i64], a: usize, b: usize) -> bool {
    let (a, b) = (a.min(b), a.max(b));
    let slope_num = i128::from(series[b] - series[a]);
    let slope_den = (b - a) as i128;
    ((a + 1)..b).all(|f| {
        // (y_f - y_a) / (f - a) < (y_b - y_a) / (b - a), denominators positive.
        i128::from(series[f] - series[a]) * slope_den < slope_num * (f - a) as i128
    })
}

fn entropy(w: &[f64]) -> f64 {
    -w.iter()
        .filter(|&&x| x > 0.0)
        .map(|&x| x * x.ln())
        .sum::<f64>()
}

proptest! {
    // ------------------------------------------------------------ weights are valid

    #[test]
    fn visibility_weights_are_valid(s in series(10), sup in support()) {
        let w = OwaWeights::visibility(&s, sup).unwrap();
        prop_assert!(w.as_slice().iter().all(|&x| (0.0..=1.0).contains(&x)), "{:?}", w);
        validate_weights(w.as_slice()).unwrap();
        let sorted = OwaWeights::visibility_of_values(&s, sup).unwrap();
        validate_weights(sorted.as_slice()).unwrap();
    }

    #[test]
    fn visibility_weights_are_valid_for_any_finite_values(
        s in prop::collection::vec(any_finite(), 1..8),
        sup in support(),
    ) {
        let w = OwaWeights::visibility_of_values(&s, sup).unwrap();
        validate_weights(w.as_slice()).unwrap();
        let eq = w.aggregate(&s).unwrap();
        let (lo, hi) = min_max(&s);
        prop_assert!(lo <= eq && eq <= hi, "{eq} outside [{lo}, {hi}]");
    }

    #[test]
    fn uniform_weights_are_valid(n in 1_usize..50) {
        let w = OwaWeights::uniform(n).unwrap();
        validate_weights(w.as_slice()).unwrap();
        prop_assert!((w.orness() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn maximum_entropy_weights_are_valid_and_hit_their_orness(n in 1_usize..16, theta in 0.0..=1.0_f64) {
        let w = OwaWeights::maximum_entropy(n, theta).unwrap();
        validate_weights(w.as_slice()).unwrap();
        prop_assert!(w.as_slice().iter().all(|&x| (0.0..=1.0).contains(&x)));
        if n > 1 {
            prop_assert!((w.orness() - theta).abs() < 1e-9, "orness {} vs {theta}", w.orness());
        }
    }

    #[test]
    fn maximum_entropy_beats_another_vector_of_the_same_orness(n in 2_usize..10, theta in 0.0..=1.0_f64) {
        // Another vector with orness theta: a mix of the max (or min) operator and the mean.
        let mut other = vec![0.0; n];
        if theta >= 0.5 {
            other.iter_mut().for_each(|w| *w = (2.0 - 2.0 * theta) / n as f64);
            other[0] += 2.0 * theta - 1.0;
        } else {
            other.iter_mut().for_each(|w| *w = 2.0 * theta / n as f64);
            other[n - 1] += 1.0 - 2.0 * theta;
        }
        prop_assert!((orness(&other).unwrap() - theta).abs() < 1e-9);
        let me = OwaWeights::maximum_entropy(n, theta).unwrap();
        prop_assert!(entropy(me.as_slice()) >= entropy(&other) - 1e-9);
    }

    #[test]
    fn reversing_weights_mirrors_orness(w in (1_usize..12).prop_flat_map(weights)) {
        let mut rev = w.clone();
        rev.reverse();
        let (o, r) = (orness(&w).unwrap(), orness(&rev).unwrap());
        prop_assert!((o + r - 1.0).abs() < 1e-12, "{o} + {r} != 1");
        prop_assert!((0.0..=1.0 + 1e-12).contains(&o));
    }

    // ------------------------------------------------------------ the OWA operator

    #[test]
    fn owa_lies_between_min_and_max((v, w) in values_and_weights()) {
        let agg = owa(&v, &w).unwrap();
        let (lo, hi) = min_max(&v);
        prop_assert!(lo <= agg && agg <= hi, "{agg} outside [{lo}, {hi}]");
    }

    #[test]
    fn owa_ignores_the_order_of_its_inputs(
        (v, w) in values_and_weights(),
        seed in any::<u64>(),
    ) {
        let mut shuffled = v.clone();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        use rand::seq::SliceRandom;
        shuffled.shuffle(&mut rng);
        prop_assert_eq!(owa(&v, &w).unwrap(), owa(&shuffled, &w).unwrap());
    }

    #[test]
    fn owa_of_a_constant_is_that_constant(c in value(), n in 1_usize..10, sup in support()) {
        let v = vec![c; n];
        let w = OwaWeights::visibility_of_values(&v, sup).unwrap();
        prop_assert_eq!(w.aggregate(&v).unwrap(), c);
        let me = OwaWeights::maximum_entropy(n, 0.3).unwrap();
        prop_assert_eq!(me.aggregate(&v).unwrap(), c);
    }

    #[test]
    fn paper_weights_are_exactly_invariant_to_power_of_two_scaling(
        s in prop::collection::vec(-100.0..100.0_f64, 1..8),
        e in -20_i32..20,
    ) {
        // With epsilon = 0 the support is homogeneous of degree 0; scaling by 2^e is exact.
        let sup = Support::Paper { epsilon: 0.0 };
        let scaled: Vec<f64> = s.iter().map(|x| x * 2.0_f64.powi(e)).collect();
        prop_assert_eq!(
            OwaWeights::visibility_of_values(&s, sup).unwrap(),
            OwaWeights::visibility_of_values(&scaled, sup).unwrap()
        );
    }

    // ------------------------------------------------------------ visibility graph

    #[test]
    fn visibility_graph_matches_brute_force(ints in prop::collection::vec(-20_i64..20, 0..12)) {
        let s: Vec<f64> = ints.iter().map(|&x| x as f64).collect();
        let edges = natural_visibility_graph(&s).unwrap();
        let mut expected = Vec::new();
        for a in 0..ints.len() {
            for b in (a + 1)..ints.len() {
                if brute_force_visible(&ints, a, b) {
                    expected.push((a, b));
                }
            }
        }
        prop_assert_eq!(edges, expected);
    }

    #[test]
    fn visibility_graph_matches_brute_force_on_dyadic_values(
        ints in prop::collection::vec(-400_i64..400, 0..10),
    ) {
        // Quarters and the like are exact in binary: the criterion must stay exact.
        let s: Vec<f64> = ints.iter().map(|&x| x as f64 / 64.0).collect();
        for a in 0..s.len() {
            for b in (a + 1)..s.len() {
                prop_assert_eq!(is_visible(&s, a, b), brute_force_visible(&ints, a, b), "({}, {})", a, b);
            }
        }
    }

    #[test]
    fn visibility_is_symmetric_and_connects_neighbours(s in series(12)) {
        for i in 0..s.len() {
            prop_assert!(!is_visible(&s, i, i));
            for k in 0..s.len() {
                prop_assert_eq!(is_visible(&s, i, k), is_visible(&s, k, i));
            }
            if i + 1 < s.len() {
                prop_assert!(is_visible(&s, i, i + 1));
            }
        }
        let edges = natural_visibility_graph(&s).unwrap();
        prop_assert!(edges.iter().all(|&(i, k)| i < k && is_visible(&s, i, k)));
        prop_assert!(edges.windows(2).all(|p| p[0] < p[1]), "sorted, no duplicates");
    }

    // ------------------------------------------------------------ the decider

    #[test]
    fn decider_values_are_finite_bounded_and_order_free(
        (rows, cols, matrix) in (1_usize..6, 1_usize..6).prop_flat_map(|(r, c)| {
            (Just(r), Just(c), prop::collection::vec(value(), r * c))
        }),
        w in weighting(),
        seed in any::<u64>(),
    ) {
        let mut d = MadmDecider::new(w).unwrap();
        let mut out = vec![0.0; rows];
        d.evaluate(&matrix, rows, cols, &mut out).unwrap();
        for (row, &eq) in matrix.chunks(cols).zip(&out) {
            let (lo, hi) = min_max(row);
            prop_assert!(eq.is_finite() && lo <= eq && eq <= hi, "{eq} for {row:?}");
        }
        // Permuting the attributes inside every row changes nothing.
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        use rand::seq::SliceRandom;
        let mut permuted = matrix.clone();
        for row in permuted.chunks_mut(cols) {
            row.shuffle(&mut rng);
        }
        let mut out2 = vec![0.0; rows];
        d.evaluate(&permuted, rows, cols, &mut out2).unwrap();
        prop_assert_eq!(&out, &out2);
        // The best row has the largest value.
        let best = d.best_row(&matrix, rows, cols, &mut rng).unwrap();
        prop_assert!(out.iter().all(|&v| v <= out[best]));
        prop_assert_eq!(d.last_values(), &out[..]);
    }

    #[test]
    fn decider_agrees_with_the_standalone_weights(row in series(12), sup in support()) {
        let mut d = MadmDecider::new(Weighting::Visibility { support: sup }).unwrap();
        let mut out = [0.0];
        d.evaluate(&row, 1, row.len(), &mut out).unwrap();
        // The decider fuses the normalisation into one division per row: equal up to rounding.
        let w = OwaWeights::visibility_of_values(&row, sup).unwrap();
        let (lo, hi) = min_max(&row);
        let tolerance = 1e-12 * lo.abs().max(hi.abs());
        let standalone = w.aggregate(&row).unwrap();
        prop_assert!((out[0] - standalone).abs() <= tolerance, "{} vs {standalone}", out[0]);
        let mut rw = vec![0.0; row.len()];
        prop_assert_eq!(d.row_weights(&row, &mut rw).unwrap(), out[0]);
        prop_assert_eq!(&rw[..], w.as_slice());
        // The slice-level OWA on the sorted row is the standalone path exactly.
        prop_assert_eq!(owa(&sorted_desc(&row), w.as_slice()).unwrap(), standalone);
    }
}
