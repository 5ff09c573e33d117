//! Value stability: fixed seeds give pinned sequences, so a change of numbers
//! (from our code or a dependency bump) is caught.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use crate::common;

use std::fmt::Write as _;

use common::TableMdp;
use dql::{
    DoubleQ, DoubleQParams, EpisodeOptions, EpsilonGreedy, ExplorationPolicy, Greedy,
    Initialisation, Learner, QLearning, QLearningParams, QTable, Softmax, TaskRewardSignal,
    run_episode,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn round6(value: f64) -> f64 {
    let rounded = (value * 1e6).round() / 1e6;
    if rounded == 0.0 { 0.0 } else { rounded }
}

fn write_table(out: &mut String, name: &str, table: &QTable) {
    writeln!(out, "{name}:").unwrap();
    for s in 0..table.n_states() {
        let row: Vec<String> = table
            .row(s)
            .iter()
            .map(|&v| format!("{:>10}", round6(v)))
            .collect();
        writeln!(out, "  s{s}: {}", row.join(" ")).unwrap();
    }
}

fn train<L: Learner, P: ExplorationPolicy>(
    learner: &mut L,
    policy: &mut P,
    policy_parameter: impl Fn(&P) -> f64,
    rng: &mut ChaCha8Rng,
) -> String {
    let mut env = TableMdp::grid(Some(20));
    let mut out = String::new();
    for episode in 0..6 {
        let options = EpisodeOptions::new(episode).recording();
        let outcome = run_episode(
            &mut env,
            learner,
            policy,
            &mut TaskRewardSignal,
            rng,
            &options,
        )
        .unwrap();
        writeln!(
            out,
            "episode {episode}: parameter {:.6} steps {:>2} return {:>4} terminated {:<5} truncated {:<5} actions {:?}",
            policy_parameter(policy),
            outcome.steps,
            outcome.task_return,
            outcome.terminated,
            outcome.truncated,
            outcome.trajectory.unwrap().actions,
        )
        .unwrap();
    }
    write_table(&mut out, "Q1", &learner.q1_table());
    write_table(&mut out, "Q2", &learner.q2_table());
    out
}

#[test]
fn double_q_with_epsilon_decreasing() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let params = DoubleQParams {
        alpha: 0.1,
        gamma: 0.95,
        xi: 0.5,
        init: Initialisation::Uniform {
            low: -0.01,
            high: 0.01,
        },
        ..DoubleQParams::default()
    };
    let mut learner = DoubleQ::new(6, 4, params, &mut rng).unwrap();
    let mut policy = EpsilonGreedy::decreasing(0.95, 0.95, 0.05).unwrap();
    let out = train(&mut learner, &mut policy, EpsilonGreedy::epsilon, &mut rng);
    insta::assert_snapshot!(out);
}

#[test]
fn q_learning_with_annealed_softmax() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    let mut learner = QLearning::new(6, 4, QLearningParams::default(), &mut rng).unwrap();
    let mut policy = Softmax::annealed(0.1, 0.95, 0.01).unwrap();
    let out = train(&mut learner, &mut policy, Softmax::temperature, &mut rng);
    insta::assert_snapshot!(out);
}

#[test]
fn selection_sequences() {
    let values = [1.0, 0.5, 0.0, -2.0];
    let ties = [0.0; 4];
    let mut softmax = Softmax::constant(0.5).unwrap();
    let mut epsilon = EpsilonGreedy::constant(0.5).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(44);
    let softmax_actions: Vec<usize> = (0..30)
        .map(|_| softmax.select(0, &values, &mut rng))
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(45);
    let epsilon_actions: Vec<usize> = (0..30)
        .map(|_| epsilon.select(0, &values, &mut rng))
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(46);
    let tie_actions: Vec<usize> = (0..30).map(|_| Greedy.select(0, &ties, &mut rng)).collect();
    insta::assert_snapshot!(format!(
        "softmax T=0.5 on [1, 0.5, 0, -2]: {softmax_actions:?}\nepsilon 0.5 on [1, 0.5, 0, -2]:   {epsilon_actions:?}\ngreedy on all ties:               {tie_actions:?}"
    ));
}
