//! The tuning trials (issue 33 item 3): the same budget for every method, trials inside their
//! stated ranges and the same on every platform, tuning seeds apart from held-out seeds, the
//! trial experiments, the choice of the best, and `tuning.csv`.

use dql::Schedule;
use eamadm::config::{ExperimentConfig, MAX_SEEDS, Method, Storage};
use eamadm::paper::{self, PaperTask};
use eamadm::tuning::{
    GRID_POINTS, MAX_TRIALS, MIN_TRIALS, Objective, Range, SearchKind, SearchSpace,
    TRIALS_PER_METHOD, TUNING_BASE_SEED, TUNING_COLUMNS, TUNING_SEEDS, Trial, TuningError,
    TuningRow, check_disjoint, choose, paper_methods, trials, tuning_plan, write_tuning_csv,
};
use eamadm::{Experiment, scores};

/// The experiments tuned: the paper's three tasks (and the robot over the paper's state).
fn tuned_tasks() -> Vec<ExperimentConfig> {
    PaperTask::ALL.into_iter().map(PaperTask::config).collect()
}

/// The law: every method the claims compare gets the same number of trials, on every
/// task, and every trial is a valid experiment of that one method on the tuning seeds.
#[test]
fn every_method_gets_the_same_number_of_trials() {
    for base in tuned_tasks() {
        let methods = paper_methods(&base);
        assert_eq!(
            methods,
            ["ea-madm", "epsilon-greedy", "epsilon-decreasing", "softmax"]
        );
        let plan = tuning_plan(&base, &methods, TRIALS_PER_METHOD).unwrap();
        for method in &methods {
            let of_method: Vec<&Trial> = plan.iter().filter(|t| t.method == *method).collect();
            assert_eq!(
                of_method.len(),
                TRIALS_PER_METHOD as usize,
                "{} {method}",
                base.name
            );
            assert_eq!(of_method.iter().filter(|t| t.paper_setting).count(), 1);
            for (index, trial) in of_method.iter().enumerate() {
                assert_eq!(trial.trial as usize, index);
                let config = trial.experiment(&base).unwrap();
                assert_eq!(config.methods.len(), 1);
                assert_eq!(config.methods[0].label, *method);
                assert_eq!(
                    (config.base_seed, config.seeds),
                    (TUNING_BASE_SEED, TUNING_SEEDS)
                );
                assert_eq!(config.task, base.task);
                assert_eq!(config.episodes, base.episodes);
            }
        }
        assert_eq!(plan.len(), methods.len() * TRIALS_PER_METHOD as usize);
    }
    const { assert!(TRIALS_PER_METHOD >= MIN_TRIALS && MIN_TRIALS >= 16) };
}

/// Trial 0 is the preset's setting: its experiment differs from the preset only in seeds,
/// name, kept trajectories and the other methods.
#[test]
fn trial_zero_is_the_presets_setting() {
    let base = paper::task2();
    for method in paper_methods(&base) {
        let trial = &trials(&base, method, 16).unwrap()[0];
        let config = trial.experiment(&base).unwrap();
        assert_eq!(config.learner, base.learner);
        assert_eq!(&config.methods[0], base.method(method).unwrap());
    }
}

