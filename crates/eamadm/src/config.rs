//! Experiment configs: the task, the methods and their parameters, episodes and seeds, as TOML.
//!
//! An [`ExperimentConfig`] is plain serde data. Every table rejects unknown keys, and
//! [`ExperimentConfig::validate`] rejects out-of-range values with a [`ConfigError`] naming the
//! field by its path (`methods[2].epsilon.factor`). [`ExperimentConfig::check`] turns a config
//! into a checked [`Experiment`](crate::Experiment) once (the values, then the task with
//! [`TaskConfig::check`], then each method against the task); nothing later checks the same
//! values again, and its errors name the key the user wrote (`task.step_cap`, not the robot
//! scenario's own field). The paper's settings are the presets of
//! [`paper`](crate::paper) ([`paper::task1`](crate::paper::task1), …), and the same values ship
//! as TOML files ([`PAPER_TASK1_TOML`], …; `crates/eamadm/configs/` in the repository).
//!
//! ```toml
//! name = "task1"
//! episodes = 200
//! seeds = 20
//! base_seed = 0
//!
//! [task]
//! kind = "maze"          # or "maze_file" (path, rewards), "maze_text" (map, rewards), "robot"
//! preset = "task1"
//!
//! [learner]              # double Q (Eq. 9), Table 1
//! alpha = 0.1
//! gamma = 0.95
//!
//! [[methods]]
//! label = "epsilon-decreasing"
//! kind = "epsilon_greedy"
//! epsilon = { exponential = { start = 0.95, factor = 0.95, floor = 0.0 } }
//! ```

use std::collections::HashSet;
use std::io;
use std::path::PathBuf;

use dql::{DoubleQParams, DqlError, EpsilonGreedy, Schedule, Softmax};
use ea_tree::EaTreeConfig;
use madm_owa::{Normalisation, Weighting};
use mazes::Preset;
use reward_std::Standardisation;
use serde::{Deserialize, Serialize};
use thiserror::Error;
use wmr_model::SubtaskRepairs;

/// The paper's Task I (Sec. VI.A, Table 1) as TOML; parses to [`paper::task1`](crate::paper::task1).
pub const PAPER_TASK1_TOML: &str = include_str!("../configs/task1.toml");
/// The paper's Task II (Sec. VI.A) as TOML; parses to [`paper::task2`](crate::paper::task2).
pub const PAPER_TASK2_TOML: &str = include_str!("../configs/task2.toml");
/// The paper's robot experiment (Sec. VI.B, Table 2) as TOML; parses to
/// [`paper::robot`](crate::paper::robot).
pub const PAPER_ROBOT_TOML: &str = include_str!("../configs/robot.toml");
/// The positive control of issue 32 as TOML; parses to
/// [`paper::aggregation_control`](crate::paper::aggregation_control).
pub const AGGREGATION_CONTROL_TOML: &str = include_str!("../configs/aggregation-control.toml");
/// The robot experiment over the paper's literal state (no target feature) as TOML; parses to
/// [`paper::robot_paper_state`](crate::paper::robot_paper_state).
pub const PAPER_ROBOT_PAPER_STATE_TOML: &str = include_str!("../configs/robot-paper-state.toml");

/// Most episodes (or pre-training episodes) a run may have: far beyond any experiment here,
/// small enough that cumulative step counts cannot overflow.
pub const MAX_EPISODES: u64 = 10_000_000;
/// Most seeds one config may ask for.
pub const MAX_SEEDS: u32 = 100_000;

/// One experiment: a task, the methods compared on it, and how long and how often they run.
///
/// Runs are pure functions of `(config, method, seed)`; seed `i` of the experiment is
/// `base_seed + i` for `i` in `0..seeds`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentConfig {
    /// Name of the experiment, copied into every [`RunRecord`](crate::RunRecord) (the paper
    /// presets use `task1`, `task2`, `robot`). A [safe slug](is_safe_slug): it names the
    /// experiment's output folder.
    pub name: String,
    /// The task every method runs on.
    pub task: TaskConfig,
    /// Training episodes of the source task (200 in the paper).
    pub episodes: u64,
    /// Number of seeds per method.
    pub seeds: u32,
    /// Seed of the first run; run `i` uses `base_seed + i`.
    #[serde(default)]
    pub base_seed: u64,
    /// Double-Q parameters of every learner (source tasks and sub-tasks): Table 1's α, γ.
    pub learner: DoubleQParams,
    /// Which training episodes keep their trajectory (the greedy evaluation always does).
    #[serde(default)]
    pub trajectories: TrajectoryConfig,
    /// How often training pauses for a greedy evaluation episode of the current policy
    /// (`[evaluation] every = k`; every [`DEFAULT_EVALUATION_EVERY`] episodes when absent).
    #[serde(default, skip_serializing_if = "EvaluationConfig::is_default")]
    pub evaluation: EvaluationConfig,
    /// The methods compared, in report order. Labels must be unique.
    pub methods: Vec<MethodSpec>,
}

