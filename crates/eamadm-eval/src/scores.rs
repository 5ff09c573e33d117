//! Per-seed final scores: one [`FinalScore`] per (task, method, seed), computed from a
//! [`RunRecord`], and `final-scores.csv` (tidy: one row per run, one column per metric) that
//! pandas, R or rliable read directly and from which every number of
//! [`claims`](crate::claims) can be recomputed.
//!
//! The metrics, per run:
//!
//! - **Final window** (C1, C2): the last [`FINAL_WINDOW`] training episodes (all of them when a
//!   run is shorter), as the report has always used. `final_steps` and `final_return` are the
//!   means of steps and task return over it, `success_rate` the share of its episodes that
//!   reached the target.
//! - **Greedy fluctuation** (C3, deciding): during training the runner plays one greedy
//!   episode of the current policy every `k` training episodes (no exploration, no learning;
//!   `RunRecord::greedy_evaluations`). Over those taken in the second half of training
//!   ([`greedy_in_second_half`]: after training episodes `⌊E/2⌋ .. E`), a seed is
//!   **stable-reaching** (`stable_reaching`) when every one of them reached the target; its
//!   `fluctuation_greedy_steps` and `fluctuation_greedy_return` are the sample SDs (divisor
//!   n − 1) of their steps and task return. A seed that fails any of them has no greedy
//!   fluctuation (an empty cell): a policy stuck at the step cap repeats the same 2000 steps
//!   and would have SD 0, the "most stable" of all, so it counts as a failure to reach
//!   (`stable_reaching = false`), never as stability. A seed with fewer than two evaluations
//!   there has no SD either (empty cell). Exploration is not part of these episodes, so a
//!   fixed-ε method is measured on the policy it learned, not on its coin.
//! - **Training-curve fluctuation** (C3, secondary, not deciding): the sample SD of steps and
//!   of task return over the second half of training's episodes (`fluctuation_steps`,
//!   `fluctuation_return`), the curves the paper plots. Exploration is part of them: a fixed-ε
//!   method (ε-greedy, ε = 0.1) keeps taking random actions to the end and its curves keep that
//!   noise, while the decreasing schedules (ε-decreasing, EA-MADM: ε < 0.006 after episode 100)
//!   hardly explore in the second half, and a seed stuck at the step cap has SD 0. They are kept
//!   as the paper's own reading, reported but not judged on.
//! - **Reaching episodes** (C4, robot): the paper takes "100 episodes that are to reach the
//!   target". We take a run's first [`REACHING_EPISODES`] training episodes that reached the
//!   target (all of them when fewer did) and report how many (`reaching_episodes`). Over them:
//!   the mean average reward (return per second), the mean time to reach the target, the mean
//!   retention time, and `retention_decay`, the least-squares slope of retention time (seconds)
//!   against the reaching episode's index 0, 1, … (seconds per reaching episode; the paper's
//!   Fig. 15 plots retention time against that index). A linear slope rather than a slope of
//!   log retention time, because retention time is often exactly 0 and its logarithm is then
//!   undefined. More negative is a faster fall. A run with no reaching episode has empty C4
//!   cells (never NaN); a slope needs two reaching episodes.
//!
//! `eamadm`'s crate docs compute, write and read back the scores of a tiny experiment
//! (`eamadm::scores::final_scores(&records, experiment.config())`).

use std::io::{Read, Write};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::Role;
use crate::columns::{Column, FieldType};
use crate::reaching::ReachingMetric;
use crate::record::{EpisodeRecord, RunRecord};
use crate::stats::{self, StatsError};

/// Training episodes at the end of a run over which `final_*` scores are averaged.
pub const FINAL_WINDOW: usize = crate::summary::DEFAULT_FINAL_WINDOW;

/// Most reaching episodes a run contributes to its C4 scores: the paper's "100 episodes that
/// are to reach the target".
pub const REACHING_EPISODES: usize = 100;

