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
