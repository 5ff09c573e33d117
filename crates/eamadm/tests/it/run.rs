//! End-to-end runs on a small maze: EA-MADM learns a near-optimal route, runs are
//! deterministic whatever the thread count, periodic greedy evaluations leave training
//! untouched, the literal standardisation is a zero learning
//! signal, and a short run's curve is pinned.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use crate::common;

use common::{only, small_config};
use eamadm::{Experiment, RunRecord};

#[test]
fn ea_madm_greedy_route_is_near_the_bfs_optimum_for_most_seeds() {
    let config = only(small_config(60, 8), &["ea-madm"]);
    let experiment = Experiment::new(config).unwrap();
    let optimum = experiment.task().optimum_steps().unwrap();
    let records = experiment.run_all().unwrap();
    let near: Vec<bool> = records
        .iter()
        .map(|r| r.evaluation.reached && r.evaluation.steps <= optimum + 4)
        .collect();
    let steps: Vec<u64> = records.iter().map(|r| r.evaluation.steps).collect();
    assert!(
        near.iter().filter(|n| **n).count() >= 6,
        "optimum {optimum}, greedy steps {steps:?}"
    );
    for record in &records {
        assert_eq!(record.evaluation.collisions, 0, "seed {}", record.seed);
    }
}

fn records_on_threads(threads: usize) -> Vec<RunRecord> {
    let config = only(
        small_config(25, 2),
        &["ea-madm", "epsilon-greedy", "softmax", "ea-madm-uniform"],
    );
    let experiment = Experiment::new(config).unwrap();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| experiment.run_all().unwrap())
}

#[test]
fn results_are_bit_identical_with_one_and_two_threads() {
    let one = records_on_threads(1);
    let two = records_on_threads(2);
    assert_eq!(one.len(), 8);
    // JSON with exact float formatting compares every bit of every float, and the order.
    let json = |records: &[RunRecord]| serde_json::to_string(records).unwrap();
    assert_eq!(json(&one), json(&two));
    assert_eq!(one, two);
    // And a run on its own equals the same run inside `run_all`.
    let experiment = Experiment::new(only(
        small_config(25, 2),
        &["ea-madm", "epsilon-greedy", "softmax", "ea-madm-uniform"],
    ))
    .unwrap();
    let (method, seed) = experiment.jobs()[1];
    assert_eq!(experiment.run(method, seed).unwrap(), one[1]);
}

#[test]
fn literal_standardisation_is_a_zero_learning_signal_and_running_is_not() {
    let config = only(small_config(20, 2), &["ea-madm-literal", "ea-madm"]);
    let records = Experiment::new(config).unwrap().run_all().unwrap();
    for record in records.iter().filter(|r| r.method == "ea-madm-literal") {
        for episode in &record.episodes {
            assert_eq!(episode.learning_return, 0.0, "{episode:?}");
        }
    }
    for record in records.iter().filter(|r| r.method == "ea-madm") {
        assert!(
            record.episodes.iter().any(|e| e.learning_return != 0.0),
            "running standardisation gave a zero signal in every episode"
        );
    }
}

#[test]
fn an_exact_tree_answers_like_the_sub_task_tables() {
    // At τ = 1 the tree is a table of the visited pairs: the storage ablation changes nothing.
    let config = only(small_config(20, 2), &["ea-madm", "ea-madm-table"]);
    let records = Experiment::new(config).unwrap().run_all().unwrap();
    let (tree, table) = records.split_at(2);
    for (tree, table) in tree.iter().zip(table) {
        assert_eq!(tree.episodes, table.episodes);
        assert_eq!(tree.evaluation, table.evaluation);
        assert!(
            tree.subtasks
                .iter()
                .all(|s| s.clusters == Some(s.visited_pairs))
        );
        assert!(table.subtasks.iter().all(|s| s.clusters.is_none()));
    }
}

#[test]
fn env_steps_count_pre_training_and_every_episode() {
    let config = only(small_config(10, 1), &["ea-madm", "epsilon-greedy"]);
    let records = Experiment::new(config).unwrap().run_all().unwrap();
    for record in &records {
        let pretrain: u64 = record.subtasks.iter().map(|s| s.env_steps).sum();
        assert_eq!(record.pretrain_env_steps, pretrain);
        let mut expected = pretrain;
        for episode in &record.episodes {
            expected += episode.steps;
            assert_eq!(episode.env_steps, expected);
        }
        assert_eq!(record.total_env_steps, expected);
        assert_eq!(record.evaluation.env_steps, expected);
    }
    assert!(records[0].pretrain_env_steps > 0);
    assert_eq!(records[1].pretrain_env_steps, 0);
    assert!(records[1].subtasks.is_empty());
}

