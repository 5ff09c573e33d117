//! The same tuning budget for every method (issue 33 item 3): hyperparameter trials as data.
//!
//! The paper gives one setting per method, and the robot's open settings were chosen by a
//! sweep over the three competitors only (docs/paper-notes.md §8.5). Here every method the
//! claims compare (EA-MADM and each competitor, on the mazes and on the robot) gets the same
//! number of trials, [`TRIALS_PER_METHOD`] by default: trial 0 is the method's setting in the
//! preset (the paper's), trials `1..` are drawn at random (random search, Bergstra & Bengio
//! 2012) from the stated ranges of [`SearchSpace::PAPER`]. Each trial is run on the
//! **tuning seeds** ([`TUNING_BASE_SEED`]` + 0..`[`TUNING_SEEDS`]), disjoint from every
//! held-out seed a config can ask for; the best trial per method by the task's [`Objective`]
//! is then run on the held-out seeds ([`Trial::held_out`]) and judged by the normal claims.
//! The protocol follows Eimer, Lindauer & Raileanu, *Hyperparameters in Reinforcement
//! Learning and How To Tune Them* (ICML 2023): separate tuning and test seeds, a stated search
//! space per algorithm, one search method and budget, reported with every trial
//! (`tuning.csv`, [`TuningRow`]); docs/paper-notes.md §19 gives the ranges and their reasons.
//!
//! Which values a method's trials vary depends on its kind ([`SearchKind`]):
//!
//! | kind | varies |
//! |---|---|
//! | EA-MADM | α, γ, ε schedule (start, decay), tree threshold τ (when it keeps trees), pre-training episodes |
//! | ε-greedy (constant ε) | α, γ, ε |
//! | ε-decreasing | α, γ, ε schedule (start, decay) |
//! | softmax | α, γ, temperature schedule (start, decay, floor) |
//!
//! α and γ are the experiment's learner (for EA-MADM also its sub-tasks' learners), so a
//! trial is an experiment of one method ([`Trial::experiment`]).
//!
//! # Draws (the same trials on every platform)
//!
//! A method's trials come from `ChaCha8Rng::seed_from_u64(SAMPLER_SEED ^ h)`, `h` the 64-bit
//! FNV-1a hash of `"<task>/<method>"`, so they do not depend on which other methods are
//! tuned. Each range is a grid of [`GRID_POINTS`] values (evenly spaced, kept to four
//! significant digits, or evenly spaced in the logarithm and rounded to three); a draw is a
//! grid index by
//! Lemire's method on 32-bit words. For each trial `1..`, in this order: α, horizon (γ),
//! then the kind's values in the order of the table above (start before decay before floor).
//! The logarithmic grids use `powf`, whose last bit may differ between platforms; a test
//! checks that no grid point lies within `10⁻⁹` (relative) of a rounding boundary, so the
//! rounded values cannot differ.
//!
//! ```
//! use eamadm::{paper, tuning};
//!
//! let task1 = paper::task1();
//! let trials = tuning::trials(&task1, "softmax", tuning::TRIALS_PER_METHOD)?;
//! assert_eq!(trials.len(), 16);
//! assert!(trials[0].paper_setting);
//! let config = trials[5].experiment(&task1)?;
//! assert_eq!(config.name, "task1-tune-softmax-t05");
//! assert_eq!(config.methods.len(), 1);
//! assert_eq!(config.base_seed, tuning::TUNING_BASE_SEED);
//! # Ok::<(), tuning::TuningError>(())
//! ```

use std::io::Write;

use dql::Schedule;
use ea_tree::EaTreeConfig;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use thiserror::Error;

use crate::columns::{Column, FieldType};
use crate::config::{
    ConfigError, ExperimentConfig, MAX_SEEDS, Method, MethodSpec, Storage, TaskConfig,
    TrajectoryConfig,
};
use crate::scores::FinalScore;
use crate::stats::{Statistic, StatsError};

/// Trials per method, the paper's setting included.
pub const TRIALS_PER_METHOD: u32 = 16;
/// The fewest trials a tuning plan may give a method (issue 33: at least 16).
pub const MIN_TRIALS: u32 = 16;
/// The most trials per method.
pub const MAX_TRIALS: u32 = 1_000;

/// Tuning seeds per trial.
pub const TUNING_SEEDS: u32 = 10;

/// The first tuning seed. Held-out seeds are `base_seed + 0..seeds` with `seeds` at most
/// [`MAX_SEEDS`]; the presets start at 0 (and the robot sweep's held-out check at 1000), so
/// tuning seeds from 10⁹ never coincide with them ([`check_disjoint`] checks any config).
pub const TUNING_BASE_SEED: u64 = 1_000_000_000;

/// Mixed into every method's sampler seed.
pub const SAMPLER_SEED: u64 = 33;

/// Values per range grid.
pub const GRID_POINTS: u32 = 1001;

/// How a range's grid is spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// Evenly spaced values, kept to four significant digits.
    Linear,
    /// Evenly spaced logarithms, each value rounded to three significant digits.
    Log,
}

