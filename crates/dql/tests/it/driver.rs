//! The episode driver: reward signals, trajectories, caps, hooks and errors.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use crate::common;

use common::TableMdp;
use dql::{
    DoubleQ, DoubleQParams, DqlError, Environment, EpisodeOptions, ExplorationPolicy, Greedy,
    Learner, RewardSignal, Step, SubtaskRewardSignal, TaskRewardSignal, run_episode,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Plays a fixed action sequence (cycling), recording the hooks it sees.
struct Scripted {
    actions: Vec<usize>,
    next: usize,
    seen_states: Vec<usize>,
    begun: Vec<u64>,
    ended: Vec<u64>,
}

impl Scripted {
    fn new(actions: &[usize]) -> Self {
        Self {
            actions: actions.to_vec(),
            next: 0,
            seen_states: Vec::new(),
            begun: Vec::new(),
            ended: Vec::new(),
        }
    }
}

impl ExplorationPolicy for Scripted {
    fn begin_episode(&mut self, episode: u64) {
        self.begun.push(episode);
        self.next = 0;
    }
    fn end_episode(&mut self, episode: u64) {
        self.ended.push(episode);
    }
    fn select<R: Rng + ?Sized>(&mut self, state: usize, _values: &[f64], _rng: &mut R) -> usize {
        self.seen_states.push(state);
        let action = self.actions[self.next % self.actions.len()];
        self.next += 1;
        action
    }
}

fn learner(rng: &mut ChaCha8Rng) -> DoubleQ {
    DoubleQ::new(6, 4, DoubleQParams::new(1.0, 0.0).unwrap(), rng).unwrap()
}

const UP: usize = 0;
const DOWN: usize = 1;
const RIGHT: usize = 3;

#[test]
fn reports_task_return_steps_and_trajectory() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut env = TableMdp::grid(None);
    let mut learner = learner(&mut rng);
    // Bump up (−5), right (−1), right (−1), down into the goal (+10).
    let mut policy = Scripted::new(&[UP, RIGHT, RIGHT, DOWN]);
    let options = EpisodeOptions::new(7).recording();
    let outcome = run_episode(
        &mut env,
        &mut learner,
        &mut policy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )
    .unwrap();
    assert_eq!(outcome.steps, 4);
    assert_eq!(outcome.task_return, 3.0);
    assert_eq!(outcome.learning_return, 3.0);
    assert!(outcome.terminated && !outcome.truncated);
    let trajectory = outcome.trajectory.unwrap();
    assert_eq!(trajectory.states, vec![0, 0, 1, 2, 5]);
    assert_eq!(trajectory.actions, vec![UP, RIGHT, RIGHT, DOWN]);
    assert_eq!(policy.seen_states, vec![0, 0, 1, 2]);
    assert_eq!(
        (policy.begun.clone(), policy.ended.clone()),
        (vec![7], vec![7])
    );
    // α = 1, γ = 0: each visited pair holds its reward in the table that was updated.
    let experience: Vec<_> = learner
        .experience()
        .map(|e| (e.state, e.action, e.updates))
        .collect();
    assert_eq!(
        experience,
        vec![(0, UP, 1), (0, RIGHT, 1), (1, RIGHT, 1), (2, DOWN, 1)]
    );
    for sample in learner.experience() {
        let reward = if sample.state == 2 {
            10.0
        } else if sample.action == UP {
            -5.0
        } else {
            -1.0
        };
        assert!(sample.q1 == reward || sample.q2 == reward);
    }
}

#[test]
fn subtask_signal_drives_learning_but_task_return_is_reported() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut env = TableMdp::grid(None);
    let mut policy = Scripted::new(&[UP, RIGHT, RIGHT, DOWN]);
    let mut bumps = learner(&mut rng);
    let options = EpisodeOptions::new(0);
    let outcome = run_episode(
        &mut env,
        &mut bumps,
        &mut policy,
        &mut SubtaskRewardSignal(1),
        &mut rng,
        &options,
    )
    .unwrap();
    assert_eq!(outcome.task_return, 3.0);
    assert_eq!(outcome.learning_return, -5.0);
    // Sub-task 1 only pays for the bump.
    let learned: Vec<f64> = bumps
        .experience()
        .map(|e| if e.updates > 0 { e.q1 + e.q2 } else { 0.0 })
        .collect();
    assert_eq!(learned, vec![-5.0, 0.0, 0.0, 0.0]);

    let mut progress = learner(&mut rng);
    let outcome = run_episode(
        &mut env,
        &mut progress,
        &mut policy,
        &mut SubtaskRewardSignal(0),
        &mut rng,
        &options,
    )
    .unwrap();
    assert_eq!(outcome.learning_return, 8.0);
}

