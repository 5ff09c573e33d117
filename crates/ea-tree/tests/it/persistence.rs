//! Save/load: lossless round trips, atomic saves, and typed errors (never a panic) for
//! truncated, corrupt and inconsistent input.
#![allow(
    clippy::unwrap_used,
    reason = "helpers outside #[test] fns unwrap too: tests may"
)]

use crate::common;

use common::{all_states, build, config, mixed_samples};
use ea_tree::{
    ActionCentre, EaTree, EaTreeConfig, LoadError, Sample, Similarity, StateCentre, WeightedJaccard,
};
use proptest::prelude::*;

fn small_tree() -> EaTree {
    let mut tree = EaTree::new(EaTreeConfig::new(0.3, 0.5).unwrap()).unwrap();
    for (state, action, q1, q2) in [
        ([0_u32, 0], 0, 1.0, 2.0),
        ([0, 1], 0, 0.1, -0.2),
        ([0, 0], 1, 3.0, 3.0),
        ([2, 2], 1, -1.5, 0.0),
    ] {
        tree.insert(Sample {
            state: &state,
            action,
            q1,
            q2,
        })
        .unwrap();
    }
    tree
}

proptest! {
    #[test]
    fn json_round_trip_is_lossless(config in config(), data in mixed_samples(3, 3, 3, 0..80)) {
        let tree = build(config, &data);
        let text = tree.to_json();
        let back: EaTree = EaTree::from_json(&text).unwrap();
        prop_assert!(back == tree);
        prop_assert_eq!(back.to_json(), text);
        prop_assert_eq!(back.index_kind(), tree.index_kind());
        // Floats come back bit for bit.
        for (a, b) in tree.clusters().zip(back.clusters()) {
            prop_assert_eq!(a.q1().to_bits(), b.q1().to_bits());
            prop_assert_eq!(a.q2().to_bits(), b.q2().to_bits());
        }
        // The rebuilt index answers as before.
        for state in all_states(2, 4) {
            for action in 0..4 {
                prop_assert_eq!(back.lookup(&state, action), tree.lookup(&state, action));
            }
        }
        // The serde impls agree with the file format.
        let via_serde: EaTree = serde_json::from_str(&serde_json::to_string(&tree).unwrap()).unwrap();
        prop_assert!(via_serde == tree);
    }

    #[test]
    fn every_strict_prefix_of_a_file_is_an_error(cut in 0.0..1.0_f64) {
        let text = small_tree().to_json();
        let trimmed = text.trim_end();
        let at = (cut * trimmed.len() as f64) as usize;
        let result = EaTree::<WeightedJaccard>::from_json(&trimmed[..at]);
        prop_assert!(
            matches!(result, Err(LoadError::Truncated { .. } | LoadError::Corrupt { .. })),
            "{:?}", result
        );
    }

    #[test]
    fn mutated_files_never_panic(position in 0.0..1.0_f64, byte in any::<u8>()) {
        let mut bytes = small_tree().to_json().into_bytes();
        let at = (position * bytes.len() as f64) as usize;
        bytes[at] = byte;
        if let Ok(text) = std::str::from_utf8(&bytes) {
            // Either a valid tree (e.g. a changed digit of a Q value) or a typed error.
            if let Ok(tree) = EaTree::<WeightedJaccard>::from_json(text) {
                let _ = tree.lookup(&[0, 0], 0);
                let _ = tree.dump();
            }
        }
    }
}

#[test]
fn truncated_file_is_reported_as_truncated() {
    let text = small_tree().to_json();
    let result = EaTree::<WeightedJaccard>::from_json(&text[..text.len() / 2]);
    assert!(
        matches!(result, Err(LoadError::Truncated { .. })),
        "{result:?}"
    );
    assert!(matches!(
        EaTree::<WeightedJaccard>::from_json(""),
        Err(LoadError::Truncated { line: 1, .. })
    ));
}

#[test]
fn corrupt_files_are_reported_as_corrupt() {
    for text in [
        "not json",
        "[1, 2, 3]",
        r#"{"format": "ea-tree", "version": "one"}"#,
        // Right header, a field of the wrong type.
        &small_tree()
            .to_json()
            .replace("\"samples_seen\": 4", "\"samples_seen\": -4"),
        // Right header, an unknown field.
        &small_tree()
            .to_json()
            .replace("\"samples_seen\"", "\"extra\": 1, \"samples_seen\""),
        // A float out of range.
        &small_tree().to_json().replace("\"q1\":3.0", "\"q1\":1e999"),
    ] {
        let result = EaTree::<WeightedJaccard>::from_json(text);
        assert!(
            matches!(result, Err(LoadError::Corrupt { .. })),
            "{text}: {result:?}"
        );
    }
}

/// `small_tree`'s file with `from` replaced by `to` (which must occur).
fn edited(from: &str, to: &str) -> String {
    let text = small_tree().to_json();
    assert!(text.contains(from), "{from} not in {text}");
    text.replacen(from, to, 1)
}

