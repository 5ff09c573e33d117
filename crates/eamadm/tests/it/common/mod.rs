//! A small maze experiment that trains in milliseconds, shared by the integration tests.

#![allow(
    dead_code,
    clippy::unwrap_used,
    reason = "each test file uses part of this module"
)]

use eamadm::config::table1_learner;
use eamadm::mazes::{GeneratorParams, Pos, Preset, generate_seeded};
use eamadm::paper::methods as paper_methods;
use eamadm::{
    EvaluationConfig, ExperimentConfig, Method, MethodSpec, TaskConfig, TrajectoryConfig,
};

/// A 10 × 10 maze with 15 obstacles, start top-left, target bottom-right.
pub(crate) fn small_map() -> String {
    let params = GeneratorParams {
        width: 10,
        height: 10,
        obstacles: 15,
        start: Pos::new(0, 0),
        target: Pos::new(9, 9),
        max_attempts: 100,
    };
    generate_seeded(&params, 3).unwrap().to_text()
}

/// The paper's methods on the small maze with Task I's rewards: `episodes` episodes (and as
/// many pre-training episodes per sub-task, a fixed number: without the presets' stopping rule,
/// which tests of its own exercise), a step cap of 300, `seeds` seeds.
pub(crate) fn small_config(episodes: u64, seeds: u32) -> ExperimentConfig {
    let mut methods: Vec<MethodSpec> = paper_methods();
    for spec in &mut methods {
        if let Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = episodes;
            ea.pretrain.until = None;
        }
    }
    ExperimentConfig {
        name: "small".to_owned(),
        task: TaskConfig::MazeText {
            map: small_map(),
            rewards: Preset::Task1,
            step_cap: Some(300),
        },
        episodes,
        seeds,
        base_seed: 100,
        learner: table1_learner(),
        trajectories: TrajectoryConfig::default(),
        evaluation: EvaluationConfig::default(),
        methods,
    }
}

/// Only the methods with these labels, in this order.
pub(crate) fn only(mut config: ExperimentConfig, labels: &[&str]) -> ExperimentConfig {
    config.methods = labels
        .iter()
        .map(|label| config.method(label).unwrap().clone())
        .collect();
    config
}