/// The task: a maze (preset, map file or inline map) or the wheeled robot.
///
/// TOML: `kind = "maze"` with `preset = "task1" | "task2"` (and optionally `rewards`, whose
/// rewards and sub-tasks to use on that layout); `kind = "maze_file"` with `path`
/// (a text map, see [`mazes::Maze::parse`]) and `rewards = "task1" | "task2"` (whose rewards
/// and sub-tasks to use); `kind = "maze_text"` with the map inline in `map`. Every kind takes
/// an optional `step_cap` overriding the task's own (2000 for the mazes); `kind = "robot"` with
/// `scenario = "default"` (the embedded analogue of the paper's Fig. 12) or the path of a
/// scenario TOML file (see [`wmr_model::Scenario`]), whose own `step_cap` (500 by default) an
/// optional `step_cap` here overrides, and whose `state.target_bins` (7 by default; 0 is the
/// paper's literal state) an optional `target_bins` here overrides; so do the optional
/// `control_period`, `reach_radius` and `distance_bins` (the settings the paper leaves open,
/// chosen by the sweep in docs/paper-notes.md §8.5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
#[non_exhaustive]
pub enum TaskConfig {
    /// One of the paper's mazes: layout, rewards, sub-tasks and step cap of the preset.
    Maze {
        /// `"task1"` or `"task2"`.
        preset: Preset,
        /// Whose rewards, sub-tasks and step cap to use on the preset's layout: `"task1"` or
        /// `"task2"`; the preset's own when absent. `rewards = "task1"` on the `task2` preset is
        /// the other reading of the paper's Task II rewards ("Similar to the scenario of task
        /// 1", Sec. VI.A), run by `eamadm::paper::Reading::Task2RewardAsTask1`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rewards: Option<Preset>,
        /// Episode step cap; the preset's (2000) when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        step_cap: Option<u32>,
    },
    /// A maze read from a text map file, with a preset's rewards and sub-tasks.
    MazeFile {
        /// Path of the map (relative paths are relative to the process's current folder).
        path: PathBuf,
        /// Whose rewards, sub-tasks and step cap to use: `"task1"` or `"task2"`.
        rewards: Preset,
        /// Episode step cap; the preset's when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        step_cap: Option<u32>,
    },
    /// A maze given inline as a text map (handy for tests and examples).
    MazeText {
        /// The map, one line per row (see [`mazes::Maze::parse`]).
        map: String,
        /// Whose rewards, sub-tasks and step cap to use: `"task1"` or `"task2"`.
        rewards: Preset,
        /// Episode step cap; the preset's when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        step_cap: Option<u32>,
    },
    /// The wheeled robot among obstacles (Sec. VI.B), in a scenario.
    Robot {
        /// `"default"` for the embedded scenario, otherwise the path of a scenario TOML file.
        scenario: String,
        /// Episode step cap; the scenario's when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        step_cap: Option<u32>,
        /// Bins over the target's horizontal image position (`state.target_bins` of the
        /// scenario, 0 = the paper's literal state); the scenario's when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        target_bins: Option<u32>,
        /// Control period Δt in seconds (`control_period` of the scenario); the scenario's
        /// when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        control_period: Option<f64>,
        /// Radius round the target within which the robot's centre has reached it
        /// (`target.reach_radius` of the scenario, m); the scenario's when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reach_radius: Option<f64>,
        /// `N_D`, the bins over the distance to the target (`state.distance_bins` of the
        /// scenario); the scenario's when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        distance_bins: Option<u32>,
    },
}

/// The value of `task.scenario` naming the embedded default robot scenario.
pub const DEFAULT_SCENARIO: &str = "default";

impl TaskConfig {
    /// The step cap override, if any.
    #[must_use]
    pub fn step_cap(&self) -> Option<u32> {
        match self {
            Self::Maze { step_cap, .. }
            | Self::MazeFile { step_cap, .. }
            | Self::MazeText { step_cap, .. }
            | Self::Robot { step_cap, .. } => *step_cap,
        }
    }
}

/// Which training episodes keep their trajectory in the run record. The greedy evaluation
/// episode after training always keeps its own.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrajectoryConfig {
    /// Keep the first training episode's trajectory.
    #[serde(default = "yes")]
    pub first: bool,
    /// Keep the last training episode's trajectory.
    #[serde(default = "yes")]
    pub last: bool,
    /// Keep these training episodes' trajectories too (0-based; each below `episodes`).
    #[serde(default)]
    pub episodes: Vec<u64>,
}

fn yes() -> bool {
    true
}

impl Default for TrajectoryConfig {
    /// First and last episode.
    fn default() -> Self {
        Self {
            first: true,
            last: true,
            episodes: Vec::new(),
        }
    }
}

impl TrajectoryConfig {
    /// Whether episode `episode` of `episodes` keeps its trajectory.
    #[must_use]
    pub fn keeps(&self, episode: u64, episodes: u64) -> bool {
        (self.first && episode == 0)
            || (self.last && episode + 1 == episodes)
            || self.episodes.contains(&episode)
    }
}

/// Training episodes between two periodic greedy evaluations when the config does not say.
pub const DEFAULT_EVALUATION_EVERY: u64 = 10;

/// The periodic greedy evaluation during training: after every `every`-th training episode
/// (episodes `k − 1, 2k − 1, …`) the run plays one episode of its current policy without
/// exploration and without learning, on its own random streams, so training is exactly what
/// it would be without it. C3's fluctuation is measured on these episodes
/// (docs/paper-notes.md, "C3 on the greedy policy").
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvaluationConfig {
    /// Training episodes between two evaluations, in `1..=episodes`;
    /// `min(`[`DEFAULT_EVALUATION_EVERY`]`, episodes)` when absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub every: Option<u64>,
}

impl EvaluationConfig {
    /// Whether nothing is set (the default is used).
    #[must_use]
    pub fn is_default(&self) -> bool {
        self.every.is_none()
    }

    /// The evaluation period of a run of `episodes` training episodes.
    #[must_use]
    pub fn every(&self, episodes: u64) -> u64 {
        self.every
            .unwrap_or_else(|| DEFAULT_EVALUATION_EVERY.min(episodes))
            .max(1)
    }

    /// Whether training episode `episode` (0-based) is followed by a greedy evaluation.
    #[must_use]
    pub fn after(&self, episode: u64, episodes: u64) -> bool {
        (episode + 1).is_multiple_of(self.every(episodes))
    }
}

