//! The indexed walk ends exactly where the literal walk of Fig. 4 ends: on every insert
//! (so trees built either way are identical) and on every lookup, for random trees and
//! thresholds.
#![allow(
    clippy::unwrap_used,
    reason = "helpers outside #[test] fns unwrap too: tests may"
)]

use crate::common;

use common::{OwnedSample, all_states, build_with, config, mixed_samples, samples};
use ea_tree::{
    ActionCentre, EaTree, EaTreeConfig, IndexKind, Similarity, StateCentre, WeightedJaccard,
};
use proptest::prelude::*;

/// Builds the same samples through `insert` and `insert_literal`, checks every step agrees,
/// then checks `lookup` against `lookup_literal` on `queries` × actions `0..=actions`.
fn check_equivalent<S: Similarity + Clone>(
    config: EaTreeConfig,
    similarity: S,
    data: &[OwnedSample],
    queries: &[Vec<u32>],
    actions: usize,
) -> Result<(), TestCaseError> {
    let mut indexed = EaTree::with_similarity(config, similarity.clone()).unwrap();
    let mut literal = EaTree::with_similarity(config, similarity).unwrap();
    for s in data {
        let a = indexed.insert(s.as_sample()).unwrap();
        let b = literal.insert_literal(s.as_sample()).unwrap();
        prop_assert_eq!(a, b, "insert of {:?}", s);
    }
    prop_assert!(indexed == literal);
    for state in queries {
        for action in 0..=actions {
            prop_assert_eq!(
                indexed.lookup(state, action),
                indexed.lookup_literal(state, action),
                "lookup {:?} {}",
                state,
                action
            );
        }
    }
    // The precomputed table agrees too (its walks share the state tests between actions).
    let table = indexed.answer_table(queries.iter().map(Vec::as_slice), actions + 1);
    for (id, state) in queries.iter().enumerate() {
        for action in 0..=actions {
            prop_assert_eq!(table.get(id, action), indexed.lookup_literal(state, action));
        }
    }
    Ok(())
}

/// Queries: every state of the space (bins one past the stored ones), the empty state, and
/// states one feature shorter and longer.
fn queries(features: usize, bins: u32) -> Vec<Vec<u32>> {
    let mut queries = all_states(features, bins + 1);
    queries.push(Vec::new());
    queries.extend(all_states(features + 1, 2));
    if features > 1 {
        queries.extend(all_states(features - 1, bins));
    }
    queries
}

proptest! {
    #[test]
    fn indexed_walk_equals_literal_walk(
        config in config(),
        (features, data) in (1..=4_usize).prop_flat_map(|f| (Just(f), samples(f, 3, 3, 0..150))),
    ) {
        check_equivalent(config, WeightedJaccard, &data, &queries(features, 3), 3)?;
    }

    #[test]
    fn indexed_walk_equals_literal_walk_on_mixed_state_lengths(
        config in config(),
        data in mixed_samples(4, 3, 3, 0..150),
    ) {
        let mut queries = queries(3, 3);
        queries.extend(all_states(4, 2));
        check_equivalent(config, WeightedJaccard, &data, &queries, 3)?;
    }

    #[test]
    fn indexed_walk_equals_literal_walk_on_wide_states(
        config in config(),
        data in samples(18, 2, 2, 0..60),
        extra in prop::collection::vec(prop::collection::vec(0..2_u32, 18), 0..40),
    ) {
        // More than 16 features: the shared-token merge falls back to scanning the chain.
        let mut queries: Vec<Vec<u32>> = data.iter().map(|s| s.state.clone()).collect();
        queries.extend(extra);
        check_equivalent(config, WeightedJaccard, &data, &queries, 2)?;
    }

    #[test]
    fn a_similarity_without_guarantees_takes_the_literal_walk_and_agrees(
        config in config(),
        data in samples(2, 3, 3, 0..80),
    ) {
        let plain = build_with(config, PlainJaccard, &data);
        let indexed = build_with(config, WeightedJaccard, &data);
        prop_assert_eq!(plain.index_kind(), IndexKind::Literal);
        for (a, b) in plain.clusters().zip(indexed.clusters()) {
            prop_assert_eq!(a.answer(), b.answer());
            prop_assert_eq!((a.state_differs(), a.action_differs()), (b.state_differs(), b.action_differs()));
        }
        prop_assert_eq!(plain.len(), indexed.len());
        check_equivalent(config, PlainJaccard, &data, &queries(2, 3), 3)?;
    }
}

/// Weighted Jaccard under another name and without declared properties.
#[derive(Debug, Clone, Copy, Default)]
struct PlainJaccard;

impl Similarity for PlainJaccard {
    fn name(&self) -> &str {
        "plain-jaccard"
    }

    fn state_similarity(&self, state: &[u32], centre: &StateCentre<'_>) -> f64 {
        WeightedJaccard.state_similarity(state, centre)
    }

    fn action_similarity(&self, action: usize, centre: &ActionCentre<'_>) -> f64 {
        WeightedJaccard.action_similarity(action, centre)
    }
}

#[test]
fn every_index_kind_is_reached() {
    let kinds = [
        (EaTreeConfig::EXACT, IndexKind::ExactPair),
        (EaTreeConfig::new(1.0, 0.0).unwrap(), IndexKind::ExactState),
        (
            EaTreeConfig::new(0.5, 1.0).unwrap(),
            IndexKind::SharedTokens,
        ),
        (EaTreeConfig::new(0.0, 1.0).unwrap(), IndexKind::Literal),
    ];
    for (config, kind) in kinds {
        assert_eq!(EaTree::new(config).unwrap().index_kind(), kind);
    }
}

