//! The experiment runner: one run per (method, seed), each a pure function of its inputs, all
//! of them in parallel.

use dql::{
    DoubleQ, DqlError, Environment, EpisodeOptions, EpisodeOutcome, EpsilonGreedy,
    ExplorationPolicy, Greedy, Learner, RewardSignal, Softmax, Step, SubtaskRewardSignal,
    TaskRewardSignal, run_episode,
};
use rand::{Rng, RngExt};
use rayon::prelude::*;
use reward_std::Standardisation;

use crate::agent::EaMadmPolicy;
use crate::config::{
    CompetitorSignal, CompetitorTraining, ConfigError, ExperimentConfig, Method, MethodSpec,
    PretrainConfig, Storage, TaskConfig,
};
use crate::error::{RunError, RunFailure};
use crate::pretrain::{PretrainedSubtask, pretrain_subtask};
use crate::prior::{PriorTable, build_prior};
use crate::record::{AgreementRecord, EpisodeRecord, RunRecord, SubtaskRecord, TrajectoryRecord};
use crate::rng::{Stream, stream_rng};
use crate::signal::StandardisedReward;
use crate::summary::DEFAULT_FINAL_WINDOW;
use crate::task::{Counting, Task, TaskEnv, TaskKind};
use wmr_model::{SubtaskRepairs, WmrEnv};

/// A validated config with its task loaded: ready to run.
#[derive(Debug, Clone)]
pub struct Experiment {
    config: ExperimentConfig,
    task: Task,
}

impl Experiment {
    /// [`ExperimentConfig::check`]: validates `config`, checks and builds its task (reading
    /// any file it names) and checks every method against the task.
    ///
    /// # Errors
    /// Any [`ConfigError`], naming the key.
    pub fn new(config: ExperimentConfig) -> Result<Self, ConfigError> {
        config.check()
    }

    /// The one place a config becomes an experiment ([`ExperimentConfig::check`]).
    pub(crate) fn from_checked_parts(config: ExperimentConfig) -> Result<Self, ConfigError> {
        config.validate()?;
        let task = config.task.check()?;
        for (index, spec) in config.methods.iter().enumerate() {
            check_method_fits(&task, spec, &format!("methods[{index}]"))?;
        }
        Ok(Self { config, task })
    }

    /// Parses a TOML config and checks it ([`ExperimentConfig::check`]).
    ///
    /// # Errors
    /// Any [`ConfigError`].
    pub fn from_toml_str(text: &str) -> Result<Self, ConfigError> {
        // Parsed only: `check` validates, once.
        toml::from_str::<ExperimentConfig>(text)?.check()
    }

    /// The config.
    #[must_use]
    pub fn config(&self) -> &ExperimentConfig {
        &self.config
    }

    /// The loaded task.
    #[must_use]
    pub fn task(&self) -> &Task {
        &self.task
    }

    /// Every run of the experiment, in the order [`run_all`](Self::run_all) returns them:
    /// method by method (config order), seed by seed within a method.
    #[must_use]
    pub fn jobs(&self) -> Vec<(&MethodSpec, u64)> {
        self.config
            .methods
            .iter()
            .flat_map(|spec| self.config.seed_values().map(move |seed| (spec, seed)))
            .collect()
    }

    /// One run: `method` (which need not be one of the config's) with seed `seed` on this
    /// experiment's task, episodes, learner and trajectory settings.
    ///
    /// A pure function of `(config, method, seed)`: every random draw comes from `ChaCha8`
    /// streams keyed by `seed` and the draw's purpose, so the record is bit-identical
    /// whatever thread runs it and whatever runs beside it.
    ///
    /// # Errors
    /// [`RunError`] naming the method and seed: an invalid method, or a failure of learning.
    pub fn run(&self, method: &MethodSpec, seed: u64) -> Result<RunRecord, RunError> {
        self.run_shared(method, seed, &SharedPretraining::none())
    }

    /// [`run`](Self::run), taking the trained sub-tasks and priors it needs from `shared`
    /// where `shared` holds them for this experiment's task, learner and `seed` (and
    /// computing the rest itself).
    ///
    /// The record is bit-identical to [`run`](Self::run)'s: `shared` holds exactly what
    /// the run would compute (the same function of the same inputs), so sharing only saves
    /// the work.
    ///
    /// # Errors
    /// As [`run`](Self::run).
    pub fn run_shared(
        &self,
        method: &MethodSpec,
        seed: u64,
        shared: &SharedPretraining,
    ) -> Result<RunRecord, RunError> {
        self.run_with_learner(method, seed, shared)
            .map(|(record, _)| record)
    }

