//! Reward constants are bounded (issue 14, items 1 and 2): a finite but huge reward passed
//! validation and overflowed the learning signal after other runs had been stored.

use mazes::{MAX_ABS_REWARD, SpecError, TaskSpec};

#[test]
fn huge_finite_rewards_are_refused_naming_the_field() {
    for value in [1e308, -1e308, 2e9] {
        let mut spec = TaskSpec::task1();
        spec.reward.target = value;
        match spec.validate().unwrap_err() {
            SpecError::RewardOutOfRange { field, limit, .. } => {
                assert_eq!(field, "reward.target");
                assert_eq!(limit, MAX_ABS_REWARD);
            }
            other => panic!("expected RewardOutOfRange, got {other}"),
        }
        let mut spec = TaskSpec::task2();
        spec.subtasks[1].reward.bump = value;
        let error = spec.validate().unwrap_err();
        assert!(
            error.to_string().contains("subtasks[1].reward.bump"),
            "{error}"
        );
    }
}

#[test]
fn rewards_up_to_the_bound_are_accepted() {
    let mut spec = TaskSpec::task1();
    spec.reward.target = MAX_ABS_REWARD;
    spec.reward.bump = -MAX_ABS_REWARD;
    assert!(spec.validate().is_ok());
}