/// A closed range of one hyperparameter and how it is searched: a grid of [`GRID_POINTS`]
/// values from `low` to `high`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Range {
    /// The smallest value.
    pub low: f64,
    /// The largest value.
    pub high: f64,
    /// Grid spacing.
    pub scale: Scale,
}

impl Range {
    const fn log(low: f64, high: f64) -> Self {
        Self {
            low,
            high,
            scale: Scale::Log,
        }
    }

    const fn linear(low: f64, high: f64) -> Self {
        Self {
            low,
            high,
            scale: Scale::Linear,
        }
    }

    /// Grid point `k` of [`GRID_POINTS`] (`k < GRID_POINTS`): the
    /// [`unrounded_point`](Self::unrounded_point) rounded to [`digits`](Self::digits)
    /// significant digits.
    #[must_use]
    pub fn point(&self, k: u32) -> f64 {
        round_to_digits(self.unrounded_point(k), self.digits())
    }

    /// Significant digits a grid point keeps: 4 on a linear grid (its steps are a thousandth
    /// of the range, so no value is lost), 3 on a logarithmic one.
    #[must_use]
    pub fn digits(&self) -> usize {
        match self.scale {
            Scale::Linear => 4,
            Scale::Log => 3,
        }
    }

    /// Grid point `k` before rounding: `low + (high − low)·k/1000` (exact IEEE operations,
    /// the same everywhere) or `low·(high/low)^(k/1000)` (`powf`, whose last bit may differ
    /// between platforms).
    #[must_use]
    pub fn unrounded_point(&self, k: u32) -> f64 {
        let last = f64::from(GRID_POINTS - 1);
        let at = f64::from(k.min(GRID_POINTS - 1));
        match self.scale {
            Scale::Linear => self.low + (self.high - self.low) * at / last,
            Scale::Log => self.low * (self.high / self.low).powf(at / last),
        }
    }
}

/// `value` rounded to `digits` significant digits through Rust's exact decimal formatting
/// (the same on every platform).
fn round_to_digits(value: f64, digits: usize) -> f64 {
    format!("{value:.prec$e}", prec = digits - 1)
        .parse()
        .unwrap_or(value)
}

/// The ranges every method's trials are drawn from (docs/paper-notes.md §19 gives the
/// reasons).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SearchSpace {
    /// Learning rate α (every learner of the trial).
    pub alpha: Range,
    /// The discount's horizon `1/(1 − γ)` in steps; γ = 1 − 1/horizon.
    pub horizon: Range,
    /// ε of the constant-ε competitor.
    pub epsilon: Range,
    /// ε in episode 0 of a decreasing schedule (ε-decreasing, EA-MADM).
    pub epsilon_start: Range,
    /// A schedule's decay time in episodes `D`; factor = 1 − 1/D per episode.
    pub decay_episodes: Range,
    /// Softmax temperature in episode 0.
    pub temperature_start: Range,
    /// Softmax temperature floor (at most the start: the smaller of the two is taken).
    pub temperature_floor: Range,
    /// EA-MADM's tree thresholds τₛ = τₐ.
    pub tree_threshold: Range,
    /// EA-MADM's sub-task pre-training episodes (rounded to a whole number).
    pub pretrain_episodes: Range,
}

impl SearchSpace {
    /// The ranges of issue 33 (docs/paper-notes.md §19).
    pub const PAPER: Self = Self {
        alpha: Range::log(0.01, 1.0),
        horizon: Range::log(10.0, 1000.0),
        epsilon: Range::log(0.005, 0.5),
        epsilon_start: Range::linear(0.1, 1.0),
        decay_episodes: Range::log(5.0, 500.0),
        temperature_start: Range::log(0.01, 10.0),
        temperature_floor: Range::log(0.001, 1.0),
        tree_threshold: Range::linear(0.3, 1.0),
        pretrain_episodes: Range::log(50.0, 800.0),
    };
}

/// Which values a method's trials vary, from its kind and schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SearchKind {
    /// EA-MADM: α, γ, ε start and decay, τ (with trees), pre-training episodes.
    EaMadm,
    /// ε-greedy with a constant ε: α, γ, ε.
    EpsilonConstant,
    /// ε-greedy with an exponential schedule: α, γ, ε start and decay.
    EpsilonDecreasing,
    /// Softmax: α, γ, temperature start, decay and floor.
    Softmax,
}

impl SearchKind {
    /// The kind of `method`, or `None` for one that is not tuned (a sub-task alone).
    #[must_use]
    pub fn of(method: &Method) -> Option<Self> {
        match method {
            Method::EaMadm(_) => Some(Self::EaMadm),
            Method::EpsilonGreedy {
                epsilon: Schedule::Constant(_),
                ..
            } => Some(Self::EpsilonConstant),
            Method::EpsilonGreedy { .. } => Some(Self::EpsilonDecreasing),
            Method::Softmax { .. } => Some(Self::Softmax),
            _ => None,
        }
    }
}

