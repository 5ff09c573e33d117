//! What the decision step does with the best sub-task values available, and how far each
//! sub-task's pre-training got, as data (issue 32): the rows of `oracle.csv` and
//! `pretraining.csv`. The facade computes the oracle rows (`eamadm::oracle`); the pre-training
//! rows come from run records ([`pretraining_rows`]). Pure data and CSV, for the report and
//! for readers of the tables.
//!
//! An [`OracleRow`] is one decision rule on one task and seed, fed sub-task values that are
//! exact (`Q*` by value iteration on a maze's known model) or, where no model exists (the
//! robot), pre-trained to convergence (the best available estimate), with the source task's
//! own column at its initial values or at the values its run learned; or one sub-task acting
//! alone on those values. Each row holds its greedy episode from the run's evaluation start
//! (steps, whether it reached, collisions, return) beside the optimum and, on a maze, the share
//! of states in which the decision picks a task-optimal action.
//!
//! For the report: [`oracle_findings`] reads, per task and decision, which part fails
//! ([`FailingPart`]: the decision rule, learning, the sub-task values, or neither) with the facts
//! behind it (the Manhattan bound, seeds reaching with initial and learned own values, seeds on
//! which the decision only follows a sub-task alone, the runs' convergence);
//! [`pretraining_summary`] says per sub-task whether pre-training converged and ever reached.
//!
//! ```
//! use eamadm_eval::oracle::{OracleRow, OracleValues, OwnValues, read_csv, write_csv};
//!
//! let row = OracleRow {
//!     task: "task1".to_owned(),
//!     decision: "ea-madm".to_owned(),
//!     values: OracleValues::Exact,
//!     own_values: OwnValues::Initial,
//!     seed: 0,
//!     optimal_share: Some(0.93),
//!     greedy_steps: 58,
//!     reached: true,
//!     collisions: 0,
//!     task_return: 157.0,
//!     optimum_steps: Some(58),
//!     manhattan_steps: Some(58),
//!     step_cap: 2000,
//! };
//! let mut csv = Vec::new();
//! write_csv(std::slice::from_ref(&row), &mut csv)?;
//! assert_eq!(read_csv(csv.as_slice())?, vec![row]);
//! # Ok::<(), eamadm_eval::oracle::OracleError>(())
//! ```

use std::io::{Read, Write};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::columns::{Column, FieldType};
use crate::record::RunRecord;
use crate::scores::{FinalScore, RunOutcome};

/// Where an oracle row's sub-task values come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum OracleValues {
    /// Each sub-task's exact `Q*`: value iteration on the task's known deterministic model
    /// (the mazes).
    #[serde(rename = "exact")]
    Exact,
    /// Each sub-task pre-trained to convergence by the presets' stopping rule: the best
    /// estimate available where no model is known (the robot). Not exact.
    #[serde(rename = "pretrained-to-convergence")]
    PretrainedToConvergence,
}

impl OracleValues {
    /// The CSV value: `exact` or `pretrained-to-convergence`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::PretrainedToConvergence => "pretrained-to-convergence",
        }
    }
}

/// The source task's own column of the decision matrix in an oracle row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OwnValues {
    /// The source learner's initial values (the decision as it first guides learning).
    Initial,
    /// The values the method's run learned (its source learner at the end of training).
    Learned,
    /// No own column: a sub-task acting alone on its values.
    None,
}

/// One decision rule's greedy behaviour on given sub-task values (a row of `oracle.csv`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OracleRow {
    /// The experiment (`task1`, `task2`, `robot`, `aggregation-control`, …).
    pub task: String,
    /// The decision rule: a method's label (`ea-madm`, `subtasks-mean`, `subtasks-max`: its
    /// aggregation of the decision matrix) or `subtaskK-alone` (sub-task K's own greedy choice).
    pub decision: String,
    /// Where the sub-task values come from.
    pub values: OracleValues,
    /// The source task's own column.
    pub own_values: OwnValues,
    /// The seed: of the run whose learned values, pre-trained sub-tasks, initial values and
    /// evaluation tie-breaks the row uses.
    pub seed: u64,
    /// On a maze: the share of states (free, reachable from the start without passing the
    /// target, the target excluded) in which the decision picks an action on a shortest path,
    /// each state weighted by the probability that the tie-break picks one; `None` on the robot
    /// (no exact optimum per state).
    pub optimal_share: Option<f64>,
    /// Steps of the greedy episode from the evaluation start (the step cap when it never
    /// reaches).
    pub greedy_steps: u64,
    /// Whether that episode reached the target.
    pub reached: bool,
    /// Its collisions (bumps, hits).
    pub collisions: u64,
    /// Its task return.
    pub task_return: f64,
    /// The task's optimum in steps: BFS on a maze, the planner's route on the robot.
    pub optimum_steps: Option<u64>,
    /// On a maze, the Manhattan distance from start to target (the optimum equals it when no
    /// obstacle forces a detour); `None` on the robot.
    pub manhattan_steps: Option<u64>,
    /// The task's episode step cap.
    pub step_cap: u32,
}

