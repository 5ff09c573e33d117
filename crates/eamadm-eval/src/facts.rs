//! What the report and the figures know beyond the scores: the paper's tasks, the experiments
//! of a run (their episodes, seeds, methods with their roles, the figures written, the robot's
//! behaviour and reward references, the equivalence margins) and the readings of the paper. Plain
//! data, so that this crate needs no other crate of the workspace: `eamadm::paper` fills the
//! paper's part and `eamadm`'s report facts the experiments'; `report-context.toml` holds it
//! as TOML beside a run's outputs.

use serde::{Deserialize, Serialize};

use crate::Role;
use crate::behaviour::MethodBehaviour;
use crate::claims::{self, ClaimOptions, ClaimsError, Verdict};
use crate::oracle::{OracleFinding, PretrainingSummary};
use crate::paper_claims::ReportedNumbers;

/// What the report needs to know beyond the scores: the tasks of the paper, the experiments of
/// this run and what was written for them. Plain data, so this crate needs no other crate of
/// the workspace; `eamadm::paper::report_context` fills the paper's part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReportContext {
    /// Whether the run is a `--quick` smoke run (the report says so).
    pub quick: bool,
    /// The paper's tasks, in run order.
    pub paper_tasks: Vec<PaperTaskFacts>,
    /// Seeds per method of the presets: what the paper-numbers note states when no experiment
    /// is planned.
    pub preset_seeds: u32,
    /// The robot's action names, in the order of
    /// [`MethodBehaviour::action_shares`](crate::MethodBehaviour::action_shares).
    pub action_names: Vec<String>,
    /// The file name of an experiment's per-episode table (under its folder).
    pub curves_file: String,
    /// The file name of an experiment's trajectory table (under its folder).
    pub trajectories_file: String,
    /// The experiments of this run, in run order.
    pub experiments: Vec<ExperimentFacts>,
    /// The readings of the paper whose verdicts the report may judge again (the
    /// [`Verdicts::sensitivity`](crate::verdicts::Verdicts::sensitivity) rows name them), in
    /// the order the report lists them.
    pub readings: Vec<ReadingFacts>,
    /// How this reproduction differs from the paper where the difference could change a
    /// verdict (`eamadm::paper::deviations`), in the order the report's first screen lists
    /// them.
    #[serde(default)]
    pub deviations: Vec<DeviationFacts>,
    /// The oracle (issue 32, `oracle.csv` read by
    /// [`oracle_findings`](crate::oracle::oracle_findings)): per task and decision rule what it
    /// does with the best sub-task values available.
    #[serde(default)]
    pub oracle: Vec<OracleFinding>,
    /// The reach sub-task's pre-training per task and method (`pretraining.csv` read by
    /// [`reach_pretraining`](crate::oracle::reach_pretraining)).
    #[serde(default)]
    pub pretraining: Vec<PretrainingSummary>,
    /// Predictions written before any run (`eamadm::paper::predictions`), judged against the
    /// run's outcome.
    #[serde(default)]
    pub predictions: Vec<PredictionFacts>,
}

/// What was predicted for a task before any run of it (docs/paper-notes.md records the
/// reasoning and the commit that fixed it first).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PredictionFacts {
    /// The task (experiment name).
    pub task: String,
    /// Where the prediction and its reasons are recorded (`§21.2`).
    pub notes: String,
    /// EA-MADM's best verdict predicted at most (`inconclusive`: no claim supported).
    pub best_verdict: Verdict,
    /// The sub-task alone EA-MADM was predicted to end as on most seeds.
    pub follows: String,
    /// Whether its decision with exact sub-task values was predicted to reach.
    pub oracle_reaches: bool,
}

/// One way this reproduction differs from the paper that could change a verdict.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct DeviationFacts {
    /// What differs, in a few words (`The mazes`).
    pub what: String,
    /// What the paper gives and what we do instead, in one or two sentences.
    pub ours: String,
    /// Where `docs/paper-notes.md` records the decision (`§7`).
    pub notes: String,
    /// The tasks it concerns (names); empty for every task.
    pub tasks: Vec<String>,
    /// The readings of the paper that rerun the other choice (their verdicts say whether it
    /// matters).
    pub readings: Vec<String>,
    /// The ablations or controls that run the other choice.
    pub methods: Vec<String>,
}

