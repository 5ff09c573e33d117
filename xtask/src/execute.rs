//! Runs every (experiment, method, seed) in parallel with rayon, resuming: a run the run store
//! under `<out>/runs/` already holds (checked) is skipped, and each finished run is appended to
//! the store as soon as it completes.
//!
//! Each run is a pure function of (config, method, seed) ([`eamadm::Experiment::run`]) and the
//! records are returned in job order, so the results do not depend on the number of threads,
//! on completion order, or on which runs were resumed.

use eamadm::{MethodSpec, RunError};
use eamadm_runs::{KeepTrajectories, RunDescription, RunStore, StoreError};
use rayon::prelude::*;
use thiserror::Error;

use crate::experiments::PlannedExperiment;
use crate::jobs::Job;
use crate::progress::{Progress, TaskProgress};

/// A run that failed, or a run file that could not be stored or read.
#[derive(Debug, Error)]
pub(crate) enum ExecuteError {
    /// Learning failed.
    #[error("experiment {experiment}: {source}")]
    Run {
        /// The experiment's name.
        experiment: String,
        /// The failure, naming method and seed.
        #[source]
        source: RunError,
    },
    /// Storing a run failed.
    #[error(transparent)]
    Store(#[from] StoreError),
}

/// What [`run_jobs`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct RunCounts {
    /// Runs computed now.
    pub(crate) ran: usize,
    /// Runs found in the store from an earlier invocation.
    pub(crate) resumed: usize,
}

/// Runs every job of `jobs` the store does not hold yet, in parallel, appending each finished
/// run to the store as soon as it completes. Records are dropped once stored, so memory holds
/// only the runs in flight; the outputs are made afterwards from the store ([`crate::finish`]).
pub(crate) fn run_jobs(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    store: &RunStore,
    keep: KeepTrajectories,
    progress: &Progress,
) -> Result<RunCounts, ExecuteError> {
    let bars: Vec<TaskProgress> = experiments
        .iter()
        .enumerate()
        .map(|(index, planned)| {
            let total = jobs.iter().filter(|job| job.experiment == index).count() as u64;
            let done = jobs
                .iter()
                .filter(|job| job.experiment == index && store.has(&job.key, keep))
                .count() as u64;
            let bar = progress.start(&planned.name, total);
            bar.skip_already_done(done);
            bar
        })
        .collect();
    let todo: Vec<&Job<'_>> = jobs
        .iter()
        .filter(|job| !store.has(&job.key, keep))
        .collect();
    // The runs of one (experiment, seed) share their pre-training: it is computed once per
    // group and dropped when the group's last run is stored, so memory holds the sub-task
    // tables of the seeds in flight only. Each record is still the pure function of
    // (config, method, seed) that `Experiment::run` computes.
    let mut groups: Vec<Vec<&Job<'_>>> = Vec::new();
    for job in &todo {
        match groups
            .iter_mut()
            .find(|group| group[0].experiment == job.experiment && group[0].seed == job.seed)
        {
            Some(group) => group.push(job),
            None => groups.push(vec![job]),
        }
    }
    groups
        .par_iter()
        .try_for_each(|group| -> Result<(), ExecuteError> {
            let planned = &experiments[group[0].experiment];
            let methods: Vec<&MethodSpec> = group.iter().map(|job| job.method).collect();
            let shared = planned
                .experiment
                .share_pretraining(&methods, group[0].seed);
            group
                .par_iter()
                .try_for_each(|job| -> Result<(), ExecuteError> {
                    let record = planned
                        .experiment
                        .run_shared(job.method, job.seed, &shared)
                        .map_err(|source| ExecuteError::Run {
                            experiment: planned.name.clone(),
                            source,
                        })?;
                    store.append(
                        &job.key,
                        &RunDescription::new(planned.config(), job.method, job.seed),
                        &record,
                        keep,
                    )?;
                    bars[job.experiment].inc();
                    Ok(())
                })
        })?;
    for bar in &bars {
        bar.finish();
    }
    Ok(RunCounts {
        ran: todo.len(),
        resumed: jobs.len() - todo.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::{Readings, Task};
    use crate::experiments::{plan_experiments, shorten};
    use crate::jobs::plan_jobs;

    #[test]
    fn resumed_runs_are_skipped_and_equal_fresh_ones() {
        // Task I only, without its readings' experiments.
        let mut planned =
            plan_experiments(&[Task::Task1], false, None, 2, true, Readings::None).unwrap();
        assert_eq!(planned.len(), 1);
        let mut config = planned[0].config().clone();
        shorten(&mut config, 4, Some(60), None);
        planned[0].experiment = eamadm::Experiment::new(config).unwrap();
        let methods = vec!["epsilon-greedy".to_owned(), "ea-madm".to_owned()];
        let jobs = plan_jobs(&planned, &methods).unwrap();
        assert_eq!(jobs.len(), 4);
        assert_eq!(jobs[0].method.label, "epsilon-greedy");
        let dir = tempfile::tempdir().unwrap();
        let keep = KeepTrajectories::Figures;
        let open = || RunStore::open(dir.path(), &mut |w: &str| panic!("{w}")).unwrap();
        let counts = run_jobs(&planned, &jobs, &open(), keep, &Progress::hidden()).unwrap();
        assert_eq!(counts, RunCounts { ran: 4, resumed: 0 });
        let store = open();
        let again = run_jobs(&planned, &jobs, &store, keep, &Progress::hidden()).unwrap();
        assert_eq!(again, RunCounts { ran: 0, resumed: 4 });
        for job in &jobs {
            let stored = store.load(&job.key, keep).unwrap().unwrap();
            let fresh = planned[0].experiment.run(job.method, job.seed).unwrap();
            assert_eq!(stored.record, eamadm_runs::compact(fresh, keep));
        }
    }
}
