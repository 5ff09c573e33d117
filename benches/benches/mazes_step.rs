//! Environment steps per second on the Task I maze (target: ≥ 100 M steps/s on one core).

use eamadm::{dql, mazes};
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use dql::Environment;
use mazes::Preset;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Steps per measured iteration.
const STEPS: usize = 1 << 16;

fn task_i_steps(c: &mut Criterion) {
    let mut env = Preset::Task1.env();
    env.reset(None);
    // A random walk, drawn up front so the benchmark measures the environment, not the RNG.
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let actions: Vec<u8> = (0..STEPS).map(|_| rng.random_range(0..4)).collect();

    let mut group = c.benchmark_group("maze_env");
    group.throughput(Throughput::Elements(STEPS as u64));
    group.bench_function("task1_random_walk_step", |b| {
        b.iter(|| {
            let mut total = 0.0;
            for &action in &actions {
                let step = env.step(black_box(usize::from(action)));
                total += step.reward + env.subtask_rewards()[1];
                if step.done() {
                    env.reset(None);
                }
            }
            black_box(total)
        });
    });
    group.finish();
}

criterion_group!(benches, task_i_steps);
criterion_main!(benches);
