//! Runs every (experiment, method, seed) in parallel with rayon, resuming: a run whose record is
//! already stored under `<out>/runs/` is loaded instead of rerun, and each finished run is stored
//! atomically as soon as it completes.
//!
//! Each run is a pure function of (config, method, seed) ([`eamadm::Experiment::run`]) and the
//! records are returned in job order, so the results do not depend on the number of threads,
//! on completion order, or on which runs were resumed.

use eamadm::config::{DEFAULT_SCENARIO, TaskConfig};
use eamadm::{ExperimentConfig, MethodSpec, RunError, RunRecord};
use rayon::prelude::*;
use serde::Serialize;
use thiserror::Error;

use crate::experiments::PlannedExperiment;
use crate::progress::{Progress, TaskProgress};
use crate::resume::{ResumeError, RunKey, RunStore};

/// Version of the numbers a run produces, in the resume key: bump it when a change of code
/// changes results without changing the config or the crate version, so that stored runs are
/// not reused.
pub(crate) const RESULTS_FORMAT: u32 = 1;

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
    /// Storing or loading a run file failed.
    #[error(transparent)]
    Resume(#[from] ResumeError),
}

/// What identifies a run for resuming: everything its record depends on.
#[derive(Debug, Serialize)]
pub(crate) struct RunDescription {
    /// [`RESULTS_FORMAT`].
    pub(crate) results_format: u32,
    /// The `eamadm` (workspace) version.
    pub(crate) crate_version: &'static str,
    /// The experiment's config with this method only, and the seed fields neutral (the seed is
    /// below), so the same run is recognised whatever `--seeds` or `--method` selected.
    pub(crate) config: ExperimentConfig,
    /// The run's seed.
    pub(crate) seed: u64,
    /// BLAKE3 of the file the task reads (a maze map or robot scenario named by path), whose
    /// content the config does not hold; absent for the embedded presets.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) task_file_blake3: Option<String>,
}

impl RunDescription {
    /// The description of running `method` with `seed` in `config`.
    pub(crate) fn new(config: &ExperimentConfig, method: &MethodSpec, seed: u64) -> Self {
        let config = ExperimentConfig {
            methods: vec![method.clone()],
            seeds: 1,
            base_seed: 0,
            ..config.clone()
        };
        Self {
            results_format: RESULTS_FORMAT,
            crate_version: env!("CARGO_PKG_VERSION"),
            task_file_blake3: task_file_digest(&config.task),
            config,
            seed,
        }
    }
}

/// The hash of the file `task` reads, if it names one (relative paths resolve as `eamadm`
/// resolves them: against the current folder). An unreadable file hashes as absent; loading
/// the task has already failed on it then.
fn task_file_digest(task: &TaskConfig) -> Option<String> {
    let path = match task {
        TaskConfig::MazeFile { path, .. } => path.clone(),
        TaskConfig::Robot { scenario, .. } if scenario != DEFAULT_SCENARIO => scenario.into(),
        _ => return None,
    };
    let bytes = std::fs::read(path).ok()?;
    Some(blake3::hash(&bytes).to_hex().to_string())
}

/// One run to do.
struct Job<'a> {
    experiment: usize,
    method: &'a MethodSpec,
    seed: u64,
    key: RunKey,
}

/// The records of one experiment, in method order (as selected), seed order within a method.
#[derive(Debug, Clone)]
pub(crate) struct ExperimentRecords {
    /// The experiment's records.
    pub(crate) records: Vec<RunRecord>,
    /// How many of them were loaded from an earlier invocation.
    pub(crate) resumed: usize,
}