/// What one trial sets.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrialParams {
    /// α of every learner.
    pub alpha: f64,
    /// γ of every learner.
    pub gamma: f64,
    /// The exploration schedule: ε for EA-MADM and the ε-greedy competitors, the temperature
    /// for softmax.
    pub exploration: Schedule,
    /// EA-MADM's tree thresholds τₛ = τₐ (none for the competitors, or EA-MADM without trees).
    pub tree_threshold: Option<f64>,
    /// EA-MADM's sub-task pre-training episodes (none for the competitors).
    pub pretrain_episodes: Option<u64>,
}

/// One trial of one method on one task.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trial {
    /// The base experiment's name (`task1`, `task2`, `robot`, …).
    pub task: String,
    /// The method's label.
    pub method: String,
    /// Its index: 0 is the preset's setting, `1..` are drawn.
    pub trial: u32,
    /// Whether this is the preset's (the paper's) setting.
    pub paper_setting: bool,
    /// What it varies.
    pub kind: SearchKind,
    /// The values.
    pub params: TrialParams,
}

/// A tuning request that cannot be served.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum TuningError {
    /// A method the base config does not have.
    #[error("tuning: {task} has no method `{method}`")]
    UnknownMethod {
        /// The base experiment.
        task: String,
        /// The label asked for.
        method: String,
    },
    /// A method with nothing to tune (a sub-task alone).
    #[error("tuning: `{method}` is a {kind} method, which has no hyperparameters to tune")]
    NotTunable {
        /// The label.
        method: String,
        /// Its kind name.
        kind: &'static str,
    },
    /// A budget outside `MIN_TRIALS..=MAX_TRIALS`.
    #[error("tuning: {trials} trials per method; expected {MIN_TRIALS} to {MAX_TRIALS}")]
    Budget {
        /// The budget asked for.
        trials: u32,
    },
    /// A held-out seed range that meets the tuning seeds.
    #[error(
        "tuning: the held-out seeds of {task} ({first}..{end}) meet the tuning seeds \
         ({TUNING_BASE_SEED}..{tuning_end}); choose a base_seed below {TUNING_BASE_SEED} − seeds"
    )]
    SeedsOverlap {
        /// The experiment.
        task: String,
        /// Its first held-out seed.
        first: u64,
        /// One past its last.
        end: u64,
        /// One past the last tuning seed.
        tuning_end: u64,
    },
    /// A number of tuning seeds outside `1..=TUNING_SEEDS`.
    #[error("tuning: {seeds} tuning seeds per trial; expected 1 to {TUNING_SEEDS}")]
    TuningSeeds {
        /// The number asked for.
        seeds: u32,
    },
    /// A trial's config that does not validate.
    #[error("tuning: {0}")]
    Config(#[from] Box<ConfigError>),
    /// Scores that give no objective value.
    #[error("tuning: trial {experiment}: {reason}")]
    Score {
        /// The trial's experiment.
        experiment: String,
        /// Why.
        reason: String,
    },
}

/// The held-out seeds of `config` must not meet the tuning seeds.
///
/// # Errors
/// [`TuningError::SeedsOverlap`].
pub fn check_disjoint(config: &ExperimentConfig) -> Result<(), TuningError> {
    let first = config.base_seed;
    let end = first.saturating_add(u64::from(config.seeds));
    let tuning_end = TUNING_BASE_SEED + u64::from(TUNING_SEEDS);
    if first < tuning_end && TUNING_BASE_SEED < end {
        return Err(TuningError::SeedsOverlap {
            task: config.name.clone(),
            first,
            end,
            tuning_end,
        });
    }
    Ok(())
}

// `MAX_SEEDS` held-out seeds from base seed 0 stay below the tuning seeds.
const _: () = assert!((MAX_SEEDS as u64) < TUNING_BASE_SEED);