#[test]
fn kept_trajectories_are_consistent() {
    let config = only(small_config(10, 1), &["ea-madm"]);
    let experiment = Experiment::new(config).unwrap();
    let record = &experiment.run_all().unwrap()[0];
    let episodes: Vec<u64> = record.trajectories.iter().map(|t| t.episode).collect();
    assert_eq!(episodes, [0, 9]);
    let maze = experiment.task().maze().unwrap();
    for trajectory in record
        .trajectories
        .iter()
        .chain(std::iter::once(&record.evaluation_trajectory))
    {
        assert_eq!(trajectory.states.len(), trajectory.actions.len() + 1);
        assert_eq!(trajectory.positions.len(), trajectory.states.len());
        let start = maze.start();
        let expected = [start.x as f64, start.y as f64];
        assert_eq!(trajectory.positions[0], expected);
    }
    assert!(record.evaluation_trajectory.greedy);
    assert_eq!(
        record.evaluation_trajectory.actions.len() as u64,
        record.evaluation.steps
    );
}

#[test]
fn short_run_curve_is_pinned() {
    let config = only(small_config(12, 1), &["ea-madm", "epsilon-decreasing"]);
    let records = Experiment::new(config).unwrap().run_all().unwrap();
    let mut text = String::from("method episode steps return learning env_steps collisions\n");
    for record in &records {
        for e in &record.episodes {
            text.push_str(&format!(
                "{} {} {} {:.6} {:.6} {} {}\n",
                record.method,
                e.episode,
                e.steps,
                e.task_return,
                e.learning_return,
                e.env_steps,
                e.collisions
            ));
        }
        text.push_str(&format!(
            "{} greedy {} {:.6} reached={}\n",
            record.method,
            record.evaluation.steps,
            record.evaluation.task_return,
            record.evaluation.reached
        ));
    }
    insta::assert_snapshot!(text);
}

#[test]
fn literal_standardisation_leaves_the_source_task_values_at_zero() {
    use dql::{DoubleQ, Environment, EpisodeOptions, Learner, Schedule, run_episode};
    use eamadm::reward_std::Standardisation;
    use eamadm::{EaMadmPolicy, PretrainConfig, StandardisedReward, Storage, build_prior};
    use rand::SeedableRng;

    let config = small_config(10, 1);
    let experiment = Experiment::new(config.clone()).unwrap();
    let env = experiment.task().maze_env().unwrap().clone();
    let pretrain = PretrainConfig {
        episodes: 10,
        ..PretrainConfig::default()
    };
    let subtasks = eamadm::pretrain_subtasks(&env, config.learner, &pretrain, 1).unwrap();
    let learners: Vec<&DoubleQ> = subtasks.iter().map(|s| &s.learner).collect();
    let (prior, _) = build_prior(&env, &learners, &Storage::default()).unwrap();
    let schedule = Schedule::Constant(0.3);
    for (mode, zero) in [
        (Standardisation::CrossSectional, true),
        (Standardisation::Running, false),
    ] {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let mut learner =
            DoubleQ::new(env.n_states(), env.n_actions(), config.learner, &mut rng).unwrap();
        let mut policy =
            EaMadmPolicy::new(prior.clone(), schedule, madm_owa::Weighting::default()).unwrap();
        let mut signal = StandardisedReward::new(mode, 2).unwrap();
        let mut env = env.clone();
        for episode in 0..10 {
            let options = EpisodeOptions::new(episode);
            run_episode(
                &mut env,
                &mut learner,
                &mut policy,
                &mut signal,
                &mut rng,
                &options,
            )
            .unwrap();
        }
        let all_zero = learner.q1_table().as_slice().iter().all(|q| *q == 0.0)
            && learner.q2_table().as_slice().iter().all(|q| *q == 0.0);
        assert_eq!(all_zero, zero, "{mode:?}");
        assert!(learner.experience().count() > 0);
    }
}

#[test]
fn summaries_group_runs_by_method() {
    let config = only(small_config(10, 3), &["softmax", "ea-madm"]);
    let records = Experiment::new(config).unwrap().run_all().unwrap();
    let summaries = eamadm::summarise(&records, 5).unwrap();
    let methods: Vec<&str> = summaries.iter().map(|s| s.method.as_str()).collect();
    assert_eq!(methods, ["softmax", "ea-madm"]);
    for summary in &summaries {
        assert_eq!((summary.seeds, summary.window), (3, 5));
        assert_eq!(summary.optimum_steps, Some(18));
        let ratio = summary.final_steps_to_optimum.unwrap();
        assert!((ratio.mean - summary.final_steps.mean / 18.0).abs() < 1e-9);
        assert!(summary.robot.is_none());
    }
    assert_eq!(summaries[0].pretrain_env_steps.mean, 0.0);
    assert!(summaries[1].pretrain_env_steps.mean > 0.0);
}