/// A method under a label: the label names it in results, files and the command line.
///
/// TOML: the label and the method's fields side by side, e.g.
/// `{ label = "softmax", kind = "softmax", temperature = { constant = 0.1 } }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MethodRepr", into = "MethodRepr")]
pub struct MethodSpec {
    /// Unique within a config; a [safe slug](is_safe_slug) (used in file names).
    pub label: String,
    /// Why the method is in the experiment: one of the paper's methods, an ablation of
    /// EA-MADM, or a control the paper does not run. TOML `role = "paper"` (default),
    /// `"ablation"` or `"control"`. Reports group and judge methods by it.
    pub role: Role,
    /// The method and its parameters.
    pub method: Method,
}

pub use eamadm_eval::Role;

/// The methods: EA-MADM (Algorithm 2) and the paper's competitors, each a double-Q learner.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Method {
    /// EA-MADM (Sec. V, Algorithm 2), with its switches (the ablations flip one each).
    EaMadm(EaMadmConfig),
    /// Plain double Q on the task reward with ε-greedy exploration (ε-decreasing with an
    /// exponential schedule). TOML `kind = "epsilon_greedy"`.
    EpsilonGreedy {
        /// The exploring rate ε per episode.
        epsilon: Schedule,
        /// What it learns from and how long it trains before its recorded episodes (controls;
        /// the paper's competitors use the defaults).
        training: CompetitorTraining,
    },
    /// Plain double Q on the task reward with softmax exploration. TOML `kind = "softmax"`.
    Softmax {
        /// The temperature T per episode.
        temperature: Schedule,
        /// As for [`EpsilonGreedy`](Self::EpsilonGreedy).
        training: CompetitorTraining,
    },
    /// A control: one pre-trained sub-task acting by itself on the task, with no MADM step.
    /// TOML `kind = "subtask_greedy"`.
    SubtaskGreedy(SubtaskGreedyConfig),
}

/// A competitor's learning signal and warm-up (TOML keys `signal` and `warmup_env_steps`
/// beside the method's other fields). The defaults are the paper's competitors: the task's
/// reward, no warm-up.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CompetitorTraining {
    /// What the learner learns from.
    pub signal: CompetitorSignal,
    /// Environment steps of training on the task *before* the recorded episodes (the
    /// budget-matched control: EA-MADM spends its sub-task pre-training's steps before its
    /// own). The warm-up runs the method's own exploration schedule from episode 0, learning
    /// from `signal`, until exactly this many steps are spent (its last episode is cut at the
    /// budget); the recorded episodes then start the schedule again at episode 0, as
    /// EA-MADM's source task does after its sub-tasks' schedules. 0: no warm-up.
    pub warmup_env_steps: u64,
    /// Repairs of the robot's sub-task rewards (TOML `subtask_rewards = { reach_goal_bonus =
    /// true, end_penalties = true }`), for a competitor learning from them (`signal`
    /// `"standardised"` or `"subtask_sum"`) on the same rewards as a repaired EA-MADM. None by
    /// default; only a robot task takes them.
    pub subtask_rewards: SubtaskRepairs,
}

/// What a competitor learns from. TOML `signal = "task" | "subtask_sum" | "standardised"`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CompetitorSignal {
    /// The task's own reward (the paper's competitors).
    #[default]
    Task,
    /// The sum of the sub-task rewards of each step: the reward information EA-MADM's
    /// sub-tasks receive, unstandardised.
    SubtaskSum,
    /// Exactly the signal EA-MADM's source task learns from: the sub-task rewards
    /// standardised with running statistics (Eq. 10–12, [`Standardisation::Running`]).
    Standardised,
}

impl CompetitorSignal {
    /// Whether the signal needs a task with sub-tasks.
    #[must_use]
    pub fn needs_subtasks(self) -> bool {
        !matches!(self, Self::Task)
    }
}

/// Most warm-up environment steps a competitor may take (far beyond any budget here).
pub const MAX_WARMUP_ENV_STEPS: u64 = 1_000_000_000;

/// A pre-trained sub-task acting alone (TOML `kind = "subtask_greedy"`): the sub-task is
/// pre-trained exactly as EA-MADM pre-trains it (same streams, so the same learner as in the
/// EA-MADM run with the same seed and `pretrain`), then the source task's episodes choose
/// ε-greedily on *that sub-task's values only*; with `learn = false` (default) the values
/// stay frozen, as EA-MADM's prior experience does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SubtaskGreedyConfig {
    /// Which sub-task (0-based, in the task's sub-task order).
    pub subtask: usize,
    /// The exploring rate per episode of the source-task episodes (EA-MADM's schedule makes
    /// the curve comparable with EA-MADM's).
    pub epsilon: Schedule,
    /// Whether the sub-task keeps learning from its own reward during those episodes.
    #[serde(default)]
    pub learn: bool,
    /// How the sub-task is pre-trained (as EA-MADM's `pretrain`).
    #[serde(default)]
    pub pretrain: PretrainConfig,
}

impl Method {
    /// The repairs of the robot's sub-task rewards this method runs with (EA-MADM's and the
    /// competitors' `subtask_rewards`); none for a sub-task alone.
    #[must_use]
    pub fn subtask_repairs(&self) -> SubtaskRepairs {
        match self {
            Self::EaMadm(config) => config.subtask_rewards,
            Self::EpsilonGreedy { training, .. } | Self::Softmax { training, .. } => {
                training.subtask_rewards
            }
            Self::SubtaskGreedy(_) => SubtaskRepairs::PAPER,
        }
    }

    /// The TOML `kind` of the method (`ea_madm`, `epsilon_greedy`, `softmax`); results carry
    /// it so that a report can tell EA-MADM variants from competitors without the config.
    #[must_use]
    pub fn kind_name(&self) -> &'static str {
        match self {
            Self::EaMadm(_) => "ea_madm",
            Self::EpsilonGreedy { .. } => "epsilon_greedy",
            Self::Softmax { .. } => "softmax",
            Self::SubtaskGreedy(_) => "subtask_greedy",
        }
    }
}

