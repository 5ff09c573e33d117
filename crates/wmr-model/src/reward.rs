//! The sub-task rewards of Eq. 6, 7 and 8 and the task's own reward.
//!
//! * Sub-task 1, reach the target faster (Eq. 6): `r₁ = −(k·D + S − C_noise)`.
//! * Sub-task 2, do not hit obstacles (Eq. 7): `r₂ = −(f·Rad + S − C_noise)`, or `−100` on a hit.
//! * Sub-task 3, keep the target in view (Eq. 8): `r₃ = +2`, or `−10` when the target is lost.
//!
//! `D` is the distance to the target (m), `C_noise` the sensors' noise constant, and
//! `S = Σ_{i=1}^{8} |i − p| · C_i / p` the sensor term. The paper prints `|n − p| · C_n` inside a
//! sum over `i` and calls `n` "the number of sensors"; we read `n` as the summation index, so
//! sensor `i`'s proximity `C_i` is weighted by its index distance from sensor `p`. With the
//! e-puck numbering (1 = front right, clockwise, 8 = front left) and the default `p = 4.5`, the
//! two rear sensors weigh 0.11, the side ones 0.33, the diagonal ones 0.56 and the two front
//! ones 0.78: obstacles ahead cost most.
//!
//! `Rad` is the angle between the heading and the robot→obstacle line of the obstacle in view,
//! unsigned, and π when none is in view. Taken literally, `−f·Rad` rewards *facing* obstacles
//! (small `Rad`): [`RadPenalty::Literal`] keeps that (the default; `f·Rad ≤ 0.1 π`, small next
//! to the other terms), [`RadPenalty::Facing`] charges `f·(π − Rad)` instead, which penalises
//! heading at an obstacle.
//!
//! The *task* reward, the one learning curves plot and the competitors learn from, is
//! `r₁ + r₂ + r₃ + goal_bonus · [target reached]`: the paper evaluates "average reward" but
//! does not define the task's reward apart from its decomposition, and the sum keeps every
//! sub-task's signal at its own scale. With the defaults it is about +1 per step in free space
//! (so ending an episode early never pays) and the goal bonus of +100 outweighs lingering near
//! the target, whose discounted worth is about `2 / (1 − γ) = 40` at `γ = 0.95`. Because the
//! per-step reward is positive, the *undiscounted* return grows with the episode's length;
//! compare runs by Sec. VI.B's average reward (return per second) instead, which favours fast
//! runs: about 20 per second for the planner's route in the default scenario, 8.5 for a
//! dithering run that also reaches the target.
//!
//! A learner trained on `r₁` alone sees only negative rewards (`r₁ ≤ C_noise`) and shares the
//! task's terminations, so ending the episode early (losing the target, say) is its optimum.
//! That is the paper's decomposition taken literally; sub-task 2 and 3 have the penalties that
//! make ending early costly.

use serde::{Deserialize, Serialize};

use crate::sensors::SENSOR_COUNT;

/// How `Rad` enters Eq. 7.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum RadPenalty {
    /// As printed: `−f·Rad`.
    #[default]
    Literal,
    /// Repaired: `−f·(π − Rad)`, largest when heading straight at the obstacle.
    Facing,
}

/// Reward constants. `k`, `p`, `f` are the paper's; the rest are its fixed numbers, exposed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RewardParams {
    /// `k` of Eq. 6 (per metre). Default 1: one metre from the target costs 1 per step.
    pub k: f64,
    /// `p` of Eq. 6 and 7, the reference sensor index; positive. Default 4.5 (between the two
    /// rear sensors, so the weights are symmetric and largest in front).
    pub p: f64,
    /// `f` of Eq. 7 (per radian). Default 0.1 (Table 1).
    pub f: f64,
    /// Reward of Eq. 7 on a hit. Default −100.
    pub hit: f64,
    /// Reward of Eq. 8 while the target is in view. Default +2.
    pub target_kept: f64,
    /// Reward of Eq. 8 when the target is lost. Default −10.
    pub target_lost: f64,
    /// Added to the task reward on the step that reaches the target. Default +100.
    pub goal_bonus: f64,
    /// How `Rad` enters Eq. 7.
    pub rad_penalty: RadPenalty,
}

impl Default for RewardParams {
    fn default() -> Self {
        Self {
            k: 1.0,
            p: 4.5,
            f: 0.1,
            hit: -100.0,
            target_kept: 2.0,
            target_lost: -10.0,
            goal_bonus: 100.0,
            rad_penalty: RadPenalty::Literal,
        }
    }
}

/// Number of sub-tasks.
pub const SUBTASK_COUNT: usize = 3;

/// Names of the sub-tasks, in reward order.
pub const SUBTASK_NAMES: [&str; SUBTASK_COUNT] = [
    "reach_target_faster",
    "avoid_obstacles",
    "keep_target_in_view",
];

/// What one transition looked like, as the rewards need it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RewardInputs<'a> {
    /// Distance from the robot's centre to the target after the step (m).
    pub target_distance: f64,
    /// Noisy proximity readings `C_1 … C_8` after the step.
    pub readings: &'a [f64; SENSOR_COUNT],
    /// `C_noise`.
    pub noise: f64,
    /// Unsigned angle to the obstacle in view (rad), π when none is.
    pub rad: f64,
    /// The step hit a wall or an obstacle.
    pub hit: bool,
    /// The target left the field of view (and was not reached).
    pub lost: bool,
}