#[test]
fn robot_runs_carry_the_robot_metrics_and_paths_in_metres() {
    let mut config = eamadm::paper::robot();
    config.episodes = 6;
    config.seeds = 1;
    config.task = eamadm::TaskConfig::Robot {
        scenario: "default".to_owned(),
        step_cap: Some(60),
        target_bins: None,
        control_period: None,
        reach_radius: None,
        distance_bins: None,
    };
    for spec in &mut config.methods {
        if let eamadm::Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = 6;
        }
    }
    let config = only(config, &["ea-madm", "softmax"]);
    let experiment = Experiment::new(config).unwrap();
    assert_eq!(experiment.task().n_actions(), 5);
    assert_eq!(experiment.task().subtask_names().len(), 3);
    let records = experiment.run_all().unwrap();
    assert_eq!(records[0].subtasks.len(), 3);
    let scenario = experiment.task().scenario().unwrap();
    for record in &records {
        for episode in record.episodes.iter().chain([&record.evaluation]) {
            let robot = episode.robot.expect("robot metrics");
            assert!(episode.steps <= 60);
            let dt = scenario.control_period;
            assert!(
                (robot.time - dt * episode.steps as f64).abs() < 1e-9,
                "{robot:?}"
            );
            assert!(robot.average_reward.is_finite());
            assert_eq!(robot.time_to_reach.is_some(), episode.reached);
        }
        for trajectory in record
            .trajectories
            .iter()
            .chain([&record.evaluation_trajectory])
        {
            assert_eq!(trajectory.positions.len(), trajectory.states.len());
            let [x, y] = trajectory.positions[0];
            assert!((x - scenario.start.x).abs() < 1e-12 && (y - scenario.start.y).abs() < 1e-12);
            for [x, y] in &trajectory.positions {
                assert!((0.0..=scenario.arena.width).contains(x), "{x}");
                assert!((0.0..=scenario.arena.height).contains(y), "{y}");
            }
        }
    }
    // Pure function of (config, method, seed), robot noise included.
    let (method, seed) = experiment.jobs()[0];
    assert_eq!(experiment.run(method, seed).unwrap(), records[0]);
}

#[test]
fn periodic_greedy_evaluations_do_not_change_training() {
    // Every method (the paper's, the ablations and every control: warm-up, reward-matched,
    // sub-task alone) evaluated after every episode and only after the last one: the training
    // episodes, the final evaluation and everything counted in training are bit-identical.
    let episodes = 12;
    let mut config = small_config(episodes, 1);
    config.methods.extend(eamadm::paper::controls(500));
    let with_every = |every: u64| {
        let mut config = config.clone();
        config.evaluation.every = Some(every);
        Experiment::new(config).unwrap().run_all().unwrap()
    };
    let often = with_every(1);
    let once = with_every(episodes);
    let default = Experiment::new(config.clone()).unwrap().run_all().unwrap();
    assert_eq!(often.len(), config.methods.len());
    for ((often, once), default) in often.iter().zip(&once).zip(&default) {
        let training = |r: &RunRecord| RunRecord {
            greedy_evaluations: Vec::new(),
            ..r.clone()
        };
        assert_eq!(training(often), training(once), "{}", often.method);
        assert_eq!(training(often), training(default), "{}", often.method);
        let numbers = |r: &RunRecord| -> Vec<u64> {
            r.greedy_evaluations.iter().map(|e| e.episode).collect()
        };
        assert_eq!(numbers(often), (1..=episodes).collect::<Vec<_>>());
        assert_eq!(numbers(once), [episodes]);
        // The default: every 10 episodes.
        assert_eq!(numbers(default), [10]);
        // The evaluation after episode k is the same whatever else is evaluated, and it
        // carries the training's cumulative steps at that point.
        assert_eq!(
            often.greedy_evaluations[episodes as usize - 1],
            once.greedy_evaluations[0],
            "{}",
            often.method
        );
        assert_eq!(
            often.greedy_evaluations[9], default.greedy_evaluations[0],
            "{}",
            often.method
        );
        for e in &often.greedy_evaluations {
            let trained = &often.episodes[e.episode as usize - 1];
            assert_eq!(e.env_steps, trained.env_steps);
            assert_eq!(e.learning_return, 0.0);
        }
    }
}

#[test]
fn an_evaluation_period_of_zero_or_beyond_the_episodes_is_refused_by_name() {
    for every in [0, 13] {
        let mut config = small_config(12, 1);
        config.evaluation.every = Some(every);
        let message = Experiment::new(config).unwrap_err().to_string();
        assert!(
            message.contains("evaluation.every") && message.contains("1..=episodes"),
            "{message}"
        );
    }
    let mut config = small_config(12, 1);
    config.evaluation.every = Some(12);
    assert!(Experiment::new(config).is_ok());
}
