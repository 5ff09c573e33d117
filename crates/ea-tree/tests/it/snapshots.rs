//! Snapshots of the text dump and the file format of small hand-built trees.
#![allow(
    clippy::unwrap_used,
    reason = "helpers outside #[test] fns unwrap too: tests may"
)]

use ea_tree::{EaTree, EaTreeConfig, Sample};

/// A 2 × 2 maze corner: three cells, two actions, one cell visited twice.
fn exact_tree() -> EaTree {
    let mut tree = EaTree::new(EaTreeConfig::EXACT).unwrap();
    for (state, action, q1, q2) in [
        ([0_u32, 0], 0, 1.0, 2.0),
        ([0, 0], 1, -1.0, -3.0),
        ([0, 1], 0, 0.5, 0.25),
        ([0, 0], 0, 2.0, 4.0),
        ([1, 1], 1, 10.0, 20.0),
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

/// Loose thresholds: states sharing a coordinate merge, centres become mixed.
fn loose_tree() -> EaTree {
    let mut tree = EaTree::new(EaTreeConfig::new(0.3, 0.5).unwrap()).unwrap();
    for (state, action, q1, q2) in [
        ([0_u32, 0], 0, 1.0, 2.0),
        ([0, 1], 0, 0.1, -0.2),
        ([0, 2], 1, 3.0, 3.0),
        ([0, 0], 1, 3.0, 3.0),
        ([2, 2], 1, -1.5, 0.0),
        ([2, 0], 0, 1.0 / 3.0, 2.0 / 3.0),
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

#[test]
fn dump_of_an_exact_tree() {
    insta::assert_snapshot!(exact_tree().dump(), @r"
    ea-tree similarity=weighted-jaccard tau_s=1 tau_a=1 samples=5 clusters=4 depth=3 longest_chain=3
    #0 n=2 s[0:0 1:0] a[0] q1=1.5 q2=3 sd=#2 ad=#1
    #1 n=1 s[0:0 1:0] a[1] q1=-1 q2=-3
    #2 n=1 s[0:0 1:1] a[0] q1=0.5 q2=0.25 sd=#3
    #3 n=1 s[0:1 1:1] a[1] q1=10 q2=20
    ");
}

#[test]
fn dump_of_a_loose_tree() {
    insta::assert_snapshot!(loose_tree().dump());
}

#[test]
fn file_of_a_loose_tree() {
    insta::assert_snapshot!(loose_tree().to_json());
}

#[test]
fn stats_of_an_exact_tree() {
    let stats = exact_tree().stats();
    // Bytes depend on the platform's layout; pin the shape.
    insta::assert_snapshot!(format!(
        "samples={} clusters={} depth={} longest_chain={} index={:?}",
        stats.samples_seen, stats.clusters, stats.depth, stats.longest_chain, stats.index
    ), @"samples=5 clusters=4 depth=3 longest_chain=3 index=ExactPair");
    assert!(stats.cluster_bytes >= 4 * 96 && stats.index_bytes > 0);
}