/// The columns of `final-scores.csv`, in order (the fields of [`FinalScore`]), each with its
/// type, unit, meaning and when it is blank: the source of `datapackage.json` and of
/// `docs/outputs.md`. A new field of [`FinalScore`] needs its entry here (a test compares the
/// CSV header with this table).
pub const COLUMNS: &[Column] = &[
    Column::new("task", FieldType::String, "The experiment's name: `task1`, `task2`, `robot`, `robot-paper-state`, or a custom config's `name`."),
    Column::new("layout", FieldType::String, "What the run's task is played on: a maze's layout as `layouts.csv` names it (`task1`, `task2`, `aggregation-control`, a family layout `f07-trap`; readings and tuning trials play their task's layout), the robot's scenario by its `name` (`fig12`, the embedded analogue of the paper's Fig. 12), which `layouts.csv` does not list."),
    Column::new("method", FieldType::String, "The method's label in the experiment's config (e.g. `ea-madm`, `softmax`, `subtask0-alone`)."),
    Column::new("role", FieldType::String, "Why the method is in the experiment: one of the paper's methods, an ablation of EA-MADM, or a control the paper does not run.").values(&["paper", "ablation", "control"]),
    Column::new("kind", FieldType::String, "The method's algorithm (`eamadm::Method::kind_name`), e.g. `ea_madm`, `epsilon_greedy`, `epsilon_decreasing`, `softmax`."),
    Column::new("seed", FieldType::Integer, "The run's seed. Runs of one seed share their random streams across methods, so rows of equal task and seed pair."),
    Column::new("episodes", FieldType::Integer, "Training episodes of the source task in the run (sub-task pre-training not counted).").unit("episodes"),
    Column::new("final_window", FieldType::Integer, "Episodes in the final window: the last 20 training episodes, or all of them in a shorter run.").unit("episodes"),
    Column::new("final_steps", FieldType::Number, "Mean steps per episode over the final window (claim C1).").unit("steps"),
    Column::new("final_return", FieldType::Number, "Mean task return (sum of the task's own rewards) per episode over the final window (claim C2).").unit("reward"),
    Column::new("success_rate", FieldType::Number, "Share of the final window's episodes that reached the target, 0 to 1.").unit("fraction"),
    Column::new("greedy_reached", FieldType::Boolean, "Whether the greedy evaluation episode after training (the final greedy policy: no exploration, no learning) reached the target."),
    Column::new("greedy_steps", FieldType::Integer, "Steps of that greedy evaluation episode (the step cap when it loops).").unit("steps"),
    Column::new("outcome", FieldType::String, "How the run ended: `converged` (the greedy policy reaches), `collapsed` (it does not, no final-window episode does, an earlier one did), `reaches_while_learning` (it does not, but final-window training episodes still reach), `never_reached` (no episode ever reached).").values(&["converged", "collapsed", "reaches_while_learning", "never_reached"]),
    Column::new("collapse_episode", FieldType::Integer, "For a collapsed run, the first training episode (0-based) of its permanent non-reaching tail: one past the last episode that reached.").unit("episode").blank_when("the outcome is not `collapsed`"),
    Column::new("fluctuation_steps", FieldType::Number, "Sample standard deviation (divisor n − 1) of steps per episode over the second half of training, episodes ⌊E/2⌋ to E − 1 (claim C3, secondary: exploration included).").unit("steps"),
    Column::new("fluctuation_return", FieldType::Number, "Sample standard deviation (divisor n − 1) of task return per episode over the second half of training (claim C3, secondary).").unit("reward"),
    Column::new("greedy_evaluations", FieldType::Integer, "Greedy evaluations taken in the second half of training: after every `evaluation.every`-th training episode (default 10) the run plays one episode of its current greedy policy (no exploration, no learning, the task's step cap), on its own random streams, so training is unchanged. C3 is judged on these.").unit("evaluations"),
    Column::new("stable_reaching", FieldType::Boolean, "Whether every greedy evaluation of the second half of training reached the target (claim C3): a seed stuck at the step cap is not stable-reaching.").blank_when("the run has no greedy evaluation in the second half of training"),
    Column::new("fluctuation_greedy_steps", FieldType::Number, "Sample standard deviation (divisor n − 1) of the steps of the greedy evaluations in the second half of training (claim C3, deciding).").unit("steps").blank_when("the run is not stable-reaching (a failure for C3, not stability), or it has fewer than two greedy evaluations in the second half"),
    Column::new("fluctuation_greedy_return", FieldType::Number, "Sample standard deviation (divisor n − 1) of the task return of the greedy evaluations in the second half of training (claim C3, deciding).").unit("reward").blank_when("the run is not stable-reaching (a failure for C3, not stability), or it has fewer than two greedy evaluations in the second half"),
    Column::new("env_steps_total", FieldType::Integer, "Environment steps of the whole run: sub-task pre-training plus training (not the greedy evaluation).").unit("steps"),
    Column::new("pretrain_env_steps", FieldType::Integer, "Environment steps spent before the recorded episodes: EA-MADM's (or a sub-task alone's) sub-task pre-training, a budget-matched competitor's warm-up; 0 for the paper's competitors.").unit("steps"),
    Column::new("step_cap", FieldType::Integer, "The task's step cap: an episode is truncated after this many steps (2000 for the paper's mazes, the scenario's for the robot, or the config's `task.step_cap`). A run whose `final_steps` equals it finished no episode of its final window.").unit("steps"),
    Column::new("optimum_steps", FieldType::Integer, "The task's optimal route in steps: the BFS shortest path of a maze, the planner's shortest route for the robot.").unit("steps").blank_when("no route is known (the robot's planner found none)"),
    Column::new("reaching_episodes", FieldType::Integer, "Reaching episodes the C4 scores are taken over: the run's first training episodes that reached the target, at most 100 (the paper's \"100 episodes that are to reach the target\").").unit("episodes"),
    Column::new("reach_average_reward", FieldType::Number, "Mean average reward (episode return divided by its duration) over the reaching episodes (claim C4).").unit("reward/s").blank_when("the task is not the robot, or no training episode reached the target"),
    Column::new("reach_time", FieldType::Number, "Mean time to reach the target over the reaching episodes (claim C4).").unit("s").blank_when("the task is not the robot, or no training episode reached the target"),
    Column::new("reach_retention_time", FieldType::Number, "Mean retention time (time stalled in front of an obstacle) over the reaching episodes.").unit("s").blank_when("the task is not the robot, or no training episode reached the target"),
    Column::new("retention_decay", FieldType::Number, "Least-squares slope of retention time against the reaching episode's index 0, 1, … (claim C4); negative: it falls.").unit("s/episode").blank_when("the task is not the robot, fewer than two training episodes reached the target, or the slope is not finite"),
];

