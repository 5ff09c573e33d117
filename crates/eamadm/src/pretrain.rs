//! Sub-task pre-training (Sec. V, Fig. 5, steps 2–3): one double-Q learner per sub-task, each
//! on its own reward, trained in parallel, for a fixed number of episodes or "to convergence"
//! by the stopping rule of [`Convergence`] (docs/paper-notes.md §21.4).

use dql::{
    DoubleQ, DoubleQParams, DqlError, Environment, EpisodeOptions, EpsilonGreedy, Greedy,
    SubtaskRewardSignal, run_episode,
};
use mazes::{Event, MazeEnv};
use rand::RngExt;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use wmr_model::{EpisodeStatus, WmrEnv};

use crate::config::{Convergence, PretrainConfig};
use crate::rng::{Stream, stream_rng};

/// What the stopping rule asks of a task beyond [`Environment`]: which sub-tasks have the target
/// as their goal, and whether an episode that just ended reached it.
pub trait SubtaskGoals: Environment {
    /// Whether sub-task `k`'s purpose is reaching the target: the stopping rule then waits for
    /// its greedy checks to reach it.
    fn subtask_has_goal(&self, k: usize) -> bool;

    /// Whether the episode that just ended reached the target (`terminated` is the episode
    /// driver's flag).
    fn reached_goal(&self, terminated: bool) -> bool;
}

impl SubtaskGoals for MazeEnv {
    /// A maze sub-task whose reward pays more for reaching the target than for any other
    /// event (the presets' "reach the target faster"; "do not hit obstacles" pays 0 there, as
    /// for any safe step, so it has no goal).
    fn subtask_has_goal(&self, k: usize) -> bool {
        self.spec().subtasks.get(k).is_some_and(|subtask| {
            let reward = &subtask.reward;
            [Event::Closer, Event::Farther, Event::Bump]
                .iter()
                .all(|&event| reward.target > reward.reward(event))
        })
    }

    fn reached_goal(&self, terminated: bool) -> bool {
        // Reaching the target is the maze's only terminal event.
        terminated
    }
}

impl SubtaskGoals for WmrEnv {
    /// The robot's sub-task 0, "reach the target faster" (Eq. 6): its purpose is reaching,
    /// whether or not its reward pays for it (under the literal Eq. 6 it does not, and the rule
    /// then runs to its cap: that is what it shows). The obstacle and view sub-tasks have no
    /// goal.
    fn subtask_has_goal(&self, k: usize) -> bool {
        k == 0
    }

    fn reached_goal(&self, _terminated: bool) -> bool {
        self.status() == EpisodeStatus::Reached
    }
}

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
    /// Pre-training episodes (not checks) that reached the target.
    #[serde(default)]
    pub reached_episodes: u64,
    /// With a stopping rule: whether it found the sub-task converged (`false`: it stopped at
    /// its cap); `None` for a fixed number of episodes.
    #[serde(default)]
    pub converged: Option<bool>,
    /// The stopping rule's greedy check episodes played (0 without a rule).
    #[serde(default)]
    pub checks: u64,
    /// Environment steps of those checks (included in `env_steps`).
    #[serde(default)]
    pub check_env_steps: u64,
    /// Whether the last check reached the target (`None` without checks).
    #[serde(default)]
    pub last_check_reached: Option<bool>,
}