/// The columns of `oracle.csv`, in order (the fields of [`OracleRow`]).
pub const ORACLE_COLUMNS: &[Column] = &[
    Column::new("task", FieldType::String, "The experiment's name (`task1`, `task2`, `robot`, `aggregation-control`)."),
    Column::new("decision", FieldType::String, "The decision rule: `ea-madm` (the paper's OWA with visibility weights on the decision matrix of Eq. 13), `subtasks-mean` / `subtasks-max` (the plain aggregators: mean or largest of the standardised columns), each with the method's own settings; or `subtaskK-alone`, sub-task K's own greedy choice."),
    Column::new("values", FieldType::String, "Where the sub-task values come from: `exact`, each sub-task's Q* by value iteration on the maze's known deterministic model; `pretrained-to-convergence`, each sub-task pre-trained by the presets' stopping rule (the robot: no model, so the best estimate available, not exact).").values(&["exact", "pretrained-to-convergence"]),
    Column::new("own_values", FieldType::String, "The source task's own column of the decision matrix: `initial` (the source learner's initial values: the decision as it first guides learning), `learned` (the values the method's run learned by the end of training), `none` (a sub-task alone).").values(&["initial", "learned", "none"]),
    Column::new("seed", FieldType::Integer, "The seed whose initial values, learned values, pre-trained sub-tasks (robot) and evaluation tie-breaks the row uses."),
    Column::new("optimal_share", FieldType::Number, "Share of the maze's states (free, reachable from the start without passing the target, the target excluded) in which the decision picks an action on a shortest path to the target (BFS), each state weighted by the chance that the tie-break picks one.").unit("fraction").blank_when("On the robot: no exact optimal action per state is known."),
    Column::new("greedy_steps", FieldType::Integer, "Steps of the decision's greedy episode (no exploration, no learning) from the run's evaluation start; the step cap when it never reaches.").unit("steps"),
    Column::new("reached", FieldType::Boolean, "Whether that greedy episode reached the target."),
    Column::new("collisions", FieldType::Integer, "Collisions (maze bumps, robot hits) in that episode.").unit("collisions"),
    Column::new("task_return", FieldType::Number, "The task return of that episode.").unit("reward"),
    Column::new("optimum_steps", FieldType::Integer, "The task's optimum: the BFS shortest path of a maze, the planner's route on the robot.").unit("steps").blank_when("When no route is known."),
    Column::new("manhattan_steps", FieldType::Integer, "On a maze, the Manhattan distance from start to target: the optimum equals it when no obstacle forces a detour (the Manhattan bound).").unit("steps").blank_when("On the robot."),
    Column::new("step_cap", FieldType::Integer, "The task's episode step cap.").unit("steps"),
];

/// One sub-task's pre-training in one run (a row of `pretraining.csv`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PretrainingRow {
    /// The experiment.
    pub task: String,
    /// The method whose run pre-trained it (EA-MADM's variants and the sub-task-alone
    /// controls).
    pub method: String,
    /// The run's seed.
    pub seed: u64,
    /// The sub-task's index in the run's record.
    pub subtask: u64,
    /// Its name.
    pub name: String,
    /// Pre-training episodes.
    pub episodes: u64,
    /// Environment steps of pre-training, the stopping rule's checks included.
    pub env_steps: u64,
    /// Steps of the stopping rule's checks.
    pub check_env_steps: u64,
    /// Pre-training episodes that reached the target.
    pub reached_episodes: u64,
    /// With the stopping rule: whether it found the sub-task converged (`false`: stopped at its
    /// cap); `None` for a fixed number of episodes.
    pub converged: Option<bool>,
    /// Whether the last check reached the target (`None` without checks).
    pub last_check_reached: Option<bool>,
    /// Whether the pre-trained sub-task's greedy episode on the task (without learning)
    /// reached the target.
    pub greedy_alone_reached: Option<bool>,
}

