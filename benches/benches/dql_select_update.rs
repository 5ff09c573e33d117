//! One ε-greedy (or softmax) select + one double-Q update on Task I's table size (900 × 4).
//!
//! Each iteration processes a batch of pre-drawn transitions, so the figure is
//! the learning core's cost per environment step, without any environment. Two
//! access patterns: states drawn uniformly at random (every row a likely cache
//! miss: the worst case) and a random walk on Task I's 30 × 30 grid (what an
//! episode looks like: the successor is a neighbour and the next step's state).

#![allow(clippy::unwrap_used, reason = "benchmark set-up may unwrap")]

use eamadm::dql;
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use dql::{
    DoubleQ, DoubleQParams, EpsilonGreedy, ExplorationPolicy, Initialisation, Learner, Softmax,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const N_STATES: usize = 900;
const N_ACTIONS: usize = 4;
const BATCH: usize = 4096;

struct Transition {
    state: usize,
    next_state: usize,
    reward: f64,
    terminated: bool,
}

/// Uniformly random states and successors, 1 in 50 steps terminal.
fn uniform_transitions(rng: &mut ChaCha8Rng) -> Vec<Transition> {
    (0..BATCH)
        .map(|_| Transition {
            state: rng.random_range(0..N_STATES),
            next_state: rng.random_range(0..N_STATES),
            reward: if rng.random_bool(0.5) { 1.0 } else { -1.0 },
            terminated: rng.random_bool(0.02),
        })
        .collect()
}

/// A random walk on a 30 × 30 grid (bumping the border stays), never terminal.
fn walk_transitions(rng: &mut ChaCha8Rng) -> Vec<Transition> {
    const SIDE: usize = 30;
    let mut state = 0;
    (0..BATCH)
        .map(|_| {
            let (row, col) = (state / SIDE, state % SIDE);
            let next_state = match rng.random_range(0..4) {
                0 if row > 0 => state - SIDE,
                1 if row + 1 < SIDE => state + SIDE,
                2 if col > 0 => state - 1,
                3 if col + 1 < SIDE => state + 1,
                _ => state,
            };
            let transition = Transition {
                state,
                next_state,
                reward: if rng.random_bool(0.5) { 1.0 } else { -1.0 },
                terminated: false,
            };
            state = next_state;
            transition
        })
        .collect()
}

fn bench<P: ExplorationPolicy>(
    c: &mut Criterion,
    group_name: &str,
    mut policy: P,
    name: &str,
    init: Initialisation,
    transitions: fn(&mut ChaCha8Rng) -> Vec<Transition>,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let params = DoubleQParams {
        init,
        ..DoubleQParams::default()
    };
    let mut learner = DoubleQ::new(N_STATES, N_ACTIONS, params, &mut rng).unwrap();
    let batch = transitions(&mut rng);
    let mut values = [0.0; N_ACTIONS];

    let mut group = c.benchmark_group(group_name);
    group.throughput(Throughput::Elements(BATCH as u64));
    group.bench_function(name, |b| {
        b.iter(|| {
            for transition in &batch {
                learner.action_values(transition.state, &mut values);
                let action = policy.select(transition.state, &values, &mut rng);
                learner.update(
                    transition.state,
                    action,
                    transition.reward,
                    transition.next_state,
                    transition.terminated,
                    &mut rng,
                );
            }
            black_box(&learner);
        });
    });
    group.finish();
}

fn select_and_update(c: &mut Criterion) {
    let learned = Initialisation::Uniform {
        low: -1.0,
        high: 1.0,
    };
    let group = "epsilon_greedy_select_plus_double_q_update_900x4";
    let epsilon_greedy = || EpsilonGreedy::constant(0.1).unwrap();
    bench(
        c,
        group,
        epsilon_greedy(),
        "uniform_states",
        learned,
        uniform_transitions,
    );
    bench(
        c,
        group,
        epsilon_greedy(),
        "grid_walk",
        learned,
        walk_transitions,
    );
    // Zero initialisation: every argmax starts as a tie, so tie-break draws
    // dominate until the values separate.
    bench(
        c,
        group,
        epsilon_greedy(),
        "uniform_states_zero_init",
        Initialisation::Zero,
        uniform_transitions,
    );
    // Softmax at Table 1's starting temperature: one `exp` per action and draw.
    let softmax = Softmax::constant(0.1).unwrap();
    bench(
        c,
        "softmax_select_plus_double_q_update_900x4",
        softmax,
        "grid_walk",
        learned,
        walk_transitions,
    );
}

criterion_group!(benches, select_and_update);
criterion_main!(benches);