/// EA-MADM's parameters (TOML `kind = "ea_madm"`). Every field but `epsilon` has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EaMadmConfig {
    /// The exploring rate ε per episode of the source task (Algorithm 2, line 17).
    pub epsilon: Schedule,
    /// OWA weights of the decision (Eq. 14–15): visibility with the paper's support
    /// (default), visibility with the distance support, or uniform.
    #[serde(default)]
    pub weighting: Weighting,
    /// The source task's learning signal (Eq. 10–12): `"running"` (default, our repair) or
    /// `"cross_sectional"` (the literal equations, identically 0).
    #[serde(default)]
    pub standardisation: Standardisation,
    /// Where the sub-tasks' experience is kept: an EA tree (default, exact thresholds) or
    /// the plain sub-task tables.
    #[serde(default)]
    pub storage: Storage,
    /// How the sub-tasks are trained before the source task starts.
    #[serde(default)]
    pub pretrain: PretrainConfig,
    /// How each attribute of the decision matrix is scaled before OWA: `"none"` (default, the
    /// paper) or `"min_max"` (per column over the state's actions; a repair, issue 21).
    #[serde(default, skip_serializing_if = "is_no_normalisation")]
    pub normalisation: Normalisation,
    /// Repairs of the robot's sub-task rewards (`{ reach_goal_bonus = true, end_penalties =
    /// true }`, see [`SubtaskRepairs`]); none by default (the paper's Eq. 6–8). Only a robot
    /// task takes them.
    #[serde(default, skip_serializing_if = "is_paper_rewards")]
    pub subtask_rewards: SubtaskRepairs,
}

fn is_no_normalisation(normalisation: &Normalisation) -> bool {
    *normalisation == Normalisation::None
}

fn is_paper_rewards(repairs: &SubtaskRepairs) -> bool {
    *repairs == SubtaskRepairs::PAPER
}

/// Where the trained sub-tasks' experience is stored and looked up from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "StorageRepr", into = "StorageRepr")]
pub enum Storage {
    /// One experience-aggregation tree per sub-task (Sec. IV.B), with these thresholds:
    /// `{ kind = "tree", state_threshold = 1.0, action_threshold = 1.0 }`.
    Tree(EaTreeConfig),
    /// The sub-tasks' own Q tables, read directly (the "no tree" ablation): `{ kind = "table" }`.
    Table,
}

/// The serialised form of [`Storage`] (an empty struct variant rejects extra keys; a unit
/// variant would not).
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum StorageRepr {
    Tree(EaTreeConfig),
    Table {},
}

impl From<StorageRepr> for Storage {
    fn from(repr: StorageRepr) -> Self {
        match repr {
            StorageRepr::Tree(config) => Self::Tree(config),
            StorageRepr::Table {} => Self::Table,
        }
    }
}

impl From<Storage> for StorageRepr {
    fn from(storage: Storage) -> Self {
        match storage {
            Storage::Tree(config) => Self::Tree(config),
            Storage::Table => Self::Table {},
        }
    }
}

impl Default for Storage {
    /// A tree with exact thresholds (`τₛ = τₐ = 1`).
    fn default() -> Self {
        Self::Tree(EaTreeConfig::EXACT)
    }
}

/// Sub-task pre-training: each sub-task's own double-Q learner, on its own reward, with an
/// ε-greedy policy on its own values.
///
/// Without `until`, every sub-task trains exactly `episodes` episodes. With `until` (the
/// stopping rule, docs/paper-notes.md §21.4: Sec. V's "trained to convergence"), `episodes` is
/// the fewest: training goes on past it until the rule finds the sub-task converged, or stops
/// at `until.max_episodes`. TOML:
/// `pretrain = { episodes = 200, epsilon = …, until = { every = 10, stable = 3, max_episodes = 1000 } }`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PretrainConfig {
    /// Episodes per sub-task: all of them without `until`, the fewest with it.
    pub episodes: u64,
    /// The sub-task learners' exploring rate per episode.
    pub epsilon: Schedule,
    /// The stopping rule "to convergence"; `None`: a fixed `episodes`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<Convergence>,
}

/// The stopping rule of sub-task pre-training (docs/paper-notes.md §21.4): after every
/// `every`-th pre-training episode the sub-task's greedy policy plays one check episode (ε = 0,
/// no learning, on its own environment copy and random streams, always from the same start and
/// with the same tie-breaks, so an unchanged policy plays the same episode). The sub-task has
/// converged when its last `stable` checks all reached the target, for a sub-task whose goal is
/// the target (a maze sub-task paid most for reaching it; the robot's "reach the target
/// faster"), or, for any other sub-task, all returned exactly the same sub-task return. It
/// stops at the first check at or after `episodes` at which it has converged, and at
/// `max_episodes` regardless. The check episodes' steps count as pre-training steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Convergence {
    /// Pre-training episodes between two checks (at least 1).
    pub every: u64,
    /// Consecutive checks that must agree (at least 1).
    pub stable: u32,
    /// The hard cap on pre-training episodes (at least `episodes`).
    pub max_episodes: u64,
}

impl Convergence {
    /// The presets' rule: a check every 10 episodes, 3 agreeing checks, at most 1000 episodes
    /// (five times the 200 a fixed pre-training ran; paper-notes §21.4).
    pub const PRESETS: Self = Self {
        every: 10,
        stable: 3,
        max_episodes: 1000,
    };
}