/// The columns of `pretraining.csv`, in order (the fields of [`PretrainingRow`]).
pub const PRETRAINING_COLUMNS: &[Column] = &[
    Column::new("task", FieldType::String, "The experiment's name."),
    Column::new("method", FieldType::String, "The method whose run pre-trained the sub-task (EA-MADM, its variants and controls, and each sub-task alone; runs of one seed with the same pre-training config pre-train the same learner)."),
    Column::new("seed", FieldType::Integer, "The run's seed."),
    Column::new("subtask", FieldType::Integer, "The sub-task's index in the run's record (0-based; a sub-task alone has one)."),
    Column::new("name", FieldType::String, "The sub-task's name."),
    Column::new("episodes", FieldType::Integer, "Pre-training episodes: fixed, or decided by the stopping rule (docs/paper-notes.md §21.4).").unit("episodes"),
    Column::new("env_steps", FieldType::Integer, "Environment steps of pre-training, the stopping rule's check episodes included.").unit("steps"),
    Column::new("check_env_steps", FieldType::Integer, "Environment steps of the stopping rule's greedy check episodes (0 without the rule).").unit("steps"),
    Column::new("reached_episodes", FieldType::Integer, "Pre-training episodes (checks not counted) that reached the target.").unit("episodes"),
    Column::new("converged", FieldType::Boolean, "With the stopping rule: whether it found the sub-task converged (false: it stopped at its cap of episodes).").blank_when("For a fixed number of pre-training episodes."),
    Column::new("last_check_reached", FieldType::Boolean, "Whether the stopping rule's last greedy check reached the target.").blank_when("Without the stopping rule."),
    Column::new("greedy_alone_reached", FieldType::Boolean, "Whether the pre-trained sub-task's greedy episode on the task, by itself and without learning, reached the target.").blank_when("When the record has no such episode."),
];

/// The pre-training rows of one run: one per sub-task of its record (none for a method
/// without sub-tasks).
#[must_use]
pub fn pretraining_rows(record: &RunRecord) -> Vec<PretrainingRow> {
    record
        .subtasks
        .iter()
        .enumerate()
        .map(|(k, subtask)| PretrainingRow {
            task: record.experiment.clone(),
            method: record.method.clone(),
            seed: record.seed,
            subtask: k as u64,
            name: subtask.name.clone(),
            episodes: subtask.episodes,
            env_steps: subtask.env_steps,
            check_env_steps: subtask.check_env_steps,
            reached_episodes: subtask.reached_episodes,
            converged: subtask.converged,
            last_check_reached: subtask.last_check_reached,
            greedy_alone_reached: subtask.greedy_alone.as_ref().map(|episode| episode.reached),
        })
        .collect()
}

/// Which part of the method fails on a task, read off the oracle rows and the runs (issue 32:
/// "the decision rule, the learning, or neither").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FailingPart {
    /// With the best sub-task values the decision reaches on every seed a sub-task alone
    /// reaches on, and its runs converge on as many seeds: nothing fails.
    Neither,
    /// With the best sub-task values the decision reaches on more seeds than its runs converge
    /// on: learning (the learned sub-task values or the source task's own) fails.
    Learning,
    /// With the best sub-task values some sub-task alone reaches on a seed on which the
    /// decision does not: the decision rule fails even with those values.
    DecisionRule,
    /// With the best sub-task values neither any decision nor any sub-task alone reaches on any
    /// seed: the sub-tasks carry no route to the target (a decomposition without the
    /// information, or sub-tasks whose training never reached).
    SubtaskValues,
}

