//! Tabular double Q-learning, exploration policies with schedules, a discrete
//! environment interface and an episode driver: the learning core of eamadm.
//!
//! This crate implements the learning parts of *An Experience Aggregative
//! Reinforcement Learning With Multi-Attribute Decision-Making for Obstacle
//! Avoidance of Wheeled Mobile Robot* that do not depend on the method itself, and
//! is usable on its own with any discrete task:
//!
//! | Paper | Here |
//! | --- | --- |
//! | Eq. 2, Q-learning | [`QLearning`] |
//! | Eq. 9 and Algorithm 1, double Q-learning | [`DoubleQ`], [`run_episode`] |
//! | Eq. 4, ε-greedy; Sec. VI ε-decreasing and softmax; Table 1 annealing | [`EpsilonGreedy`], [`Softmax`], [`Schedule`] |
//!
//! **Eq. 9 is corrected.** The paper prints the successor's action as
//! `argmax_a Q1(s_t, a)`; it must be taken at `s_{t+1}`. [`DoubleQ`] implements van
//! Hasselt's (2010) update: with probability ξ (default 0.5)
//! `Q1(s,a) ← (1−α) Q1(s,a) + α [r + γ Q2(s', argmax_a' Q1(s',a'))]`, otherwise
//! the mirror image for `Q2`. The redundant `max` in front of `Q2(…)` is dropped.
//! Algorithm 2, line 28 has the same kind of typo and uses this same update.
//!
//! Decisions the paper leaves open: a *terminated* step does not bootstrap, a
//! *truncated* one (the step cap) does ([`Step`]); every argmax breaks ties
//! uniformly at random with the caller's RNG; behaviour uses the mean of the two
//! estimators (Algorithm 2, line 20; [`BehaviourValues`]); schedules are per
//! episode, `max(floor, start · factor^episode)`.
//!
//! # Pieces
//!
//! * [`Environment`] and [`Step`]: a discrete episodic task in Gymnasium's shape.
//! * [`Learner`]: [`DoubleQ`] and [`QLearning`], with validated, serialisable
//!   [`DoubleQParams`] / [`QLearningParams`]; estimators readable per pair, per
//!   row, or as dense [`QTable`]s (with a random tie-breaking argmax).
//! * [`ExplorationPolicy`]: an open trait; [`Greedy`], [`EpsilonGreedy`] and
//!   [`Softmax`] built in (also as one serialisable [`BuiltinPolicy`]).
//! * [`RewardSignal`]: what the learner learns from ([`TaskRewardSignal`],
//!   [`SubtaskRewardSignal`], or your own), independent of the task return reported.
//! * [`run_episode`]: one episode of all of the above.
//! * [`DeterministicModel`] and [`value_iteration`]: a task's exact optimal action values
//!   `Q*`, when its model is known, small and deterministic (the fixed point the learners
//!   approach; the mazes expose theirs).
//!
//! Every random draw comes from an RNG the caller passes in; nothing here touches
//! a global or thread-local generator. Bad hyper-parameters are [`DqlError`]s that
//! name the parameter and the value.
//!
//! # Example
//!
//! A corridor of five cells: start in cell 0, reach cell 4 (+10, terminal); every
//! other step costs 1; an episode is truncated after 50 steps.
//!
//! ```
//! use dql::{
//!     DoubleQ, DoubleQParams, EpisodeOptions, EpsilonGreedy, Environment, Greedy, Learner,
//!     Step, TaskRewardSignal, run_episode,
//! };
//! use rand::SeedableRng;
//! use rand_chacha::ChaCha8Rng;
//!
//! struct Corridor {
//!     position: usize,
//!     steps: u32,
//! }
//!
//! impl Environment for Corridor {
//!     fn n_states(&self) -> usize {
//!         5
//!     }
//!     fn n_actions(&self) -> usize {
//!         2 // 0 = left, 1 = right
//!     }
//!     fn reset(&mut self, _seed: Option<u64>) -> usize {
//!         self.position = 0;
//!         self.steps = 0;
//!         0
//!     }
//!     fn step(&mut self, action: usize) -> Step {
//!         self.position = if action == 1 { self.position + 1 } else { self.position.saturating_sub(1) };
//!         self.steps += 1;
//!         let terminated = self.position == 4;
//!         Step {
//!             next_state: self.position,
//!             reward: if terminated { 10.0 } else { -1.0 },
//!             terminated,
//!             truncated: !terminated && self.steps >= 50,
//!         }
//!     }
//! }
//!
//! # fn main() -> Result<(), dql::DqlError> {
//! let mut rng = ChaCha8Rng::seed_from_u64(7);
//! let mut env = Corridor { position: 0, steps: 0 };
//! let params = DoubleQParams { alpha: 0.5, gamma: 0.9, ..DoubleQParams::default() };
//! let mut learner = DoubleQ::new(env.n_states(), env.n_actions(), params, &mut rng)?;
//! // ε-decreasing: ε = 0.95 in episode 0, then × 0.95 per episode, at least 0.05.
//! let mut policy = EpsilonGreedy::decreasing(0.95, 0.95, 0.05)?;
//!
//! for episode in 0..200 {
//!     let options = EpisodeOptions::new(episode);
//!     run_episode(&mut env, &mut learner, &mut policy, &mut TaskRewardSignal, &mut rng, &options)?;
//! }
//!
//! // The greedy policy now walks straight to the goal: 3 × (−1) + 10.
//! let options = EpisodeOptions::new(0).without_learning().recording();
//! let outcome = run_episode(&mut env, &mut learner, &mut Greedy, &mut TaskRewardSignal, &mut rng, &options)?;
//! assert!(outcome.terminated);
//! assert_eq!(outcome.steps, 4);
//! assert_eq!(outcome.task_return, 7.0);
//! assert_eq!(outcome.trajectory.map(|t| t.actions), Some(vec![1, 1, 1, 1]));
//!
//! // Every visited (state, action) with its final Q1 and Q2, e.g. for an experience tree.
//! let visited = learner.experience().count();
//! assert!(visited >= 4);
//! # Ok(())
//! # }
//! ```

pub mod double_q;
pub mod draw;
pub mod env;
pub mod episode;
pub mod error;
pub mod learner;
pub mod model;
pub mod policy;
pub mod q_learning;
pub mod reward_signal;
pub mod schedule;
pub mod table;

pub use double_q::{BehaviourValues, DoubleQ, DoubleQParams};
pub use draw::Coin;
pub use env::{Environment, RgbFrame, Step};
pub use episode::{EpisodeOptions, EpisodeOutcome, Trajectory, run_episode};
pub use error::DqlError;
pub use learner::{ExperienceSample, Learner};
pub use model::{DeterministicModel, MAX_SWEEPS, Transition, ValueIteration, value_iteration};
pub use policy::{BuiltinPolicy, EpsilonGreedy, ExplorationPolicy, Greedy, Softmax};
pub use q_learning::{QLearning, QLearningParams};
pub use reward_signal::{RewardSignal, SubtaskRewardSignal, TaskRewardSignal};
pub use schedule::Schedule;
pub use table::{Initialisation, MAX_ABS_INITIAL_VALUE, QTable, argmax_random_tie, max_value};
