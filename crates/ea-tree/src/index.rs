//! Indexes that let a walk skip clusters the literal walk of Fig. 4 would pass over.
//!
//! # Chains
//! Follow "state differs" edges from the root, or from any "action differs" child, and you
//! get a *chain*. Every cluster lies on exactly one chain, and a walk always enters a chain
//! at its head and leaves it at the **first** cluster whose state test passes (then it either
//! stops there or takes that cluster's "action differs" edge into the head of another
//! chain); when no cluster of the chain passes, it ends at the chain's tail. So a walk is
//! exactly determined by answering, for each chain it enters, "which is the first cluster of
//! this chain whose state test passes for the query?" The indexes answer that question
//! faster than testing every cluster in turn, and only that question: everything else (the
//! action tests, which edge to follow) is done as in the literal walk.
//!
//! # `ExactState` (τₛ = 1, similarity with [`state_exact_at_one`](crate::SimilarityProperties))
//! A state test passes exactly when the cluster is *pure* with the query's state (every
//! member had it). A hash map gives, for each state, the first pure cluster of the root
//! chain. Pure clusters stay pure (at τₛ = 1 only identical states merge) and mixed ones
//! never match, so the map only grows. Other chains are walked literally. In a tree built
//! by inserts at τₛ = 1 a sample only enters the "action differs" child of a cluster of its
//! own state, so those chains hold clusters of one state and the rest of the walk is at
//! most as long as the number of clusters holding the query's state.
//!
//! # `ExactPair` (τₛ = τₐ = 1, similarity exact at one for states and actions)
//! The `ExactState` index, plus, for lookups, a hash map from `(s, a)` to the cluster where
//! the walk for `(s, a)` ends, for every pair whose walk ends at a cluster. A walk that
//! ends at a cluster ends at one that is pure in both state and action, so the keys to
//! consider are those of the pure clusters; the map is filled by walking for each of them
//! (on load) and kept exact on insert: a new cluster for `(s, a)` is only ever opened
//! where the walk for `(s, a)` fell off the tree, and afterwards that walk ends at it, while
//! every other walk through the same spot still falls off (the new cluster has no children).
//! Merges change no centre at τ = 1 (only identical samples merge). A pair missing from the
//! map therefore has no prior experience. Keys are stored inline (no pointer to chase) for
//! states of up to 7 features and actions that fit a `u32`; other queries take the
//! `ExactState` walk.
//!
//! # `SharedTokens` (0 < τₛ, similarity [`bounded_by_shared_tokens`](crate::SimilarityProperties))
//! A cluster whose centre carries only `k` of the query's `d` tokens has state similarity
//! at most `k / d`, so it cannot pass when `k / d < τₛ`. Each chain keeps, per token, the
//! ascending positions of its clusters whose centre carries that token. Merging the query's
//! `d` posting lists visits exactly the clusters carrying at least one query token, in chain
//! order, with `k` for free; clusters with too small a `k` are skipped without evaluating the
//! similarity, the others are tested as in the literal walk. Centres only ever gain tokens,
//! so a merge adds a position to a list and never removes one.

use std::collections::HashMap;

use crate::cluster::{Cluster, ClusterId};
use crate::encoding::Token;

/// Which lookup index a tree uses (chosen from its thresholds and similarity).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum IndexKind {
    /// No index: every walk is the literal walk (τₛ = 0, or a similarity without guarantees).
    Literal,
    /// Hash map from a state to its cluster on the root chain (τₛ = 1, τₐ < 1).
    ExactState,
    /// Hash map from `(s, a)` to its cluster, over the `ExactState` index (τₛ = τₐ = 1).
    ExactPair,
    /// Per-chain posting lists of state tokens (0 < τₛ < 1).
    SharedTokens,
}