impl RewardParams {
    /// `S = Σ_{i=1}^{8} |i − p| · C_i / p`.
    #[must_use]
    pub fn sensor_term(&self, readings: &[f64; SENSOR_COUNT]) -> f64 {
        let mut sum = 0.0;
        let mut index = 1.0;
        for reading in readings {
            sum += (index - self.p).abs() * reading;
            index += 1.0;
        }
        sum / self.p
    }

    /// Eq. 6: `−(k·D + S − C_noise)`.
    #[must_use]
    pub fn reach(&self, inputs: &RewardInputs<'_>) -> f64 {
        -(self.k * inputs.target_distance + self.sensor_term(inputs.readings) - inputs.noise)
    }

    /// Eq. 7: `−(f·Rad + S − C_noise)`, or the hit reward.
    #[must_use]
    pub fn avoid(&self, inputs: &RewardInputs<'_>) -> f64 {
        if inputs.hit {
            return self.hit;
        }
        let angle = match self.rad_penalty {
            RadPenalty::Literal => inputs.rad,
            RadPenalty::Facing => std::f64::consts::PI - inputs.rad,
        };
        -(self.f * angle + self.sensor_term(inputs.readings) - inputs.noise)
    }

    /// Eq. 8: `+2` while the target is kept, `−10` when it is lost.
    #[must_use]
    pub fn view(&self, inputs: &RewardInputs<'_>) -> f64 {
        if inputs.lost {
            self.target_lost
        } else {
            self.target_kept
        }
    }

    /// The three sub-task rewards, in [`SUBTASK_NAMES`] order.
    #[must_use]
    pub fn subtasks(&self, inputs: &RewardInputs<'_>) -> [f64; SUBTASK_COUNT] {
        [self.reach(inputs), self.avoid(inputs), self.view(inputs)]
    }

    /// The task reward: the sum of the sub-task rewards, plus the goal bonus on reaching.
    #[must_use]
    pub fn task(&self, subtasks: &[f64; SUBTASK_COUNT], reached: bool) -> f64 {
        subtasks.iter().sum::<f64>() + if reached { self.goal_bonus } else { 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(readings: &[f64; SENSOR_COUNT]) -> RewardInputs<'_> {
        RewardInputs {
            target_distance: 0.5,
            readings,
            noise: 0.02,
            rad: 0.3,
            hit: false,
            lost: false,
        }
    }

    #[test]
    fn sensor_weights_follow_index_distance_from_p() {
        let params = RewardParams::default();
        let mut readings = [0.0; SENSOR_COUNT];
        readings[0] = 1.0; // sensor 1: |1 − 4.5| / 4.5
        assert!((params.sensor_term(&readings) - 3.5 / 4.5).abs() < 1e-15);
        readings = [1.0; SENSOR_COUNT];
        // 2 · (3.5 + 2.5 + 1.5 + 0.5) / 4.5 = 16 / 4.5.
        assert!((params.sensor_term(&readings) - 16.0 / 4.5).abs() < 1e-15);
        let integer_p = RewardParams { p: 4.0, ..params };
        // |i − 4| = 3, 2, 1, 0, 1, 2, 3, 4 ⇒ 16 / 4.
        assert!((integer_p.sensor_term(&readings) - 4.0).abs() < 1e-15);
    }

    #[test]
    fn eq6_7_8_by_hand() {
        let params = RewardParams::default();
        let mut readings = [0.0; SENSOR_COUNT];
        readings[7] = 0.5; // sensor 8: weight 3.5 / 4.5
        let s = 0.5 * 3.5 / 4.5;
        let i = inputs(&readings);
        assert!((params.reach(&i) - -(0.5 + s - 0.02)).abs() < 1e-15);
        assert!((params.avoid(&i) - -(0.1 * 0.3 + s - 0.02)).abs() < 1e-15);
        assert_eq!(params.view(&i), 2.0);
        let facing = RewardParams {
            rad_penalty: RadPenalty::Facing,
            ..params
        };
        let expected = -(0.1 * (std::f64::consts::PI - 0.3) + s - 0.02);
        assert!((facing.avoid(&i) - expected).abs() < 1e-15);
        let hit = RewardInputs { hit: true, ..i };
        assert_eq!(params.avoid(&hit), -100.0);
        let lost = RewardInputs { lost: true, ..i };
        assert_eq!(params.view(&lost), -10.0);
        let sub = params.subtasks(&i);
        assert!((params.task(&sub, true) - (sub.iter().sum::<f64>() + 100.0)).abs() < 1e-12);
    }

    #[test]
    fn literal_rad_penalty_prefers_facing_the_obstacle() {
        // The degeneracy we keep by default: a smaller angle to the obstacle pays more.
        let params = RewardParams::default();
        let readings = [0.0; SENSOR_COUNT];
        let facing = RewardInputs {
            rad: 0.0,
            ..inputs(&readings)
        };
        let away = RewardInputs {
            rad: 0.7,
            ..inputs(&readings)
        };
        assert!(params.avoid(&facing) > params.avoid(&away));
        let repaired = RewardParams {
            rad_penalty: RadPenalty::Facing,
            ..params
        };
        assert!(repaired.avoid(&facing) < repaired.avoid(&away));
    }
}
