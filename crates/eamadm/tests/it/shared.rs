//! Sharing pre-training among the methods of a seed is an optimisation that cannot change a
//! bit: every record of `run_all` (shared per seed) and of `run_shared` equals the record of
//! `run` (each run pre-training for itself), at one and at two threads.

use eamadm::{Experiment, ExperimentConfig, Method, SharedPretraining};

/// `config` cut short: few episodes and pre-training episodes, two seeds, every method.
fn short(mut config: ExperimentConfig) -> ExperimentConfig {
    config.episodes = 6;
    config.seeds = 2;
    for spec in &mut config.methods {
        match &mut spec.method {
            Method::EaMadm(ea) => ea.pretrain.episodes = 6,
            Method::SubtaskGreedy(alone) => alone.pretrain.episodes = 6,
            _ => {}
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