/// The trials of `method` in `base`: `budget` of them, trial 0 its setting in `base`.
///
/// # Errors
/// [`TuningError::UnknownMethod`], [`TuningError::NotTunable`], [`TuningError::Budget`].
pub fn trials(
    base: &ExperimentConfig,
    method: &str,
    budget: u32,
) -> Result<Vec<Trial>, TuningError> {
    if !(MIN_TRIALS..=MAX_TRIALS).contains(&budget) {
        return Err(TuningError::Budget { trials: budget });
    }
    let spec = base
        .method(method)
        .ok_or_else(|| TuningError::UnknownMethod {
            task: base.name.clone(),
            method: method.to_owned(),
        })?;
    let kind = SearchKind::of(&spec.method).ok_or(TuningError::NotTunable {
        method: method.to_owned(),
        kind: spec.method.kind_name(),
    })?;
    let mut sampler = Sampler::new(&base.name, method);
    let space = SearchSpace::PAPER;
    let mut trials = Vec::with_capacity(budget as usize);
    trials.push(Trial {
        task: base.name.clone(),
        method: method.to_owned(),
        trial: 0,
        paper_setting: true,
        kind,
        params: preset_params(base, spec),
    });
    let keeps_trees =
        matches!(&spec.method, Method::EaMadm(c) if matches!(c.storage, Storage::Tree(_)));
    for trial in 1..budget {
        let alpha = sampler.draw(space.alpha);
        let gamma = 1.0 - 1.0 / sampler.draw(space.horizon);
        let decay = |sampler: &mut Sampler| 1.0 - 1.0 / sampler.draw(space.decay_episodes);
        let (exploration, tree_threshold, pretrain_episodes) = match kind {
            SearchKind::EpsilonConstant => {
                (Schedule::Constant(sampler.draw(space.epsilon)), None, None)
            }
            SearchKind::EpsilonDecreasing => {
                let start = sampler.draw(space.epsilon_start);
                let factor = decay(&mut sampler);
                (
                    Schedule::Exponential {
                        start,
                        factor,
                        floor: 0.0,
                    },
                    None,
                    None,
                )
            }
            SearchKind::Softmax => {
                let start = sampler.draw(space.temperature_start);
                let factor = decay(&mut sampler);
                let floor = sampler.draw(space.temperature_floor).min(start);
                (
                    Schedule::Exponential {
                        start,
                        factor,
                        floor,
                    },
                    None,
                    None,
                )
            }
            SearchKind::EaMadm => {
                let start = sampler.draw(space.epsilon_start);
                let factor = decay(&mut sampler);
                let tau = keeps_trees.then(|| sampler.draw(space.tree_threshold));
                // The grid's values are rounded; whole episodes, at least 1.
                let episodes = sampler.draw(space.pretrain_episodes).round().max(1.0) as u64;
                (
                    Schedule::Exponential {
                        start,
                        factor,
                        floor: 0.0,
                    },
                    tau,
                    Some(episodes),
                )
            }
        };
        trials.push(Trial {
            task: base.name.clone(),
            method: method.to_owned(),
            trial,
            paper_setting: false,
            kind,
            params: TrialParams {
                alpha,
                gamma,
                exploration,
                tree_threshold,
                pretrain_episodes,
            },
        });
    }
    Ok(trials)
}

/// Every tunable method's trials in `base` among `methods` (in that order), `budget` each.
///
/// # Errors
/// As [`trials`].
pub fn tuning_plan(
    base: &ExperimentConfig,
    methods: &[&str],
    budget: u32,
) -> Result<Vec<Trial>, TuningError> {
    let mut plan = Vec::new();
    for method in methods {
        plan.extend(trials(base, method, budget)?);
    }
    Ok(plan)
}

/// The labels of the methods the claims compare in `base` (role `paper`): the ones a tuning
/// plan tunes.
#[must_use]
pub fn paper_methods(base: &ExperimentConfig) -> Vec<&str> {
    base.methods
        .iter()
        .filter(|spec| spec.role == crate::Role::Paper)
        .map(|spec| spec.label.as_str())
        .collect()
}

/// The setting of `spec` in `base`.
fn preset_params(base: &ExperimentConfig, spec: &MethodSpec) -> TrialParams {
    let (exploration, tree_threshold, pretrain_episodes) = match &spec.method {
        Method::EaMadm(config) => (
            config.epsilon,
            match config.storage {
                Storage::Tree(tree) => Some(tree.state_threshold),
                Storage::Table => None,
            },
            Some(config.pretrain.episodes),
        ),
        Method::EpsilonGreedy { epsilon, .. } => (*epsilon, None, None),
        Method::Softmax { temperature, .. } => (*temperature, None, None),
        Method::SubtaskGreedy(config) => (config.epsilon, None, Some(config.pretrain.episodes)),
    };
    TrialParams {
        alpha: base.learner.alpha,
        gamma: base.learner.gamma,
        exploration,
        tree_threshold,
        pretrain_episodes,
    }
}

impl Trial {
    /// The trial's experiment name: `<task>-tune-<method>-t<NN>`.
    #[must_use]
    pub fn experiment_name(&self) -> String {
        format!("{}-tune-{}-t{:02}", self.task, self.method, self.trial)
    }

    /// The method of `base` with this trial's values.
    fn method(&self, base: &ExperimentConfig) -> Result<MethodSpec, TuningError> {
        let mut spec = base
            .method(&self.method)
            .ok_or_else(|| TuningError::UnknownMethod {
                task: base.name.clone(),
                method: self.method.clone(),
            })?
            .clone();
        let params = &self.params;
        match &mut spec.method {
            Method::EaMadm(config) => {
                config.epsilon = params.exploration;
                if let (Some(tau), Storage::Tree(_)) = (params.tree_threshold, config.storage) {
                    config.storage = Storage::Tree(EaTreeConfig {
                        state_threshold: tau,
                        action_threshold: tau,
                    });
                }
                if let Some(episodes) = params.pretrain_episodes {
                    // With the stopping rule the drawn length is the fewest episodes; the
                    // rule's cap must stay at least that (docs/paper-notes.md §23).
                    config.pretrain.episodes = episodes;
                    if let Some(until) = &mut config.pretrain.until {
                        until.max_episodes = until.max_episodes.max(episodes);
                    }
                }
            }
            Method::EpsilonGreedy { epsilon, .. } => *epsilon = params.exploration,
            Method::Softmax { temperature, .. } => *temperature = params.exploration,
            other => {
                return Err(TuningError::NotTunable {
                    method: self.method.clone(),
                    kind: other.kind_name(),
                });
            }
        }
        Ok(spec)
    }