/// Drawn trials lie in the stated ranges, vary what their kind varies and nothing else, and
/// are the same whichever other methods are tuned and in whatever order.
#[test]
fn drawn_trials_stay_in_their_ranges() {
    let space = SearchSpace::PAPER;
    let within = |range: Range, value: f64| range.low <= value && value <= range.high;
    for base in tuned_tasks() {
        for method in paper_methods(&base) {
            let all = trials(&base, method, 64).unwrap();
            assert_eq!(&all[..16], &trials(&base, method, 16).unwrap()[..]);
            let preset = base.method(method).unwrap();
            for trial in &all[1..] {
                let p = trial.params;
                assert!(within(space.alpha, p.alpha), "{p:?}");
                let horizon = 1.0 / (1.0 - p.gamma);
                assert!((9.999..=1000.001).contains(&horizon), "{p:?}");
                let config = trial.experiment(&base).unwrap();
                let spec = &config.methods[0];
                match (trial.kind, p.exploration) {
                    (SearchKind::EpsilonConstant, Schedule::Constant(epsilon)) => {
                        assert!(within(space.epsilon, epsilon));
                    }
                    (
                        SearchKind::EpsilonDecreasing | SearchKind::EaMadm,
                        Schedule::Exponential {
                            start,
                            factor,
                            floor,
                        },
                    ) => {
                        assert!(within(space.epsilon_start, start));
                        assert!((0.8..=0.998).contains(&factor), "{factor}");
                        assert_eq!(floor, 0.0);
                    }
                    (
                        SearchKind::Softmax,
                        Schedule::Exponential {
                            start,
                            factor,
                            floor,
                        },
                    ) => {
                        assert!(within(space.temperature_start, start));
                        assert!((0.8..=0.998).contains(&factor));
                        assert!(floor <= start && floor >= space.temperature_floor.low);
                    }
                    other => panic!("{method}: unexpected {other:?}"),
                }
                match (&spec.method, &preset.method) {
                    (Method::EaMadm(tuned), Method::EaMadm(paper)) => {
                        let episodes = p.pretrain_episodes.unwrap();
                        assert!((50..=800).contains(&episodes));
                        assert_eq!(tuned.pretrain.episodes, episodes);
                        let tau = p.tree_threshold.unwrap();
                        assert!(within(space.tree_threshold, tau));
                        assert!(
                            matches!(tuned.storage, Storage::Tree(t) if t.state_threshold == tau && t.action_threshold == tau)
                        );
                        // Nothing else of the method changes.
                        assert_eq!(tuned.weighting, paper.weighting);
                        assert_eq!(tuned.standardisation, paper.standardisation);
                        assert_eq!(tuned.pretrain.epsilon, paper.pretrain.epsilon);
                    }
                    (tuned, paper) => {
                        assert_eq!(p.pretrain_episodes, None);
                        assert_eq!(p.tree_threshold, None);
                        assert_eq!(tuned.kind_name(), paper.kind_name());
                    }
                }
                assert_eq!(config.learner.alpha, p.alpha);
                assert_eq!(config.learner.gamma, p.gamma);
                assert_eq!(config.learner.xi, base.learner.xi);
            }
        }
        // A method's trials do not depend on the others tuned or their order.
        let forward = tuning_plan(&base, &["softmax", "ea-madm"], 16).unwrap();
        let backward = tuning_plan(&base, &["ea-madm", "softmax"], 16).unwrap();
        assert_eq!(forward[..16], backward[16..]);
    }
}

/// The trials are the same on every platform: the grid points are rounded to three (log) or
/// four (linear) significant digits, and no grid point lies within 10⁻⁹ (relative) of a rounding boundary,
/// so a last-bit difference of `powf` between platforms cannot change a rounded value.
#[test]
fn every_grid_point_rounds_the_same_on_every_platform() {
    let space = SearchSpace::PAPER;
    let ranges = [
        space.alpha,
        space.horizon,
        space.epsilon,
        space.epsilon_start,
        space.decay_episodes,
        space.temperature_start,
        space.temperature_floor,
        space.tree_threshold,
        space.pretrain_episodes,
    ];
    for range in ranges {
        assert_eq!(range.point(0), range.low);
        assert_eq!(range.point(GRID_POINTS - 1), range.high);
        let rounded = |value: f64| format!("{value:.prec$e}", prec = range.digits() - 1);
        for k in 0..GRID_POINTS {
            let value = range.unrounded_point(k);
            let want = rounded(value);
            assert_eq!(
                rounded(value * (1.0 - 1e-9)),
                want,
                "{range:?} point {k}: {value}"
            );
            assert_eq!(
                rounded(value * (1.0 + 1e-9)),
                want,
                "{range:?} point {k}: {value}"
            );
            assert_eq!(range.point(k), want.parse::<f64>().unwrap());
        }
    }
}

