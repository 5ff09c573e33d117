//! At τₛ = τₐ = 1 the tree answers exactly like a table.
//!
//! Identical `(s, a)` samples merge into one cluster, so the table to compare with holds, per
//! `(s, a)`, the *mean* of the inserted Q1 and Q2 and how many samples were inserted; a pair
//! never inserted has no entry (the tree says "no prior experience").
#![allow(
    clippy::unwrap_used,
    reason = "helpers outside #[test] fns unwrap too: tests may"
)]

use crate::common;

use std::collections::HashMap;

use common::{all_states, build, close, samples};
use ea_tree::{EaTree, EaTreeConfig, EaTreeError, IndexKind, TableEntry};
use proptest::prelude::*;

/// Per (s, a): sum of Q1, sum of Q2, number of samples.
type MeanTable = HashMap<(Vec<u32>, usize), (f64, f64, u64)>;

fn mean_table(samples: &[common::OwnedSample]) -> MeanTable {
    let mut table = MeanTable::new();
    for s in samples {
        let entry = table
            .entry((s.state.clone(), s.action))
            .or_insert((0.0, 0.0, 0));
        entry.0 += s.q1;
        entry.1 += s.q2;
        entry.2 += 1;
    }
    table
}

proptest! {
    #[test]
    fn exact_tree_answers_like_a_table_of_means(
        (features, data) in (1..=3_usize).prop_flat_map(|f| (Just(f), samples(f, 4, 4, 0..120))),
        seed in any::<u64>(),
    ) {
        // Any insertion order gives the same answers.
        let mut shuffled = data.clone();
        let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed);
        rand::seq::SliceRandom::shuffle(shuffled.as_mut_slice(), &mut rng);
        let table = mean_table(&data);
        for order in [&data, &shuffled] {
            let tree = build(EaTreeConfig::EXACT, order);
            prop_assert_eq!(tree.index_kind(), IndexKind::ExactPair);
            prop_assert_eq!(tree.len(), table.len());
            prop_assert_eq!(tree.samples_seen(), data.len() as u64);
            for state in all_states(features, 5) {
                for action in 0..5 {
                    let answer = tree.lookup(&state, action);
                    prop_assert_eq!(answer, tree.lookup_literal(&state, action));
                    match (answer, table.get(&(state.clone(), action))) {
                        (None, None) => {}
                        (Some(answer), Some(&(q1, q2, n))) => {
                            prop_assert_eq!(answer.count, n);
                            let n = n as f64;
                            prop_assert!(close(answer.q1, q1 / n), "q1 {} vs {}", answer.q1, q1 / n);
                            prop_assert!(close(answer.q2, q2 / n), "q2 {} vs {}", answer.q2, q2 / n);
                        }
                        (answer, entry) => {
                            prop_assert!(false, "{:?} {}: tree {:?}, table {:?}", state, action, answer, entry);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn bulk_build_ignores_entry_order(
        visited in prop::collection::btree_map((0..30_usize, 0..4_usize), (common::q_value(), common::q_value()), 0..80),
        seed in any::<u64>(),
    ) {
        let features: Vec<[u32; 2]> = (0..30).map(|s| [s as u32 % 6, s as u32 / 6]).collect();
        let entries: Vec<TableEntry<'_>> = visited
            .iter()
            .map(|(&(state_id, action), &(q1, q2))| TableEntry {
                state_id,
                state: &features[state_id],
                action,
                q1,
                q2,
            })
            .collect();
        let mut shuffled = entries.clone();
        let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(seed);
        rand::seq::SliceRandom::shuffle(shuffled.as_mut_slice(), &mut rng);
        let sorted = EaTree::from_table(EaTreeConfig::EXACT, entries.clone()).unwrap();
        let from_shuffled = EaTree::from_table(EaTreeConfig::EXACT, shuffled).unwrap();
        // Bit-identical trees, and a table lookup: one cluster per visited pair.
        prop_assert_eq!(&sorted, &from_shuffled);
        prop_assert_eq!(sorted.len(), visited.len());
        let answers = sorted.answer_table(features.iter().map(<[u32; 2]>::as_slice), 4);
        for (state_id, state) in features.iter().enumerate() {
            for action in 0..4 {
                let answer = answers.get(state_id, action);
                prop_assert_eq!(answer, sorted.lookup(state, action));
                prop_assert_eq!(
                    answer.map(|a| (a.q1, a.q2, a.count)),
                    visited.get(&(state_id, action)).map(|&(q1, q2)| (q1, q2, 1))
                );
            }
        }
    }
}

#[test]
fn bulk_build_rejects_duplicates_and_conflicting_features() {
    let entry = |state_id, state: &'static [u32], action| TableEntry {
        state_id,
        state,
        action,
        q1: 0.0,
        q2: 0.0,
    };
    let duplicate = EaTree::from_table(
        EaTreeConfig::EXACT,
        [
            entry(2, &[1, 1], 0),
            entry(1, &[0, 1], 3),
            entry(2, &[1, 1], 0),
        ],
    );
    assert_eq!(
        duplicate,
        Err(EaTreeError::DuplicateTableEntry {
            state_id: 2,
            action: 0
        })
    );
    let conflicting = EaTree::from_table(
        EaTreeConfig::EXACT,
        [entry(2, &[1, 1], 0), entry(2, &[1, 2], 1)],
    );
    assert_eq!(
        conflicting,
        Err(EaTreeError::InconsistentStateFeatures { state_id: 2 })
    );
    let mut tree = EaTree::new(EaTreeConfig::EXACT).unwrap();
    let bad = [entry(0, &[1], 0), entry(1, &[], 0)];
    assert_eq!(tree.insert_table(bad), Err(EaTreeError::EmptyState));
    assert!(tree.is_empty(), "a rejected table inserts nothing");
}

#[test]
fn answer_table_out_of_range_is_none() {
    let tree = EaTree::from_table(
        EaTreeConfig::EXACT,
        [TableEntry {
            state_id: 0,
            state: &[0],
            action: 1,
            q1: 2.0,
            q2: 4.0,
        }],
    )
    .unwrap();
    let answers = tree.answer_table([[0_u32].as_slice(), &[1]], 2);
    assert_eq!((answers.n_states(), answers.n_actions()), (2, 2));
    assert_eq!(answers.get(0, 1).map(|a| a.q_mean()), Some(3.0));
    assert_eq!(answers.get(0, 0), None);
    assert_eq!(answers.get(1, 1), None);
    assert_eq!(answers.get(0, 2), None);
    assert_eq!(answers.get(usize::MAX, 1), None);
    assert_eq!(answers.distinct_clusters(), 1);
}