    /// The trial as an experiment of its one method on the tuning seeds: named
    /// [`experiment_name`](Self::experiment_name), `base`'s task, episodes and evaluation,
    /// the trial's α and γ, [`TUNING_SEEDS`] seeds from [`TUNING_BASE_SEED`], no training
    /// trajectory kept.
    ///
    /// # Errors
    /// [`TuningError::UnknownMethod`] or [`TuningError::NotTunable`] when `base` is not the
    /// trial's, [`TuningError::Config`] when the result does not validate.
    pub fn experiment(&self, base: &ExperimentConfig) -> Result<ExperimentConfig, TuningError> {
        self.experiment_on(base, TUNING_SEEDS)
    }

    /// As [`experiment`](Self::experiment) on `seeds` tuning seeds from [`TUNING_BASE_SEED`]
    /// (the suite's `--quick` runs fewer; at most [`TUNING_SEEDS`]).
    ///
    /// # Errors
    /// As [`experiment`](Self::experiment), and [`TuningError::TuningSeeds`].
    pub fn experiment_on(
        &self,
        base: &ExperimentConfig,
        seeds: u32,
    ) -> Result<ExperimentConfig, TuningError> {
        if !(1..=TUNING_SEEDS).contains(&seeds) {
            return Err(TuningError::TuningSeeds { seeds });
        }
        self.config(base, self.experiment_name(), TUNING_BASE_SEED, seeds)
    }

    /// The trial (a method's chosen one) on `base`'s own held-out seeds: named
    /// `<task>-best-<method>`, otherwise as [`experiment`](Self::experiment). Its runs pair by
    /// seed with `base`'s (streams depend on the seed only), so "each at its best" verdicts
    /// compare these experiments' rows.
    ///
    /// # Errors
    /// As [`experiment`](Self::experiment), and [`TuningError::SeedsOverlap`].
    pub fn held_out(&self, base: &ExperimentConfig) -> Result<ExperimentConfig, TuningError> {
        check_disjoint(base)?;
        self.config(
            base,
            format!("{}-best-{}", self.task, self.method),
            base.base_seed,
            base.seeds,
        )
    }

    fn config(
        &self,
        base: &ExperimentConfig,
        name: String,
        base_seed: u64,
        seeds: u32,
    ) -> Result<ExperimentConfig, TuningError> {
        let method = self.method(base)?;
        let mut learner = base.learner;
        learner.alpha = self.params.alpha;
        learner.gamma = self.params.gamma;
        let config = ExperimentConfig {
            name,
            task: base.task.clone(),
            episodes: base.episodes,
            seeds,
            base_seed,
            learner,
            trajectories: TrajectoryConfig {
                first: false,
                last: false,
                episodes: Vec::new(),
            },
            evaluation: base.evaluation.clone(),
            methods: vec![method],
        };
        config.validate().map_err(Box::new)?;
        Ok(config)
    }
}

/// What a trial is scored by on its tuning seeds, decided per task before any trial ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// Mazes: the IQM over seeds of `final_steps` (claim C1's metric), lower is better. The
    /// return would not do: under Task I's rule every bump-free reaching episode returns the
    /// same whatever its length.
    FinalStepsIqm,
    /// Robot: the mean over seeds of `success_rate` (final-window share of episodes that
    /// reach), higher is better: what the robot's sweep chose by (docs/paper-notes.md §8.5).
    SuccessRateMean,
}

impl Objective {
    /// The objective of `task`'s trials.
    #[must_use]
    pub fn of(task: &TaskConfig) -> Self {
        match task {
            TaskConfig::Robot { .. } => Self::SuccessRateMean,
            _ => Self::FinalStepsIqm,
        }
    }

    /// `final_steps_iqm` or `success_rate_mean`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::FinalStepsIqm => "final_steps_iqm",
            Self::SuccessRateMean => "success_rate_mean",
        }
    }

    /// Whether `a` is strictly better than `b`.
    #[must_use]
    pub fn better(self, a: f64, b: f64) -> bool {
        match self {
            Self::FinalStepsIqm => a < b,
            Self::SuccessRateMean => a > b,
        }
    }

    /// The objective over a trial's final scores (one row per tuning seed).
    ///
    /// # Errors
    /// [`StatsError::Empty`] for no row.
    pub fn score(self, rows: &[FinalScore]) -> Result<f64, StatsError> {
        match self {
            Self::FinalStepsIqm => {
                let values: Vec<f64> = rows.iter().map(|row| row.final_steps).collect();
                Statistic::Iqm.of(&values)
            }
            Self::SuccessRateMean => {
                let values: Vec<f64> = rows.iter().map(|row| row.success_rate).collect();
                Statistic::Mean.of(&values)
            }
        }
    }
}