    /// [`run_shared`](Self::run_shared), also returning the source task's learner as training
    /// left it (for EA-MADM, the own values of its decision matrix; for a sub-task alone, the
    /// sub-task's learner): what the run learned, for analyses the record does not hold
    /// (`eamadm::oracle`). The record is the one [`run`](Self::run) returns.
    ///
    /// # Errors
    /// As [`run`](Self::run).
    pub fn run_with_learner(
        &self,
        method: &MethodSpec,
        seed: u64,
        shared: &SharedPretraining,
    ) -> Result<(RunRecord, DoubleQ), RunError> {
        let fail = |source: RunFailure| RunError::new(&method.label, seed, source);
        method
            .validate("method")
            .and_then(|()| check_method_fits(&self.task, method, "method"))
            .map_err(|error| fail(RunFailure::from(error)))?;
        let optimum = self.task.optimum_steps();
        let repairs = method.method.subtask_repairs();
        let shared = shared.fits(self, seed);
        match self.task.kind() {
            TaskKind::Maze(env) => {
                run_on(env.as_ref(), &self.config, method, seed, optimum, shared)
            }
            TaskKind::Robot(env) if repairs != SubtaskRepairs::PAPER => {
                // The repairs change what the environment pays each sub-task: the run gets its
                // own copy of the task with them, and its own pre-training, since the shared one
                // learned the paper's sub-task rewards. The scenario was checked when the task
                // was built, and repairs are switches no bound reads: it is not checked again.
                let repaired =
                    WmrEnv::from_checked(env.checked_scenario().clone().with_repairs(repairs));
                let unshared = SharedPretraining::none();
                run_on(&repaired, &self.config, method, seed, optimum, &unshared)
            }
            TaskKind::Robot(env) => {
                run_on(env.as_ref(), &self.config, method, seed, optimum, shared)
            }
        }
        .map_err(fail)
    }

    /// The pre-training (and the priors built from it) that the runs of `methods` with
    /// `seed` would each do, done once: every distinct `(pre-training config, sub-task)`
    /// trained once, every distinct `(pre-training config, storage)` prior built once, in
    /// parallel on the current rayon pool. Pass the result to
    /// [`run_shared`](Self::run_shared) for each of those runs, and drop it when they are
    /// done.
    ///
    /// Methods that fail validation, and pre-trainings that fail, are left out: their runs
    /// then compute (and report) them themselves, so errors are those of
    /// [`run`](Self::run).
    #[must_use]
    pub fn share_pretraining(&self, methods: &[&MethodSpec], seed: u64) -> SharedPretraining {
        self.share_pretraining_with(methods, seed, &NoPretrainingCache)
    }

    /// [`share_pretraining`](Self::share_pretraining), asking `cache` for each trained
    /// sub-task before training it and handing it each sub-task it trained: how trained
    /// sub-tasks outlive the process (a run store's pre-trained artefacts, computed by
    /// whichever job needs them first and loaded by the others).
    ///
    /// A sub-task `cache` returns is used only if it has the shape, learner parameters, name
    /// and episode count this experiment would train it with; otherwise it is trained again
    /// (and handed to `cache`). The cache's keys must hold everything training depends on
    /// ([`PretrainingCache`]); then the records are bit-identical to
    /// [`run`](Self::run)'s.
    #[must_use]
    pub fn share_pretraining_with(
        &self,
        methods: &[&MethodSpec],
        seed: u64,
        cache: &dyn PretrainingCache,
    ) -> SharedPretraining {
        match self.task.kind() {
            TaskKind::Maze(env) => {
                SharedPretraining::compute(env.as_ref(), self, methods, seed, cache)
            }
            TaskKind::Robot(env) => {
                SharedPretraining::compute(env.as_ref(), self, methods, seed, cache)
            }
        }
    }

    /// The pre-trainings the runs of `methods` share, and a [`PretrainingCache`] is asked
    /// for: each distinct (pre-training config, sub-task) of the valid methods that pre-train
    /// on the paper's sub-task rewards, in the order first met (what
    /// [`share_pretraining_with`](Self::share_pretraining_with) loads or trains).
    #[must_use]
    pub fn shared_pretrainings(&self, methods: &[&MethodSpec]) -> Vec<(PretrainConfig, usize)> {
        let mut trainings: Vec<(PretrainConfig, usize)> = Vec::new();
        let mut need = |pretrain: &PretrainConfig, k: usize| {
            if !trainings.iter().any(|(p, j)| *j == k && p == pretrain) {
                trainings.push((*pretrain, k));
            }
        };
        for method in methods {
            if !self.shares_pretraining(method) {
                continue;
            }
            match &method.method {
                Method::EaMadm(ea) => {
                    for k in 0..self.task.subtask_names().len() {
                        need(&ea.pretrain, k);
                    }
                }
                Method::SubtaskGreedy(alone) => need(&alone.pretrain, alone.subtask),
                Method::EpsilonGreedy { .. } | Method::Softmax { .. } => {}
            }
        }
        trainings
    }

    /// Whether `method` is valid here and pre-trains on the paper's sub-task rewards (a
    /// repaired method pre-trains on other rewards: it shares nothing).
    fn shares_pretraining(&self, method: &MethodSpec) -> bool {
        method.validate("method").is_ok()
            && check_method_fits(&self.task, method, "method").is_ok()
            && method.method.subtask_repairs() == SubtaskRepairs::PAPER
    }

    /// Every run of the experiment ([`jobs`](Self::jobs)), in parallel on the current rayon
    /// pool, returned in job order. Bit-identical whatever the number of threads.
    ///
    /// # Errors
    /// The first failing run in job order.
    pub fn run_all(&self) -> Result<Vec<RunRecord>, RunError> {
        self.run_all_with(|_| {})
    }

