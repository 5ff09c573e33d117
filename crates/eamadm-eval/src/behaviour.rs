//! Why each method behaves as it does, computed from the run records: per method the share of
//! each action in the final window, its final-window success with a Wilson interval, and for
//! EA-MADM how often its decision agrees with each sub-task's best action, which sub-task
//! dominated, and what each sub-task's learner learned to expect from the start state.
//!
//! Everything here is a pure function of the records, so the report (xtask) only formats it.
//! [`BehaviourAccumulator`] takes the records one at a time and keeps only per-method sums, so
//! a report made from a stream of runs holds none of them.

use serde::{Deserialize, Serialize};

use crate::record::{EpisodeRecord, RunRecord, SubtaskRecord};
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
    /// Mean over seeds of the learner's largest start value, `max_a (Q1 + Q2) / 2` at the start
    /// state: the value of its learned greedy policy from the start, what
    /// `eamadm::diagnosis` sets against the reward definition's reference values. It can
    /// exceed the largest of `start_values` (a mean per action), since seeds differ in their
    /// best action. 0 without start values.
    #[serde(default)]
    pub learned_start_value: f64,
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

impl Endings {
    /// Counts how `episode` ended.
    fn add(&mut self, episode: &EpisodeRecord) {
        if episode.reached {
            self.reached += 1;
        } else if episode.truncated {
            self.truncated += 1;
        } else {
            self.failed += 1;
        }
    }
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
///
/// The records go through a [`BehaviourAccumulator`] in order, so a caller that streams its
/// runs through one gets the same numbers bit for bit.
#[must_use]
pub fn behaviour(records: &[RunRecord]) -> Vec<MethodBehaviour> {
    let mut accumulator = BehaviourAccumulator::default();
    for record in records {
        accumulator.push(record);
    }
    accumulator.finish()
}

/// [`behaviour`] of an experiment's runs, accumulated one run at a time: per method sums and
/// counts (of actions, endings, agreements, start values), never the runs, so memory does not
/// grow with the number of seeds. Sums are added in push order, so pushing the runs in the
/// order of a slice gives [`behaviour`] of that slice bit for bit.
#[derive(Debug, Clone, Default)]
pub struct BehaviourAccumulator {
    /// One per method, in the order methods were first pushed.
    methods: Vec<MethodAccumulator>,
}

impl BehaviourAccumulator {
    /// Adds one run (of any method of the experiment).
    pub fn push(&mut self, record: &RunRecord) {
        let index = match self.methods.iter().position(|m| m.method == record.method) {
            Some(index) => index,
            None => {
                self.methods.push(MethodAccumulator::new(&record.method));
                self.methods.len() - 1
            }
        };
        self.methods[index].push(record);
    }

    /// The behaviour of every method pushed, in the order each was first pushed.
    #[must_use]
    pub fn finish(self) -> Vec<MethodBehaviour> {
        self.methods
            .into_iter()
            .map(MethodAccumulator::finish)
            .collect()
    }
}

/// The running sums of one method.
#[derive(Debug, Clone)]
struct MethodAccumulator {
    method: String,
    seeds: usize,
    /// Per action, its final-window count summed over runs (as long as the longest run's).
    action_counts: Vec<u64>,
    endings: Endings,
    final_episodes: u64,
    final_steps: u64,
    seeds_reaching: usize,
    /// The most sub-tasks of a run with an agreement record.
    agreement_subtasks: usize,
    decisions: u64,
    /// Per sub-task, its agreeing decisions summed over runs (as long as the longest run's).
    agrees: Vec<u64>,
    /// Per sub-task index of any run, its running sums.
    subtasks: Vec<SubtaskAccumulator>,
}

/// The running sums of sub-task `k` over the runs that have one.
#[derive(Debug, Clone, Default)]
struct SubtaskAccumulator {
    /// The name in the first run that has this sub-task.
    name: Option<String>,
    /// Sums of the start values of the runs with the most actions seen so far (runs with
    /// fewer are left out, as [`behaviour`] leaves out the runs with fewer than the most).
    start_value_sums: Vec<f64>,
    /// Runs summed into `start_value_sums`.
    start_value_runs: usize,
    /// Sum over every run with start values of its largest start value.
    best_value_sum: f64,
    /// Runs summed into `best_value_sum`.
    best_value_runs: usize,
    greedy_steps: f64,
    greedy_runs: usize,
    greedy_endings: Endings,
}

impl MethodAccumulator {
    fn new(method: &str) -> Self {
        Self {
            method: method.to_owned(),
            seeds: 0,
            action_counts: Vec::new(),
            endings: Endings::default(),
            final_episodes: 0,
            final_steps: 0,
            seeds_reaching: 0,
            agreement_subtasks: 0,
            decisions: 0,
            agrees: Vec::new(),
            subtasks: Vec::new(),
        }
    }