impl Default for PretrainConfig {
    /// 200 episodes of ε-decreasing (0.95, × 0.95 per episode): Table 1's schedule for as
    /// long as the source task trains; no stopping rule (the presets add
    /// [`Convergence::PRESETS`], `paper::pretrain_to_convergence`).
    fn default() -> Self {
        Self {
            episodes: 200,
            epsilon: table1_epsilon_decreasing(),
            until: None,
        }
    }
}

/// Table 1's ε schedule: 0.95 in episode 0, × 0.95 per episode, no floor.
#[must_use]
pub fn table1_epsilon_decreasing() -> Schedule {
    Schedule::Exponential {
        start: 0.95,
        factor: 0.95,
        floor: 0.0,
    }
}

/// Table 1's temperature schedule: 0.1 in episode 0, × 0.95 per episode, at least 0.01.
#[must_use]
pub fn table1_temperature() -> Schedule {
    Schedule::Exponential {
        start: 0.1,
        factor: 0.95,
        floor: 0.01,
    }
}

/// The serialised form of a [`MethodSpec`]: label and fields side by side, tagged by `kind`.
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum MethodRepr {
    EaMadm {
        label: String,
        #[serde(default)]
        role: Role,
        epsilon: Schedule,
        #[serde(default)]
        weighting: Weighting,
        #[serde(default)]
        standardisation: Standardisation,
        #[serde(default)]
        storage: Storage,
        #[serde(default)]
        pretrain: PretrainConfig,
        #[serde(default, skip_serializing_if = "is_no_normalisation")]
        normalisation: Normalisation,
        #[serde(default, skip_serializing_if = "is_paper_rewards")]
        subtask_rewards: SubtaskRepairs,
    },
    EpsilonGreedy {
        label: String,
        #[serde(default)]
        role: Role,
        epsilon: Schedule,
        #[serde(default, skip_serializing_if = "is_task_signal")]
        signal: CompetitorSignal,
        #[serde(default, skip_serializing_if = "is_zero")]
        warmup_env_steps: u64,
        #[serde(default, skip_serializing_if = "is_paper_rewards")]
        subtask_rewards: SubtaskRepairs,
    },
    Softmax {
        label: String,
        #[serde(default)]
        role: Role,
        temperature: Schedule,
        #[serde(default, skip_serializing_if = "is_task_signal")]
        signal: CompetitorSignal,
        #[serde(default, skip_serializing_if = "is_zero")]
        warmup_env_steps: u64,
        #[serde(default, skip_serializing_if = "is_paper_rewards")]
        subtask_rewards: SubtaskRepairs,
    },
    SubtaskGreedy {
        label: String,
        #[serde(default)]
        role: Role,
        subtask: usize,
        epsilon: Schedule,
        #[serde(default)]
        learn: bool,
        #[serde(default)]
        pretrain: PretrainConfig,
    },
}

fn is_task_signal(signal: &CompetitorSignal) -> bool {
    *signal == CompetitorSignal::Task
}

#[expect(
    clippy::trivially_copy_pass_by_ref,
    reason = "serde's skip_serializing_if passes a reference"
)]
fn is_zero(value: &u64) -> bool {
    *value == 0
}

impl From<MethodRepr> for MethodSpec {
    fn from(repr: MethodRepr) -> Self {
        match repr {
            MethodRepr::EaMadm {
                label,
                role,
                epsilon,
                weighting,
                standardisation,
                storage,
                pretrain,
                normalisation,
                subtask_rewards,
            } => Self {
                label,
                role,
                method: Method::EaMadm(EaMadmConfig {
                    epsilon,
                    weighting,
                    standardisation,
                    storage,
                    pretrain,
                    normalisation,
                    subtask_rewards,
                }),
            },
            MethodRepr::EpsilonGreedy {
                label,
                role,
                epsilon,
                signal,
                warmup_env_steps,
                subtask_rewards,
            } => Self {
                label,
                role,
                method: Method::EpsilonGreedy {
                    epsilon,
                    training: CompetitorTraining {
                        signal,
                        warmup_env_steps,
                        subtask_rewards,
                    },
                },
            },
            MethodRepr::Softmax {
                label,
                role,
                temperature,
                signal,
                warmup_env_steps,
                subtask_rewards,
            } => Self {
                label,
                role,
                method: Method::Softmax {
                    temperature,
                    training: CompetitorTraining {
                        signal,
                        warmup_env_steps,
                        subtask_rewards,
                    },
                },
            },
            MethodRepr::SubtaskGreedy {
                label,
                role,
                subtask,
                epsilon,
                learn,
                pretrain,
            } => Self {
                label,
                role,
                method: Method::SubtaskGreedy(SubtaskGreedyConfig {
                    subtask,
                    epsilon,
                    learn,
                    pretrain,
                }),
            },
        }
    }
}

impl From<MethodSpec> for MethodRepr {
    fn from(spec: MethodSpec) -> Self {
        let label = spec.label;
        let role = spec.role;
        match spec.method {
            Method::EaMadm(config) => Self::EaMadm {
                label,
                role,
                epsilon: config.epsilon,
                weighting: config.weighting,
                standardisation: config.standardisation,
                storage: config.storage,
                pretrain: config.pretrain,
                normalisation: config.normalisation,
                subtask_rewards: config.subtask_rewards,
            },
            Method::EpsilonGreedy { epsilon, training } => Self::EpsilonGreedy {
                label,
                role,
                epsilon,
                signal: training.signal,
                warmup_env_steps: training.warmup_env_steps,
                subtask_rewards: training.subtask_rewards,
            },
            Method::Softmax {
                temperature,
                training,
            } => Self::Softmax {
                label,
                role,
                temperature,
                signal: training.signal,
                warmup_env_steps: training.warmup_env_steps,
                subtask_rewards: training.subtask_rewards,
            },
            Method::SubtaskGreedy(config) => Self::SubtaskGreedy {
                label,
                role,
                subtask: config.subtask,
                epsilon: config.epsilon,
                learn: config.learn,
                pretrain: config.pretrain,
            },
        }
    }
}