    /// [`run_all`](Self::run_all), calling `on_done` with each record as soon as its run
    /// finishes (in completion order, from any thread), e.g. to save it or move a progress
    /// bar.
    ///
    /// # Errors
    /// The first failing run in job order.
    ///
    /// The methods of one seed share their pre-training
    /// ([`share_pretraining`](Self::share_pretraining)), held only while that seed's runs are
    /// in flight.
    pub fn run_all_with(
        &self,
        on_done: impl Fn(&RunRecord) + Sync,
    ) -> Result<Vec<RunRecord>, RunError> {
        let methods: Vec<&MethodSpec> = self.config.methods.iter().collect();
        let by_seed: Vec<Vec<Result<RunRecord, RunError>>> = self
            .config
            .seed_values()
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|seed| {
                let shared = self.share_pretraining(&methods, seed);
                methods
                    .par_iter()
                    .map(|method| {
                        let record = self.run_shared(method, seed, &shared)?;
                        on_done(&record);
                        Ok(record)
                    })
                    .collect()
            })
            .collect();
        // Job order is method by method, seed by seed within a method.
        let mut by_seed: Vec<_> = by_seed.into_iter().map(Vec::into_iter).collect();
        let mut records = Vec::with_capacity(methods.len() * by_seed.len());
        for _ in &methods {
            for runs in &mut by_seed {
                if let Some(record) = runs.next() {
                    records.push(record?);
                }
            }
        }
        Ok(records)
    }
}

/// Where [`Experiment::share_pretraining_with`] looks for trained sub-tasks before training
/// them, and where it puts those it trained: a store that outlives the process.
///
/// A trained sub-task is a pure function of the experiment's task (`config.task`, with the
/// content of any file it names: [`Task::input_text`], the bytes the task was built from), its
/// learner parameters (`config.learner`), the pre-training config, the sub-task `k` (whose raw
/// reward it learns: pre-training does not standardise rewards) and the seed, and of the code;
/// an implementation must key what it keeps by all of them, or it hands back a learner another
/// run trained.
pub trait PretrainingCache: Sync {
    /// Sub-task `k` of `experiment`'s task trained with `pretrain` and `seed`, if kept.
    fn load(
        &self,
        experiment: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        seed: u64,
    ) -> Option<PretrainedSubtask>;

    /// Keeps `subtask`, just trained as sub-task `k` of `experiment`'s task with `pretrain`
    /// and `seed`.
    fn save(
        &self,
        experiment: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        seed: u64,
        subtask: &PretrainedSubtask,
    );
}

/// The cache that keeps nothing: [`Experiment::share_pretraining`]'s.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoPretrainingCache;

impl PretrainingCache for NoPretrainingCache {
    fn load(
        &self,
        _: &Experiment,
        _: &PretrainConfig,
        _: usize,
        _: u64,
    ) -> Option<PretrainedSubtask> {
        None
    }

    fn save(&self, _: &Experiment, _: &PretrainConfig, _: usize, _: u64, _: &PretrainedSubtask) {}
}

/// Pre-training shared by the runs of one seed of one experiment: trained sub-task learners
/// keyed by `(pre-training config, sub-task)` and the priors built from them keyed by
/// `(pre-training config, storage)` ([`Experiment::share_pretraining`]).
///
/// It remembers the task (its config and the text of any file it names), learner parameters
/// and seed it was computed for, and [`Experiment::run_shared`] uses it only for a run that
/// matches all of them, so a mismatched one costs time, never a wrong bit.
#[derive(Debug, Clone, Default)]
pub struct SharedPretraining {
    /// What it was computed for: task, its file's text, learner parameters and seed (`None`:
    /// nothing).
    basis: Option<(TaskConfig, Option<String>, dql::DoubleQParams, u64)>,
    subtasks: Vec<SharedSubtask>,
    priors: Vec<SharedPrior>,
}

/// One trained sub-task and the pre-training config it was trained with.
#[derive(Debug, Clone)]
struct SharedSubtask {
    pretrain: PretrainConfig,
    subtask: PretrainedSubtask,
    k: usize,
}

/// One prior and what it was built from.
#[derive(Debug, Clone)]
struct SharedPrior {
    pretrain: PretrainConfig,
    storage: Storage,
    prior: PriorTable,
    tree_stats: Vec<Option<ea_tree::TreeStats>>,
}

impl SharedPretraining {
    /// Nothing shared: every run computes its own pre-training.
    #[must_use]
    pub fn none() -> Self {
        Self::default()
    }

    /// Number of trained sub-tasks held.
    #[must_use]
    pub fn subtask_count(&self) -> usize {
        self.subtasks.len()
    }

    /// Number of priors held.
    #[must_use]
    pub fn prior_count(&self) -> usize {
        self.priors.len()
    }

    /// `self` if it was computed for `experiment`'s task and learner and `seed`, else nothing.
    fn fits(&self, experiment: &Experiment, seed: u64) -> &Self {
        static NONE: SharedPretraining = SharedPretraining {
            basis: None,
            subtasks: Vec::new(),
            priors: Vec::new(),
        };
        match &self.basis {
            Some((task, input, learner, at))
                if *task == experiment.config.task
                    && input.as_deref() == experiment.task.input_text()
                    && *learner == experiment.config.learner
                    && *at == seed =>
            {
                self
            }
            _ => &NONE,
        }
    }

    pub(crate) fn subtask(
        &self,
        pretrain: &PretrainConfig,
        k: usize,
    ) -> Option<&PretrainedSubtask> {
        self.subtasks
            .iter()
            .find(|shared| shared.k == k && shared.pretrain == *pretrain)
            .map(|shared| &shared.subtask)
    }

