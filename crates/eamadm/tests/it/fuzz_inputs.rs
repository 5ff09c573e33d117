//! The fuzz suite of the input parsers and loaders (issue 14, item 12): byte-mutated seed inputs
//! and random bytes go through each loader, and every case must end in a value or a typed error,
//! never a panic (proptest turns a panic into a failed test; an abort kills the test binary,
//! which fails too).
//!
//! - experiment configs: `ExperimentConfig::from_toml_str`, then `Experiment::new` (which loads
//!   the task: maze BFS, the robot's planner) and, when that succeeds, the plan of jobs;
//! - maze text maps: `Maze::parse`, then a maze environment with Task I's rewards and a few steps;
//! - robot scenarios: `Scenario::from_toml_str`, the planner (with a small search budget) and a
//!   few environment steps.
//!
//! Tree files are fuzzed in `ea-tree`'s tests. The case count is bounded for `cargo test` (a few
//! seconds); `EAMADM_FUZZ_CASES=20000 cargo test --release -p eamadm --test it fuzz` runs longer.

use dql::Environment as _;
use eamadm::mazes::{Maze, MazeEnv, TaskSpec};
use eamadm::wmr_model::{PlannerParams, Scenario, WmrEnv, shortest_plan};
use eamadm::{Experiment, ExperimentConfig, PAPER_ROBOT_TOML, PAPER_TASK1_TOML, PAPER_TASK2_TOML};
use proptest::prelude::*;

use crate::mutate::{fuzz_config, mutated_text};

/// Seed configs: the three paper configs and a small inline maze with every optional table.
fn config_corpus() -> Vec<String> {
    let inline = r#"
name = "inline"
episodes = 3
seeds = 2
base_seed = 7

[task]
kind = "maze_text"
map = "S.#\n..T\n"
rewards = "task2"
step_cap = 20

[learner]
alpha = 0.5
gamma = 0.9
xi = 0.5
init = { kind = "uniform", low = -0.1, high = 0.1 }

[trajectories]
first = true
last = false
episodes = [1]

[[methods]]
label = "ea"
kind = "ea_madm"
epsilon = { constant = 0.1 }
weighting = { kind = "visibility", support = { kind = "paper" } }
storage = { kind = "tree", state_threshold = 0.5, action_threshold = 1.0 }
pretrain = { episodes = 2, epsilon = { constant = 0.5 } }

[[methods]]
label = "soft"
kind = "softmax"
role = "control"
temperature = { exponential = { start = 1.0, factor = 0.9, floor = 0.1 } }
"#;
    vec![
        PAPER_TASK1_TOML.to_owned(),
        PAPER_TASK2_TOML.to_owned(),
        PAPER_ROBOT_TOML.to_owned(),
        inline.to_owned(),
    ]
}

fn load_config(text: &str) {
    let Ok(config) = ExperimentConfig::from_toml_str(text) else {
        return;
    };
    // A validated config must serialise and parse back.
    let back = config.to_toml_string().unwrap();
    assert_eq!(ExperimentConfig::from_toml_str(&back).unwrap(), config);
    if let Ok(experiment) = Experiment::new(config) {
        let _ = experiment.jobs();
    }
}

fn maze_corpus() -> Vec<String> {
    vec![
        "S.#\n..T\n".to_owned(),
        "; a comment\nS...\n.##.\n...T\n".to_owned(),
        eamadm::mazes::Preset::Task1.maze().to_text(),
    ]
}

fn load_maze(text: &str) {
    let Ok(maze) = Maze::parse(text) else {
        return;
    };
    assert_eq!(Maze::parse(&maze.to_text()).unwrap(), maze);
    let _ = maze.shortest_path_len();
    let mut env = MazeEnv::new(maze, TaskSpec::task1()).unwrap();
    env.reset(Some(1));
    for step in 0..8 {
        let outcome = env.step(step % env.n_actions());
        assert!(outcome.reward.is_finite());
        assert!(env.subtask_rewards().iter().all(|r| r.is_finite()));
        if outcome.done() {
            break;
        }
    }
}

fn scenario_corpus() -> Vec<String> {
    vec![Scenario::default_scenario().to_toml_string().unwrap()]
}

fn load_scenario(text: &str) {
    let Ok(scenario) = Scenario::from_toml_str(text) else {
        return;
    };
    // A small search budget keeps each case short; the search itself is what is exercised.
    let params = PlannerParams {
        max_expansions: 5_000,
        ..PlannerParams::default()
    };
    let _ = shortest_plan(&scenario, &params);
    let Ok(mut env) = WmrEnv::new(scenario) else {
        return;
    };
    env.reset(Some(3));
    for step in 0..5 {
        let outcome = env.step(step % env.n_actions());
        if outcome.done() {
            break;
        }
    }
}

proptest! {
    #![proptest_config(fuzz_config())]

    #[test]
    fn fuzz_mutated_configs_never_panic(text in mutated_text(config_corpus())) {
        load_config(&text);
    }

    #[test]
    fn fuzz_random_configs_never_panic(text in "[a-z_=\\[\\]{}\" .,0-9\n-]{0,200}") {
        load_config(&text);
    }

    #[test]
    fn fuzz_mutated_maze_maps_never_panic(text in mutated_text(maze_corpus())) {
        load_maze(&text);
    }

    #[test]
    fn fuzz_random_maze_maps_never_panic(text in "[.#ST;\r\n x]{0,120}") {
        load_maze(&text);
    }
}

proptest! {
    // The robot's loader runs its planner and a few physics steps per case: fewer cases.
    #![proptest_config(ProptestConfig { cases: fuzz_config().cases / 4, ..fuzz_config() })]

    #[test]
    fn fuzz_mutated_robot_scenarios_never_panic(text in mutated_text(scenario_corpus())) {
        load_scenario(&text);
    }
}
