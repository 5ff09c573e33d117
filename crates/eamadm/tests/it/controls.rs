//! The controls the paper does not run: each changes what it claims to change. A sub-task
//! alone acts on that sub-task's values, budget-matched competitors spend their budget before
//! their recorded episodes, reward-matched ones learn from another signal, thresholds below 1
//! aggregate; agreement and action counts add up; records round-trip and stay bit-identical at
//! 1 and 2 threads.

use eamadm::paper::controls;
use eamadm::{
    CompetitorSignal, Convergence, Experiment, ExperimentConfig, Method, MethodSpec, Role,
    RunRecord, Storage,
};

use crate::common::{only, small_config};

const EPISODES: u64 = 30;

/// The small maze with EA-MADM, the competitors and every control (pre-training at least as
/// long as training, with a bounded stopping rule), `budget` warm-up steps for the
/// budget-matched ones.
fn config_with_controls(seeds: u32, budget: u64) -> ExperimentConfig {
    let mut config = small_config(EPISODES, seeds);
    config.methods.extend(controls(budget));
    for spec in &mut config.methods {
        let pretrain = match &mut spec.method {
            Method::EaMadm(ea) => &mut ea.pretrain,
            Method::SubtaskGreedy(alone) => &mut alone.pretrain,
            _ => continue,
        };
        pretrain.episodes = EPISODES;
        // the presets' stopping rule, bounded for a test: a check every 5 episodes, at most
        // twice as many
        pretrain.until = Some(Convergence {
            every: 5,
            stable: 3,
            max_episodes: 2 * EPISODES,
        });
    }
    config
}

fn run(config: &ExperimentConfig, label: &str, seed: u64) -> RunRecord {
    let experiment = Experiment::new(config.clone()).unwrap();
    experiment.run(config.method(label).unwrap(), seed).unwrap()
}

#[test]
fn the_controls_are_marked_as_controls() {
    let labels: Vec<(String, Role)> = controls(1)
        .into_iter()
        .map(|spec| (spec.label, spec.role))
        .collect();
    assert_eq!(labels.len(), 12);
    assert!(labels.iter().all(|(_, role)| *role == Role::Control));
    for config in [
        eamadm::paper::task1(),
        eamadm::paper::task2(),
        eamadm::paper::aggregation_control(),
    ] {
        let n = config
            .methods
            .iter()
            .filter(|spec| spec.role == Role::Control)
            .count();
        assert_eq!(n, 12, "{}", config.name);
    }
}

#[test]
fn action_and_agreement_counts_add_up() {
    let config = config_with_controls(2, 500);
    for record in Experiment::new(config.clone()).unwrap().run_all().unwrap() {
        let window = usize::try_from(record.final_window_episodes).unwrap();
        let window_steps: u64 = record.episodes[record.episodes.len() - window..]
            .iter()
            .map(|e| e.steps)
            .sum();
        assert_eq!(
            record.final_window_actions.iter().sum::<u64>(),
            window_steps,
            "{}",
            record.method
        );
        assert_eq!(record.final_window_actions.len(), 4);
        let is_ea_madm = matches!(
            config.method(&record.method).unwrap().method,
            Method::EaMadm(_)
        );
        assert_eq!(record.agreement.is_some(), is_ea_madm, "{}", record.method);
        if let Some(agreement) = &record.agreement {
            for counts in [&agreement.final_window, &agreement.training] {
                assert_eq!(counts.agrees.len(), 2);
                let least = counts.agrees.iter().copied().min().unwrap();
                assert!(counts.agrees.iter().all(|a| *a <= counts.decisions));
                assert!(counts.agrees_with_all <= least);
                assert!(counts.missing_experience <= counts.decisions);
            }
            // Exploitation steps of the window are some of its steps; the window is part of
            // training.
            let (window, all) = (&agreement.final_window, &agreement.training);
            assert!(window.decisions <= window_steps);
            assert!(window.decisions <= all.decisions);
            for (w, a) in window.agrees.iter().zip(&all.agrees) {
                assert!(w <= a);
            }
            // Late in training ε is small: most steps are decisions.
            assert!(all.decisions > 0);
        }
    }
}

#[test]
fn a_subtask_alone_acts_on_that_subtasks_values() {
    let config = config_with_controls(1, 0);
    let seed = 100;
    let ea_madm = run(&config, "ea-madm", seed);
    for k in 0..2 {
        let alone = run(&config, &format!("subtask{k}-alone"), seed);
        // The same pre-training as inside EA-MADM: the same sub-task record.
        assert_eq!(alone.subtasks.len(), 1);
        let (mine, theirs) = (&alone.subtasks[0], &ea_madm.subtasks[k]);
        assert_eq!(mine.env_steps, theirs.env_steps);
        assert_eq!(mine.visited_pairs, theirs.visited_pairs);
        assert_eq!(mine.greedy_alone, theirs.greedy_alone);
        assert_eq!(alone.pretrain_env_steps, mine.env_steps);
        // Frozen values: its greedy evaluation is the sub-task's greedy episode alone.
        let greedy = mine.greedy_alone.as_ref().unwrap();
        assert_eq!(alone.evaluation.steps, greedy.steps);
        assert_eq!(alone.evaluation.task_return, greedy.task_return);
        assert_eq!(alone.evaluation.reached, greedy.reached);
        assert_eq!(greedy.env_steps, greedy.steps);
    }
    // Each EA-MADM sub-task has its own greedy episode.
    assert!(ea_madm.subtasks.iter().all(|s| s.greedy_alone.is_some()));
}

