//! Sub-task pre-training (Sec. V, Fig. 5, steps 2–3): one double-Q learner per sub-task, each
//! on its own reward, trained in parallel.

use dql::{
    DoubleQ, DoubleQParams, DqlError, Environment, EpisodeOptions, EpsilonGreedy,
    SubtaskRewardSignal, run_episode,
};
use rand::RngExt;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::config::PretrainConfig;
use crate::rng::{Stream, stream_rng};

/// One trained sub-task. It serialises (the learner through [`DoubleQ`]'s checked form), so a
/// run store can keep it for other processes (`eamadm-runs`' pre-trained artefacts).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PretrainedSubtask {
    /// The sub-task's name.
    pub name: String,
    /// Its trained learner (its experience is `learner.experience()`).
    pub learner: DoubleQ,
    /// Episodes trained.
    pub episodes: u64,
    /// Environment steps consumed.
    pub env_steps: u64,
    /// Steps of the last episode.
    pub last_episode_steps: u64,
}

/// Trains every sub-task of `env` with double Q on its own reward
/// ([`dql::SubtaskRewardSignal`]) and ε-greedy exploration on its own values, for
/// `config.episodes` episodes each.
///
/// Each sub-task has its own clone of `env` and its own random streams derived from
/// `(seed, k)`, and the sub-tasks run as parallel rayon jobs (one per sub-task) collected in
/// sub-task order: the result is the same whatever the number of threads.
///
/// # Errors
/// A [`DqlError`] for invalid parameters or an environment that breaks its contract.
pub fn pretrain_subtasks<E: Environment + Clone + Send + Sync>(
    env: &E,
    learner: DoubleQParams,
    config: &PretrainConfig,
    seed: u64,
) -> Result<Vec<PretrainedSubtask>, DqlError> {
    let names = env.subtask_names();
    (0..env.n_subtasks())
        .into_par_iter()
        .map(|k| {
            let name = names
                .get(k)
                .cloned()
                .unwrap_or_else(|| format!("sub-task {k}"));
            train_subtask(env.clone(), k, name, learner, config, seed)
        })
        .collect()
}

/// Trains sub-task `k` of `env` alone, exactly as [`pretrain_subtasks`] trains it (the same
/// random streams, so the same learner as in a [`pretrain_subtasks`] call with the same
/// arguments).
///
/// # Errors
/// A [`DqlError`] for invalid parameters, a sub-task `k` the environment does not have, or
/// an environment that breaks its contract.
pub fn pretrain_subtask<E: Environment + Clone>(
    env: &E,
    k: usize,
    learner: DoubleQParams,
    config: &PretrainConfig,
    seed: u64,
) -> Result<PretrainedSubtask, DqlError> {
    let name = env
        .subtask_names()
        .get(k)
        .cloned()
        .unwrap_or_else(|| format!("sub-task {k}"));
    train_subtask(env.clone(), k, name, learner, config, seed)
}

fn train_subtask<E: Environment>(
    mut env: E,
    k: usize,
    name: String,
    params: DoubleQParams,
    config: &PretrainConfig,
    seed: u64,
) -> Result<PretrainedSubtask, DqlError> {
    let mut rng = stream_rng(seed, Stream::Pretrain(k));
    let mut env_seeds = stream_rng(seed, Stream::PretrainEnvironment(k));
    let mut learner = DoubleQ::new(env.n_states(), env.n_actions(), params, &mut rng)?;
    let mut policy = EpsilonGreedy::new(config.epsilon)?;
    let mut signal = SubtaskRewardSignal(k);
    let mut env_steps = 0;
    let mut last_episode_steps = 0;
    for episode in 0..config.episodes {
        let options = EpisodeOptions::new(episode).with_seed(env_seeds.random());
        let outcome = run_episode(
            &mut env,
            &mut learner,
            &mut policy,
            &mut signal,
            &mut rng,
            &options,
        )?;
        env_steps += outcome.steps;
        last_episode_steps = outcome.steps;
    }
    Ok(PretrainedSubtask {
        name,
        learner,
        episodes: config.episodes,
        env_steps,
        last_episode_steps,
    })
}