/// What the oracle says about one decision rule on one task, for the report's sentence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OracleFinding {
    /// The experiment.
    pub task: String,
    /// The decision rule (a method's label, `ea-madm` for the paper's).
    pub decision: String,
    /// Where the sub-task values come from.
    pub values: OracleValues,
    /// Seeds with an initial-values row of the decision.
    pub seeds: u64,
    /// The task's optimum in steps.
    pub optimum_steps: Option<u64>,
    /// On a maze, the Manhattan distance from start to target.
    pub manhattan_steps: Option<u64>,
    /// Whether the optimum equals the Manhattan distance: no obstacle forces a detour, so the
    /// distance-shaped sub-task alone can be optimal (`None` on the robot).
    pub at_manhattan_bound: Option<bool>,
    /// Seeds on which the decision with the best values and the source task's initial values
    /// reaches the target.
    pub reaches_initial: u64,
    /// Seeds on which it reaches with the values its run learned instead.
    pub reaches_learned: u64,
    /// Median steps of its greedy episodes with the initial own values (the step cap for a
    /// seed that does not reach); `None` without such rows.
    #[serde(default)]
    pub median_steps_initial: Option<f64>,
    /// Median steps with the learned own values.
    #[serde(default)]
    pub median_steps_learned: Option<f64>,
    /// On a maze, the mean over seeds of the share of states whose decision (initial own
    /// values) is a shortest-path action; `None` on the robot.
    #[serde(default)]
    pub optimal_share_initial: Option<f64>,
    /// The same with the learned own values.
    #[serde(default)]
    pub optimal_share_learned: Option<f64>,
    /// The sub-task alone (`subtaskK-alone`) reaching on most seeds (the first of them, so
    /// sub-task 0 when none reaches), and on how many.
    pub best_subtask_alone: Option<(String, u64)>,
    /// Seeds on which the decision's initial-values episode equals that sub-task alone's (the
    /// same steps, reaching or not): the decision only follows it.
    pub equals_subtask_alone: u64,
    /// Seeds on which the decision's own runs converged (`final-scores.csv`), when they ran.
    pub runs_converged: Option<u64>,
    /// Which part fails.
    pub failing_part: FailingPart,
}

