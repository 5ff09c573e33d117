//! The runs of a plan as jobs, and the loop that runs them into the run store.
//!
//! A [`Job`] is one (experiment, method, seed) with its [`RunKey`]; [`plan_jobs`] lists them in
//! job order (experiment, then method as selected, then seed; a job's shard is [`crate::shard`]'s).
//! [`run_jobs`] runs every job the store does not hold yet, in parallel with rayon, resuming: a
//! run the store already holds (checked) is skipped, and each finished run is appended to the
//! store as soon as it completes.
//!
//! Each run is a pure function of (config, method, seed) ([`eamadm::Experiment::run`]) and the
//! records are returned in job order, so the results do not depend on the number of threads,
//! on completion order, or on which runs were resumed.

use std::sync::atomic::{AtomicUsize, Ordering};

use eamadm::{
    Experiment, MethodSpec, PretrainConfig, PretrainedSubtask, PretrainingCache, RunError,
};
use rayon::prelude::*;
use thiserror::Error;

use crate::key::ResumeError;
use crate::{
    AppendReceipt, KeepTrajectories, PretrainedStore, PretrainingDescription, RunDescription,
    RunKey, RunStore, StoreError,
};

/// One run to do.
#[derive(Debug, Clone)]
pub struct Job<'a> {
    /// Index of its experiment in the plan.
    pub experiment: usize,
    /// The method.
    pub method: &'a MethodSpec,
    /// The seed.
    pub seed: u64,
    /// The run's key.
    pub key: RunKey,
}

impl<'a> Job<'a> {
    /// The job's line in a plan's job list (`reproduce-paper --list-jobs`): its experiment
    /// (`experiment`, running the task `task`), method and seed, and the command-line
    /// arguments that run exactly it: `run-job --key KEY` followed by the plan's own
    /// arguments `plan`.
    #[must_use]
    pub fn line(&'a self, experiment: &'a str, task: &'a str, plan: &[String]) -> JobLine<'a> {
        let mut run = vec![
            "run-job".to_owned(),
            "--key".to_owned(),
            self.key.to_string(),
        ];
        run.extend_from_slice(plan);
        JobLine {
            key: self.key.as_str(),
            experiment,
            task,
            method: &self.method.label,
            seed: self.seed,
            run,
        }
    }
}

/// One line of a plan's job list, for GNU parallel, SLURM or any job engine (serialised as one
/// JSON object).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct JobLine<'a> {
    /// The run's key.
    pub key: &'a str,
    /// The experiment (also the bundle and output folder name).
    pub experiment: &'a str,
    /// The task the experiment runs (`task1`, `task2`, `robot`, … or `config` for a config
    /// file, `family` for a family layout).
    pub task: &'a str,
    /// The method's label.
    pub method: &'a str,
    /// The seed.
    pub seed: u64,
    /// The command-line arguments that run exactly this job into the plan's run store.
    pub run: Vec<String>,
}

