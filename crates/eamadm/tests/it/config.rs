//! Experiment configs: the embedded TOML files equal the named constructors; unknown keys and
//! out-of-range values are rejected with messages naming them.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use eamadm::config::{
    AGGREGATION_CONTROL_TOML, PAPER_ROBOT_PAPER_STATE_TOML, PAPER_ROBOT_TOML, PAPER_TASK1_TOML,
    PAPER_TASK2_TOML,
};
use eamadm::{ConfigError, Experiment, ExperimentConfig};

/// The presets are their embedded TOML parsed (the TOML holds every value once); their methods
/// are those the method builders make, with the budgets the presets themselves state.
#[test]
fn presets_are_built_from_the_method_builders() {
    use eamadm::paper::{self, PaperTask};
    let texts = [
        (PaperTask::Task1, PAPER_TASK1_TOML),
        (PaperTask::Task2, PAPER_TASK2_TOML),
        (PaperTask::Robot, PAPER_ROBOT_TOML),
        (PaperTask::RobotPaperState, PAPER_ROBOT_PAPER_STATE_TOML),
        (PaperTask::AggregationControl, AGGREGATION_CONTROL_TOML),
    ];
    for (task, text) in texts {
        assert_eq!(
            task.config(),
            ExperimentConfig::from_toml_str(text).unwrap()
        );
    }
    let budget = |task: PaperTask| task.pretrain_budget().unwrap();
    assert_eq!(budget(PaperTask::Task1), 464_000);
    assert_eq!(budget(PaperTask::Task2), 896_000);
    assert_eq!(budget(PaperTask::Robot), 53_000);
    assert_eq!(budget(PaperTask::AggregationControl), 2_640_000);
    assert_eq!(PaperTask::RobotPaperState.pretrain_budget(), None);
    for task in [
        PaperTask::Task1,
        PaperTask::Task2,
        PaperTask::AggregationControl,
    ] {
        assert_eq!(
            task.config().methods,
            [paper::methods(), paper::controls(budget(task))].concat(),
            "{task:?}"
        );
    }
    assert_eq!(
        paper::robot().methods,
        [
            paper::methods(),
            paper::robot_repairs(),
            paper::robot_controls(budget(PaperTask::Robot)),
        ]
        .concat()
    );
    assert_eq!(
        paper::robot_paper_state().methods,
        [paper::methods(), paper::aggregators()].concat()
    );
}

#[test]
fn presets_round_trip_through_toml() {
    for config in [
        eamadm::paper::task1(),
        eamadm::paper::task2(),
        eamadm::paper::aggregation_control(),
    ] {
        let text = config.to_toml_string().unwrap();
        assert_eq!(
            ExperimentConfig::from_toml_str(&text).unwrap(),
            config,
            "{text}"
        );
    }
}

#[test]
fn presets_load() {
    for config in [
        eamadm::paper::task1(),
        eamadm::paper::task2(),
        eamadm::paper::aggregation_control(),
    ] {
        let experiment = Experiment::new(config).unwrap();
        // The paper's 4 methods, 4 ablations and 12 controls (the two aggregators among
        // them), `paper::seeds()` seeds each.
        assert_eq!(
            experiment.jobs().len(),
            (8 + 12) * eamadm::paper::seeds() as usize
        );
    }
}

/// Replaces the first occurrence of `from` in Task I's TOML by `to`.
fn edited(from: &str, to: &str) -> String {
    assert!(
        PAPER_TASK1_TOML.contains(from),
        "{from:?} not in the preset"
    );
    PAPER_TASK1_TOML.replacen(from, to, 1)
}

fn error_of(text: &str) -> String {
    match ExperimentConfig::from_toml_str(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(error) => error.to_string(),
    }
}

#[test]
fn unknown_keys_are_rejected_and_named() {
    let cases = [
        ("episodes = 200", "episodes = 200\nepisdoes = 3", "episdoes"),
        ("alpha = 0.1", "alpha = 0.1\nlambda = 0.9", "lambda"),
        (
            "init = { kind = \"zero\" }",
            "init = { kind = \"zero\", scale = 1 }",
            "scale",
        ),
        (
            "storage = { kind = \"table\" }",
            "storage = { kind = \"table\", size = 1 }",
            "size",
        ),
        (
            "weighting = { kind = \"uniform\" }",
            "weighting = { kind = \"uniform\", n = 1 }",
            "n",
        ),
        (
            "support = { kind = \"distance\" }",
            "support = { kind = \"distance\", range = 1 }",
            "range",
        ),
        (
            "preset = \"task1\"",
            "preset = \"task1\"\nsize = 30",
            "size",
        ),
        ("first = true", "first = true\nevery = 5", "every"),
        (
            "epsilon = { constant = 0.1 }",
            "epsilon = { constant = 0.1 }\ntemperature = { constant = 0.1 }",
            "temperature",
        ),
        (
            "epsilon = { exponential = { start = 0.95, factor = 0.95, floor = 0.0 } }",
            "epsilon = { exponential = { start = 0.95, factor = 0.95, floor = 0.0, min = 0.1 } }",
            "min",
        ),
        (
            "storage = { kind = \"tree\", state_threshold = 1.0, action_threshold = 1.0 }",
            "storage = { kind = \"tree\", state_threshold = 1.0, action_threshold = 1.0, depth = 3 }",
            "depth",
        ),
        (
            "support = { kind = \"paper\", epsilon = 1e-9 }",
            "support = { kind = \"paper\", eps = 1e-9 }",
            "eps",
        ),
        (
            "pretrain = { episodes = 200,",
            "pretrain = { episodes = 200, threads = 2,",
            "threads",
        ),
    ];
    for (from, to, key) in cases {
        let message = error_of(&edited(from, to));
        assert!(message.contains(key), "{key:?} not named in: {message}");
    }
}

