//! The discrete state of Sec. III.B: distance to the target × obstacle image position × angle,
//! optionally × the target's horizontal image position.
//!
//! * distance to the target: `N_D` equal bins over `[0, distance_max]` (farther clamps into
//!   the last bin);
//! * the obstacle's image ratio δ (Eq. 5): `N_O` equal bins over the interval δ can take
//!   (`[½, 1]` for the default vertical reading, see [`DeltaAxis`](crate::DeltaAxis));
//! * the angle between the heading and the robot→obstacle line: `N_A` equal bins over the
//!   horizontal field of view `[−fov/2, fov/2]` (clamped);
//! * optionally (`N_T = target_bins ≥ 1`, not in the paper) the target's horizontal position
//!   in the camera image, Eq. 5 in its horizontal form: `δ_T = ½ (tan β_T / tan β₁ʰ + 1)` with
//!   `β_T` the target's bearing from the optical axis (clockwise positive, so `δ_T` runs left to
//!   right across the image) and `β₁ʰ` half the horizontal field of view, in `N_T` equal bins
//!   over `[0, 1]`. `N_T = 0` is the paper's literal state, which has no bearing to the target.
//!
//! When no obstacle is in view, image position and angle are both undefined, so each distance
//! bin has a single "no obstacle" state rather than `N_A` copies of one. With `T = max(N_T, 1)`
//! there are `N_D · T · (N_O · N_A + 1)` states, indexed `(d · T + t) · (N_O · N_A + 1) + o · N_A + a`,
//! where the slot `N_O · N_A` means "no obstacle in view" and `t = 0` when `N_T = 0`.

use serde::{Deserialize, Serialize};

use crate::camera::{CameraParams, ObstacleSighting};

/// Bin counts and the distance scale of the state.
///
/// Defaults: `N_D = 10` bins of 10 cm (`distance_max = 1` m covers the default start, 0.76 m
/// from the target, with room to back off); `N_O = 4` δ bins, which with the default camera
/// split obstacle distances at about 12, 18 and 36 cm (δ − ½ is ∝ 1 / distance, so near
/// obstacles get the fine bins); `N_A = 6` angle bins of 14.5°, an even count so that an
/// obstacle is always either left or right of the heading; `N_T = 7` target bins (see
/// [`DEFAULT_TARGET_BINS`]). 10 · 7 · (4 · 6 + 1) = 1750 states; the paper's literal state
/// ([`StateParams::paper`], `N_T = 0`) has 10 · (4 · 6 + 1) = 250.
///
/// Bounds (checked by [`Scenario::validate`](crate::Scenario::validate)): every bin count is
/// at most [`MAX_BINS`] and the state count at most [`MAX_STATES`], so that the learners' tables
/// (several `f64` per state and action) fit in memory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StateParams {
    /// `N_D`: number of distance bins.
    pub distance_bins: u32,
    /// Distance covered by the distance bins (m).
    pub distance_max: f64,
    /// `N_O`: number of image-position (δ) bins.
    pub image_bins: u32,
    /// `N_A`: number of angle bins.
    pub angle_bins: u32,
    /// `N_T`: number of bins over the target's horizontal image position `δ_T`; 0 leaves the
    /// target's bearing out of the state, as in the paper.
    pub target_bins: u32,
}

/// The default `N_T`. Chosen by measurement (docs/paper-notes.md §8, "Target bearing
/// feature"): with 7 bins the competitors learn to reach the target; 3 bins are too coarse to
/// aim within the 5 cm reach radius, and more bins split the visits the table learns from.
pub const DEFAULT_TARGET_BINS: u32 = 7;

/// Largest bin count of any state feature.
pub const MAX_BINS: u32 = 1000;

/// Largest number of states a scenario may have: 2²⁰. A double-Q learner keeps two tables of
/// five `f64` per state (80 MiB at this bound); EA-MADM keeps such tables per sub-task.
pub const MAX_STATES: u64 = 1 << 20;

impl Default for StateParams {
    fn default() -> Self {
        Self {
            target_bins: DEFAULT_TARGET_BINS,
            ..Self::paper()
        }
    }
}

