//! Similarity between a sample and a cluster centre, and the default: weighted Jaccard.

use crate::cluster::{ActionCentre, StateCentre};
use crate::encoding::count_ratio;

/// How similar a sample's state and action are to a cluster's centre.
///
/// Both functions should return a value in `[0, 1]`; the tree compares it with its
/// thresholds as `similarity >= τ`, so a `NaN` simply never matches (and never panics).
pub trait Similarity {
    /// A stable name saved with the tree; loading refuses a file written under another name.
    fn name(&self) -> &str;

    /// Similarity of the token set of `state` (see [`crate::encoding`]) to a state centre.
    fn state_similarity(&self, state: &[u32], centre: &StateCentre<'_>) -> f64;

    /// Similarity of the one-token set `{action}` to an action centre.
    fn action_similarity(&self, action: usize, centre: &ActionCentre<'_>) -> f64;

    /// An upper bound of [`state_similarity`](Similarity::state_similarity)`(state, centre)`
    /// for a `state` of `state_len` features of which the centre carries exactly
    /// `shared_tokens`, found without looking the tokens up. The shared-token index skips a
    /// cluster whose bound is below `τₛ` without computing its similarity. The default,
    /// infinity, skips nothing. A bound below the similarity makes the indexed walk disagree
    /// with the literal one (it never makes it panic).
    fn state_similarity_bound(
        &self,
        state_len: usize,
        shared_tokens: usize,
        centre: &StateCentre<'_>,
    ) -> f64 {
        let _ = (state_len, shared_tokens, centre);
        f64::INFINITY
    }

    /// What [`state_similarity`](Similarity::state_similarity) guarantees, so the indexed
    /// lookup may skip clusters that cannot match. The default promises nothing, and the
    /// tree then always takes the literal walk. A promise that does not hold makes the
    /// indexed lookup disagree with the literal walk (it never makes it panic).
    fn properties(&self) -> SimilarityProperties {
        SimilarityProperties::NONE
    }
}

/// Guarantees a [`Similarity`] may give about its state similarity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SimilarityProperties {
    /// `state_similarity(s, c) >= 1` exactly when every member of `c` had the state `s`.
    /// Lets the tree find, at `τₛ = 1`, a state's cluster through a hash map.
    pub state_exact_at_one: bool,
    /// `action_similarity(a, c) >= 1` exactly when every member of `c` took the action `a`.
    /// With `state_exact_at_one`, lets the tree answer at `τₛ = τₐ = 1` through a hash map
    /// from `(s, a)` to its cluster.
    pub action_exact_at_one: bool,
    /// `state_similarity(s, c) <= k / |s|`, where `k` counts the tokens of `s` carried by at
    /// least one member of `c` (and `<= 0` for an empty `s`). Lets the tree skip, below
    /// `τₛ = 1`, the clusters that share too few tokens with the query.
    pub bounded_by_shared_tokens: bool,
}

impl SimilarityProperties {
    /// No guarantee: lookups take the literal walk.
    pub const NONE: Self = Self {
        state_exact_at_one: false,
        action_exact_at_one: false,
        bounded_by_shared_tokens: false,
    };
}

/// Weighted Jaccard similarity `Σ min(x_t, c_t) / Σ max(x_t, c_t)` between a sample's
/// indicator vector `x` and a centre `c` (the mean of its members' indicator vectors).
///
/// On 0/1 vectors (a centre with one member) it is the set Jaccard `|A ∩ B| / |A ∪ B|`
/// ([`set_jaccard`](crate::set_jaccard)). With `n` members, `d` query tokens, `m` the summed
/// member counts of the query's tokens and `T` the summed counts of all centre tokens,
/// it is `m / (n·d + T − m)`, computed from integers, so a centre equal to the query's
/// indicator gives exactly 1. For an action `a` it is `n_a / (2n − n_a)`.
/// Two empty sets have similarity 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WeightedJaccard;

impl Similarity for WeightedJaccard {
    fn name(&self) -> &str {
        "weighted-jaccard"
    }

    fn state_similarity(&self, state: &[u32], centre: &StateCentre<'_>) -> f64 {
        let shared = u128::from(centre.overlap(state).count);
        let members = u128::from(centre.members());
        let query_mass = members * state.len() as u128;
        // Σmax·n = n·d + T − m ≥ n·d, because m ≤ T.
        let union = (query_mass + u128::from(centre.total_count())).saturating_sub(shared);
        if union == 0 {
            1.0
        } else {
            count_ratio(shared, union)
        }
    }

    fn state_similarity_bound(
        &self,
        state_len: usize,
        shared_tokens: usize,
        centre: &StateCentre<'_>,
    ) -> f64 {
        // The summed counts m of the query's tokens are at most n·k (each of the k carried
        // tokens is carried by at most n members) and at most T. The similarity
        // m / (n·d + T − m) grows with m, and so does its rounded value (converting and
        // dividing round monotonically), so m's largest possible value bounds it exactly.
        let members = u128::from(centre.members());
        let total = u128::from(centre.total_count());
        let most = (members * shared_tokens as u128).min(total);
        let union = (members * state_len as u128 + total).saturating_sub(most);
        if union == 0 {
            1.0
        } else {
            count_ratio(most, union)
        }
    }

    fn action_similarity(&self, action: usize, centre: &ActionCentre<'_>) -> f64 {
        let took = u128::from(centre.action_count(action));
        let union = (2 * u128::from(centre.members())).saturating_sub(took);
        if union == 0 {
            1.0
        } else {
            count_ratio(took, union)
        }
    }

    fn properties(&self) -> SimilarityProperties {
        // State exact at one: 2m = n·d + T with m ≤ n·d and m ≤ T, so m = n·d = T: all n
        // members carry all d query tokens and nothing else. Action exact at one:
        // n_a = 2n − n_a, so n_a = n. Bounded: m ≤ n·k and the denominator is ≥ n·d, so
        // the similarity is ≤ k/d (and 0 for d = 0 against a non-empty centre).
        SimilarityProperties {
            state_exact_at_one: true,
            action_exact_at_one: true,
            bounded_by_shared_tokens: true,
        }
    }
}