/// A config that cannot be used. Every variant names the field (a path such as
/// `methods[2].epsilon.factor`) or, for TOML syntax and unknown keys, the line and the key.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ConfigError {
    /// Not TOML, a missing or mistyped field, or an unknown key (the message names the key and
    /// shows the line).
    #[error("experiment config: {0}")]
    Toml(#[from] toml::de::Error),
    /// A value outside its range.
    #[error("experiment config: `{field}` = {value}: expected {expected}")]
    Invalid {
        /// Path of the field, e.g. `methods[2].epsilon.factor`.
        field: String,
        /// The value found, as written.
        value: String,
        /// What the field must be, in words.
        expected: String,
    },
    /// A file the config names cannot be read.
    #[error("experiment config: `{field}`: cannot read {}: {source}", path.display())]
    Read {
        /// The field naming the file, e.g. `task.path`.
        field: String,
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: io::Error,
    },
    /// A robot scenario that does not parse or is invalid.
    #[error("experiment config: `{field}`: {source}")]
    Scenario {
        /// The field naming the scenario (`task.scenario`).
        field: String,
        /// The scenario's error (naming its own field).
        #[source]
        source: wmr_model::ScenarioError,
    },
    /// A learner's or exploration's parameters that `dql` rejects for a reason other than one
    /// parameter's value (which is [`ConfigError::Invalid`]).
    #[error("experiment config: `{field}`: {source}")]
    Learner {
        /// The method's field, e.g. `methods[1].epsilon`.
        field: String,
        /// `dql`'s error.
        #[source]
        source: DqlError,
    },
    /// A weighting that `madm-owa` rejects.
    #[error("experiment config: `{field}`: {source}")]
    Weighting {
        /// The weighting's field, e.g. `methods[0].weighting.orness`.
        field: String,
        /// `madm-owa`'s error (naming its own parameter).
        #[source]
        source: madm_owa::MadmError,
    },
    /// A maze task whose reward specification `mazes` rejects.
    #[error("experiment config: `{field}`: {source}")]
    MazeSpec {
        /// The field naming the task (`task`).
        field: String,
        /// `mazes`' error (naming the spec's own field).
        #[source]
        source: mazes::SpecError,
    },
    /// A maze map that does not parse.
    #[error("experiment config: `{field}`: {source}")]
    Maze {
        /// The field holding or naming the map (`task.map` or `task.path`).
        field: String,
        /// The parse error (with line and column).
        #[source]
        source: mazes::ParseError,
    },
}

impl ConfigError {
    /// The path of the offending field, when the error is about one field.
    #[must_use]
    pub fn field(&self) -> Option<&str> {
        match self {
            Self::Invalid { field, .. }
            | Self::Read { field, .. }
            | Self::Maze { field, .. }
            | Self::Scenario { field, .. }
            | Self::Learner { field, .. }
            | Self::Weighting { field, .. }
            | Self::MazeSpec { field, .. } => Some(field),
            Self::Toml(_) => None,
        }
    }

    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Self::Invalid {
            field: field.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }

    /// A `dql` parameter error, re-addressed under `prefix` (`methods[1]` + `epsilon.factor`).
    fn from_dql(prefix: &str, error: DqlError) -> Self {
        match error {
            DqlError::InvalidParameter {
                name,
                value,
                expected,
            } => Self::invalid(join(prefix, &name), readable_number(value), expected),
            other => Self::Learner {
                field: prefix.to_owned(),
                source: other,
            },
        }
    }
}

/// A number as a person would write it: plain when moderate, in exponent form when huge or
/// tiny (`1e308`, not 309 digits).
fn readable_number(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude != 0.0 && !(1e-6..1e16).contains(&magnitude) {
        format!("{value:e}")
    } else {
        value.to_string()
    }
}

fn join(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_owned()
    } else {
        format!("{prefix}.{name}")
    }
}

impl ExperimentConfig {
    /// Parses and validates a TOML config.
    ///
    /// # Errors
    /// [`ConfigError::Toml`] for bad TOML, a missing, mistyped or unknown key;
    /// [`ConfigError::Invalid`] for a value out of range (see [`validate`](Self::validate)).
    pub fn from_toml_str(text: &str) -> Result<Self, ConfigError> {
        let config: Self = toml::from_str(text)?;
        config.validate()?;
        Ok(config)
    }

    /// The config as TOML (parses back to an equal config).
    ///
    /// # Errors
    /// Only if a value cannot be written as TOML (never for a validated config).
    pub fn to_toml_string(&self) -> Result<String, toml::ser::Error> {
        toml::to_string(self)
    }