    fn push(&mut self, run: &RunRecord) {
        self.seeds += 1;
        add_counts(&mut self.action_counts, &run.final_window_actions);
        let window = usize::try_from(run.final_window_episodes).unwrap_or(usize::MAX);
        let from = run.episodes.len().saturating_sub(window);
        let mut reached_here = false;
        for episode in &run.episodes[from..] {
            self.final_episodes += 1;
            self.final_steps += episode.steps;
            self.endings.add(episode);
            reached_here |= episode.reached;
        }
        self.seeds_reaching += usize::from(reached_here);
        if let Some(agreement) = &run.agreement {
            self.agreement_subtasks = self.agreement_subtasks.max(run.subtasks.len());
            self.decisions += agreement.final_window.decisions;
            add_counts(&mut self.agrees, &agreement.final_window.agrees);
        }
        if self.subtasks.len() < run.subtasks.len() {
            self.subtasks
                .resize_with(run.subtasks.len(), SubtaskAccumulator::default);
        }
        for (sums, subtask) in self.subtasks.iter_mut().zip(&run.subtasks) {
            sums.push(subtask);
        }
    }

    fn finish(self) -> MethodBehaviour {
        let all_steps: u64 = self.action_counts.iter().sum();
        let action_shares = self
            .action_counts
            .iter()
            .map(|&c| share(c, all_steps))
            .collect();
        let success = wilson(
            self.endings.reached,
            self.final_episodes,
            SUCCESS_CONFIDENCE,
        )
        .ok();

        // EA-MADM's sub-tasks: agreement pooled over seeds, start values averaged.
        let n_subtasks = self.agreement_subtasks;
        let mut agrees = self.agrees;
        agrees.resize(n_subtasks, 0);
        let decisions = self.decisions;
        let subtasks: Vec<SubtaskBehaviour> = self
            .subtasks
            .into_iter()
            .take(n_subtasks)
            .zip(&agrees)
            .map(|(sums, &agreeing)| sums.finish(share(agreeing, decisions)))
            .collect();
        let dominant_subtask = (decisions > 0)
            .then(|| {
                (0..n_subtasks).reduce(|best, k| if agrees[k] > agrees[best] { k } else { best })
            })
            .flatten();
        #[expect(clippy::cast_precision_loss, reason = "step counts stay far below 2⁵³")]
        let mean_final_steps = if self.final_episodes == 0 {
            0.0
        } else {
            self.final_steps as f64 / self.final_episodes as f64
        };
        MethodBehaviour {
            method: self.method,
            seeds: self.seeds,
            final_episodes: self.final_episodes,
            final_endings: self.endings,
            success,
            seeds_reaching: self.seeds_reaching,
            mean_final_steps,
            action_shares,
            subtasks,
            dominant_subtask,
            decisions,
        }
    }
}

/// Adds `counts` into `totals` element by element, growing `totals` with zeros to fit.
fn add_counts(totals: &mut Vec<u64>, counts: &[u64]) {
    if totals.len() < counts.len() {
        totals.resize(counts.len(), 0);
    }
    for (total, count) in totals.iter_mut().zip(counts) {
        *total += count;
    }
}

impl SubtaskAccumulator {
    fn push(&mut self, subtask: &SubtaskRecord) {
        if self.name.is_none() {
            self.name = Some(subtask.name.clone());
        }
        if let Some(best) = subtask.start_values.iter().copied().reduce(f64::max) {
            self.best_value_sum += best;
            self.best_value_runs += 1;
        }
        let actions = subtask.start_values.len();
        if actions > self.start_value_sums.len() {
            // More actions than every earlier run: those are left out of the mean.
            self.start_value_sums = vec![0.0; actions];
            self.start_value_runs = 0;
        }
        if actions == self.start_value_sums.len() {
            for (sum, value) in self.start_value_sums.iter_mut().zip(&subtask.start_values) {
                *sum += value;
            }
            self.start_value_runs += 1;
        }
        if let Some(episode) = &subtask.greedy_alone {
            #[expect(clippy::cast_precision_loss, reason = "step counts stay far below 2⁵³")]
            let episode_steps = episode.steps as f64;
            self.greedy_steps += episode_steps;
            self.greedy_runs += 1;
            self.greedy_endings.add(episode);
        }
    }

