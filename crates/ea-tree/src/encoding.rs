//! How a sample's state and action become token sets (the input of Jaccard similarity).
//!
//! A discrete state is given as its feature bins, one `u32` per feature: `[x, y]` for a
//! maze cell, `[distance_bin, image_bin, angle_bin]` for the robot. Its token set is
//! `{ (i, state[i]) : i = 0 .. state.len() }`, so two states share a token exactly when
//! they agree on one feature. Pairing the bin with its feature index keeps "x = 3" and
//! "y = 3" apart. An action `a` is the one-token set `{ a }`.
//!
//! As indicator vectors over all possible tokens, a state has weight 1 on each of its
//! tokens and 0 elsewhere; a cluster centre is the mean of its members' indicator
//! vectors, so the weight of a token is the fraction of members that carry it.

use serde::{Deserialize, Serialize};

/// Longest state (in features) a tree accepts: feature indices are stored as `u32`.
pub const MAX_FEATURES: usize = u32::MAX as usize;

/// One state token: feature `feature` is in bin `bin`.
///
/// Tokens order by feature, then bin, which is the order [`state_tokens`] yields them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Token {
    /// Index of the feature in the state's feature list.
    pub feature: u32,
    /// The feature's discrete bin.
    pub bin: u32,
}

/// The token set of a state, in ascending token order (no allocation).
///
/// Features beyond [`MAX_FEATURES`] cannot be encoded and are not yielded; trees reject such
/// states on insert.
pub fn state_tokens(state: &[u32]) -> impl Iterator<Item = Token> + '_ {
    (0..=u32::MAX)
        .zip(state)
        .map(|(feature, &bin)| Token { feature, bin })
}

/// Set Jaccard similarity `|A ∩ B| / |A ∪ B|` of two token sets given in ascending order
/// without repeats (as [`state_tokens`] yields them). Two empty sets are identical: 1.
///
/// This is the similarity between two *samples*; against a cluster centre the tree uses its
/// weighted form (see [`WeightedJaccard`](crate::WeightedJaccard)), which equals this one
/// when the centre holds a single member.
pub fn set_jaccard(a: &[Token], b: &[Token]) -> f64 {
    let (mut i, mut j, mut shared) = (0, 0, 0_usize);
    while let (Some(x), Some(y)) = (a.get(i), b.get(j)) {
        match x.cmp(y) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => {
                shared += 1;
                i += 1;
                j += 1;
            }
        }
    }
    let union = a.len() + b.len() - shared;
    if union == 0 {
        1.0
    } else {
        count_ratio(shared as u128, union as u128)
    }
}

/// `numerator / denominator` of two counts as `f64` (exact while both are below 2^53).
#[inline]
pub(crate) fn count_ratio(numerator: u128, denominator: u128) -> f64 {
    // Counts stay far below 2^53 in any real tree, so the conversions are exact and
    // equal counts give exactly 1.0 (what τ = 1 relies on).
    match (u64::try_from(numerator), u64::try_from(denominator)) {
        // `u128 as f64` is a software routine (`__floattidf`), the tree build's hottest
        // call; `u64 as f64` is one instruction. Both round the same integer to the nearest
        // `f64` (ties to even), so the result is the same bit for bit.
        (Ok(numerator), Ok(denominator)) => numerator as f64 / denominator as f64,
        _ => count_ratio_wide(numerator, denominator),
    }
}

/// [`count_ratio`] for counts of any size, converted from `u128` directly.
fn count_ratio_wide(numerator: u128, denominator: u128) -> f64 {
    numerator as f64 / denominator as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_pair_each_bin_with_its_feature() {
        let tokens: Vec<Token> = state_tokens(&[3, 3, 7]).collect();
        assert_eq!(
            tokens,
            vec![
                Token { feature: 0, bin: 3 },
                Token { feature: 1, bin: 3 },
                Token { feature: 2, bin: 7 },
            ]
        );
    }

    proptest::proptest! {
        /// The `u64` fast path of `count_ratio` equals the `u128` conversion bit for bit,
        /// near 2^53 and 2^64 too (where rounding happens), and beyond `u64` it is that path.
        #[test]
        fn count_ratio_equals_the_wide_conversion(
            numerator in proptest::prop_oneof![
                0..1_u128 << 20,
                (1_u128 << 53) - 4..(1_u128 << 53) + 4_096,
                (1_u128 << 64) - 4_096..(1_u128 << 64) + 4_096,
                proptest::num::u128::ANY,
            ],
            denominator in proptest::prop_oneof![
                1..1_u128 << 20,
                (1_u128 << 63)..(1_u128 << 63) + 4_096,
                (1_u128 << 64) - 4_096..(1_u128 << 64) + 4_096,
                1..=u128::MAX,
            ],
        ) {
            proptest::prop_assert_eq!(
                count_ratio(numerator, denominator).to_bits(),
                count_ratio_wide(numerator, denominator).to_bits()
            );
        }
    }

    #[test]
    fn set_jaccard_counts_shared_over_union() {
        let a: Vec<Token> = state_tokens(&[1, 2]).collect();
        let b: Vec<Token> = state_tokens(&[1, 5]).collect();
        assert!((set_jaccard(&a, &b) - 1.0 / 3.0).abs() < 1e-15);
        assert!((set_jaccard(&a, &a) - 1.0).abs() < f64::EPSILON);
        assert!(set_jaccard(&a, &[]).abs() < f64::EPSILON);
        assert!((set_jaccard(&[], &[]) - 1.0).abs() < f64::EPSILON);
    }
}