/// One preset's TOML with the first occurrence of `from` replaced by `to`.
fn edited_preset(preset: &str, from: &str, to: &str) -> String {
    assert!(preset.contains(from), "{from:?} not in the preset");
    preset.replacen(from, to, 1)
}

/// Every family of bad values, each loaded from TOML and checked once
/// (`Experiment::from_toml_str`, i.e. `ExperimentConfig::check`): the error names exactly the
/// key the user wrote. The robot's overrides are blamed on their own keys, never on
/// `task.scenario` (issue 36 item 4).
#[test]
fn a_bad_value_is_blamed_on_the_key_the_user_wrote() {
    let task1 = |from: &str, to: &str| edited_preset(PAPER_TASK1_TOML, from, to);
    let robot = |from: &str, to: &str| edited_preset(PAPER_ROBOT_TOML, from, to);
    let cases = [
        // Counts and seeds.
        (task1("episodes = 200", "episodes = 0"), "episodes"),
        (task1("seeds = 20", "seeds = 0"), "seeds"),
        (
            task1("base_seed = 0", "base_seed = 18446744073709551615"),
            "base_seed",
        ),
        // The learner.
        (task1("alpha = 0.1", "alpha = 1.5"), "learner.alpha"),
        (task1("gamma = 0.95", "gamma = -0.1"), "learner.gamma"),
        (
            task1(
                "init = { kind = \"zero\" }",
                "init = { kind = \"uniform\", low = 1.0, high = 0.0 }",
            ),
            "learner.init.high",
        ),
        (
            task1("episodes = []", "episodes = [200]"),
            "trajectories.episodes[0]",
        ),
        // Methods: schedules, weighting, storage, pre-training, labels.
        (
            task1(
                "epsilon = { constant = 0.1 }",
                "epsilon = { constant = 1.1 }",
            ),
            "methods[1].epsilon",
        ),
        (
            task1(
                "temperature = { exponential = { start = 0.1, factor = 0.95, floor = 0.01 } }",
                "temperature = { exponential = { start = 0.1, factor = 1.95, floor = 0.01 } }",
            ),
            "methods[3].temperature.factor",
        ),
        (
            task1("state_threshold = 1.0", "state_threshold = 1.5"),
            "methods[0].storage.state_threshold",
        ),
        (
            task1("epsilon = 1e-9", "epsilon = -1.0"),
            "methods[0].weighting.support.epsilon",
        ),
        (
            task1("pretrain = { episodes = 200,", "pretrain = { episodes = 0,"),
            "methods[0].pretrain.episodes",
        ),
        (
            task1("label = \"softmax\"", "label = \"soft max\""),
            "methods[3].label",
        ),
        (
            task1("label = \"softmax\"", "label = \"ea-madm\""),
            "methods[3].label",
        ),
        // A method that does not fit the task.
        (task1("subtask = 1", "subtask = 7"), "methods[9].subtask"),
        // The maze's step cap: zero and too large, on its own key.
        (
            task1("preset = \"task1\"", "preset = \"task1\"\nstep_cap = 0"),
            "task.step_cap",
        ),
        (
            task1(
                "preset = \"task1\"",
                "preset = \"task1\"\nstep_cap = 4000000000",
            ),
            "task.step_cap",
        ),
        // The robot's overrides, each on its own key, not on `task.scenario`.
        (robot("step_cap = 250", "step_cap = 0"), "task.step_cap"),
        (
            robot("step_cap = 250", "step_cap = 200000"),
            "task.step_cap",
        ),
        (
            robot("control_period = 0.4", "control_period = -0.4"),
            "task.control_period",
        ),
        (
            robot("control_period = 0.4", "control_period = 60.0"),
            "task.control_period",
        ),
        (
            robot("reach_radius = 0.10", "reach_radius = 0.0"),
            "task.reach_radius",
        ),
        // So large that the robot starts within reach: a layout error, still the override's.
        (
            robot("reach_radius = 0.10", "reach_radius = 5.0"),
            "task.reach_radius",
        ),
        (
            robot("distance_bins = 30", "distance_bins = 0"),
            "task.distance_bins",
        ),
        // Too many states in all: blamed on the bins the config set.
        (
            robot(
                "distance_bins = 30",
                "distance_bins = 1000\ntarget_bins = 1000",
            ),
            "task.distance_bins",
        ),
        (
            robot(
                "distance_bins = 30",
                "distance_bins = 30\ntarget_bins = 5000",
            ),
            "task.target_bins",
        ),
    ];
    for (text, key) in &cases {
        let Err(error) = Experiment::from_toml_str(text) else {
            panic!("accepted a bad value for {key}");
        };
        assert_eq!(error.field(), Some(*key), "{error}");
        assert!(error.to_string().contains(&format!("`{key}`")), "{error}");
    }
}