    fn finish(self, agreement: f64) -> SubtaskBehaviour {
        let start_values: Vec<f64> = self
            .start_value_sums
            .iter()
            .map(|&s| mean(s, self.start_value_runs))
            .collect();
        let best_start_action =
            start_values.iter().enumerate().fold(
                0,
                |best, (a, &v)| if v > start_values[best] { a } else { best },
            );
        SubtaskBehaviour {
            name: self.name.unwrap_or_default(),
            start_values,
            best_start_action,
            learned_start_value: mean(self.best_value_sum, self.best_value_runs),
            agreement,
            greedy_alone_steps: mean(self.greedy_steps, self.greedy_runs),
            greedy_alone_endings: self.greedy_endings,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{AgreementCounts, AgreementRecord, EpisodeRecord, TrajectoryRecord};

    #[test]
    fn shares_and_means_handle_empty_totals() {
        assert_eq!(share(3, 0), 0.0);
        assert_eq!(share(1, 4), 0.25);
        assert_eq!(mean(3.0, 0), 0.0);
        assert_eq!(mean(3.0, 2), 1.5);
        assert!(behaviour(&[]).is_empty());
    }

    fn episode(steps: u64, reached: bool, truncated: bool) -> EpisodeRecord {
        EpisodeRecord {
            episode: 0,
            steps,
            task_return: 0.0,
            learning_return: 0.0,
            terminated: !truncated,
            truncated,
            reached,
            collisions: 0,
            env_steps: 0,
            robot: None,
        }
    }

    fn subtask(name: &str, start_values: Vec<f64>, greedy: Option<EpisodeRecord>) -> SubtaskRecord {
        SubtaskRecord {
            name: name.to_owned(),
            episodes: 1,
            env_steps: 1,
            last_episode_steps: 1,
            visited_pairs: 1,
            clusters: None,
            answered_pairs: 0,
            tree_samples: None,
            tree_bytes: None,
            table_bytes: 0,
            greedy_alone: greedy,
            start_values,
            reached_episodes: 0,
            converged: None,
            checks: 0,
            check_env_steps: 0,
            last_check_reached: None,
        }
    }

    fn run(
        method: &str,
        actions: Vec<u64>,
        subtasks: Vec<SubtaskRecord>,
        agrees: Option<(u64, Vec<u64>)>,
    ) -> RunRecord {
        let counts = |(decisions, agrees): (u64, Vec<u64>)| AgreementCounts {
            decisions,
            agrees,
            agrees_with_all: 0,
            missing_experience: 0,
        };
        RunRecord {
            experiment: "robot".to_owned(),
            method: method.to_owned(),
            seed: 0,
            optimum_steps: None,
            subtasks,
            pretrain_env_steps: 0,
            episodes: vec![
                episode(9, false, true),
                episode(4, true, false),
                episode(6, false, false),
            ],
            total_env_steps: 19,
            trajectories: Vec::new(),
            greedy_evaluations: Vec::new(),
            evaluation: episode(4, true, false),
            evaluation_trajectory: TrajectoryRecord {
                episode: 3,
                greedy: true,
                states: vec![0],
                actions: Vec::new(),
                positions: vec![[0.0, 0.0]],
            },
            final_window_episodes: 2,
            final_window_actions: actions,
            agreement: agrees.map(|final_window| AgreementRecord {
                training: counts(final_window.clone()),
                final_window: counts(final_window),
            }),
        }
    }

    /// Ragged runs: the rules for runs that disagree on the number of actions, sub-tasks and
    /// start values hold when the runs arrive one at a time.
    #[test]
    fn ragged_runs_are_pooled_by_the_stated_rules() {
        let greedy = Some(episode(7, false, true));
        let records = [
            run("softmax", vec![1, 2], Vec::new(), None),
            run(
                "ea-madm",
                vec![3, 0, 1],
                vec![subtask("near", vec![1.0, 3.0], greedy.clone())],
                Some((4, vec![1])),
            ),
            run("softmax", vec![0, 1, 5], Vec::new(), None),
            run(
                "ea-madm",
                vec![1, 1, 1],
                vec![
                    subtask("far", vec![2.0, 1.0, 8.0], None),
                    subtask("other", vec![0.5, 0.25], greedy.clone()),
                ],
                Some((6, vec![3, 6])),
            ),
            // A run without agreement counts its sub-tasks' start values, not their agreement.
            run(
                "ea-madm",
                vec![0, 0, 0],
                vec![
                    subtask("far", vec![4.0, 5.0, 2.0], None),
                    subtask("other", vec![0.25, 0.75], None),
                    subtask("third", vec![1.0], None),
                ],
                None,
            ),
        ];
        let methods = behaviour(&records);
        assert_eq!(methods.len(), 2);
        let softmax = &methods[0];
        assert_eq!(softmax.method, "softmax");
        assert_eq!(softmax.seeds, 2);
        assert_eq!(softmax.action_shares, vec![1.0 / 9.0, 3.0 / 9.0, 5.0 / 9.0]);
        // Final window: the last two episodes of each run, one reached and one failed.
        assert_eq!(softmax.final_episodes, 4);
        assert_eq!(
            softmax.final_endings,
            Endings {
                reached: 2,
                failed: 2,
                truncated: 0
            }
        );
        assert_eq!(softmax.seeds_reaching, 2);
        assert_eq!(softmax.mean_final_steps, 5.0);
        assert!(softmax.subtasks.is_empty());

        let ea = &methods[1];
        assert_eq!(ea.decisions, 10);
        // Two sub-tasks: the most of a run with agreement counts (the third run's third is out).
        assert_eq!(ea.subtasks.len(), 2);
        let first = &ea.subtasks[0];
        assert_eq!(first.name, "near");
        // Start values of the runs with the most actions (3) only.
        assert_eq!(first.start_values, vec![3.0, 3.0, 5.0]);
        assert_eq!(first.best_start_action, 2);
        // The mean of each run's own best start value: (3 + 8 + 5) / 3, above the best mean.
        assert_eq!(first.learned_start_value, 16.0 / 3.0);
        assert_eq!(first.agreement, 0.4);
        assert_eq!(first.greedy_alone_steps, 7.0);
        assert_eq!(first.greedy_alone_endings.truncated, 1);
        let second = &ea.subtasks[1];
        assert_eq!(second.start_values, vec![0.375, 0.5]);
        assert_eq!(second.agreement, 0.6);
        assert_eq!(ea.dominant_subtask, Some(1));

        // Streaming the same runs in the same order gives the same numbers, bit for bit.
        let mut accumulator = BehaviourAccumulator::default();
        for record in &records {
            accumulator.push(record);
        }
        assert_eq!(accumulator.finish(), methods);
    }
}