/// One reading of the paper as the report describes it (`eamadm::paper::Reading`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReadingFacts {
    /// Its name, as in `sensitivity.csv`, e.g. `gamma-0.99`.
    pub name: String,
    /// What it changes, in words.
    pub change: String,
    /// The paper's words it rests on, in one sentence.
    pub source: String,
    /// The methods it runs again (labels).
    pub methods: Vec<String>,
}

/// One of the paper's tasks as the report names it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PaperTaskFacts {
    /// The config's `name` and the `task` column: `task1`, `task2`, `robot`, ….
    pub name: String,
    /// The title for people: `Task I`, `Robot`, ….
    pub title: String,
    /// How a sentence names it: `Task I`, `the robot`, ….
    pub title_in_sentence: String,
    /// Whether it is a robot task (its report has the robot's C4 metrics).
    pub robot: bool,
    /// What the paper reports for EA-MADM on it, if anything.
    pub reported: Option<ReportedNumbers>,
}

/// One experiment of this run and what was written for it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExperimentFacts {
    /// Folder name and `task` column.
    pub name: String,
    /// Title for people.
    pub title: String,
    /// Training episodes per run.
    pub episodes: u64,
    /// Seeds per method.
    pub seeds: u32,
    /// The discount γ of its learners (the robot's behaviour table states values per step).
    pub gamma: f64,
    /// The figures written for it.
    pub figures: Figures,
    /// Each method's behaviour, for a robot experiment; empty where there is none.
    pub behaviour: Vec<MethodBehaviour>,
    /// The robot's sub-task rewards under each set of repairs its methods learn from, with
    /// what they value three ways to play (`eamadm::diagnosis`), the paper's rewards first;
    /// empty for a maze. (Written as `reward_readings` before issue 36; still read.)
    #[serde(alias = "reward_readings")]
    pub reward_references: Vec<RewardReference>,
    /// The exploring rate ε of each method that explores ε-greedily, over the final window.
    pub final_epsilon: Vec<FinalEpsilon>,
    /// The equivalence margin of each metric its task defines one for, with its reason
    /// (`eamadm::Task::equivalence_margins`); empty in a context written before margins
    /// existed, which then judges nothing equivalent.
    #[serde(default)]
    pub margins: Vec<claims::Margin>,
    /// Each method as its config states it (label, role, kind, what a control matches), in
    /// the order its runs came (the job order; methods not run after them): what the
    /// verdicts and the text know of a method beyond its scores, so that nothing is read off
    /// a label, and the order the figures of a folder are drawn again in. Empty in a context written before it existed (no
    /// control is then known by its family).
    #[serde(default)]
    pub methods: Vec<MethodFacts>,
    /// The paper's figures this experiment's figures are the analogues of.
    #[serde(default)]
    pub paper_figures: PaperFigures,
    /// The first seed: the runs' seeds are `base_seed .. base_seed + seeds`.
    #[serde(default)]
    pub base_seed: u64,
    /// Whether its tables (`curves.csv.gz`, `trajectories.csv.gz`) were written beside its
    /// figures (the main job writes them; a report of `eamadm.run`'s results has none).
    #[serde(default)]
    pub tables_written: bool,
}

impl ExperimentFacts {
    /// The facts of the method labelled `label`, if the experiment has it.
    #[must_use]
    pub fn method(&self, label: &str) -> Option<&MethodFacts> {
        self.methods.iter().find(|m| m.label == label)
    }
}

/// One method of an experiment as its config states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodFacts {
    /// Its label.
    pub label: String,
    /// Why it is in the experiment.
    pub role: Role,
    /// Its kind (`ea_madm`, `epsilon_greedy`, `softmax`, `subtask_greedy`).
    pub kind: String,
    /// What a control gives the competitors or takes from EA-MADM, from its config (`signal`,
    /// `warmup_env_steps`, `kind = "subtask_greedy"`); `None` for every other method.
    #[serde(default)]
    pub control: Option<ControlFamily>,
    /// An EA-MADM that keeps its sub-tasks' experience in trees: the state threshold τₛ.
    #[serde(default)]
    pub tree_threshold: Option<f64>,
}