    pub(crate) fn prior(
        &self,
        pretrain: &PretrainConfig,
        storage: &Storage,
    ) -> Option<(&PriorTable, &[Option<ea_tree::TreeStats>])> {
        self.priors
            .iter()
            .find(|shared| shared.pretrain == *pretrain && shared.storage == *storage)
            .map(|shared| (&shared.prior, shared.tree_stats.as_slice()))
    }

    fn compute<E: TaskEnv>(
        prototype: &E,
        experiment: &Experiment,
        methods: &[&MethodSpec],
        seed: u64,
        cache: &dyn PretrainingCache,
    ) -> Self {
        let config = &experiment.config;
        // What the valid methods pre-train: (config, sub-task) pairs, and (config, storage)
        // priors, each once, in the order first met.
        let trainings = experiment.shared_pretrainings(methods);
        let mut priors: Vec<(PretrainConfig, Storage)> = Vec::new();
        for method in methods {
            if let Method::EaMadm(ea) = &method.method
                && experiment.shares_pretraining(method)
                && !priors
                    .iter()
                    .any(|(p, s)| *p == ea.pretrain && *s == ea.storage)
            {
                priors.push((ea.pretrain, ea.storage));
            }
        }
        let subtasks: Vec<SharedSubtask> = trainings
            .into_par_iter()
            .filter_map(|(pretrain, k)| {
                let names = prototype.subtask_names();
                let kept = cache
                    .load(experiment, &pretrain, k, seed)
                    .filter(|kept| fits_training(prototype, config, &pretrain, k, &names, kept));
                let subtask = match kept {
                    Some(kept) => kept,
                    None => {
                        let trained =
                            pretrain_subtask(prototype, k, config.learner, &pretrain, seed).ok()?;
                        cache.save(experiment, &pretrain, k, seed, &trained);
                        trained
                    }
                };
                Some(SharedSubtask {
                    pretrain,
                    subtask,
                    k,
                })
            })
            .collect();
        let mut shared = Self {
            basis: Some((
                config.task.clone(),
                experiment.task.input_text().map(str::to_owned),
                config.learner,
                seed,
            )),
            subtasks,
            priors: Vec::new(),
        };
        let built: Vec<SharedPrior> = priors
            .into_par_iter()
            .filter_map(|(pretrain, storage)| {
                let learners: Vec<&DoubleQ> = (0..prototype.n_subtasks())
                    .map(|k| shared.subtask(&pretrain, k).map(|s| &s.learner))
                    .collect::<Option<_>>()?;
                let (prior, tree_stats) = build_prior(prototype, &learners, &storage).ok()?;
                Some(SharedPrior {
                    pretrain,
                    storage,
                    prior,
                    tree_stats,
                })
            })
            .collect();
        shared.priors = built;
        shared
    }
}

/// Whether `kept`, a sub-task a [`PretrainingCache`] returned for sub-task `k` of
/// `prototype` trained with `pretrain`, is what training it would give in shape and
/// provenance: a stale or misfiled one is trained again rather than trusted.
fn fits_training<E: TaskEnv>(
    prototype: &E,
    config: &ExperimentConfig,
    pretrain: &PretrainConfig,
    k: usize,
    names: &[String],
    kept: &PretrainedSubtask,
) -> bool {
    let name = names
        .get(k)
        .cloned()
        .unwrap_or_else(|| format!("sub-task {k}"));
    kept.learner.n_states() == prototype.n_states()
        && kept.learner.n_actions() == prototype.n_actions()
        && *kept.learner.params() == config.learner
        && kept.name == name
        && match pretrain.until {
            None => kept.episodes == pretrain.episodes && kept.converged.is_none(),
            Some(rule) => {
                (pretrain.episodes..=rule.max_episodes).contains(&kept.episodes)
                    && kept.converged.is_some()
            }
        }
}

/// One run of `method` with `seed` in the experiment `config` (see [`Experiment::run`]).
///
/// Loads the task first; to run many, build an [`Experiment`] once.
///
/// # Errors
/// [`RunError`] for an invalid config or method, or a failure of learning.
pub fn run(
    config: &ExperimentConfig,
    method: &MethodSpec,
    seed: u64,
) -> Result<RunRecord, RunError> {
    let experiment = Experiment::new(config.clone())
        .map_err(|error| RunError::new(&method.label, seed, error))?;
    experiment.run(method, seed)
}

/// Every run of `config`, in parallel (see [`Experiment::run_all`]).
///
/// # Errors
/// [`RunError`] for an invalid config, or the first failing run.
pub fn run_all(config: &ExperimentConfig) -> Result<Vec<RunRecord>, RunError> {
    let experiment = Experiment::new(config.clone())
        .map_err(|error| RunError::new("", config.base_seed, error))?;
    experiment.run_all()
}