#[test]
fn custom_signal_sees_every_step_and_the_episode_start() {
    struct Combined {
        episodes: u32,
        seen: Vec<(f64, Vec<f64>)>,
    }
    impl RewardSignal for Combined {
        fn begin_episode(&mut self, n_subtasks: usize) -> Result<(), DqlError> {
            assert_eq!(n_subtasks, 2);
            self.episodes += 1;
            Ok(())
        }
        fn learning_reward(&mut self, step: &Step, subtask_rewards: &[f64]) -> f64 {
            self.seen.push((step.reward, subtask_rewards.to_vec()));
            subtask_rewards.iter().sum::<f64>() / 2.0
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut env = TableMdp::grid(None);
    let mut signal = Combined {
        episodes: 0,
        seen: Vec::new(),
    };
    // Bump up, right to 1, down into the pit.
    let mut policy = Scripted::new(&[UP, RIGHT, DOWN]);
    let options = EpisodeOptions::new(0).with_max_steps(10);
    let outcome = run_episode(
        &mut env,
        &mut learner(&mut rng),
        &mut policy,
        &mut signal,
        &mut rng,
        &options,
    )
    .unwrap();
    assert_eq!(signal.episodes, 1);
    assert_eq!(
        signal.seen,
        vec![
            (-5.0, vec![0.0, -5.0]),
            (-1.0, vec![-1.0, 0.0]),
            (-10.0, vec![-10.0, 0.0])
        ]
    );
    assert_eq!(outcome.learning_return, -8.0);
    assert_eq!(outcome.task_return, -16.0);
}

#[test]
fn caps_truncate_and_learning_can_be_switched_off() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut policy = Scripted::new(&[UP]);
    // The environment's own cap.
    let mut env = TableMdp::grid(Some(5));
    let mut learner = learner(&mut rng);
    let outcome = run_episode(
        &mut env,
        &mut learner,
        &mut policy,
        &mut TaskRewardSignal,
        &mut rng,
        &EpisodeOptions::new(0),
    )
    .unwrap();
    assert_eq!(
        (outcome.steps, outcome.terminated, outcome.truncated),
        (5, false, true)
    );
    // The driver's cap, without learning.
    let before = learner.clone();
    let mut env = TableMdp::grid(None);
    let options = EpisodeOptions::new(1)
        .with_max_steps(3)
        .without_learning()
        .with_seed(9);
    let outcome = run_episode(
        &mut env,
        &mut learner,
        &mut policy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )
    .unwrap();
    assert_eq!(
        (outcome.steps, outcome.terminated, outcome.truncated),
        (3, false, true)
    );
    assert_eq!(outcome.task_return, -15.0);
    assert_eq!(learner, before);
    assert!(outcome.trajectory.is_none());
}

#[test]
fn contract_violations_are_errors() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut env = TableMdp::grid(None);
    let mut small = DoubleQ::new(5, 4, DoubleQParams::default(), &mut rng).unwrap();
    let options = EpisodeOptions::new(0);
    let error = run_episode(
        &mut env,
        &mut small,
        &mut Greedy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )
    .unwrap_err();
    assert_eq!(
        error,
        DqlError::ShapeMismatch {
            what: "state count",
            environment: 6,
            learner: 5
        }
    );

    let mut learner = learner(&mut rng);
    let error = run_episode(
        &mut env,
        &mut learner,
        &mut Greedy,
        &mut SubtaskRewardSignal(2),
        &mut rng,
        &options,
    )
    .unwrap_err();
    assert_eq!(
        error,
        DqlError::SubtaskOutOfRange {
            index: 2,
            n_subtasks: 2
        }
    );
    assert!(error.to_string().contains("sub-task 2"));

    let mut policy = Scripted::new(&[RIGHT, 4]);
    let error = run_episode(
        &mut env,
        &mut learner,
        &mut policy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )
    .unwrap_err();
    assert_eq!(
        error,
        DqlError::ActionOutOfRange {
            action: 4,
            n_actions: 4,
            step: 2
        }
    );

    struct Broken;
    impl Environment for Broken {
        fn n_states(&self) -> usize {
            6
        }
        fn n_actions(&self) -> usize {
            4
        }
        fn reset(&mut self, _seed: Option<u64>) -> usize {
            0
        }
        fn step(&mut self, action: usize) -> Step {
            Step {
                next_state: if action == 0 { 6 } else { 1 },
                reward: f64::NAN,
                terminated: false,
                truncated: false,
            }
        }
    }
    let mut policy = Scripted::new(&[0]);
    let error = run_episode(
        &mut Broken,
        &mut learner,
        &mut policy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )
    .unwrap_err();
    assert_eq!(
        error,
        DqlError::StateOutOfRange {
            state: 6,
            n_states: 6,
            step: 1
        }
    );
    let mut policy = Scripted::new(&[1]);
    let before = learner.clone();
    let error = run_episode(
        &mut Broken,
        &mut learner,
        &mut policy,
        &mut TaskRewardSignal,
        &mut rng,
        &options,
    )
    .unwrap_err();
    assert!(matches!(
        error,
        DqlError::NonFiniteReward {
            which: "task",
            step: 1,
            ..
        }
    ));
    assert_eq!(learner, before);
}

