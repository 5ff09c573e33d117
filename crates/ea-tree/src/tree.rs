//! The experience-aggregation tree: insertion and lookup by the walk of Fig. 4.

use crate::cluster::{ActionCentre, Cluster, ClusterId, StateCentre};
use crate::config::EaTreeConfig;
use crate::encoding::{MAX_FEATURES, Token, state_tokens};
use crate::error::EaTreeError;
use crate::index::{IndexKind, MAX_MERGED_TOKENS, SharedTokenIndex, Vacancy, WalkEnd, WalkIndex};
use crate::similarity::{Similarity, WeightedJaccard};

/// One experience sample `(s, a, Q1(s, a), Q2(s, a))` of a sub-task.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample<'a> {
    /// The state's feature bins (see [`crate::encoding`]); at least one feature.
    pub state: &'a [u32],
    /// The action.
    pub action: usize,
    /// The first double-Q estimate.
    pub q1: f64,
    /// The second double-Q estimate.
    pub q2: f64,
}

/// What [`EaTree::insert`] did with a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Insertion {
    /// The cluster that now holds the sample.
    pub cluster: ClusterId,
    /// `true` if the sample opened a new cluster, `false` if it merged into an existing one.
    pub created: bool,
}

/// Prior experience found for a query `(s, a)`: the matching cluster's centre values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Answer {
    /// The cluster that matched.
    pub cluster: ClusterId,
    /// Mean Q1 of the cluster's members.
    pub q1: f64,
    /// Mean Q2 of the cluster's members.
    pub q2: f64,
    /// Number of samples in the cluster.
    pub count: u64,
}

impl Answer {
    /// `(Q1 + Q2) / 2`, the value the MADM step uses (finite for finite Q1, Q2).
    #[must_use]
    pub fn q_mean(&self) -> f64 {
        0.5 * self.q1 + 0.5 * self.q2
    }
}

/// Read-only view of one cluster.
#[derive(Debug, Clone, Copy)]
pub struct ClusterView<'a> {
    id: ClusterId,
    cluster: &'a Cluster,
}

impl<'a> ClusterView<'a> {
    /// The cluster's id.
    #[must_use]
    pub fn id(&self) -> ClusterId {
        self.id
    }

    /// Number of members.
    #[must_use]
    pub fn count(&self) -> u64 {
        self.cluster.count
    }

    /// Mean Q1 of the members.
    #[must_use]
    pub fn q1(&self) -> f64 {
        self.cluster.q1
    }

    /// Mean Q2 of the members.
    #[must_use]
    pub fn q2(&self) -> f64 {
        self.cluster.q2
    }

    /// The state half of the centre.
    #[must_use]
    pub fn state_centre(&self) -> StateCentre<'a> {
        self.cluster.state_centre()
    }

    /// The action half of the centre.
    #[must_use]
    pub fn action_centre(&self) -> ActionCentre<'a> {
        self.cluster.action_centre()
    }

    /// The "state differs" child (yellow in Fig. 4).
    #[must_use]
    pub fn state_differs(&self) -> Option<ClusterId> {
        self.cluster.state_differs
    }

    /// The "action differs" child (red in Fig. 4).
    #[must_use]
    pub fn action_differs(&self) -> Option<ClusterId> {
        self.cluster.action_differs
    }

    /// The cluster's centre values as a lookup answer.
    #[must_use]
    pub fn answer(&self) -> Answer {
        Answer {
            cluster: self.id,
            q1: self.cluster.q1,
            q2: self.cluster.q2,
            count: self.cluster.count,
        }
    }
}

/// The experience-aggregation tree of Sec. IV.B, Fig. 4.
///
/// A binary tree of clusters. A walk for `(s, a)` starts at the root; at each cluster it
/// tests the state (`similarity ≥ τₛ`), then the action (`≥ τₐ`):
///
/// * state similar and action similar → this cluster;
/// * state similar, action not → go to the "action differs" child;
/// * state not similar → go to the "state differs" child;
/// * the child is empty → insert: a new cluster there; lookup: no prior experience.
///
/// [`insert`](Self::insert) and [`lookup`](Self::lookup) use an index that provably ends
/// every walk where the literal one ends (see [`crate::IndexKind`]);
/// [`insert_literal`](Self::insert_literal) and [`lookup_literal`](Self::lookup_literal)
/// walk cluster by cluster exactly as the figure draws it.
#[derive(Debug, Clone)]
pub struct EaTree<S = WeightedJaccard> {
    pub(crate) config: EaTreeConfig,
    pub(crate) similarity: S,
    pub(crate) clusters: Vec<Cluster>,
    pub(crate) samples_seen: u64,
    pub(crate) index: WalkIndex,
}