    /// Checks every value that serde cannot and that needs no task: counts at least 1,
    /// schedules, the learner's α, γ, ξ and initialisation, OWA weighting parameters, tree
    /// thresholds, unique labels, kept trajectory episodes. The task's own values (its step
    /// cap, the robot's settings, the files it names) are checked once, when the task is built
    /// ([`check`](Self::check), [`TaskConfig::check`]).
    ///
    /// # Errors
    /// The first problem found, as [`ConfigError::Invalid`] naming the field's path.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_label("name", &self.name)?;
        if self.episodes == 0 || self.episodes > MAX_EPISODES {
            return Err(ConfigError::invalid(
                "episodes",
                self.episodes,
                format!("an episode count in 1..={MAX_EPISODES}"),
            ));
        }
        if self.seeds == 0 || self.seeds > MAX_SEEDS {
            return Err(ConfigError::invalid(
                "seeds",
                self.seeds,
                format!("a seed count in 1..={MAX_SEEDS}"),
            ));
        }
        if self.base_seed.checked_add(u64::from(self.seeds)).is_none() {
            return Err(ConfigError::invalid(
                "base_seed",
                self.base_seed,
                "a base seed such that base_seed + seeds fits in 64 bits",
            ));
        }
        self.learner
            .validate()
            .map_err(|error| ConfigError::from_dql("learner", error))?;
        for (index, &episode) in self.trajectories.episodes.iter().enumerate() {
            if episode >= self.episodes {
                return Err(ConfigError::invalid(
                    format!("trajectories.episodes[{index}]"),
                    episode,
                    format!("an episode index below episodes = {}", self.episodes),
                ));
            }
        }
        if let Some(every) = self.evaluation.every
            && (every == 0 || every > self.episodes)
        {
            return Err(ConfigError::invalid(
                "evaluation.every",
                every,
                format!(
                    "a number of training episodes between greedy evaluations in 1..=episodes \
                     (episodes = {})",
                    self.episodes
                ),
            ));
        }
        if self.methods.is_empty() {
            return Err(ConfigError::invalid("methods", "[]", "at least one method"));
        }
        let mut labels = HashSet::new();
        for (index, spec) in self.methods.iter().enumerate() {
            let path = format!("methods[{index}]");
            spec.validate(&path)?;
            if !labels.insert(spec.label.as_str()) {
                return Err(ConfigError::invalid(
                    format!("{path}.label"),
                    format!("{:?}", spec.label),
                    "a label no other method of the config has",
                ));
            }
        }
        Ok(())
    }

    /// Checks the config once and returns it as a checked [`Experiment`](crate::Experiment):
    /// [`validate`](Self::validate), then the task ([`TaskConfig::check`], reading any file it
    /// names), then every method against the task. Nothing later checks these values again,
    /// and a checked experiment runs to its end. Errors name the key the user wrote
    /// (`task.step_cap`, `methods[2].learner.alpha`, `task.scenario.obstacles[0].radius`).
    ///
    /// # Errors
    /// The first problem found, as a [`ConfigError`] naming its key.
    pub fn check(self) -> Result<crate::Experiment, ConfigError> {
        crate::Experiment::from_checked_parts(self)
    }

    /// The seeds of the experiment: `base_seed, base_seed + 1, …` (`seeds` of them).
    pub fn seed_values(&self) -> impl Iterator<Item = u64> + use<> {
        let base = self.base_seed;
        (0..u64::from(self.seeds)).map(move |i| base + i)
    }

    /// The method with this label.
    #[must_use]
    pub fn method(&self, label: &str) -> Option<&MethodSpec> {
        self.methods.iter().find(|spec| spec.label == label)
    }
}

/// Table 1's learner: α = 0.1, γ = 0.95 (ξ = 0.5, zero initialisation).
#[must_use]
pub fn table1_learner() -> DoubleQParams {
    DoubleQParams {
        alpha: 0.1,
        gamma: 0.95,
        ..DoubleQParams::default()
    }
}

impl MethodSpec {
    /// Checks the label and the method's parameters; `path` prefixes field names in errors.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self, path: &str) -> Result<(), ConfigError> {
        check_label(&join(path, "label"), &self.label)?;
        match &self.method {
            Method::EpsilonGreedy { epsilon, training } => {
                EpsilonGreedy::new(*epsilon).map_err(|e| ConfigError::from_dql(path, e))?;
                training.validate(path)?;
            }
            Method::Softmax {
                temperature,
                training,
            } => {
                Softmax::new(*temperature).map_err(|e| ConfigError::from_dql(path, e))?;
                training.validate(path)?;
            }
            Method::EaMadm(config) => config.validate(path)?,
            Method::SubtaskGreedy(config) => {
                EpsilonGreedy::new(config.epsilon).map_err(|e| ConfigError::from_dql(path, e))?;
                validate_pretrain(path, &config.pretrain)?;
            }
        }
        Ok(())
    }
}

impl EaMadmConfig {
    /// Checks ε, the weighting, the tree thresholds and the pre-training; `path` prefixes
    /// field names in errors.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self, path: &str) -> Result<(), ConfigError> {
        EpsilonGreedy::new(self.epsilon).map_err(|e| ConfigError::from_dql(path, e))?;
        if let Err(error) = self.weighting.validate() {
            let field = match &self.weighting {
                Weighting::Visibility { .. } => "weighting.support.epsilon",
                Weighting::MaximumEntropy { .. } => "weighting.orness",
                _ => "weighting",
            };
            return Err(ConfigError::Weighting {
                field: join(path, field),
                source: error,
            });
        }
        if let Storage::Tree(tree) = &self.storage {
            for (name, value) in [
                ("state_threshold", tree.state_threshold),
                ("action_threshold", tree.action_threshold),
            ] {
                if !(0.0..=1.0).contains(&value) {
                    return Err(ConfigError::invalid(
                        join(path, &format!("storage.{name}")),
                        value,
                        "a similarity threshold in [0, 1]",
                    ));
                }
            }
        }
        validate_pretrain(path, &self.pretrain)
    }
}

impl CompetitorTraining {
    /// Checks the warm-up budget; `path` prefixes field names in errors. (Whether the task has
    /// the sub-tasks a signal needs is checked when the task is loaded.)
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming `warmup_env_steps`.
    pub fn validate(&self, path: &str) -> Result<(), ConfigError> {
        if self.warmup_env_steps > MAX_WARMUP_ENV_STEPS {
            return Err(ConfigError::invalid(
                join(path, "warmup_env_steps"),
                self.warmup_env_steps,
                format!("a step budget in 0..={MAX_WARMUP_ENV_STEPS}"),
            ));
        }
        Ok(())
    }
}

