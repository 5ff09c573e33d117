//! A cluster (one tree node): its centre, kept as exact member counts, and its two children.
//!
//! The centre of Sec. IV.B is the mean of the members' state indicator vectors, action
//! indicator vectors, Q1 and Q2. For the two indicator vectors we store *how many members
//! carry each token* plus the member count: the mean weight of a token is `count / members`,
//! computed on demand. Counts are exact, never drift with rounding, survive a save/load
//! bit for bit, and make "the centre equals this sample's indicator vector" (what τ = 1
//! asks) an exact integer comparison. Q1 and Q2 are running means.

use serde::{Deserialize, Serialize};

use crate::encoding::{Token, count_ratio, state_tokens};

/// Index of a cluster in its tree (clusters are numbered in creation order from 0, the root).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ClusterId(pub(crate) u32);

impl ClusterId {
    /// The root cluster (the first sample inserted).
    pub const ROOT: Self = Self(0);

    /// The cluster's position in creation order.
    #[must_use]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl std::fmt::Display for ClusterId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{}", self.0)
    }
}

/// How many members of a cluster carry a state token.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TokenCount {
    pub(crate) token: Token,
    pub(crate) count: u64,
}

/// How many members of a cluster took an action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ActionCount {
    pub(crate) action: usize,
    pub(crate) count: u64,
}

/// One node of the tree.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Cluster {
    /// Number of members (> 0).
    pub(crate) count: u64,
    /// Member counts per state token, ascending by token, every count in `1..=count`.
    pub(crate) state_tokens: Vec<TokenCount>,
    /// Sum of `state_tokens` counts (the centre's total weight times `count`).
    pub(crate) state_total: u64,
    /// Member counts per action, ascending by action, summing to `count`.
    pub(crate) actions: Vec<ActionCount>,
    /// Mean Q1 of the members.
    pub(crate) q1: f64,
    /// Mean Q2 of the members.
    pub(crate) q2: f64,
    /// Where samples whose *state* is not similar go (yellow in Fig. 4).
    pub(crate) state_differs: Option<ClusterId>,
    /// Where samples with a similar state but a dissimilar *action* go (red in Fig. 4).
    pub(crate) action_differs: Option<ClusterId>,
}

impl Cluster {
    /// A cluster holding the single sample `(state, action, q1, q2)`.
    pub(crate) fn singleton(state: &[u32], action: usize, q1: f64, q2: f64) -> Self {
        let state_tokens: Vec<TokenCount> = state_tokens(state)
            .map(|token| TokenCount { token, count: 1 })
            .collect();
        Self {
            count: 1,
            state_total: state_tokens.len() as u64,
            state_tokens,
            actions: vec![ActionCount { action, count: 1 }],
            q1,
            q2,
            state_differs: None,
            action_differs: None,
        }
    }

    /// Adds one member; calls `on_new_token` for every state token the centre did not carry.
    pub(crate) fn absorb(
        &mut self,
        state: &[u32],
        action: usize,
        q1: f64,
        q2: f64,
        mut on_new_token: impl FnMut(Token),
    ) {
        self.count = self.count.saturating_add(1);
        for token in state_tokens(state) {
            match self.state_tokens.binary_search_by(|t| t.token.cmp(&token)) {
                Ok(at) => {
                    let held = &mut self.state_tokens[at].count;
                    *held = held.saturating_add(1);
                }
                Err(at) => {
                    self.state_tokens.insert(at, TokenCount { token, count: 1 });
                    on_new_token(token);
                }
            }
            self.state_total = self.state_total.saturating_add(1);
        }
        match self.actions.binary_search_by(|a| a.action.cmp(&action)) {
            Ok(at) => {
                let took = &mut self.actions[at].count;
                *took = took.saturating_add(1);
            }
            Err(at) => self.actions.insert(at, ActionCount { action, count: 1 }),
        }
        self.q1 = running_mean(self.q1, q1, self.count);
        self.q2 = running_mean(self.q2, q2, self.count);
    }

    /// Read-only view of the state centre.
    pub(crate) fn state_centre(&self) -> StateCentre<'_> {
        StateCentre {
            members: self.count,
            tokens: &self.state_tokens,
            total: self.state_total,
        }
    }

    /// Read-only view of the action centre.
    pub(crate) fn action_centre(&self) -> ActionCentre<'_> {
        ActionCentre {
            members: self.count,
            actions: &self.actions,
        }
    }

    /// The state whose indicator vector this centre is, if every member had the same state
    /// `[b0, b1, …]` (features numbered 0, 1, … without gaps); `None` for a mixed centre.
    pub(crate) fn pure_state(&self) -> Option<impl Iterator<Item = u32> + '_> {
        let pure = self.state_total == self.count.saturating_mul(self.state_tokens.len() as u64)
            && self
                .state_tokens
                .iter()
                .zip(0_u32..)
                .all(|(t, feature)| t.count == self.count && t.token.feature == feature);
        pure.then(|| self.state_tokens.iter().map(|t| t.token.bin))
    }

    /// Heap bytes owned by this cluster (its two centre vectors, by capacity).
    pub(crate) fn heap_bytes(&self) -> usize {
        self.state_tokens.capacity() * size_of::<TokenCount>()
            + self.actions.capacity() * size_of::<ActionCount>()
    }
}

/// Mean of `n` values given the mean of the first `n - 1` and the `n`-th value `x`.
///
/// Finite inputs give a finite result: the step is formed from halves that cannot overflow
/// and the result is clamped to lie between the old mean and `x`, where the true mean is.
pub(crate) fn running_mean(mean: f64, x: f64, n: u64) -> f64 {
    if n <= 1 {
        return x;
    }
    let n = n as f64;
    let step = x / n - mean / n;
    (mean + step).clamp(mean.min(x), mean.max(x))
}

