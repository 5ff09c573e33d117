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
//! The *task* reward, the one learning curves plot and the competitors learn from, is not
//! defined by the paper for the robot: it gives the sub-task rewards (Eq. 6–8), lets the source
//! task learn from their standardised values, and leaves the competitors' reward unstated.
//! [`TaskReward`] selects it:
//!
//! * [`TaskReward::Progress`] (the default) is the paper's own reward for "reach the target
//!   without hitting" in the mazes (Task I, Sec. VI.A), carried over: `+1` when the step brought
//!   the robot closer to the target (by more than `min_progress`, default 0: strictly closer),
//!   `−1` otherwise (a `stop`, a turn on the spot's worth of no progress, or a step away), and
//!   on the terminal steps, instead: Eq. 7's `−100` on a hit, `+100` (`goal_bonus`) on reaching
//!   the target, Eq. 8's `−10` when the target is lost. A step's reward then says which way the
//!   target lies, idling costs (`stop` for ever is worth `−1 / (1 − γ) = −20` at `γ = 0.95`),
//!   and only reaching pays a bonus: a run that never finishes must give back, in steps away,
//!   most of what it gained in steps towards the target.
//! * [`TaskReward::SubtaskSum`]: `r₁ + r₂ + r₃ + goal_bonus · [target reached]`, which keeps
//!   every sub-task's signal at its own scale. It is *not* the default because it pays for
//!   surviving rather than for finishing: Eq. 8's `+2` for keeping the target in view
//!   dominates, so it is about `+1.2` per step in free space, and a step towards the target
//!   earns only `2·k·0.025 = 0.05` more than a step away. In the default scenario, `stop` for
//!   ever at the start is worth 23.8 (discounted, `γ = 0.95`), about as much as reaching the
//!   target with a deterministic table over the states ([`tabular_policy`]'s 183-step run:
//!   24.3; a 60-step table: 26.9) and two thirds of the planner's 34-step route (35.0), which no
//!   table can follow (none within 50 steps was found). Under it no learner reached the
//!   target in any training episode (10 seeds × 200 episodes). Under `Progress` the same four
//!   are worth −20, 5.7, 13.2 and 34.7.
//!
//! Average reward (Sec. VI.B: return per second) favours fast runs under both schemes.
//!
//! A learner trained on `r₁` alone sees only negative rewards (`r₁ ≤ C_noise`) and shares the
//! task's terminations, so ending the episode early (losing the target, say) is its optimum.
//! That is the paper's decomposition taken literally; sub-task 2 and 3 have the penalties that
//! make ending early costly.

use serde::{Deserialize, Serialize};

#[cfg(doc)]
use crate::planner::tabular_policy;
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

/// Repairs of the sub-task rewards (issue 21 item 4), each off in the paper's
/// literal reading. In TOML (`[reward]`): `repairs = { reach_goal_bonus = true,
/// end_penalties = true }`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SubtaskRepairs {
    /// Sub-task 1 (Eq. 6, reach the target faster) gets [`RewardParams::goal_bonus`] on the
    /// step that reaches the target instead of Eq. 6's value, as the maze's "reach faster"
    /// sub-task gets the maze's goal reward and as the competitors' task reward does. Without
    /// it no sub-task is ever paid for reaching.
    pub reach_goal_bonus: bool,
    /// Every sub-task, not only the one whose equation names the event, gets the penalty of
    /// the step that ends the episode: [`RewardParams::hit`] on a hit (Eq. 7's −100),
    /// [`RewardParams::target_lost`] when the target is lost (Eq. 8's −10). The paper ends the
    /// episode on both for every sub-task, but only Eq. 7 and Eq. 8 charge for it, so Eq. 6's
    /// learner is best off ending episodes early.
    pub end_penalties: bool,
}

impl SubtaskRepairs {
    /// The paper's literal rewards: no repair.
    pub const PAPER: Self = Self {
        reach_goal_bonus: false,
        end_penalties: false,
    };
}

/// The task's own reward: what the competitors learn from and the learning curves plot.
///
/// In TOML: `task = { kind = "progress" }` (fields `closer`, `farther`, `min_progress` may be
/// given) or `task = { kind = "subtask_sum" }` in the `[reward]` section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TaskReward {
    /// Task I's reward of the mazes (Sec. VI.A): `closer` when the step reduced the distance
    /// to the target by more than `min_progress`, `farther` otherwise; on a hit, on reaching
    /// and on losing the target, [`RewardParams::hit`], [`RewardParams::goal_bonus`] and
    /// [`RewardParams::target_lost`] instead (in that precedence).
    Progress {
        /// Reward of a step that got closer. Default +1.
        #[serde(default = "default_closer")]
        closer: f64,
        /// Reward of a step that did not (including `stop`). Default −1.
        #[serde(default = "default_farther")]
        farther: f64,
        /// Distance (m) a step must gain to count as closer; non-negative. Default 0.
        #[serde(default)]
        min_progress: f64,
    },
    /// `r₁ + r₂ + r₃`, plus [`RewardParams::goal_bonus`] on reaching. Makes wandering optimal
    /// in the default scenario (see the [module docs](self)).
    SubtaskSum,
}

