//! Laws of the tree for any thresholds: centres are means, counts are member counts,
//! re-inserting a sample adds no cluster, clusters never outnumber samples.
#![allow(
    clippy::unwrap_used,
    reason = "helpers outside #[test] fns unwrap too: tests may"
)]

use crate::common;

use common::{OwnedSample, build, close, config, mixed_samples, samples};
use ea_tree::{
    EaTree, EaTreeConfig, EaTreeError, Sample, Similarity, StateCentre, Token, WeightedJaccard,
    set_jaccard, state_tokens,
};
use proptest::prelude::*;

proptest! {
    #[test]
    fn centre_is_the_mean_of_members_and_count_their_number(
        config in config(),
        data in mixed_samples(3, 3, 3, 1..80),
    ) {
        let mut tree = EaTree::new(config).unwrap();
        let mut members: Vec<Vec<&OwnedSample>> = Vec::new();
        for s in &data {
            let insertion = tree.insert(s.as_sample()).unwrap();
            if insertion.created {
                prop_assert_eq!(insertion.cluster.index(), members.len());
                members.push(Vec::new());
            }
            members[insertion.cluster.index()].push(s);
        }
        prop_assert_eq!(tree.len(), members.len());
        for (view, members) in tree.clusters().zip(&members) {
            let n = members.len() as u64;
            prop_assert_eq!(view.count(), n);
            let n_f = n as f64;
            let q1 = members.iter().map(|m| m.q1).sum::<f64>() / n_f;
            let q2 = members.iter().map(|m| m.q2).sum::<f64>() / n_f;
            prop_assert!(close(view.q1(), q1) && close(view.q2(), q2));
            // Token and action weights are the fraction of members carrying them.
            let centre = view.state_centre();
            let mut total = 0;
            for (token, count) in centre.tokens() {
                let carrying = members
                    .iter()
                    .filter(|m| state_tokens(&m.state).any(|t| t == token))
                    .count() as u64;
                prop_assert_eq!(count, carrying);
                total += count;
            }
            let tokens_of_members: usize = members.iter().map(|m| m.state.len()).sum();
            prop_assert_eq!(total, tokens_of_members as u64);
            prop_assert_eq!(centre.total_count(), total);
            let actions = view.action_centre();
            for (action, count) in actions.actions() {
                prop_assert_eq!(count, members.iter().filter(|m| m.action == action).count() as u64);
            }
            prop_assert_eq!(actions.actions().map(|(_, c)| c).sum::<u64>(), n);
        }
    }

    #[test]
    fn reinserting_the_last_sample_never_adds_a_cluster(
        config in config(),
        data in mixed_samples(3, 3, 3, 1..60),
    ) {
        let mut tree = EaTree::new(config).unwrap();
        for s in &data {
            let first = tree.insert(s.as_sample()).unwrap();
            let again = tree.insert(s.as_sample()).unwrap();
            prop_assert!(!again.created);
            prop_assert_eq!(again.cluster, first.cluster);
        }
    }

    #[test]
    fn at_exact_thresholds_reinserting_any_sample_never_adds_a_cluster(
        data in samples(2, 4, 3, 1..60),
    ) {
        let mut tree = build(EaTreeConfig::EXACT, &data);
        let clusters = tree.len();
        for s in &data {
            prop_assert!(!tree.insert(s.as_sample()).unwrap().created);
        }
        prop_assert_eq!(tree.len(), clusters);
    }

    #[test]
    fn clusters_never_outnumber_samples(config in config(), data in mixed_samples(4, 3, 4, 0..100)) {
        let tree = build(config, &data);
        let stats = tree.stats();
        prop_assert!(stats.clusters as u64 <= stats.samples_seen);
        prop_assert_eq!(stats.samples_seen, data.len() as u64);
        prop_assert!(stats.longest_chain <= stats.depth && stats.depth <= stats.clusters);
        prop_assert!(data.is_empty() || stats.clusters >= 1);
    }

    #[test]
    fn weighted_jaccard_of_a_one_member_centre_is_set_jaccard(
        a in prop::collection::vec(0..3_u32, 1..5),
        b in prop::collection::vec(0..3_u32, 1..5),
        action_a in 0..3_usize,
        action_b in 0..3_usize,
    ) {
        let tree = build(EaTreeConfig::EXACT, &[OwnedSample { state: b.clone(), action: action_b, q1: 0.0, q2: 0.0 }]);
        let root = tree.clusters().next().unwrap();
        let tokens_a: Vec<Token> = state_tokens(&a).collect();
        let tokens_b: Vec<Token> = state_tokens(&b).collect();
        let weighted = WeightedJaccard.state_similarity(&a, &root.state_centre());
        prop_assert_eq!(weighted, set_jaccard(&tokens_a, &tokens_b));
        let action = WeightedJaccard.action_similarity(action_a, &root.action_centre());
        prop_assert_eq!(action, if action_a == action_b { 1.0 } else { 0.0 });
    }

    /// The bound the shared-token index skips clusters by is never below the similarity, for
    /// any centre (mixed state lengths included) and query, given how many of the query's
    /// tokens the centre carries.
    #[test]
    fn the_state_similarity_bound_is_never_below_the_similarity(
        config in config(),
        data in mixed_samples(4, 3, 3, 1..60),
        query in prop::collection::vec(0..3_u32, 0..5),
    ) {
        let tree = build(config, &data);
        for view in tree.clusters() {
            let centre = view.state_centre();
            let shared = centre.overlap(&query).tokens;
            let bound = WeightedJaccard.state_similarity_bound(query.len(), shared, &centre);
            let similarity = WeightedJaccard.state_similarity(&query, &centre);
            prop_assert!(bound >= similarity, "{} < {}", bound, similarity);
        }
    }

    #[test]
    fn similarities_lie_in_the_unit_interval_and_one_means_identical(
        config in config(),
        data in mixed_samples(3, 3, 3, 1..40),
        query in prop::collection::vec(0..3_u32, 0..4),
        action in 0..4_usize,
    ) {
        let tree = build(config, &data);
        for view in tree.clusters() {
            let centre: StateCentre<'_> = view.state_centre();
            let s = WeightedJaccard.state_similarity(&query, &centre);
            let a = WeightedJaccard.action_similarity(action, &view.action_centre());
            prop_assert!((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&a));
            let pure = centre.tokens().count() == query.len()
                && centre.tokens().zip(state_tokens(&query)).all(|((t, c), q)| t == q && c == centre.members());
            prop_assert_eq!(s >= 1.0, pure);
        }
    }
}

