//! Solves the default scenario three ways and draws the runs.
//!
//! `cargo run --release -p wmr-model --example fig12 -- [scenario.toml] [out.svg]`
//!
//! Prints the planner's shortest route, a deterministic table over the discrete state that
//! reaches the target, and how long uniformly random policies survive; writes an SVG of the
//! runs when an output path is given.

use std::collections::BTreeMap;

use dql::Environment;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wmr_model::{
    PlannerParams, RenderedPath, Scenario, WmrEnv, render_svg, shortest_plan, tabular_policy,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scenario = match args.first() {
        Some(path) if path.ends_with(".toml") => {
            Scenario::from_toml_str(&std::fs::read_to_string(path)?)?
        }
        _ => Scenario::default_scenario(),
    };
    let output = args.iter().find(|a| a.ends_with(".svg"));
    let mut env = WmrEnv::new(scenario.clone())?;
    println!(
        "scenario {:?}: {} states, {} actions, {} obstacles",
        scenario.name,
        env.n_states(),
        env.n_actions(),
        scenario.obstacles.len()
    );
    let mut paths: Vec<(Vec<_>, String)> = Vec::new();

    match shortest_plan(&scenario, &PlannerParams::default()) {
        Some(plan) => {
            env.reset(Some(0));
            for action in &plan.actions {
                env.step(action.index());
            }
            let m = env.metrics();
            println!(
                "planner: {} steps ({:.1} s), {} nodes expanded; replayed: {:?}, return {:.2}, \
                 average reward {:.2}/s, retention {:.1} s",
                plan.actions.len(),
                plan.duration(scenario.control_period),
                plan.expanded,
                m.status,
                m.task_return,
                m.average_reward(),
                m.retention_time
            );
            paths.push((env.path().to_vec(), "planner".into()));
        }
        None => println!("planner: no route found"),
    }

    match tabular_policy(&scenario, 200, 5_000_000) {
        Some(table) => {
            env.reset(Some(0));
            while let Some(action) = table.actions[env.state()] {
                if env.step(action.index()).done() {
                    break;
                }
            }
            let m = env.metrics();
            println!(
                "state table: {} states used, {} steps, {:?}, return {:.2}, average reward \
                 {:.2}/s, retention {:.1} s",
                table.actions.iter().flatten().count(),
                m.steps,
                m.status,
                m.task_return,
                m.average_reward(),
                m.retention_time
            );
            paths.push((env.path().to_vec(), "state table".into()));
        }
        None => println!("state table: none found within the budget"),
    }

    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let episodes = 10_000;
    let mut steps = 0;
    let mut outcomes = BTreeMap::new();
    for episode in 0..episodes {
        env.reset(Some(episode));
        while !env.step(rng.random_range(0..5)).done() {}
        steps += env.metrics().steps;
        *outcomes.entry(format!("{:?}", env.status())).or_insert(0) += 1;
        if episode < 3 {
            paths.push((env.path().to_vec(), format!("random {episode}")));
        }
    }
    let mean = steps as f64 / episodes as f64;
    println!("random policy: {mean:.1} steps per episode on average, outcomes {outcomes:?}");

    if let Some(path) = output {
        let rendered: Vec<RenderedPath<'_>> = paths
            .iter()
            .map(|(points, label)| RenderedPath { points, label })
            .collect();
        std::fs::write(path, render_svg(&scenario, &rendered))?;
        println!("wrote {path}");
    }
    Ok(())
}
