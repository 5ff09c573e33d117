//! The episode driver: one episode of a learner and a policy on an environment
//! (the inner loop of Algorithm 1).

use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::env::Environment;
use crate::error::DqlError;
use crate::learner::Learner;
use crate::policy::ExplorationPolicy;
use crate::reward_signal::RewardSignal;

/// How to run one episode. Every field has a default; an unknown field is an error that names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EpisodeOptions {
    /// 0-based index of the episode, handed to the policy's per-episode hooks
    /// (so its schedules advance). Default 0.
    pub episode: u64,
    /// Seed passed to [`Environment::reset`]; `None` continues the environment's
    /// own random stream. Default `None`.
    pub seed: Option<u64>,
    /// A step cap enforced by the driver, on top of any the environment has.
    /// Reaching it ends the episode as *truncated* (the last update bootstrapped,
    /// as for any truncation). Default `None`.
    pub max_steps: Option<u64>,
    /// Update the learner after every step. `false` evaluates the current values
    /// without changing them. Default `true`.
    pub learn: bool,
    /// Record the visited states and chosen actions. Default `false` (and then
    /// the episode allocates nothing per step).
    pub record_trajectory: bool,
}

impl Default for EpisodeOptions {
    fn default() -> Self {
        Self {
            episode: 0,
            seed: None,
            max_steps: None,
            learn: true,
            record_trajectory: false,
        }
    }
}

impl EpisodeOptions {
    /// Default options for episode `episode`.
    #[must_use]
    pub fn new(episode: u64) -> Self {
        Self {
            episode,
            ..Self::default()
        }
    }

    /// The same options with `reset` seeded by `seed`.
    #[must_use]
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = Some(seed);
        self
    }

    /// The same options with a driver-side step cap.
    #[must_use]
    pub fn with_max_steps(mut self, max_steps: u64) -> Self {
        self.max_steps = Some(max_steps);
        self
    }

    /// The same options, recording the trajectory.
    #[must_use]
    pub fn recording(mut self) -> Self {
        self.record_trajectory = true;
        self
    }

    /// The same options, without learning.
    #[must_use]
    pub fn without_learning(mut self) -> Self {
        self.learn = false;
        self
    }
}

/// The states visited and actions taken in one episode.
///
/// `states[t]` is the state in which `actions[t]` was taken, and
/// `states[t + 1]` the state it led to, so `states.len() == actions.len() + 1`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Trajectory {
    /// Visited states, starting with the one `reset` returned.
    pub states: Vec<usize>,
    /// Chosen actions.
    pub actions: Vec<usize>,
}

/// What one episode did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EpisodeOutcome {
    /// Number of transitions (environment steps).
    pub steps: u64,
    /// Sum of the task's rewards ([`Step::reward`](crate::Step::reward)), whatever
    /// the learning signal: the return learning curves plot.
    pub task_return: f64,
    /// Sum of the rewards the learner was given by the [`RewardSignal`].
    pub learning_return: f64,
    /// The episode ended inside the task (goal, hit, lost target).
    pub terminated: bool,
    /// The episode was cut by a step cap (the environment's or the driver's).
    pub truncated: bool,
    /// The trajectory, when [`EpisodeOptions::record_trajectory`] was set.
    pub trajectory: Option<Trajectory>,
}

/// Action counts up to which [`run_episode`] keeps the action values on the stack.
const INLINE_ACTIONS: usize = 8;