/// Trains every sub-task of `env` with double Q on its own reward
/// ([`dql::SubtaskRewardSignal`]) and ε-greedy exploration on its own values, for
/// `config.episodes` episodes each, or with `config.until` until the stopping rule stops it.
///
/// Each sub-task has its own clone of `env` and its own random streams derived from
/// `(seed, k)`, and the sub-tasks run as parallel rayon jobs (one per sub-task) collected in
/// sub-task order: the result is the same whatever the number of threads.
///
/// # Errors
/// A [`DqlError`] for invalid parameters or an environment that breaks its contract.
pub fn pretrain_subtasks<E: SubtaskGoals + Clone + Send + Sync>(
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
pub fn pretrain_subtask<E: SubtaskGoals + Clone>(
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

fn train_subtask<E: SubtaskGoals + Clone>(
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
    let mut checker = config
        .until
        .map(|rule| Checker::new(&env, k, rule, seed, env.subtask_has_goal(k)));
    let cap = config
        .until
        .map_or(config.episodes, |rule| rule.max_episodes);
    let mut env_steps = 0;
    let mut last_episode_steps = 0;
    let mut reached_episodes = 0;
    let mut episodes = 0;
    let mut converged = None;
    while episodes < cap {
        let options = EpisodeOptions::new(episodes).with_seed(env_seeds.random());
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
        reached_episodes += u64::from(env.reached_goal(outcome.terminated));
        episodes += 1;
        if let Some(checker) = checker.as_mut() {
            if episodes.is_multiple_of(checker.rule.every) {
                env_steps += checker.check(&mut learner, episodes)?;
                if episodes >= config.episodes && checker.converged() {
                    converged = Some(true);
                    break;
                }
            }
            if episodes == cap {
                converged = Some(false);
            }
        } else if episodes == config.episodes {
            break;
        }
    }
    let (checks, check_env_steps, last_check_reached) = checker.map_or((0, 0, None), |c| {
        (
            c.history.len() as u64,
            c.env_steps,
            c.history.last().map(|h| h.1),
        )
    });
    Ok(PretrainedSubtask {
        name,
        learner,
        episodes,
        env_steps,
        last_episode_steps,
        reached_episodes,
        converged,
        checks,
        check_env_steps,
        last_check_reached,
    })
}

/// The stopping rule's checks of one sub-task: its greedy episodes and their outcomes.
struct Checker<E> {
    env: E,
    k: usize,
    rule: Convergence,
    seed: u64,
    /// The reset seed of every check (the same each time).
    env_seed: u64,
    has_goal: bool,
    /// Per check: the sub-task's return and whether it reached the target.
    history: Vec<(f64, bool)>,
    env_steps: u64,
}

impl<E: SubtaskGoals + Clone> Checker<E> {
    fn new(env: &E, k: usize, rule: Convergence, seed: u64, has_goal: bool) -> Self {
        Self {
            env: env.clone(),
            k,
            rule,
            seed,
            env_seed: stream_rng(seed, Stream::PretrainCheckEnvironment(k)).random(),
            has_goal,
            history: Vec::new(),
            env_steps: 0,
        }
    }

    /// One greedy check episode of `learner` (no learning, no exploration): same start and
    /// tie-break stream every time. Returns its steps.
    fn check(&mut self, learner: &mut DoubleQ, done: u64) -> Result<u64, DqlError> {
        let mut rng = stream_rng(self.seed, Stream::PretrainCheck(self.k));
        let options = EpisodeOptions::new(done)
            .with_seed(self.env_seed)
            .without_learning();
        let outcome = run_episode(
            &mut self.env,
            learner,
            &mut Greedy,
            &mut SubtaskRewardSignal(self.k),
            &mut rng,
            &options,
        )?;
        let reached = self.env.reached_goal(outcome.terminated);
        self.history.push((outcome.learning_return, reached));
        self.env_steps += outcome.steps;
        Ok(outcome.steps)
    }

    /// Whether the last `stable` checks agree: all reached the target (a sub-task with that
    /// goal), or all returned the same (any other).
    fn converged(&self) -> bool {
        let stable = self.rule.stable as usize;
        if self.history.len() < stable {
            return false;
        }
        let last = &self.history[self.history.len() - stable..];
        if self.has_goal {
            last.iter().all(|&(_, reached)| reached)
        } else {
            last.iter()
                .all(|&(value, _)| value.to_bits() == last[0].0.to_bits())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::table1_learner;
    use mazes::{Maze, TaskSpec};

    fn env() -> MazeEnv {
        let maze = Maze::parse("S....\n.##..\n...#.\n.#...\n....T\n").unwrap();
        MazeEnv::new(
            maze,
            TaskSpec {
                step_cap: 60,
                ..TaskSpec::task1()
            },
        )
        .unwrap()
    }

    fn fixed(episodes: u64) -> PretrainConfig {
        PretrainConfig {
            episodes,
            ..PretrainConfig::default()
        }
    }

    fn rule(episodes: u64, every: u64, max_episodes: u64) -> PretrainConfig {
        PretrainConfig {
            until: Some(Convergence {
                every,
                stable: 3,
                max_episodes,
            }),
            ..fixed(episodes)
        }
    }

    #[test]
    fn only_the_reach_sub_task_of_a_maze_has_the_target_as_its_goal() {
        let env = env();
        assert!(env.subtask_has_goal(0));
        assert!(!env.subtask_has_goal(1));
        assert!(!env.subtask_has_goal(2));
        let robot = WmrEnv::default();
        assert!(robot.subtask_has_goal(0));
        assert!(!robot.subtask_has_goal(1) && !robot.subtask_has_goal(2));
    }

    /// The checks play on their own copy and streams: a sub-task the rule stopped after `n`
    /// episodes is the learner a fixed pre-training of `n` episodes gives, with the checks'
    /// steps added to its count.
    #[test]
    fn the_rule_only_decides_when_to_stop() {
        let env = env();
        for k in 0..2 {
            let ruled = pretrain_subtask(&env, k, table1_learner(), &rule(20, 5, 400), 3).unwrap();
            assert!((20..=400).contains(&ruled.episodes));
            assert_eq!(ruled.episodes % 5, 0, "it stops at a check");
            let plain =
                pretrain_subtask(&env, k, table1_learner(), &fixed(ruled.episodes), 3).unwrap();
            assert_eq!(ruled.learner, plain.learner, "sub-task {k}");
            assert_eq!(ruled.reached_episodes, plain.reached_episodes);
            assert_eq!(ruled.env_steps, plain.env_steps + ruled.check_env_steps);
            assert_eq!(ruled.checks, ruled.episodes / 5);
            assert_eq!(plain.converged, None);
            assert_eq!((plain.checks, plain.check_env_steps), (0, 0));
            assert_eq!(plain.last_check_reached, None);
            // On this small maze both converge well before the cap: the reach sub-task's checks
            // reach the target, the other's return settles.
            assert_eq!(ruled.converged, Some(true), "sub-task {k}");
            if k == 0 {
                assert_eq!(ruled.last_check_reached, Some(true));
            }
        }
    }

    /// A goal the sub-task cannot reach in time: training runs to the cap and says so.
    #[test]
    fn the_cap_stops_a_sub_task_that_never_converges() {
        let env = env();
        // Ten episodes at most, a check every 5 and 3 agreeing checks needed: never enough.
        let capped = pretrain_subtask(&env, 0, table1_learner(), &rule(5, 5, 10), 3).unwrap();
        assert_eq!(capped.episodes, 10);
        assert_eq!(capped.converged, Some(false));
        assert_eq!(capped.checks, 2);
        assert!(capped.check_env_steps > 0);
    }
}
