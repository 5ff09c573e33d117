//! Strategies and helpers shared by the integration tests.
#![allow(
    dead_code,
    unreachable_pub,
    clippy::unwrap_used,
    reason = "each test module uses part of these shared helpers, and test helpers may unwrap"
)]

use ea_tree::{EaTree, EaTreeConfig, Sample, Similarity};
use proptest::prelude::*;

/// A sample that owns its state.
#[derive(Debug, Clone, PartialEq)]
pub struct OwnedSample {
    pub state: Vec<u32>,
    pub action: usize,
    pub q1: f64,
    pub q2: f64,
}

impl OwnedSample {
    pub fn as_sample(&self) -> Sample<'_> {
        Sample {
            state: &self.state,
            action: self.action,
            q1: self.q1,
            q2: self.q2,
        }
    }
}

/// Q values: finite, of either sign, sometimes repeated exactly.
pub fn q_value() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -100.0..100.0_f64,
        1 => (-4..=4_i32).prop_map(f64::from),
    ]
}

/// Samples whose states all have `features` features, bins in `0..bins`, actions in
/// `0..actions`: a small space, so that states and pairs repeat.
pub fn samples(
    features: usize,
    bins: u32,
    actions: usize,
    len: std::ops::Range<usize>,
) -> impl Strategy<Value = Vec<OwnedSample>> {
    prop::collection::vec(
        (
            prop::collection::vec(0..bins, features),
            0..actions,
            q_value(),
            q_value(),
        )
            .prop_map(|(state, action, q1, q2)| OwnedSample {
                state,
                action,
                q1,
                q2,
            }),
        len,
    )
}

/// Samples whose states have between 1 and `max_features` features (mixed lengths).
pub fn mixed_samples(
    max_features: usize,
    bins: u32,
    actions: usize,
    len: std::ops::Range<usize>,
) -> impl Strategy<Value = Vec<OwnedSample>> {
    prop::collection::vec(
        (
            prop::collection::vec(0..bins, 1..=max_features),
            0..actions,
            q_value(),
            q_value(),
        )
            .prop_map(|(state, action, q1, q2)| OwnedSample {
                state,
                action,
                q1,
                q2,
            }),
        len,
    )
}

/// A threshold: the boundary values and the similarities small states reach exactly, or any.
pub fn threshold() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(0.0),
        Just(1.0),
        Just(1.0 / 3.0),
        Just(0.5),
        Just(0.2),
        Just(2.0 / 3.0),
        0.0..=1.0_f64,
    ]
}

/// Thresholds, with the exact ones (each with its own index) drawn often.
pub fn config() -> impl Strategy<Value = EaTreeConfig> {
    prop_oneof![
        1 => Just(EaTreeConfig::EXACT),
        1 => threshold().prop_map(|a| EaTreeConfig::new(1.0, a).unwrap()),
        4 => (threshold(), threshold()).prop_map(|(s, a)| EaTreeConfig::new(s, a).unwrap()),
    ]
}

/// Every state with `features` features and bins in `0..bins`.
pub fn all_states(features: usize, bins: u32) -> Vec<Vec<u32>> {
    let mut states = vec![Vec::new()];
    for _ in 0..features {
        states = states
            .into_iter()
            .flat_map(|s| {
                (0..bins).map(move |b| {
                    let mut next = s.clone();
                    next.push(b);
                    next
                })
            })
            .collect();
    }
    states
}

/// A tree holding `samples`, inserted in order through the indexed path.
pub fn build(config: EaTreeConfig, samples: &[OwnedSample]) -> EaTree {
    let mut tree = EaTree::new(config).unwrap();
    for s in samples {
        tree.insert(s.as_sample()).unwrap();
    }
    tree
}

/// A tree holding `samples` with a custom similarity.
pub fn build_with<S: Similarity>(
    config: EaTreeConfig,
    similarity: S,
    samples: &[OwnedSample],
) -> EaTree<S> {
    let mut tree = EaTree::with_similarity(config, similarity).unwrap();
    for s in samples {
        tree.insert(s.as_sample()).unwrap();
    }
    tree
}

/// `a` and `b` agree to a relative 1e-9 (running means against sums divided once).
pub fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}