/// Checks what only the task can tell: EA-MADM, a sub-task alone and the reward-matched
/// signals need sub-tasks (and the sub-task named must exist).
fn check_method_fits(task: &Task, spec: &MethodSpec, path: &str) -> Result<(), ConfigError> {
    let n_subtasks = task.subtask_names().len();
    match &spec.method {
        Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. }
            if training.signal.needs_subtasks() && n_subtasks == 0 =>
        {
            return Err(ConfigError::invalid(
                format!("{path}.signal"),
                format!("{:?}", training.signal),
                "\"task\": this task has no sub-tasks whose rewards could be learned from",
            ));
        }
        Method::SubtaskGreedy(alone) if alone.subtask >= n_subtasks => {
            return Err(ConfigError::invalid(
                format!("{path}.subtask"),
                alone.subtask,
                format!("a sub-task index below the task's {n_subtasks} sub-tasks"),
            ));
        }
        _ => {}
    }
    if spec.method.subtask_repairs() != SubtaskRepairs::PAPER
        && !matches!(task.kind(), TaskKind::Robot(_))
    {
        return Err(ConfigError::invalid(
            format!("{path}.subtask_rewards"),
            format!("{:?}", spec.method.subtask_repairs()),
            "no repairs: they repair the robot's sub-task rewards (Eq. 6-8), and this task is not the robot",
        ));
    }
    if let Method::EaMadm(config) = &spec.method {
        if task.subtask_names().is_empty() {
            return Err(ConfigError::invalid(
                format!("{path}.kind"),
                "\"ea_madm\"",
                "a method the task supports: EA-MADM needs a task with sub-tasks",
            ));
        }
        if matches!(config.weighting, madm_owa::Weighting::Given { .. }) {
            return Err(ConfigError::invalid(
                format!("{path}.weighting.kind"),
                "\"given\"",
                "visibility, uniform or maximum_entropy (EA-MADM rows lose attributes where a \
                 sub-task has no experience, so fixed-length weights cannot apply)",
            ));
        }
    }
    Ok(())
}

/// The run on a concrete environment type.
fn run_on<E: TaskEnv>(
    prototype: &E,
    config: &ExperimentConfig,
    spec: &MethodSpec,
    seed: u64,
    optimum_steps: Option<u64>,
    shared: &SharedPretraining,
) -> Result<(RunRecord, DoubleQ), RunFailure> {
    let mut init_rng = stream_rng(seed, Stream::SourceInit);
    let learner = DoubleQ::new(
        prototype.n_states(),
        prototype.n_actions(),
        config.learner,
        &mut init_rng,
    )?;
    let window = config.episodes.min(DEFAULT_FINAL_WINDOW as u64);
    let final_from = config.episodes - window;
    let mut session = Session {
        env: Counting::new(prototype.clone()),
        periodic_env: Counting::new(prototype.clone()),
        learner,
        config,
        seed,
    };
    let n_actions = prototype.n_actions();
    let table_bytes = (prototype.n_states() * n_actions * 2 * std::mem::size_of::<f64>()) as u64;
    let outcome = match &spec.method {
        Method::EaMadm(ea) => {
            let pretrained = shared_subtasks(prototype, config, &ea.pretrain, seed, shared)?;
            let pretrained: Vec<&PretrainedSubtask> =
                pretrained.iter().map(AsRef::as_ref).collect();
            let learners: Vec<&DoubleQ> = pretrained.iter().map(|s| &s.learner).collect();
            let (prior, tree_stats) = match shared.prior(&ea.pretrain, &ea.storage) {
                Some((prior, tree_stats)) => (prior.clone(), tree_stats.to_vec()),
                None => build_prior(prototype, &learners, &ea.storage)?,
            };
            let mut subtasks = Vec::with_capacity(pretrained.len());
            for (k, (subtask, stats)) in pretrained.iter().zip(tree_stats).enumerate() {
                subtasks.push(SubtaskRecord {
                    name: subtask.name.clone(),
                    episodes: subtask.episodes,
                    env_steps: subtask.env_steps,
                    last_episode_steps: subtask.last_episode_steps,
                    visited_pairs: subtask.learner.experience().count() as u64,
                    clusters: stats.map(|stats| stats.clusters as u64),
                    answered_pairs: prior.answered_pairs(k),
                    tree_samples: stats.map(|stats| stats.samples_seen),
                    tree_bytes: stats.map(|stats| stats.bytes() as u64),
                    table_bytes,
                    greedy_alone: Some(session.greedy_alone(&subtask.learner)?),
                    start_values: start_values(prototype, &subtask.learner),
                    reached_episodes: subtask.reached_episodes,
                    converged: subtask.converged,
                    checks: subtask.checks,
                    check_env_steps: subtask.check_env_steps,
                    last_check_reached: subtask.last_check_reached,
                });
            }
            let pretrain_env_steps = subtasks.iter().map(|s| s.env_steps).sum();
            // The periodic evaluations' policy: the same decision rule on its own copy of the
            // prior (its cache and counts are its own, so the training policy never sees them).
            let mut periodic = EaMadmPolicy::new(prior.clone(), ea.epsilon, ea.weighting.clone())?
                .with_normalisation(ea.normalisation)
                .without_exploration();
            let policy = EaMadmPolicy::new(prior, ea.epsilon, ea.weighting.clone())?
                .with_normalisation(ea.normalisation)
                .with_agreement(&learners, final_from);
            let mut policy = ActionTally::new(policy, n_actions, final_from);
            let mut signal = StandardisedReward::new(ea.standardisation, subtasks.len())?;
            let trained = session.train(
                &mut policy,
                &mut signal,
                &mut periodic,
                pretrain_env_steps,
                true,
            )?;
            if let Some(error) = policy.inner.failure().or(periodic.failure()) {
                return Err(RunFailure::Decision(error.clone()));
            }
            let agreement = policy.inner.agreement();
            let mut greedy = policy.inner.without_exploration();
            let evaluation = session.evaluate(&mut greedy, trained.env_steps)?;
            if let Some(error) = greedy.failure() {
                return Err(RunFailure::Decision(error.clone()));
            }
            RunParts {
                subtasks,
                pretrain_env_steps,
                trained,
                evaluation,
                actions: policy.counts,
                agreement,
            }
        }
        Method::EpsilonGreedy { epsilon, training } => {
            let policy = EpsilonGreedy::new(*epsilon)?;
            session.competitor(policy, *training, final_from)?
        }
        Method::Softmax {
            temperature,
            training,
        } => {
            let policy = Softmax::new(*temperature)?;
            session.competitor(policy, *training, final_from)?
        }
        Method::SubtaskGreedy(alone) => {
            let pretrained = match shared.subtask(&alone.pretrain, alone.subtask) {
                Some(subtask) => subtask.clone(),
                None => pretrain_subtask(
                    prototype,
                    alone.subtask,
                    config.learner,
                    &alone.pretrain,
                    seed,
                )?,
            };
            let subtask = SubtaskRecord {
                name: pretrained.name.clone(),
                episodes: pretrained.episodes,
                env_steps: pretrained.env_steps,
                last_episode_steps: pretrained.last_episode_steps,
                visited_pairs: pretrained.learner.experience().count() as u64,
                clusters: None,
                answered_pairs: pretrained.learner.experience().count() as u64,
                tree_samples: None,
                tree_bytes: None,
                table_bytes,
                greedy_alone: Some(session.greedy_alone(&pretrained.learner)?),
                start_values: start_values(prototype, &pretrained.learner),
                reached_episodes: pretrained.reached_episodes,
                converged: pretrained.converged,
                checks: pretrained.checks,
                check_env_steps: pretrained.check_env_steps,
                last_check_reached: pretrained.last_check_reached,
            };
            let pretrain_env_steps = pretrained.env_steps;
            // The source task's episodes act (and, with `learn`, learn) on the sub-task's own
            // values and reward.
            session.learner = pretrained.learner;
            let mut policy =
                ActionTally::new(EpsilonGreedy::new(alone.epsilon)?, n_actions, final_from);
            let mut signal = SubtaskRewardSignal(alone.subtask);
            let trained = session.train(
                &mut policy,
                &mut signal,
                &mut Greedy,
                pretrain_env_steps,
                alone.learn,
            )?;
            let evaluation = session.evaluate(&mut Greedy, trained.env_steps)?;
            RunParts {
                subtasks: vec![subtask],
                pretrain_env_steps,
                trained,
                evaluation,
                actions: policy.counts,
                agreement: None,
            }
        }
    };
    let RunParts {
        subtasks,
        pretrain_env_steps,
        trained,
        evaluation: (evaluation, evaluation_trajectory),
        actions,
        agreement,
    } = outcome;
    let record = RunRecord {
        experiment: config.name.clone(),
        method: spec.label.clone(),
        seed,
        optimum_steps,
        subtasks,
        pretrain_env_steps,
        episodes: trained.episodes,
        total_env_steps: trained.env_steps,
        trajectories: trained.trajectories,
        greedy_evaluations: trained.greedy_evaluations,
        evaluation,
        evaluation_trajectory,
        final_window_episodes: window,
        final_window_actions: actions,
        agreement,
    };
    Ok((record, session.learner))
}