impl EaTree<WeightedJaccard> {
    /// An empty tree with weighted Jaccard similarity.
    ///
    /// # Errors
    /// [`EaTreeError::InvalidThreshold`] if `config` is invalid.
    pub fn new(config: EaTreeConfig) -> Result<Self, EaTreeError> {
        Self::with_similarity(config, WeightedJaccard)
    }
}

impl<S: Similarity> EaTree<S> {
    /// An empty tree with a custom similarity.
    ///
    /// # Errors
    /// [`EaTreeError::InvalidThreshold`] if `config` is invalid.
    pub fn with_similarity(config: EaTreeConfig, similarity: S) -> Result<Self, EaTreeError> {
        config.validate()?;
        let kind = index_kind(&config, &similarity);
        Ok(Self {
            config,
            similarity,
            clusters: Vec::new(),
            samples_seen: 0,
            index: WalkIndex::empty(kind),
        })
    }

    /// The thresholds.
    #[must_use]
    pub fn config(&self) -> &EaTreeConfig {
        &self.config
    }

    /// The similarity.
    #[must_use]
    pub fn similarity(&self) -> &S {
        &self.similarity
    }

    /// Which index [`lookup`](Self::lookup) and [`insert`](Self::insert) use.
    #[must_use]
    pub fn index_kind(&self) -> IndexKind {
        self.index.kind()
    }

    /// Number of clusters.
    #[must_use]
    pub fn len(&self) -> usize {
        self.clusters.len()
    }

