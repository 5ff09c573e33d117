//! The oracle (`eamadm::oracle`): EA-MADM's decision and the plain aggregators fed exact
//! sub-task values on the mazes, converged ones on the robot.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use eamadm::oracle::{OracleValues, OwnValues, oracle_rows, oracle_rows_of};
use eamadm::{Experiment, ExperimentConfig, Method, NoPretrainingCache, paper};

/// `config` cut to one seed, a few episodes and a short, bounded pre-training.
fn short(mut config: ExperimentConfig, episodes: u64) -> ExperimentConfig {
    config.seeds = 1;
    config.episodes = episodes;
    config.trajectories.episodes.clear();
    for spec in &mut config.methods {
        let pretrain = match &mut spec.method {
            Method::EaMadm(ea) => &mut ea.pretrain,
            Method::SubtaskGreedy(alone) => &mut alone.pretrain,
            _ => continue,
        };
        pretrain.episodes = episodes;
        if let Some(until) = pretrain.until.as_mut() {
            until.every = episodes;
            until.max_episodes = 2 * episodes;
        }
    }
    config
}

/// paper-notes §21.1: with exact sub-task values and the source task's initial (zero) values,
/// EA-MADM's decision and the mean of standardised columns are the reach sub-task's own greedy
/// choice in every state, so their rows equal `subtask0-alone`'s; on the control that choice is
/// trapped, on Task I it is optimal.
#[test]
fn with_exact_values_the_decision_is_the_reach_subtasks_own() {
    for (config, reaches) in [
        (paper::task1(), true),
        (paper::aggregation_control(), false),
    ] {
        let experiment = Experiment::new(short(config, 5)).unwrap();
        let rows = oracle_rows(&experiment, &NoPretrainingCache).unwrap();
        // 3 decisions × (initial, learned) + 2 sub-tasks alone, one seed.
        assert_eq!(rows.len(), 3 * 2 + 2);
        let alone = rows
            .iter()
            .find(|r| r.decision == "subtask0-alone")
            .unwrap();
        assert_eq!(alone.own_values, OwnValues::None);
        assert_eq!(alone.reached, reaches, "{}", experiment.config().name);
        for decision in ["ea-madm", "subtasks-mean"] {
            let row = rows
                .iter()
                .find(|r| r.decision == decision && r.own_values == OwnValues::Initial)
                .unwrap();
            assert_eq!(row.values, OracleValues::Exact);
            assert_eq!(
                (row.reached, row.greedy_steps, row.optimal_share),
                (alone.reached, alone.greedy_steps, alone.optimal_share),
                "{decision} on {}",
                experiment.config().name
            );
        }
        for row in &rows {
            let share = row.optimal_share.unwrap();
            assert!((0.0..=1.0).contains(&share), "{row:?}");
            assert_eq!(row.optimum_steps, experiment.task().optimum_steps());
            assert!(row.greedy_steps <= u64::from(row.step_cap));
        }
        if reaches {
            // Task I is at the Manhattan bound and the exact reach sub-task walks it.
            assert_eq!(alone.optimum_steps, alone.manhattan_steps);
            assert_eq!(Some(alone.greedy_steps), alone.optimum_steps);
            assert_eq!(alone.optimal_share, Some(1.0));
        } else {
            assert_eq!(alone.optimum_steps, Some(64));
            assert_eq!(alone.manhattan_steps, Some(24));
            assert_eq!(alone.greedy_steps, u64::from(alone.step_cap));
        }
    }
}

/// On the robot the sub-task values are pre-trained ones, named so, and no optimal share exists.
#[test]
fn on_the_robot_the_values_are_pretrained_and_named_so() {
    let mut config = short(paper::robot(), 3);
    config.methods.retain(|spec| {
        ["ea-madm", "subtasks-mean", "epsilon-greedy"].contains(&spec.label.as_str())
    });
    let experiment = Experiment::new(config).unwrap();
    let rows = oracle_rows(&experiment, &NoPretrainingCache).unwrap();
    assert_eq!(rows.len(), 2 * 2 + 3);
    assert!(
        rows.iter()
            .all(|r| r.values == OracleValues::PretrainedToConvergence)
    );
    assert!(
        rows.iter()
            .all(|r| r.optimal_share.is_none() && r.manhattan_steps.is_none())
    );
    // The learned row replays the run's own evaluation: the same greedy episode.
    let record = experiment
        .run(experiment.config().method("ea-madm").unwrap(), 0)
        .unwrap();
    let learned = rows
        .iter()
        .find(|r| r.decision == "ea-madm" && r.own_values == OwnValues::Learned)
        .unwrap();
    assert_eq!(learned.greedy_steps, record.evaluation.steps);
    assert_eq!(learned.reached, record.evaluation.reached);
    assert_eq!(learned.task_return, record.evaluation.task_return);
}

/// An experiment without any of the decisions has no oracle rows.
#[test]
fn no_decision_no_rows() {
    let mut config = short(paper::task1(), 3);
    config.methods.retain(|spec| spec.label == "softmax");
    let experiment = Experiment::new(config).unwrap();
    assert!(
        oracle_rows(&experiment, &NoPretrainingCache)
            .unwrap()
            .is_empty()
    );
}

/// A plan that runs only some methods (`reproduce-paper --method`) has the oracle rows of the
/// decisions it runs and no others: each decision's rows repeat its run once per seed, so the
/// others would cost as much as running them (paper-notes §24.2). The rows it keeps are the
/// ones the whole experiment's oracle gives.
#[test]
fn the_oracle_of_a_narrower_plan_has_only_the_decisions_it_runs() {
    let experiment = Experiment::new(short(paper::task1(), 5)).unwrap();
    let all = oracle_rows(&experiment, &NoPretrainingCache).unwrap();
    let none = oracle_rows_of(&experiment, &NoPretrainingCache, |label| {
        label == "epsilon-greedy"
    })
    .unwrap();
    assert!(none.is_empty(), "{none:?}");
    let ea_madm =
        oracle_rows_of(&experiment, &NoPretrainingCache, |label| label == "ea-madm").unwrap();
    // EA-MADM's (initial, learned) and the two sub-tasks alone, one seed.
    assert_eq!(ea_madm.len(), 2 + 2);
    for row in &ea_madm {
        assert!(all.contains(row), "{row:?}");
        assert!(row.decision == "ea-madm" || row.decision.ends_with("-alone"));
    }
}
