//! Runs every (experiment, method, seed) in parallel with rayon, resuming: a run the run store
//! under `<out>/runs/` already holds (checked) is skipped, and each finished run is appended to
//! the store as soon as it completes.
//!
//! Each run is a pure function of (config, method, seed) ([`eamadm::Experiment::run`]) and the
//! records are returned in job order, so the results do not depend on the number of threads,
//! on completion order, or on which runs were resumed.

use std::sync::atomic::{AtomicUsize, Ordering};

use eamadm::{
    Experiment, MethodSpec, PretrainConfig, PretrainedSubtask, PretrainingCache, RunError,
};
use eamadm_runs::{
    AppendReceipt, KeepTrajectories, PretrainedStore, PretrainingDescription, RunDescription,
    RunStore, StoreError,
};
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
    /// Sub-tasks pre-trained now (and stored as artefacts for other processes).
    pub(crate) pretrained: usize,
    /// Pre-trained sub-tasks loaded from the store's artefacts instead.
    pub(crate) pretrained_loaded: usize,
}

/// What [`run_jobs`] did, and the receipts of the runs it stored: with them the store is
/// reopened without reading those runs back ([`RunStore::open_with_receipts`]).
#[derive(Debug)]
pub(crate) struct Executed {
    /// The counts.
    pub(crate) counts: RunCounts,
    /// One receipt per run computed now, in no particular order.
    pub(crate) receipts: Vec<AppendReceipt>,
}

/// The run store's pre-trained artefacts ([`eamadm_runs::pretrained`]) as the cache of
/// [`eamadm::Experiment::share_pretraining_with`], counting what it loads and what is trained.
/// A damaged artefact, or one that cannot be written, is a warning: the sub-task is trained
/// (again), which costs time, never a wrong bit.
struct ArtefactCache<'a> {
    artefacts: PretrainedStore,
    warn: &'a (dyn Fn(&str) + Sync),
    trained: AtomicUsize,
    loaded: AtomicUsize,
}

impl PretrainingCache for ArtefactCache<'_> {
    fn load(
        &self,
        experiment: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        seed: u64,
    ) -> Option<PretrainedSubtask> {
        let description = PretrainingDescription::new(experiment, pretrain, k, seed);
        match self.artefacts.load(&description) {
            Ok(Some(subtask)) => {
                self.loaded.fetch_add(1, Ordering::Relaxed);
                Some(subtask)
            }
            Ok(None) => None,
            Err(error) => {
                (self.warn)(&format!(
                    "{error}; ignored, sub-task {k} of seed {seed} is pre-trained again"
                ));
                None
            }
        }
    }

    fn save(
        &self,
        experiment: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        seed: u64,
        subtask: &PretrainedSubtask,
    ) {
        self.trained.fetch_add(1, Ordering::Relaxed);
        let description = PretrainingDescription::new(experiment, pretrain, k, seed);
        if let Err(error) = self.artefacts.save(&description, subtask) {
            (self.warn)(&format!(
                "{error}; other processes will pre-train this sub-task themselves"
            ));
        }
    }
}

