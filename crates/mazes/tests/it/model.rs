//! The maze as a deterministic model ([`MazeEnv::model`]): it is the environment's dynamics and
//! rewards, and its value-iteration `Q*` is what the learners converge to.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use dql::{
    DoubleQ, DoubleQParams, EpisodeOptions, EpsilonGreedy, Learner, QLearning, QLearningParams,
    SubtaskRewardSignal, TaskRewardSignal, run_episode, value_iteration,
};
use mazes::{Action, Event, Maze, MazeEnv, Preset, RewardScheme, TaskSpec};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const TINY: &str = "S.#\n.#.\n..T\n";

/// Every pair of the model is the maze's transition: successor, the scheme's reward for its
/// event, terminal exactly on reaching the target.
#[test]
fn the_model_is_the_environments_dynamics() {
    for preset in Preset::ALL {
        let env = preset.env();
        let maze = env.maze();
        for (k, scheme) in [
            env.spec().reward,
            env.spec().subtasks[0].reward,
            RewardScheme::DO_NOT_HIT,
        ]
        .iter()
        .enumerate()
        {
            let model = env.model(scheme).unwrap();
            assert_eq!(model.n_states(), maze.n_tiles());
            for state in 0..maze.n_tiles() {
                let from = maze.pos_of(state).unwrap();
                for action in Action::ALL {
                    let (next, event) = maze.transition(from, action);
                    let step = model.transition(state, action.index());
                    assert_eq!(step.next, maze.state_of(next).unwrap(), "{preset:?} {k}");
                    assert_eq!(step.reward, scheme.reward(event));
                    assert_eq!(step.terminal, event == Event::Target);
                }
            }
        }
        assert_eq!(env.task_model(), env.model(&env.spec().reward).unwrap());
        assert_eq!(
            env.subtask_model(1),
            Some(env.model(&env.spec().subtasks[1].reward).unwrap())
        );
        assert_eq!(env.subtask_model(2), None);
    }
}

#[test]
fn a_scheme_that_is_not_finite_is_refused_by_name() {
    let env = Preset::Task1.env();
    let bad = RewardScheme {
        bump: f64::NAN,
        ..RewardScheme::TASK_I
    };
    let error = env.model(&bad).unwrap_err();
    assert!(error.to_string().contains("scheme.bump"), "{error}");
}

/// States a learner acts from: free tiles reachable from the start without passing the target
/// (reaching it ends the episode), the target excluded.
fn live_states(maze: &Maze) -> Vec<usize> {
    let mut live = vec![false; maze.n_tiles()];
    let mut stack = vec![maze.start()];
    live[maze.state_of(maze.start()).unwrap()] = true;
    while let Some(at) = stack.pop() {
        for (_, next) in maze.free_neighbours(at) {
            let index = maze.state_of(next).unwrap();
            if !live[index] {
                live[index] = true;
                if next != maze.target() {
                    stack.push(next);
                }
            }
        }
    }
    (0..maze.n_tiles())
        .filter(|&s| live[s] && maze.pos_of(s) != Some(maze.target()))
        .collect()
}

/// Double Q and Q-learning, behaving uniformly at random (every pair keeps being visited) with
/// a constant step size on this deterministic task, converge to the model's `Q*` for each
/// reward the task pays: the task's own and both sub-tasks'. The step cap truncates most
/// episodes; bootstrapping on truncation is what makes the infinite-horizon `Q*` the limit.
#[test]
fn the_learners_converge_to_value_iteration_on_a_tiny_maze() {
    let gamma = 0.9;
    let maze = Maze::parse(TINY).unwrap();
    let spec = TaskSpec {
        step_cap: 12,
        ..TaskSpec::task1()
    };
    let env = MazeEnv::new(maze.clone(), spec).unwrap();
    let live = live_states(&maze);
    assert_eq!(
        live.len(),
        5,
        "S, its right neighbour and the L down to the target"
    );
    // None: the task's reward; Some(k): sub-task k's.
    for signal in [None, Some(0), Some(1)] {
        let model = match signal {
            None => env.task_model(),
            Some(k) => env.subtask_model(k).unwrap(),
        };
        let optimal = value_iteration(&model, gamma, 1e-12).unwrap().q;
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        let params = DoubleQParams {
            alpha: 0.5,
            gamma,
            ..DoubleQParams::default()
        };
        let mut double_q = DoubleQ::new(maze.n_tiles(), 4, params, &mut rng).unwrap();
        let mut q_learning = QLearning::new(
            maze.n_tiles(),
            4,
            QLearningParams::new(0.5, gamma).unwrap(),
            &mut rng,
        )
        .unwrap();
        let mut policy = EpsilonGreedy::constant(1.0).unwrap();
        for episode in 0..4000 {
            let options = EpisodeOptions::new(episode);
            let mut env_a = env.clone();
            let mut env_b = env.clone();
            match signal {
                None => {
                    run_episode(
                        &mut env_a,
                        &mut double_q,
                        &mut policy,
                        &mut TaskRewardSignal,
                        &mut rng,
                        &options,
                    )
                    .unwrap();
                    run_episode(
                        &mut env_b,
                        &mut q_learning,
                        &mut policy,
                        &mut TaskRewardSignal,
                        &mut rng,
                        &options,
                    )
                    .unwrap();
                }
                Some(k) => {
                    run_episode(
                        &mut env_a,
                        &mut double_q,
                        &mut policy,
                        &mut SubtaskRewardSignal(k),
                        &mut rng,
                        &options,
                    )
                    .unwrap();
                    run_episode(
                        &mut env_b,
                        &mut q_learning,
                        &mut policy,
                        &mut SubtaskRewardSignal(k),
                        &mut rng,
                        &options,
                    )
                    .unwrap();
                }
            }
        }
        for &s in &live {
            for a in 0..4 {
                let want = optimal.get(s, a);
                for (name, got) in [
                    ("double Q, Q1", double_q.q1_table().get(s, a)),
                    ("double Q, Q2", double_q.q2_table().get(s, a)),
                    ("Q-learning", q_learning.q1_table().get(s, a)),
                ] {
                    assert!(
                        (got - want).abs() < 1e-6,
                        "{signal:?} {name} at state {s}, action {a}: {got} vs Q* {want}"
                    );
                }
            }
        }
    }
}