/// Where a walk ended without finding a cluster: the empty child it reached.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Vacancy {
    /// The tree has no cluster yet; a new cluster becomes the root.
    EmptyTree,
    /// The "state differs" child of this cluster is empty.
    StateDiffers(ClusterId),
    /// The "action differs" child of this cluster is empty.
    ActionDiffers(ClusterId),
}

/// The end of a walk.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum WalkEnd {
    /// Both tests passed at this cluster.
    Found(ClusterId),
    /// The walk fell off the tree here ("no prior experience"; a new cluster on insert).
    Vacant(Vacancy),
}

/// A cluster's chain and its position on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct ChainPlace {
    chain: u32,
    position: u32,
}

/// Data of the [`IndexKind::ExactState`] index.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct ExactStateIndex {
    /// For every state with a pure cluster on the root chain, the first such cluster.
    first_on_root_chain: HashMap<Box<[u32]>, ClusterId>,
    /// Last cluster of the root chain.
    root_chain_tail: Option<ClusterId>,
    /// For [`IndexKind::ExactPair`]: where the walk for each `(s, a)` ends at a cluster.
    pairs: Option<HashMap<PairKey, ClusterId>>,
}

/// A `(state, action)` pair stored inline: the state's bins followed by the action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PairKey {
    len: u32,
    // Unused words stay 0, so equal pairs are equal keys.
    words: [u32; PairKey::MAX_FEATURES + 1],
}

impl PairKey {
    /// Most state features an inline key holds.
    pub(crate) const MAX_FEATURES: usize = 7;

    /// The key of `(state, action)`, if it fits inline.
    pub(crate) fn new(state: &[u32], action: usize) -> Option<Self> {
        if state.len() > Self::MAX_FEATURES {
            return None;
        }
        let mut words = [0; Self::MAX_FEATURES + 1];
        words[..state.len()].copy_from_slice(state);
        words[state.len()] = u32::try_from(action).ok()?;
        let len = u32::try_from(state.len() + 1).ok()?;
        Some(Self { len, words })
    }
}

impl std::hash::Hash for PairKey {
    fn hash<H: std::hash::Hasher>(&self, hasher: &mut H) {
        self.words[..self.len as usize].hash(hasher);
    }
}

/// Data of the [`IndexKind::SharedTokens`] index.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct SharedTokenIndex {
    /// Chain and position of every cluster, by cluster id.
    places: Vec<ChainPlace>,
    /// The clusters of each chain, head first.
    chains: Vec<Vec<ClusterId>>,
    /// Ascending positions, on a chain, of the clusters whose centre carries a token.
    postings: HashMap<(u32, Token), Vec<u32>>,
}

/// The lookup index of a tree; always derived from the clusters, never saved.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum WalkIndex {
    /// See [`IndexKind::Literal`].
    Literal,
    /// See [`IndexKind::ExactState`].
    ExactState(ExactStateIndex),
    /// See [`IndexKind::SharedTokens`].
    SharedTokens(SharedTokenIndex),
}

impl WalkIndex {
    /// An empty index of the given kind.
    pub(crate) fn empty(kind: IndexKind) -> Self {
        match kind {
            IndexKind::Literal => Self::Literal,
            IndexKind::ExactState => Self::ExactState(ExactStateIndex::default()),
            IndexKind::ExactPair => Self::ExactState(ExactStateIndex {
                pairs: Some(HashMap::new()),
                ..ExactStateIndex::default()
            }),
            IndexKind::SharedTokens => Self::SharedTokens(SharedTokenIndex::default()),
        }
    }