/// What a control is, by its config: the controls that explain a verdict (the paper does not
/// run them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ControlFamily {
    /// A competitor learning from the reward information EA-MADM's sub-tasks get (`signal =
    /// "standardised"` or `"subtask_sum"`) instead of the task reward.
    RewardMatched,
    /// A competitor that first trains on the task for EA-MADM's pre-training budget
    /// (`warmup_env_steps`).
    BudgetMatched,
    /// One pre-trained sub-task acting alone, without the MADM step (`kind =
    /// "subtask_greedy"`).
    SubtaskAlone {
        /// Which sub-task (0-based).
        subtask: usize,
        /// Whether it keeps learning during the source task's episodes (frozen otherwise, as
        /// EA-MADM's prior experience is).
        learns: bool,
    },
}

/// The exploring rate ε of one method over the final window of training (its schedule's
/// values at the window's first and last episode): how many random actions a final-window
/// episode takes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FinalEpsilon {
    /// The method's label.
    pub method: String,
    /// ε at the final window's first episode.
    pub first: f64,
    /// ε at the final window's last episode.
    pub last: f64,
}

/// The robot's sub-task rewards under one set of repairs (none: the paper's Eq. 6–8): what
/// each sub-task's reward definition makes of reaching, of ending the episode at once and of
/// idling, discounted at the learners' γ, and the methods that learn from it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RewardReference {
    /// The repairs, as a reader names them (`goal bonus for reach`, `end penalties`); empty
    /// for the paper's rewards.
    pub repairs: Vec<String>,
    /// The methods whose sub-tasks (or whose shaped training signal) use these rewards, in
    /// config order.
    pub methods: Vec<String>,
    /// Steps of the straight full-speed run from the start to the reach radius that `reach`
    /// values.
    pub reach_steps: u32,
    /// The episode step cap that `idle` runs to.
    pub step_cap: u32,
    /// Per sub-task, in the task's sub-task order.
    pub subtasks: Vec<SubtaskReference>,
}

/// One sub-task's reward definition under a [`RewardReference`]: `Σ γᵗ rₜ` of three ways to
/// play an episode (`wmr_model::ReferenceValues`), and the controls that run it alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SubtaskReference {
    /// The sub-task's name.
    pub name: String,
    /// Reaching by the straight run.
    pub reach: f64,
    /// One step, then the target is lost (the episode ends).
    pub lose_at_once: f64,
    /// `stop` at the start until the step cap.
    pub idle: f64,
    /// The methods that run this sub-task alone (`(label, whether it keeps learning)`).
    pub alone: Vec<(String, bool)>,
}

impl SubtaskReference {
    /// Whether the reward values reaching above both ending at once and idling.
    #[must_use]
    pub fn reaching_pays(&self) -> bool {
        self.reach > self.lose_at_once && self.reach > self.idle
    }

    /// The way of playing whose value is closest to `value` (a learner's start value): what
    /// the learner has most likely learned.
    #[must_use]
    pub fn closest_play(&self, value: f64) -> Play {
        [
            (self.reach, Play::Reach),
            (self.lose_at_once, Play::LoseAtOnce),
            (self.idle, Play::Idle),
        ]
        .into_iter()
        .fold((f64::INFINITY, Play::Reach), |best, (v, play)| {
            let distance = (v - value).abs();
            if distance < best.0 {
                (distance, play)
            } else {
                best
            }
        })
        .1
    }

    /// The way of playing its reward values most (the first of equals in the order reach,
    /// lose at once, idle).
    #[must_use]
    pub fn best_play(&self) -> Play {
        if self.reaching_pays() {
            Play::Reach
        } else if self.lose_at_once >= self.idle {
            Play::LoseAtOnce
        } else {
            Play::Idle
        }
    }

