//! The robot's curves over *reaching* episodes (C4; the paper's Fig. 13–15): per run, a
//! metric's values over its first [`REACHING_EPISODES`] training episodes that reached the
//! target, in order, and per reaching-episode index how many seeds contribute (a seed with
//! fewer reaching episodes drops out to the right). The C4 scores of
//! [`scores`](crate::scores) are means over the same episodes ([`first_reaching`]), so a
//! figure and its table draw on one selection.
//!
//! ```
//! use eamadm_eval::reaching::{ReachingMetric, seeds_contributing};
//! use eamadm_eval::RobotEpisodeMetrics;
//!
//! let metrics = RobotEpisodeMetrics {
//!     time: 12.0,
//!     average_reward: 3.5,
//!     time_to_reach: Some(9.6),
//!     retention_time: 1.2,
//! };
//! assert_eq!(ReachingMetric::ReachingTime.value(&metrics), 9.6);
//! // Three seeds with 3, 1 and no reaching episodes: index 1 has 2 seeds, 2 and 3 have 1.
//! assert_eq!(seeds_contributing(&[3, 1, 0]), [2, 1, 1]);
//! ```

use crate::record::{EpisodeRecord, RobotEpisodeMetrics, RunRecord};
use crate::scores::REACHING_EPISODES;

/// A robot metric of a reaching episode that C4 draws and scores.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReachingMetric {
    /// Return per second (Fig. 13).
    AverageReward,
    /// Seconds to reach the target (Fig. 14); the episode's time when no time is recorded.
    ReachingTime,
    /// Seconds in front of obstacles (Fig. 15).
    RetentionTime,
}

impl ReachingMetric {
    /// The three, in the paper's figure order.
    pub const ALL: [Self; 3] = [Self::AverageReward, Self::ReachingTime, Self::RetentionTime];

    /// The metric of one reaching episode.
    #[must_use]
    pub fn value(self, metrics: &RobotEpisodeMetrics) -> f64 {
        match self {
            Self::AverageReward => metrics.average_reward,
            Self::ReachingTime => metrics.time_to_reach.unwrap_or(metrics.time),
            Self::RetentionTime => metrics.retention_time,
        }
    }
}

/// The first [`REACHING_EPISODES`] training episodes of `episodes` that reached the target, in
/// order: the paper's "100 episodes that are to reach the target".
pub fn first_reaching(episodes: &[EpisodeRecord]) -> impl Iterator<Item = &EpisodeRecord> {
    episodes
        .iter()
        .filter(|e| e.reached)
        .take(REACHING_EPISODES)
}

/// `metric` over the run's first reaching episodes ([`first_reaching`]), at most
/// [`REACHING_EPISODES`] values; empty when the run never reached the target or is not a
/// robot run. An episode without robot metrics or with a NaN value is left out (it has no
/// value to draw).
#[must_use]
pub fn reaching_curve(record: &RunRecord, metric: ReachingMetric) -> Vec<f64> {
    first_reaching(&record.episodes)
        .filter_map(|e| e.robot.as_ref())
        .map(|m| metric.value(m))
        .filter(|v| !v.is_nan())
        .collect()
}

/// Per reaching-episode index `x` (from 0), the number of curves of `lengths` that have a
/// value there (length above `x`), up to the longest curve: a non-increasing step function.
#[must_use]
pub fn seeds_contributing(lengths: &[usize]) -> Vec<usize> {
    let longest = lengths.iter().copied().max().unwrap_or(0);
    (0..longest)
        .map(|x| lengths.iter().filter(|&&len| len > x).count())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn episode(reached: bool, average_reward: f64) -> EpisodeRecord {
        EpisodeRecord {
            episode: 0,
            steps: 10,
            task_return: 1.0,
            learning_return: 1.0,
            terminated: reached,
            truncated: false,
            reached,
            collisions: 0,
            env_steps: 10,
            robot: Some(RobotEpisodeMetrics {
                time: 4.0,
                average_reward,
                time_to_reach: reached.then_some(3.0),
                retention_time: 0.5,
            }),
        }
    }

    #[test]
    fn the_curve_takes_the_first_hundred_reaching_episodes_in_order() {
        let episodes: Vec<EpisodeRecord> = (0..400)
            .map(|i| episode(i % 3 == 0, f64::from(i)))
            .collect();
        let taken: Vec<f64> = first_reaching(&episodes)
            .filter_map(|e| e.robot.map(|m| m.average_reward))
            .collect();
        assert_eq!(taken.len(), REACHING_EPISODES);
        assert_eq!(taken[..3], [0.0, 3.0, 6.0]);
        assert_eq!(taken[REACHING_EPISODES - 1], 297.0);
    }

    #[test]
    fn seeds_contributing_counts_the_curves_long_enough() {
        assert_eq!(seeds_contributing(&[]), Vec::<usize>::new());
        assert_eq!(seeds_contributing(&[0, 0]), Vec::<usize>::new());
        let counts = seeds_contributing(&[100, 40, 40, 7]);
        assert_eq!(counts.len(), 100);
        assert_eq!(
            (counts[0], counts[6], counts[7], counts[39], counts[40]),
            (4, 4, 3, 3, 1)
        );
        assert!(counts.windows(2).all(|w| w[0] >= w[1]));
    }
}