/// The jobs of `experiments` × `methods` × seeds, in job order. A label an experiment's
/// config lacks is skipped there (the caller checked the labels against the plan).
///
/// # Errors
/// A run whose description cannot be keyed ([`RunKey::of`]).
pub fn plan_jobs<'a>(
    experiments: &[&'a Experiment],
    methods: &[String],
) -> Result<Vec<Job<'a>>, ResumeError> {
    let mut jobs = Vec::new();
    for (index, experiment) in experiments.iter().enumerate() {
        let config = experiment.config();
        for label in methods {
            let Some(method) = config.method(label) else {
                continue;
            };
            for seed in config.seed_values() {
                let key = RunKey::of(&RunDescription::new(experiment, method, seed))?;
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

/// A run that failed, or a run file that could not be stored or read.
#[derive(Debug, Error)]
pub enum ExecuteError {
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
pub struct RunCounts {
    /// Runs computed now.
    pub ran: usize,
    /// Runs found in the store from an earlier invocation.
    pub resumed: usize,
    /// Sub-tasks pre-trained now (and stored as artefacts for other processes).
    pub pretrained: usize,
    /// Pre-trained sub-tasks loaded from the store's artefacts instead.
    pub pretrained_loaded: usize,
}

/// What [`run_jobs`] did, and the receipts of the runs it stored: with them the store is
/// reopened without reading those runs back ([`RunStore::open_with_receipts`]).
#[derive(Debug)]
pub struct Executed {
    /// The counts.
    pub counts: RunCounts,
    /// One receipt per run computed now, in no particular order.
    pub receipts: Vec<AppendReceipt>,
}

/// The run store's pre-trained artefacts ([`crate::pretrained`]) as the cache of
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
/// run to the store as soon as it completes, and calls `stored` with each job stored. Records
/// are dropped once stored, so memory holds only the runs in flight (and a receipt of each, a
/// few dozen bytes); the outputs are made afterwards from the store. Pre-trained sub-tasks are
/// looked for in, and stored to, `artefacts`; a damaged or unwritable artefact is passed to
/// `warn` and the sub-task trained again.
///
/// # Errors
/// A run that fails ([`ExecuteError::Run`]) or cannot be stored ([`ExecuteError::Store`]);
/// the runs stored before it stay stored.
pub fn run_jobs(
    experiments: &[&Experiment],
    jobs: &[Job<'_>],
    store: &RunStore,
    artefacts: &PretrainedStore,
    keep: KeepTrajectories,
    stored: &(dyn Fn(&Job<'_>) + Sync),
    warn: &(dyn Fn(&str) + Sync),
) -> Result<Executed, ExecuteError> {
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
    let batch = store.batch(crate::BatchLimit::default())?;
    let receipts = groups
        .par_iter()
        .map(|group| -> Result<Vec<AppendReceipt>, ExecuteError> {
            let experiment = experiments[group[0].experiment];
            let methods: Vec<&MethodSpec> = group.iter().map(|job| job.method).collect();
            let shared = experiment.share_pretraining_with(&methods, group[0].seed, &cache);
            group
                .par_iter()
                .map(|job| -> Result<AppendReceipt, ExecuteError> {
                    let record = experiment
                        .run_shared(job.method, job.seed, &shared)
                        .map_err(|source| ExecuteError::Run {
                            experiment: experiment.config().name.clone(),
                            source,
                        })?;
                    let receipt = batch.append(
                        &job.key,
                        &RunDescription::new(experiment, job.method, job.seed),
                        &record,
                        keep,
                    )?;
                    stored(job);
                    Ok(receipt)
                })
                .collect()
        })
        .collect::<Result<Vec<Vec<AppendReceipt>>, ExecuteError>>();
    // Synced whether or not a run failed: what was stored stays stored.
    let synced = batch.finish();
    let receipts: Vec<AppendReceipt> = receipts?.into_iter().flatten().collect();
    synced?;
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

    /// Task I's preset on `seeds` seeds, shortened to `episodes` episodes of at most 60 steps
    /// (as `reproduce-paper --quick` and then shorter).
    fn task1(seeds: u32, episodes: u64) -> eamadm::ExperimentConfig {
        let mut config = eamadm::paper::task1();
        config.seeds = seeds;
        config
            .shortened(&eamadm::Shortening::QUICK)
            .shortened(&eamadm::Shortening {
                maze_step_cap: Some(60),
                ..eamadm::Shortening::episodes(episodes)
            })
    }

    #[test]
    fn a_jobs_line_names_the_run_and_the_arguments_that_run_it() {
        let experiment = Experiment::new(task1(2, 3)).unwrap();
        let methods = ["softmax".to_owned()];
        let jobs = plan_jobs(&[&experiment], &methods).unwrap();
        assert_eq!(jobs.len(), 2);
        let plan = ["--seeds".to_owned(), "2".to_owned()];
        let line = jobs[1].line("task1", "task1", &plan);
        assert_eq!((line.method, line.seed), ("softmax", jobs[1].seed));
        assert_eq!(
            line.run,
            ["run-job", "--key", jobs[1].key.as_str(), "--seeds", "2"]
        );
        let json: serde_json::Value = serde_json::to_value(&line).unwrap();
        assert_eq!(json["key"], jobs[1].key.as_str());
        assert_eq!(json["experiment"], "task1");
    }

    /// Counts nothing (what a caller without progress bars passes).
    fn unseen(_: &Job<'_>) {}

    /// The artefact cache of a test's folder `dir` (beside its output folder).
    fn cache(dir: &std::path::Path) -> PretrainedStore {
        PretrainedStore::new(&dir.join("cache"))
    }

    #[test]
    fn resumed_runs_are_skipped_and_equal_fresh_ones() {
        let experiment = Experiment::new(task1(2, 4)).unwrap();
        let planned = [&experiment];
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
            &unseen,
            &quiet,
        )
        .unwrap();
        let counts = executed.counts;
        // One receipt per run computed, and the store reopened with them is the store read in
        // full.
        let mut received: Vec<&crate::RunKey> = executed
            .receipts
            .iter()
            .map(crate::AppendReceipt::key)
            .collect();
        received.sort();
        let mut planned_keys: Vec<&crate::RunKey> = jobs.iter().map(|job| &job.key).collect();
        planned_keys.sort();
        assert_eq!(received, planned_keys);
        let trusting =
            RunStore::open_with_receipts(dir.path(), &executed.receipts, &mut |w| panic!("{w}"))
                .unwrap();
        assert_eq!(trusting.keys(), open().keys());
        let subtasks = experiment.task().subtask_names().len();
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
            &unseen,
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
            let fresh = experiment.run(job.method, job.seed).unwrap();
            assert_eq!(stored.record, crate::compact(fresh, keep));
        }
    }

    /// Task I, shortened, with two EA-MADM methods (which pre-train the same sub-tasks) over
    /// `seeds` seeds: its planned experiment and jobs are made by the caller.
    fn two_ea_madm_methods(seeds: u32) -> (Experiment, Vec<String>) {
        let config = task1(seeds, 3);
        let methods: Vec<String> = config
            .methods
            .iter()
            .filter(|m| matches!(m.method, eamadm::Method::EaMadm(_)))
            .map(|m| m.label.clone())
            .take(2)
            .collect();
        assert_eq!(methods.len(), 2);
        (Experiment::new(config).unwrap(), methods)
    }

    fn artefact_files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
        let mut files: Vec<_> = std::fs::read_dir(dir.join("cache"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|path| !path.ends_with(crate::atomic::WRITERS_LOCK_FILE))
            .collect();
        files.sort();
        files
    }

    #[test]
    fn processes_sharing_a_folder_pretrain_each_subtask_once_and_equal_a_lone_run() {
        let (experiment, methods) = two_ea_madm_methods(2);
        let planned = [&experiment];
        let jobs = plan_jobs(&planned, &methods).unwrap();
        assert_eq!(jobs.len(), 4);
        let subtasks = experiment.task().subtask_names().len();
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
                &unseen,
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
            let fresh = experiment.run(job.method, job.seed).unwrap();
            assert_eq!(stored.record, crate::compact(fresh, keep));
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
        let (experiment, methods) = two_ea_madm_methods(1);
        let mut config = experiment.config().clone();
        config.task = eamadm::TaskConfig::MazeFile {
            path: map.clone(),
            rewards: eamadm::mazes::Preset::Task1,
            step_cap: Some(60),
        };
        let experiment = Experiment::new(config.clone()).unwrap();
        let planned = [&experiment];
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
            &unseen,
            &quiet,
        )
        .unwrap();
        // Every run stored under its planned key, its description hashing to it.
        let store = open();
        for job in &jobs {
            let stored = store.load(&job.key, keep).unwrap().unwrap();
            let fresh = experiment.run(job.method, job.seed).unwrap();
            assert_eq!(stored.record, crate::compact(fresh, keep));
        }
        // A plan loaded now reads the new map: other keys, and no artefact of the old map.
        let reloaded = Experiment::new(config).unwrap();
        let replanned = [&reloaded];
        let jobs = plan_jobs(&replanned, &methods).unwrap();
        assert!(jobs.iter().all(|job| !store.has(&job.key, keep)));
        let counts = run_jobs(
            &replanned,
            &jobs,
            &store,
            &cache(dir.path()),
            keep,
            &unseen,
            &quiet,
        )
        .unwrap()
        .counts;
        assert_eq!(counts.pretrained_loaded, 0, "{counts:?}");
        assert!(counts.pretrained > 0);
    }

    #[test]
    fn a_damaged_artefact_is_trained_again_with_a_warning() {
        let (experiment, methods) = two_ea_madm_methods(1);
        let planned = [&experiment];
        let jobs = plan_jobs(&planned, &methods).unwrap();
        let subtasks = experiment.task().subtask_names().len();
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
            &unseen,
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
            &unseen,
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
        let fresh = experiment.run(jobs[1].method, jobs[1].seed).unwrap();
        assert_eq!(stored.record, crate::compact(fresh, keep));
    }
}