/// One [`OracleFinding`] per task and decision of `rows` (in the order they first appear; the
/// sub-tasks alone are not decisions), with the runs' outcomes from `scores`.
#[must_use]
pub fn oracle_findings(rows: &[OracleRow], scores: &[FinalScore]) -> Vec<OracleFinding> {
    let mut keys: Vec<(&str, &str)> = Vec::new();
    for row in rows {
        let key = (row.task.as_str(), row.decision.as_str());
        if row.own_values != OwnValues::None && !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.into_iter()
        .map(|(task, decision)| {
            let of = |own: OwnValues| {
                rows.iter().filter(move |r| {
                    r.task == task && r.decision == decision && r.own_values == own
                })
            };
            let initial: Vec<&OracleRow> = of(OwnValues::Initial).collect();
            let first = initial
                .first()
                .copied()
                .or_else(|| of(OwnValues::Learned).next())
                .expect("a decision has a row");
            let learned: Vec<&OracleRow> = of(OwnValues::Learned).collect();
            let reaches_initial = initial.iter().filter(|r| r.reached).count() as u64;
            let reaches_learned = learned.iter().filter(|r| r.reached).count() as u64;
            let mut alone: Vec<(String, Vec<&OracleRow>)> = Vec::new();
            for row in rows
                .iter()
                .filter(|r| r.task == task && r.own_values == OwnValues::None)
            {
                match alone.iter_mut().find(|(name, _)| *name == row.decision) {
                    Some((_, seeds)) => seeds.push(row),
                    None => alone.push((row.decision.clone(), vec![row])),
                }
            }
            let reaching = |seeds: &[&OracleRow]| seeds.iter().filter(|r| r.reached).count() as u64;
            // The first sub-task among those reaching on most seeds (sub-task 0, the reach
            // sub-task, when none reaches).
            let best = alone
                .iter()
                .fold(
                    None::<&(String, Vec<&OracleRow>)>,
                    |best, candidate| match best {
                        Some(best) if reaching(&best.1) >= reaching(&candidate.1) => Some(best),
                        _ => Some(candidate),
                    },
                )
                .map(|(name, seeds)| (name.clone(), seeds.clone()));
            let equals_subtask_alone = best.as_ref().map_or(0, |(_, seeds)| {
                initial
                    .iter()
                    .filter(|row| {
                        seeds.iter().any(|other| {
                            other.seed == row.seed
                                && other.reached == row.reached
                                && other.greedy_steps == row.greedy_steps
                        })
                    })
                    .count() as u64
            });
            // A seed some sub-task alone reaches on and the decision (initial values) does not.
            let rule_misses = initial.iter().any(|row| {
                !row.reached
                    && alone.iter().any(|(_, seeds)| {
                        seeds
                            .iter()
                            .any(|other| other.seed == row.seed && other.reached)
                    })
            });
            let any_reaches = reaches_initial > 0
                || reaches_learned > 0
                || alone.iter().any(|(_, seeds)| reaching(seeds) > 0);
            let runs: Vec<&FinalScore> = scores
                .iter()
                .filter(|score| score.task == task && score.method == decision)
                .collect();
            let runs_converged = (!runs.is_empty()).then(|| {
                runs.iter()
                    .filter(|score| score.outcome == RunOutcome::Converged)
                    .count() as u64
            });
            let failing_part = if !any_reaches {
                FailingPart::SubtaskValues
            } else if rule_misses {
                FailingPart::DecisionRule
            } else if runs_converged.is_some_and(|converged| converged < reaches_initial) {
                FailingPart::Learning
            } else {
                FailingPart::Neither
            };
            OracleFinding {
                task: task.to_owned(),
                decision: decision.to_owned(),
                values: first.values,
                seeds: initial.len() as u64,
                optimum_steps: first.optimum_steps,
                manhattan_steps: first.manhattan_steps,
                at_manhattan_bound: first
                    .manhattan_steps
                    .map(|manhattan| first.optimum_steps == Some(manhattan)),
                reaches_initial,
                reaches_learned,
                median_steps_initial: median_steps(&initial),
                median_steps_learned: median_steps(&learned),
                optimal_share_initial: mean_share(&initial),
                optimal_share_learned: mean_share(&learned),
                best_subtask_alone: best.map(|(name, seeds)| {
                    let n = reaching(&seeds);
                    (name, n)
                }),
                equals_subtask_alone,
                runs_converged,
                failing_part,
            }
        })
        .collect()
}

/// The median greedy steps of `rows` (the mean of the two middle ones for an even count).
fn median_steps(rows: &[&OracleRow]) -> Option<f64> {
    let mut steps: Vec<u64> = rows.iter().map(|r| r.greedy_steps).collect();
    steps.sort_unstable();
    let n = steps.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(steps[n / 2] as f64),
        _ => Some((steps[n / 2 - 1] as f64 + steps[n / 2] as f64) / 2.0),
    }
}

/// The mean optimal-action share of `rows`, when every row has one.
fn mean_share(rows: &[&OracleRow]) -> Option<f64> {
    let shares: Option<Vec<f64>> = rows.iter().map(|r| r.optimal_share).collect();
    let shares = shares?;
    (!shares.is_empty()).then(|| shares.iter().sum::<f64>() / shares.len() as f64)
}

/// The reach sub-task's pre-training (sub-task 0: the sub-task paid for reaching the target
/// in every preset) of each method that pre-trains more than one sub-task (EA-MADM, its
/// variants and the plain aggregators; not a sub-task alone), per task, in first-appearance
/// order: what the report says about whether pre-training ever reached.
#[must_use]
pub fn reach_pretraining(rows: &[PretrainingRow]) -> Vec<PretrainingSummary> {
    let several: std::collections::BTreeSet<(&str, &str)> = rows
        .iter()
        .filter(|r| r.subtask > 0)
        .map(|r| (r.task.as_str(), r.method.as_str()))
        .collect();
    let reach: Vec<PretrainingRow> = rows
        .iter()
        .filter(|r| r.subtask == 0 && several.contains(&(r.task.as_str(), r.method.as_str())))
        .cloned()
        .collect();
    pretraining_summary(&reach)
}