fn validate_pretrain(path: &str, config: &PretrainConfig) -> Result<(), ConfigError> {
    let pretrain = join(path, "pretrain");
    if config.episodes == 0 || config.episodes > MAX_EPISODES {
        return Err(ConfigError::invalid(
            join(&pretrain, "episodes"),
            config.episodes,
            format!("an episode count in 1..={MAX_EPISODES}"),
        ));
    }
    EpsilonGreedy::new(config.epsilon).map_err(|e| ConfigError::from_dql(&pretrain, e))?;
    if let Some(until) = config.until {
        let until_path = join(&pretrain, "until");
        if until.every == 0 || until.every > MAX_EPISODES {
            return Err(ConfigError::invalid(
                join(&until_path, "every"),
                until.every,
                format!("episodes between checks in 1..={MAX_EPISODES}"),
            ));
        }
        if until.stable == 0 {
            return Err(ConfigError::invalid(
                join(&until_path, "stable"),
                until.stable,
                "at least 1 check",
            ));
        }
        if until.max_episodes < config.episodes || until.max_episodes > MAX_EPISODES {
            return Err(ConfigError::invalid(
                join(&until_path, "max_episodes"),
                until.max_episodes,
                format!(
                    "a cap in {}..={MAX_EPISODES} (at least pretrain.episodes, the fewest)",
                    config.episodes
                ),
            ));
        }
    }
    Ok(())
}

/// Largest file a config may be read from, or name (a maze map, a robot scenario): 1 MiB. The
/// paper's configs, maps and scenarios are a few KiB; the limit keeps a mistaken path (a device,
/// a log) from filling memory.
pub const MAX_INPUT_FILE_BYTES: u64 = 1 << 20;

/// Reads a text input file (a config, or a file a config names) with bounds: it must be a
/// regular file (not a folder, device or FIFO, which could hang or never end) of at most
/// [`MAX_INPUT_FILE_BYTES`], in UTF-8. `field` names what points at the file in errors
/// (`--config`, `task.path`, `task.scenario`).
///
/// # Errors
/// [`ConfigError::Read`] naming `field` and `path`: missing, unreadable, not a regular file,
/// too large, or not UTF-8.
pub fn read_input_file(path: &std::path::Path, field: &str) -> Result<String, ConfigError> {
    use std::io::Read as _;
    let fail = |source: io::Error| ConfigError::Read {
        field: field.to_owned(),
        path: path.to_path_buf(),
        source,
    };
    let invalid = |message: String| fail(io::Error::new(io::ErrorKind::InvalidInput, message));
    // Look before opening: opening a FIFO for reading blocks until a writer appears.
    let metadata = std::fs::metadata(path).map_err(fail)?;
    if !metadata.is_file() {
        return Err(invalid(
            "not a regular file (folders, devices and pipes are refused)".to_owned(),
        ));
    }
    let too_large = || {
        invalid(format!(
            "larger than the limit of {MAX_INPUT_FILE_BYTES} bytes (1 MiB) for input files"
        ))
    };
    if metadata.len() > MAX_INPUT_FILE_BYTES {
        return Err(too_large());
    }
    // Opened without waiting on a FIFO swapped in since the look (`O_NONBLOCK`), and checked
    // again on the open file.
    let mut options = std::fs::File::options();
    options.read(true);
    #[cfg(target_os = "linux")]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, 0o4000);
    #[cfg(target_os = "macos")]
    std::os::unix::fs::OpenOptionsExt::custom_flags(&mut options, 0x4);
    let file = options.open(path).map_err(fail)?;
    if !file.metadata().map_err(fail)?.is_file() {
        return Err(invalid(
            "not a regular file (folders, devices and pipes are refused)".to_owned(),
        ));
    }
    let mut bytes = Vec::new();
    // The file may have grown since: read one byte past the limit at most.
    file.take(MAX_INPUT_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(fail)?;
    if bytes.len() as u64 > MAX_INPUT_FILE_BYTES {
        return Err(too_large());
    }
    String::from_utf8(bytes).map_err(|error| {
        invalid(format!(
            "not UTF-8 text (invalid byte at offset {})",
            error.utf8_error().valid_up_to()
        ))
    })
}

/// Names an experiment or method may not have, compared without regard to case: the entries
/// the reproduction tooling keeps in its output folder beside the experiments' folders
/// ([`crate::output_names::TOP_LEVEL`]; its own bookkeeping entries are hidden names, which
/// slugs cannot be), and the device
/// names Windows reserves. An experiment's name becomes a folder in that output folder, so one of
/// these would overwrite or mix with another output.
pub const RESERVED_NAMES: &[&str] = &crate::output_names::RESERVED;

/// Whether `label` is a safe slug for a file or folder name: 1 to 64 characters from ASCII
/// letters, digits, `-`, `_` and `.`, starting with a letter or digit (so never `.`, `..` or a
/// hidden name), never ending with `.`, and not one of [`RESERVED_NAMES`] (ignoring case).
#[must_use]
pub fn is_safe_slug(label: &str) -> bool {
    let Some(first) = label.chars().next() else {
        return false;
    };
    label.len() <= 64
        && first.is_ascii_alphanumeric()
        && !label.ends_with('.')
        && label
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
        && !RESERVED_NAMES
            .iter()
            .any(|reserved| reserved.eq_ignore_ascii_case(label))
}

/// Labels and names go into file and folder names: they must be [safe slugs](is_safe_slug).
fn check_label(field: &str, label: &str) -> Result<(), ConfigError> {
    if is_safe_slug(label) {
        Ok(())
    } else {
        Err(ConfigError::invalid(
            field,
            format!("{label:?}"),
            "a name of 1 to 64 characters from letters, digits, '-', '_' and '.', starting with a \
             letter or digit, not ending with '.', and not a reserved name (runs, results.json, \
             REPORT.md, or a Windows device name such as con or nul)",
        ))
    }
}