/// Runs one episode: reset, then select → step → learn until the episode
/// terminates or is truncated.
///
/// In order: checks that `env` and `learner` have the same numbers of states and
/// actions, calls `signal.begin_episode(env.n_subtasks())` and
/// `policy.begin_episode(options.episode)`, resets `env` with `options.seed`, then
/// for each step
/// 1. writes the learner's action values for the current state into a buffer (on
///    the stack for up to eight actions, else allocated once per episode),
/// 2. asks `policy` for an action (given the state, the values and `rng`),
/// 3. steps `env`, and turns the step and `env.subtask_rewards()` into the
///    learning reward with `signal`,
/// 4. (if `options.learn`) calls
///    `learner.update(state, action, learning_reward, next_state, step.terminated, rng)`:
///    a terminated step does not bootstrap, a truncated one does,
///
/// and finally calls `policy.end_episode(options.episode)`. All randomness of the
/// policy and the learner comes from `rng`; the environment uses its own stream.
/// Without trajectory recording nothing is allocated per step.
///
/// # Errors
/// [`DqlError::ShapeMismatch`] before the episode starts; whatever
/// `signal.begin_episode` returns (e.g. [`DqlError::SubtaskOutOfRange`]); and, when
/// a component breaks its contract mid-episode, [`DqlError::StateOutOfRange`],
/// [`DqlError::ActionOutOfRange`] or [`DqlError::NonFiniteReward`] (the learner is
/// not updated with the offending step, and `policy.end_episode` is not called).
pub fn run_episode<E, L, P, S, R>(
    env: &mut E,
    learner: &mut L,
    policy: &mut P,
    signal: &mut S,
    rng: &mut R,
    options: &EpisodeOptions,
) -> Result<EpisodeOutcome, DqlError>
where
    E: Environment + ?Sized,
    L: Learner,
    P: ExplorationPolicy,
    S: RewardSignal + ?Sized,
    R: Rng + ?Sized,
{
    let n_states = learner.n_states();
    let n_actions = learner.n_actions();
    if env.n_states() != n_states {
        return Err(DqlError::ShapeMismatch {
            what: "state count",
            environment: env.n_states(),
            learner: n_states,
        });
    }
    if env.n_actions() != n_actions {
        return Err(DqlError::ShapeMismatch {
            what: "action count",
            environment: env.n_actions(),
            learner: n_actions,
        });
    }
    signal.begin_episode(env.n_subtasks())?;
    policy.begin_episode(options.episode);

    let mut state = env.reset(options.seed);
    if state >= n_states {
        return Err(DqlError::StateOutOfRange {
            state,
            n_states,
            step: 0,
        });
    }
    let mut trajectory = options.record_trajectory.then(|| Trajectory {
        states: vec![state],
        actions: Vec::new(),
    });
    // On the stack for the mazes' four and the robot's five actions: a heap buffer per episode
    // was a malloc and a free for every one of the runner's short episodes.
    let mut inline = [0.0; INLINE_ACTIONS];
    let mut heap = Vec::new();
    let action_values: &mut [f64] = if n_actions <= INLINE_ACTIONS {
        &mut inline[..n_actions]
    } else {
        heap.resize(n_actions, 0.0);
        &mut heap
    };
    let mut outcome = EpisodeOutcome {
        steps: 0,
        task_return: 0.0,
        learning_return: 0.0,
        terminated: false,
        truncated: false,
        trajectory: None,
    };

    loop {
        if options.max_steps.is_some_and(|cap| outcome.steps >= cap) {
            outcome.truncated = true;
            break;
        }
        learner.action_values(state, action_values);
        let action = policy.select(state, action_values, rng);
        if action >= n_actions {
            return Err(DqlError::ActionOutOfRange {
                action,
                n_actions,
                step: outcome.steps + 1,
            });
        }
        let step = env.step(action);
        outcome.steps += 1;
        if step.next_state >= n_states {
            return Err(DqlError::StateOutOfRange {
                state: step.next_state,
                n_states,
                step: outcome.steps,
            });
        }
        if !step.reward.is_finite() {
            return Err(DqlError::NonFiniteReward {
                which: "task",
                step: outcome.steps,
                value: step.reward,
            });
        }
        let learning_reward = signal.learning_reward(&step, env.subtask_rewards());
        if !learning_reward.is_finite() {
            return Err(DqlError::NonFiniteReward {
                which: "learning signal",
                step: outcome.steps,
                value: learning_reward,
            });
        }
        if options.learn {
            learner.update(
                state,
                action,
                learning_reward,
                step.next_state,
                step.terminated,
                rng,
            );
        }
        outcome.task_return += step.reward;
        outcome.learning_return += learning_reward;
        if let Some(trajectory) = trajectory.as_mut() {
            trajectory.actions.push(action);
            trajectory.states.push(step.next_state);
        }
        state = step.next_state;
        if step.terminated {
            outcome.terminated = true;
            break;
        }
        if step.truncated {
            outcome.truncated = true;
            break;
        }
    }

    policy.end_episode(options.episode);
    outcome.trajectory = trajectory;
    Ok(outcome)
}