/// A bad value in a scenario file is blamed on `task.scenario.<its field>`; a value the config
/// overrides is the override's, even where the file's own was fine.
#[test]
fn a_bad_value_in_a_scenario_file_is_blamed_under_task_scenario() {
    let scenario = eamadm::wmr_model::DEFAULT_SCENARIO_TOML.replacen(
        "[arena]",
        "[sensors]\nnoise = 2.0\n\n[arena]",
        1,
    );
    let path = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("blamed-scenario.toml");
    std::fs::write(&path, scenario).unwrap();
    let text = edited_preset(
        PAPER_ROBOT_TOML,
        "scenario = \"default\"",
        &format!("scenario = {:?}", path.display().to_string()),
    );
    let error = Experiment::from_toml_str(&text).unwrap_err();
    assert_eq!(
        error.field(),
        Some("task.scenario.sensors.noise"),
        "{error}"
    );
    let capped = text.replacen("step_cap = 250", "step_cap = 0", 1);
    let error = Experiment::from_toml_str(&capped).unwrap_err();
    assert_eq!(error.field(), Some("task.step_cap"), "{error}");
}

#[test]
fn the_pretraining_schedule_is_checked_under_its_own_path() {
    let mut config = eamadm::paper::task1();
    let eamadm::Method::EaMadm(ea) = &mut config.methods[0].method else {
        panic!("methods[0] is EA-MADM");
    };
    ea.pretrain.epsilon = dql::Schedule::Exponential {
        start: 0.5,
        factor: 0.9,
        floor: 0.6,
    };
    let error = config.validate().unwrap_err();
    assert_eq!(error.field(), Some("methods[0].pretrain.epsilon.floor"));
}

/// The stopping rule's parameters are checked under their own path: a check interval and a
/// window of at least 1, a cap no smaller than the fewest episodes.
#[test]
fn the_stopping_rule_is_checked_under_its_own_path() {
    let rule = "until = { every = 10, stable = 3, max_episodes = 1000 }";
    for (bad, field, value) in [
        (
            "until = { every = 0, stable = 3, max_episodes = 1000 }",
            "methods[0].pretrain.until.every",
            "0",
        ),
        (
            "until = { every = 10, stable = 0, max_episodes = 1000 }",
            "methods[0].pretrain.until.stable",
            "0",
        ),
        (
            "until = { every = 10, stable = 3, max_episodes = 150 }",
            "methods[0].pretrain.until.max_episodes",
            "150",
        ),
    ] {
        let error = ExperimentConfig::from_toml_str(&edited(rule, bad)).unwrap_err();
        assert_eq!(error.field(), Some(field), "{error}");
        assert!(error.to_string().contains(value), "{error}");
    }
    // An unknown key of the rule is named too.
    let message = error_of(&edited(
        rule,
        "until = { every = 10, stable = 3, max_episodes = 1000, patience = 2 }",
    ));
    assert!(message.contains("patience"), "{message}");
}

#[test]
fn type_errors_and_syntax_errors_name_the_line() {
    let message = error_of(&edited("episodes = 200", "episodes = \"many\""));
    assert!(message.contains("episodes"), "{message}");
    assert!(message.contains("line"), "{message}");
}

#[test]
fn files_named_by_the_task_are_read_when_loading() {
    let text = PAPER_TASK1_TOML.replacen(
        "kind = \"maze\"\npreset = \"task1\"",
        "kind = \"maze_file\"\npath = \"/nonexistent/eamadm/test.map\"\nrewards = \"task1\"",
        1,
    );
    let config = ExperimentConfig::from_toml_str(&text).unwrap();
    let error = Experiment::new(config).unwrap_err();
    assert!(matches!(error, ConfigError::Read { .. }), "{error}");
    assert_eq!(error.field(), Some("task.path"));

    let text = PAPER_TASK1_TOML.replacen(
        "kind = \"maze\"\npreset = \"task1\"",
        "kind = \"maze_text\"\nmap = \"S.#\\n.X.\\n..T\\n\"\nrewards = \"task1\"",
        1,
    );
    let config = ExperimentConfig::from_toml_str(&text).unwrap();
    let error = Experiment::new(config).unwrap_err();
    assert_eq!(error.field(), Some("task.map"), "{error}");
}
