//! The runs of a plan as jobs: one per (experiment, method, seed), in job order (experiment,
//! then method as selected, then seed), each with its [`RunKey`] (a job's shard is
//! [`eamadm_runs::shard`]'s), and the job list as JSON lines for any job engine.

use eamadm::MethodSpec;
use serde::Serialize;

use crate::cli::ReproduceArgs;
use crate::experiments::PlannedExperiment;
use eamadm_runs::key::{ResumeError, RunDescription, RunKey};

/// One run to do.
#[derive(Debug, Clone)]
pub(crate) struct Job<'a> {
    /// Index of its experiment in the plan.
    pub(crate) experiment: usize,
    /// The method.
    pub(crate) method: &'a MethodSpec,
    /// The seed.
    pub(crate) seed: u64,
    /// The run's key.
    pub(crate) key: RunKey,
}

/// The jobs of `experiments` × `methods` × seeds, in job order.
pub(crate) fn plan_jobs<'a>(
    experiments: &'a [PlannedExperiment],
    methods: &[String],
) -> Result<Vec<Job<'a>>, ResumeError> {
    let mut jobs = Vec::new();
    for (index, planned) in experiments.iter().enumerate() {
        let config = planned.config();
        for label in methods {
            // Labels were checked against the config's; a label absent here is skipped.
            let Some(method) = config.method(label) else {
                continue;
            };
            for seed in config.seed_values() {
                let key = RunKey::of(&RunDescription::new(&planned.experiment, method, seed))?;
                jobs.push(Job {
                    experiment: index,
                    method,
                    seed,
                    key,
                });
            }
        }
    }
    Ok(jobs)
}

pub(crate) use eamadm_runs::shard::Shard;

/// One line of `--list-jobs`.
#[derive(Debug, Serialize)]
pub(crate) struct JobLine<'a> {
    /// The run's key.
    pub(crate) key: &'a str,
    /// The experiment (also the bundle and output folder name).
    pub(crate) experiment: &'a str,
    /// The task the experiment runs (`task1`, `task2`, `robot`, or `config` for a config file).
    pub(crate) task: &'a str,
    /// The method's label.
    pub(crate) method: &'a str,
    /// The seed.
    pub(crate) seed: u64,
    /// The `cargo xtask` arguments that run exactly this job into the plan's run store.
    pub(crate) run: Vec<String>,
}

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
        arguments.extend(["--readings".to_owned(), args.readings.name().to_owned()]);
    }
    for suite in &args.suites {
        arguments.extend(["--suite".to_owned(), suite.name().to_owned()]);
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