/// Every sub-task of `prototype` trained with `pretrain`: taken from `shared` where it holds
/// it, trained here (in parallel, as [`crate::pretrain_subtasks`] does) otherwise.
fn shared_subtasks<'s, E: TaskEnv>(
    prototype: &E,
    config: &ExperimentConfig,
    pretrain: &PretrainConfig,
    seed: u64,
    shared: &'s SharedPretraining,
) -> Result<Vec<std::borrow::Cow<'s, PretrainedSubtask>>, DqlError> {
    (0..prototype.n_subtasks())
        .into_par_iter()
        .map(|k| match shared.subtask(pretrain, k) {
            Some(subtask) => Ok(std::borrow::Cow::Borrowed(subtask)),
            None => pretrain_subtask(prototype, k, config.learner, pretrain, seed)
                .map(std::borrow::Cow::Owned),
        })
        .collect()
}

/// What one method's run produced, before it becomes a [`RunRecord`].
struct RunParts {
    subtasks: Vec<SubtaskRecord>,
    pretrain_env_steps: u64,
    trained: Trained,
    evaluation: (EpisodeRecord, TrajectoryRecord),
    actions: Vec<u64>,
    agreement: Option<AgreementRecord>,
}

/// A policy that counts the actions it takes in the final window (episodes from
/// `final_from` on), exploring steps included.
struct ActionTally<P> {
    inner: P,
    counts: Vec<u64>,
    final_from: u64,
    active: bool,
}

impl<P> ActionTally<P> {
    fn new(inner: P, n_actions: usize, final_from: u64) -> Self {
        Self {
            inner,
            counts: vec![0; n_actions],
            final_from,
            active: false,
        }
    }
}

impl<P: ExplorationPolicy> ExplorationPolicy for ActionTally<P> {
    fn begin_episode(&mut self, episode: u64) {
        self.active = episode >= self.final_from;
        self.inner.begin_episode(episode);
    }

    fn end_episode(&mut self, episode: u64) {
        self.inner.end_episode(episode);
    }

    #[inline]
    fn select<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action_values: &[f64],
        rng: &mut R,
    ) -> usize {
        let action = self.inner.select(state, action_values, rng);
        if self.active
            && let Some(count) = self.counts.get_mut(action)
        {
            *count += 1;
        }
        action
    }
}