/// Value stability: the first drawn trials of every method on Task I.
#[test]
fn the_first_trials_are_pinned() {
    let base = paper::task1();
    let mut lines = Vec::new();
    for method in paper_methods(&base) {
        for trial in &trials(&base, method, 16).unwrap()[1..4] {
            lines.push(format!("{} {:?}", trial.experiment_name(), trial.params));
        }
    }
    insta::assert_snapshot!(lines.join("\n"));
}

/// Tuning seeds never meet a held-out seed: not the presets', not any seed a config starting
/// at 0 can ask for, and a config whose seeds would is refused.
#[test]
fn tuning_seeds_are_disjoint_from_held_out_seeds() {
    let tuning = TUNING_BASE_SEED..TUNING_BASE_SEED + u64::from(TUNING_SEEDS);
    for base in tuned_tasks() {
        check_disjoint(&base).unwrap();
        assert!(base.seed_values().all(|seed| !tuning.contains(&seed)));
        let mut widest = base.clone();
        widest.seeds = MAX_SEEDS;
        check_disjoint(&widest).unwrap();
        let trial = &trials(&base, "ea-madm", 16).unwrap()[3];
        let held_out = trial.held_out(&base).unwrap();
        assert_eq!(held_out.name, format!("{}-best-ea-madm", base.name));
        assert_eq!(
            held_out.seed_values().collect::<Vec<_>>(),
            base.seed_values().collect::<Vec<_>>()
        );
        let tuned = trial.experiment(&base).unwrap();
        assert!(tuned.seed_values().all(|seed| tuning.contains(&seed)));
    }
    let mut overlapping = paper::task1();
    overlapping.base_seed = TUNING_BASE_SEED - 5;
    let error = check_disjoint(&overlapping).unwrap_err();
    assert_eq!(
        error.to_string(),
        "tuning: the held-out seeds of task1 (999999995..1000000015) meet the tuning seeds \
         (1000000000..1000000010); choose a base_seed below 1000000000 − seeds"
    );
    let trial = &trials(&paper::task1(), "softmax", 16).unwrap()[1];
    assert!(matches!(
        trial.held_out(&overlapping),
        Err(TuningError::SeedsOverlap { .. })
    ));
}

#[test]
fn bad_requests_are_typed_errors() {
    let base = paper::task1();
    for budget in [0, MIN_TRIALS - 1, MAX_TRIALS + 1] {
        let error = trials(&base, "softmax", budget).unwrap_err();
        assert!(matches!(error, TuningError::Budget { trials } if trials == budget));
    }
    assert_eq!(
        trials(&base, "nope", 16).unwrap_err().to_string(),
        "tuning: task1 has no method `nope`"
    );
    assert_eq!(
        trials(&base, "subtask0-alone", 16).unwrap_err().to_string(),
        "tuning: `subtask0-alone` is a subtask_greedy method, which has no hyperparameters to tune"
    );
    // A trial applied to a config without its method.
    let trial = &trials(&base, "softmax", 16).unwrap()[2];
    let mut other = base.clone();
    other.methods.retain(|spec| spec.label != "softmax");
    assert!(matches!(
        trial.experiment(&other),
        Err(TuningError::UnknownMethod { .. })
    ));
}

/// The objective of each task, scored from a real (shortened) trial's final scores.
#[test]
fn a_trial_runs_and_is_scored_by_its_tasks_objective() {
    let base = paper::task1();
    assert_eq!(Objective::of(&base.task), Objective::FinalStepsIqm);
    assert_eq!(
        Objective::of(&paper::robot().task),
        Objective::SuccessRateMean
    );
    let trial = &trials(&base, "epsilon-decreasing", 16).unwrap()[4];
    let mut config = trial.experiment(&base).unwrap();
    config.episodes = 5;
    config.seeds = 3;
    if let eamadm::TaskConfig::Maze { step_cap, .. } = &mut config.task {
        *step_cap = Some(300);
    }
    let experiment = Experiment::new(config).unwrap();
    let records = experiment.run_all().unwrap();
    let rows = scores::final_scores(&records, &experiment).unwrap();
    assert_eq!(rows.len(), 3);
    assert!(rows.iter().all(|row| row.seed >= TUNING_BASE_SEED));
    let score = Objective::FinalStepsIqm.score(&rows).unwrap();
    let mut steps: Vec<f64> = rows.iter().map(|row| row.final_steps).collect();
    steps.sort_by(f64::total_cmp);
    // Three values: the IQM drops none, it is the mean.
    assert!((score - steps.iter().sum::<f64>() / 3.0).abs() < 1e-9);
    assert!(Objective::FinalStepsIqm.better(58.0, 60.0));
    assert!(Objective::SuccessRateMean.better(0.8, 0.6));
    assert!(Objective::FinalStepsIqm.score(&[]).is_err());
}