#[test]
fn the_index_skips_the_degenerate_chain() {
    // 30 × 30 states × 4 actions at τ = 1: the root chain holds all 900 states.
    let mut tree = EaTree::new(EaTreeConfig::EXACT).unwrap();
    for x in 0..30 {
        for y in 0..30 {
            for action in 0..4 {
                tree.insert(ea_tree::Sample {
                    state: &[x, y],
                    action,
                    q1: f64::from(x),
                    q2: f64::from(y),
                })
                .unwrap();
            }
        }
    }
    let stats = tree.stats();
    assert_eq!(
        (stats.clusters, stats.longest_chain, stats.depth),
        (3600, 900, 903)
    );
    assert_eq!(tree.literal_walk_length(&[29, 29], 3), 903);
    let answer = tree.lookup(&[29, 29], 3).unwrap();
    assert_eq!((answer.q1, answer.q2, answer.count), (29.0, 29.0, 1));
    assert_eq!(tree.lookup_literal(&[29, 29], 3), Some(answer));
}

/// One cluster of an arbitrary tree: its members and where it hangs.
#[derive(Debug, Clone)]
struct ArbitraryCluster {
    members: Vec<(Vec<u32>, usize)>,
    q: (f64, f64),
    /// Which earlier cluster (modulo the clusters with a free child) and which child.
    parent: (usize, bool),
}

/// The JSON of a structurally valid tree of any shape, whose centres are means of
/// arbitrary members: the kind of tree a loaded file may hold, not only what inserts build.
fn arbitrary_tree_json(config: EaTreeConfig, clusters: &[ArbitraryCluster]) -> String {
    let mut links: Vec<[Option<usize>; 2]> = vec![[None, None]; clusters.len()];
    for (i, cluster) in clusters.iter().enumerate().skip(1) {
        let free: Vec<(usize, usize)> = (0..i)
            .flat_map(|p| (0..2).map(move |side| (p, side)))
            .filter(|&(p, side)| links[p][side].is_none())
            .collect();
        let preferred = usize::from(cluster.parent.1);
        let (p, _) = free[cluster.parent.0 % free.len()];
        let side = if links[p][preferred].is_none() {
            preferred
        } else {
            1 - preferred
        };
        links[p][side] = Some(i);
    }
    let records: Vec<String> = clusters
        .iter()
        .zip(&links)
        .map(|(cluster, link)| {
            let mut tokens = std::collections::BTreeMap::new();
            let mut actions = std::collections::BTreeMap::new();
            for (state, action) in &cluster.members {
                for (feature, bin) in state.iter().enumerate() {
                    *tokens.entry((feature, *bin)).or_insert(0_u64) += 1;
                }
                *actions.entry(*action).or_insert(0_u64) += 1;
            }
            let state: Vec<[u64; 3]> = tokens
                .iter()
                .map(|(&(f, b), &c)| [f as u64, u64::from(b), c])
                .collect();
            let actions: Vec<[u64; 2]> = actions.iter().map(|(&a, &c)| [a as u64, c]).collect();
            serde_json::json!({
                "count": cluster.members.len(),
                "state": state,
                "actions": actions,
                "q1": cluster.q.0,
                "q2": cluster.q.1,
                "state_differs": link[0],
                "action_differs": link[1],
            })
            .to_string()
        })
        .collect();
    let samples: usize = clusters.iter().map(|c| c.members.len()).sum();
    format!(
        r#"{{"format":"ea-tree","version":1,"similarity":"weighted-jaccard","config":{},"samples_seen":{},"clusters":[{}]}}"#,
        serde_json::to_string(&config).unwrap(),
        samples,
        records.join(",")
    )
}

fn arbitrary_cluster() -> impl Strategy<Value = ArbitraryCluster> {
    (
        // Mostly pure clusters (one distinct member), so that exact thresholds match often.
        prop_oneof![
            2 => (prop::collection::vec(0..3_u32, 1..=3), 0..3_usize, 1..3_usize)
                .prop_map(|(s, a, n)| vec![(s, a); n]),
            1 => prop::collection::vec((prop::collection::vec(0..3_u32, 1..=3), 0..3_usize), 1..4),
        ],
        (common::q_value(), common::q_value()),
        (any::<usize>(), any::<bool>()),
    )
        .prop_map(|(members, q, parent)| ArbitraryCluster { members, q, parent })
}

proptest! {
    #[test]
    fn indexed_walk_equals_literal_walk_on_arbitrary_loaded_trees(
        config in config(),
        clusters in prop::collection::vec(arbitrary_cluster(), 1..40),
        more in samples(2, 3, 3, 0..20),
    ) {
        let json = arbitrary_tree_json(config, &clusters);
        let mut tree: EaTree = EaTree::from_json(&json).unwrap();
        let mut literal = tree.clone();
        let queries = queries(3, 3);
        for state in &queries {
            for action in 0..=3 {
                prop_assert_eq!(tree.lookup(state, action), tree.lookup_literal(state, action));
            }
        }
        // Inserting into a loaded tree keeps the two walks in step.
        for s in &more {
            prop_assert_eq!(tree.insert(s.as_sample()).unwrap(), literal.insert_literal(s.as_sample()).unwrap());
        }
        for state in &queries {
            for action in 0..=3 {
                prop_assert_eq!(tree.lookup(state, action), tree.lookup_literal(state, action));
            }
        }
    }
}
