//! Learner construction, accessors, behaviour values and persistence.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use dql::{
    BehaviourValues, DoubleQ, DoubleQParams, DqlError, Initialisation, Learner, QLearning,
    QLearningParams, QTable,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn trained_double_q() -> DoubleQ {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let params = DoubleQParams {
        init: Initialisation::Uniform {
            low: -1.0,
            high: 1.0,
        },
        ..DoubleQParams::default()
    };
    let mut learner = DoubleQ::new(3, 2, params, &mut rng).unwrap();
    for step in 0..20 {
        learner.update(
            step % 3,
            step % 2,
            1.0,
            (step + 1) % 3,
            step % 7 == 0,
            &mut rng,
        );
    }
    learner
}

#[test]
fn uniform_initialisation_draws_q1_then_q2_within_range() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let init = Initialisation::Uniform {
        low: -0.5,
        high: 0.25,
    };
    let params = DoubleQParams {
        init,
        ..DoubleQParams::default()
    };
    let learner = DoubleQ::new(4, 3, params, &mut rng).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let q1 = QTable::initialised(4, 3, &init, &mut rng).unwrap();
    let q2 = QTable::initialised(4, 3, &init, &mut rng).unwrap();
    assert_eq!(learner.q1_table(), q1);
    assert_eq!(learner.q2_table(), q2);
    assert!(
        q1.as_slice()
            .iter()
            .chain(q2.as_slice())
            .all(|v| (-0.5..0.25).contains(v))
    );
    assert_ne!(q1, q2);
}

#[test]
fn accessors_agree_with_each_other() {
    let learner = trained_double_q();
    let (q1, q2) = (learner.q1_table(), learner.q2_table());
    for s in 0..3 {
        assert_eq!(learner.q1_row(s), q1.row(s));
        assert_eq!(learner.q2_row(s), q2.row(s));
        for a in 0..2 {
            assert_eq!(learner.q1(s, a), q1.get(s, a));
            assert_eq!(learner.q2(s, a), q2.get(s, a));
        }
    }
    let rebuilt = DoubleQ::from_tables(*learner.params(), &q1, &q2).unwrap();
    assert_eq!(rebuilt.q1_table(), q1);
    assert_eq!(rebuilt.q2_table(), q2);
    assert!(rebuilt.update_counts().iter().all(|&c| c == 0));
    let total: u32 = learner.update_counts().iter().sum();
    assert_eq!(total, 20);
}

#[test]
fn behaviour_values_sum_or_mean() {
    let q1 = QTable::from_values(1, 3, vec![1.0, -2.0, 0.5]).unwrap();
    let q2 = QTable::from_values(1, 3, vec![3.0, 0.0, 0.5]).unwrap();
    let mut values = [0.0; 3];
    let mean = DoubleQ::from_tables(DoubleQParams::default(), &q1, &q2).unwrap();
    mean.action_values(0, &mut values);
    assert_eq!(values, [2.0, -1.0, 0.5]);
    let params = DoubleQParams {
        behaviour: BehaviourValues::Sum,
        ..DoubleQParams::default()
    };
    let sum = DoubleQ::from_tables(params, &q1, &q2).unwrap();
    sum.action_values(0, &mut values);
    assert_eq!(values, [4.0, -2.0, 1.0]);
}

#[test]
fn mismatched_tables_are_rejected() {
    let error = DoubleQ::from_tables(
        DoubleQParams::default(),
        &QTable::zeros(3, 2).unwrap(),
        &QTable::zeros(3, 4).unwrap(),
    )
    .unwrap_err();
    assert_eq!(
        error,
        DqlError::TableShapeMismatch {
            first_states: 3,
            first_actions: 2,
            second_states: 3,
            second_actions: 4
        }
    );
}

#[test]
fn an_out_of_range_action_is_an_error_and_writes_neither_estimator() {
    let mut learner = trained_double_q();
    let before = learner.clone();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let error = learner
        .try_update(0, 2, 1.0, 1, false, &mut rng)
        .unwrap_err();
    assert_eq!(
        error,
        DqlError::IndexOutOfRange {
            argument: "action",
            index: 2,
            len: 2
        }
    );
    assert_eq!(learner.q1_table(), before.q1_table());
    assert_eq!(learner.q2_table(), before.q2_table());
    assert_eq!(learner.update_counts(), before.update_counts());
}

#[test]
fn out_of_range_states_are_errors_naming_the_argument() {
    let mut learner = trained_double_q();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let n_states = learner.n_states();
    let error = learner
        .try_update(n_states, 0, 1.0, 0, false, &mut rng)
        .unwrap_err();
    assert!(matches!(
        error,
        DqlError::IndexOutOfRange {
            argument: "state",
            ..
        }
    ));
    let error = learner
        .try_update(0, 0, 1.0, n_states, false, &mut rng)
        .unwrap_err();
    assert!(matches!(
        error,
        DqlError::IndexOutOfRange {
            argument: "next_state",
            ..
        }
    ));
    learner.try_update(0, 1, 1.0, 1, false, &mut rng).unwrap();
}

#[test]
fn learners_round_trip_through_serde_with_validation() {
    let learner = trained_double_q();
    let json = serde_json::to_string(&learner).unwrap();
    let restored: DoubleQ = serde_json::from_str(&json).unwrap();
    // serde_json parses floats to within an ulp unless its `float_roundtrip`
    // feature is on; everything else must match exactly.
    assert_eq!(restored.params(), learner.params());
    assert_eq!(restored.update_counts(), learner.update_counts());
    for (table, original) in [
        (restored.q1_table(), learner.q1_table()),
        (restored.q2_table(), learner.q2_table()),
    ] {
        for (a, b) in table.as_slice().iter().zip(original.as_slice()) {
            assert!((a - b).abs() <= 1e-15, "{a} != {b}");
        }
    }

    let mut value: serde_json::Value = serde_json::from_str(&json).unwrap();
    value["update_counts"] = serde_json::json!([1, 2]);
    let error = serde_json::from_value::<DoubleQ>(value).unwrap_err();
    assert!(error.to_string().contains("2 update counts"), "{error}");
    let mut value: serde_json::Value = serde_json::from_str(&json).unwrap();
    value["params"]["alpha"] = serde_json::json!(0.0);
    let error = serde_json::from_value::<DoubleQ>(value).unwrap_err();
    assert!(error.to_string().contains("`alpha` = 0"), "{error}");

    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut q = QLearning::new(2, 2, QLearningParams::default(), &mut rng).unwrap();
    q.update(0, 1, 2.0, 1, false, &mut rng);
    let json = serde_json::to_string(&q).unwrap();
    let restored: QLearning = serde_json::from_str(&json).unwrap();
    assert_eq!(restored.update_counts(), q.update_counts());
    assert_eq!(restored.q().n_states(), 2);
    assert!((restored.q1(0, 1) - q.q1(0, 1)).abs() <= 1e-15);
}