/// The best trial per method, the lowest index among equals (the preset's setting wins a
/// tie); nothing is chosen while a trial of the method lacks its score.
#[test]
fn the_best_trial_is_chosen_per_method() {
    let base = paper::task1();
    let objective = Objective::of(&base.task);
    let plan = tuning_plan(&base, &["softmax", "ea-madm"], 16).unwrap();
    let mut rows: Vec<TuningRow> = plan.iter().map(|t| TuningRow::new(t, objective)).collect();
    for (i, row) in rows.iter_mut().enumerate() {
        row.score = Some(match (row.method.as_str(), row.trial) {
            ("softmax", 0 | 7) => 60.0,
            ("softmax", _) => 100.0 + i as f64,
            (_, 9) => 58.0,
            (_, 15) => 200.0,
            _ => 70.0,
        });
    }
    rows[16 + 15].score = None;
    choose(&mut rows, objective);
    let chosen: Vec<(&str, u32)> = rows
        .iter()
        .filter(|r| r.chosen == Some(true))
        .map(|r| (r.method.as_str(), r.trial))
        .collect();
    assert_eq!(chosen, [("softmax", 0)]);
    assert!(rows[16..].iter().all(|r| r.chosen.is_none()));
    rows[16 + 15].score = Some(200.0);
    choose(&mut rows, objective);
    let chosen: Vec<(&str, u32)> = rows
        .iter()
        .filter(|r| r.chosen == Some(true))
        .map(|r| (r.method.as_str(), r.trial))
        .collect();
    assert_eq!(chosen, [("softmax", 0), ("ea-madm", 9)]);
    assert_eq!(rows.iter().filter(|r| r.chosen == Some(false)).count(), 30);
}