/// Runs every job of `jobs` the store does not hold yet, in parallel, appending each finished
/// run to the store as soon as it completes. Records are dropped once stored, so memory holds
/// only the runs in flight (and a receipt of each, a few dozen bytes); the outputs are made
/// afterwards from the store ([`crate::finish`]).
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
    // tables of the seeds in flight only. Each sub-task is first looked for among the store's
    // pre-trained artefacts (another process, shard or experiment may have trained it) and
    // stored there once trained. Each record is still the pure function of
    // (config, method, seed) that `Experiment::run` computes.
    let cache = ArtefactCache {
        artefacts: artefacts.clone(),
        warn,
        trained: AtomicUsize::new(0),
        loaded: AtomicUsize::new(0),
    };
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
    // One file and one sync per batch of runs rather than per run (a group commit,
    // `eamadm_runs::LooseBatch`): a crash of the machine loses at most the last batches'
    // runs, which the next invocation finds torn or missing and recomputes.
    let batch = store.batch(eamadm_runs::BatchLimit::default())?;
    let receipts = groups
        .par_iter()
        .map(|group| -> Result<Vec<AppendReceipt>, ExecuteError> {
            let planned = &experiments[group[0].experiment];
            let methods: Vec<&MethodSpec> = group.iter().map(|job| job.method).collect();
            let shared = planned
                .experiment
                .share_pretraining_with(&methods, group[0].seed, &cache);
            group
                .par_iter()
                .map(|job| -> Result<AppendReceipt, ExecuteError> {
                    let record = planned
                        .experiment
                        .run_shared(job.method, job.seed, &shared)
                        .map_err(|source| ExecuteError::Run {
                            experiment: planned.name.clone(),
                            source,
                        })?;
                    let receipt = batch.append(
                        &job.key,
                        &RunDescription::new(&planned.experiment, job.method, job.seed),
                        &record,
                        keep,
                    )?;
                    bars[job.experiment].inc();
                    Ok(receipt)
                })
                .collect()
        })
        .collect::<Result<Vec<Vec<AppendReceipt>>, ExecuteError>>();
    // Synced whether or not a run failed: what was stored stays stored.
    let synced = batch.finish();
    let receipts: Vec<AppendReceipt> = receipts?.into_iter().flatten().collect();
    synced?;
    for bar in &bars {
        bar.finish();
    }
    Ok(Executed {
        counts: RunCounts {
            ran: todo.len(),
            resumed: jobs.len() - todo.len(),
            pretrained: cache.trained.into_inner(),
            pretrained_loaded: cache.loaded.into_inner(),
        },
        receipts,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::{Readings, Task};
    use crate::experiments::plan_experiments;
    use crate::jobs::plan_jobs;

    /// The artefact cache of a test's folder `dir` (beside its output folder).
    fn cache(dir: &std::path::Path) -> PretrainedStore {
        PretrainedStore::new(&dir.join("cache"))
    }

    #[test]
    fn resumed_runs_are_skipped_and_equal_fresh_ones() {
        // Task I only, without its readings' experiments.
        let mut planned =
            plan_experiments(&[Task::Task1], false, None, 2, true, Readings::None).unwrap();
        assert_eq!(planned.len(), 1);
        let config = planned[0].config().shortened(&eamadm::Shortening {
            maze_step_cap: Some(60),
            ..eamadm::Shortening::episodes(4)
        });
        planned[0].experiment = eamadm::Experiment::new(config).unwrap();
        let methods = vec!["epsilon-greedy".to_owned(), "ea-madm".to_owned()];
        let jobs = plan_jobs(&planned, &methods).unwrap();
        assert_eq!(jobs.len(), 4);
        assert_eq!(jobs[0].method.label, "epsilon-greedy");
        let dir = tempfile::tempdir().unwrap();
        let keep = KeepTrajectories::Figures;
        let open = || RunStore::open(dir.path(), &mut |w: &str| panic!("{w}")).unwrap();
        let quiet = |w: &str| panic!("{w}");
        let executed = run_jobs(
            &planned,
            &jobs,
            &open(),
            &cache(dir.path()),
            keep,
            &Progress::hidden(),
            &quiet,
        )
        .unwrap();
        let counts = executed.counts;
        // One receipt per run computed, and the store reopened with them is the store read in
        // full.
        let mut received: Vec<&eamadm_runs::RunKey> = executed
            .receipts
            .iter()
            .map(eamadm_runs::AppendReceipt::key)
            .collect();
        received.sort();
        let mut planned_keys: Vec<&eamadm_runs::RunKey> = jobs.iter().map(|job| &job.key).collect();
        planned_keys.sort();
        assert_eq!(received, planned_keys);
        let trusting =
            RunStore::open_with_receipts(dir.path(), &executed.receipts, &mut |w| panic!("{w}"))
                .unwrap();
        assert_eq!(trusting.keys(), open().keys());
        let subtasks = planned[0].experiment.task().subtask_names().len();
        assert_eq!(
            counts,
            RunCounts {
                ran: 4,
                resumed: 0,
                pretrained: 2 * subtasks,
                pretrained_loaded: 0
            }
        );
        let store = open();
        let again = run_jobs(
            &planned,
            &jobs,
            &store,
            &cache(dir.path()),
            keep,
            &Progress::hidden(),
            &quiet,
        )
        .unwrap()
        .counts;
        assert_eq!(
            again,
            RunCounts {
                ran: 0,
                resumed: 4,
                ..RunCounts::default()
            }
        );
        for job in &jobs {
            let stored = store.load(&job.key, keep).unwrap().unwrap();
            let fresh = planned[0].experiment.run(job.method, job.seed).unwrap();
            assert_eq!(stored.record, eamadm_runs::compact(fresh, keep));
        }
    }

    /// Task I, shortened, with two EA-MADM methods (which pre-train the same sub-tasks) over
    /// `seeds` seeds: its planned experiment and jobs are made by the caller.
    fn two_ea_madm_methods(seeds: u32) -> (Vec<PlannedExperiment>, Vec<String>) {
        let mut planned =
            plan_experiments(&[Task::Task1], false, None, seeds, true, Readings::None).unwrap();
        planned.truncate(1);
        let config = planned[0].config().shortened(&eamadm::Shortening {
            maze_step_cap: Some(60),
            ..eamadm::Shortening::episodes(3)
        });
        let methods: Vec<String> = config
            .methods
            .iter()
            .filter(|m| matches!(m.method, eamadm::Method::EaMadm(_)))
            .map(|m| m.label.clone())
            .take(2)
            .collect();
        assert_eq!(methods.len(), 2);
        planned[0].experiment = eamadm::Experiment::new(config).unwrap();
        (planned, methods)
    }

    fn artefact_files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        let mut files: Vec<_> = std::fs::read_dir(dir.join("cache"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|path| !path.ends_with(eamadm_runs::atomic::WRITERS_LOCK_FILE))
            .collect();
        files.sort();
        files
    }

    #[test]
    fn processes_sharing_a_folder_pretrain_each_subtask_once_and_equal_a_lone_run() {
        let (planned, methods) = two_ea_madm_methods(2);
        let jobs = plan_jobs(&planned, &methods).unwrap();
        assert_eq!(jobs.len(), 4);
        let subtasks = planned[0].experiment.task().subtask_names().len();
        let dir = tempfile::tempdir().unwrap();
        let keep = KeepTrajectories::Figures;
        let open = || RunStore::open(dir.path(), &mut |w: &str| panic!("{w}")).unwrap();
        let quiet = |w: &str| panic!("{w}");
        // One `run-job` (or shard) per job, one after the other, each its own store and cache,
        // as separate processes have.
        let mut trained = 0;
        let mut loaded = 0;
        for job in &jobs {
            let counts = run_jobs(
                &planned,
                std::slice::from_ref(job),
                &open(),
                &cache(dir.path()),
                keep,
                &Progress::hidden(),
                &quiet,
            )
            .unwrap()
            .counts;
            assert_eq!(counts.ran, 1);
            trained += counts.pretrained;
            loaded += counts.pretrained_loaded;
        }
        // Each (seed, sub-task) trained once, by the first job of its seed; the other loads.
        assert_eq!(trained, 2 * subtasks);
        assert_eq!(loaded, 2 * subtasks);
        assert_eq!(artefact_files(dir.path()).len(), 2 * subtasks);
        // Artefacts are not runs, and the records equal lone runs bit for bit.
        let store = open();
        assert_eq!(store.len(), 4);
        for job in &jobs {
            let stored = store.load(&job.key, keep).unwrap().unwrap();
            let fresh = planned[0].experiment.run(job.method, job.seed).unwrap();
            assert_eq!(stored.record, eamadm_runs::compact(fresh, keep));
        }
    }

    /// A `maze_file` config whose map is replaced while its runs are going (an editor saving,
    /// a sync tool): the runs, their keys and the pre-trained artefacts all belong to the map
    /// the experiment was loaded from. 9dc06af hashed the file again for every key, so its
    /// artefacts trained on the old map were stored under the new map's keys (and loaded by a
    /// later run on the new map), and its runs' descriptions did not hash to their keys.
    #[test]
    fn a_map_file_replaced_mid_run_changes_neither_the_runs_nor_their_keys() {
        let dir = tempfile::tempdir().unwrap();
        let map = dir.path().join("maze.map");
        let old_map = eamadm::mazes::Preset::Task1.maze().to_text();
        std::fs::write(&map, &old_map).unwrap();
        let (mut planned, methods) = two_ea_madm_methods(1);
        let mut config = planned[0].config().clone();
        config.task = eamadm::TaskConfig::MazeFile {
            path: map.clone(),
            rewards: eamadm::mazes::Preset::Task1,
            step_cap: Some(60),
        };
        planned[0].experiment = eamadm::Experiment::new(config.clone()).unwrap();
        let jobs = plan_jobs(&planned, &methods).unwrap();
        // Another map of the same size: one wall moved.
        let new_map = old_map.replacen(".#", "#.", 1);
        assert_ne!(new_map, old_map);
        std::fs::write(&map, &new_map).unwrap();
        let out = dir.path().join("out");
        let keep = KeepTrajectories::Figures;
        let open = || RunStore::open(&out, &mut |w: &str| panic!("{w}")).unwrap();
        let quiet = |w: &str| panic!("{w}");
        run_jobs(
            &planned,
            &jobs,
            &open(),
            &cache(dir.path()),
            keep,
            &Progress::hidden(),
            &quiet,
        )
        .unwrap();
        // Every run stored under its planned key, its description hashing to it.
        let store = open();
        for job in &jobs {
            let stored = store.load(&job.key, keep).unwrap().unwrap();
            let fresh = planned[0].experiment.run(job.method, job.seed).unwrap();
            assert_eq!(stored.record, eamadm_runs::compact(fresh, keep));
        }
        // A plan loaded now reads the new map: other keys, and no artefact of the old map.
        let mut replanned = planned.clone();
        replanned[0].experiment = eamadm::Experiment::new(config).unwrap();
        let jobs = plan_jobs(&replanned, &methods).unwrap();
        assert!(jobs.iter().all(|job| !store.has(&job.key, keep)));
        let counts = run_jobs(
            &replanned,
            &jobs,
            &store,
            &cache(dir.path()),
            keep,
            &Progress::hidden(),
            &quiet,
        )
        .unwrap()
        .counts;
        assert_eq!(counts.pretrained_loaded, 0, "{counts:?}");
        assert!(counts.pretrained > 0);
    }

    #[test]
    fn a_damaged_artefact_is_trained_again_with_a_warning() {
        let (planned, methods) = two_ea_madm_methods(1);
        let jobs = plan_jobs(&planned, &methods).unwrap();
        let subtasks = planned[0].experiment.task().subtask_names().len();
        let dir = tempfile::tempdir().unwrap();
        let keep = KeepTrajectories::Figures;
        let open = || RunStore::open(dir.path(), &mut |w: &str| panic!("{w}")).unwrap();
        let quiet = |w: &str| panic!("{w}");
        let first = run_jobs(
            &planned,
            &jobs[..1],
            &open(),
            &cache(dir.path()),
            keep,
            &Progress::hidden(),
            &quiet,
        )
        .unwrap()
        .counts;
        assert_eq!(first.pretrained, subtasks);
        let files = artefact_files(dir.path());
        let whole = std::fs::read(&files[0]).unwrap();
        std::fs::write(&files[0], &whole[..whole.len() - 9]).unwrap();
        let warnings = std::sync::Mutex::new(Vec::new());
        let collect = |w: &str| warnings.lock().unwrap().push(w.to_owned());
        let second = run_jobs(
            &planned,
            &jobs[1..],
            &open(),
            &cache(dir.path()),
            keep,
            &Progress::hidden(),
            &collect,
        )
        .unwrap()
        .counts;
        assert_eq!(
            (second.pretrained, second.pretrained_loaded),
            (1, subtasks - 1)
        );
        let warnings = warnings.into_inner().unwrap();
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("pre-trained again"), "{}", warnings[0]);
        // Trained again and stored again: the artefact is whole once more.
        assert_eq!(std::fs::read(&files[0]).unwrap(), whole);
        let stored = open().load(&jobs[1].key, keep).unwrap().unwrap();
        let fresh = planned[0]
            .experiment
            .run(jobs[1].method, jobs[1].seed)
            .unwrap();
        assert_eq!(stored.record, eamadm_runs::compact(fresh, keep));
    }
}