/// How a run ended, from what its record holds: the greedy evaluation episode after training
/// (the final greedy policy, no exploration, no learning) and the `reached` flag of every
/// training episode. Exactly one applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunOutcome {
    /// The final greedy policy reaches the target.
    Converged,
    /// The final greedy policy does not reach the target, and neither does any episode of
    /// the final window, but an earlier training episode did: the run reached and then
    /// stopped reaching for good. The episode it happened (one past the last reaching one) is
    /// [`FinalScore::collapse_episode`].
    Collapsed,
    /// The final greedy policy does not reach the target, but training episodes of the final
    /// window still do: the learner reaches only while it keeps learning (online updates
    /// break the loops the frozen greedy policy falls into).
    ReachesWhileLearning,
    /// Neither the final greedy policy nor any training episode reached the target.
    NeverReached,
}

impl RunOutcome {
    /// Every outcome, in table order.
    pub const ALL: [Self; 4] = [
        Self::Converged,
        Self::Collapsed,
        Self::ReachesWhileLearning,
        Self::NeverReached,
    ];

    /// The CSV name: `converged`, `collapsed` or `never_reached`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Converged => "converged",
            Self::Collapsed => "collapsed",
            Self::ReachesWhileLearning => "reaches_while_learning",
            Self::NeverReached => "never_reached",
        }
    }

    /// The outcome of a run whose greedy evaluation `greedy_reached`, with its training
    /// episodes `episodes` and a final window of the last `window` of them, and the collapse
    /// episode when it collapsed.
    #[must_use]
    pub fn of(
        greedy_reached: bool,
        episodes: &[EpisodeRecord],
        window: usize,
    ) -> (Self, Option<u64>) {
        if greedy_reached {
            return (Self::Converged, None);
        }
        let window_start = episodes.len().saturating_sub(window);
        match episodes.iter().rposition(|e| e.reached) {
            Some(last) if last >= window_start => (Self::ReachesWhileLearning, None),
            Some(last) => (Self::Collapsed, Some(last as u64 + 1)),
            None => (Self::NeverReached, None),
        }
    }
}

/// Scores that cannot be computed.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ScoresError {
    /// A run with no training episode.
    #[error("run {method} seed {seed} of {task}: no training episode; give `episodes` ≥ 1")]
    NoEpisodes {
        /// The experiment.
        task: String,
        /// The method's label.
        method: String,
        /// The seed.
        seed: u64,
    },
    /// A record whose method the config does not have.
    #[error(
        "run {method} seed {seed}: the config of {task} has no method with that label; pass the \
         config the records were made with"
    )]
    UnknownMethod {
        /// The experiment.
        task: String,
        /// The label.
        method: String,
        /// The seed.
        seed: u64,
    },
    /// A statistic failed (a non-finite return).
    #[error("run {method} seed {seed} of {task}: {source}")]
    Stats {
        /// The experiment.
        task: String,
        /// The label.
        method: String,
        /// The seed.
        seed: u64,
        /// Why.
        #[source]
        source: Box<StatsError>,
    },
    /// Reading or writing the CSV failed.
    #[error("final-scores CSV: {0}")]
    Csv(#[from] csv::Error),
}