#[test]
fn inconsistent_files_name_the_problem() {
    let cases = [
        (
            edited("\"count\":2", "\"count\":0"),
            "cluster #0",
            "count is 0",
        ),
        (
            edited("\"state_differs\":2", "\"state_differs\":9"),
            "cluster #0",
            "state_differs is #9",
        ),
        (
            edited("\"state_differs\":2", "\"state_differs\":0"),
            "cluster #0",
            "state_differs is #0",
        ),
        (
            edited(
                "\"state_differs\":null,\"action_differs\":null",
                "\"state_differs\":2,\"action_differs\":null",
            ),
            "cluster #1",
            "state_differs #2 already has a parent",
        ),
        (
            edited("\"actions\":[[0,2]]", "\"actions\":[[0,1]]"),
            "cluster #0",
            "action counts sum to 1",
        ),
        (
            edited("\"actions\":[[0,2]]", "\"actions\":[[1,1],[0,1]]"),
            "cluster #0",
            "not strictly ascending",
        ),
        (
            edited("[[0,0,2],", "[[0,0,3],"),
            "cluster #0",
            "outside 1..=2",
        ),
        (
            edited("[[0,0,2],[1,0,1],[1,1,1]]", "[[0,0,2],[1,0,2],[1,1,1]]"),
            "cluster #0",
            "feature 1 is carried 3 times",
        ),
        (
            edited("[[0,0,2],[1,0,1],[1,1,1]]", "[[0,0,1]]"),
            "cluster #0",
            "carry only 1 state tokens",
        ),
        (
            edited("\"samples_seen\": 4", "\"samples_seen\": 5"),
            "tree",
            "samples_seen is 5",
        ),
    ];
    for (text, location, problem) in cases {
        match EaTree::<WeightedJaccard>::from_json(&text) {
            Err(LoadError::Inconsistent {
                location: l,
                problem: p,
            }) => {
                assert!(l.starts_with(location), "{l} vs {location}");
                assert!(p.contains(problem), "{p:?} lacks {problem:?}");
            }
            other => panic!("expected Inconsistent({problem}), got {other:?}\n{text}"),
        }
    }
    // An orphan: the link to cluster #1 removed.
    let orphan = edited("\"action_differs\":1", "\"action_differs\":null");
    match EaTree::<WeightedJaccard>::from_json(&orphan) {
        Err(LoadError::Inconsistent { location, problem }) => {
            assert_eq!(location, "cluster #1");
            assert!(problem.contains("no cluster links to it"));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_header_config_and_similarity_are_typed() {
    let version = edited("\"version\": 1", "\"version\": 2");
    assert!(matches!(
        EaTree::<WeightedJaccard>::from_json(&version),
        Err(LoadError::UnsupportedFormat { version: 2, .. })
    ));
    let format = edited("\"format\": \"ea-tree\"", "\"format\": \"q-table\"");
    assert!(matches!(
        EaTree::<WeightedJaccard>::from_json(&format),
        Err(LoadError::UnsupportedFormat { .. })
    ));
    let threshold = edited("\"state_threshold\":0.3", "\"state_threshold\":1.3");
    assert!(matches!(
        EaTree::<WeightedJaccard>::from_json(&threshold),
        Err(LoadError::InvalidConfig(_))
    ));
    let text = small_tree().to_json();
    match EaTree::from_json_with(&text, Other) {
        Err(LoadError::SimilarityMismatch { expected, found }) => {
            assert_eq!(
                (expected.as_str(), found.as_str()),
                ("other", "weighted-jaccard")
            );
        }
        other => panic!("{other:?}"),
    }
}

#[derive(Debug, Default)]
struct Other;

impl Similarity for Other {
    fn name(&self) -> &str {
        "other"
    }
    fn state_similarity(&self, _: &[u32], _: &StateCentre<'_>) -> f64 {
        0.0
    }
    fn action_similarity(&self, _: usize, _: &ActionCentre<'_>) -> f64 {
        0.0
    }
}

#[test]
fn load_restores_the_tree_from_its_json_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tree.json");
    let tree = small_tree();
    std::fs::write(&path, tree.to_json()).unwrap();
    let loaded: EaTree = EaTree::load(&path).unwrap();
    assert_eq!(loaded, tree);
    let empty = EaTree::new(EaTreeConfig::EXACT).unwrap();
    std::fs::write(&path, empty.to_json()).unwrap();
    assert_eq!(EaTree::<WeightedJaccard>::load(&path).unwrap(), empty);
    // Errors name the path.
    let missing = dir.path().join("missing.json");
    match EaTree::<WeightedJaccard>::load(&missing) {
        Err(e @ LoadError::Io { .. }) => assert!(e.to_string().contains("missing.json")),
        other => panic!("{other:?}"),
    }
}
