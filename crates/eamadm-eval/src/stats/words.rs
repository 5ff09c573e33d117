//! The 32-bit words of a seeded `ChaCha8` stream, read in blocks, and Lemire's uniform index
//! drawn from them (see [the module docs](super), "Random draws").

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How many words are read from the generator at a time.
const BLOCK: usize = 64;

/// The words `ChaCha8Rng::seed_from_u64(seed)` gives by `next_u32`, the same words in the same
/// order, read [`BLOCK`] at a time. The generator keeps its position inside its own buffer
/// (`rand_core`'s `BlockRng` stores it in the buffer's first word), so a word drawn one at a
/// time waits for the previous draw's store of that position; here the position is a field of
/// its own, and a draw is a load and an increment. Any words read ahead and not used are
/// dropped with the stream, which no one else reads.
pub(crate) struct Words {
    rng: ChaCha8Rng,
    block: [u32; BLOCK],
    /// The next word of `block` to give; [`BLOCK`] when it is used up.
    next: usize,
}

impl Words {
    /// The stream of `ChaCha8Rng::seed_from_u64(seed)`.
    pub(crate) fn seed_from_u64(seed: u64) -> Self {
        Self {
            rng: ChaCha8Rng::seed_from_u64(seed),
            block: [0; BLOCK],
            next: BLOCK,
        }
    }

    /// The next word.
    #[inline]
    pub(crate) fn next_u32(&mut self) -> u32 {
        if self.next == BLOCK {
            self.refill();
        }
        let word = self.block[self.next % BLOCK];
        self.next += 1;
        word
    }

    /// Reads the next [`BLOCK`] words: `fill_bytes` gives whole words in stream order, each
    /// as its 4 little-endian bytes.
    #[cold]
    fn refill(&mut self) {
        let mut bytes = [0_u8; 4 * BLOCK];
        self.rng.fill_bytes(&mut bytes);
        for (word, bytes) in self.block.iter_mut().zip(bytes.as_chunks::<4>().0) {
            *word = u32::from_le_bytes(*bytes);
        }
        self.next = 0;
    }

    /// An index uniform on `0..k` (`k ≥ 1`) by Lemire's multiply-and-reject method: exactly
    /// uniform, one word per draw except on the rare rejection.
    #[inline]
    pub(crate) fn uniform_below(&mut self, k: u32) -> u32 {
        let bound = u64::from(k);
        let mut product = u64::from(self.next_u32()) * bound;
        if (product as u32) < k {
            let threshold = k.wrapping_neg() % k;
            while (product as u32) < threshold {
                product = u64::from(self.next_u32()) * bound;
            }
        }
        (product >> 32) as u32
    }

    /// `count` indices uniform on `0..k` (`k ≥ 1`), each handed to `take`: the indices and
    /// the words used are those of `count` calls of [`uniform_below`](Self::uniform_below),
    /// but the block is walked without a check per word for its end. Lemire's method keeps a
    /// word `w` exactly when `(w k) mod 2³² ≥ (2³² − k) mod k`; that bound is below `k`, so
    /// it is computed only for the rare word with `(w k) mod 2³² < k`.
    #[inline]
    pub(crate) fn uniform_below_each(&mut self, k: u32, count: usize, mut take: impl FnMut(usize)) {
        let bound = u64::from(k);
        let mut remaining = count;
        while remaining > 0 {
            if self.next == BLOCK {
                self.refill();
            }
            // At most `remaining` words are kept from the next `walked` ones, so none of them
            // is read beyond need; a rejected word only leaves one more to draw.
            let walked = remaining.min(BLOCK - self.next);
            let mut rejected = 0;
            for &word in &self.block[self.next..self.next + walked] {
                let product = u64::from(word) * bound;
                let low = product as u32;
                if low < k && low < k.wrapping_neg() % k {
                    rejected += 1;
                } else {
                    take((product >> 32) as usize);
                }
            }
            self.next += walked;
            remaining -= walked - rejected;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_words_are_the_generators_words() {
        for seed in [0, 1, 12_345] {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut words = Words::seed_from_u64(seed);
            for _ in 0..5 * BLOCK + 7 {
                assert_eq!(words.next_u32(), rng.next_u32());
            }
        }
    }

    #[test]
    fn lemire_draw_covers_the_range_uniformly() {
        let mut words = Words::seed_from_u64(1);
        let mut seen = [0_u32; 7];
        for _ in 0..70_000 {
            seen[words.uniform_below(7) as usize] += 1;
        }
        assert!(
            seen.iter().all(|&c| (9_500..10_500).contains(&c)),
            "{seen:?}"
        );
        assert_eq!(words.uniform_below(1), 0);
    }

    #[test]
    fn drawing_many_equals_drawing_one_at_a_time() {
        for (k, count) in [(1, 5), (7, 200), (20, 20), (1000, 1000), (3 << 30, 300)] {
            let mut one = Words::seed_from_u64(u64::from(k));
            let mut many = Words::seed_from_u64(u64::from(k));
            for _ in 0..3 {
                let want: Vec<usize> = (0..count).map(|_| one.uniform_below(k) as usize).collect();
                let mut got = Vec::new();
                many.uniform_below_each(k, count, |i| got.push(i));
                assert_eq!(got, want, "k = {k}");
            }
            // And the stream goes on from the same word.
            assert_eq!(many.next_u32(), one.next_u32());
        }
    }

    #[test]
    fn lemire_draw_rejects_as_defined() {
        // k = 3·2³⁰: threshold (2³² − k) mod k = 2³⁰, so about a quarter of the words are
        // rejected; the kept ones map as ⌊w k / 2³²⌋.
        let k = 3 << 30;
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut words = Words::seed_from_u64(9);
        for _ in 0..1000 {
            let want = loop {
                let product = u64::from(rng.next_u32()) * u64::from(k);
                if (product as u32) >= 1 << 30 {
                    break (product >> 32) as u32;
                }
            };
            assert_eq!(words.uniform_below(k), want);
        }
    }
}