    /// `true` before the first sample.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.clusters.is_empty()
    }

    /// Number of samples inserted so far.
    #[must_use]
    pub fn samples_seen(&self) -> u64 {
        self.samples_seen
    }

    /// The cluster `id`, if it exists.
    #[must_use]
    pub fn cluster(&self, id: ClusterId) -> Option<ClusterView<'_>> {
        self.clusters
            .get(id.index())
            .map(|cluster| ClusterView { id, cluster })
    }

    /// All clusters in creation order (the root first).
    pub fn clusters(&self) -> impl Iterator<Item = ClusterView<'_>> {
        (0_u32..)
            .zip(&self.clusters)
            .map(|(id, cluster)| ClusterView {
                id: ClusterId(id),
                cluster,
            })
    }

    /// Adds one sample: merges it into the cluster the walk ends at, or opens a new
    /// cluster in the empty child it ends at. Same result as
    /// [`insert_literal`](Self::insert_literal), faster.
    ///
    /// Streaming mode is calling this for every sample as it comes; bulk mode is
    /// [`insert_table`](Self::insert_table).
    ///
    /// # Errors
    /// [`EaTreeError::EmptyState`], [`EaTreeError::TooManyFeatures`],
    /// [`EaTreeError::NonFiniteQ`], or [`EaTreeError::TooManyClusters`]; the tree is
    /// unchanged on error.
    pub fn insert(&mut self, sample: Sample<'_>) -> Result<Insertion, EaTreeError> {
        check_sample(&sample)?;
        let end = self.walk_indexed(sample.state, sample.action);
        self.store(end, sample)
    }

    /// [`insert`](Self::insert) by the literal walk of Fig. 4 (for tests and benchmarks).
    ///
    /// # Errors
    /// As [`insert`](Self::insert).
    pub fn insert_literal(&mut self, sample: Sample<'_>) -> Result<Insertion, EaTreeError> {
        check_sample(&sample)?;
        let end = self.walk_literal(sample.state, sample.action);
        self.store(end, sample)
    }

    /// Prior experience for `(state, action)`: the centre values of the cluster where the
    /// walk of Fig. 4 ends, or `None` ("no prior experience"). Allocates nothing.
    #[must_use]
    pub fn lookup(&self, state: &[u32], action: usize) -> Option<Answer> {
        if state.len() > MAX_FEATURES {
            return None;
        }
        if let WalkIndex::ExactState(index) = &self.index
            && let Some(found) = index.pair(state, action)
        {
            return found.map(|id| self.answer(id));
        }
        match self.walk_indexed(state, action) {
            WalkEnd::Found(id) => Some(self.answer(id)),
            WalkEnd::Vacant(_) => None,
        }
    }

    /// [`lookup`](Self::lookup) by the literal walk of Fig. 4 (for tests and benchmarks).
    #[must_use]
    pub fn lookup_literal(&self, state: &[u32], action: usize) -> Option<Answer> {
        if state.len() > MAX_FEATURES {
            return None;
        }
        match self.walk_literal(state, action) {
            WalkEnd::Found(id) => Some(self.answer(id)),
            WalkEnd::Vacant(_) => None,
        }
    }

    /// Number of clusters the literal walk for `(state, action)` visits (its cost).
    #[must_use]
    pub fn literal_walk_length(&self, state: &[u32], action: usize) -> usize {
        let mut visited = 0;
        let mut at = (!self.clusters.is_empty()).then_some(ClusterId::ROOT);
        while let Some(id) = at {
            visited += 1;
            let cluster = &self.clusters[id.index()];
            at = match self.step(id, cluster, state, action) {
                Step::Stop(_) => None,
                Step::Next(next) => Some(next),
            };
        }
        visited
    }

    /// Releases spare capacity of the clusters and the index (done after a bulk build;
    /// useful after streaming, before a tree is only read).
    pub fn shrink_to_fit(&mut self) {
        self.clusters.shrink_to_fit();
        for cluster in &mut self.clusters {
            cluster.state_tokens.shrink_to_fit();
            cluster.actions.shrink_to_fit();
        }
        self.index.shrink_to_fit();
    }

    /// Derives the lookup index from the clusters (after a load).
    pub(crate) fn rebuild_index(&mut self) {
        self.index = WalkIndex::rebuild(index_kind(&self.config, &self.similarity), &self.clusters);
        if self.index.kind() != IndexKind::ExactPair {
            return;
        }
        // A walk that ends at a cluster ends at one pure in state and action, so walking
        // for the key of every such cluster finds every pair with prior experience.
        let mut found = Vec::new();
        for cluster in &self.clusters {
            let (Some(state), [only]) = (cluster.pure_state(), cluster.actions.as_slice()) else {
                continue;
            };
            if only.count != cluster.count {
                continue;
            }
            let state: Vec<u32> = state.collect();
            if let WalkEnd::Found(id) = self.walk_indexed(&state, only.action) {
                found.push((state, only.action, id));
            }
        }
        if let WalkIndex::ExactState(index) = &mut self.index {
            for (state, action, id) in found {
                index.set_pair(&state, action, id);
            }
        }
    }

    fn answer(&self, id: ClusterId) -> Answer {
        let cluster = &self.clusters[id.index()];
        Answer {
            cluster: id,
            q1: cluster.q1,
            q2: cluster.q2,
            count: cluster.count,
        }
    }

    fn state_passes(&self, state: &[u32], cluster: &Cluster) -> bool {
        self.similarity
            .state_similarity(state, &cluster.state_centre())
            >= self.config.state_threshold
    }

    fn action_passes(&self, action: usize, cluster: &Cluster) -> bool {
        self.similarity
            .action_similarity(action, &cluster.action_centre())
            >= self.config.action_threshold
    }

    /// One step of the literal walk at cluster `id`.
    fn step(&self, id: ClusterId, cluster: &Cluster, state: &[u32], action: usize) -> Step {
        if self.state_passes(state, cluster) {
            self.after_state_passed(id, cluster, action)
        } else {
            match cluster.state_differs {
                Some(next) => Step::Next(next),
                None => Step::Stop(WalkEnd::Vacant(Vacancy::StateDiffers(id))),
            }
        }
    }

    /// The step at a cluster whose state test passed: stop here, or go to "action differs".
    fn after_state_passed(&self, id: ClusterId, cluster: &Cluster, action: usize) -> Step {
        if self.action_passes(action, cluster) {
            Step::Stop(WalkEnd::Found(id))
        } else {
            match cluster.action_differs {
                Some(next) => Step::Next(next),
                None => Step::Stop(WalkEnd::Vacant(Vacancy::ActionDiffers(id))),
            }
        }
    }

    /// The literal walk of Fig. 4 from the root.
    fn walk_literal(&self, state: &[u32], action: usize) -> WalkEnd {
        if self.clusters.is_empty() {
            return WalkEnd::Vacant(Vacancy::EmptyTree);
        }
        self.walk_literal_from(ClusterId::ROOT, state, action)
    }

    /// The literal walk of Fig. 4 from cluster `start`.
    fn walk_literal_from(&self, start: ClusterId, state: &[u32], action: usize) -> WalkEnd {
        let mut at = start;
        loop {
            match self.step(at, &self.clusters[at.index()], state, action) {
                Step::Stop(end) => return end,
                Step::Next(next) => at = next,
            }
        }
    }

    /// The walk through the index: ends where [`walk_literal`](Self::walk_literal) ends.
    fn walk_indexed(&self, state: &[u32], action: usize) -> WalkEnd {
        if self.clusters.is_empty() {
            return WalkEnd::Vacant(Vacancy::EmptyTree);
        }
        match &self.index {
            WalkIndex::Literal => self.walk_literal_from(ClusterId::ROOT, state, action),
            WalkIndex::ExactState(index) => {
                // The literal walk leaves the root chain at the first cluster whose state
                // test passes; at τₛ = 1 that is the first pure cluster of this state.
                let Some(id) = index.first_on_root_chain(state) else {
                    let tail = index
                        .root_chain_tail()
                        .expect("a non-empty tree has a root chain");
                    return WalkEnd::Vacant(Vacancy::StateDiffers(tail));
                };
                match self.after_state_passed(id, &self.clusters[id.index()], action) {
                    Step::Stop(end) => end,
                    Step::Next(next) => self.walk_literal_from(next, state, action),
                }
            }
            WalkIndex::SharedTokens(index) => {
                let mut head = ClusterId::ROOT;
                loop {
                    let chain = index.chain_of(head);
                    let Some(id) = self.first_state_match(index, chain, state) else {
                        let tail = *index
                            .chain(chain)
                            .last()
                            .expect("every chain holds at least its head");
                        return WalkEnd::Vacant(Vacancy::StateDiffers(tail));
                    };
                    match self.after_state_passed(id, &self.clusters[id.index()], action) {
                        Step::Stop(end) => return end,
                        Step::Next(next) => head = next,
                    }
                }
            }
        }
    }

    /// [`lookup`](Self::lookup) of `(state, action)` for every action `0..n_actions`, in
    /// order, passed to `emit`. Each walk with the shared-token index enters chains and asks
    /// of each "which is the first cluster whose state test passes?", a question that does
    /// not involve the action; that answer is found once per chain for the state here
    /// (`memo`, a scratch buffer) and reused by every action's walk, which is otherwise the
    /// walk of [`walk_indexed`](Self::walk_indexed). The answers are those of `lookup`.
    pub(crate) fn lookup_each_action(
        &self,
        state: &[u32],
        n_actions: usize,
        memo: &mut Vec<(u32, Option<ClusterId>)>,
        mut emit: impl FnMut(Option<Answer>),
    ) {
        let index = match &self.index {
            WalkIndex::SharedTokens(index)
                if state.len() <= MAX_FEATURES && !self.clusters.is_empty() =>
            {
                index
            }
            // Walks that take no shared-token chains share nothing: each action's own lookup.
            _ => {
                (0..n_actions).for_each(|action| emit(self.lookup(state, action)));
                return;
            }
        };
        memo.clear();
        for action in 0..n_actions {
            let mut head = ClusterId::ROOT;
            let answer = loop {
                let chain = index.chain_of(head);
                let first = match memo.iter().find(|(seen, _)| *seen == chain) {
                    Some(&(_, first)) => first,
                    None => {
                        let first = self.first_state_match(index, chain, state);
                        memo.push((chain, first));
                        first
                    }
                };
                let Some(id) = first else {
                    break None;
                };
                match self.after_state_passed(id, &self.clusters[id.index()], action) {
                    Step::Stop(WalkEnd::Found(id)) => break Some(self.answer(id)),
                    Step::Stop(WalkEnd::Vacant(_)) => break None,
                    Step::Next(next) => head = next,
                }
            };
            emit(answer);
        }
    }

    /// The first cluster of `chain` whose state test passes, visiting only clusters that
    /// share enough tokens with `state` (see [`crate::index`]).
    fn first_state_match(
        &self,
        index: &SharedTokenIndex,
        chain: u32,
        state: &[u32],
    ) -> Option<ClusterId> {
        let members = index.chain(chain);
        if state.len() > MAX_MERGED_TOKENS {
            return members
                .iter()
                .copied()
                .find(|id| self.state_passes(state, &self.clusters[id.index()]));
        }
        let min_shared = min_shared_tokens(self.config.state_threshold, state.len());
        let mut lists: [&[u32]; MAX_MERGED_TOKENS] = [&[]; MAX_MERGED_TOKENS];
        for (list, token) in lists.iter_mut().zip(state_tokens(state)) {
            *list = index.postings(chain, token);
        }
        let lists = &mut lists[..state.len()];
        loop {
            // Too few lists left to reach `min_shared` at any later position.
            if lists.iter().filter(|l| !l.is_empty()).count() < min_shared {
                return None;
            }
            let position = lists.iter().filter_map(|l| l.first()).min().copied()?;
            let mut shared = 0;
            for list in lists.iter_mut() {
                if list.first() == Some(&position) {
                    shared += 1;
                    *list = &list[1..];
                }
            }
            if shared >= min_shared {
                let id = members[position as usize];
                let cluster = &self.clusters[id.index()];
                // The bound needs no token lookups and is never below the similarity, so a
                // cluster it rules out would fail the state test.
                let may_pass = self.similarity.state_similarity_bound(
                    state.len(),
                    shared,
                    &cluster.state_centre(),
                ) >= self.config.state_threshold;
                if may_pass && self.state_passes(state, cluster) {
                    return Some(id);
                }
            }
        }
    }

    /// Stores `sample` where a walk ended.
    fn store(&mut self, end: WalkEnd, sample: Sample<'_>) -> Result<Insertion, EaTreeError> {
        let insertion = match end {
            WalkEnd::Found(id) => {
                let index = &mut self.index;
                self.clusters[id.index()].absorb(
                    sample.state,
                    sample.action,
                    sample.q1,
                    sample.q2,
                    |token: Token| index.on_new_token(id, token),
                );
                Insertion {
                    cluster: id,
                    created: false,
                }
            }
            WalkEnd::Vacant(vacancy) => {
                let id = u32::try_from(self.clusters.len())
                    .ok()
                    .filter(|&id| id < u32::MAX)
                    .map(ClusterId)
                    .ok_or(EaTreeError::TooManyClusters {
                        clusters: self.clusters.len(),
                    })?;
                let cluster = Cluster::singleton(sample.state, sample.action, sample.q1, sample.q2);
                match vacancy {
                    Vacancy::EmptyTree => {}
                    Vacancy::StateDiffers(parent) => {
                        self.clusters[parent.index()].state_differs = Some(id);
                    }
                    Vacancy::ActionDiffers(parent) => {
                        self.clusters[parent.index()].action_differs = Some(id);
                    }
                }
                self.index.on_new_cluster(id, vacancy, &cluster);
                if let WalkIndex::ExactState(index) = &mut self.index {
                    // The walk for this pair fell off here; from now on it ends at `id`.
                    index.set_pair(sample.state, sample.action, id);
                }
                self.clusters.push(cluster);
                Insertion {
                    cluster: id,
                    created: true,
                }
            }
        };
        self.samples_seen = self.samples_seen.saturating_add(1);
        Ok(insertion)
    }
}

