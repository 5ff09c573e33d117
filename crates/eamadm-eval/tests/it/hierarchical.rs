//! The two-level bootstrap over layouts and seeds (issue 33): against a plain materialising
//! implementation of its documented draws (bit for bit), its laws (symmetry, the one-level
//! cases equal the plain bootstrap, pairing), and reference values: the exact variance of the
//! bootstrap distribution and, for a tiny sample, the exact distribution by enumeration.

use eamadm_eval::stats::hierarchical::{HierarchicalBootstrap, Stages};
use eamadm_eval::stats::{Bootstrap, Statistic, StatsError};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Lemire's index below `k`, one word of `rng` at a time.
fn below(rng: &mut ChaCha8Rng, k: usize) -> usize {
    let k = k as u64;
    loop {
        let product = u64::from(rng.next_u32()) * k;
        if (product as u32 as u64) >= ((1_u64 << 32) - k) % k {
            return (product >> 32) as usize;
        }
    }
}

fn sorted(x: &[f64]) -> Vec<f64> {
    let mut sorted = x.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted
}

/// The documented draws, materialised: layouts in canonical order (`within` statistic, then
/// sorted values compared lexicographically, then length), each resample built value by value and its statistic
/// taken by `Statistic::of`.
fn replicates_by_materialising(
    bootstrap: &HierarchicalBootstrap,
    layouts: &[Vec<f64>],
    within: Statistic,
    across: Statistic,
) -> Vec<f64> {
    let mut canonical: Vec<Vec<f64>> = layouts.iter().map(|l| sorted(l)).collect();
    canonical.sort_by(|a, b| {
        within
            .of(a)
            .unwrap()
            .total_cmp(&within.of(b).unwrap())
            .then_with(|| {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| x.total_cmp(y))
                    .find(|o| o.is_ne())
                    .unwrap_or_else(|| a.len().cmp(&b.len()))
            })
    });
    let a = canonical.len();
    let mut rng = ChaCha8Rng::seed_from_u64(bootstrap.seed);
    (0..bootstrap.resamples)
        .map(|_| {
            let picks: Vec<usize> = if a == 1 {
                vec![0]
            } else {
                (0..a).map(|_| below(&mut rng, a)).collect()
            };
            let values: Vec<f64> = picks
                .iter()
                .map(|&layout| {
                    let seeds = &canonical[layout];
                    let resample: Vec<f64> =
                        if seeds.len() == 1 || bootstrap.stages == Stages::LayoutsOnly {
                            seeds.clone()
                        } else {
                            (0..seeds.len())
                                .map(|_| seeds[below(&mut rng, seeds.len())])
                                .collect()
                        };
                    within.of(&resample).unwrap()
                })
                .collect();
            across.of(&values).unwrap()
        })
        .collect()
}

fn layouts_strategy(max_layouts: usize, max_seeds: usize) -> impl Strategy<Value = Vec<Vec<f64>>> {
    let value = prop_oneof![
        (-50_i32..50).prop_map(f64::from),
        -1e3..1e3_f64,
        Just(0.1),
        Just(0.2),
        Just(0.3),
    ];
    prop::collection::vec(prop::collection::vec(value, 1..=max_seeds), 1..=max_layouts)
}

fn statistic() -> impl Strategy<Value = Statistic> {
    prop_oneof![
        Just(Statistic::Mean),
        Just(Statistic::Median),
        Just(Statistic::Iqm)
    ]
}

fn stages() -> impl Strategy<Value = Stages> {
    prop_oneof![Just(Stages::LayoutsThenSeeds), Just(Stages::LayoutsOnly)]
}

fn views(layouts: &[Vec<f64>]) -> Vec<&[f64]> {
    layouts.iter().map(Vec::as_slice).collect()
}

