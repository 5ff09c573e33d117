//! Why each method behaves as it does, computed from the run records: per method the share of
//! each action in the final window, its final-window success with a Wilson interval, and for
//! EA-MADM how often its decision agrees with each sub-task's best action, which sub-task
//! dominated, and what each sub-task's learner learned to expect from the start state.
//!
//! Everything here is a pure function of the records, so the report (xtask) only formats it.

use serde::{Deserialize, Serialize};

use crate::record::RunRecord;
use crate::stats::{Interval, wilson};

/// Confidence of the success intervals.
pub const SUCCESS_CONFIDENCE: f64 = 0.95;

/// One sub-task of EA-MADM, pooled over seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SubtaskBehaviour {
    /// The sub-task's name.
    pub name: String,
    /// Mean over seeds of the pre-trained learner's behaviour value of each action in the
    /// start state.
    pub start_values: Vec<f64>,
    /// The action with the largest mean start value (the first of equals).
    pub best_start_action: usize,
    /// Share of EA-MADM's final-window decisions (exploitation steps) equal to one of this
    /// sub-task's greedy actions, pooled over seeds.
    pub agreement: f64,
    /// Mean steps of the sub-task's greedy policy run alone on the task (one episode per seed).
    pub greedy_alone_steps: f64,
    /// How those greedy episodes ended: reached, ended otherwise inside the task (hit or target
    /// lost), cut by the step cap; counts over seeds.
    pub greedy_alone_endings: Endings,
}

/// How a set of episodes ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Endings {
    /// Reached the target.
    pub reached: u64,
    /// Ended inside the task without reaching (a hit, the target lost).
    pub failed: u64,
    /// Cut by the step cap.
    pub truncated: u64,
}

/// One method, pooled over its seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodBehaviour {
    /// The method's label.
    pub method: String,
    /// Seeds pooled.
    pub seeds: usize,
    /// Final-window episodes over all seeds.
    pub final_episodes: u64,
    /// How the final-window episodes ended.
    pub final_endings: Endings,
    /// Share of final-window episodes that reached the target, with its Wilson interval
    /// (episodes pooled over seeds, [`SUCCESS_CONFIDENCE`]); `None` without episodes.
    pub success: Option<Interval>,
    /// Seeds with at least one reaching episode in the final window.
    pub seeds_reaching: usize,
    /// Mean steps of a final-window episode.
    pub mean_final_steps: f64,
    /// Share of each action among the final window's steps (exploring steps included).
    pub action_shares: Vec<f64>,
    /// EA-MADM's sub-tasks (empty for the competitors).
    pub subtasks: Vec<SubtaskBehaviour>,
    /// The sub-task whose greedy action EA-MADM's decisions agreed with most often (`None`
    /// for the competitors or without decisions).
    pub dominant_subtask: Option<usize>,
    /// Final-window decisions (exploitation steps) of EA-MADM, over all seeds.
    pub decisions: u64,
}

fn share(count: u64, total: u64) -> f64 {
    if total == 0 {
        0.0
    } else {
        #[expect(clippy::cast_precision_loss, reason = "step counts stay far below 2⁵³")]
        let ratio = count as f64 / total as f64;
        ratio
    }
}

#[expect(
    clippy::cast_precision_loss,
    reason = "counts of seeds and steps stay far below 2⁵³"
)]
fn mean(total: f64, count: usize) -> f64 {
    if count == 0 {
        0.0
    } else {
        total / count as f64
    }
}

/// The behaviour of every method in `records` (runs of one experiment, any order), in the
/// order methods first appear. Records of one method must agree on the number of actions.
#[must_use]
pub fn behaviour(records: &[RunRecord]) -> Vec<MethodBehaviour> {
    let mut methods: Vec<&str> = Vec::new();
    for record in records {
        if !methods.contains(&record.method.as_str()) {
            methods.push(&record.method);
        }
    }
    methods
        .into_iter()
        .map(|method| {
            let runs: Vec<&RunRecord> = records.iter().filter(|r| r.method == method).collect();
            method_behaviour(method, &runs)
        })
        .collect()
}