#[test]
fn hyper_parameter_errors_name_the_parameter_and_value() {
    use dql::{EpsilonGreedy, Initialisation, QTable, Schedule, Softmax};
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let cases: Vec<(DqlError, &str)> = vec![
        (DoubleQParams::new(0.0, 0.9).unwrap_err(), "`alpha` = 0"),
        (DoubleQParams::new(1.5, 0.9).unwrap_err(), "`alpha` = 1.5"),
        (
            DoubleQParams::new(f64::NAN, 0.9).unwrap_err(),
            "`alpha` = NaN",
        ),
        (DoubleQParams::new(0.1, -0.1).unwrap_err(), "`gamma` = -0.1"),
        (
            DoubleQParams {
                xi: 1.1,
                ..DoubleQParams::default()
            }
            .validate()
            .unwrap_err(),
            "`xi` = 1.1",
        ),
        (
            DoubleQ::new(
                6,
                4,
                DoubleQParams {
                    init: Initialisation::Uniform {
                        low: 1.0,
                        high: 0.0,
                    },
                    ..DoubleQParams::default()
                },
                &mut rng,
            )
            .unwrap_err(),
            "`init.high` = 0",
        ),
        (EpsilonGreedy::constant(1.2).unwrap_err(), "`epsilon` = 1.2"),
        (
            EpsilonGreedy::decreasing(0.9, 1.5, 0.0).unwrap_err(),
            "`epsilon.factor` = 1.5",
        ),
        (
            EpsilonGreedy::decreasing(0.9, 0.0, 0.0).unwrap_err(),
            "`epsilon.factor` = 0",
        ),
        (
            EpsilonGreedy::decreasing(0.5, 0.9, 0.6).unwrap_err(),
            "`epsilon.floor` = 0.6",
        ),
        (Softmax::constant(0.0).unwrap_err(), "`temperature` = 0"),
        (
            Softmax::constant(f64::INFINITY).unwrap_err(),
            "`temperature` = inf",
        ),
        (
            Softmax::annealed(0.1, 0.95, 0.0).unwrap_err(),
            "`temperature.floor` = 0",
        ),
        (
            Softmax::new(Schedule::Exponential {
                start: -1.0,
                factor: 0.5,
                floor: 0.01,
            })
            .unwrap_err(),
            "`temperature.start` = -1",
        ),
    ];
    for (error, expected) in cases {
        assert!(
            error.to_string().contains(expected),
            "{error} does not contain {expected}"
        );
    }
    assert_eq!(
        QTable::zeros(0, 4).unwrap_err(),
        DqlError::InvalidShape {
            n_states: 0,
            n_actions: 4
        }
    );
    assert_eq!(
        QTable::zeros(3, 0).unwrap_err(),
        DqlError::InvalidShape {
            n_states: 3,
            n_actions: 0
        }
    );
    assert!(QTable::zeros(usize::MAX, 2).is_err());
    assert!(matches!(
        QTable::from_values(1, 2, vec![0.0, f64::NAN]).unwrap_err(),
        DqlError::NonFiniteValue { state: 0, action: 1, value } if value.is_nan()
    ));
}

#[test]
fn parameters_round_trip_through_serde_and_invalid_policies_do_not_deserialise() {
    use dql::{BuiltinPolicy, EpsilonGreedy, QTable, Softmax};
    let params: DoubleQParams = serde_json::from_str(r#"{"alpha": 0.1, "gamma": 0.95}"#).unwrap();
    assert_eq!(params, DoubleQParams::default());
    let json = serde_json::to_string(&DoubleQParams::default()).unwrap();
    assert_eq!(
        json,
        r#"{"alpha":0.1,"gamma":0.95,"xi":0.5,"init":{"kind":"zero"},"behaviour":"mean"}"#
    );

    let policy: BuiltinPolicy = serde_json::from_str(
        r#"{"kind": "softmax", "temperature": {"exponential": {"start": 0.1, "factor": 0.95, "floor": 0.01}}}"#,
    )
    .unwrap();
    assert_eq!(
        policy,
        BuiltinPolicy::Softmax(Softmax::annealed(0.1, 0.95, 0.01).unwrap())
    );
    let policy = BuiltinPolicy::from(EpsilonGreedy::constant(0.1).unwrap());
    let json = serde_json::to_string(&policy).unwrap();
    assert_eq!(
        json,
        r#"{"kind":"epsilon_greedy","epsilon":{"constant":0.1}}"#
    );
    assert_eq!(
        serde_json::from_str::<BuiltinPolicy>(&json).unwrap(),
        policy
    );
    let error =
        serde_json::from_str::<EpsilonGreedy>(r#"{"epsilon": {"constant": 2.0}}"#).unwrap_err();
    assert!(error.to_string().contains("`epsilon` = 2"), "{error}");

    let table = QTable::from_values(2, 2, vec![1.0, 2.0, 3.0, 4.0]).unwrap();
    let json = serde_json::to_string(&table).unwrap();
    assert_eq!(serde_json::from_str::<QTable>(&json).unwrap(), table);
    assert!(
        serde_json::from_str::<QTable>(r#"{"n_states":2,"n_actions":2,"values":[1.0]}"#).is_err()
    );
}