/// What one step of the literal walk does.
enum Step {
    /// The walk ends.
    Stop(WalkEnd),
    /// The walk continues at this cluster.
    Next(ClusterId),
}

/// The index a tree with these thresholds and similarity can use.
pub(crate) fn index_kind<S: Similarity>(config: &EaTreeConfig, similarity: &S) -> IndexKind {
    let properties = similarity.properties();
    if config.state_threshold >= 1.0 && properties.state_exact_at_one {
        if config.action_threshold >= 1.0 && properties.action_exact_at_one {
            IndexKind::ExactPair
        } else {
            IndexKind::ExactState
        }
    } else if config.state_threshold > 0.0 && properties.bounded_by_shared_tokens {
        IndexKind::SharedTokens
    } else {
        IndexKind::Literal
    }
}

/// The fewest query tokens a centre must carry to possibly reach `threshold` (> 0): the
/// smallest `k ≥ 1` not ruled out by `k / d < threshold`.
fn min_shared_tokens(threshold: f64, tokens: usize) -> usize {
    // Rule a count out only when it falls short by more than any rounding in the similarity
    // could make up (relative 1e-9 against errors of order 1e-16): skipping must be safe.
    let needed = threshold * tokens as f64 * (1.0 - 1e-9);
    (1..=tokens)
        .find(|&k| {
            let k = k as f64;
            k >= needed
        })
        .unwrap_or(tokens.max(1))
}

