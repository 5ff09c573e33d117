//! OWA aggregation, natural visibility graphs and the visibility-weighted multi-attribute
//! decision of the EA-MADM paper (*An Experience Aggregative Reinforcement Learning With
//! Multi-Attribute Decision-Making for Obstacle Avoidance of Wheeled Mobile Robot*,
//! Sec. II.B and IV.C, Eq. 3 and 13–16).
//!
//! # What is here
//!
//! * **OWA** (Yager 1988, the paper's Eq. 3): [`owa`], [`owa_sorted`], [`orness`],
//!   [`andness`], [`validate_weights`] and the validated weight vector [`OwaWeights`] with its
//!   generators: uniform, caller-given, maximum-entropy for a given orness, visibility-based.
//! * **Natural visibility graph** (Lacasa et al., PNAS 2008; the paper's Eq. 14, garbled by
//!   OCR): [`is_visible`] and [`natural_visibility_graph`].
//! * **Visibility weights** (Eq. 15) with a selectable [`Support`]:
//!   [`visibility_weights_into`].
//! * **The MADM decision** (Eq. 13, 16): [`MadmDecider`] evaluates every row of a decision
//!   matrix (actions × attributes) and picks the best row, ties broken by a caller-supplied RNG,
//!   without allocating after its first call. [`Weighting`] (a serde config value) selects the
//!   weights it applies.
//! * **Per-attribute normalisation** (not in the paper; standard MADM practice): [`Normalisation`]
//!   scales each column of a decision matrix onto `[0, 1]` (min–max) or to its standard score
//!   (z-score, [`ColumnSummary`]) before aggregation, a repair the caller opts into.
//!
//! # The paper's procedure, and what we changed
//!
//! For each action (row) the attributes are sorted in descending order (Step 1); sorted
//! positions that see each other in the natural visibility graph support each other (Step 2);
//! each position's weight is its share of the total support (Step 3, Eq. 15); the row's value is
//! the weighted sum of its sorted attributes (Step 4, Eq. 16). Degeneracies and repairs:
//!
//! * **Eq. 15's support `S(x, y) = x·y / |x − y|²` is degenerate:** it divides by zero on ties
//!   (ties are adjacent after sorting, hence always visible), is negative for values of opposite
//!   sign and is unbounded. The default [`Support::Paper`] is
//!   `max(0, x·y) / (|x − y|² + ε)` with `ε` = [`DEFAULT_EPSILON`] (`1e-9`); `ε = 0` keeps the
//!   literal form. [`Support::Distance`] (`1 − |x − y| / range`) is a bounded alternative.
//!   With a small `ε` an exact tie between two non-zero attributes gets a support of about
//!   `x²/ε` and dominates its row's weights (the limit the literal formula points to).
//! * **Fallback:** when a row's total support is 0 or not finite (no supporting pair, the
//!   literal `ε = 0` on a tie, or products overflowing for attributes beyond about `1e154`),
//!   its weights are uniform. Weights are therefore always valid (in `[0, 1]`, summing to 1).
//! * **Eq. 16 prints `ω_j`** (the action index); it must be `ω_k` (the sorted position).
//! * **Visibility is strict:** a point exactly on a line of sight blocks it, so ties and
//!   straight-line runs connect only neighbours.
//! * **Never NaN:** every aggregate is clamped to `[min, max]` of its values, so finite input
//!   gives a finite result; NaN or infinite input is a typed [`MadmError`].
//!
//! # Example
//!
//! The worked example of the project's paper notes: attributes `(0.9, 0.7, 0.6, 0.3)` see each
//! other along the edges `(0,1), (0,2), (1,2), (2,3)`, receive supports
//! `(21.75, 57.75, 50, 2)` and aggregate to ≈ 0.689; the row that is best on every attribute
//! wins.
//!
//! ```
//! use madm_owa::{MadmDecider, OwaWeights, Support, Weighting, natural_visibility_graph};
//! use rand::SeedableRng;
//!
//! let row = [0.9, 0.7, 0.6, 0.3];
//! assert_eq!(natural_visibility_graph(&row)?, [(0, 1), (0, 2), (1, 2), (2, 3)]);
//!
//! let w = OwaWeights::visibility_of_values(&row, Support::default())?;
//! assert!((w.as_slice()[1] - 57.75 / 131.5).abs() < 1e-6);
//! assert!((w.aggregate(&row)? - 0.689).abs() < 1e-3);
//!
//! // Five actions x four attributes, the robot task's shape.
//! let matrix = [
//!     0.9, 0.7, 0.6, 0.3, //
//!     0.2, 0.1, 0.0, 0.4, //
//!     0.9, 0.8, 0.6, 0.3, //
//!     0.5, 0.5, 0.5, 0.5, //
//!     -1.0, 0.3, 0.2, 0.1, //
//! ];
//! let mut decider = MadmDecider::new(Weighting::default())?;
//! let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(42);
//! assert_eq!(decider.best_row(&matrix, 5, 4, &mut rng)?, 2);
//! # Ok::<(), madm_owa::MadmError>(())
//! ```

mod decision;
mod error;
mod normalise;
mod owa;
mod support;
mod visibility;
mod weights;

pub use decision::{MadmDecider, Weighting};
pub use error::MadmError;
pub use normalise::{ColumnSummary, Normalisation};
pub use owa::{WEIGHT_SUM_TOLERANCE, andness, orness, owa, owa_sorted, validate_weights};
pub use support::{DEFAULT_EPSILON, Support, visibility_weights_into};
pub use visibility::{is_visible, natural_visibility_graph};
pub use weights::OwaWeights;