fn default_closer() -> f64 {
    1.0
}

fn default_farther() -> f64 {
    -1.0
}

impl Default for TaskReward {
    /// `Progress { closer: 1, farther: −1, min_progress: 0 }`.
    fn default() -> Self {
        Self::Progress {
            closer: default_closer(),
            farther: default_farther(),
            min_progress: 0.0,
        }
    }
}

/// What the task reward needs to know about one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaskStep {
    /// Distance to the target before the step minus the distance after it (m): positive when
    /// the step got closer.
    pub progress: f64,
    /// The step hit a wall or an obstacle.
    pub hit: bool,
    /// The step reached the target (without a hit).
    pub reached: bool,
    /// The target left the field of view (and was not reached).
    pub lost: bool,
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
    /// The task reward on the step that reaches the target (added to the sub-task sum under
    /// [`TaskReward::SubtaskSum`]). Default +100.
    pub goal_bonus: f64,
    /// How `Rad` enters Eq. 7.
    pub rad_penalty: RadPenalty,
    /// Repairs of the sub-task rewards (issue 21), none by default (the paper's Eq. 6–8).
    pub repairs: SubtaskRepairs,
    /// The task's own reward. Default [`TaskReward::Progress`] (+1 / −1).
    pub task: TaskReward,
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
            repairs: SubtaskRepairs::PAPER,
            task: TaskReward::default(),
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
    /// Noisy proximity values `C_1 … C_8` after the step.
    pub sensor_values: &'a [f64; SENSOR_COUNT],
    /// `C_noise`.
    pub noise: f64,
    /// Unsigned angle to the obstacle in view (rad), π when none is.
    pub rad: f64,
    /// The step hit a wall or an obstacle.
    pub hit: bool,
    /// The target left the field of view (and was not reached).
    pub lost: bool,
    /// The step reached the target (without a hit). Only [`SubtaskRepairs::reach_goal_bonus`]
    /// reads it.
    pub reached: bool,
}

impl RewardParams {
    /// `S = Σ_{i=1}^{8} |i − p| · C_i / p`.
    #[must_use]
    pub fn sensor_term(&self, sensor_values: &[f64; SENSOR_COUNT]) -> f64 {
        let mut sum = 0.0;
        let mut index = 1.0;
        for value in sensor_values {
            sum += (index - self.p).abs() * value;
            index += 1.0;
        }
        sum / self.p
    }

    /// Eq. 6: `−(k·D + S − C_noise)`.
    #[must_use]
    pub fn reach(&self, inputs: &RewardInputs<'_>) -> f64 {
        self.reach_with(inputs, self.sensor_term(inputs.sensor_values))
    }

    /// [`reach`](Self::reach) given the sensor term `S` of `inputs.sensor_values`.
    fn reach_with(&self, inputs: &RewardInputs<'_>, sensor_term: f64) -> f64 {
        -(self.k * inputs.target_distance + sensor_term - inputs.noise)
    }

    /// Eq. 7: `−(f·Rad + S − C_noise)`, or the hit reward.
    #[must_use]
    pub fn avoid(&self, inputs: &RewardInputs<'_>) -> f64 {
        self.avoid_with(inputs, self.sensor_term(inputs.sensor_values))
    }

