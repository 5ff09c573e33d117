//! Why `claims` may pair runs by seed: every random stream of a run is keyed by the seed and
//! its purpose, never by the method's label or position, so two methods run on one seed draw
//! from the same streams (and the same pre-trained sub-tasks for EA-MADM and a sub-task alone,
//! which `controls.rs` checks).

use eamadm::{Experiment, RunRecord};

use crate::common::small_config;

#[test]
fn a_method_under_another_label_and_position_gives_the_same_run() {
    let mut config = small_config(20, 1);
    let mut copy = config.methods[0].clone();
    copy.label = format!("{}-copy", copy.label);
    config.methods.push(copy);
    let experiment = Experiment::new(config.clone()).unwrap();
    let run =
        |index: usize, seed| -> RunRecord { experiment.run(&config.methods[index], seed).unwrap() };
    let last = config.methods.len() - 1;
    let (original, copy) = (run(0, 7), run(last, 7));
    assert_eq!(original.episodes, copy.episodes);
    assert_eq!(original.evaluation, copy.evaluation);
    assert_eq!(original.subtasks, copy.subtasks);
    // Another seed draws other streams.
    assert_ne!(run(0, 8).episodes, original.episodes);
}