fn method_behaviour(method: &str, runs: &[&RunRecord]) -> MethodBehaviour {
    let n_actions = runs
        .iter()
        .map(|r| r.final_window_actions.len())
        .max()
        .unwrap_or(0);
    let mut action_counts = vec![0_u64; n_actions];
    let mut endings = Endings::default();
    let (mut final_episodes, mut final_steps, mut seeds_reaching) = (0_u64, 0_u64, 0_usize);
    for run in runs {
        for (total, count) in action_counts.iter_mut().zip(&run.final_window_actions) {
            *total += count;
        }
        let window = usize::try_from(run.final_window_episodes).unwrap_or(usize::MAX);
        let from = run.episodes.len().saturating_sub(window);
        let mut reached_here = false;
        for episode in &run.episodes[from..] {
            final_episodes += 1;
            final_steps += episode.steps;
            if episode.reached {
                endings.reached += 1;
                reached_here = true;
            } else if episode.truncated {
                endings.truncated += 1;
            } else {
                endings.failed += 1;
            }
        }
        seeds_reaching += usize::from(reached_here);
    }
    let all_steps: u64 = action_counts.iter().sum();
    let action_shares = action_counts.iter().map(|&c| share(c, all_steps)).collect();
    let success = wilson(endings.reached, final_episodes, SUCCESS_CONFIDENCE).ok();

    // EA-MADM's sub-tasks: agreement pooled over seeds, start values averaged.
    let n_subtasks = runs
        .iter()
        .filter(|r| r.agreement.is_some())
        .map(|r| r.subtasks.len())
        .max()
        .unwrap_or(0);
    let mut decisions = 0_u64;
    let mut agrees = vec![0_u64; n_subtasks];
    for run in runs {
        if let Some(agreement) = &run.agreement {
            decisions += agreement.final_window.decisions;
            for (total, count) in agrees.iter_mut().zip(&agreement.final_window.agrees) {
                *total += count;
            }
        }
    }
    let subtasks: Vec<SubtaskBehaviour> = (0..n_subtasks)
        .map(|k| subtask_behaviour(runs, k, share(agrees[k], decisions)))
        .collect();
    let dominant_subtask = (decisions > 0)
        .then(|| (0..n_subtasks).reduce(|best, k| if agrees[k] > agrees[best] { k } else { best }))
        .flatten();
    #[expect(clippy::cast_precision_loss, reason = "step counts stay far below 2⁵³")]
    let mean_final_steps = if final_episodes == 0 {
        0.0
    } else {
        final_steps as f64 / final_episodes as f64
    };
    MethodBehaviour {
        method: method.to_owned(),
        seeds: runs.len(),
        final_episodes,
        final_endings: endings,
        success,
        seeds_reaching,
        mean_final_steps,
        action_shares,
        subtasks,
        dominant_subtask,
        decisions,
    }
}

fn subtask_behaviour(runs: &[&RunRecord], k: usize, agreement: f64) -> SubtaskBehaviour {
    let with_subtask: Vec<_> = runs.iter().filter_map(|r| r.subtasks.get(k)).collect();
    let name = with_subtask
        .first()
        .map_or_else(String::new, |s| s.name.clone());
    let n_actions = with_subtask
        .iter()
        .map(|s| s.start_values.len())
        .max()
        .unwrap_or(0);
    let mut sums = vec![0.0; n_actions];
    let mut counted = 0;
    for subtask in &with_subtask {
        if subtask.start_values.len() == n_actions {
            for (sum, value) in sums.iter_mut().zip(&subtask.start_values) {
                *sum += value;
            }
            counted += 1;
        }
    }
    let start_values: Vec<f64> = sums.iter().map(|&s| mean(s, counted)).collect();
    let best_start_action =
        start_values.iter().enumerate().fold(
            0,
            |best, (a, &v)| if v > start_values[best] { a } else { best },
        );
    let mut endings = Endings::default();
    let mut steps = 0.0;
    let mut greedy_runs = 0;
    for subtask in &with_subtask {
        if let Some(episode) = &subtask.greedy_alone {
            #[expect(clippy::cast_precision_loss, reason = "step counts stay far below 2⁵³")]
            let episode_steps = episode.steps as f64;
            steps += episode_steps;
            greedy_runs += 1;
            if episode.reached {
                endings.reached += 1;
            } else if episode.truncated {
                endings.truncated += 1;
            } else {
                endings.failed += 1;
            }
        }
    }
    SubtaskBehaviour {
        name,
        start_values,
        best_start_action,
        agreement,
        greedy_alone_steps: mean(steps, greedy_runs),
        greedy_alone_endings: endings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_and_means_handle_empty_totals() {
        assert_eq!(share(3, 0), 0.0);
        assert_eq!(share(1, 4), 0.25);
        assert_eq!(mean(3.0, 0), 0.0);
        assert_eq!(mean(3.0, 2), 1.5);
        assert!(behaviour(&[]).is_empty());
    }
}