    /// The index of an existing (validated) tree, replaying cluster creation in id order.
    ///
    /// Parents always have smaller ids than their children, so replaying in id order
    /// reproduces the index that inserting the same clusters one by one maintained. The
    /// `(s, a)` map of [`IndexKind::ExactPair`] is left empty: it needs walks, which the tree
    /// runs afterwards (see `EaTree::rebuild_index`).
    pub(crate) fn rebuild(kind: IndexKind, clusters: &[Cluster]) -> Self {
        let mut vacancies = vec![Vacancy::EmptyTree; clusters.len()];
        for (parent, cluster) in (0_u32..).zip(clusters) {
            if let Some(child) = cluster.state_differs {
                vacancies[child.index()] = Vacancy::StateDiffers(ClusterId(parent));
            }
            if let Some(child) = cluster.action_differs {
                vacancies[child.index()] = Vacancy::ActionDiffers(ClusterId(parent));
            }
        }
        let mut index = Self::empty(kind);
        for ((id, cluster), vacancy) in (0_u32..).zip(clusters).zip(vacancies) {
            index.on_new_cluster(ClusterId(id), vacancy, cluster);
        }
        index
    }

    /// Which kind of index this is.
    pub(crate) fn kind(&self) -> IndexKind {
        match self {
            Self::Literal => IndexKind::Literal,
            Self::ExactState(index) if index.pairs.is_some() => IndexKind::ExactPair,
            Self::ExactState(_) => IndexKind::ExactState,
            Self::SharedTokens(_) => IndexKind::SharedTokens,
        }
    }

    /// Records `cluster`, just created as `id` in the empty child `vacancy`.
    pub(crate) fn on_new_cluster(&mut self, id: ClusterId, vacancy: Vacancy, cluster: &Cluster) {
        match self {
            Self::Literal => {}
            Self::ExactState(index) => {
                let on_root_chain = match vacancy {
                    Vacancy::EmptyTree => true,
                    Vacancy::StateDiffers(parent) => index.root_chain_tail == Some(parent),
                    Vacancy::ActionDiffers(_) => false,
                };
                if on_root_chain {
                    index.root_chain_tail = Some(id);
                    if let Some(state) = cluster.pure_state() {
                        let state: Box<[u32]> = state.collect();
                        index.first_on_root_chain.entry(state).or_insert(id);
                    }
                }
            }
            Self::SharedTokens(index) => {
                let chain = match vacancy {
                    Vacancy::StateDiffers(parent) => index.places[parent.index()].chain,
                    Vacancy::EmptyTree | Vacancy::ActionDiffers(_) => {
                        index.chains.push(Vec::new());
                        u32::try_from(index.chains.len() - 1)
                            .expect("chains never outnumber clusters, whose ids are u32")
                    }
                };
                let members = &mut index.chains[chain as usize];
                let position = u32::try_from(members.len())
                    .expect("a chain never holds more clusters than the tree, whose ids are u32");
                members.push(id);
                index.places.push(ChainPlace { chain, position });
                for t in &cluster.state_tokens {
                    // The new cluster is the last of its chain: pushing keeps lists ascending.
                    index
                        .postings
                        .entry((chain, t.token))
                        .or_default()
                        .push(position);
                }
            }
        }
    }

    /// Records that the centre of `id` now carries `token` (it did not before).
    pub(crate) fn on_new_token(&mut self, id: ClusterId, token: Token) {
        // ExactState: at τₛ = 1 only identical states merge, so no centre gains a token.
        if let Self::SharedTokens(index) = self {
            let place = index.places[id.index()];
            let list = index.postings.entry((place.chain, token)).or_default();
            if let Err(at) = list.binary_search(&place.position) {
                list.insert(at, place.position);
            }
        }
    }

    /// Releases spare capacity.
    pub(crate) fn shrink_to_fit(&mut self) {
        match self {
            Self::Literal => {}
            Self::ExactState(index) => {
                index.first_on_root_chain.shrink_to_fit();
                if let Some(pairs) = index.pairs.as_mut() {
                    pairs.shrink_to_fit();
                }
            }
            Self::SharedTokens(index) => {
                index.places.shrink_to_fit();
                index.chains.shrink_to_fit();
                index.chains.iter_mut().for_each(Vec::shrink_to_fit);
                index.postings.shrink_to_fit();
                index.postings.values_mut().for_each(Vec::shrink_to_fit);
            }
        }
    }

