//! The experiment runner: one run per (method, seed), each a pure function of its inputs, all
//! of them in parallel.

use dql::{
    DoubleQ, DqlError, EpisodeOptions, EpisodeOutcome, EpsilonGreedy, ExplorationPolicy, Greedy,
    Learner, RewardSignal, Softmax, TaskRewardSignal, run_episode,
};
use rand::RngExt;
use rayon::prelude::*;

use crate::agent::EaMadmPolicy;
use crate::config::{ConfigError, ExperimentConfig, Method, MethodSpec};
use crate::error::{RunError, RunFailure};
use crate::pretrain::pretrain_subtasks;
use crate::prior::build_prior;
use crate::record::{EpisodeRecord, RunRecord, SubtaskRecord, TrajectoryRecord};
use crate::rng::{Stream, stream_rng};
use crate::signal::StandardisedReward;
use crate::task::{Counting, Task, TaskEnv, TaskKind};

/// A validated config with its task loaded: ready to run.
#[derive(Debug, Clone)]
pub struct Experiment {
    config: ExperimentConfig,
    task: Task,
}

impl Experiment {
    /// Validates `config`, loads its task (reading any file it names) and checks every method
    /// against the task.
    ///
    /// # Errors
    /// Any [`ConfigError`], naming the field.
    pub fn new(config: ExperimentConfig) -> Result<Self, ConfigError> {
        config.validate()?;
        let task = Task::load(&config.task)?;
        for (index, spec) in config.methods.iter().enumerate() {
            check_method_fits(&task, spec, &format!("methods[{index}]"))?;
        }
        Ok(Self { config, task })
    }