/// One row of `tuning.csv`: a trial, its values and (once run) its score.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TuningRow {
    /// The base experiment.
    pub task: String,
    /// The method's label.
    pub method: String,
    /// The trial's index (0: the preset's setting).
    pub trial: u32,
    /// Whether the trial is the preset's setting.
    pub paper_setting: bool,
    /// The trial's experiment (`<task>-tune-<method>-t<NN>`).
    pub experiment: String,
    /// α.
    pub alpha: f64,
    /// γ.
    pub gamma: f64,
    /// ε (or the temperature, see `exploration`) in episode 0.
    pub exploration_start: f64,
    /// Its factor per episode (1 for a constant).
    pub exploration_factor: f64,
    /// Its floor (the constant itself for a constant).
    pub exploration_floor: f64,
    /// `epsilon` or `temperature`.
    pub exploration: &'static str,
    /// EA-MADM's τ.
    pub tree_threshold: Option<f64>,
    /// EA-MADM's pre-training episodes.
    pub pretrain_episodes: Option<u64>,
    /// Tuning seeds the trial ran on.
    pub tuning_seeds: u32,
    /// The first of them.
    pub first_tuning_seed: u64,
    /// The objective's name.
    pub objective: &'static str,
    /// The objective over the tuning seeds; blank until the trial ran.
    pub score: Option<f64>,
    /// Whether it is its method's best trial; blank until every trial of the method ran.
    pub chosen: Option<bool>,
}

impl TuningRow {
    /// The row of `trial` in a task with `objective`, not yet scored.
    #[must_use]
    pub fn new(trial: &Trial, objective: Objective) -> Self {
        let (start, factor, floor) = match trial.params.exploration {
            Schedule::Constant(value) => (value, 1.0, value),
            Schedule::Exponential {
                start,
                factor,
                floor,
            } => (start, factor, floor),
        };
        Self {
            task: trial.task.clone(),
            method: trial.method.clone(),
            trial: trial.trial,
            paper_setting: trial.paper_setting,
            experiment: trial.experiment_name(),
            alpha: trial.params.alpha,
            gamma: trial.params.gamma,
            exploration_start: start,
            exploration_factor: factor,
            exploration_floor: floor,
            exploration: match trial.kind {
                SearchKind::Softmax => "temperature",
                _ => "epsilon",
            },
            tree_threshold: trial.params.tree_threshold,
            pretrain_episodes: trial.params.pretrain_episodes,
            tuning_seeds: TUNING_SEEDS,
            first_tuning_seed: TUNING_BASE_SEED,
            objective: objective.name(),
            score: None,
            chosen: None,
        }
    }
}

/// Marks each method's best scored trial `chosen` (the others `false`) once every trial of the
/// method has a score: the best by `objective`, the lowest trial index among equals (so the
/// preset's setting wins a tie). Methods with an unscored trial stay blank.
pub fn choose(rows: &mut [TuningRow], objective: Objective) {
    let mut methods: Vec<(String, String)> = Vec::new();
    for row in rows.iter() {
        let key = (row.task.clone(), row.method.clone());
        if !methods.contains(&key) {
            methods.push(key);
        }
    }
    for (task, method) in methods {
        let of_method = |row: &TuningRow| row.task == task && row.method == method;
        if rows
            .iter()
            .filter(|r| of_method(r))
            .any(|r| r.score.is_none())
        {
            continue;
        }
        let mut best: Option<(f64, u32)> = None;
        for row in rows.iter().filter(|r| of_method(r)) {
            let score = row.score.unwrap_or(f64::NAN);
            let replace = match best {
                None => true,
                Some((best_score, best_trial)) => {
                    objective.better(score, best_score)
                        || (score == best_score && row.trial < best_trial)
                }
            };
            if replace {
                best = Some((score, row.trial));
            }
        }
        for row in rows.iter_mut().filter(|r| of_method(r)) {
            row.chosen = Some(best.is_some_and(|(_, trial)| trial == row.trial));
        }
    }
}

/// The columns of `tuning.csv`, in order (the fields of [`TuningRow`]).
pub const TUNING_COLUMNS: &[Column] = &[
    Column::new("task", FieldType::String, "The experiment tuned (`task1`, `task2`, `robot`, …): the held-out verdicts are judged there."),
    Column::new("method", FieldType::String, "The method's label."),
    Column::new("trial", FieldType::Integer, "The trial's index within its method: 0 is the preset's (the paper's) setting, 1 and up were drawn from the stated ranges. Every method has the same number of trials."),
    Column::new("paper_setting", FieldType::Boolean, "Whether the trial is the preset's setting (trial 0)."),
    Column::new("experiment", FieldType::String, "The trial's experiment, `<task>-tune-<method>-t<NN>`: its runs in the run store."),
    Column::new("alpha", FieldType::Number, "Learning rate α of every learner of the trial."),
    Column::new("gamma", FieldType::Number, "Discount γ of every learner of the trial."),
    Column::new("exploration_start", FieldType::Number, "ε (or the temperature, see `exploration`) in episode 0."),
    Column::new("exploration_factor", FieldType::Number, "The schedule's factor per episode; 1 for a constant ε."),
    Column::new("exploration_floor", FieldType::Number, "The schedule's floor; the constant itself for a constant ε."),
    Column::new("exploration", FieldType::String, "What the schedule is: ε of an ε-greedy policy, or a softmax temperature.").values(&["epsilon", "temperature"]),
    Column::new("tree_threshold", FieldType::Number, "EA-MADM's tree thresholds τₛ = τₐ.").blank_when("the method is not EA-MADM, or keeps its sub-tasks' tables instead of trees"),
    Column::new("pretrain_episodes", FieldType::Integer, "EA-MADM's sub-task pre-training episodes (the fewest, when the stopping rule trains on to convergence; its cap is raised to at least this).").unit("episodes").blank_when("the method is not EA-MADM"),
    Column::new("tuning_seeds", FieldType::Integer, "Seeds the trial ran on (tuning seeds, disjoint from the held-out seeds)."),
    Column::new("first_tuning_seed", FieldType::Integer, "The first tuning seed; the others follow it."),
    Column::new("objective", FieldType::String, "What the trial is scored by: the IQM over tuning seeds of `final_steps` (mazes, lower is better) or the mean of `success_rate` (robot, higher is better).").values(&["final_steps_iqm", "success_rate_mean"]),
    Column::new("score", FieldType::Number, "The objective over the trial's tuning seeds.").blank_when("the trial has not run"),
    Column::new("chosen", FieldType::Boolean, "Whether this is its method's best trial (the lowest index among equal scores): the setting run on the held-out seeds for the \"each at its best\" verdicts.").blank_when("some trial of the method has not run"),
];

