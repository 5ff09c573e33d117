//! `--suite tuning` in the plan: the experiments of its two stages ([`eamadm::tuning::TaskTuning`]
//! holds the logic) as planned experiments, stage 2 planned only once every stage-1 run is in
//! the given stores, and its outputs (`tuning.csv`, the "each at its best" scores).

use std::sync::Arc;

use eamadm::Experiment;
use eamadm::findings::ChosenTrial;
use eamadm::scores::FinalScore;
use eamadm::tuning::{self, TRIALS_PER_METHOD, TUNING_SEEDS, TaskTuning, TuningRow};

use crate::Failure;
use crate::cli::{KeepTrajectories, Suite};
use crate::experiments::PlannedExperiment;
use crate::jobs::Job;
use eamadm_runs::RunStore;

/// Which experiment of the tuning suite a planned experiment is.
#[derive(Debug, Clone)]
pub(crate) struct TuningRun {
    /// The index of the tuned (base) experiment in the plan.
    pub(crate) base: usize,
    /// Its tuning (shared by the task's experiments).
    pub(crate) tuning: Arc<TaskTuning>,
    /// Stage 2 (a chosen trial on the held-out seeds) rather than stage 1 (a trial on the
    /// tuning seeds).
    pub(crate) held_out: bool,
}

/// Tuning seeds per trial: [`TUNING_SEEDS`], or [`crate::plan::QUICK_SEEDS`] for `--quick`.
pub(crate) fn tuning_seeds(quick: bool) -> u32 {
    if quick {
        crate::plan::QUICK_SEEDS.min(TUNING_SEEDS)
    } else {
        TUNING_SEEDS
    }
}

/// Stage 1 of `suites` (empty without [`Suite::Tuning`]): for each base experiment of
/// `experiments` that the suite tunes ([`tuning::SUITE_TASKS`]), the trials of its paper
/// methods among `methods`, [`TRIALS_PER_METHOD`] each, as experiments on the tuning seeds.
pub(crate) fn stage1(
    suites: &[Suite],
    experiments: &[PlannedExperiment],
    methods: &[String],
    quick: bool,
) -> Result<Vec<PlannedExperiment>, Failure> {
    if !suites.contains(&Suite::Tuning) {
        return Ok(Vec::new());
    }
    let mut planned = Vec::new();
    for (base, experiment) in experiments.iter().enumerate() {
        if experiment.reading.is_some()
            || experiment.tuning.is_some()
            || !tuning::SUITE_TASKS.contains(&experiment.name.as_str())
        {
            continue;
        }
        let config = experiment.config();
        let tuned: Vec<&str> = tuning::paper_methods(config)
            .into_iter()
            .filter(|label| methods.iter().any(|m| m == label))
            .collect();
        if tuned.is_empty() {
            continue;
        }
        let tuning = Arc::new(
            TaskTuning::new(config, &tuned, TRIALS_PER_METHOD, tuning_seeds(quick))
                .map_err(Failure::invalid)?,
        );
        for (trial, trial_config) in tuning
            .trials
            .iter()
            .zip(tuning.stage1().map_err(Failure::invalid)?)
        {
            planned.push(planned_experiment(
                experiment,
                trial_config,
                format!(
                    "{} trial {} of {}",
                    experiment.title, trial.trial, trial.method
                ),
                TuningRun {
                    base,
                    tuning: Arc::clone(&tuning),
                    held_out: false,
                },
            )?);
        }
    }
    Ok(planned)
}

fn planned_experiment(
    base: &PlannedExperiment,
    config: eamadm::ExperimentConfig,
    title: String,
    run: TuningRun,
) -> Result<PlannedExperiment, Failure> {
    let name = config.name.clone();
    let experiment = Experiment::new(config)
        .map_err(|error| Failure::invalid(format!("{} ({}): {error}", name, base.name)))?;
    Ok(PlannedExperiment {
        name,
        title,
        experiment,
        reading: None,
        tuning: Some(run),
        family: None,
    })
}