    /// The value of `play`.
    #[must_use]
    pub fn value(&self, play: Play) -> f64 {
        match play {
            Play::Reach => self.reach,
            Play::LoseAtOnce => self.lose_at_once,
            Play::Idle => self.idle,
        }
    }
}

/// A way to play a robot episode that [`SubtaskReference`] values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Play {
    /// Drive straight to the target.
    Reach,
    /// End the episode at once by losing the target.
    LoseAtOnce,
    /// Stay at the start until the step cap.
    Idle,
}

impl Play {
    /// How a sentence names it.
    #[must_use]
    pub fn words(self) -> &'static str {
        match self {
            Self::Reach => "reaching",
            Self::LoseAtOnce => "ending the episode at once",
            Self::Idle => "idling to the step cap",
        }
    }
}

/// The figure files written for an experiment and the captions of its key figures.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Figures {
    /// File names under the experiment's folder, in the order written.
    pub files: Vec<String>,
    /// `(file name, one-line caption)` of the key figures, in the order they are shown.
    pub captions: Vec<(String, String)>,
    /// The figures left out because they would be empty axes, and why; one sentence
    /// (`eamadm_present::report::not_drawn_sentence`) stands for them in the report.
    pub not_drawn: Vec<NotDrawn>,
}

/// The paper's figures an experiment's figures are the analogues of (`Fig. 7`, …); `None`
/// where the paper has none (a config of one's own, or the robot, whose Fig. 13–15 the reaching
/// figures name themselves).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PaperFigures {
    /// Steps per episode.
    pub steps: Option<String>,
    /// Return per episode.
    pub task_return: Option<String>,
    /// The greedy paths.
    pub trajectories: Option<String>,
}

/// A figure that is not written because it would show nothing: empty axes (no method it
/// draws has a value to plot) or lines that are all 0.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct NotDrawn {
    /// The file it would have been.
    pub file: String,
    /// What it would have shown, e.g. `reaching time over reaching episodes (Fig. 14)`.
    pub what: String,
    /// Why it shows nothing, as a clause: e.g. `none of EA-MADM, softmax reached the target
    /// in any training episode of any seed`.
    pub why: String,
}

impl ReportContext {
    /// The paper's task named `name`, if it is one.
    pub fn paper_task(&self, name: &str) -> Option<&PaperTaskFacts> {
        self.paper_tasks.iter().find(|t| t.name == name)
    }

    /// The experiment named `name`, if the run has it.
    #[must_use]
    pub fn experiment(&self, name: &str) -> Option<&ExperimentFacts> {
        self.experiments.iter().find(|e| e.name == name)
    }

    /// The facts of the method labelled `label` on `task`, if the run states them.
    #[must_use]
    pub fn method(&self, task: &str, label: &str) -> Option<&MethodFacts> {
        self.experiment(task)?.method(label)
    }

    /// The title of `task`: the experiment's, else the paper task's, else its name.
    pub fn task_title(&self, task: &str) -> String {
        self.experiments
            .iter()
            .find(|p| p.name == task)
            .map(|p| p.title.clone())
            .or_else(|| self.paper_task(task).map(|t| t.title.clone()))
            .unwrap_or_else(|| task.to_owned())
    }
}

impl ReportContext {
    /// The equivalence margins of the run's experiments, by experiment name (the `task`
    /// column), for [`ClaimOptions::margins`].
    ///
    /// # Errors
    /// [`ClaimsError::BadMargin`] naming the task and column of a margin that is not positive
    /// and finite.
    pub fn margins(&self) -> Result<claims::Margins, ClaimsError> {
        let mut margins = claims::Margins::new();
        for experiment in &self.experiments {
            margins.insert(&experiment.name, &experiment.margins)?;
        }
        Ok(margins)
    }

    /// [`ClaimOptions::default`] with the margins of the run's experiments
    /// ([`Self::margins`]): the options the main job judges with.
    ///
    /// # Errors
    /// As [`Self::margins`].
    pub fn claim_options(&self) -> Result<ClaimOptions, ClaimsError> {
        Ok(ClaimOptions {
            margins: self.margins()?,
            ..ClaimOptions::default()
        })
    }
}