proptest! {
    /// The replicates are the documented draws materialised, bit for bit.
    #[test]
    fn replicates_equal_the_materialised_draws(
        layouts in layouts_strategy(6, 7),
        within in statistic(),
        across in statistic(),
        stages in stages(),
        seed: u64,
    ) {
        let bootstrap = HierarchicalBootstrap { resamples: 40, seed, stages, ..Default::default() };
        let got = bootstrap.replicates(&views(&layouts), within, across).unwrap();
        let want = replicates_by_materialising(&bootstrap, &layouts, within, across);
        prop_assert_eq!(
            got.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            want.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
    }

    /// Reordering the layouts, or the seeds within a layout, changes no bit.
    #[test]
    fn order_changes_no_bit(
        layouts in layouts_strategy(6, 6),
        within in statistic(),
        across in statistic(),
        rotate in 0..6_usize,
    ) {
        let bootstrap = HierarchicalBootstrap { resamples: 200, ..Default::default() };
        let original = bootstrap.interval(&views(&layouts), within, across).unwrap();
        let mut shuffled: Vec<Vec<f64>> = layouts.iter().rev().cloned().collect();
        for seeds in &mut shuffled {
            let turn = rotate % seeds.len();
            seeds.rotate_left(turn);
        }
        let again = bootstrap.interval(&views(&shuffled), within, across).unwrap();
        prop_assert_eq!(original.estimate.to_bits(), again.estimate.to_bits());
        prop_assert_eq!(original.low.to_bits(), again.low.to_bits());
        prop_assert_eq!(original.high.to_bits(), again.high.to_bits());
    }

    /// One seed per layout: exactly the plain bootstrap of the layout values with `across`.
    /// Layouts only: exactly the plain bootstrap of the layouts' `within` values.
    #[test]
    fn one_level_cases_are_the_plain_bootstrap(
        layouts in layouts_strategy(8, 5),
        within in statistic(),
        across in statistic(),
        seed: u64,
    ) {
        let plain = Bootstrap::new(300, 0.9, seed).unwrap();
        let two = HierarchicalBootstrap::new(300, 0.9, seed, Stages::LayoutsThenSeeds).unwrap();
        let singles: Vec<Vec<f64>> = layouts.iter().map(|l| vec![l[0]]).collect();
        let values: Vec<f64> = singles.iter().map(|l| l[0]).collect();
        prop_assert_eq!(
            two.interval(&views(&singles), within, across).unwrap(),
            plain.interval(&values, across).unwrap()
        );

        let only = HierarchicalBootstrap { stages: Stages::LayoutsOnly, ..two };
        let within_values: Vec<f64> = layouts.iter().map(|l| within.of(l).unwrap()).collect();
        prop_assert_eq!(
            only.interval(&views(&layouts), within, across).unwrap(),
            plain.interval(&within_values, across).unwrap()
        );
    }

    /// One layout: exactly the plain bootstrap of its seeds with `within`.
    #[test]
    fn one_layout_is_the_plain_bootstrap_of_its_seeds(
        seeds in prop::collection::vec(-1e3..1e3_f64, 1..30),
        within in statistic(),
        across in statistic(),
        seed: u64,
    ) {
        let plain = Bootstrap::new(300, 0.95, seed).unwrap();
        let two = HierarchicalBootstrap::new(300, 0.95, seed, Stages::LayoutsThenSeeds).unwrap();
        prop_assert_eq!(
            two.interval(&[seeds.as_slice()], within, across).unwrap(),
            plain.interval(&seeds, within).unwrap()
        );
    }

    /// The paired interval is the interval of the differences, layout by layout and seed by
    /// seed.
    #[test]
    fn paired_is_the_interval_of_the_differences(
        x in layouts_strategy(5, 6),
        shift in -5.0..5.0_f64,
        within in statistic(),
        across in statistic(),
    ) {
        let y: Vec<Vec<f64>> = x
            .iter()
            .enumerate()
            .map(|(i, l)| l.iter().enumerate().map(|(j, v)| v * 0.5 + shift + (i + j) as f64).collect())
            .collect();
        let differences: Vec<Vec<f64>> = x
            .iter()
            .zip(&y)
            .map(|(a, b)| a.iter().zip(b).map(|(p, q)| p - q).collect())
            .collect();
        let bootstrap = HierarchicalBootstrap { resamples: 200, ..Default::default() };
        prop_assert_eq!(
            bootstrap.paired_difference(&views(&x), &views(&y), within, across).unwrap(),
            bootstrap.interval(&views(&differences), within, across).unwrap()
        );
    }
}

/// Means at both levels: the plug-in quantities of the exact bootstrap variance.
fn exact_variance(layouts: &[Vec<f64>], stages: Stages) -> f64 {
    let a = layouts.len() as f64;
    let means: Vec<f64> = layouts
        .iter()
        .map(|l| l.iter().sum::<f64>() / l.len() as f64)
        .collect();
    let grand = means.iter().sum::<f64>() / a;
    let between = means.iter().map(|m| (m - grand).powi(2)).sum::<f64>() / a;
    let within = layouts
        .iter()
        .zip(&means)
        .map(|(l, m)| {
            let n = l.len() as f64;
            l.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n / n
        })
        .sum::<f64>()
        / a;
    match stages {
        Stages::LayoutsThenSeeds => (between + within) / a,
        Stages::LayoutsOnly => between / a,
    }
}

fn mean_and_variance(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    (mean, variance)
}

/// Reference values: for means at both levels the bootstrap distribution's mean is the
/// estimate and its variance is `(1/a)(s_b² + (1/a) Σ v_i/n_i)` (two stages) or `s_b²/a`
/// (layouts only), the formulas of the module docs. 100 000 replicates put the Monte-Carlo
/// variance within about 1 % of it.
#[test]
fn the_bootstrap_variance_is_the_documented_formula() {
    // Six layouts, seeds 3 to 8, layout effects and seed noise of comparable size.
    let layouts: Vec<Vec<f64>> = vec![
        vec![58.0, 60.0, 58.0, 2000.0, 64.0],
        vec![73.0, 75.0, 81.0],
        vec![120.0, 90.0, 100.0, 140.0, 95.0, 101.0, 99.0, 180.0],
        vec![300.0, 310.0, 290.0, 500.0],
        vec![61.0, 59.0, 60.0, 62.0, 58.0, 60.0],
        vec![1000.0, 800.0, 1200.0],
    ];
    for stages in [Stages::LayoutsThenSeeds, Stages::LayoutsOnly] {
        let bootstrap = HierarchicalBootstrap::new(100_000, 0.95, 11, stages).unwrap();
        let replicates = bootstrap
            .replicates(&views(&layouts), Statistic::Mean, Statistic::Mean)
            .unwrap();
        let (mean, variance) = mean_and_variance(&replicates);
        let estimate =
            HierarchicalBootstrap::estimate(&views(&layouts), Statistic::Mean, Statistic::Mean)
                .unwrap();
        let exact = exact_variance(&layouts, stages);
        assert!(
            (mean - estimate).abs() < 4.0 * (exact / 1e5).sqrt(),
            "{stages:?}: replicate mean {mean} against the estimate {estimate}"
        );
        assert!(
            (variance / exact - 1.0).abs() < 0.03,
            "{stages:?}: Monte-Carlo variance {variance} against the exact {exact}"
        );
    }
    // The second stage adds exactly the within-layout term: the two differ by it.
    let gap = exact_variance(&layouts, Stages::LayoutsThenSeeds)
        - exact_variance(&layouts, Stages::LayoutsOnly);
    assert!(gap > 0.0);
}

/// Reference values by enumeration: layouts `[0, 1]` and `[2, 5, 9]`, means at both levels.
/// Every replicate is one of 4 layout draws times the seed draws of each drawn layout, all
/// equally likely; the Monte-Carlo CDF must match the exact one at every atom boundary.
#[test]
fn a_tiny_sample_matches_its_exact_bootstrap_distribution() {
    let layouts = [vec![0.0, 1.0], vec![2.0, 5.0, 9.0]];
    // Every (ordered) resample of a layout's seeds, as its mean with its probability.
    let resample_means = |seeds: &[f64]| -> Vec<(f64, f64)> {
        let n = seeds.len();
        let total = n.pow(n as u32);
        (0..total)
            .map(|mut code| {
                let mut sum = 0.0;
                for _ in 0..n {
                    sum += seeds[code % n];
                    code /= n;
                }
                (sum / n as f64, 1.0 / total as f64)
            })
            .collect()
    };
    let mut exact: Vec<(f64, f64)> = Vec::new();
    for first in 0..2 {
        for second in 0..2 {
            for (m1, p1) in resample_means(&layouts[first]) {
                for (m2, p2) in resample_means(&layouts[second]) {
                    exact.push(((m1 + m2) / 2.0, 0.25 * p1 * p2));
                }
            }
        }
    }
    let resamples = 200_000;
    let bootstrap =
        HierarchicalBootstrap::new(resamples, 0.95, 5, Stages::LayoutsThenSeeds).unwrap();
    let replicates = bootstrap
        .replicates(&views(&layouts), Statistic::Mean, Statistic::Mean)
        .unwrap();
    for threshold in [0.25, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.5, 6.0, 8.0] {
        let want: f64 = exact
            .iter()
            .filter(|(v, _)| *v <= threshold + 1e-12)
            .map(|(_, p)| p)
            .sum();
        let got = replicates
            .iter()
            .filter(|&&v| v <= threshold + 1e-12)
            .count() as f64
            / f64::from(resamples);
        let se = (want * (1.0 - want) / f64::from(resamples)).sqrt();
        assert!(
            (got - want).abs() <= 4.0 * se + 1e-9,
            "P(θ* ≤ {threshold}): Monte Carlo {got}, exact {want}"
        );
    }
}

/// Value stability: the interval of a fixed family-like sample (five layouts, a few seeds
/// each) with the default settings, to the last printed digit.
#[test]
fn a_fixed_sample_gives_pinned_intervals() {
    let layouts: Vec<Vec<f64>> = vec![
        vec![-2.0, 0.0, 0.0, 1.0, -4.0],
        vec![10.0, 12.0, 9.0],
        vec![0.0, 0.0, 0.0, 0.0],
        vec![-30.0, 5.0, -12.0, -8.0, -1.0, 2.0],
        vec![3.0, 4.0],
    ];
    let mut lines = Vec::new();
    for stages in [Stages::LayoutsThenSeeds, Stages::LayoutsOnly] {
        for (within, across) in [
            (Statistic::Mean, Statistic::Mean),
            (Statistic::Mean, Statistic::Iqm),
            (Statistic::Median, Statistic::Median),
        ] {
            let bootstrap = HierarchicalBootstrap {
                stages,
                ..Default::default()
            };
            let interval = bootstrap
                .interval(&views(&layouts), within, across)
                .unwrap();
            lines.push(format!(
                "{stages:?} {} of {}: {:.4} [{:.4}, {:.4}]",
                across.name(),
                within.name(),
                interval.estimate,
                interval.low,
                interval.high
            ));
        }
    }
    insta::assert_snapshot!(lines.join("\n"));
}

#[test]
fn bad_input_is_a_typed_error() {
    let bootstrap = HierarchicalBootstrap::default();
    let (mean, iqm) = (Statistic::Mean, Statistic::Iqm);
    assert_eq!(
        bootstrap.interval(&[], mean, mean),
        Err(StatsError::Empty { what: "layouts" })
    );
    assert_eq!(
        bootstrap.interval(&[&[1.0], &[]], mean, mean),
        Err(StatsError::EmptyGroup { group: 1 })
    );
    assert_eq!(
        bootstrap
            .interval(&[&[1.0], &[2.0, f64::NAN]], mean, iqm)
            .unwrap_err()
            .to_string(),
        "group 1, value 1 = NaN is not finite: remove or replace it"
    );
    let zero = HierarchicalBootstrap {
        resamples: 0,
        ..bootstrap
    };
    assert!(matches!(
        zero.interval(&[&[1.0]], mean, mean),
        Err(StatsError::InvalidParameter {
            name: "resamples",
            ..
        })
    ));
    assert!(matches!(
        HierarchicalBootstrap::new(10, 1.0, 0, Stages::LayoutsOnly),
        Err(StatsError::InvalidParameter {
            name: "confidence",
            ..
        })
    ));
    let unpaired = bootstrap
        .paired_difference(&[&[1.0, 2.0]], &[&[1.0, 2.0], &[3.0]], mean, mean)
        .unwrap_err();
    assert_eq!(
        unpaired.to_string(),
        "y = 2 layouts against x's 1 is invalid: expected as many layouts as x, in the same order \
         (pairs by layout and seed)"
    );
    let seeds = bootstrap
        .paired_difference(
            &[&[1.0, 2.0], &[3.0]],
            &[&[1.0, 2.0], &[3.0, 4.0]],
            mean,
            mean,
        )
        .unwrap_err();
    assert_eq!(
        seeds.to_string(),
        "y = layout 1 with 2 values against x's 1 is invalid: expected one value per seed of \
         x's layout, in the same seed order"
    );
    assert_eq!(
        bootstrap.paired_difference(&[&[1.0, f64::INFINITY]], &[&[1.0, 2.0]], mean, mean),
        Err(StatsError::NonFiniteInGroup {
            group: 0,
            index: 1,
            value: f64::INFINITY
        })
    );
    assert_eq!(
        bootstrap.paired_difference(&[&[f64::MAX]], &[&[-f64::MAX]], mean, mean),
        Err(StatsError::Overflow {
            what: "paired difference"
        })
    );
}