/// The final scores of the runs of `jobs` that `keep_job` keeps, from the first of `stores`
/// holding each; `None` when one is in none of them.
fn stored_scores(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    stores: &[RunStore],
    keep: KeepTrajectories,
    keep_job: impl Fn(&Job<'_>) -> bool,
) -> Result<Option<Vec<FinalScore>>, Failure> {
    let mut scores = Vec::new();
    for job in jobs.iter().filter(|job| keep_job(job)) {
        let mut found = None;
        for store in stores {
            if let Some(run) = store.load(&job.key, keep).map_err(Failure::failed)? {
                found = Some(run);
                break;
            }
        }
        let Some(run) = found else {
            return Ok(None);
        };
        scores.push(
            eamadm::scores::final_score_of(&run.record, &experiments[job.experiment].experiment)
                .map_err(Failure::failed)?,
        );
    }
    Ok(Some(scores))
}

/// What stage 2 of a plan is, given the stores its stage-1 runs may be in.
#[derive(Debug)]
pub(crate) enum Stage2 {
    /// The plan has no tuning suite, or its stage 2 is planned already.
    None,
    /// Stage 1 is not complete in the stores: this many of its runs are missing.
    Pending {
        /// Stage-1 runs in none of the stores.
        missing: usize,
        /// Stage-1 runs of the plan.
        of: usize,
    },
    /// Each tuned task's chosen trials on the held-out seeds, to be appended to the plan.
    Planned(Vec<PlannedExperiment>),
}

/// Stage 2 of the plan `experiments` (with `jobs`): planned when every stage-1 run is in
/// `stores` (each trial is scored and each method's best chosen), pending otherwise.
pub(crate) fn stage2(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    stores: &[RunStore],
    keep: KeepTrajectories,
) -> Result<Stage2, Failure> {
    let is_stage1 = |job: &Job<'_>| {
        experiments[job.experiment]
            .tuning
            .as_ref()
            .is_some_and(|run| !run.held_out)
    };
    let stage1_jobs = jobs.iter().filter(|job| is_stage1(job)).count();
    let planned_already = experiments
        .iter()
        .any(|e| e.tuning.as_ref().is_some_and(|run| run.held_out));
    if stage1_jobs == 0 || planned_already {
        return Ok(Stage2::None);
    }
    let missing = jobs
        .iter()
        .filter(|job| is_stage1(job) && !stores.iter().any(|store| store.has(&job.key, keep)))
        .count();
    if missing > 0 {
        return Ok(Stage2::Pending {
            missing,
            of: stage1_jobs,
        });
    }
    let Some(scores) = stored_scores(experiments, jobs, stores, keep, is_stage1)? else {
        return Ok(Stage2::Pending {
            missing: 1,
            of: stage1_jobs,
        });
    };
    let mut planned = Vec::new();
    for (base, tuning) in tunings(experiments) {
        let rows = tuning.rows(&scores).map_err(Failure::failed)?;
        let Some(chosen) = tuning.stage2(&rows).map_err(Failure::failed)? else {
            return Err(Failure::failed(format!(
                "--suite tuning: every stage-1 run of {} is stored, yet some method has no \
                 chosen trial",
                experiments[base].name
            )));
        };
        for (trial, config) in chosen {
            planned.push(planned_experiment(
                &experiments[base],
                config,
                format!(
                    "{} at its best: {} (trial {})",
                    experiments[base].title, trial.method, trial.trial
                ),
                TuningRun {
                    base,
                    tuning: Arc::clone(&tuning),
                    held_out: true,
                },
            )?);
        }
    }
    Ok(Stage2::Planned(planned))
}

/// Each tuned base experiment's index and tuning, in plan order.
fn tunings(experiments: &[PlannedExperiment]) -> Vec<(usize, Arc<TaskTuning>)> {
    let mut tunings: Vec<(usize, Arc<TaskTuning>)> = Vec::new();
    for run in experiments.iter().filter_map(|e| e.tuning.as_ref()) {
        if !tunings.iter().any(|(base, _)| *base == run.base) {
            tunings.push((run.base, Arc::clone(&run.tuning)));
        }
    }
    tunings
}

/// What the suite's runs give the outputs: `tuning.csv`'s rows, the held-out scores renamed
/// into their tasks and the chosen trials.
#[derive(Debug, Default)]
pub(crate) struct TuningOutcome {
    /// Every trial of every tuned task, scored and chosen.
    pub(crate) rows: Vec<TuningRow>,
    /// The held-out runs of the chosen trials under their tasks' names.
    pub(crate) at_best: Vec<FinalScore>,
    /// Each method's chosen trial.
    pub(crate) chosen: Vec<ChosenTrial>,
}

