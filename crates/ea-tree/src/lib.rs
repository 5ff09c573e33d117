//! Experience-aggregation tree: Jaccard-clustered storage of `(s, a, Q1, Q2)` samples, the
//! storage half of the EA-MADM paper (Sec. IV.B, Fig. 4).
//!
//! A trained sub-task's experience is a set of quadruples `(s, a, Q1(s, a), Q2(s, a))`. The
//! tree clusters them: every node is a cluster whose *centre* is the mean of its members'
//! state indicator vector, action indicator vector, Q1 and Q2, with a member count. A walk
//! for `(s, a)` starts at the root and, at each cluster (Fig. 4):
//!
//! * state similar (`sim_s ≥ τₛ`) and action similar (`sim_a ≥ τₐ`) → this cluster;
//! * state similar, action not → the "action differs" child (red in Fig. 4);
//! * state not similar → the "state differs" child (yellow in Fig. 4);
//! * an empty child → [`EaTree::insert`] opens a new cluster there,
//!   [`EaTree::lookup`] answers `None` ("no prior experience").
//!
//! Inserting merges the sample into the cluster the walk found (the centre moves to the new
//! mean). Looking up returns that cluster's mean Q1, Q2 and count ([`Answer`]).
//!
//! # Encoding and similarity
//! A state is given as its discrete feature bins (`[x, y]` for a maze cell); its token set is
//! `{(i, state[i])}`, and an action is a one-token set (see [`encoding`]). Similarity is
//! Jaccard: [`set_jaccard`] between samples, and against a centre the weighted Jaccard
//! `Σ min / Σ max` of [`WeightedJaccard`], which equals set Jaccard for a one-member
//! centre. Centres are kept as exact member counts per token, so at `τₛ = τₐ = 1` only
//! identical `(s, a)` merge and the tree answers like a table of per-`(s, a)` means. Another
//! similarity can be plugged in through the [`Similarity`] trait.
//!
//! # Which samples go in
//! Bulk mode ([`EaTree::insert_table`], [`EaTree::from_table`]): one sample per visited
//! `(s, a)` of a trained sub-task with its final Q1, Q2, inserted in ascending
//! `(state id, action)` order. Streaming mode: call [`EaTree::insert`] for every sample as it
//! comes. Both use the same insert path.
//!
//! # The degenerate chain, and the index that fixes it
//! Taken literally, the structure degenerates. At `τₛ = 1` every new state fails the state
//! test at every cluster of the root's "state differs" chain and is appended at its end, so
//! that chain holds one cluster per distinct state (900 for a 30 × 30 maze) and a literal walk
//! costs O(#states) similarity tests: the tree is a linked list. Below 1 it is the same
//! whenever states rarely resemble each other. We keep the paper's answers and make them
//! fast: [`EaTree::lookup`] and [`EaTree::insert`] go through an index ([`IndexKind`]) that
//! jumps straight to the first cluster of a chain whose state test can pass: at
//! `τₛ = τₐ = 1` a hash map from `(s, a)` to its cluster answers a lookup in one probe; at
//! `τₛ = 1` a hash map from a state to its cluster on the root chain; below 1, per-chain
//! posting lists of state tokens skip the clusters sharing too few tokens with the query. It
//! ends every walk exactly where the literal walk ends (the argument is in the [`index`]
//! module; property tests check it on random trees, loaded trees of any shape, and random
//! thresholds). [`EaTree::lookup_literal`] and [`EaTree::insert_literal`]
//! keep the literal walk. For the fastest reads of a finished tree,
//! [`EaTree::answer_table`] answers every `(state, action)` once.
//!
//! # Example
//! ```
//! use ea_tree::{EaTree, EaTreeConfig, Sample};
//!
//! let mut tree = EaTree::new(EaTreeConfig::EXACT)?;
//! // Two samples of the same (s, a) merge; a new action of the same state opens a cluster.
//! tree.insert(Sample { state: &[3, 4], action: 0, q1: 1.0, q2: 3.0 })?;
//! tree.insert(Sample { state: &[3, 4], action: 0, q1: 2.0, q2: 5.0 })?;
//! tree.insert(Sample { state: &[3, 4], action: 1, q1: -1.0, q2: -1.0 })?;
//! assert_eq!(tree.len(), 2);
//!
//! let answer = tree.lookup(&[3, 4], 0).expect("stored");
//! assert_eq!((answer.q1, answer.q2, answer.count), (1.5, 4.0, 2));
//! assert_eq!(answer.q_mean(), 2.75);
//! assert_eq!(tree.lookup(&[3, 5], 0), None); // no prior experience
//! assert_eq!(tree.lookup_literal(&[3, 4], 0), Some(answer));
//!
//! // Below τ = 1 similar states share a cluster: [3, 5] shares one of [3, 4]'s two tokens.
//! let mut loose = EaTree::new(EaTreeConfig::new(0.3, 1.0)?)?;
//! loose.insert(Sample { state: &[3, 4], action: 0, q1: 1.0, q2: 1.0 })?;
//! loose.insert(Sample { state: &[3, 5], action: 0, q1: 3.0, q2: 3.0 })?;
//! assert_eq!(loose.len(), 1);
//! println!("{}", loose.dump());
//! # Ok::<(), ea_tree::EaTreeError>(())
//! ```

pub mod bulk;
pub mod cluster;
pub mod config;
pub mod encoding;
pub mod error;
pub mod index;
pub mod persist;
pub mod similarity;
pub mod stats;
pub mod tree;

pub use bulk::{AnswerTable, TableEntry};
pub use cluster::{ActionCentre, ClusterId, StateCentre, StateOverlap};
pub use config::EaTreeConfig;
pub use encoding::{MAX_FEATURES, Token, set_jaccard, state_tokens};
pub use error::{EaTreeError, LoadError};
pub use index::IndexKind;
pub use similarity::{Similarity, SimilarityProperties, WeightedJaccard};
pub use stats::TreeStats;
pub use tree::{Answer, ClusterView, EaTree, Insertion, Sample};