    /// [`avoid`](Self::avoid) given the sensor term `S` of `inputs.sensor_values`.
    fn avoid_with(&self, inputs: &RewardInputs<'_>, sensor_term: f64) -> f64 {
        if inputs.hit {
            return self.hit;
        }
        let angle = match self.rad_penalty {
            RadPenalty::Literal => inputs.rad,
            RadPenalty::Facing => std::f64::consts::PI - inputs.rad,
        };
        -(self.f * angle + sensor_term - inputs.noise)
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

    /// The three sub-task rewards, in [`SUBTASK_NAMES`] order, with [`RewardParams::repairs`]
    /// applied.
    #[must_use]
    pub fn subtasks(&self, inputs: &RewardInputs<'_>) -> [f64; SUBTASK_COUNT] {
        if self.repairs.end_penalties && (inputs.hit || inputs.lost) {
            let penalty = if inputs.hit {
                self.hit
            } else {
                self.target_lost
            };
            return [penalty; SUBTASK_COUNT];
        }
        // Eq. 6 and 7 share `S`: taken once, the same value.
        let sensor_term = self.sensor_term(inputs.sensor_values);
        let reach = if self.repairs.reach_goal_bonus && inputs.reached {
            self.goal_bonus
        } else {
            self.reach_with(inputs, sensor_term)
        };
        [
            reach,
            self.avoid_with(inputs, sensor_term),
            self.view(inputs),
        ]
    }

    /// The task reward of one step, by [`RewardParams::task`]; `subtasks` are the step's
    /// sub-task rewards (used by [`TaskReward::SubtaskSum`]).
    #[must_use]
    pub fn task(&self, subtasks: &[f64; SUBTASK_COUNT], step: &TaskStep) -> f64 {
        match self.task {
            TaskReward::SubtaskSum => {
                subtasks.iter().sum::<f64>() + if step.reached { self.goal_bonus } else { 0.0 }
            }
            TaskReward::Progress {
                closer,
                farther,
                min_progress,
            } => {
                if step.hit {
                    self.hit
                } else if step.reached {
                    self.goal_bonus
                } else if step.lost {
                    self.target_lost
                } else if step.progress > min_progress {
                    closer
                } else {
                    farther
                }
            }
        }
    }
}

/// What one sub-task's reward definition makes of three ways to play an episode, discounted
/// (issue 21 item 3's diagnosis): reach the target, end the episode at once by losing the
/// target, or idle at the start until the step cap. See [`RewardParams::reference_values`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ReferenceValues {
    /// A straight run at full speed from the start to the reach radius, no obstacle sensed
    /// (sensor term 0, `Rad = π`): the most favourable reaching episode for Eq. 6 and 7, whose
    /// obstacle terms only subtract.
    pub reach: f64,
    /// One step, then the target is lost (Eq. 8's −10; the episode ends). The step that reaches
    /// or loses the target is rewarded as the scenario's [`SubtaskRepairs`] say.
    pub lose_at_once: f64,
    /// `stop` at the start, target in view and no obstacle sensed, until the step cap.
    pub idle: f64,
}

/// How an episode is played for [`RewardParams::reference_values`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceEpisode {
    /// Distance from the start to the target (m).
    pub start_distance: f64,
    /// Distance at which the target counts as reached (m).
    pub reach_radius: f64,
    /// Distance one full-speed step covers (m); positive.
    pub step_length: f64,
    /// The step cap.
    pub step_cap: u32,
    /// The discount γ.
    pub gamma: f64,
    /// `C_noise`.
    pub noise: f64,
}

impl ReferenceEpisode {
    /// Steps of the straight run: `⌈(start_distance − reach_radius) / step_length⌉`, at least 1.
    #[must_use]
    pub fn reach_steps(&self) -> u32 {
        let gap = (self.start_distance - self.reach_radius).max(0.0);
        // finite, non-negative and far below u32::MAX for any validated scenario
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "bounded above"
        )]
        let steps = (gap / self.step_length).ceil().min(f64::from(u32::MAX)) as u32;
        steps.max(1)
    }
}

impl RewardParams {
    /// Each sub-task's discounted value (`Σ γᵗ rₜ`) of reaching, of losing the target at once
    /// and of idling, from its reward definition alone (Eq. 6–8 with this scenario's
    /// constants), in [`SUBTASK_NAMES`] order. Set against a learner's value of the start
    /// state (from its Q-table) it shows which way of playing the learner has found worth most:
    /// under the paper's rewards Eq. 6 values losing the target at once above reaching (every
    /// step costs and there is no goal bonus), Eq. 8 values idling above both.
    #[must_use]
    pub fn reference_values(&self, episode: &ReferenceEpisode) -> [ReferenceValues; SUBTASK_COUNT] {
        let quiet = [0.0; SENSOR_COUNT];
        let free = |distance: f64, lost: bool, reached: bool| RewardInputs {
            target_distance: distance,
            sensor_values: &quiet,
            noise: episode.noise,
            rad: std::f64::consts::PI,
            hit: false,
            lost,
            reached,
        };
        let mut values = [ReferenceValues {
            reach: 0.0,
            lose_at_once: 0.0,
            idle: 0.0,
        }; SUBTASK_COUNT];
        let steps = episode.reach_steps();
        let mut discount = 1.0;
        for t in 1..=steps {
            let distance = (episode.start_distance - f64::from(t) * episode.step_length)
                .max(episode.reach_radius.min(episode.start_distance));
            let rewards = self.subtasks(&free(distance, false, t == steps));
            for (value, r) in values.iter_mut().zip(rewards) {
                value.reach += discount * r;
            }
            discount *= episode.gamma;
        }
        for (value, r) in
            values
                .iter_mut()
                .zip(self.subtasks(&free(episode.start_distance, true, false)))
        {
            value.lose_at_once = r;
        }
        let mut discount = 1.0;
        let idle = self.subtasks(&free(episode.start_distance, false, false));
        for _ in 0..episode.step_cap {
            for (value, r) in values.iter_mut().zip(idle) {
                value.idle += discount * r;
            }
            discount *= episode.gamma;
        }
        values
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(sensor_values: &[f64; SENSOR_COUNT]) -> RewardInputs<'_> {
        RewardInputs {
            target_distance: 0.5,
            sensor_values,
            noise: 0.02,
            rad: 0.3,
            hit: false,
            lost: false,
            reached: false,
        }
    }

