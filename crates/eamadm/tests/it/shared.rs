//! Sharing pre-training among the methods of a seed is an optimisation that cannot change a
//! bit: every record of `run_all` (shared per seed) and of `run_shared` equals the record of
//! `run` (each run pre-training for itself), at one and at two threads.

use std::sync::Mutex;

use eamadm::{
    Experiment, ExperimentConfig, Method, PretrainConfig, PretrainedSubtask, PretrainingCache,
    SharedPretraining,
};

/// A cache in memory that counts what it is handed; `misfile` answers sub-task `k` with the
/// next sub-task's learner (a wrong artefact the facade must refuse).
#[derive(Default)]
struct MemoryCache {
    kept: Mutex<Vec<(PretrainConfig, usize, u64, PretrainedSubtask)>>,
    saves: Mutex<usize>,
    misfile: bool,
}

impl PretrainingCache for MemoryCache {
    fn load(
        &self,
        _: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        seed: u64,
    ) -> Option<PretrainedSubtask> {
        let kept = self.kept.lock().unwrap();
        let n = kept.iter().map(|(_, j, _, _)| j + 1).max().unwrap_or(1);
        let wanted = if self.misfile { (k + 1) % n } else { k };
        kept.iter()
            .find(|(p, j, s, _)| p == pretrain && *j == wanted && *s == seed)
            .map(|(_, _, _, subtask)| subtask.clone())
    }

    fn save(
        &self,
        _: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        seed: u64,
        subtask: &PretrainedSubtask,
    ) {
        *self.saves.lock().unwrap() += 1;
        let mut kept = self.kept.lock().unwrap();
        kept.retain(|(p, j, s, _)| !(p == pretrain && *j == k && *s == seed));
        kept.push((*pretrain, k, seed, subtask.clone()));
    }
}

/// Runs every job sharing through `cache`; returns the records in job order.
fn run_through(experiment: &Experiment, cache: &MemoryCache) -> Vec<eamadm::RunRecord> {
    let methods: Vec<_> = experiment.config().methods.iter().collect();
    experiment
        .jobs()
        .into_iter()
        .map(|(method, seed)| {
            let shared = experiment.share_pretraining_with(&methods, seed, cache);
            experiment.run_shared(method, seed, &shared).unwrap()
        })
        .collect()
}

/// `config` cut short: few episodes and pre-training episodes (the stopping rule checking
/// every 2, capped at 12), two seeds, every method.
fn short(mut config: ExperimentConfig) -> ExperimentConfig {
    config.episodes = 6;
    config.seeds = 2;
    for spec in &mut config.methods {
        let pretrain = match &mut spec.method {
            Method::EaMadm(ea) => &mut ea.pretrain,
            Method::SubtaskGreedy(alone) => &mut alone.pretrain,
            _ => continue,
        };
        pretrain.episodes = 6;
        if let Some(until) = pretrain.until.as_mut() {
            until.every = 2;
            until.max_episodes = 12;
        }
    }
    config
}

fn check(config: ExperimentConfig) {
    let experiment = Experiment::new(config).unwrap();
    let unshared: Vec<_> = experiment
        .jobs()
        .into_iter()
        .map(|(method, seed)| experiment.run(method, seed).unwrap())
        .collect();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let shared = pool.install(|| experiment.run_all().unwrap());
        assert_eq!(shared, unshared, "{threads} threads");
    }
    // A pre-training computed for another seed is not used (the run computes its own).
    let methods: Vec<_> = experiment.config().methods.iter().collect();
    let other_seed = experiment.share_pretraining(&methods, 99);
    assert!(other_seed.subtask_count() > 0);
    let (method, seed) = experiment.jobs()[0];
    assert_eq!(
        experiment.run_shared(method, seed, &other_seed).unwrap(),
        unshared[0]
    );
    assert_eq!(
        experiment
            .run_shared(method, seed, &SharedPretraining::none())
            .unwrap(),
        unshared[0]
    );
    // Through a cache that outlives the sharing (another process's artefacts): trained once
    // and handed over, then loaded, and the records do not change.
    let cache = MemoryCache::default();
    assert_eq!(run_through(&experiment, &cache), unshared);
    let trained = *cache.saves.lock().unwrap();
    let distinct = cache.kept.lock().unwrap().len();
    assert!(distinct > 0);
    *cache.saves.lock().unwrap() = 0;
    assert_eq!(run_through(&experiment, &cache), unshared);
    assert_eq!(*cache.saves.lock().unwrap(), 0, "everything loaded");
    // A cache handing back another sub-task's learner is refused: every sub-task is trained
    // again (at least once each; refused again for each job), and the records do not change.
    let misfiled = MemoryCache {
        kept: Mutex::new(cache.kept.into_inner().unwrap()),
        saves: Mutex::new(0),
        misfile: true,
    };
    if experiment.task().subtask_names().len() > 1 {
        assert_eq!(run_through(&experiment, &misfiled), unshared);
        assert!(*misfiled.saves.lock().unwrap() >= trained.min(distinct));
    }
}

#[test]
fn shared_maze_runs_equal_unshared_ones() {
    let config = short(eamadm::paper::task1());
    // The family shares: one training per sub-task, one prior per (pre-training, storage).
    let experiment = Experiment::new(config.clone()).unwrap();
    let methods: Vec<_> = experiment.config().methods.iter().collect();
    let shared = experiment.share_pretraining(&methods, 0);
    assert_eq!(shared.subtask_count(), 2);
    let ea_methods = methods
        .iter()
        .filter(|spec| matches!(spec.method, Method::EaMadm(_)))
        .count();
    assert!(
        (2..ea_methods).contains(&shared.prior_count()),
        "{} priors for {ea_methods} EA-MADM methods (tree and table storage at least)",
        shared.prior_count()
    );
    check(config);
}

#[test]
fn shared_robot_runs_equal_unshared_ones() {
    let mut config = short(eamadm::paper::robot());
    config
        .methods
        .retain(|spec| matches!(spec.method, Method::EaMadm(_)) || spec.label == "epsilon-greedy");
    check(config);
}
