//! A snapshot of an episode restores it exactly: the restored environment continues bit for
//! bit as the original, wherever it is taken (mid-episode, after an end, across resets that
//! continue the noise stream), through JSON, and whatever the restoring environment did before.

use dql::{Environment, Step};
use proptest::prelude::*;
use wmr_model::{EpisodeSnapshot, Scenario, SnapshotError, WmrEnv};

/// Everything observable after one step, as bits.
fn observed(env: &WmrEnv, step: Option<Step>) -> Vec<u64> {
    let mut bits: Vec<u64> = env.sensor_values().iter().map(|r| r.to_bits()).collect();
    bits.extend(env.subtask_rewards().iter().map(|r| r.to_bits()));
    let m = env.metrics();
    bits.extend([
        m.time.to_bits(),
        m.task_return.to_bits(),
        m.path_length.to_bits(),
        m.retention_time.to_bits(),
        m.steps as u64,
        env.state() as u64,
        env.pose().translation.vector.x.to_bits(),
        env.pose().rotation.angle().to_bits(),
    ]);
    if let Some(step) = step {
        bits.extend([
            step.next_state as u64,
            step.reward.to_bits(),
            u64::from(step.terminated),
            u64::from(step.truncated),
        ]);
    }
    bits
}

/// Steps `env` with `actions`, resetting (without a seed: the noise stream continues) after
/// each end; returns what it observed.
fn drive(env: &mut WmrEnv, actions: &[usize]) -> Vec<Vec<u64>> {
    actions
        .iter()
        .map(|&action| {
            let step = env.step(action);
            let seen = observed(env, Some(step));
            if step.terminated || step.truncated {
                env.reset(None);
            }
            seen
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]

    #[test]
    fn a_restored_episode_continues_bit_for_bit(
        seed in any::<u64>(),
        before in prop::collection::vec(0..5usize, 0..150),
        after in prop::collection::vec(0..5usize, 1..150),
        elsewhere in prop::collection::vec(0..5usize, 0..60),
    ) {
        let mut scenario = Scenario::default_scenario();
        scenario.step_cap = 40;
        let mut original = WmrEnv::new(scenario.clone()).unwrap();
        original.reset(Some(seed));
        drive(&mut original, &before);
        let snapshot = original.snapshot();
        let text = serde_json::to_string(&snapshot).unwrap();
        let read: EpisodeSnapshot = serde_json::from_str(&text).unwrap();
        prop_assert_eq!(&read, &snapshot);

        // The restoring environment has its own history (another seed, other poses in memory).
        let mut restored = WmrEnv::new(scenario).unwrap();
        restored.reset(Some(seed ^ 0x5555));
        drive(&mut restored, &elsewhere);
        restored.restore(&read).unwrap();
        prop_assert_eq!(observed(&restored, None), observed(&original, None));
        prop_assert_eq!(restored.path(), original.path());
        prop_assert_eq!(drive(&mut restored, &after), drive(&mut original, &after));
    }
}

#[test]
fn a_snapshot_of_another_environment_is_refused_and_changes_nothing() {
    let mut small = Scenario::default_scenario();
    small.state.distance_bins = 2;
    small.state.target_bins = 0;
    let mut env = WmrEnv::new(small).unwrap();
    let mut big = WmrEnv::new(Scenario::default_scenario()).unwrap();
    // Find a step into a state the small discretisation does not have.
    let snapshot = (0..200)
        .find_map(|_| {
            let step = big.step(0);
            if step.terminated || step.truncated {
                big.reset(None);
            }
            (big.state() >= env.n_states()).then(|| big.snapshot())
        })
        .expect("the default state has more states than the small one");
    let before = observed(&env, None);
    let error = env.restore(&snapshot).unwrap_err();
    assert!(matches!(error, SnapshotError::State { .. }), "{error}");
    assert_eq!(observed(&env, None), before);

    let mut text: serde_json::Value = serde_json::to_value(env.snapshot()).unwrap();
    text["path"] = serde_json::json!([]);
    let no_path: EpisodeSnapshot = serde_json::from_value(text).unwrap();
    assert_eq!(env.restore(&no_path), Err(SnapshotError::Path));
}

/// A snapshot written before issue 36 renamed its fields (`readings` → `sensor_values`,
/// `metrics.outcome` → `metrics.status`) still reads, as the same snapshot: a pickled Python
/// environment of an earlier version unpickles.
#[test]
fn a_snapshot_with_the_old_field_names_reads_as_the_same_snapshot() {
    let mut env = WmrEnv::new(Scenario::default_scenario()).unwrap();
    env.reset(Some(3));
    env.step(0);
    let snapshot = env.snapshot();
    let mut old = serde_json::to_value(&snapshot).unwrap();
    let object = old.as_object_mut().unwrap();
    let values = object.remove("sensor_values").unwrap();
    object.insert("readings".to_owned(), values);
    let metrics = object["metrics"].as_object_mut().unwrap();
    let status = metrics.remove("status").unwrap();
    metrics.insert("outcome".to_owned(), status);
    let read: EpisodeSnapshot = serde_json::from_value(old).unwrap();
    assert_eq!(read, snapshot);
}
