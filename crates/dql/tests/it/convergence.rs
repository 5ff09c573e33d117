//! Both learners reach the value-iteration Q* on a small deterministic MDP.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use crate::common;

use common::TableMdp;
use dql::{
    DoubleQ, DoubleQParams, EpisodeOptions, EpsilonGreedy, Learner, QLearning, QLearningParams,
    QTable, TaskRewardSignal, run_episode,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const GAMMA: f64 = 0.9;
const TOLERANCE: f64 = 1e-9;

/// Largest |Q(s, a) − Q*(s, a)| over the states the agent acts from.
fn max_error(table: &QTable, optimal: &[f64], live: &[usize]) -> f64 {
    let mut worst: f64 = 0.0;
    for &s in live {
        for a in 0..table.n_actions() {
            worst = worst.max((table.get(s, a) - optimal[s * table.n_actions() + a]).abs());
        }
    }
    worst
}

/// Trains with uniformly random behaviour (ε = 1), so every pair keeps being visited.
fn train<L: Learner>(learner: &mut L, env: &mut TableMdp, rng: &mut ChaCha8Rng, episodes: u64) {
    let mut policy = EpsilonGreedy::constant(1.0).unwrap();
    for episode in 0..episodes {
        let outcome = run_episode(
            env,
            learner,
            &mut policy,
            &mut TaskRewardSignal,
            rng,
            &EpisodeOptions::new(episode),
        )
        .unwrap();
        assert!(outcome.terminated || outcome.truncated);
    }
}

/// Runs for both a long cap and a short one: with the short cap most episodes are
/// truncated, and only bootstrapping on truncation reaches the infinite-horizon Q*.
#[test]
fn double_q_reaches_value_iteration_q_star() {
    for (cap, episodes) in [(50, 3000), (3, 20_000)] {
        let mut env = TableMdp::grid(Some(cap));
        let optimal = env.optimal_q(GAMMA);
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let params = DoubleQParams {
            alpha: 0.5,
            gamma: GAMMA,
            ..DoubleQParams::default()
        };
        let mut learner = DoubleQ::new(6, 4, params, &mut rng).unwrap();
        train(&mut learner, &mut env, &mut rng, episodes);
        let live = env.live_states();
        let e1 = max_error(&learner.q1_table(), &optimal, &live);
        let e2 = max_error(&learner.q2_table(), &optimal, &live);
        assert!(
            e1 < TOLERANCE && e2 < TOLERANCE,
            "cap {cap}: errors {e1}, {e2}"
        );
    }
}

#[test]
fn q_learning_reaches_value_iteration_q_star() {
    for (cap, episodes) in [(50, 3000), (3, 20_000)] {
        let mut env = TableMdp::grid(Some(cap));
        let optimal = env.optimal_q(GAMMA);
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let params = QLearningParams {
            alpha: 0.5,
            ..QLearningParams::new(0.5, GAMMA).unwrap()
        };
        let mut learner = QLearning::new(6, 4, params, &mut rng).unwrap();
        train(&mut learner, &mut env, &mut rng, episodes);
        let error = max_error(&learner.q1_table(), &optimal, &env.live_states());
        assert!(error < TOLERANCE, "cap {cap}: error {error}");
    }
}

/// The optimal policy read off the trained double-Q values walks 0 → 1 → 2 → 5.
#[test]
fn greedy_policy_after_training_is_optimal() {
    let mut env = TableMdp::grid(Some(50));
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let params = DoubleQParams {
        alpha: 0.5,
        gamma: GAMMA,
        ..DoubleQParams::default()
    };
    let mut learner = DoubleQ::new(6, 4, params, &mut rng).unwrap();
    train(&mut learner, &mut env, &mut rng, 500);
    let options = EpisodeOptions::new(0).without_learning().recording();
    let outcome = run_episode(
        &mut env,
        &mut learner,
        &mut dql::Greedy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )
    .unwrap();
    assert_eq!(outcome.trajectory.unwrap().states, vec![0, 1, 2, 5]);
    assert_eq!(outcome.task_return, 8.0);
}

/// Sanity check of the reference itself: Q*(0, right) = −1 + γ(−1 + γ·10).
#[test]
fn value_iteration_reference_is_right() {
    let optimal = TableMdp::grid(None).optimal_q(GAMMA);
    let expected = -1.0 + GAMMA * (-1.0 + GAMMA * 10.0);
    assert!((optimal[3] - expected).abs() < 1e-12);
    // Entering the pit is terminal: Q*(1, down) = −10 exactly.
    assert_eq!(optimal[4 + 1], -10.0);
}