    #[test]
    fn repairs_pay_the_goal_to_reach_and_end_penalties_to_all() {
        let quiet = [0.0; SENSOR_COUNT];
        let paper = RewardParams::default();
        let both = RewardParams {
            repairs: SubtaskRepairs {
                reach_goal_bonus: true,
                end_penalties: true,
            },
            ..paper
        };
        let reached = RewardInputs {
            reached: true,
            ..inputs(&quiet)
        };
        assert_eq!(paper.subtasks(&reached), paper.subtasks(&inputs(&quiet)));
        let [reach, avoid, view] = both.subtasks(&reached);
        assert_eq!(reach, 100.0);
        assert_eq!([avoid, view], [paper.avoid(&reached), 2.0]);
        let hit = RewardInputs {
            hit: true,
            ..inputs(&quiet)
        };
        assert_eq!(both.subtasks(&hit), [-100.0; SUBTASK_COUNT]);
        assert_eq!(paper.subtasks(&hit)[1], -100.0);
        assert!(paper.subtasks(&hit)[0] > -1.0);
        let lost = RewardInputs {
            lost: true,
            ..inputs(&quiet)
        };
        assert_eq!(both.subtasks(&lost), [-10.0; SUBTASK_COUNT]);
        // The reference values follow: with the repairs, reaching beats ending at once.
        let episode = ReferenceEpisode {
            start_distance: 0.8,
            reach_radius: 0.1,
            step_length: 0.05,
            step_cap: 250,
            gamma: 0.95,
            noise: 0.02,
        };
        let [reach, avoid, _] = both.reference_values(&episode);
        assert!(reach.reach > reach.lose_at_once, "{reach:?}");
        assert!(avoid.reach > avoid.lose_at_once, "{avoid:?}");
    }

    #[test]
    fn sensor_weights_follow_index_distance_from_p() {
        let params = RewardParams::default();
        let mut sensor_values = [0.0; SENSOR_COUNT];
        sensor_values[0] = 1.0; // sensor 1: |1 − 4.5| / 4.5
        assert!((params.sensor_term(&sensor_values) - 3.5 / 4.5).abs() < 1e-15);
        sensor_values = [1.0; SENSOR_COUNT];
        // 2 · (3.5 + 2.5 + 1.5 + 0.5) / 4.5 = 16 / 4.5.
        assert!((params.sensor_term(&sensor_values) - 16.0 / 4.5).abs() < 1e-15);
        let integer_p = RewardParams { p: 4.0, ..params };
        // |i − 4| = 3, 2, 1, 0, 1, 2, 3, 4 ⇒ 16 / 4.
        assert!((integer_p.sensor_term(&sensor_values) - 4.0).abs() < 1e-15);
    }

    #[test]
    fn eq6_7_8_by_hand() {
        let params = RewardParams::default();
        let mut sensor_values = [0.0; SENSOR_COUNT];
        sensor_values[7] = 0.5; // sensor 8: weight 3.5 / 4.5
        let s = 0.5 * 3.5 / 4.5;
        let i = inputs(&sensor_values);
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
        let sum = RewardParams {
            task: TaskReward::SubtaskSum,
            ..params
        };
        let reaching = TaskStep {
            progress: 0.02,
            hit: false,
            reached: true,
            lost: false,
        };
        assert!((sum.task(&sub, &reaching) - (sub.iter().sum::<f64>() + 100.0)).abs() < 1e-12);
    }