impl StateParams {
    /// The paper's literal state (Sec. III.B): distance × obstacle image bin × angle bin, with
    /// no target feature (`N_T = 0`); otherwise the defaults.
    #[must_use]
    pub fn paper() -> Self {
        Self {
            distance_bins: 10,
            distance_max: 1.0,
            image_bins: 4,
            angle_bins: 6,
            target_bins: 0,
        }
    }

    /// `max(N_T, 1)`: the number of target slots per distance bin.
    #[must_use]
    pub fn target_slots(&self) -> u32 {
        self.target_bins.max(1)
    }

    /// The number of states, `N_D · max(N_T, 1) · (N_O · N_A + 1)`, computed without overflow.
    #[must_use]
    pub fn state_count(&self) -> u128 {
        u128::from(self.distance_bins)
            * u128::from(self.target_slots())
            * (u128::from(self.image_bins) * u128::from(self.angle_bins) + 1)
    }
}

/// A state's bins. `obstacle` is `None` when no obstacle is in view.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct StateBins {
    /// Distance bin, `0..N_D`.
    pub distance: u32,
    /// Target image-position bin, `0..N_T` (always 0 when `N_T = 0`).
    pub target: u32,
    /// `(image bin in 0..N_O, angle bin in 0..N_A)` of the obstacle in view.
    pub obstacle: Option<(u32, u32)>,
}

/// Maps observations to state indices and back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Discretiser {
    params: StateParams,
    delta_range: (f64, f64),
    half_fov: f64,
    target_slots: usize,
}

/// Bin of `x` among `bins` equal bins over `[lo, hi]`; values outside (and NaN) clamp to the
/// end bins.
#[must_use]
pub fn uniform_bin(x: f64, lo: f64, hi: f64, bins: u32) -> u32 {
    let fraction = (x - lo) / (hi - lo);
    if fraction.is_nan() || fraction <= 0.0 {
        return 0;
    }
    let scaled = fraction * f64::from(bins);
    if scaled >= f64::from(bins - 1) {
        bins - 1
    } else {
        // 0 < scaled < bins − 1 < 2³²: the cast truncates, which for a positive value is
        // `floor` (without its call: `floor` is a library routine on baseline x86-64).
        scaled as u32
    }
}

impl Discretiser {
    /// A discretiser for `params` (bin counts ≥ 1, validated by the scenario) and `camera`.
    #[must_use]
    pub fn new(params: StateParams, camera: &CameraParams) -> Self {
        Self {
            params,
            delta_range: camera.delta_axis.range(),
            half_fov: camera.horizontal_fov / 2.0,
            target_slots: params.target_slots() as usize,
        }
    }

    /// The bin counts and distance scale.
    #[must_use]
    pub fn params(&self) -> &StateParams {
        &self.params
    }

    fn slots_per_distance(&self) -> usize {
        self.params.image_bins as usize * self.params.angle_bins as usize + 1
    }