/// Writes `rows` as `tuning.csv`: a header of [`TUNING_COLUMNS`]' names, one row per trial.
///
/// # Errors
/// What the writer returns.
pub fn write_tuning_csv<W: Write>(rows: &[TuningRow], writer: W) -> Result<(), csv::Error> {
    let mut csv = csv::Writer::from_writer(writer);
    if rows.is_empty() {
        csv.write_record(TUNING_COLUMNS.iter().map(|c| c.name))?;
    }
    for row in rows {
        csv.serialize(row)?;
    }
    csv.flush()?;
    Ok(())
}

/// The paper experiments `--suite tuning` tunes: the claims are judged on these three (the
/// robot over the paper's literal state is a reading of the robot, not a claim's task).
pub const SUITE_TASKS: [&str; 3] = ["task1", "task2", "robot"];

/// One task's tuning in two stages (docs/paper-notes.md §23): stage 1 runs every trial on the
/// tuning seeds ([`stage1`](Self::stage1)); once all of them are stored, [`rows`](Self::rows)
/// scores each trial by the task's [`Objective`] and marks each method's best
/// ([`choose`]), and stage 2 runs each method's chosen trial on the held-out seeds
/// ([`stage2`](Self::stage2), [`Trial::held_out`]). Stage 2 cannot be planned before stage
/// 1 is complete: which trial runs depends on every trial's score.
///
/// ```
/// use eamadm::{paper, tuning};
///
/// let task1 = paper::task1();
/// let tuning = tuning::TaskTuning::new(&task1, &tuning::paper_methods(&task1), 16, 10)?;
/// assert_eq!(tuning.stage1()?.len(), 4 * 16);
/// // Nothing ran yet: no score, nothing chosen, no stage 2.
/// let rows = tuning.rows(&[])?;
/// assert!(rows.iter().all(|row| row.score.is_none() && row.chosen.is_none()));
/// assert!(tuning.stage2(&rows)?.is_none());
/// # Ok::<(), tuning::TuningError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct TaskTuning {
    /// The experiment tuned (its held-out seeds are the stage-2 seeds).
    pub base: ExperimentConfig,
    /// Every trial of every tuned method, method-major ([`tuning_plan`]).
    pub trials: Vec<Trial>,
    /// Tuning seeds per trial (from [`TUNING_BASE_SEED`]).
    pub tuning_seeds: u32,
}

impl TaskTuning {
    /// The tuning of `methods` in `base`, `budget` trials each, on `tuning_seeds` seeds.
    ///
    /// # Errors
    /// As [`tuning_plan`]; [`TuningError::SeedsOverlap`] when `base`'s held-out seeds meet the
    /// tuning seeds; [`TuningError::TuningSeeds`].
    pub fn new(
        base: &ExperimentConfig,
        methods: &[&str],
        budget: u32,
        tuning_seeds: u32,
    ) -> Result<Self, TuningError> {
        check_disjoint(base)?;
        if !(1..=TUNING_SEEDS).contains(&tuning_seeds) {
            return Err(TuningError::TuningSeeds {
                seeds: tuning_seeds,
            });
        }
        Ok(Self {
            base: base.clone(),
            trials: tuning_plan(base, methods, budget)?,
            tuning_seeds,
        })
    }

    /// The task's objective.
    #[must_use]
    pub fn objective(&self) -> Objective {
        Objective::of(&self.base.task)
    }

    /// Stage 1: each trial's experiment on the tuning seeds, in trial order.
    ///
    /// # Errors
    /// As [`Trial::experiment_on`].
    pub fn stage1(&self) -> Result<Vec<ExperimentConfig>, TuningError> {
        self.trials
            .iter()
            .map(|trial| trial.experiment_on(&self.base, self.tuning_seeds))
            .collect()
    }

