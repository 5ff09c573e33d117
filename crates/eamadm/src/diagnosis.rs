//! Why a robot run's sub-tasks reach the target or not, in numbers (issue 21 item 3): each
//! sub-task learner's value of the start state, from its Q-table
//! ([`SubtaskRecord::start_values`](crate::record::SubtaskRecord::start_values)), beside what
//! its reward definition (Eq. 6–8, with the run's repairs) makes of reaching, of ending the
//! episode at once and of idling at γ ([`wmr_model::RewardParams::reference_values`]).
//!
//! A learner whose start value sits near "idle" or "lose at once" and far from "reach" has
//! learned what its reward pays for; when no sub-task's reward values reaching above the
//! alternatives, no aggregation of their values can lead to the target.

use serde::Serialize;
use wmr_model::{ReferenceEpisode, ReferenceValues, SUBTASK_COUNT, SUBTASK_NAMES, SubtaskRepairs};

use crate::config::{CompetitorSignal, Method};
use crate::facts::{RewardReference, SubtaskReference};
use crate::record::RunRecord;
use crate::runner::Experiment;
use crate::task::Task;

/// One sub-task's learned start value against its reward's reference values.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SubtaskDiagnosis {
    /// The sub-task's name.
    pub name: String,
    /// `max_a (Q1 + Q2) / 2` of the sub-task's learner at the start state.
    pub learned_start_value: f64,
    /// What its reward definition makes of reaching, losing the target at once and idling.
    pub reference: ReferenceValues,
}

impl SubtaskDiagnosis {
    /// The way of playing (`"reach"`, `"lose at once"`, `"idle"`) whose reference value is
    /// closest to the learned start value: what the learner has most likely learned.
    #[must_use]
    pub fn closest_play(&self) -> &'static str {
        let r = &self.reference;
        [
            (r.reach, "reach"),
            (r.lose_at_once, "lose at once"),
            (r.idle, "idle"),
        ]
        .into_iter()
        .map(|(value, name)| ((value - self.learned_start_value).abs(), name))
        .fold((f64::INFINITY, "reach"), |best, next| {
            if next.0 < best.0 { next } else { best }
        })
        .1
    }

    /// Whether the reward definition values reaching above both ending at once and idling.
    #[must_use]
    pub fn reaching_pays(&self) -> bool {
        self.reference.reach > self.reference.lose_at_once
            && self.reference.reach > self.reference.idle
    }
}

/// The diagnosis of every sub-task of `record` (a run on the robot `task` with the sub-task
/// rewards repaired by `repairs`, discount `gamma`), or `None` when the task is not the robot or
/// the run pre-trained no sub-task (a competitor).
#[must_use]
pub fn subtask_diagnosis(
    task: &Task,
    record: &RunRecord,
    repairs: SubtaskRepairs,
    gamma: f64,
) -> Option<Vec<SubtaskDiagnosis>> {
    if record.subtasks.is_empty() {
        return None;
    }
    let (_, references) = reference_values(task, repairs, gamma)?;
    Some(
        record
            .subtasks
            .iter()
            .zip(references)
            .map(|(subtask, reference)| SubtaskDiagnosis {
                name: subtask.name.clone(),
                learned_start_value: subtask
                    .start_values
                    .iter()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max),
                reference,
            })
            .collect(),
    )
}

/// The reference episode of the robot `task` at discount `gamma` and each sub-task's
/// [`ReferenceValues`] under the sub-task rewards repaired by `repairs`; `None` for a maze.
#[must_use]
pub fn reference_values(
    task: &Task,
    repairs: SubtaskRepairs,
    gamma: f64,
) -> Option<(ReferenceEpisode, [ReferenceValues; SUBTASK_COUNT])> {
    let scenario = task.scenario()?;
    let episode = ReferenceEpisode {
        start_distance: (scenario.target.x - scenario.start.x)
            .hypot(scenario.target.y - scenario.start.y),
        reach_radius: scenario.target.reach_radius,
        step_length: scenario.robot.max_linear_speed() * scenario.control_period,
        step_cap: scenario.step_cap,
        gamma,
        noise: scenario.sensors.noise,
    };
    let mut reward = scenario.reward;
    reward.repairs = repairs;
    let references = reward.reference_values(&episode);
    Some((episode, references))
}

/// The repairs a method's sub-task rewards run with, when it learns from them at all: EA-MADM
/// and a sub-task alone always, a competitor only on a shaped signal.
fn learns_from_subtask_rewards(method: &Method) -> Option<SubtaskRepairs> {
    match method {
        Method::EaMadm(_) | Method::SubtaskGreedy(_) => Some(method.subtask_repairs()),
        Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } => {
            (training.signal != CompetitorSignal::Task).then(|| method.subtask_repairs())
        }
    }
}

/// How a reader names `repairs`: empty for the paper's rewards.
fn repair_names(repairs: SubtaskRepairs) -> Vec<String> {
    let mut names = Vec::new();
    if repairs.reach_goal_bonus {
        names.push("goal bonus for reach".to_owned());
    }
    if repairs.end_penalties {
        names.push("end penalties".to_owned());
    }
    names
}

