//! Values a config may hold are bounded so that no validated config makes a non-finite Q-value
//! or reward (issue 14, items 1 and 2), and a non-finite decision row that appears anyway is a
//! typed run error, not a panic.

use eamadm::agent::EaMadmPolicy;
use eamadm::prior::PriorTable;
use eamadm::{ConfigError, Experiment, ExperimentConfig};

/// The issue's reproduction: a 2 × 2 inline maze, one EA-MADM method, the given initial value.
fn tiny_config(init: &str) -> String {
    format!(
        r#"
name = "tiny"
episodes = 3
seeds = 1

[task]
kind = "maze_text"
map = "S.\n.T\n"
rewards = "task1"
step_cap = 50

[learner]
alpha = 0.1
gamma = 0.95
init = {{ kind = "constant", value = {init} }}

[[methods]]
label = "ea-madm"
kind = "ea_madm"
epsilon = {{ constant = 0.1 }}
pretrain = {{ episodes = 3, epsilon = {{ constant = 0.5 }} }}
"#
    )
}

#[test]
fn huge_initial_values_are_refused_at_validation() {
    // 1e308 and -1e308 panicked in the agent, 5e307 ran; all are refused now.
    for init in ["1e308", "-1e308", "5e307", "2e9"] {
        let error = ExperimentConfig::from_toml_str(&tiny_config(init)).unwrap_err();
        assert!(matches!(error, ConfigError::Invalid { .. }), "{error}");
        assert_eq!(error.field(), Some("learner.init.value"), "{error}");
        assert!(error.to_string().contains("1e9"), "{error}");
        assert!(error.to_string().len() < 200, "readable: {error}");
    }
}

#[test]
fn the_largest_allowed_initial_values_run_to_finite_results() {
    for init in ["1e9", "-1e9"] {
        let experiment = Experiment::from_toml_str(&tiny_config(init)).unwrap();
        let (method, seed) = experiment.jobs()[0];
        let record = experiment.run(method, seed).unwrap();
        assert!(record.episodes.iter().all(|e| e.task_return.is_finite()));
    }
}

/// Should a decision row hold a non-finite value anyway, the policy still picks an action (it
/// cannot fail mid-step) and reports the error; the runner turns it into a `RunError`.
#[test]
fn a_non_finite_decision_row_is_reported_not_a_panic() {
    use rand::SeedableRng as _;
    let prior = PriorTable::from_fn(1, 3, 2, |_, _, _| Some(1.0));
    let mut policy = EaMadmPolicy::new(
        prior,
        dql::Schedule::Constant(0.0),
        madm_owa::Weighting::default(),
    )
    .unwrap();
    assert!(policy.failure().is_none());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
    let action = policy.decide(0, &[f64::INFINITY, 0.5, f64::NAN], &mut rng);
    assert_eq!(
        action, 1,
        "the rows that cannot be valued count as the worst"
    );
    assert!(policy.failure().is_some());
}