    #[test]
    fn literal_rad_penalty_prefers_facing_the_obstacle() {
        // The degeneracy we keep by default: a smaller angle to the obstacle pays more.
        let params = RewardParams::default();
        let sensor_values = [0.0; SENSOR_COUNT];
        let facing = RewardInputs {
            rad: 0.0,
            ..inputs(&sensor_values)
        };
        let away = RewardInputs {
            rad: 0.7,
            ..inputs(&sensor_values)
        };
        assert!(params.avoid(&facing) > params.avoid(&away));
        let repaired = RewardParams {
            rad_penalty: RadPenalty::Facing,
            ..params
        };
        assert!(repaired.avoid(&facing) < repaired.avoid(&away));
    }

    fn step(progress: f64) -> TaskStep {
        TaskStep {
            progress,
            hit: false,
            reached: false,
            lost: false,
        }
    }

    #[test]
    fn progress_reward_is_task_one_with_the_robot_terminals() {
        let params = RewardParams::default();
        let sub = [-0.5, -0.3, 2.0]; // ignored by Progress
        assert_eq!(params.task(&sub, &step(0.025)), 1.0);
        assert_eq!(params.task(&sub, &step(1e-12)), 1.0); // strictly closer counts
        assert_eq!(params.task(&sub, &step(0.0)), -1.0); // stop: no progress
        assert_eq!(params.task(&sub, &step(-0.025)), -1.0);
        let reached = TaskStep {
            reached: true,
            ..step(0.025)
        };
        assert_eq!(params.task(&sub, &reached), 100.0);
        let lost = TaskStep {
            lost: true,
            ..step(0.025)
        };
        assert_eq!(params.task(&sub, &lost), -10.0);
        let hit = TaskStep {
            hit: true,
            lost: true,
            ..step(0.025)
        };
        assert_eq!(params.task(&sub, &hit), -100.0); // a hit outranks everything
        let banded = RewardParams {
            task: TaskReward::Progress {
                closer: 1.0,
                farther: -1.0,
                min_progress: 0.01,
            },
            ..params
        };
        assert_eq!(banded.task(&sub, &step(0.005)), -1.0);
        assert_eq!(banded.task(&sub, &step(0.02)), 1.0);
    }

    #[test]
    fn subtask_sum_barely_tells_closer_from_farther() {
        // One full-speed step (2.5 cm) towards or away from the target in free space: under
        // SubtaskSum the two differ only through Eq. 6's k·D, by 2 · k · 0.025 = 0.05 on a
        // reward of about +1.2; under Progress they differ by 2.
        let sensor_values = [0.0; SENSOR_COUNT];
        let at = |target_distance| RewardInputs {
            target_distance,
            rad: std::f64::consts::PI,
            ..inputs(&sensor_values)
        };
        let sum = RewardParams {
            task: TaskReward::SubtaskSum,
            ..RewardParams::default()
        };
        let (closer, farther) = (at(0.475), at(0.525));
        let gap = sum.task(&sum.subtasks(&closer), &step(0.025))
            - sum.task(&sum.subtasks(&farther), &step(-0.025));
        assert!((gap - 0.05).abs() < 1e-12, "{gap}");
        assert!(sum.task(&sum.subtasks(&farther), &step(-0.025)) > 1.0);
        let progress = RewardParams::default();
        let gap = progress.task(&progress.subtasks(&closer), &step(0.025))
            - progress.task(&progress.subtasks(&farther), &step(-0.025));
        assert_eq!(gap, 2.0);
    }

    #[test]
    fn reference_values_show_why_the_literal_subtasks_do_not_reach() {
        let params = RewardParams::default();
        let episode = ReferenceEpisode {
            start_distance: 0.8,
            reach_radius: 0.1,
            step_length: 0.05,
            step_cap: 250,
            gamma: 0.95,
            noise: 0.02,
        };
        assert_eq!(episode.reach_steps(), 14);
        let [reach, avoid, view] = params.reference_values(&episode);
        // Eq. 6: every step costs about k·D, so ending at once beats a 14-step run.
        assert!(reach.lose_at_once > reach.reach, "{reach:?}");
        assert!((reach.lose_at_once - (-(0.8 - 0.02))).abs() < 1e-12);
        // Eq. 8: +2 per step in view; idling to the cap is worth most.
        assert!(
            view.idle > view.reach && view.reach > view.lose_at_once,
            "{view:?}"
        );
        assert!((view.lose_at_once + 10.0).abs() < 1e-12);
        // Eq. 7 with nothing sensed: −(f·π − C_noise) per step, so shorter is better too.
        assert!(
            avoid.lose_at_once > avoid.reach && avoid.reach > avoid.idle,
            "{avoid:?}"
        );
    }
}