/// The report's [`RewardReference`]s of a robot `experiment`: one per distinct repair of the
/// sub-task rewards among its methods that learn from them, the paper's rewards first (always
/// present on the robot), each with its methods and the controls that run a sub-task alone.
/// Empty for a maze. The values are discounted at the experiment's learner γ.
#[must_use]
pub fn reward_references(experiment: &Experiment) -> Vec<RewardReference> {
    let config = experiment.config();
    let mut repairs_seen = vec![SubtaskRepairs::PAPER];
    for spec in &config.methods {
        if let Some(repairs) = learns_from_subtask_rewards(&spec.method)
            && !repairs_seen.contains(&repairs)
        {
            repairs_seen.push(repairs);
        }
    }
    repairs_seen
        .into_iter()
        .filter_map(|repairs| {
            let (episode, references) =
                reference_values(experiment.task(), repairs, config.learner.gamma)?;
            let learners = || {
                config
                    .methods
                    .iter()
                    .filter(move |spec| learns_from_subtask_rewards(&spec.method) == Some(repairs))
            };
            Some(RewardReference {
                repairs: repair_names(repairs),
                methods: learners().map(|spec| spec.label.clone()).collect(),
                reach_steps: episode.reach_steps(),
                step_cap: episode.step_cap,
                subtasks: SUBTASK_NAMES
                    .iter()
                    .zip(references)
                    .enumerate()
                    .map(|(k, (name, values))| SubtaskReference {
                        name: (*name).to_owned(),
                        reach: values.reach,
                        lose_at_once: values.lose_at_once,
                        idle: values.idle,
                        alone: learners()
                            .filter_map(|spec| match &spec.method {
                                Method::SubtaskGreedy(alone) if alone.subtask == k => {
                                    Some((spec.label.clone(), alone.learn))
                                }
                                _ => None,
                            })
                            .collect(),
                    })
                    .collect(),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Method;
    use crate::runner::Experiment;

    #[test]
    fn literal_sub_tasks_never_find_reaching_worth_it() {
        let mut config = crate::paper::robot();
        config.episodes = 2;
        config.seeds = 1;
        let mut spec = config.methods[0].clone();
        if let Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = 5;
        }
        config.methods = vec![spec.clone()];
        let experiment = Experiment::new(config).unwrap();
        let record = experiment.run(&spec, 0).unwrap();
        let diagnosis =
            subtask_diagnosis(experiment.task(), &record, SubtaskRepairs::PAPER, 0.95).unwrap();
        assert_eq!(diagnosis.len(), 3);
        assert!(
            diagnosis.iter().all(|d| !d.reaching_pays()),
            "{diagnosis:?}"
        );
        assert_eq!(diagnosis[2].name, "keep_target_in_view");
        // Eq. 8 pays +2 per step in view: idling to the 250-step cap is worth about 2 / (1 − γ)
        assert!((diagnosis[2].reference.idle - 40.0).abs() < 0.01);
        let repaired = SubtaskRepairs {
            reach_goal_bonus: true,
            end_penalties: true,
        };
        let fixed = subtask_diagnosis(experiment.task(), &record, repaired, 0.95).unwrap();
        assert!(fixed[0].reference.reach > fixed[0].reference.lose_at_once);
        let closest = SubtaskDiagnosis {
            name: "x".to_owned(),
            learned_start_value: 39.0,
            reference: diagnosis[2].reference,
        };
        assert_eq!(closest.closest_play(), "idle");
    }

    #[test]
    fn the_robot_preset_has_one_reward_reference_per_repair_with_its_learners() {
        let mut config = crate::paper::robot();
        config.seeds = 1;
        let experiment = Experiment::new(config).unwrap();
        let references = reward_references(&experiment);
        // The paper's rewards, goal bonus, end penalties and both.
        assert_eq!(references.len(), 4);
        let paper = &references[0];
        assert!(paper.repairs.is_empty());
        assert!(paper.methods.iter().any(|m| m == "ea-madm"));
        assert!(paper.methods.iter().any(|m| m == "softmax-shaped"));
        // The competitors on the task reward learn from none of the repaired rewards.
        assert!(
            references
                .iter()
                .all(|r| !r.methods.iter().any(|m| m == "softmax"))
        );
        assert_eq!(paper.subtasks.len(), 3);
        assert!(paper.subtasks.iter().all(|s| !s.reaching_pays()));
        assert_eq!(
            paper.subtasks[0].alone,
            vec![
                ("subtask0-alone".to_owned(), false),
                ("subtask0-alone-learning".to_owned(), true)
            ]
        );
        let both = references.iter().find(|r| r.repairs.len() == 2).unwrap();
        assert!(both.methods.iter().any(|m| m == "ea-madm-repaired"));
        assert!(both.subtasks[0].reach > both.subtasks[0].lose_at_once);
        // A maze has none.
        let maze = Experiment::new(crate::paper::task1()).unwrap();
        assert!(reward_references(&maze).is_empty());
    }
}
