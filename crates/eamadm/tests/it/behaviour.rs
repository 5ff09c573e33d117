//! `eamadm::behaviour` on real (short) robot runs: shares are shares, agreement is a share of
//! EA-MADM's decisions, every sub-task reports its start-state values, and the success interval
//! contains the success share.

use eamadm::{Experiment, Method, behaviour};

#[test]
fn behaviour_of_a_short_robot_run_is_well_formed() {
    let mut config = eamadm::paper::robot();
    config.episodes = 8;
    config.seeds = 2;
    config
        .methods
        .retain(|spec| ["ea-madm", "softmax"].contains(&spec.label.as_str()));
    for spec in &mut config.methods {
        if let Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = 8;
        }
    }
    let records = Experiment::new(config).unwrap().run_all().unwrap();
    let methods = behaviour(&records);
    assert_eq!(
        methods
            .iter()
            .map(|m| m.method.as_str())
            .collect::<Vec<_>>(),
        ["ea-madm", "softmax"]
    );
    for method in &methods {
        assert_eq!(method.seeds, 2);
        assert_eq!(method.final_episodes, 16);
        let endings = method.final_endings;
        assert_eq!(endings.reached + endings.failed + endings.truncated, 16);
        assert_eq!(method.action_shares.len(), 5);
        let total: f64 = method.action_shares.iter().sum();
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        let success = method.success.unwrap();
        assert!(success.low <= success.estimate && success.estimate <= success.high);
        assert!(method.mean_final_steps >= 1.0);
    }
    let ea = &methods[0];
    assert_eq!(ea.subtasks.len(), 3);
    assert!(ea.decisions > 0);
    assert!(ea.dominant_subtask.is_some());
    for subtask in &ea.subtasks {
        assert_eq!(subtask.start_values.len(), 5);
        assert!((0.0..=1.0).contains(&subtask.agreement));
        assert!(subtask.best_start_action < 5);
        let endings = subtask.greedy_alone_endings;
        assert_eq!(endings.reached + endings.failed + endings.truncated, 2);
    }
    assert!(methods[1].subtasks.is_empty());
    assert_eq!(methods[1].dominant_subtask, None);
}