#[test]
fn a_subtask_index_the_task_lacks_is_refused_naming_the_field() {
    let mut config = config_with_controls(1, 0);
    if let Method::SubtaskGreedy(alone) = &mut config
        .methods
        .iter_mut()
        .find(|s| s.label == "subtask1-alone")
        .unwrap()
        .method
    {
        alone.subtask = 2;
    }
    let error = Experiment::new(config).unwrap_err();
    assert!(error.field().unwrap().ends_with(".subtask"), "{error}");
    assert!(
        error.to_string().contains("below the task's 2 sub-tasks"),
        "{error}"
    );
}

#[test]
fn budget_matched_competitors_spend_the_budget_first() {
    let seed = 101;
    let probe = config_with_controls(1, 0);
    let budget = run(&probe, "ea-madm", seed).pretrain_env_steps;
    let config = config_with_controls(1, budget);
    for label in ["epsilon-greedy", "epsilon-decreasing", "softmax"] {
        let plain = run(&config, label, seed);
        let matched = run(&config, &format!("{label}-budget"), seed);
        assert_eq!(plain.pretrain_env_steps, 0);
        assert_eq!(matched.pretrain_env_steps, budget, "{label}");
        let trained: u64 = matched.episodes.iter().map(|e| e.steps).sum();
        assert_eq!(matched.total_env_steps, budget + trained);
        assert_eq!(
            matched.episodes[0].env_steps,
            budget + matched.episodes[0].steps
        );
        // The warm-up taught it something: its first recorded episode differs.
        assert_ne!(plain.episodes, matched.episodes, "{label}");
    }
}

#[test]
fn a_warmup_beyond_the_limit_is_refused_naming_the_field() {
    let text = eamadm::PAPER_TASK1_TOML.replacen(
        "warmup_env_steps = 464000",
        "warmup_env_steps = 1000000000000",
        1,
    );
    let error = ExperimentConfig::from_toml_str(&text).unwrap_err();
    assert_eq!(
        error.field(),
        Some("methods[10].warmup_env_steps"),
        "{error}"
    );
}

#[test]
fn reward_matched_competitors_learn_from_another_signal() {
    let seed = 102;
    let mut config = config_with_controls(1, 0);
    let mut summed = config.method("softmax-shaped").unwrap().clone();
    summed.label = "softmax-summed".to_owned();
    if let Method::Softmax { training, .. } = &mut summed.method {
        training.signal = CompetitorSignal::SubtaskSum;
    }
    config.methods.push(summed);
    for label in ["epsilon-greedy", "epsilon-decreasing", "softmax"] {
        let plain = run(&config, label, seed);
        let shaped = run(&config, &format!("{label}-shaped"), seed);
        for episode in &plain.episodes {
            assert_eq!(episode.learning_return, episode.task_return);
        }
        assert!(
            shaped
                .episodes
                .iter()
                .any(|e| e.learning_return != e.task_return),
            "{label}"
        );
        assert_ne!(plain.episodes, shaped.episodes, "{label}");
    }
    let summed = run(&config, "softmax-summed", seed);
    let shaped = run(&config, "softmax-shaped", seed);
    assert_ne!(summed.episodes, shaped.episodes);
}

#[test]
fn thresholds_below_one_aggregate_and_one_is_the_table() {
    let mut config = config_with_controls(1, 0);
    let table = config.method("ea-madm-table").unwrap().clone();
    config.methods.push(MethodSpec {
        label: "ea-madm-tau1".to_owned(),
        method: match table.method {
            Method::EaMadm(mut ea) => {
                ea.storage = Storage::default();
                Method::EaMadm(ea)
            }
            other => other,
        },
        ..table
    });
    let seed = 103;
    let exact = run(&config, "ea-madm-tau1", seed);
    let table = run(&config, "ea-madm-table", seed);
    let coarse = run(&config, "ea-madm-tau0.33", seed);
    for (k, subtask) in exact.subtasks.iter().enumerate() {
        // τ = 1: one cluster per visited pair, answering like the table.
        assert_eq!(subtask.clusters, Some(subtask.visited_pairs));
        assert_eq!(subtask.tree_samples, Some(subtask.visited_pairs));
        assert!(subtask.tree_bytes.unwrap() > 0);
        assert_eq!(table.subtasks[k].clusters, None);
        assert_eq!(table.subtasks[k].tree_bytes, None);
        assert_eq!(subtask.answered_pairs, table.subtasks[k].answered_pairs);
        // τ = 0.33: the same samples in fewer clusters, answering more pairs.
        let merged = &coarse.subtasks[k];
        assert_eq!(merged.tree_samples, subtask.tree_samples);
        assert!(merged.clusters.unwrap() < subtask.clusters.unwrap());
        assert!(merged.answered_pairs >= subtask.answered_pairs);
    }
    assert_eq!(exact.episodes, table.episodes);
    assert_eq!(exact.agreement, table.agreement);
    assert_eq!(exact.evaluation, table.evaluation);
    assert_ne!(exact.episodes, coarse.episodes);
}

fn records_on_threads(config: &ExperimentConfig, threads: usize) -> Vec<RunRecord> {
    let experiment = Experiment::new(config.clone()).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| experiment.run_all().unwrap())
}

#[test]
fn controls_are_bit_identical_at_one_and_two_threads_and_round_trip() {
    let config = only(
        config_with_controls(2, 300),
        &[
            "ea-madm",
            "subtask0-alone",
            "softmax-budget",
            "epsilon-decreasing-shaped",
            "ea-madm-tau0.33",
        ],
    );
    let one = records_on_threads(&config, 1);
    let two = records_on_threads(&config, 2);
    let json = serde_json::to_string(&one).unwrap();
    assert_eq!(json, serde_json::to_string(&two).unwrap());
    let back: Vec<RunRecord> = serde_json::from_str(&json).unwrap();
    assert_eq!(back, one);
}
