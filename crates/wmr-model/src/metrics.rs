//! Per-episode measurements of Sec. VI.B: return, average reward, time to reach the target,
//! retention time.
//!
//! *Retention time* is the paper's "time the robot stays in front of obstacles", made
//! measurable: the time spent in steps that end with an obstacle in the camera's view whose
//! feature point is within `retention_distance` of the camera, and during which the distance to
//! the target shrank by less than `retention_progress` times what a full-speed forward step
//! covers (`v_max · Δt`). Stopping, backing off, or turning on the spot in front of a nearby
//! obstacle counts; driving past it towards the target does not.

use serde::{Deserialize, Serialize};

use crate::reward::SUBTASK_COUNT;

/// How retention is measured.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MetricsParams {
    /// An obstacle counts as "in front" when its feature point is in view and at most this far
    /// from the camera (m). Default 0.15: about six full-speed steps.
    pub retention_distance: f64,
    /// A step "makes no progress" when the distance to the target shrinks by less than this
    /// fraction of a full-speed forward step. Default 0.25.
    pub retention_progress: f64,
}

impl Default for MetricsParams {
    fn default() -> Self {
        Self {
            retention_distance: 0.15,
            retention_progress: 0.25,
        }
    }
}

/// How an episode stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum EpisodeStatus {
    /// Still going.
    #[default]
    Running,
    /// Reached the target (terminal).
    Reached,
    /// Hit a wall or an obstacle (terminal).
    Hit,
    /// The target left the camera's view (terminal).
    LostTarget,
    /// Cut by the step cap (truncated, not terminal).
    Truncated,
}

impl EpisodeStatus {
    /// Ended inside the task: reached, hit or lost.
    #[must_use]
    pub fn is_terminal(self) -> bool {
        matches!(self, Self::Reached | Self::Hit | Self::LostTarget)
    }

    /// The episode is over, for any reason.
    #[must_use]
    pub fn is_done(self) -> bool {
        self != Self::Running
    }
}

/// What an episode has accumulated so far.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct EpisodeMetrics {
    /// Steps taken.
    pub steps: usize,
    /// Simulated time (s): `steps · Δt`.
    pub time: f64,
    /// Sum of the task rewards.
    pub task_return: f64,
    /// Sums of each sub-task's rewards.
    pub subtask_returns: [f64; SUBTASK_COUNT],
    /// How the episode stands.
    #[serde(alias = "outcome")]
    pub status: EpisodeStatus,
    /// Time at which the target was reached (s), if it was.
    pub time_to_reach: Option<f64>,
    /// Steps counted as retention (see the module docs).
    pub retention_steps: usize,
    /// Retention time (s): `retention_steps · Δt`.
    pub retention_time: f64,
    /// Length of the path travelled by the robot's centre (m).
    pub path_length: f64,
}

impl EpisodeMetrics {
    /// Average reward of Sec. VI.B: the task return divided by the episode time (per second);
    /// 0 before the first step.
    #[must_use]
    pub fn average_reward(&self) -> f64 {
        if self.time > 0.0 {
            self.task_return / self.time
        } else {
            0.0
        }
    }
}