/// A competitor's learning signal ([`CompetitorSignal`]) as a [`RewardSignal`].
enum CompetitorReward {
    Task,
    SubtaskSum,
    Standardised(StandardisedReward),
}

impl CompetitorReward {
    fn new(signal: CompetitorSignal, n_subtasks: usize) -> Result<Self, RunFailure> {
        Ok(match signal {
            CompetitorSignal::Task => Self::Task,
            CompetitorSignal::SubtaskSum => Self::SubtaskSum,
            CompetitorSignal::Standardised => Self::Standardised(StandardisedReward::new(
                Standardisation::Running,
                n_subtasks,
            )?),
        })
    }
}

impl RewardSignal for CompetitorReward {
    fn begin_episode(&mut self, n_subtasks: usize) -> Result<(), DqlError> {
        match self {
            Self::Task | Self::SubtaskSum => Ok(()),
            Self::Standardised(signal) => signal.begin_episode(n_subtasks),
        }
    }

    #[inline]
    fn learning_reward(&mut self, step: &Step, subtask_rewards: &[f64]) -> f64 {
        match self {
            Self::Task => TaskRewardSignal.learning_reward(step, subtask_rewards),
            Self::SubtaskSum => subtask_rewards.iter().sum(),
            Self::Standardised(signal) => signal.learning_reward(step, subtask_rewards),
        }
    }
}

/// The source task's learner on its environment, for one run.
struct Session<'a, E> {
    env: Counting<E>,
    /// The environment of the periodic greedy evaluations: a copy of its own, so that the
    /// training episodes' environment never sees them.
    periodic_env: Counting<E>,
    learner: DoubleQ,
    config: &'a ExperimentConfig,
    seed: u64,
}

/// What training produced.
struct Trained {
    episodes: Vec<EpisodeRecord>,
    trajectories: Vec<TrajectoryRecord>,
    /// The periodic greedy evaluations ([`crate::config::EvaluationConfig`]), in order.
    greedy_evaluations: Vec<EpisodeRecord>,
    /// Cumulative environment steps, pre-training included.
    env_steps: u64,
}