/// The outcome of the suite from `scores`, the final scores of every run of its experiments
/// in `experiments`; `None` when the plan has no tuning suite.
pub(crate) fn outcome(
    experiments: &[PlannedExperiment],
    scores: &[FinalScore],
) -> Result<Option<TuningOutcome>, tuning::TuningError> {
    let tunings = tunings(experiments);
    if tunings.is_empty() {
        return Ok(None);
    }
    let mut outcome = TuningOutcome::default();
    for (base, tuning) in tunings {
        let rows = tuning.rows(scores)?;
        outcome.chosen.extend(tuning::chosen_trials(&rows));
        outcome.rows.extend(rows);
        outcome
            .at_best
            .extend(tuning::at_best_scores(&experiments[base].name, scores));
    }
    Ok(Some(outcome))
}

/// The message of a plan whose stage 2 waits for stage 1.
pub(crate) fn pending_message(missing: usize, of: usize) -> String {
    format!(
        "--suite tuning: stage 2 (each method's chosen trial on the held-out seeds) is planned \
         only once stage 1 is complete in this output folder's run store; {missing} of its {of} \
         runs are missing. Run them (or merge the shards into one folder), then rerun the same \
         command: stage 2's jobs are listed then"
    )
}

/// Appends stage 2 to `experiments` when `stores` hold every stage-1 run; returns the missing
/// and planned stage-1 runs while it must wait (`None`: planned, planned already, or no
/// tuning suite).
pub(crate) fn extend_with_stage2(
    experiments: &mut Vec<PlannedExperiment>,
    methods: &[String],
    stores: &[RunStore],
    keep: KeepTrajectories,
) -> Result<Option<(usize, usize)>, Failure> {
    let stage = {
        let jobs = crate::jobs::plan_jobs(experiments, methods).map_err(Failure::failed)?;
        stage2(experiments, &jobs, stores, keep)?
    };
    Ok(match stage {
        Stage2::None => None,
        Stage2::Pending { missing, of } => Some((missing, of)),
        Stage2::Planned(planned) => {
            experiments.extend(planned);
            None
        }
    })
}

/// The plan's tuning suite for people (empty without one): runs per stage, and whether stage
/// 2 waits for stage 1.
pub(crate) fn describe(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    pending: Option<(usize, usize)>,
) -> String {
    let stage = |held_out: bool| {
        jobs.iter()
            .filter(|job| {
                experiments[job.experiment]
                    .tuning
                    .as_ref()
                    .is_some_and(|run| run.held_out == held_out)
            })
            .count()
    };
    let tasks: Vec<&str> = tunings(experiments)
        .iter()
        .map(|(base, _)| experiments[*base].name.as_str())
        .collect();
    if tasks.is_empty() {
        return String::new();
    }
    let (stage1, stage2) = (stage(false), stage(true));
    let second = match pending {
        Some((missing, _)) => {
            format!("stage 2 is planned once stage 1 is stored ({missing} of its runs to go)")
        }
        None if stage2 > 0 => {
            format!("stage 2: {stage2} runs (each method's chosen trial on the held-out seeds)")
        }
        None => "stage 2: none".to_owned(),
    };
    format!(
        "  tuning:   {}: stage 1: {stage1} runs ({TRIALS_PER_METHOD} trials per method on the \
         tuning seeds); {second}\n",
        tasks.join(", ")
    )
}