    /// Estimated heap bytes of the index.
    pub(crate) fn heap_bytes(&self) -> usize {
        match self {
            Self::Literal => 0,
            Self::ExactState(index) => {
                hash_map_heap_bytes::<Box<[u32]>, ClusterId>(index.first_on_root_chain.capacity())
                    + index
                        .first_on_root_chain
                        .keys()
                        .map(|k| size_of_val::<[u32]>(k))
                        .sum::<usize>()
                    + index.pairs.as_ref().map_or(0, |pairs| {
                        hash_map_heap_bytes::<PairKey, ClusterId>(pairs.capacity())
                    })
            }
            Self::SharedTokens(index) => {
                index.places.capacity() * size_of::<ChainPlace>()
                    + index.chains.capacity() * size_of::<Vec<ClusterId>>()
                    + index
                        .chains
                        .iter()
                        .map(|c| c.capacity() * size_of::<ClusterId>())
                        .sum::<usize>()
                    + hash_map_heap_bytes::<(u32, Token), Vec<u32>>(index.postings.capacity())
                    + index
                        .postings
                        .values()
                        .map(|p| p.capacity() * size_of::<u32>())
                        .sum::<usize>()
            }
        }
    }
}

impl ExactStateIndex {
    /// The first cluster of the root chain whose centre is exactly `state`.
    pub(crate) fn first_on_root_chain(&self, state: &[u32]) -> Option<ClusterId> {
        self.first_on_root_chain.get(state).copied()
    }

    /// The last cluster of the root chain (`None` only for an empty tree).
    pub(crate) fn root_chain_tail(&self) -> Option<ClusterId> {
        self.root_chain_tail
    }

    /// With an `(s, a)` map: `Some(answer)` for a query it covers (`Some(None)`: no prior
    /// experience), `None` when the query does not fit an inline key or there is no map.
    pub(crate) fn pair(&self, state: &[u32], action: usize) -> Option<Option<ClusterId>> {
        let pairs = self.pairs.as_ref()?;
        let key = PairKey::new(state, action)?;
        Some(pairs.get(&key).copied())
    }

    /// Records that the walk for `(state, action)` now ends at `id` (no-op without a map or
    /// for a pair that does not fit a key).
    pub(crate) fn set_pair(&mut self, state: &[u32], action: usize, id: ClusterId) {
        if let (Some(pairs), Some(key)) = (self.pairs.as_mut(), PairKey::new(state, action)) {
            pairs.insert(key, id);
        }
    }
}

/// Most query tokens the posting-list merge handles on the stack; longer states fall back to
/// testing every cluster of the chain (same answer, no allocation).
pub(crate) const MAX_MERGED_TOKENS: usize = 16;

impl SharedTokenIndex {
    /// The chain `head` starts (a walk only ever enters a chain at its head).
    pub(crate) fn chain_of(&self, head: ClusterId) -> u32 {
        self.places[head.index()].chain
    }

    /// The clusters of `chain`, head first.
    pub(crate) fn chain(&self, chain: u32) -> &[ClusterId] {
        &self.chains[chain as usize]
    }

    /// Ascending positions on `chain` of the clusters carrying `token`.
    pub(crate) fn postings(&self, chain: u32, token: Token) -> &[u32] {
        self.postings
            .get(&(chain, token))
            .map_or(&[], Vec::as_slice)
    }
}

/// Estimated heap bytes of a `std` `HashMap` (hashbrown layout: a power-of-two number of
/// buckets at most 7/8 full, one control byte per bucket plus one group of 16).
pub(crate) fn hash_map_heap_bytes<K, V>(capacity: usize) -> usize {
    if capacity == 0 {
        return 0;
    }
    let buckets = if capacity < 8 {
        if capacity < 4 { 4 } else { 8 }
    } else {
        (capacity.saturating_mul(8) / 7).next_power_of_two()
    };
    buckets * (size_of::<(K, V)>() + 1) + 16
}