/// The state half of a cluster centre: how many of its members carry each state token.
///
/// The centre's weight for a token is `token_count / members`, the fraction of members
/// whose state contains it (the mean of their indicator vectors).
#[derive(Debug, Clone, Copy)]
pub struct StateCentre<'a> {
    members: u64,
    tokens: &'a [TokenCount],
    total: u64,
}

impl<'a> StateCentre<'a> {
    /// Number of members of the cluster.
    #[must_use]
    pub fn members(&self) -> u64 {
        self.members
    }

    /// How many members carry `token`.
    #[must_use]
    pub fn token_count(&self, token: Token) -> u64 {
        self.tokens
            .binary_search_by(|t| t.token.cmp(&token))
            .map_or(0, |at| self.tokens[at].count)
    }

    /// The centre's weight for `token`: the fraction of members that carry it, in `[0, 1]`.
    #[must_use]
    pub fn weight(&self, token: Token) -> f64 {
        count_ratio(self.token_count(token).into(), self.members.into())
    }

    /// Sum of all token counts (members × mean number of features per member).
    #[must_use]
    pub fn total_count(&self) -> u64 {
        self.total
    }

    /// Number of distinct tokens the centre carries.
    #[must_use]
    pub fn distinct_tokens(&self) -> usize {
        self.tokens.len()
    }

    /// Every token the centre carries with its member count, in ascending token order.
    pub fn tokens(&self) -> impl Iterator<Item = (Token, u64)> + 'a {
        self.tokens.iter().map(|t| (t.token, t.count))
    }

    /// Overlap of the centre with the token set of `state`: the summed member counts of
    /// the state's tokens, and how many of its tokens the centre carries at all.
    #[must_use]
    pub fn overlap(&self, state: &[u32]) -> StateOverlap {
        let mut rest = self.tokens;
        let mut overlap = StateOverlap {
            count: 0,
            tokens: 0,
        };
        for token in state_tokens(state) {
            // Query tokens ascend, so each search continues where the last one stopped.
            let at = rest.partition_point(|t| t.token < token);
            match rest.get(at) {
                Some(t) if t.token == token => {
                    overlap.count += t.count;
                    overlap.tokens += 1;
                    rest = &rest[at + 1..];
                }
                _ => rest = &rest[at..],
            }
        }
        overlap
    }
}

/// How a state's token set overlaps a state centre (see [`StateCentre::overlap`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StateOverlap {
    /// Σ over the state's tokens of the number of members carrying that token.
    pub count: u64,
    /// Number of the state's tokens that at least one member carries.
    pub tokens: usize,
}

/// The action half of a cluster centre: how many of its members took each action.
#[derive(Debug, Clone, Copy)]
pub struct ActionCentre<'a> {
    members: u64,
    actions: &'a [ActionCount],
}

impl<'a> ActionCentre<'a> {
    /// Number of members of the cluster.
    #[must_use]
    pub fn members(&self) -> u64 {
        self.members
    }

    /// How many members took `action`.
    #[must_use]
    pub fn action_count(&self, action: usize) -> u64 {
        self.actions
            .binary_search_by(|a| a.action.cmp(&action))
            .map_or(0, |at| self.actions[at].count)
    }

    /// The centre's weight for `action`: the fraction of members that took it.
    #[must_use]
    pub fn weight(&self, action: usize) -> f64 {
        count_ratio(self.action_count(action).into(), self.members.into())
    }

    /// Every action taken by a member with its count, in ascending action order.
    pub fn actions(&self) -> impl Iterator<Item = (usize, u64)> + 'a {
        self.actions.iter().map(|a| (a.action, a.count))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_mean_is_the_mean_and_stays_finite() {
        let mut mean = 0.0;
        for (n, x) in (1..).zip([1.0, 2.0, 6.0]) {
            mean = running_mean(mean, x, n);
        }
        assert!((mean - 3.0).abs() < 1e-12);
        let huge = running_mean(f64::MAX, -f64::MAX, 2);
        assert!(huge.is_finite() && huge.abs() < 1e300);
        let top = running_mean(f64::MAX, f64::MAX, 7);
        assert!(top.is_finite());
    }

    #[test]
    fn absorb_counts_tokens_and_reports_new_ones() {
        let mut cluster = Cluster::singleton(&[1, 2], 0, 1.0, 2.0);
        let mut new = Vec::new();
        cluster.absorb(&[1, 3], 2, 3.0, 4.0, |t| new.push(t));
        assert_eq!(new, vec![Token { feature: 1, bin: 3 }]);
        let centre = cluster.state_centre();
        assert_eq!(centre.members(), 2);
        assert_eq!(centre.token_count(Token { feature: 0, bin: 1 }), 2);
        assert_eq!(centre.total_count(), 4);
        assert!((centre.weight(Token { feature: 1, bin: 2 }) - 0.5).abs() < f64::EPSILON);
        assert_eq!(
            centre.overlap(&[1, 3]),
            StateOverlap {
                count: 3,
                tokens: 2
            }
        );
        assert_eq!(cluster.action_centre().action_count(2), 1);
        assert!((cluster.q1 - 2.0).abs() < f64::EPSILON);
        assert!(cluster.pure_state().is_none());
        let pure = Cluster::singleton(&[4, 5], 1, 0.0, 0.0);
        assert_eq!(
            pure.pure_state().map(Iterator::collect::<Vec<_>>),
            Some(vec![4, 5])
        );
    }
}
