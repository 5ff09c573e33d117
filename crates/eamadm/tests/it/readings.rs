//! A reading of the paper reruns only the methods it changes: a reading that changes nothing
//! reruns the base runs bit for bit, and `eamadm::sensitivity` finds every verdict holds
//! (moved from xtask's `sensitivity_report`).

use eamadm::claims::ClaimOptions;
use eamadm::paper::Reading;
use eamadm::sensitivity::{Change, ReadingRuns};
use eamadm::{Experiment, Role, RunRecord, Shortening};

#[test]
fn a_reading_that_changes_nothing_reruns_the_base_runs_bit_for_bit_and_holds() {
    let mut config = eamadm::paper::task1().shortened(&Shortening {
        maze_step_cap: Some(80),
        ..Shortening::episodes(6)
    });
    config.seeds = 2;
    let base = Experiment::new(config.clone()).unwrap();
    // A reading whose change is nothing, rerunning two of the paper's methods.
    let mut no_op = config.clone();
    no_op.name = "task1-reading-no-op".to_owned();
    no_op
        .methods
        .retain(|m| m.label == "softmax" || m.label == "epsilon-greedy");
    let rerun = Experiment::new(no_op.clone()).unwrap();
    let paper: Vec<_> = config
        .methods
        .iter()
        .filter(|m| m.role == Role::Paper)
        .collect();
    let mut base_scores = Vec::new();
    let mut reading = ReadingRuns {
        reading: "no-op".to_owned(),
        task: "task1".to_owned(),
        methods: no_op.methods.iter().map(|m| m.label.clone()).collect(),
        scores: Vec::new(),
    };
    for method in &paper {
        for seed in config.seed_values() {
            let record = base.run(method, seed).unwrap();
            base_scores.push(eamadm::scores::final_score_of(&record, &base).unwrap());
            if let Some(spec) = no_op.method(&method.label) {
                let again = rerun.run(spec, seed).unwrap();
                assert_eq!(again.experiment, "task1-reading-no-op");
                let renamed = RunRecord {
                    experiment: record.experiment.clone(),
                    ..again
                };
                assert_eq!(renamed, record, "{} seed {seed}", method.label);
                reading
                    .scores
                    .push(eamadm::scores::final_score_of(&renamed, &rerun).unwrap());
            }
        }
    }
    let rows = eamadm::sensitivity::sensitivity(&base_scores, &[reading], &ClaimOptions::default())
        .unwrap();
    assert_eq!(rows.len(), 3, "C1–C3 on Task I");
    assert!(
        rows.iter().all(|row| row.change == Change::Holds),
        "{rows:?}"
    );
    // A real reading on the same base does change its reruns.
    let gamma = Reading::Gamma099.apply(&config).unwrap();
    assert_eq!(gamma.learner.gamma, 0.99);
}