/// Runs `methods` × seeds of every experiment, resuming from and storing into `store`.
pub(crate) fn run_experiments(
    experiments: &[PlannedExperiment],
    methods: &[String],
    store: &RunStore,
    progress: &Progress,
) -> Result<Vec<ExperimentRecords>, ExecuteError> {
    let mut jobs = Vec::new();
    for (index, planned) in experiments.iter().enumerate() {
        let config = planned.config();
        for label in methods {
            // Labels were checked against the config's; a label absent here is skipped.
            let Some(method) = config.method(label) else {
                continue;
            };
            for seed in config.seed_values() {
                let key = RunKey::of(&RunDescription::new(config, method, seed))?;
                jobs.push(Job {
                    experiment: index,
                    method,
                    seed,
                    key,
                });
            }
        }
    }
    let bars: Vec<TaskProgress> = experiments
        .iter()
        .enumerate()
        .map(|(index, planned)| {
            let total = jobs.iter().filter(|job| job.experiment == index).count() as u64;
            let done = jobs
                .iter()
                .filter(|job| job.experiment == index && store.is_done(&job.key))
                .count() as u64;
            let bar = progress.start(&planned.name, total);
            bar.skip_already_done(done);
            bar
        })
        .collect();

    let results: Vec<(usize, RunRecord, bool)> = jobs
        .par_iter()
        .map(|job| {
            let planned = &experiments[job.experiment];
            if let Some(record) = store.load::<RunRecord>(&job.key)? {
                return Ok((job.experiment, record, true));
            }
            let record = planned
                .experiment
                .run(job.method, job.seed)
                .map_err(|source| ExecuteError::Run {
                    experiment: planned.name.clone(),
                    source,
                })?;
            store.store(
                &job.key,
                &RunDescription::new(planned.config(), job.method, job.seed),
                &record,
            )?;
            bars[job.experiment].inc();
            Ok((job.experiment, record, false))
        })
        .collect::<Result<_, ExecuteError>>()?;
    for bar in &bars {
        bar.finish();
    }

    let mut grouped: Vec<ExperimentRecords> = experiments
        .iter()
        .map(|_| ExperimentRecords {
            records: Vec::new(),
            resumed: 0,
        })
        .collect();
    for (experiment, record, resumed) in results {
        grouped[experiment].records.push(record);
        grouped[experiment].resumed += usize::from(resumed);
    }
    Ok(grouped)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::Task;
    use crate::experiments::{plan_experiments, shorten};

    #[test]
    fn the_key_ignores_other_methods_and_the_seed_count() {
        let config = ExperimentConfig::paper_task1();
        let method = config.method("softmax").unwrap().clone();
        let key = |config: &ExperimentConfig, seed| {
            RunKey::of(&RunDescription::new(config, &method, seed)).unwrap()
        };
        let mut fewer = config.clone();
        fewer.seeds = 3;
        fewer.methods.truncate(4);
        assert_eq!(key(&config, 2), key(&fewer, 2));
        assert_ne!(key(&config, 2), key(&config, 3));
        let mut other = config.clone();
        other.episodes = 199;
        assert_ne!(key(&config, 2), key(&other, 2));
    }

    #[test]
    fn the_key_follows_the_content_of_a_task_file() {
        let dir = tempfile::tempdir().unwrap();
        let map = dir.path().join("maze.map");
        std::fs::write(&map, "S..\n.#.\n..T\n").unwrap();
        let mut config = ExperimentConfig::paper_task1();
        config.task = TaskConfig::MazeFile {
            path: map.clone(),
            rewards: eamadm::mazes::Preset::Task1,
            step_cap: None,
        };
        let method = config.methods[1].clone();
        let key = || RunKey::of(&RunDescription::new(&config, &method, 0)).unwrap();
        let before = key();
        std::fs::write(&map, "S.#\n...\n..T\n").unwrap();
        assert_ne!(key(), before);
        // The presets carry no file, so their keys do not change with this field.
        let preset = RunDescription::new(&ExperimentConfig::paper_task1(), &method, 0);
        assert_eq!(preset.task_file_blake3, None);
        assert!(
            !crate::resume::canonical_json(&preset)
                .unwrap()
                .contains("task_file")
        );
    }

    #[test]
    fn resumed_runs_equal_fresh_ones() {
        let mut planned = plan_experiments(&[Task::Task1], false, None, 2, true).unwrap();
        let mut config = planned[0].config().clone();
        shorten(&mut config, 4, Some(60), None);
        planned[0].experiment = eamadm::Experiment::new(config).unwrap();
        let methods = vec!["epsilon-greedy".to_owned(), "ea-madm".to_owned()];
        let dir = tempfile::tempdir().unwrap();
        let store = RunStore::new(dir.path());
        let fresh = run_experiments(&planned, &methods, &store, &Progress::hidden()).unwrap();
        assert_eq!(fresh[0].records.len(), 4);
        assert_eq!(fresh[0].resumed, 0);
        assert_eq!(fresh[0].records[0].method, "epsilon-greedy");
        let again = run_experiments(&planned, &methods, &store, &Progress::hidden()).unwrap();
        assert_eq!(again[0].resumed, 4);
        assert_eq!(again[0].records, fresh[0].records);
    }
}