/// Whether the runs of `jobs` missing from `stores` are all stage-2 runs of a tuning suite
/// (and some are missing): what a merge of shards that ran stage 1 finds.
pub(crate) fn only_stage2_missing(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    stores: &[RunStore],
    keep: KeepTrajectories,
) -> bool {
    let mut missing = jobs
        .iter()
        .filter(|job| !stores.iter().any(|store| store.has(&job.key, keep)))
        .peekable();
    missing.peek().is_some()
        && missing.all(|job| {
            experiments[job.experiment]
                .tuning
                .as_ref()
                .is_some_and(|run| run.held_out)
        })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use eamadm::findings::Findings;
    use eamadm::tuning::TUNING_COLUMNS;

    use super::*;
    use crate::cli::{MergeArgs, Readings, ReproduceArgs, ReproduceCommand, RunModeArgs, Task};
    use crate::plan::Workspace;
    use crate::reproduce::{merge, prepare, reproduce_paper};

    fn workspace() -> (tempfile::TempDir, Workspace) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("fixtures")).unwrap();
        let root = dir.path().canonicalize().unwrap();
        (
            dir,
            Workspace {
                current_dir: root.clone(),
                root,
            },
        )
    }

    /// A tiny tuning plan: Task I shortened by --quick, EA-MADM against softmax, two held-out
    /// seeds (three tuning seeds), no readings.
    fn tiny(out: &str, suites: Vec<Suite>) -> ReproduceArgs {
        ReproduceArgs {
            seeds: Some(2),
            tasks: vec![Task::Task1],
            methods: vec!["ea-madm".to_owned(), "softmax".to_owned()],
            config: None,
            out: Some(out.into()),
            quick: true,
            wait: false,
            keep_trajectories: KeepTrajectories::Figures,
            readings: Readings::None,
            pretrained_cache: None,
            suites,
            family_size: None,
        }
    }

    fn run(ws: &Workspace, plan: ReproduceArgs, mode: RunModeArgs) -> Result<(), crate::Failure> {
        reproduce_paper(&ReproduceCommand { plan, mode }, ws)
    }

    fn read(folder: &Path, file: &str) -> String {
        std::fs::read_to_string(folder.join(file)).unwrap()
    }

    /// The law at the plan: on every tuned task each method the claims compare has
    /// the same number of stage-1 experiments, one per trial, each of the one method.
    #[test]
    fn the_plan_gives_every_method_the_same_number_of_trials() {
        let (_dir, ws) = workspace();
        let mut args = tiny("out", vec![Suite::Tuning]);
        args.tasks = vec![Task::Task1, Task::Task2, Task::Robot, Task::RobotPaperState];
        args.methods = Vec::new();
        let (_, experiments) = prepare(&args, &ws).unwrap();
        for task in tuning::SUITE_TASKS {
            let trials: Vec<&PlannedExperiment> = experiments
                .iter()
                .filter(|e| {
                    e.tuning
                        .as_ref()
                        .is_some_and(|run| experiments[run.base].name == task)
                })
                .collect();
            let mut per_method: Vec<(String, usize)> = Vec::new();
            for trial in &trials {
                assert_eq!(trial.config().methods.len(), 1, "{}", trial.name);
                let label = &trial.config().methods[0].label;
                match per_method.iter_mut().find(|(m, _)| m == label) {
                    Some((_, count)) => *count += 1,
                    None => per_method.push((label.clone(), 1)),
                }
            }
            assert_eq!(
                per_method,
                ["ea-madm", "epsilon-greedy", "epsilon-decreasing", "softmax"]
                    .map(|m| (m.to_owned(), TRIALS_PER_METHOD as usize)),
                "{task}"
            );
        }
        // The robot over the paper's state is not a claim's task: not tuned.
        assert!(
            !experiments
                .iter()
                .any(|e| e.name.starts_with("robot-paper-state-tune-"))
        );
        // Without the suite, nothing of it is planned.
        args.suites.clear();
        let (_, plain) = prepare(&args, &ws).unwrap();
        assert!(plain.iter().all(|e| e.tuning.is_none()));
    }

    /// Stage 2 is planned only once stage 1 is in the store: not from an empty folder nor
    /// from a shard's part; a merge of the shards stores stage 1 and says to rerun; the rerun
    /// runs stage 2 and writes what one invocation writes, byte for byte.
    #[test]
    fn stage_two_is_planned_only_after_stage_one() {
        let (_dir, ws) = workspace();
        let suites = vec![Suite::Tuning];
        let (plan, mut experiments) = prepare(&tiny("empty", suites.clone()), &ws).unwrap();
        let stage1 = experiments.iter().filter(|e| e.tuning.is_some()).count();
        assert_eq!(stage1, 2 * TRIALS_PER_METHOD as usize);
        let pending = extend_with_stage2(
            &mut experiments,
            &plan.methods,
            &[],
            KeepTrajectories::Figures,
        )
        .unwrap();
        // 2 methods × 16 trials × 3 tuning seeds (--quick).
        assert_eq!(pending, Some((96, 96)));
        assert!(
            !experiments
                .iter()
                .any(|e| e.tuning.as_ref().is_some_and(|run| run.held_out))
        );

        // Two shards: each holds part of stage 1, so neither plans stage 2.
        for k in 1..=2 {
            let mode = RunModeArgs {
                shard: Some(format!("{k}/2")),
                ..RunModeArgs::default()
            };
            run(&ws, tiny(&format!("shard{k}"), suites.clone()), mode).unwrap();
        }
        let failure = merge(
            &MergeArgs {
                plan: tiny("merged", suites.clone()),
                stores: vec!["shard1".into(), "shard2".into()],
                verify: None,
            },
            &ws,
        )
        .unwrap_err();
        assert_eq!(failure.exit_code, 1);
        assert!(
            failure.message.contains("stage 1 is complete")
                && failure.message.contains("stage 2 (4 runs"),
            "{}",
            failure.message
        );
        assert!(!ws.root.join("merged/REPORT.md").exists());
        // Now stage 1 is in the merged folder's store, and stage 2 is planned from it.
        let (plan, mut experiments) = prepare(&tiny("merged", suites.clone()), &ws).unwrap();
        let store = RunStore::open_read_only(&ws.root.join("merged"), &mut |_| {}).unwrap();
        let pending = extend_with_stage2(
            &mut experiments,
            &plan.methods,
            std::slice::from_ref(&store),
            KeepTrajectories::Figures,
        )
        .unwrap();
        assert_eq!(pending, None);
        let held_out: Vec<&str> = experiments
            .iter()
            .filter(|e| e.tuning.as_ref().is_some_and(|run| run.held_out))
            .map(|e| e.name.as_str())
            .collect();
        assert_eq!(held_out, ["task1-best-ea-madm", "task1-best-softmax"]);
        // The rerun of the same command runs stage 2 and reports.
        run(&ws, tiny("merged", suites.clone()), RunModeArgs::default()).unwrap();
        // One invocation does both stages in sequence, and writes the same outputs.
        run(&ws, tiny("whole", suites), RunModeArgs::default()).unwrap();
        for file in [
            "REPORT.md",
            "tuning.csv",
            "findings.json",
            "final-scores.csv",
        ] {
            assert_eq!(
                read(&ws.root.join("merged"), file),
                read(&ws.root.join("whole"), file),
                "{file}"
            );
        }
    }

    /// `tuning.csv` has its documented columns and one chosen trial per method, the best by
    /// the objective (the lowest index among equals); the "each at its best" verdicts are the
    /// claims judged on the chosen trials run again here on the held-out seeds, apart from the
    /// paper-setting verdicts, which are those of the plan without the suite.
    #[test]
    fn the_at_its_best_verdicts_of_a_tiny_plan() {
        let (_dir, ws) = workspace();
        run(
            &ws,
            tiny("tuned", vec![Suite::Tuning]),
            RunModeArgs::default(),
        )
        .unwrap();
        run(&ws, tiny("plain", vec![]), RunModeArgs::default()).unwrap();
        let (tuned, plain) = (ws.root.join("tuned"), ws.root.join("plain"));
        assert!(!plain.join("tuning.csv").exists());

        // tuning.csv: its columns, every trial, one chosen per method, the best.
        let text = read(&tuned, "tuning.csv");
        let mut csv = csv::Reader::from_reader(text.as_bytes());
        let header: Vec<String> = csv.headers().unwrap().iter().map(str::to_owned).collect();
        let names: Vec<&str> = TUNING_COLUMNS.iter().map(|c| c.name).collect();
        assert_eq!(header, names);
        let rows: Vec<csv::StringRecord> = csv.records().map(Result::unwrap).collect();
        assert_eq!(rows.len(), 2 * TRIALS_PER_METHOD as usize);
        let column = |name: &str| names.iter().position(|n| *n == name).unwrap();
        let mut chosen_trials = Vec::new();
        for method in ["ea-madm", "softmax"] {
            let of: Vec<&csv::StringRecord> = rows
                .iter()
                .filter(|r| &r[column("method")] == method)
                .collect();
            assert_eq!(of.len(), TRIALS_PER_METHOD as usize);
            let score = |r: &csv::StringRecord| r[column("score")].parse::<f64>().unwrap();
            let best = of
                .iter()
                .min_by(|a, b| score(a).total_cmp(&score(b)))
                .map(|r| score(r))
                .unwrap();
            let expected = of.iter().find(|r| score(r) == best).unwrap();
            let chosen: Vec<&&csv::StringRecord> = of
                .iter()
                .filter(|r| &r[column("chosen")] == "true")
                .collect();
            assert_eq!(chosen.len(), 1, "{method}");
            assert_eq!(chosen[0][column("trial")], expected[column("trial")]);
            assert!(of.iter().all(|r| &r[column("tuning_seeds")] == "3"));
            chosen_trials.push(expected[column("trial")].parse::<u32>().unwrap());
        }
        let package = read(&tuned, "datapackage.json");
        assert!(package.contains("\"path\": \"tuning.csv\""), "{package}");
        assert!(!read(&plain, "datapackage.json").contains("tuning.csv"));

        // The paper-setting verdicts are those of the plan without the suite.
        let findings = Findings::from_json(&read(&tuned, "findings.json")).unwrap();
        let without = Findings::from_json(&read(&plain, "findings.json")).unwrap();
        assert_eq!(findings.tasks, without.tasks);
        assert!(without.at_best.is_empty());
        let report = read(&tuned, "REPORT.md");
        let start = report
            .find(eamadm_present_heading())
            .expect("the report has the section");
        let end = start + report[start..].find("\n## Task I").unwrap() + 1;
        assert_eq!(
            format!("{}{}", &report[..start], &report[end..]),
            read(&plain, "REPORT.md"),
            "the report gains the section and nothing else changes"
        );

        // The at-its-best verdicts: the chosen trials run here, apart from the store.
        let [at_best] = &findings.at_best[..] else {
            panic!("one tuned task: {:?}", findings.at_best);
        };
        assert_eq!(at_best.task, "task1");
        let chosen: Vec<(&str, u32)> = at_best
            .chosen
            .iter()
            .map(|c| (c.method.as_str(), c.trial))
            .collect();
        assert_eq!(
            chosen,
            [("ea-madm", chosen_trials[0]), ("softmax", chosen_trials[1])]
        );
        let base = crate::experiments::quick(&eamadm::paper::task1());
        let base = eamadm::ExperimentConfig { seeds: 2, ..base };
        let tuning = TaskTuning::new(&base, &["ea-madm", "softmax"], TRIALS_PER_METHOD, 3).unwrap();
        let mut scores = Vec::new();
        for (method, trial) in chosen {
            let trial = tuning
                .trials
                .iter()
                .find(|t| t.method == method && t.trial == trial)
                .unwrap();
            let experiment = Experiment::new(trial.held_out(&base).unwrap()).unwrap();
            for record in experiment.run_all().unwrap() {
                let mut score = eamadm::scores::final_score_of(&record, &experiment).unwrap();
                score.task = "task1".to_owned();
                scores.push(score);
            }
        }
        let context =
            eamadm::paper::report_context_from_toml(&read(&tuned, "report-context.toml")).unwrap();
        let options = context.claim_options().unwrap();
        let judged = eamadm::claims::judge(&scores, &options).unwrap();
        let expected: Vec<(String, eamadm::claims::Verdict)> = judged
            .iter()
            .filter(|j| j.method == "ea-madm")
            .map(|j| (j.claim.id.to_owned(), j.verdict))
            .collect();
        let got: Vec<(String, eamadm::claims::Verdict)> = at_best
            .verdicts
            .iter()
            .map(|v| (v.claim.clone(), v.verdict))
            .collect();
        assert_eq!(got, expected);
        assert_eq!(got.len(), 3, "C1–C3 are claimed on Task I");
        let seeds = at_best.converged.seeds;
        assert_eq!(seeds, 2, "paired over the two held-out seeds");
    }

    fn eamadm_present_heading() -> &'static str {
        "## Each method at its best (same tuning budget)"
    }
}