#[test]
fn tuning_csv_has_its_documented_columns() {
    let base = paper::robot();
    let objective = Objective::of(&base.task);
    let plan = tuning_plan(&base, &paper_methods(&base), 16).unwrap();
    let rows: Vec<TuningRow> = plan.iter().map(|t| TuningRow::new(t, objective)).collect();
    let mut bytes = Vec::new();
    write_tuning_csv(&rows, &mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .unwrap()
        .iter()
        .map(str::to_owned)
        .collect();
    let names: Vec<&str> = TUNING_COLUMNS.iter().map(|c| c.name).collect();
    assert_eq!(header, names);
    let records: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(records.len(), 64);
    // The softmax trials name their schedule a temperature; EA-MADM's fill τ and episodes.
    let softmax = records.iter().find(|r| &r[1] == "softmax").unwrap();
    assert_eq!(&softmax[10], "temperature");
    assert_eq!(&softmax[11], "");
    let ea_madm = records
        .iter()
        .find(|r| &r[1] == "ea-madm" && &r[2] == "3")
        .unwrap();
    assert!(!ea_madm[11].is_empty() && !ea_madm[12].is_empty());
    assert_eq!(&ea_madm[15], "success_rate_mean");
    assert_eq!((&ea_madm[16], &ea_madm[17]), ("", ""));
    let mut empty = Vec::new();
    write_tuning_csv(&[], &mut empty).unwrap();
    assert_eq!(
        String::from_utf8(empty).unwrap().trim_end(),
        names.join(",")
    );
}

/// The two stages of a task's tuning: stage 2 is planned only once every trial of every
/// method is scored, then holds each method's best trial on the held-out seeds; the held-out
/// rows are renamed into the task for the "each at its best" verdicts, and nothing else is.
#[test]
fn stage_two_follows_only_a_complete_stage_one() {
    use eamadm::tuning::{TaskTuning, at_best_scores, chosen_trials};

    let base = paper::task1();
    let tuning = TaskTuning::new(&base, &["softmax", "ea-madm"], 16, 2).unwrap();
    let stage1 = tuning.stage1().unwrap();
    assert_eq!(stage1.len(), 32);
    assert!(
        stage1
            .iter()
            .all(|c| c.seeds == 2 && c.base_seed == TUNING_BASE_SEED)
    );
    assert!(matches!(
        TaskTuning::new(&base, &["softmax"], 16, TUNING_SEEDS + 1),
        Err(TuningError::TuningSeeds { .. })
    ));

    // One real (shortened) run gives a row to copy; each trial's rows say its experiment.
    let mut config = stage1[0].clone();
    config.episodes = 3;
    config.seeds = 1;
    let experiment = Experiment::new(config).unwrap();
    let template =
        scores::final_scores(&experiment.run_all().unwrap(), &experiment).unwrap()[0].clone();
    let row_of = |experiment: &str, method: &str, steps: f64| scores::FinalScore {
        task: experiment.to_owned(),
        method: method.to_owned(),
        final_steps: steps,
        ..template.clone()
    };
    let mut all = Vec::new();
    for trial in &tuning.trials {
        // softmax is best at trial 5, EA-MADM ties at trials 0 and 3 (trial 0 wins).
        let steps = match (trial.method.as_str(), trial.trial) {
            ("softmax", 5) | ("ea-madm", 0 | 3) => 58.0,
            _ => 90.0 + f64::from(trial.trial),
        };
        all.push(row_of(&trial.experiment_name(), &trial.method, steps));
        all.push(row_of(&trial.experiment_name(), &trial.method, steps));
    }
    // A trial's rows missing: that method is not chosen, and stage 2 waits.
    let missing = "task1-tune-ea-madm-t07";
    let partial: Vec<scores::FinalScore> =
        all.iter().filter(|r| r.task != missing).cloned().collect();
    let rows = tuning.rows(&partial).unwrap();
    assert!(
        rows.iter()
            .filter(|r| r.method == "ea-madm")
            .all(|r| r.chosen.is_none())
    );
    assert_eq!(
        rows.iter().filter(|r| r.chosen == Some(true)).count(),
        1,
        "softmax is complete"
    );
    assert!(tuning.stage2(&rows).unwrap().is_none());

    let rows = tuning.rows(&all).unwrap();
    assert!(
        rows.iter()
            .all(|r| r.tuning_seeds == 2 && r.score.is_some())
    );
    let stage2 = tuning.stage2(&rows).unwrap().unwrap();
    let chosen: Vec<(&str, u32, &str, u32)> = stage2
        .iter()
        .map(|(t, c)| (t.method.as_str(), t.trial, c.name.as_str(), c.seeds))
        .collect();
    assert_eq!(
        chosen,
        [
            ("softmax", 5, "task1-best-softmax", base.seeds),
            ("ea-madm", 0, "task1-best-ea-madm", base.seeds)
        ]
    );
    let trials = chosen_trials(&rows);
    assert_eq!(trials.len(), 2);
    assert!(trials.iter().all(|c| c.trials == 16 && c.tuning_seeds == 2));

    // Held-out rows of the task's `-best-` experiments are renamed; others are left out.
    let held_out = [
        row_of("task1-best-softmax", "softmax", 60.0),
        row_of("task1-best-ea-madm", "ea-madm", 61.0),
        row_of("task2-best-softmax", "softmax", 62.0),
        row_of("task1-best-softmax", "ea-madm", 63.0),
        row_of("task1", "softmax", 64.0),
    ];
    let renamed = at_best_scores("task1", &held_out);
    let kept: Vec<(&str, &str, f64)> = renamed
        .iter()
        .map(|r| (r.task.as_str(), r.method.as_str(), r.final_steps))
        .collect();
    assert_eq!(
        kept,
        [("task1", "softmax", 60.0), ("task1", "ea-madm", 61.0)]
    );
}