/// Rejects samples a tree cannot store.
pub(crate) fn check_sample(sample: &Sample<'_>) -> Result<(), EaTreeError> {
    if sample.state.is_empty() {
        return Err(EaTreeError::EmptyState);
    }
    if sample.state.len() > MAX_FEATURES {
        return Err(EaTreeError::TooManyFeatures {
            len: sample.state.len(),
            max: MAX_FEATURES,
        });
    }
    for (name, value) in [("q1", sample.q1), ("q2", sample.q2)] {
        if !value.is_finite() {
            return Err(EaTreeError::NonFiniteQ { name, value });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn min_shared_tokens_is_the_ceiling_of_threshold_times_tokens() {
        assert_eq!(min_shared_tokens(1.0, 2), 2);
        assert_eq!(min_shared_tokens(0.5, 2), 1);
        assert_eq!(min_shared_tokens(0.51, 2), 2);
        assert_eq!(min_shared_tokens(1.0 / 3.0, 3), 1);
        assert_eq!(min_shared_tokens(2.0 / 3.0, 3), 2);
        assert_eq!(min_shared_tokens(1e-300, 5), 1);
        assert_eq!(min_shared_tokens(0.5, 0), 1);
    }

    fn grid_tree(config: EaTreeConfig) -> EaTree {
        let mut tree = EaTree::new(config).unwrap();
        for x in 0..5 {
            for y in 0..5 {
                for a in 0..3 {
                    let q = f64::from(x * 100 + y * 10) + a as f64;
                    tree.insert(Sample {
                        state: &[x, y],
                        action: a,
                        q1: q,
                        q2: -q,
                    })
                    .unwrap();
                }
            }
        }
        tree
    }

    #[test]
    fn incremental_index_equals_rebuilt_index() {
        for config in [
            EaTreeConfig::EXACT,
            EaTreeConfig::new(1.0, 0.4).unwrap(),
            EaTreeConfig::new(0.3, 1.0).unwrap(),
            EaTreeConfig::new(0.2, 0.5).unwrap(),
            EaTreeConfig::new(0.0, 0.5).unwrap(),
        ] {
            let tree = grid_tree(config);
            let mut rebuilt = tree.clone();
            rebuilt.rebuild_index();
            assert_eq!(tree.index, rebuilt.index, "{config:?}");
        }
    }

    #[test]
    fn index_kind_follows_thresholds() {
        assert_eq!(
            grid_tree(EaTreeConfig::EXACT).index_kind(),
            IndexKind::ExactPair
        );
        let exact_state = EaTreeConfig::new(1.0, 0.5).unwrap();
        assert_eq!(grid_tree(exact_state).index_kind(), IndexKind::ExactState);
        let shared = EaTreeConfig::new(0.5, 1.0).unwrap();
        assert_eq!(grid_tree(shared).index_kind(), IndexKind::SharedTokens);
        let literal = EaTreeConfig::new(0.0, 1.0).unwrap();
        assert_eq!(grid_tree(literal).index_kind(), IndexKind::Literal);
    }

    #[test]
    fn index_bytes_count_every_map() {
        let pair = grid_tree(EaTreeConfig::EXACT).stats();
        let state = grid_tree(EaTreeConfig::new(1.0, 0.5).unwrap()).stats();
        assert_eq!(pair.cluster_bytes, state.cluster_bytes);
        // The (s, a) map holds 75 inline keys of 36 bytes plus a 4-byte id.
        assert!(
            pair.index_bytes >= state.index_bytes + 75 * 40,
            "{pair:?} {state:?}"
        );
        assert_eq!(
            grid_tree(EaTreeConfig::new(0.0, 1.0).unwrap())
                .stats()
                .index_bytes,
            0
        );
    }

    #[test]
    fn exact_tree_root_chain_is_one_cluster_per_state() {
        let tree = grid_tree(EaTreeConfig::EXACT);
        assert_eq!(tree.len(), 75);
        // The literal walk for the last state passes every other state first.
        assert_eq!(tree.literal_walk_length(&[4, 4], 0), 25);
        assert_eq!(tree.literal_walk_length(&[4, 4], 2), 27);
    }
}