    /// The `tuning.csv` rows of the trials, scored from `scores` (final scores of any runs: a
    /// trial's are the rows whose task is its experiment) and, for each method whose every
    /// trial has a score, chosen ([`choose`]). A trial without rows stays unscored.
    ///
    /// # Errors
    /// [`TuningError::Score`] when a trial's rows give no objective value.
    pub fn rows(&self, scores: &[FinalScore]) -> Result<Vec<TuningRow>, TuningError> {
        let objective = self.objective();
        let mut rows = Vec::with_capacity(self.trials.len());
        for trial in &self.trials {
            let mut row = TuningRow::new(trial, objective);
            row.tuning_seeds = self.tuning_seeds;
            let of_trial: Vec<FinalScore> = scores
                .iter()
                .filter(|score| score.task == row.experiment && score.method == trial.method)
                .cloned()
                .collect();
            if !of_trial.is_empty() {
                let score = objective
                    .score(&of_trial)
                    .map_err(|error| TuningError::Score {
                        experiment: row.experiment.clone(),
                        reason: error.to_string(),
                    })?;
                if !score.is_finite() {
                    return Err(TuningError::Score {
                        experiment: row.experiment.clone(),
                        reason: format!("the objective is {score}"),
                    });
                }
                row.score = Some(score);
            }
            rows.push(row);
        }
        choose(&mut rows, objective);
        Ok(rows)
    }

    /// Stage 2: each method's chosen trial (by `rows`, from [`rows`](Self::rows)) with its
    /// experiment on the held-out seeds, in method order; `None` while some method has no
    /// chosen trial (stage 1 is not complete).
    ///
    /// # Errors
    /// As [`Trial::held_out`].
    pub fn stage2(
        &self,
        rows: &[TuningRow],
    ) -> Result<Option<Vec<(Trial, ExperimentConfig)>>, TuningError> {
        let mut methods: Vec<&str> = Vec::new();
        for trial in &self.trials {
            if !methods.contains(&trial.method.as_str()) {
                methods.push(&trial.method);
            }
        }
        let mut chosen = Vec::with_capacity(methods.len());
        for method in methods {
            let Some(row) = rows
                .iter()
                .find(|row| row.method == method && row.chosen == Some(true))
            else {
                return Ok(None);
            };
            let Some(trial) = self
                .trials
                .iter()
                .find(|trial| trial.method == method && trial.trial == row.trial)
            else {
                return Ok(None);
            };
            chosen.push((trial.clone(), trial.held_out(&self.base)?));
        }
        Ok(Some(chosen))
    }
}

/// The final scores of the "each at its best" verdicts on `base`: the rows of its stage-2
/// experiments (`<base>-best-<method>`, [`Trial::held_out`]) renamed into `base`, so that
/// the claims judge them as one task and pair them by seed (a run's streams depend on its
/// seed only, not on the experiment's name).
#[must_use]
pub fn at_best_scores(base: &str, held_out: &[FinalScore]) -> Vec<FinalScore> {
    let prefix = format!("{base}-best-");
    held_out
        .iter()
        .filter(|score| {
            score
                .task
                .strip_prefix(&prefix)
                .is_some_and(|method| method == score.method)
        })
        .map(|score| FinalScore {
            task: base.to_owned(),
            ..score.clone()
        })
        .collect()
}

/// Each method's chosen trial in `rows` (in row order), for the findings.
#[must_use]
pub fn chosen_trials(rows: &[TuningRow]) -> Vec<crate::findings::ChosenTrial> {
    let trials_of = |row: &TuningRow| {
        let count = rows
            .iter()
            .filter(|other| other.task == row.task && other.method == row.method)
            .count();
        u32::try_from(count).unwrap_or(u32::MAX)
    };
    rows.iter()
        .filter(|row| row.chosen == Some(true))
        .map(|row| crate::findings::ChosenTrial {
            trials: trials_of(row),
            tuning_seeds: row.tuning_seeds,
            task: row.task.clone(),
            method: row.method.clone(),
            trial: row.trial,
            paper_setting: row.paper_setting,
            objective: row.objective.to_owned(),
            score: row.score.unwrap_or(f64::NAN),
        })
        .collect()
}

/// Draws grid points of ranges from a method's own stream.
struct Sampler {
    rng: ChaCha8Rng,
}

impl Sampler {
    fn new(task: &str, method: &str) -> Self {
        let key = format!("{task}/{method}");
        Self {
            rng: ChaCha8Rng::seed_from_u64(SAMPLER_SEED ^ fnv1a(key.as_bytes())),
        }
    }

    /// A grid point of `range`, the index by Lemire's method on 32-bit words.
    fn draw(&mut self, range: Range) -> f64 {
        let k = GRID_POINTS;
        let mut product = u64::from(self.rng.next_u32()) * u64::from(k);
        if (product as u32) < k {
            let threshold = k.wrapping_neg() % k;
            while (product as u32) < threshold {
                product = u64::from(self.rng.next_u32()) * u64::from(k);
            }
        }
        range.point((product >> 32) as u32)
    }
}

/// The 64-bit FNV-1a hash.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |hash, &byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    })
}
