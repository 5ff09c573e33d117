//! Training steps per second on Task I (30 × 30, the paper's maze): plain double Q with
//! ε-greedy against EA-MADM (MADM exploitation over two sub-tasks' prior experience and the
//! running-standardised signal), both at ε = 0.1 after 100 warm-up episodes, so that the
//! figure is the steady-state cost of one step (select, environment step, learning signal,
//! update). Also: one EA-MADM decision alone, and reading a state's prior experience from the
//! precomputed table against looking it up in the trees at every step.

#![allow(clippy::unwrap_used, reason = "benchmark set-up may unwrap")]

use eamadm::{dql, madm_owa};
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use dql::{
    DoubleQ, Environment, EpisodeOptions, EpsilonGreedy, ExplorationPolicy, Learner, RewardSignal,
    Schedule, TaskRewardSignal, run_episode,
};
use eamadm::config::{table1_epsilon_decreasing, table1_learner};
use eamadm::ea_tree::{EaTree, EaTreeConfig, TableEntry};
use eamadm::mazes::{MazeEnv, Preset};
use eamadm::reward_std::Standardisation;
use eamadm::{EaMadmPolicy, PretrainConfig, PriorTable, StandardisedReward, Storage};
use madm_owa::Weighting;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Steps per benchmark iteration.
const STEPS: u64 = 20_000;

/// Runs training episodes until exactly `steps` steps have been taken.
fn train<P: ExplorationPolicy, S: RewardSignal>(
    env: &mut MazeEnv,
    learner: &mut DoubleQ,
    policy: &mut P,
    signal: &mut S,
    rng: &mut ChaCha8Rng,
    steps: u64,
) {
    let mut done = 0;
    while done < steps {
        let options = EpisodeOptions::new(0).with_max_steps(steps - done);
        done += run_episode(env, learner, policy, signal, rng, &options)
            .unwrap()
            .steps;
    }
}

/// Warm-up: 100 training episodes with `policy` (an ε-decreasing one).
fn warm_up<P: ExplorationPolicy, S: RewardSignal>(
    env: &mut MazeEnv,
    learner: &mut DoubleQ,
    policy: &mut P,
    signal: &mut S,
    rng: &mut ChaCha8Rng,
) {
    for episode in 0..100 {
        let options = EpisodeOptions::new(episode);
        run_episode(env, learner, policy, signal, rng, &options).unwrap();
    }
}

fn prior_of(env: &MazeEnv) -> (PriorTable, Vec<EaTree>) {
    let pretrained =
        eamadm::pretrain_subtasks(env, table1_learner(), &PretrainConfig::default(), 1).unwrap();
    let learners: Vec<&DoubleQ> = pretrained.iter().map(|s| &s.learner).collect();
    let (prior, _) = eamadm::build_prior(env, &learners, &Storage::default()).unwrap();
    let features: Vec<Vec<u32>> = (0..env.n_states()).map(|s| env.state_features(s)).collect();
    let trees = learners
        .iter()
        .map(|learner| {
            EaTree::from_table(
                EaTreeConfig::EXACT,
                learner.experience().map(|e| TableEntry {
                    state_id: e.state,
                    state: &features[e.state],
                    action: e.action,
                    q1: e.q1,
                    q2: e.q2,
                }),
            )
            .unwrap()
        })
        .collect();
    (prior, trees)
}

fn training(c: &mut Criterion) {
    let mut group = c.benchmark_group("task1_training_steps");
    group.throughput(Throughput::Elements(STEPS));

    let mut env = Preset::Task1.env();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut learner =
        DoubleQ::new(env.n_states(), env.n_actions(), table1_learner(), &mut rng).unwrap();
    let mut warm = EpsilonGreedy::new(table1_epsilon_decreasing()).unwrap();
    warm_up(
        &mut env,
        &mut learner,
        &mut warm,
        &mut TaskRewardSignal,
        &mut rng,
    );
    let mut policy = EpsilonGreedy::constant(0.1).unwrap();
    group.bench_function("epsilon_greedy", |b| {
        b.iter(|| {
            train(
                &mut env,
                &mut learner,
                &mut policy,
                &mut TaskRewardSignal,
                &mut rng,
                STEPS,
            );
        });
    });

    let (prior, _) = prior_of(&env);
    let mut learner =
        DoubleQ::new(env.n_states(), env.n_actions(), table1_learner(), &mut rng).unwrap();
    let mut signal = StandardisedReward::new(Standardisation::Running, 2).unwrap();
    let mut warm = EaMadmPolicy::new(
        prior.clone(),
        table1_epsilon_decreasing(),
        Weighting::default(),
    )
    .unwrap();
    warm_up(&mut env, &mut learner, &mut warm, &mut signal, &mut rng);
    let mut policy =
        EaMadmPolicy::new(prior, Schedule::Constant(0.1), Weighting::default()).unwrap();
    group.bench_function("ea_madm", |b| {
        b.iter(|| {
            train(
                &mut env,
                &mut learner,
                &mut policy,
                &mut signal,
                &mut rng,
                STEPS,
            );
        });
    });
    group.finish();
}

fn decision(c: &mut Criterion) {
    let env = Preset::Task1.env();
    let (prior, trees) = prior_of(&env);
    let features: Vec<Vec<u32>> = (0..env.n_states()).map(|s| env.state_features(s)).collect();
    let states: Vec<usize> = (0..env.n_states()).step_by(7).collect();
    // Two own-value rows differing in every action, alternated: every row is recomputed.
    let own = [[0.3, -1.2, 0.8, 2.5], [0.4, -1.1, 0.7, 2.4]];

    let mut group = c.benchmark_group("task1_decision");
    group.throughput(Throughput::Elements(states.len() as u64));
    let mut policy =
        EaMadmPolicy::new(prior.clone(), Schedule::Constant(0.0), Weighting::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut turn = 0;
    group.bench_function("ea_madm_decide_all_rows_new", |b| {
        b.iter(|| {
            turn ^= 1;
            for &state in &states {
                black_box(policy.decide(state, black_box(&own[turn]), &mut rng));
            }
        });
    });
    // Reading the 4 × 2 prior answers of a state: precomputed table against tree lookups.
    group.bench_function("prior_from_table", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &state in &states {
                for action in 0..4 {
                    for k in 0..2 {
                        sum += prior.get(state, action, k).unwrap_or(0.0);
                    }
                }
            }
            black_box(sum)
        });
    });
    group.bench_function("prior_from_tree_lookups", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &state in &states {
                for action in 0..4 {
                    for tree in &trees {
                        sum += tree
                            .lookup(&features[state], action)
                            .map_or(0.0, |a| a.q_mean());
                    }
                }
            }
            black_box(sum)
        });
    });
    group.finish();
}

criterion_group!(benches, training, decision);
criterion_main!(benches);