/// The final scores of one run (one task, method and seed): one row of `final-scores.csv`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FinalScore {
    /// The experiment's name (`task1`, `task2`, `robot`, or a custom config's).
    pub task: String,
    /// What the run's task is played on ([`MethodRoles::layout`]): a maze's layout as
    /// `layouts.csv` names it (`task1`, `f07-trap`, …), the robot's scenario (`fig12`).
    pub layout: String,
    /// The method's label.
    pub method: String,
    /// Why the method is in the experiment: `paper`, `ablation` or `control`.
    pub role: Role,
    /// The method's kind (`eamadm::Method::kind_name`): `ea_madm`,
    /// `epsilon_greedy`, `softmax`, ….
    pub kind: String,
    /// The run's seed.
    pub seed: u64,
    /// Training episodes of the run.
    pub episodes: u64,
    /// Episodes in the final window (`min(FINAL_WINDOW, episodes)`).
    pub final_window: usize,
    /// Mean steps per episode over the final window (C1).
    pub final_steps: f64,
    /// Mean task return per episode over the final window (C2).
    pub final_return: f64,
    /// Share of final-window episodes that reached the target.
    pub success_rate: f64,
    /// Whether the greedy evaluation episode after training reached the target.
    pub greedy_reached: bool,
    /// Steps of the greedy evaluation episode.
    pub greedy_steps: u64,
    /// How the run ended (see [`RunOutcome`]).
    pub outcome: RunOutcome,
    /// For a [`RunOutcome::Collapsed`] run, the first training episode of its permanent
    /// non-reaching tail (one past the last training episode that reached); empty otherwise.
    pub collapse_episode: Option<u64>,
    /// Sample SD of steps per episode over the second half of training (C3).
    pub fluctuation_steps: f64,
    /// Sample SD of task return per episode over the second half of training (C3).
    pub fluctuation_return: f64,
    /// Periodic greedy evaluations in the second half of training: those taken after
    /// training episodes `⌊E/2⌋ .. E` (the episodes `fluctuation_steps` is taken over); 0 for
    /// a record without them.
    pub greedy_evaluations: u64,
    /// Whether every one of those evaluations reached the target (C3's stable-reaching
    /// seed); empty when there is none.
    pub stable_reaching: Option<bool>,
    /// Sample SD of the steps of those evaluations (C3, deciding): only for a stable-reaching
    /// seed with at least two of them, empty otherwise — a seed stuck at the step cap has SD
    /// 0 there, and counts as a failure to reach, not as stability.
    pub fluctuation_greedy_steps: Option<f64>,
    /// Sample SD of the task return of those evaluations (C3, deciding); filled as
    /// `fluctuation_greedy_steps`.
    pub fluctuation_greedy_return: Option<f64>,
    /// Environment steps of the whole run, sub-task pre-training included.
    pub env_steps_total: u64,
    /// Environment steps of sub-task pre-training (0 for the competitors).
    pub pretrain_env_steps: u64,
    /// The task's step cap (an episode is truncated after this many steps): a seed whose
    /// `final_steps` equals it never finished an episode in its final window.
    pub step_cap: u32,
    /// The task's optimal route in steps, when known (BFS for a maze, the planner's route for
    /// the robot).
    pub optimum_steps: Option<u64>,
    /// Reaching episodes the C4 scores are taken over (at most [`REACHING_EPISODES`]).
    pub reaching_episodes: u64,
    /// Mean average reward (return per second) over the reaching episodes (C4; robot only).
    pub reach_average_reward: Option<f64>,
    /// Mean time to reach the target in seconds over the reaching episodes (C4; robot only).
    pub reach_time: Option<f64>,
    /// Mean retention time in seconds over the reaching episodes (robot only).
    pub reach_retention_time: Option<f64>,
    /// Least-squares slope of retention time against reaching-episode index, in seconds per
    /// reaching episode (C4; robot only, at least two reaching episodes). Negative: it falls.
    pub retention_decay: Option<f64>,
}

