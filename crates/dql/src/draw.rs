//! Biased coins from one `u32` draw each.
//!
//! Every step flips Bernoulli coins (explore? which estimator to update?).
//! Taking each from a single `u32` rather than an `f64` (a `u64`) halves the
//! generator output a step consumes (refilling `ChaCha8` was 16 % of a step);
//! the cost is a resolution of 2⁻³², far below anything a learning curve can
//! see. (Small index draws need nothing of ours: `rand` already samples a
//! `usize` range that fits in `u32` from one `u32`.)

use rand::Rng;

/// `2³²`: the number of equally likely values of one `u32` draw.
const TWO_POW_32: f64 = 4_294_967_296.0;

/// A biased coin that comes up heads with probability `p`, flipped with one
/// `u32` draw.
///
/// Heads when the draw `u` satisfies `u < ⌈p · 2³²⌉`, so the probability of
/// heads is `⌈p · 2³²⌉ / 2³²`: exact for `p = 0`, `p = 1` and every multiple of
/// 2⁻³² (0.5 included), and never more than 2⁻³² above `p` otherwise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Coin {
    /// Heads iff `u64::from(u) < threshold`; in `0..=2³²`.
    threshold: u64,
}

impl Coin {
    /// A coin with heads probability `p`, clamped to [0, 1] (NaN gives 0).
    #[must_use]
    pub fn new(p: f64) -> Self {
        let scaled = (p.clamp(0.0, 1.0) * TWO_POW_32).ceil();
        // `scaled` is an integer in [0, 2³²] (NaN clamps to NaN, and NaN as u64 is 0).
        let threshold = scaled as u64;
        Self { threshold }
    }

    /// Flips the coin: `true` with the coin's probability. Draws one `u32`.
    #[inline(always)]
    pub fn flip<R: Rng + ?Sized>(&self, rng: &mut R) -> bool {
        u64::from(rng.next_u32()) < self.threshold
    }
}