impl<E: TaskEnv> Session<'_, E> {
    /// A paper competitor or its control: warm-up (if any), training and evaluation.
    fn competitor<P: ExplorationPolicy>(
        &mut self,
        policy: P,
        training: CompetitorTraining,
        final_from: u64,
    ) -> Result<RunParts, RunFailure> {
        let mut signal = CompetitorReward::new(training.signal, self.env.n_subtasks())?;
        let mut policy = ActionTally::new(policy, self.env.n_actions(), final_from);
        let warmup_env_steps =
            self.warm_up(&mut policy.inner, &mut signal, training.warmup_env_steps)?;
        let trained = self.train(
            &mut policy,
            &mut signal,
            &mut Greedy,
            warmup_env_steps,
            true,
        )?;
        let evaluation = self.evaluate(&mut Greedy, trained.env_steps)?;
        Ok(RunParts {
            subtasks: Vec::new(),
            pretrain_env_steps: warmup_env_steps,
            trained,
            evaluation,
            actions: policy.counts,
            agreement: None,
        })
    }

    /// Trains on the task with `policy` and `signal` for exactly `budget` environment steps
    /// (episodes 0, 1, … of the policy's schedule; the last one cut at the budget), before
    /// the recorded episodes. Returns the steps spent (`budget`).
    fn warm_up<P: ExplorationPolicy, S: RewardSignal>(
        &mut self,
        policy: &mut P,
        signal: &mut S,
        budget: u64,
    ) -> Result<u64, DqlError> {
        let mut rng = stream_rng(self.seed, Stream::Warmup);
        let mut env_seeds = stream_rng(self.seed, Stream::WarmupEnvironment);
        let mut spent = 0;
        let mut episode = 0;
        while spent < budget {
            let options = EpisodeOptions::new(episode)
                .with_seed(env_seeds.random())
                .with_max_steps(budget - spent);
            let outcome = run_episode(
                &mut self.env,
                &mut self.learner,
                policy,
                signal,
                &mut rng,
                &options,
            )?;
            // Every episode takes at least one step, so the loop ends.
            spent += outcome.steps.max(1);
            episode += 1;
        }
        Ok(spent)
    }

    /// Trains for the config's episodes; `env_steps` counts the steps already spent
    /// (pre-training or warm-up); `learn = false` acts without updating the learner.
    ///
    /// After every `k`-th episode (`config.evaluation`) it plays one episode of `greedy` (the
    /// training policy without exploration) without learning, on its own environment copy
    /// and its own random streams ([`Stream::PeriodicEvaluation`]): nothing of training sees
    /// it, so the training episodes are bit-identical whatever `k`; each evaluation has streams
    /// of its own (keyed by the episodes done), so it is the same whichever others are made.
    fn train<P: ExplorationPolicy, G: ExplorationPolicy, S: RewardSignal>(
        &mut self,
        policy: &mut P,
        signal: &mut S,
        greedy: &mut G,
        mut env_steps: u64,
        learn: bool,
    ) -> Result<Trained, DqlError> {
        let episodes = self.config.episodes;
        let mut rng = stream_rng(self.seed, Stream::SourceTraining);
        let mut env_seeds = stream_rng(self.seed, Stream::SourceEnvironment);
        let mut records = Vec::with_capacity(usize::try_from(episodes).unwrap_or(0));
        let mut trajectories = Vec::new();
        let mut greedy_evaluations = Vec::new();
        for episode in 0..episodes {
            let mut options = EpisodeOptions::new(episode).with_seed(env_seeds.random());
            options.record_trajectory = self.config.trajectories.keeps(episode, episodes);
            options.learn = learn;
            let outcome = run_episode(
                &mut self.env,
                &mut self.learner,
                policy,
                signal,
                &mut rng,
                &options,
            )?;
            env_steps += outcome.steps;
            records.push(self.record(episode, &outcome, env_steps));
            if let Some(trajectory) = self.trajectory(episode, false, &outcome) {
                trajectories.push(trajectory);
            }
            if self.config.evaluation.after(episode, episodes) {
                let done = episode + 1;
                let mut periodic_rng = stream_rng(self.seed, Stream::PeriodicEvaluation(done));
                let env_seed =
                    stream_rng(self.seed, Stream::PeriodicEvaluationEnvironment(done)).random();
                let options = EpisodeOptions::new(done)
                    .with_seed(env_seed)
                    .without_learning();
                let outcome = run_episode(
                    &mut self.periodic_env,
                    &mut self.learner,
                    greedy,
                    &mut TaskRewardSignal,
                    &mut periodic_rng,
                    &options,
                )?;
                let mut record =
                    episode_record(&self.periodic_env, episode + 1, &outcome, env_steps);
                record.learning_return = 0.0;
                greedy_evaluations.push(record);
            }
        }
        Ok(Trained {
            episodes: records,
            trajectories,
            greedy_evaluations,
            env_steps,
        })
    }

    /// One greedy episode without learning, with its trajectory.
    fn evaluate<P: ExplorationPolicy>(
        &mut self,
        policy: &mut P,
        env_steps: u64,
    ) -> Result<(EpisodeRecord, TrajectoryRecord), DqlError> {
        let (outcome, mut record) = greedy_episode(
            &mut self.env,
            &mut self.learner,
            policy,
            self.config.episodes,
            self.seed,
            true,
        )?;
        record.env_steps = env_steps;
        let trajectory = self
            .trajectory(record.episode, true, &outcome)
            .expect("the evaluation episode records its trajectory");
        Ok((record, trajectory))
    }

    /// A pre-trained sub-task's greedy policy by itself: the evaluation episode (same start,
    /// same tie-break stream) acted greedily on the sub-task's own values.
    fn greedy_alone(&mut self, subtask: &DoubleQ) -> Result<EpisodeRecord, DqlError> {
        let mut learner = subtask.clone();
        let (_, record) = greedy_episode(
            &mut self.env,
            &mut learner,
            &mut Greedy,
            self.config.episodes,
            self.seed,
            false,
        )?;
        Ok(record)
    }

    fn record(&self, episode: u64, outcome: &EpisodeOutcome, env_steps: u64) -> EpisodeRecord {
        episode_record(&self.env, episode, outcome, env_steps)
    }

    fn trajectory(
        &self,
        episode: u64,
        greedy: bool,
        outcome: &EpisodeOutcome,
    ) -> Option<TrajectoryRecord> {
        outcome
            .trajectory
            .as_ref()
            .map(|trajectory| TrajectoryRecord {
                episode,
                greedy,
                states: trajectory.states.clone(),
                actions: trajectory.actions.clone(),
                positions: self.env.inner.positions(trajectory),
            })
    }
}

/// One greedy episode of `learner` without learning, numbered `episode`, on the evaluation
/// streams of `seed`; its record counts only its own steps in `env_steps`.
pub(crate) fn greedy_episode<E: TaskEnv, P: ExplorationPolicy>(
    env: &mut Counting<E>,
    learner: &mut DoubleQ,
    policy: &mut P,
    episode: u64,
    seed: u64,
    recording: bool,
) -> Result<(EpisodeOutcome, EpisodeRecord), DqlError> {
    let mut rng = stream_rng(seed, Stream::Evaluation);
    let env_seed = stream_rng(seed, Stream::EvaluationEnvironment).random();
    let mut options = EpisodeOptions::new(episode)
        .with_seed(env_seed)
        .without_learning();
    options.record_trajectory = recording;
    let outcome = run_episode(
        env,
        learner,
        policy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )?;
    let mut record = episode_record(env, episode, &outcome, outcome.steps);
    record.learning_return = 0.0;
    Ok((outcome, record))
}

pub(crate) fn episode_record<E: TaskEnv>(
    env: &Counting<E>,
    episode: u64,
    outcome: &EpisodeOutcome,
    env_steps: u64,
) -> EpisodeRecord {
    EpisodeRecord {
        episode,
        steps: outcome.steps,
        task_return: outcome.task_return,
        learning_return: outcome.learning_return,
        terminated: outcome.terminated,
        truncated: outcome.truncated,
        reached: env.inner.reached(outcome.terminated),
        collisions: env.collisions(),
        env_steps,
        robot: env.inner.robot_metrics(),
    }
}

/// `learner`'s behaviour values of each action in the start state of `prototype` (a fresh copy
/// is reset, so the run's own environment and its random stream are untouched).
fn start_values<E: Environment + Clone>(prototype: &E, learner: &DoubleQ) -> Vec<f64> {
    let start = prototype.clone().reset(None);
    let mut values = vec![0.0; prototype.n_actions()];
    learner.action_values(start, &mut values);
    values
}