impl FinalScore {
    /// The value of a numeric column of [`COLUMNS`] (`None` for an empty cell or a text
    /// column). Booleans are 0 or 1.
    #[must_use]
    #[expect(
        clippy::cast_precision_loss,
        reason = "step counts and seeds are far below 2^52"
    )]
    pub fn value(&self, column: &str) -> Option<f64> {
        match column {
            "seed" => Some(self.seed as f64),
            "episodes" => Some(self.episodes as f64),
            "final_window" => Some(self.final_window as f64),
            "final_steps" => Some(self.final_steps),
            "final_return" => Some(self.final_return),
            "success_rate" => Some(self.success_rate),
            "greedy_reached" => Some(if self.greedy_reached { 1.0 } else { 0.0 }),
            "greedy_steps" => Some(self.greedy_steps as f64),
            "collapse_episode" => self.collapse_episode.map(|e| e as f64),
            "fluctuation_steps" => Some(self.fluctuation_steps),
            "fluctuation_return" => Some(self.fluctuation_return),
            "greedy_evaluations" => Some(self.greedy_evaluations as f64),
            "stable_reaching" => self.stable_reaching.map(|s| if s { 1.0 } else { 0.0 }),
            "fluctuation_greedy_steps" => self.fluctuation_greedy_steps,
            "fluctuation_greedy_return" => self.fluctuation_greedy_return,
            "env_steps_total" => Some(self.env_steps_total as f64),
            "pretrain_env_steps" => Some(self.pretrain_env_steps as f64),
            "step_cap" => Some(f64::from(self.step_cap)),
            "optimum_steps" => self.optimum_steps.map(|steps| steps as f64),
            "reaching_episodes" => Some(self.reaching_episodes as f64),
            "reach_average_reward" => self.reach_average_reward,
            "reach_time" => self.reach_time,
            "reach_retention_time" => self.reach_retention_time,
            "retention_decay" => self.retention_decay,
            _ => None,
        }
    }
}

