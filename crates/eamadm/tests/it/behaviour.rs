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

/// `report-context.toml` reads back to the very context it was written from, the robot's
/// behaviour floats bit for bit, so a folder's report can be rendered again byte for byte.
#[test]
fn the_report_context_round_trips_through_its_toml() {
    let mut config = eamadm::paper::robot();
    config.episodes = 6;
    config.seeds = 2;
    config
        .methods
        .retain(|spec| ["ea-madm", "softmax"].contains(&spec.label.as_str()));
    for spec in &mut config.methods {
        if let Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = 6;
        }
    }
    let records = Experiment::new(config.clone()).unwrap().run_all().unwrap();
    let mut context = eamadm::paper::report_context(true);
    let mut facts = eamadm::paper::experiment_facts("robot", "Robot", &config);
    facts.behaviour = behaviour(&records);
    facts.figures.files = vec!["steps.svg".to_owned()];
    facts.figures.captions = vec![("steps.svg".to_owned(), "a \"quoted\" ε caption".to_owned())];
    context.experiments.push(facts);
    let text = eamadm::paper::report_context_toml(&context).unwrap();
    let back = eamadm::paper::report_context_from_toml(&text).unwrap();
    assert_eq!(back, context);
    let bits = |c: &eamadm::facts::ReportContext| -> Vec<u64> {
        c.experiments[0]
            .behaviour
            .iter()
            .flat_map(|m| m.action_shares.iter().map(|x| x.to_bits()))
            .collect()
    };
    assert_eq!(bits(&back), bits(&context));
    assert!(eamadm::paper::report_context_from_toml("quick = 1").is_err());
}