    /// Number of states, `N_D · max(N_T, 1) · (N_O · N_A + 1)`.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.params.distance_bins as usize * self.target_slots * self.slots_per_distance()
    }

    /// The bins of an observation: distance to the target, the target's horizontal image
    /// position `target_ratio` (`δ_T`, see [`CameraView::target_ratio`](crate::CameraView)) and
    /// the obstacle in view, if any.
    #[must_use]
    pub fn bins(
        &self,
        target_distance: f64,
        target_ratio: f64,
        obstacle: Option<&ObstacleSighting>,
    ) -> StateBins {
        let p = &self.params;
        StateBins {
            distance: uniform_bin(target_distance, 0.0, p.distance_max, p.distance_bins),
            target: if p.target_bins == 0 {
                0
            } else {
                uniform_bin(target_ratio, 0.0, 1.0, p.target_bins)
            },
            obstacle: obstacle.map(|seen| {
                let (lo, hi) = self.delta_range;
                (
                    uniform_bin(seen.delta, lo, hi, p.image_bins),
                    uniform_bin(seen.angle, -self.half_fov, self.half_fov, p.angle_bins),
                )
            }),
        }
    }

    /// The index of `bins`, in `0..n_states()` (bins must be in range).
    #[must_use]
    pub fn index(&self, bins: StateBins) -> usize {
        let slot = match bins.obstacle {
            Some((image, angle)) => {
                image as usize * self.params.angle_bins as usize + angle as usize
            }
            None => self.slots_per_distance() - 1,
        };
        (bins.distance as usize * self.target_slots + bins.target as usize)
            * self.slots_per_distance()
            + slot
    }

    /// The bins of state `index`, or `None` when it is out of range.
    #[must_use]
    pub fn bins_of(&self, index: usize) -> Option<StateBins> {
        if index >= self.n_states() {
            return None;
        }
        let slots = self.slots_per_distance();
        let (row, slot) = (index / slots, index % slots);
        let (distance, target) = (row / self.target_slots, row % self.target_slots);
        let angle_bins = self.params.angle_bins as usize;
        let obstacle = (slot + 1 < slots).then(|| (slot / angle_bins, slot % angle_bins));
        // Every quotient here is below a u32 bin count.
        let to_u32 = |x: usize| u32::try_from(x).expect("bin below a u32 count");
        Some(StateBins {
            distance: to_u32(distance),
            target: to_u32(target),
            obstacle: obstacle.map(|(o, a)| (to_u32(o), to_u32(a))),
        })
    }

    /// Features of state `index` for similarity measures: `[distance bin, image bin, angle
    /// bin]`, then the target bin when `N_T ≥ 1`, where "no obstacle in view" is image bin `N_O`
    /// and angle bin `N_A`. Out-of-range indices give an empty vector.
    #[must_use]
    pub fn features(&self, index: usize) -> Vec<u32> {
        self.bins_of(index).map_or_else(Vec::new, |bins| {
            let (image, angle) = bins
                .obstacle
                .unwrap_or((self.params.image_bins, self.params.angle_bins));
            let mut features = vec![bins.distance, image, angle];
            if self.params.target_bins >= 1 {
                features.push(bins.target);
            }
            features
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_bins_clamp_at_both_ends() {
        assert_eq!(uniform_bin(-1.0, 0.0, 1.0, 4), 0);
        assert_eq!(uniform_bin(0.0, 0.0, 1.0, 4), 0);
        assert_eq!(uniform_bin(0.26, 0.0, 1.0, 4), 1);
        assert_eq!(uniform_bin(0.99, 0.0, 1.0, 4), 3);
        assert_eq!(uniform_bin(1.0, 0.0, 1.0, 4), 3);
        assert_eq!(uniform_bin(7.0, 0.0, 1.0, 4), 3);
        assert_eq!(uniform_bin(f64::NAN, 0.0, 1.0, 4), 0);
        assert_eq!(uniform_bin(0.5, 0.0, 1.0, 1), 0);
    }

    #[test]
    fn index_and_bins_are_inverse() {
        let d = Discretiser::new(StateParams::paper(), &CameraParams::default());
        assert_eq!(d.n_states(), 250);
        for index in 0..d.n_states() {
            let bins = d.bins_of(index).expect("in range");
            assert_eq!(d.index(bins), index);
        }
        assert_eq!(d.bins_of(250), None);
        assert_eq!(d.features(24), vec![0, 4, 6]);
        assert_eq!(d.features(25 + 7), vec![1, 1, 1]);
        assert_eq!(d.features(24 + 25 * 9), vec![9, 4, 6]);
        assert!(d.features(250).is_empty());
    }

    #[test]
    fn target_bins_multiply_the_states_and_come_back() {
        let d = Discretiser::new(StateParams::default(), &CameraParams::default());
        assert_eq!(d.n_states(), 1750);
        for index in 0..d.n_states() {
            let bins = d.bins_of(index).expect("in range");
            assert_eq!(d.index(bins), index);
        }
        // Distance bin 1, target bin 3 (the middle of 7), no obstacle.
        let bins = d.bins(0.15, 0.5, None);
        assert_eq!((bins.distance, bins.target, bins.obstacle), (1, 3, None));
        assert_eq!(d.index(bins), (7 + 3) * 25 + 24);
        assert_eq!(d.features(d.index(bins)), vec![1, 4, 6, 3]);
        // `δ_T` at the image's edges clamps into the end bins.
        assert_eq!(d.bins(0.15, -0.2, None).target, 0);
        assert_eq!(d.bins(0.15, 1.0, None).target, 6);
        // N_T = 0 ignores `δ_T`.
        let paper = Discretiser::new(StateParams::paper(), &CameraParams::default());
        assert_eq!(paper.bins(0.15, 0.9, None).target, 0);
    }
}