/// What [`final_scores`] needs to know of an experiment beyond its records: each method's
/// role and kind, and the task's step cap. `eamadm` implements it for its loaded `Experiment`
/// (the step cap is the loaded task's), so `final_scores(&records, &experiment)`.
pub trait MethodRoles {
    /// The role and kind (`ea_madm`, `epsilon_greedy`, …: `eamadm::Method::kind_name`) of the
    /// method labelled `label`; `None` when the experiment has no such method.
    fn role_and_kind(&self, label: &str) -> Option<(Role, &'static str)>;

    /// The task's step cap: steps after which an episode is truncated.
    fn step_cap(&self) -> u32;

    /// What the task is played on: the `layout` of its rows (a maze's layout as
    /// `layouts.csv` names it, the robot's scenario's name).
    fn layout(&self) -> String;
}

/// The final scores of `records`, in record order. `config` is the experiment (for each
/// method's role and kind, and the step cap).
///
/// # Errors
/// [`ScoresError::NoEpisodes`], [`ScoresError::UnknownMethod`], [`ScoresError::Stats`] for a
/// non-finite return.
pub fn final_scores(
    records: &[RunRecord],
    config: &impl MethodRoles,
) -> Result<Vec<FinalScore>, ScoresError> {
    records
        .iter()
        .map(|record| final_score_of(record, config))
        .collect()
}

/// The final score of one run of the experiment `config` (which gives its method's role and
/// kind, and the step cap): one row of [`final_scores`], for a caller that streams runs and keeps only their rows.
///
/// # Errors
/// As [`final_scores`].
pub fn final_score_of(
    record: &RunRecord,
    config: &impl MethodRoles,
) -> Result<FinalScore, ScoresError> {
    let (role, kind) =
        config
            .role_and_kind(&record.method)
            .ok_or_else(|| ScoresError::UnknownMethod {
                task: record.experiment.clone(),
                method: record.method.clone(),
                seed: record.seed,
            })?;
    final_score(record, role, kind, config.step_cap(), &config.layout())
}

/// The final score of one run whose method has this `role` and `kind`, on a task whose
/// episodes are truncated after `step_cap` steps, played on `layout`.
///
/// # Errors
/// [`ScoresError::NoEpisodes`]; [`ScoresError::Stats`] for a non-finite return.
#[expect(
    clippy::cast_precision_loss,
    reason = "episode and step counts are far below 2^52"
)]
pub fn final_score(
    record: &RunRecord,
    role: Role,
    kind: &str,
    step_cap: u32,
    layout: &str,
) -> Result<FinalScore, ScoresError> {
    let stats_error = |source| ScoresError::Stats {
        task: record.experiment.clone(),
        method: record.method.clone(),
        seed: record.seed,
        source: Box::new(source),
    };
    let episodes = &record.episodes;
    if episodes.is_empty() {
        return Err(ScoresError::NoEpisodes {
            task: record.experiment.clone(),
            method: record.method.clone(),
            seed: record.seed,
        });
    }
    let steps = |e: &EpisodeRecord| e.steps as f64;
    let window = &episodes[episodes.len().saturating_sub(FINAL_WINDOW)..];
    let second_half = &episodes[episodes.len() / 2..];
    let of = |part: &[EpisodeRecord], f: &dyn Fn(&EpisodeRecord) -> f64| -> Vec<f64> {
        part.iter().map(f).collect()
    };
    let final_steps = stats::mean(&of(window, &steps)).map_err(stats_error)?;
    let final_return = stats::mean(&of(window, &|e| e.task_return)).map_err(stats_error)?;
    let success_rate = window.iter().filter(|e| e.reached).count() as f64 / window.len() as f64;
    let fluctuation_steps = stats::sample_sd(&of(second_half, &steps)).map_err(stats_error)?;
    let fluctuation_return =
        stats::sample_sd(&of(second_half, &|e| e.task_return)).map_err(stats_error)?;
    let greedy = greedy_in_second_half(record);
    let stable_reaching = (!greedy.is_empty()).then(|| greedy.iter().all(|e| e.reached));
    let (fluctuation_greedy_steps, fluctuation_greedy_return) =
        if stable_reaching == Some(true) && greedy.len() >= 2 {
            (
                Some(stats::sample_sd(&of(&greedy, &steps)).map_err(stats_error)?),
                Some(stats::sample_sd(&of(&greedy, &|e| e.task_return)).map_err(stats_error)?),
            )
        } else {
            (None, None)
        };

    let reaching: Vec<&EpisodeRecord> = crate::reaching::first_reaching(episodes).collect();
    let robot: Vec<_> = reaching.iter().filter_map(|e| e.robot).collect();
    let is_robot = episodes.iter().any(|e| e.robot.is_some());
    let (reach_average_reward, reach_time, reach_retention_time, retention_decay) =
        if is_robot && !robot.is_empty() {
            let of = |metric: ReachingMetric| -> Vec<f64> {
                robot.iter().map(|m| metric.value(m)).collect()
            };
            let average = of(ReachingMetric::AverageReward);
            let time = of(ReachingMetric::ReachingTime);
            let retention = of(ReachingMetric::RetentionTime);
            (
                Some(stats::mean(&average).map_err(stats_error)?),
                Some(stats::mean(&time).map_err(stats_error)?),
                Some(stats::mean(&retention).map_err(stats_error)?),
                slope(&retention),
            )
        } else {
            (None, None, None, None)
        };

    let (outcome, collapse_episode) =
        RunOutcome::of(record.evaluation.reached, episodes, FINAL_WINDOW);
    Ok(FinalScore {
        task: record.experiment.clone(),
        layout: layout.to_owned(),
        method: record.method.clone(),
        role,
        kind: kind.to_owned(),
        seed: record.seed,
        episodes: episodes.len() as u64,
        final_window: window.len(),
        final_steps,
        final_return,
        success_rate,
        greedy_reached: record.evaluation.reached,
        greedy_steps: record.evaluation.steps,
        outcome,
        collapse_episode,
        fluctuation_steps,
        fluctuation_return,
        greedy_evaluations: greedy.len() as u64,
        stable_reaching,
        fluctuation_greedy_steps,
        fluctuation_greedy_return,
        env_steps_total: record.total_env_steps,
        pretrain_env_steps: record.pretrain_env_steps,
        step_cap,
        optimum_steps: record.optimum_steps,
        reaching_episodes: reaching.len() as u64,
        reach_average_reward,
        reach_time,
        reach_retention_time,
        retention_decay,
    })
}

/// The periodic greedy evaluations of `record` taken in the second half of training: after
/// training episodes `⌊E/2⌋ .. E` of its `E` episodes, i.e. those whose `episode` (the
/// training episodes done before it) exceeds `⌊E/2⌋`. C3's greedy fluctuation and
/// stable-reaching are taken over them.
#[must_use]
pub fn greedy_in_second_half(record: &RunRecord) -> Vec<EpisodeRecord> {
    let half = record.episodes.len() as u64 / 2;
    record
        .greedy_evaluations
        .iter()
        .filter(|e| e.episode > half)
        .cloned()
        .collect()
}

/// Least-squares slope of `y` against its index `0, 1, …, n − 1`:
/// `Σ (i − ī)(yᵢ − ȳ) / Σ (i − ī)²`; `None` for fewer than two points or a non-finite result.
#[must_use]
#[expect(
    clippy::cast_precision_loss,
    reason = "at most REACHING_EPISODES points"
)]
pub fn slope(y: &[f64]) -> Option<f64> {
    let n = y.len();
    if n < 2 {
        return None;
    }
    let x_mean = (n - 1) as f64 / 2.0;
    let y_mean = y.iter().sum::<f64>() / n as f64;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &value) in y.iter().enumerate() {
        let dx = i as f64 - x_mean;
        sxy += dx * (value - y_mean);
        sxx += dx * dx;
    }
    Some(sxy / sxx).filter(|s| s.is_finite())
}

