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

#[test]
fn embedded_toml_files_are_the_named_constructors() {
    assert_eq!(
        ExperimentConfig::from_toml_str(PAPER_TASK1_TOML).unwrap(),
        eamadm::paper::task1()
    );
    assert_eq!(
        ExperimentConfig::from_toml_str(PAPER_TASK2_TOML).unwrap(),
        eamadm::paper::task2()
    );
    assert_eq!(
        ExperimentConfig::from_toml_str(PAPER_ROBOT_TOML).unwrap(),
        eamadm::paper::robot()
    );
    assert_eq!(
        ExperimentConfig::from_toml_str(PAPER_ROBOT_PAPER_STATE_TOML).unwrap(),
        eamadm::paper::robot_paper_state()
    );
    assert_eq!(
        ExperimentConfig::from_toml_str(AGGREGATION_CONTROL_TOML).unwrap(),
        eamadm::paper::aggregation_control()
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
        // them), `paper::SEEDS` seeds each.
        assert_eq!(
            experiment.jobs().len(),
            (8 + 12) * eamadm::paper::SEEDS as usize
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

#[test]
fn out_of_range_values_are_rejected_with_their_path() {
    let cases = [
        ("episodes = 200", "episodes = 0", "`episodes`"),
        ("seeds = 20", "seeds = 0", "`seeds`"),
        ("alpha = 0.1", "alpha = 1.5", "`learner.alpha`"),
        ("gamma = 0.95", "gamma = -0.1", "`learner.gamma`"),
        (
            "init = { kind = \"zero\" }",
            "init = { kind = \"uniform\", low = 1.0, high = 0.0 }",
            "`learner.init.high`",
        ),
        (
            "episodes = []",
            "episodes = [200]",
            "`trajectories.episodes[0]`",
        ),
        (
            "epsilon = { constant = 0.1 }",
            "epsilon = { constant = 1.1 }",
            "`methods[1].epsilon`",
        ),
        (
            "temperature = { exponential = { start = 0.1, factor = 0.95, floor = 0.01 } }",
            "temperature = { exponential = { start = 0.1, factor = 1.95, floor = 0.01 } }",
            "`methods[3].temperature.factor`",
        ),
        (
            "state_threshold = 1.0",
            "state_threshold = 1.5",
            "`methods[0].storage.state_threshold`",
        ),
        (
            "epsilon = 1e-9",
            "epsilon = -1.0",
            "`methods[0].weighting.support.epsilon`",
        ),
        (
            "pretrain = { episodes = 200,",
            "pretrain = { episodes = 0,",
            "`methods[0].pretrain.episodes`",
        ),
        (
            "label = \"softmax\"",
            "label = \"soft max\"",
            "`methods[3].label`",
        ),
        (
            "label = \"softmax\"",
            "label = \"ea-madm\"",
            "`methods[3].label`",
        ),
        (
            "preset = \"task1\"",
            "preset = \"task1\"\nstep_cap = 0",
            "`task.step_cap`",
        ),
    ];
    for (from, to, field) in cases {
        let message = error_of(&edited(from, to));
        assert!(message.contains(field), "{field} not named in: {message}");
    }
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