/// One sub-task's pre-training over the seeds of one method's runs: whether it converged and
/// whether it ever reached the target (for the robot, the question of issue 32).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PretrainingSummary {
    /// The experiment.
    pub task: String,
    /// The method whose runs pre-trained it.
    pub method: String,
    /// The sub-task's index in the runs' records.
    pub subtask: u64,
    /// Its name.
    pub name: String,
    /// Seeds (runs).
    pub seeds: u64,
    /// Seeds on which the stopping rule found it converged (`None` without the rule).
    pub converged_seeds: Option<u64>,
    /// Seeds on which at least one pre-training episode reached the target.
    pub seeds_reaching: u64,
    /// Pre-training episodes that reached the target, over all seeds.
    pub reaching_episodes: u64,
    /// Seeds on which its pre-trained greedy episode alone reached the target.
    pub greedy_alone_reaching: u64,
    /// Mean pre-training episodes per seed.
    pub mean_episodes: f64,
    /// Mean pre-training environment steps per seed (checks included).
    pub mean_env_steps: f64,
}

/// [`PretrainingSummary`] per task, method and sub-task of `rows`, in first-appearance order.
#[must_use]
pub fn pretraining_summary(rows: &[PretrainingRow]) -> Vec<PretrainingSummary> {
    let mut groups: Vec<Vec<&PretrainingRow>> = Vec::new();
    for row in rows {
        match groups.iter_mut().find(|group| {
            let first = group[0];
            first.task == row.task && first.method == row.method && first.subtask == row.subtask
        }) {
            Some(group) => group.push(row),
            None => groups.push(vec![row]),
        }
    }
    groups
        .into_iter()
        .map(|group| {
            let first = group[0];
            let n = group.len() as f64;
            let count =
                |f: &dyn Fn(&PretrainingRow) -> bool| group.iter().filter(|r| f(r)).count() as u64;
            PretrainingSummary {
                task: first.task.clone(),
                method: first.method.clone(),
                subtask: first.subtask,
                name: first.name.clone(),
                seeds: group.len() as u64,
                converged_seeds: group
                    .iter()
                    .any(|r| r.converged.is_some())
                    .then(|| count(&|r| r.converged == Some(true))),
                seeds_reaching: count(&|r| r.reached_episodes > 0),
                reaching_episodes: group.iter().map(|r| r.reached_episodes).sum(),
                greedy_alone_reaching: count(&|r| r.greedy_alone_reached == Some(true)),
                mean_episodes: group.iter().map(|r| r.episodes as f64).sum::<f64>() / n,
                mean_env_steps: group.iter().map(|r| r.env_steps as f64).sum::<f64>() / n,
            }
        })
        .collect()
}