#[test]
fn thresholds_outside_the_unit_interval_are_rejected() {
    for (s, a, name) in [
        (1.5, 0.5, "state_threshold"),
        (-0.1, 0.5, "state_threshold"),
        (f64::NAN, 0.5, "state_threshold"),
        (0.5, 2.0, "action_threshold"),
        (0.5, f64::INFINITY, "action_threshold"),
    ] {
        match EaTreeConfig::new(s, a) {
            Err(EaTreeError::InvalidThreshold { name: got, .. }) => assert_eq!(got, name),
            other => panic!("({s}, {a}) gave {other:?}"),
        }
    }
    let bad = EaTreeConfig {
        state_threshold: 0.5,
        action_threshold: -1.0,
    };
    assert!(matches!(
        EaTree::new(bad),
        Err(EaTreeError::InvalidThreshold {
            name: "action_threshold",
            ..
        })
    ));
    assert_eq!(EaTreeConfig::default(), EaTreeConfig::EXACT);
    let parsed: EaTreeConfig =
        serde_json::from_str(r#"{"state_threshold":0.25,"action_threshold":1.0}"#).unwrap();
    assert_eq!(parsed, EaTreeConfig::new(0.25, 1.0).unwrap());
    assert!(serde_json::from_str::<EaTreeConfig>(r#"{"state_threshold":0.25}"#).is_err());
}

#[test]
fn bad_samples_are_rejected_and_leave_the_tree_unchanged() {
    let mut tree = EaTree::new(EaTreeConfig::EXACT).unwrap();
    tree.insert(Sample {
        state: &[1],
        action: 0,
        q1: 1.0,
        q2: 1.0,
    })
    .unwrap();
    let before = tree.clone();
    let cases = [
        (
            Sample {
                state: &[],
                action: 0,
                q1: 0.0,
                q2: 0.0,
            },
            EaTreeError::EmptyState,
        ),
        (
            Sample {
                state: &[1],
                action: 0,
                q1: f64::NAN,
                q2: 0.0,
            },
            EaTreeError::NonFiniteQ {
                name: "q1",
                value: f64::NAN,
            },
        ),
        (
            Sample {
                state: &[1],
                action: 0,
                q1: 0.0,
                q2: f64::NEG_INFINITY,
            },
            EaTreeError::NonFiniteQ {
                name: "q2",
                value: f64::NEG_INFINITY,
            },
        ),
    ];
    for (sample, expected) in cases {
        let got = tree.insert(sample).unwrap_err();
        // NaN != NaN: compare the rendered errors.
        assert_eq!(got.to_string(), expected.to_string());
        assert_eq!(
            tree.insert_literal(sample).unwrap_err().to_string(),
            expected.to_string()
        );
    }
    assert_eq!(tree, before);
    assert_eq!(tree.samples_seen(), 1);
}

#[test]
fn extreme_q_values_keep_means_finite() {
    let mut tree = EaTree::new(EaTreeConfig::EXACT).unwrap();
    for q in [f64::MAX, -f64::MAX, f64::MAX, f64::MAX] {
        tree.insert(Sample {
            state: &[0],
            action: 0,
            q1: q,
            q2: -q,
        })
        .unwrap();
    }
    let answer = tree.lookup(&[0], 0).unwrap();
    assert!(answer.q1.is_finite() && answer.q2.is_finite() && answer.q_mean().is_finite());
    assert!(answer.q1 > 0.0 && answer.q2 < 0.0);
}
