//! The draws of the structured layouts: 32-bit words of a seeded `ChaCha8Rng`, turned into
//! indices by Lemire's multiply-and-reject method.
//!
//! Every draw reads whole `u32` words (`next_u32`) and does integer arithmetic only, so a
//! layout is the same on every platform; and the index of a draw is computed here rather
//! than by `rand`'s range sampling, whose algorithm may change between versions.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A seeded stream of uniform indices.
pub(crate) struct Draws {
    rng: ChaCha8Rng,
}

impl Draws {
    /// The stream of `ChaCha8Rng::seed_from_u64(seed)`.
    pub(crate) fn seeded(seed: u64) -> Self {
        Self {
            rng: ChaCha8Rng::seed_from_u64(seed),
        }
    }

    /// An index uniform on `0..k` (`k ≥ 1`): a word `w` is kept when
    /// `(w·k) mod 2³² ≥ (2³² − k) mod k` and maps to `⌊w·k / 2³²⌋` (Lemire, *Fast random
    /// integer generation in an interval*, 2019); otherwise the next word is tried. Exactly
    /// uniform.
    pub(crate) fn below(&mut self, k: u32) -> u32 {
        debug_assert!(k >= 1, "an index below 0 does not exist");
        let bound = u64::from(k);
        let mut product = u64::from(self.rng.next_u32()) * bound;
        if (product as u32) < k {
            let threshold = k.wrapping_neg() % k;
            while (product as u32) < threshold {
                product = u64::from(self.rng.next_u32()) * bound;
            }
        }
        (product >> 32) as u32
    }

    /// Moves `count` entries of `pool`, chosen uniformly without replacement, to its front
    /// (a partial Fisher–Yates shuffle: for `i` in `0..count`, swap entry `i` with entry
    /// `i + below(len − i)`). `count ≤ pool.len() ≤ u32::MAX`.
    pub(crate) fn choose_front<T>(&mut self, pool: &mut [T], count: usize) {
        debug_assert!(count <= pool.len());
        let len = pool.len();
        for i in 0..count {
            // `len − i ≤ len ≤ u32::MAX` (the pools are tile lists of at most MAX_LAYOUT_TILES).
            let j = i + self.below((len - i) as u32) as usize;
            pool.swap(i, j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn below_is_lemire_on_the_generators_words() {
        // k = 3·2³⁰: the threshold (2³² − k) mod k is 2³⁰, so about a quarter of the words
        // are rejected.
        let k = 3 << 30;
        let mut words = ChaCha8Rng::seed_from_u64(4);
        let mut draws = Draws::seeded(4);
        for _ in 0..1000 {
            let want = loop {
                let product = u64::from(words.next_u32()) * u64::from(k);
                if (product as u32) >= 1 << 30 {
                    break (product >> 32) as u32;
                }
            };
            assert_eq!(draws.below(k), want);
        }
    }

    #[test]
    fn below_covers_its_range_evenly() {
        let mut draws = Draws::seeded(1);
        let mut seen = [0_u32; 5];
        for _ in 0..50_000 {
            seen[draws.below(5) as usize] += 1;
        }
        assert!(
            seen.iter().all(|&c| (9_500..10_500).contains(&c)),
            "{seen:?}"
        );
        assert_eq!(draws.below(1), 0);
    }

    #[test]
    fn choose_front_picks_distinct_entries() {
        let mut draws = Draws::seeded(7);
        let mut pool: Vec<u32> = (0..20).collect();
        draws.choose_front(&mut pool, 8);
        let mut front = pool[..8].to_vec();
        front.sort_unstable();
        front.dedup();
        assert_eq!(front.len(), 8);
        let mut all = pool.clone();
        all.sort_unstable();
        assert_eq!(all, (0..20).collect::<Vec<_>>());
    }
}
