//! The runs of a plan as jobs ([`eamadm_runs::jobs`]: keys, job order, the job loop) for the
//! planned experiments, with a progress bar per experiment, and the job list as JSON lines for
//! any job engine.

use eamadm::Experiment;
use eamadm_runs::jobs::{ExecuteError, Executed};
use eamadm_runs::key::ResumeError;
use eamadm_runs::{KeepTrajectories, PretrainedStore, RunStore};

use crate::cli::ReproduceArgs;
use crate::experiments::PlannedExperiment;
use crate::progress::{Progress, TaskProgress};

pub(crate) use eamadm_runs::jobs::{Job, RunCounts};

/// The loaded experiments of `planned`, in plan order.
fn loaded(planned: &[PlannedExperiment]) -> Vec<&Experiment> {
    planned.iter().map(|planned| &planned.experiment).collect()
}

/// The jobs of `experiments` × `methods` × seeds, in job order.
pub(crate) fn plan_jobs<'a>(
    experiments: &'a [PlannedExperiment],
    methods: &[String],
) -> Result<Vec<Job<'a>>, ResumeError> {
    eamadm_runs::jobs::plan_jobs(&loaded(experiments), methods)
}

/// Runs the jobs the store lacks ([`eamadm_runs::jobs::run_jobs`]), one progress bar per
/// experiment counting its stored runs (those resumed counted at once).
pub(crate) fn run_jobs(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    store: &RunStore,
    artefacts: &PretrainedStore,
    keep: KeepTrajectories,
    progress: &Progress,
    warn: &(dyn Fn(&str) + Sync),
) -> Result<Executed, ExecuteError> {
    let bars: Vec<TaskProgress> = experiments
        .iter()
        .enumerate()
        .map(|(index, planned)| {
            let of_it = jobs.iter().filter(|job| job.experiment == index);
            let done = of_it
                .clone()
                .filter(|job| store.has(&job.key, keep))
                .count();
            let bar = progress.start(&planned.name, of_it.count() as u64);
            bar.skip_already_done(done as u64);
            bar
        })
        .collect();
    let stored = |job: &Job<'_>| bars[job.experiment].inc();
    let executed = eamadm_runs::jobs::run_jobs(
        &loaded(experiments),
        jobs,
        store,
        artefacts,
        keep,
        &stored,
        warn,
    )?;
    for bar in &bars {
        bar.finish();
    }
    Ok(executed)
}

pub(crate) use eamadm_runs::shard::Shard;

/// The plan options of `args` as command-line arguments (the same plan when given again), with
/// relative paths made absolute against `current_dir` so a job runs from any folder.
pub(crate) fn plan_arguments(
    args: &ReproduceArgs,
    out: &std::path::Path,
    current_dir: &std::path::Path,
) -> Vec<String> {
    let mut arguments = Vec::new();
    if let Some(seeds) = args.seeds {
        arguments.extend(["--seeds".to_owned(), seeds.to_string()]);
    }
    for task in &args.tasks {
        arguments.extend(["--task".to_owned(), task.name().to_owned()]);
    }
    for method in &args.methods {
        arguments.extend(["--method".to_owned(), method.clone()]);
    }
    if let Some(config) = &args.config {
        arguments.extend([
            "--config".to_owned(),
            current_dir.join(config).display().to_string(),
        ]);
    }
    arguments.extend(["--out".to_owned(), out.display().to_string()]);
    if args.quick {
        arguments.push("--quick".to_owned());
    }
    if args.keep_trajectories == crate::cli::KeepTrajectories::All {
        arguments.extend(["--keep-trajectories".to_owned(), "all".to_owned()]);
    }
    if args.readings != crate::cli::Readings::All {
        arguments.extend(["--readings".to_owned(), value_name(&args.readings)]);
    }
    for suite in &args.suites {
        arguments.extend(["--suite".to_owned(), value_name(suite)]);
    }
    if let Some(size) = args.family_size {
        arguments.extend(["--family-size".to_owned(), size.to_string()]);
    }
    if let Some(cache) = &args.pretrained_cache {
        arguments.extend([
            "--pretrained-cache".to_owned(),
            current_dir.join(cache).display().to_string(),
        ]);
    }
    arguments
}

/// The command-line name of a `--readings` or `--suite` value (clap's, from its derive).
fn value_name(value: &impl clap::ValueEnum) -> String {
    value
        .to_possible_value()
        .map_or_else(String::new, |value| value.get_name().to_owned())
}