/// Writing or reading `oracle.csv` or `pretraining.csv` failed.
#[derive(Debug, Error)]
#[error("oracle tables: {0}")]
pub struct OracleError(#[from] csv::Error);

fn write_rows<W: Write, T: Serialize>(
    rows: &[T],
    columns: &[Column],
    writer: W,
) -> Result<(), OracleError> {
    let mut csv = csv::Writer::from_writer(writer);
    if rows.is_empty() {
        csv.write_record(columns.iter().map(|c| c.name))?;
    }
    for row in rows {
        csv.serialize(row)?;
    }
    csv.flush().map_err(csv::Error::from)?;
    Ok(())
}

/// Writes `rows` as `oracle.csv`: a header of [`ORACLE_COLUMNS`]' names, one row each; empty
/// cells for absent values; floats printed so that they read back bit for bit.
///
/// # Errors
/// [`OracleError`] when writing fails.
pub fn write_csv<W: Write>(rows: &[OracleRow], writer: W) -> Result<(), OracleError> {
    write_rows(rows, ORACLE_COLUMNS, writer)
}

/// Reads an `oracle.csv` written by [`write_csv`].
///
/// # Errors
/// [`OracleError`] for unreadable or malformed input (naming the line).
pub fn read_csv<R: Read>(reader: R) -> Result<Vec<OracleRow>, OracleError> {
    let mut csv = csv::Reader::from_reader(reader);
    Ok(csv.deserialize().collect::<Result<_, _>>()?)
}

/// Writes `rows` as `pretraining.csv` (header [`PRETRAINING_COLUMNS`]).
///
/// # Errors
/// [`OracleError`] when writing fails.
pub fn write_pretraining_csv<W: Write>(
    rows: &[PretrainingRow],
    writer: W,
) -> Result<(), OracleError> {
    write_rows(rows, PRETRAINING_COLUMNS, writer)
}

/// Reads a `pretraining.csv` written by [`write_pretraining_csv`].
///
/// # Errors
/// [`OracleError`] for unreadable or malformed input (naming the line).
pub fn read_pretraining_csv<R: Read>(reader: R) -> Result<Vec<PretrainingRow>, OracleError> {
    let mut csv = csv::Reader::from_reader(reader);
    Ok(csv.deserialize().collect::<Result<_, _>>()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row() -> OracleRow {
        OracleRow {
            task: "robot".to_owned(),
            decision: "subtask0-alone".to_owned(),
            values: OracleValues::PretrainedToConvergence,
            own_values: OwnValues::None,
            seed: 3,
            optimal_share: None,
            greedy_steps: 250,
            reached: false,
            collisions: 1,
            task_return: -0.1 + 0.2,
            optimum_steps: Some(17),
            manhattan_steps: None,
            step_cap: 250,
        }
    }

    fn at(task: &str, decision: &str, own: OwnValues, seed: u64, reached: bool) -> OracleRow {
        OracleRow {
            task: task.to_owned(),
            decision: decision.to_owned(),
            values: OracleValues::Exact,
            own_values: own,
            seed,
            optimal_share: Some(1.0),
            greedy_steps: if reached { 58 } else { 2000 },
            reached,
            collisions: 0,
            task_return: 0.0,
            optimum_steps: Some(58),
            manhattan_steps: Some(if task == "bound" { 58 } else { 24 }),
            step_cap: 2000,
        }
    }

    fn score(task: &str, method: &str, seed: u64, converged: bool) -> FinalScore {
        let mut row: FinalScore = serde_json::from_value(serde_json::json!({
            "task": task, "layout": task, "method": method, "role": "paper", "kind": "ea_madm", "seed": seed,
            "episodes": 10, "final_window": 10, "final_steps": 58.0, "final_return": 0.0,
            "success_rate": 1.0, "greedy_reached": converged, "greedy_steps": 58,
            "outcome": "converged", "fluctuation_steps": 0.0, "fluctuation_return": 0.0,
            "greedy_evaluations": 0, "env_steps_total": 0, "pretrain_env_steps": 0,
            "step_cap": 2000, "reaching_episodes": 0
        }))
        .unwrap();
        if !converged {
            row.outcome = RunOutcome::NeverReached;
        }
        row
    }

    /// Each part that can fail, from rows that show it: the decision follows the sub-task
    /// alone everywhere (neither, or learning when the runs converge less), misses where a
    /// sub-task alone reaches (the rule), or nothing reaches at all (the sub-task values).
    #[test]
    fn findings_name_the_part_that_fails() {
        use OwnValues::{Initial, Learned, None as Alone};
        let mut rows = Vec::new();
        for seed in 0..2 {
            for (task, decision_reaches, alone_reaches) in [
                ("bound", true, true),
                ("learning", true, true),
                ("rule", seed == 0, true),
                ("trap", false, false),
            ] {
                rows.push(at(task, "ea-madm", Initial, seed, decision_reaches));
                rows.push(at(task, "ea-madm", Learned, seed, decision_reaches));
                rows.push(at(task, "subtask0-alone", Alone, seed, alone_reaches));
                rows.push(at(task, "subtask1-alone", Alone, seed, false));
            }
        }
        let scores = vec![
            score("bound", "ea-madm", 0, true),
            score("bound", "ea-madm", 1, true),
            score("learning", "ea-madm", 0, true),
            score("learning", "ea-madm", 1, false),
        ];
        let findings = oracle_findings(&rows, &scores);
        let part = |task: &str| {
            findings
                .iter()
                .find(|f| f.task == task)
                .map(|f| f.failing_part)
                .unwrap()
        };
        assert_eq!(part("bound"), FailingPart::Neither);
        assert_eq!(part("learning"), FailingPart::Learning);
        assert_eq!(part("rule"), FailingPart::DecisionRule);
        assert_eq!(part("trap"), FailingPart::SubtaskValues);
        let bound = &findings[0];
        assert_eq!(bound.at_manhattan_bound, Some(true));
        assert_eq!(
            (bound.reaches_initial, bound.reaches_learned, bound.seeds),
            (2, 2, 2)
        );
        assert_eq!(
            bound.best_subtask_alone,
            Some(("subtask0-alone".to_owned(), 2))
        );
        assert_eq!(bound.equals_subtask_alone, 2);
        assert_eq!(bound.runs_converged, Some(2));
        let trap = findings.iter().find(|f| f.task == "trap").unwrap();
        assert_eq!(trap.at_manhattan_bound, Some(false));
        assert_eq!(
            trap.best_subtask_alone,
            Some(("subtask0-alone".to_owned(), 0))
        );
        assert_eq!(trap.runs_converged, None);
        assert_eq!(trap.equals_subtask_alone, 2, "trapped alike");
        assert_eq!(findings.len(), 4, "sub-tasks alone are not decisions");
    }

    #[test]
    fn the_pretraining_summary_counts_per_sub_task() {
        let row = |seed: u64, subtask: u64, reached: u64, converged: Option<bool>| PretrainingRow {
            task: "robot".to_owned(),
            method: "ea-madm".to_owned(),
            seed,
            subtask,
            name: format!("s{subtask}"),
            episodes: if converged == Some(true) { 200 } else { 1000 },
            env_steps: 100 * (seed + 1),
            check_env_steps: 10,
            reached_episodes: reached,
            converged,
            last_check_reached: converged.map(|_| false),
            greedy_alone_reached: Some(reached > 5),
        };
        let rows = vec![
            row(0, 0, 0, Some(false)),
            row(0, 1, 3, Some(true)),
            row(1, 0, 7, Some(true)),
            row(1, 1, 0, Some(true)),
        ];
        let summary = pretraining_summary(&rows);
        assert_eq!(summary.len(), 2);
        let reach = &summary[0];
        assert_eq!((reach.subtask, reach.seeds), (0, 2));
        assert_eq!(reach.converged_seeds, Some(1));
        assert_eq!((reach.seeds_reaching, reach.reaching_episodes), (1, 7));
        assert_eq!(reach.greedy_alone_reaching, 1);
        assert_eq!(reach.mean_episodes, 600.0);
        assert_eq!(reach.mean_env_steps, 150.0);
        assert_eq!(summary[1].converged_seeds, Some(2));
        let fixed: Vec<PretrainingRow> = rows
            .into_iter()
            .map(|r| PretrainingRow {
                converged: None,
                ..r
            })
            .collect();
        assert_eq!(pretraining_summary(&fixed)[0].converged_seeds, None);
    }

    #[test]
    fn the_headers_are_the_documented_columns() {
        let mut csv = Vec::new();
        write_csv(&[row()], &mut csv).unwrap();
        let text = String::from_utf8(csv).unwrap();
        assert_eq!(
            text.lines().next().unwrap(),
            crate::columns::names(ORACLE_COLUMNS).join(",")
        );
        assert!(text.contains(",pretrained-to-convergence,none,3,,250,false,1,"));
        assert_eq!(read_csv(text.as_bytes()).unwrap(), vec![row()]);
        let mut empty = Vec::new();
        write_csv(&[], &mut empty).unwrap();
        assert_eq!(
            String::from_utf8(empty).unwrap().trim_end(),
            crate::columns::names(ORACLE_COLUMNS).join(",")
        );

        let pretraining = PretrainingRow {
            task: "robot".to_owned(),
            method: "ea-madm".to_owned(),
            seed: 0,
            subtask: 0,
            name: "reach_target_faster".to_owned(),
            episodes: 1000,
            env_steps: 8223,
            check_env_steps: 600,
            reached_episodes: 0,
            converged: Some(false),
            last_check_reached: Some(false),
            greedy_alone_reached: None,
        };
        let mut csv = Vec::new();
        write_pretraining_csv(std::slice::from_ref(&pretraining), &mut csv).unwrap();
        let text = String::from_utf8(csv).unwrap();
        assert_eq!(
            text.lines().next().unwrap(),
            crate::columns::names(PRETRAINING_COLUMNS).join(",")
        );
        assert_eq!(
            read_pretraining_csv(text.as_bytes()).unwrap(),
            vec![pretraining]
        );
    }
}