    /// Parses, validates and loads a TOML config ([`ExperimentConfig::from_toml_str`], then
    /// [`new`](Self::new)).
    ///
    /// # Errors
    /// Any [`ConfigError`].
    pub fn from_toml_str(text: &str) -> Result<Self, ConfigError> {
        Self::new(ExperimentConfig::from_toml_str(text)?)
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
        let fail = |source: RunFailure| RunError::new(&method.label, seed, source);
        method
            .validate("method")
            .and_then(|()| check_method_fits(&self.task, method, "method"))
            .map_err(|error| fail(RunFailure::from(error)))?;
        let optimum = self.task.optimum_steps();
        match self.task.kind() {
            TaskKind::Maze(env) => run_on(env.as_ref(), &self.config, method, seed, optimum),
            TaskKind::Robot(env) => run_on(env.as_ref(), &self.config, method, seed, optimum),
        }
        .map_err(fail)
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
    pub fn run_all_with(
        &self,
        on_done: impl Fn(&RunRecord) + Sync,
    ) -> Result<Vec<RunRecord>, RunError> {
        self.jobs()
            .into_par_iter()
            .map(|(method, seed)| {
                let record = self.run(method, seed)?;
                on_done(&record);
                Ok(record)
            })
            .collect()
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

/// Checks what only the task can tell: EA-MADM needs sub-tasks.
fn check_method_fits(task: &Task, spec: &MethodSpec, path: &str) -> Result<(), ConfigError> {
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
) -> Result<RunRecord, RunFailure> {
    let mut init_rng = stream_rng(seed, Stream::SourceInit);
    let learner = DoubleQ::new(
        prototype.n_states(),
        prototype.n_actions(),
        config.learner,
        &mut init_rng,
    )?;
    let mut session = Session {
        env: Counting::new(prototype.clone()),
        learner,
        config,
        seed,
    };
    let (subtasks, pretrain_env_steps, trained, evaluation) = match &spec.method {
        Method::EaMadm(ea) => {
            let pretrained = pretrain_subtasks(prototype, config.learner, &ea.pretrain, seed)?;
            let learners: Vec<&DoubleQ> = pretrained.iter().map(|s| &s.learner).collect();
            let (prior, clusters) = build_prior(prototype, &learners, &ea.storage)?;
            let subtasks: Vec<SubtaskRecord> = pretrained
                .iter()
                .zip(clusters)
                .enumerate()
                .map(|(k, (subtask, clusters))| SubtaskRecord {
                    name: subtask.name.clone(),
                    episodes: subtask.episodes,
                    env_steps: subtask.env_steps,
                    last_episode_steps: subtask.last_episode_steps,
                    visited_pairs: subtask.learner.experience().count() as u64,
                    clusters,
                    answered_pairs: prior.answered_pairs(k),
                })
                .collect();
            let pretrain_env_steps = subtasks.iter().map(|s| s.env_steps).sum();
            let mut policy = EaMadmPolicy::new(prior, ea.epsilon, ea.weighting.clone())?;
            let mut signal = StandardisedReward::new(ea.standardisation, subtasks.len())?;
            let trained = session.train(&mut policy, &mut signal, pretrain_env_steps)?;
            let mut greedy = policy.without_exploration();
            let evaluation = session.evaluate(&mut greedy, trained.env_steps)?;
            (subtasks, pretrain_env_steps, trained, evaluation)
        }
        Method::EpsilonGreedy { epsilon } => {
            let mut policy = EpsilonGreedy::new(*epsilon)?;
            let trained = session.train(&mut policy, &mut TaskRewardSignal, 0)?;
            let evaluation = session.evaluate(&mut Greedy, trained.env_steps)?;
            (Vec::new(), 0, trained, evaluation)
        }
        Method::Softmax { temperature } => {
            let mut policy = Softmax::new(*temperature)?;
            let trained = session.train(&mut policy, &mut TaskRewardSignal, 0)?;
            let evaluation = session.evaluate(&mut Greedy, trained.env_steps)?;
            (Vec::new(), 0, trained, evaluation)
        }
    };
    let (evaluation, evaluation_trajectory) = evaluation;
    Ok(RunRecord {
        experiment: config.name.clone(),
        method: spec.label.clone(),
        seed,
        optimum_steps,
        subtasks,
        pretrain_env_steps,
        episodes: trained.episodes,
        total_env_steps: trained.env_steps,
        trajectories: trained.trajectories,
        evaluation,
        evaluation_trajectory,
    })
}

/// The source task's learner on its environment, for one run.
struct Session<'a, E> {
    env: Counting<E>,
    learner: DoubleQ,
    config: &'a ExperimentConfig,
    seed: u64,
}

/// What training produced.
struct Trained {
    episodes: Vec<EpisodeRecord>,
    trajectories: Vec<TrajectoryRecord>,
    /// Cumulative environment steps, pre-training included.
    env_steps: u64,
}

impl<E: TaskEnv> Session<'_, E> {
    /// Trains for the config's episodes; `env_steps` counts the steps already spent
    /// (pre-training).
    fn train<P: ExplorationPolicy, S: RewardSignal>(
        &mut self,
        policy: &mut P,
        signal: &mut S,
        mut env_steps: u64,
    ) -> Result<Trained, DqlError> {
        let episodes = self.config.episodes;
        let mut rng = stream_rng(self.seed, Stream::SourceTraining);
        let mut env_seeds = stream_rng(self.seed, Stream::SourceEnvironment);
        let mut records = Vec::with_capacity(usize::try_from(episodes).unwrap_or(0));
        let mut trajectories = Vec::new();
        for episode in 0..episodes {
            let mut options = EpisodeOptions::new(episode).with_seed(env_seeds.random());
            options.record_trajectory = self.config.trajectories.keeps(episode, episodes);
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
        }
        Ok(Trained {
            episodes: records,
            trajectories,
            env_steps,
        })
    }

    /// One greedy episode without learning, with its trajectory.
    fn evaluate<P: ExplorationPolicy>(
        &mut self,
        policy: &mut P,
        env_steps: u64,
    ) -> Result<(EpisodeRecord, TrajectoryRecord), DqlError> {
        let mut rng = stream_rng(self.seed, Stream::Evaluation);
        let env_seed = stream_rng(self.seed, Stream::EvaluationEnvironment).random();
        let episode = self.config.episodes;
        let options = EpisodeOptions::new(episode)
            .with_seed(env_seed)
            .without_learning()
            .recording();
        let outcome = run_episode(
            &mut self.env,
            &mut self.learner,
            policy,
            &mut TaskRewardSignal,
            &mut rng,
            &options,
        )?;
        let mut record = self.record(episode, &outcome, env_steps);
        record.learning_return = 0.0;
        let trajectory = self
            .trajectory(episode, true, &outcome)
            .expect("the evaluation episode records its trajectory");
        Ok((record, trajectory))
    }

    fn record(&self, episode: u64, outcome: &EpisodeOutcome, env_steps: u64) -> EpisodeRecord {
        EpisodeRecord {
            episode,
            steps: outcome.steps,
            task_return: outcome.task_return,
            learning_return: outcome.learning_return,
            terminated: outcome.terminated,
            truncated: outcome.truncated,
            reached: self.env.inner.reached(outcome.terminated),
            collisions: self.env.collisions(),
            env_steps,
            robot: self.env.inner.robot_metrics(),
        }
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