/// Writes `rows` as `final-scores.csv`: a header of the names of [`COLUMNS`], one row per run; empty cells
/// for absent values; floats printed so that they read back bit for bit.
///
/// # Errors
/// [`ScoresError::Csv`] when writing fails.
pub fn write_csv<W: Write>(rows: &[FinalScore], writer: W) -> Result<(), ScoresError> {
    let mut csv = csv::Writer::from_writer(writer);
    if rows.is_empty() {
        csv.write_record(COLUMNS.iter().map(|c| c.name))?;
    }
    for row in rows {
        csv.serialize(row)?;
    }
    csv.flush().map_err(csv::Error::from)?;
    Ok(())
}

/// Reads a `final-scores.csv` written by [`write_csv`].
///
/// # Errors
/// [`ScoresError::Csv`] for unreadable or malformed input (naming the line).
pub fn read_csv<R: Read>(reader: R) -> Result<Vec<FinalScore>, ScoresError> {
    let mut csv = csv::Reader::from_reader(reader);
    Ok(csv.deserialize().collect::<Result<_, _>>()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::TrajectoryRecord;

    #[test]
    fn slope_of_a_line_and_of_too_few_points() {
        assert_eq!(slope(&[5.0, 3.0, 1.0]), Some(-2.0));
        assert_eq!(slope(&[2.0, 2.0, 2.0, 2.0]), Some(0.0));
        assert_eq!(slope(&[1.0]), None);
        assert_eq!(slope(&[]), None);
        // y = 1 + 0.5 i with noise that cancels: 1.0, 1.6, 1.9, 2.5 → slope 0.48.
        let s = slope(&[1.0, 1.6, 1.9, 2.5]).unwrap();
        assert!((s - 0.48).abs() < 1e-12, "{s}");
    }

    #[test]
    fn outcomes_are_exhaustive_and_date_the_collapse() {
        let episode = |reached| EpisodeRecord {
            episode: 0,
            steps: 1,
            task_return: 0.0,
            learning_return: 0.0,
            terminated: reached,
            truncated: !reached,
            reached,
            collisions: 0,
            env_steps: 1,
            robot: None,
        };
        let run = |flags: &[bool]| flags.iter().map(|&r| episode(r)).collect::<Vec<_>>();
        let collapsed = run(&[false, true, true, false, true, false, false]);
        assert_eq!(
            RunOutcome::of(false, &collapsed, 2),
            (RunOutcome::Collapsed, Some(5))
        );
        assert_eq!(
            RunOutcome::of(true, &collapsed, 2),
            (RunOutcome::Converged, None)
        );
        // A window of 3 holds episode 4, which reached: it still reaches while learning.
        assert_eq!(
            RunOutcome::of(false, &collapsed, 3),
            (RunOutcome::ReachesWhileLearning, None)
        );
        assert_eq!(
            RunOutcome::of(false, &run(&[false, false]), 2),
            (RunOutcome::NeverReached, None)
        );
    }

    /// A run of `episodes` training episodes of 10 steps each whose greedy evaluations (one
    /// after every episode) take `greedy[i]` steps and reach when below the cap of 2000.
    fn run_with_greedy(episodes: u64, greedy: &[u64]) -> RunRecord {
        let episode = |i: u64, steps: u64| EpisodeRecord {
            episode: i,
            steps,
            task_return: -(steps as f64),
            learning_return: 0.0,
            terminated: steps < 2000,
            truncated: steps >= 2000,
            reached: steps < 2000,
            collisions: 0,
            env_steps: 0,
            robot: None,
        };
        let trajectory = TrajectoryRecord {
            episode: episodes,
            greedy: true,
            states: vec![0],
            actions: Vec::new(),
            positions: vec![[0.0, 0.0]],
        };
        RunRecord {
            experiment: "t".into(),
            method: "m".into(),
            seed: 0,
            optimum_steps: None,
            subtasks: Vec::new(),
            pretrain_env_steps: 0,
            episodes: (0..episodes).map(|i| episode(i, 10)).collect(),
            total_env_steps: 10 * episodes,
            trajectories: Vec::new(),
            greedy_evaluations: greedy
                .iter()
                .zip(1..)
                .map(|(&steps, i)| episode(i, steps))
                .collect(),
            evaluation: episode(episodes, 10),
            evaluation_trajectory: trajectory,
            final_window_episodes: 0,
            final_window_actions: Vec::new(),
            agreement: None,
        }
    }

    #[test]
    fn a_seed_stuck_at_the_cap_is_not_stable_reaching_and_has_no_greedy_fluctuation() {
        // Six episodes: the second half is evaluations 4, 5, 6 (after episodes 3, 4, 5).
        let stuck = final_score(
            &run_with_greedy(6, &[12, 14, 2000, 2000, 2000, 2000]),
            Role::Paper,
            "x",
            2000,
            "t",
        )
        .unwrap();
        assert_eq!(stuck.greedy_evaluations, 3);
        assert_eq!(stuck.stable_reaching, Some(false));
        assert_eq!(stuck.fluctuation_greedy_steps, None);
        assert_eq!(stuck.fluctuation_greedy_return, None);
        // Its training curve is flat: SD 0 there, the metric the greedy one replaces.
        assert_eq!(stuck.fluctuation_steps, 0.0);
        // One failure in the window is enough; failures before it do not count.
        let once = final_score(
            &run_with_greedy(6, &[2000, 2000, 2000, 20, 2000, 20]),
            Role::Paper,
            "x",
            2000,
            "t",
        )
        .unwrap();
        assert_eq!(once.stable_reaching, Some(false));
        let late = final_score(
            &run_with_greedy(6, &[2000, 2000, 2000, 20, 22, 24]),
            Role::Paper,
            "x",
            2000,
            "t",
        )
        .unwrap();
        assert_eq!(late.stable_reaching, Some(true));
        assert_eq!(late.fluctuation_greedy_steps, Some(2.0));
        assert_eq!(late.fluctuation_greedy_return, Some(2.0));
        // Without evaluations (an old record): nothing to say.
        let none = final_score(&run_with_greedy(6, &[]), Role::Paper, "x", 2000, "t").unwrap();
        assert_eq!((none.greedy_evaluations, none.stable_reaching), (0, None));
    }

    #[test]
    fn columns_are_the_fields_in_order() {
        let row = FinalScore {
            task: "t".into(),
            layout: "l".into(),
            method: "m".into(),
            role: Role::Control,
            kind: "softmax".into(),
            seed: 3,
            episodes: 10,
            final_window: 10,
            final_steps: 1.5,
            final_return: -2.0,
            success_rate: 0.5,
            greedy_reached: true,
            greedy_steps: 7,
            outcome: RunOutcome::Converged,
            collapse_episode: None,
            fluctuation_steps: 0.25,
            fluctuation_return: 0.125,
            greedy_evaluations: 3,
            stable_reaching: Some(false),
            fluctuation_greedy_steps: None,
            fluctuation_greedy_return: None,
            env_steps_total: 99,
            pretrain_env_steps: 0,
            step_cap: 500,
            optimum_steps: Some(12),
            reaching_episodes: 0,
            reach_average_reward: None,
            reach_time: None,
            reach_retention_time: None,
            retention_decay: Some(-0.1),
        };
        let mut bytes = Vec::new();
        write_csv(std::slice::from_ref(&row), &mut bytes).unwrap();
        let text = String::from_utf8(bytes.clone()).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            crate::columns::names(COLUMNS).join(",")
        );
        assert_eq!(
            lines.next().unwrap(),
            "t,l,m,control,softmax,3,10,10,1.5,-2.0,0.5,true,7,converged,,0.25,0.125,3,false,,,99,0,500,12,0,,,,-0.1"
        );
        assert_eq!(read_csv(bytes.as_slice()).unwrap(), vec![row.clone()]);
        for column in COLUMNS {
            if column.field_type != FieldType::String {
                let absent = matches!(
                    column.name,
                    "fluctuation_greedy_steps"
                        | "fluctuation_greedy_return"
                        | "collapse_episode"
                        | "reach_average_reward"
                        | "reach_time"
                        | "reach_retention_time"
                );
                assert_eq!(row.value(column.name).is_none(), absent, "{}", column.name);
                // A column that is blank here must say when it can be.
                assert!(!absent || column.blank_when.is_some(), "{}", column.name);
            }
        }
        // The descriptions state the windows the code uses.
        let described = |name: &str| COLUMNS.iter().find(|c| c.name == name).unwrap().description;
        assert!(described("final_window").contains(&format!("last {FINAL_WINDOW} ")));
        assert!(described("reaching_episodes").contains(&format!("at most {REACHING_EPISODES} ")));
    }
}
