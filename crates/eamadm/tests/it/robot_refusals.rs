//! Robot experiments that cannot be solved or held in memory are refused when the config is
//! loaded, with a typed error naming the field (issue 12, item 5; issue 14, item 2), and the
//! robot presets load: `robot` with the target feature, `robot-paper-state` without.

use std::path::PathBuf;

use eamadm::wmr_model::{DEFAULT_SCENARIO_TOML, PlanError, ScenarioError};
use eamadm::{ConfigError, Experiment, ExperimentConfig, TaskConfig};

/// Writes `scenario` to a file of its own under Cargo's temporary folder for tests.
fn scenario_file(name: &str, scenario: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("refusal-{name}.toml"));
    std::fs::write(&path, scenario).expect("the test folder is writable");
    path
}

fn robot_config(
    scenario: String,
    step_cap: Option<u32>,
    target_bins: Option<u32>,
) -> ExperimentConfig {
    let mut config = eamadm::paper::robot();
    config.task = TaskConfig::Robot {
        scenario,
        step_cap,
        target_bins,
        control_period: None,
        reach_radius: None,
        distance_bins: None,
    };
    config
}

/// Why a robot config is refused (it must be).
fn refusal(config: ExperimentConfig) -> ConfigError {
    match Experiment::new(config) {
        Err(error) => error,
        Ok(_) => panic!("the config must be refused"),
    }
}

/// The key a refusal blames, as the user wrote it.
fn key_of(error: &ConfigError) -> &str {
    error
        .field()
        .unwrap_or_else(|| panic!("no key named: {error}"))
}

#[test]
fn the_robot_presets_load_with_and_without_the_target_feature() {
    let robot = Experiment::new(eamadm::paper::robot()).expect("valid");
    // N_D · N_T · (N_O · N_A + 1) with the presets' 30 distance bins (docs/paper-notes.md §8.5)
    assert_eq!(robot.task().n_states(), 30 * 7 * 25);
    assert_eq!(robot.task().optimum_steps(), Some(17)); // 0.4 s steps, 10 cm reach radius
    let paper = Experiment::new(eamadm::paper::robot_paper_state()).expect("valid");
    assert_eq!(paper.task().n_states(), 30 * 25);
    assert_eq!(paper.config().name, "robot-paper-state");
}

#[test]
fn a_walled_off_target_is_refused_at_load_time() {
    // A wall across the whole arena just before the target.
    let walled = format!(
        "{DEFAULT_SCENARIO_TOML}\n[[obstacles]]\nshape = \"rectangle\"\nx = 0.82\ny = 0.5\n\
         width = 0.02\nheight = 1.0\n"
    );
    let path = scenario_file("walled", &walled);
    let refused = refusal(robot_config(path.display().to_string(), None, None));
    assert_eq!(key_of(&refused), "task.scenario.target", "{refused}");
    let ConfigError::Scenario { source: error, .. } = refused else {
        panic!("expected a scenario error, got {refused}");
    };
    assert!(
        matches!(
            error,
            ScenarioError::TargetUnreachable {
                reason: PlanError::NoRoute { .. },
                ..
            }
        ),
        "{error}"
    );
    assert!(error.to_string().starts_with("`target`"), "{error}");
}

#[test]
fn overrides_that_cannot_be_held_in_memory_are_refused() {
    // Used to abort allocating a 64 GB episode buffer; blamed on the key the user wrote.
    let error = refusal(robot_config("default".to_owned(), Some(u32::MAX), None));
    assert_eq!(key_of(&error), "task.step_cap", "{error}");
    // Used to abort allocating the state table (here through the target feature).
    let error = refusal(robot_config(
        "default".to_owned(),
        None,
        Some(2_147_483_647),
    ));
    assert_eq!(key_of(&error), "task.target_bins", "{error}");
}

#[test]
fn scenario_files_with_oversized_numbers_are_refused() {
    for (name, edit, field) in [
        ("arena", ("width = 1.0", "width = 1e17"), "arena.width"),
        (
            "bins",
            ("[arena]", "[state]\ndistance_bins = 2147483647\n\n[arena]"),
            "state.distance_bins",
        ),
        (
            "noise",
            ("[arena]", "[sensors]\nnoise = 1e308\n\n[arena]"),
            "sensors.noise",
        ),
        (
            "goal",
            ("[arena]", "[reward]\ngoal_bonus = 1e308\n\n[arena]"),
            "reward.goal_bonus",
        ),
    ] {
        let text = DEFAULT_SCENARIO_TOML.replacen(edit.0, edit.1, 1);
        assert_ne!(text, DEFAULT_SCENARIO_TOML, "{name}: the edit applies");
        let path = scenario_file(name, &text);
        let error = refusal(robot_config(path.display().to_string(), None, None));
        assert_eq!(
            key_of(&error),
            format!("task.scenario.{field}"),
            "{name}: {error}"
        );
    }
}

#[test]
fn sub_task_reward_repairs_are_refused_off_the_robot() {
    let mut config = eamadm::paper::task1();
    let repaired = eamadm::paper::robot_repairs()
        .into_iter()
        .find(|spec| spec.label == "ea-madm-goal-bonus")
        .expect("a repaired method");
    config.methods = vec![repaired];
    match Experiment::new(config) {
        Err(ConfigError::Invalid { field, .. }) => {
            assert_eq!(field, "methods[0].subtask_rewards");
        }
        Err(other) => panic!("expected an invalid field, got {other}"),
        Ok(_) => panic!("repairs of the robot's rewards must be refused on a maze"),
    }
}

#[test]
fn a_repaired_method_runs_on_the_robot_with_its_own_rewards() {
    let mut config = eamadm::paper::robot();
    config.episodes = 3;
    config.seeds = 1;
    let shorten = |mut spec: eamadm::MethodSpec| {
        if let eamadm::Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = 10;
        }
        spec
    };
    let paper = shorten(config.methods[0].clone());
    assert_eq!(paper.label, "ea-madm");
    let repaired = shorten(
        eamadm::paper::robot_repairs()
            .into_iter()
            .find(|spec| spec.label == "ea-madm-end-penalties")
            .expect("the end-penalty repair"),
    );
    config.methods = vec![paper.clone(), repaired.clone()];
    let experiment = Experiment::new(config).expect("valid");
    let literal = experiment.run(&paper, 0).expect("runs");
    let ended = experiment.run(&repaired, 0).expect("runs");
    assert_eq!(literal.episodes.len(), 3);
    // The source task learns from the standardised sub-task rewards: where an episode ends by
    // losing the target, every sub-task pays −10 under the repair (a zero-spread step, then)
    // and only Eq. 8 does without it, so the learning returns differ.
    let returns = |record: &eamadm::RunRecord| -> Vec<f64> {
        record.episodes.iter().map(|e| e.learning_return).collect()
    };
    assert_ne!(
        returns(&literal),
        returns(&ended),
        "the repair changes the learning signal"
    );
}
