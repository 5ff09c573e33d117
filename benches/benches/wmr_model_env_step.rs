//! Environment steps per second in the default scenario (8 ray casts, camera, rewards, state).

use eamadm::{dql, wmr_model};
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use dql::Environment;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wmr_model::{PlannerParams, Scenario, WmrEnv, shortest_plan};

const STEPS: usize = 10_000;

fn env_steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("env_step");
    group.throughput(Throughput::Elements(STEPS as u64));

    // Uniformly random actions: short episodes (about 13 steps), so resets are included.
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let random_actions: Vec<usize> = (0..STEPS).map(|_| rng.random_range(0..5)).collect();
    let mut env = WmrEnv::default();
    group.bench_function("random_actions", |b| {
        b.iter(|| {
            let mut total = 0.0;
            for &action in &random_actions {
                let step = env.step(black_box(action));
                total += step.reward;
                if step.done() {
                    env.reset(None);
                }
            }
            black_box(total)
        });
    });

    // The planner's route, replayed over and over: every step near obstacles, all the way to
    // the target.
    let scenario = Scenario::default_scenario();
    let plan = shortest_plan(&scenario, &PlannerParams::default()).expect("solvable");
    let route: Vec<usize> = plan.actions.iter().map(|a| a.index()).collect();
    let mut env = WmrEnv::default();
    group.bench_function("planned_route", |b| {
        b.iter(|| {
            let mut total = 0.0;
            let mut at = 0;
            for _ in 0..STEPS {
                let step = env.step(black_box(route[at]));
                total += step.reward;
                at += 1;
                if step.done() {
                    env.reset(None);
                    at = 0;
                }
            }
            black_box(total)
        });
    });
    group.finish();
}

criterion_group!(benches, env_steps);
criterion_main!(benches);
