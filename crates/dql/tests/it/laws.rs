//! Mathematical laws of the learners, the schedules and the policies.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use dql::{
    Coin, DoubleQ, DoubleQParams, EpsilonGreedy, ExplorationPolicy, Greedy, Initialisation,
    Learner, QLearning, QLearningParams, Schedule, Softmax, argmax_random_tie, max_value,
};
use proptest::prelude::*;
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A double-Q learner with uniformly random tables (so cells are distinguishable)
/// plus a transition inside its shape.
#[derive(Debug, Clone)]
struct Case {
    n_states: usize,
    n_actions: usize,
    seed: u64,
    state: usize,
    action: usize,
    next_state: usize,
    other_next_state: usize,
    reward: f64,
    alpha: f64,
    gamma: f64,
    xi: f64,
    terminated: bool,
    /// Initialise with few distinct values, so argmax ties occur.
    coarse: bool,
}

fn case() -> impl Strategy<Value = Case> {
    (1_usize..6, 1_usize..5).prop_flat_map(|(n_states, n_actions)| {
        (
            (
                Just(n_states),
                Just(n_actions),
                any::<u64>(),
                0..n_states,
                0..n_actions,
                0..n_states,
                0..n_states,
            ),
            (
                -1e3_f64..1e3,
                0.001_f64..=1.0,
                0.0_f64..=1.0,
                0.0_f64..=1.0,
                any::<bool>(),
                any::<bool>(),
            ),
        )
            .prop_map(
                |(
                    (n_states, n_actions, seed, state, action, next_state, other_next_state),
                    (reward, alpha, gamma, xi, terminated, coarse),
                )| Case {
                    n_states,
                    n_actions,
                    seed,
                    state,
                    action,
                    next_state,
                    other_next_state,
                    reward,
                    alpha,
                    gamma,
                    xi,
                    terminated,
                    coarse,
                },
            )
    })
}

fn double_q(case: &Case, rng: &mut ChaCha8Rng) -> DoubleQ {
    let params = DoubleQParams {
        alpha: case.alpha,
        gamma: case.gamma,
        xi: case.xi,
        init: Initialisation::Uniform {
            low: -10.0,
            high: 10.0,
        },
        ..DoubleQParams::default()
    };
    let mut learner = DoubleQ::new(case.n_states, case.n_actions, params, rng).unwrap();
    if case.coarse {
        for s in 0..case.n_states {
            for a in 0..case.n_actions {
                let q1 = (learner.q1(s, a) / 4.0).round();
                let q2 = (learner.q2(s, a) / 4.0).round();
                learner.q1_row_mut(s)[a] = q1;
                learner.q2_row_mut(s)[a] = q2;
            }
        }
    }
    learner
}

fn q_learning(case: &Case, rng: &mut ChaCha8Rng) -> QLearning {
    let params = QLearningParams {
        alpha: case.alpha,
        gamma: case.gamma,
        init: Initialisation::Uniform {
            low: -10.0,
            high: 10.0,
        },
    };
    QLearning::new(case.n_states, case.n_actions, params, rng).unwrap()
}

/// Indices where two row-major tables differ.
fn changed_cells(before: &[f64], after: &[f64]) -> Vec<usize> {
    (0..before.len())
        .filter(|&i| before[i].to_bits() != after[i].to_bits())
        .collect()
}

proptest! {
    #[test]
    fn alpha_one_gamma_zero_sets_the_cell_to_the_reward(case in case()) {
        let case = Case { alpha: 1.0, gamma: 0.0, ..case };
        let mut rng = ChaCha8Rng::seed_from_u64(case.seed);
        let mut dq = double_q(&case, &mut rng);
        let mut q = q_learning(&case, &mut rng);
        let (s, a) = (case.state, case.action);
        let (q1_before, q2_before) = (dq.q1(s, a), dq.q2(s, a));
        dq.update(s, a, case.reward, case.next_state, case.terminated, &mut rng);
        q.update(s, a, case.reward, case.next_state, case.terminated, &mut rng);
        let (q1, q2) = (dq.q1(s, a), dq.q2(s, a));
        // Exactly one of the two tables holds the reward, the other is untouched.
        prop_assert!(
            (q1 == case.reward && q2.to_bits() == q2_before.to_bits())
                || (q2 == case.reward && q1.to_bits() == q1_before.to_bits()),
            "q1 {q1_before} -> {q1}, q2 {q2_before} -> {q2}, reward {}", case.reward
        );
        prop_assert_eq!(q.q1(s, a), case.reward);
    }

    /// The whole double-Q update against an independent reference model: one
    /// `u32` draw picks the table (ξ), the updated table's argmax at s' (ties at
    /// random, one draw only on a tie) picks the action the other table evaluates.
    #[test]
    fn double_q_update_touches_exactly_one_cell_of_one_table(case in case()) {
        let mut rng = ChaCha8Rng::seed_from_u64(case.seed);
        let mut learner = double_q(&case, &mut rng);
        let before = learner.clone();
        let mut reference_rng = rng.clone();
        learner.update(case.state, case.action, case.reward, case.next_state, case.terminated, &mut rng);

        // The ξ coin: one u32 draw u, heads iff u < ⌈ξ·2³²⌉, i.e. iff u < ξ·2³².
        let first = f64::from(reference_rng.next_u32()) < case.xi * 4_294_967_296.0;
        let (updated_before, other_before) = if first {
            (before.q1_table(), before.q2_table())
        } else {
            (before.q2_table(), before.q1_table())
        };
        let target = if case.terminated {
            case.reward
        } else {
            let best = argmax_random_tie(updated_before.row(case.next_state), &mut reference_rng);
            case.reward + case.gamma * other_before.get(case.next_state, best)
        };
        let old = updated_before.get(case.state, case.action);
        let expected = (1.0 - case.alpha) * old + case.alpha * target;
        let (updated_after, other_after) = if first {
            (learner.q1_table(), learner.q2_table())
        } else {
            (learner.q2_table(), learner.q1_table())
        };
        prop_assert_eq!(other_after, other_before);
        let changed = changed_cells(updated_before.as_slice(), updated_after.as_slice());
        let cell = case.state * case.n_actions + case.action;
        prop_assert!(changed.is_empty() || changed == vec![cell]);
        prop_assert_eq!(updated_after.get(case.state, case.action).to_bits(), expected.to_bits());
        // Both streams consumed the same draws.
        prop_assert_eq!(rng.random::<u64>(), reference_rng.random::<u64>());
        // The update counter moved for (s, a) only.
        for (i, (&now, &then)) in learner.update_counts().iter().zip(before.update_counts()).enumerate() {
            prop_assert_eq!(now, then + u32::from(i == cell));
        }
    }

    #[test]
    fn q_learning_update_touches_exactly_one_cell(case in case()) {
        let mut rng = ChaCha8Rng::seed_from_u64(case.seed);
        let mut learner = q_learning(&case, &mut rng);
        let before = learner.clone();
        learner.update(case.state, case.action, case.reward, case.next_state, case.terminated, &mut rng);
        let bootstrap = if case.terminated { 0.0 } else { before.q().max(case.next_state) };
        let old = before.q1(case.state, case.action);
        let expected = (1.0 - case.alpha) * old + case.alpha * (case.reward + case.gamma * bootstrap);
        let cell = case.state * case.n_actions + case.action;
        let changed = changed_cells(before.q().as_slice(), learner.q().as_slice());
        prop_assert!(changed.is_empty() || changed == vec![cell]);
        prop_assert_eq!(learner.q1(case.state, case.action).to_bits(), expected.to_bits());
        prop_assert_eq!(learner.update_count(case.state, case.action), 1);
    }

    #[test]
    fn terminal_update_ignores_the_next_state(case in case()) {
        let case = Case { terminated: true, ..case };
        let mut rng = ChaCha8Rng::seed_from_u64(case.seed);
        let dq = double_q(&case, &mut rng);
        let q = q_learning(&case, &mut rng);
        let (mut dq_a, mut dq_b, mut q_a, mut q_b) = (dq.clone(), dq, q.clone(), q);
        let (mut rng_a, mut rng_b) = (rng.clone(), rng);
        let (s, a, r) = (case.state, case.action, case.reward);
        dq_a.update(s, a, r, case.next_state, true, &mut rng_a);
        dq_b.update(s, a, r, case.other_next_state, true, &mut rng_b);
        q_a.update(s, a, r, case.next_state, true, &mut rng_a);
        q_b.update(s, a, r, case.other_next_state, true, &mut rng_b);
        prop_assert_eq!(dq_a, dq_b);
        prop_assert_eq!(q_a, q_b);
        prop_assert_eq!(rng_a.random::<u64>(), rng_b.random::<u64>());
    }

    #[test]
    fn behaviour_values_are_the_mean_of_the_estimators(case in case()) {
        let mut rng = ChaCha8Rng::seed_from_u64(case.seed);
        let learner = double_q(&case, &mut rng);
        let mut values = vec![0.0; case.n_actions];
        learner.action_values(case.state, &mut values);
        for (a, &value) in values.iter().enumerate() {
            let mean = 0.5 * (learner.q1(case.state, a) + learner.q2(case.state, a));
            prop_assert_eq!(value, mean);
        }
    }

    /// A coin is heads exactly when its one `u32` draw `u` satisfies `u < p·2³²`.
    #[test]
    fn coin_is_heads_below_its_threshold(p in prop_oneof![0.0_f64..=1.0, Just(0.0), Just(1.0)], seed in any::<u64>()) {
        let coin = Coin::new(p);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut reference = rng.clone();
        for _ in 0..20 {
            let expected = f64::from(reference.next_u32()) < p * 4_294_967_296.0;
            prop_assert_eq!(coin.flip(&mut rng), expected);
        }
        if p == 0.0 {
            prop_assert!(!(0..100).any(|_| coin.flip(&mut rng)));
        }
        if p == 1.0 {
            prop_assert!((0..100).all(|_| coin.flip(&mut rng)));
        }
    }

    #[test]
    fn exponential_schedules_stay_in_range_and_never_increase(
        start in 0.0_f64..=1.0,
        factor in prop_oneof![0.001_f64..=1.0, Just(1.0), 0.999_999_f64..1.0],
        floor_share in 0.0_f64..=1.0,
        episodes in 1_u64..3000,
    ) {
        let floor = start * floor_share;
        let schedule = Schedule::Exponential { start, factor, floor };
        EpsilonGreedy::new(schedule).unwrap();
        prop_assert_eq!(schedule.value(0), start);
        let mut previous = start;
        for episode in 0..=episodes {
            let value = schedule.value(episode);
            prop_assert!(floor <= value && value <= start, "episode {episode}: {value}");
            prop_assert!(value <= previous, "episode {episode}: {value} > {previous}");
            previous = value;
        }
    }

    /// The closed form agrees with the literal rule "ε ← max(floor, ε · factor)
    /// after every episode".
    #[test]
    fn exponential_schedule_is_repeated_multiplication(
        start in 0.01_f64..=10.0,
        factor in 0.5_f64..=1.0,
        floor_share in 0.01_f64..=1.0,
    ) {
        let floor = start * floor_share;
        let schedule = Schedule::Exponential { start, factor, floor };
        Softmax::new(schedule).unwrap();
        let mut literal = start;
        for episode in 0..200 {
            prop_assert_eq!(schedule.value(episode), literal.max(floor));
            literal = (literal * factor).max(floor);
        }
    }

    /// The O(1) step agrees bit for bit with the definition (`value`, repeated
    /// multiplication), walking the episodes in order and jumping about.
    #[test]
    fn the_incremental_schedule_value_is_the_definition(
        start in prop_oneof![0.0_f64..=1.0, Just(1.0), Just(0.0), 1e-300_f64..1e-290],
        factor in prop_oneof![0.001_f64..=1.0, Just(1.0), 0.999_f64..1.0],
        floor_share in prop_oneof![0.0_f64..=1.0, Just(0.0), Just(1.0)],
        jumps in prop::collection::vec(0_u64..50, 0..20),
    ) {
        let floor = start * floor_share;
        let schedule = Schedule::Exponential { start, factor, floor };
        let mut value = schedule.value(0);
        for episode in 0..1500 {
            prop_assert_eq!(value.to_bits(), schedule.value(episode).to_bits(), "episode {}", episode);
            prop_assert_eq!(schedule.value_from(episode, value, episode).to_bits(), value.to_bits());
            value = schedule.value_from(episode, value, episode + 1);
        }
        let (mut at, mut known) = (0_u64, schedule.value(0));
        for jump in jumps {
            let episode = if jump % 3 == 0 { at.saturating_sub(jump) } else { at + jump };
            let value = schedule.value_from(at, known, episode);
            prop_assert_eq!(value.to_bits(), schedule.value(episode).to_bits());
            (at, known) = (episode, value);
        }
        let constant = Schedule::Constant(start);
        prop_assert_eq!(constant.value_from(3, start, 4), start);
    }

    /// Policies walking episodes in order use the schedule's values exactly.
    #[test]
    fn policies_follow_their_schedule_bit_for_bit(
        start in 0.0_f64..=1.0,
        factor in 0.5_f64..=1.0,
        floor_share in 0.0_f64..=1.0,
        order in prop::collection::vec(0_u64..300, 1..30),
    ) {
        let floor = start * floor_share;
        let schedule = Schedule::Exponential { start, factor, floor };
        let mut greedy = EpsilonGreedy::new(schedule).unwrap();
        let mut softmax = Softmax::new(Schedule::Exponential { start: start + 0.01, factor, floor }).unwrap();
        let episodes = (0..300).chain(order);
        for episode in episodes {
            greedy.begin_episode(episode);
            softmax.begin_episode(episode);
            prop_assert_eq!(greedy.epsilon().to_bits(), schedule.value(episode).to_bits());
            prop_assert_eq!(softmax.temperature().to_bits(), softmax.schedule().value(episode).to_bits());
        }
    }

    #[test]
    fn softmax_probabilities_are_finite_and_sum_to_one(
        values in prop::collection::vec(-1e9_f64..=1e9, 1..10),
        log10_temperature in -6.0_f64..=3.0,
        seed in any::<u64>(),
    ) {
        let policy = Softmax::constant(10_f64.powf(log10_temperature)).unwrap();
        let mut probabilities = vec![0.0; values.len()];
        policy.probabilities(&values, &mut probabilities);
        let total: f64 = probabilities.iter().sum();
        prop_assert!((total - 1.0).abs() < 1e-12, "sum {total}");
        for (i, &p) in probabilities.iter().enumerate() {
            prop_assert!(p.is_finite() && (0.0..=1.0).contains(&p));
            for (j, &q) in probabilities.iter().enumerate() {
                if values[i] > values[j] {
                    prop_assert!(p >= q);
                }
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut policy = policy;
        for _ in 0..20 {
            let action = policy.select(0, &values, &mut rng);
            prop_assert!(probabilities[action] > 0.0);
        }
    }

    #[test]
    fn argmax_returns_a_maximiser(
        values in prop::collection::vec(prop_oneof![-3_i32..3, -1000_i32..1000], 1..12),
        seed in any::<u64>(),
    ) {
        let values: Vec<f64> = values.into_iter().map(f64::from).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let index = argmax_random_tie(&values, &mut rng);
        prop_assert_eq!(values[index], max_value(&values));
        let ties = values.iter().filter(|&&v| v == max_value(&values)).count();
        // A unique maximum consumes no randomness.
        let mut fresh = ChaCha8Rng::seed_from_u64(seed);
        if ties == 1 {
            prop_assert_eq!(rng.random::<u64>(), fresh.random::<u64>());
        }
    }

    /// Law: whatever the length (four values take their own unrolled path), the argmax is the
    /// documented draw — no draw for a unique maximum, else the `random_range(0..ties)`-th
    /// maximiser in index order — and leaves the generator where that rule leaves it.
    #[test]
    fn argmax_ties_are_the_documented_draw_at_every_length(
        values in prop::collection::vec(-1_i32..2, 1..9),
        seed in any::<u64>(),
    ) {
        let values: Vec<f64> = values.into_iter().map(f64::from).collect();
        let best = max_value(&values);
        let maximisers: Vec<usize> = (0..values.len()).filter(|&i| values[i] == best).collect();
        let mut expected_rng = ChaCha8Rng::seed_from_u64(seed);
        let expected = if maximisers.len() == 1 {
            maximisers[0]
        } else {
            maximisers[expected_rng.random_range(0..maximisers.len())]
        };
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        prop_assert_eq!(argmax_random_tie(&values, &mut rng), expected);
        prop_assert_eq!(rng.random::<u64>(), expected_rng.random::<u64>());
    }

    #[test]
    fn epsilon_zero_is_greedy(
        values in prop::collection::vec(prop_oneof![-3_i32..3, -1000_i32..1000], 1..12),
        seed in any::<u64>(),
    ) {
        let values: Vec<f64> = values.into_iter().map(f64::from).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut policy = EpsilonGreedy::constant(0.0).unwrap();
        let mut greedy = Greedy;
        for _ in 0..10 {
            prop_assert_eq!(values[policy.select(0, &values, &mut rng)], max_value(&values));
            prop_assert_eq!(values[greedy.select(0, &values, &mut rng)], max_value(&values));
        }
    }
}

/// Counts how often each action is selected in `draws` selections.
fn frequencies<P: ExplorationPolicy>(
    policy: &mut P,
    values: &[f64],
    draws: u32,
    seed: u64,
) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut counts = vec![0_u32; values.len()];
    for _ in 0..draws {
        counts[policy.select(0, values, &mut rng)] += 1;
    }
    counts
        .into_iter()
        .map(|c| f64::from(c) / f64::from(draws))
        .collect()
}

/// Sampling frequencies within `tolerance` of `expected`. With 200 000 draws the
/// standard error of a frequency is at most 0.0012, so a tolerance of 0.01 is
/// more than eight standard errors: a seeded check that cannot flake.
fn assert_close(observed: &[f64], expected: &[f64], tolerance: f64) {
    for (o, e) in observed.iter().zip(expected) {
        assert!(
            (o - e).abs() < tolerance,
            "observed {observed:?}, expected {expected:?}"
        );
    }
}

const DRAWS: u32 = 200_000;

#[test]
fn epsilon_one_is_uniform() {
    let values = [5.0, -1.0, 0.0, 2.0];
    let mut policy = EpsilonGreedy::constant(1.0).unwrap();
    assert_close(
        &frequencies(&mut policy, &values, DRAWS, 1),
        &[0.25; 4],
        0.01,
    );
}

#[test]
fn epsilon_greedy_mixes_greedy_and_uniform() {
    let values = [5.0, -1.0, 0.0, 2.0];
    let mut policy = EpsilonGreedy::constant(0.2).unwrap();
    assert_close(
        &frequencies(&mut policy, &values, DRAWS, 2),
        &[0.85, 0.05, 0.05, 0.05],
        0.01,
    );
}

#[test]
fn ties_are_broken_uniformly() {
    let values = [1.0, 3.0, 3.0, 0.0, 3.0];
    let third = 1.0 / 3.0;
    assert_close(
        &frequencies(&mut Greedy, &values, DRAWS, 3),
        &[0.0, third, third, 0.0, third],
        0.01,
    );
}

#[test]
fn softmax_samples_its_probabilities() {
    let values = [1.0, 0.5, 0.0, -2.0];
    let mut policy = Softmax::constant(0.5).unwrap();
    let mut expected = [0.0; 4];
    policy.probabilities(&values, &mut expected);
    assert_close(
        &frequencies(&mut policy, &values, DRAWS, 4),
        &expected,
        0.01,
    );
}

#[test]
fn softmax_survives_extreme_values_and_temperatures() {
    let values = [1e9, -1e9, 1e9, 0.0];
    for temperature in [1e-6, 1e-3, 1.0, 1e12] {
        let mut policy = Softmax::constant(temperature).unwrap();
        let mut probabilities = [0.0; 4];
        policy.probabilities(&values, &mut probabilities);
        assert!(probabilities.iter().all(|p| p.is_finite()));
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let action = policy.select(0, &values, &mut rng);
        assert!(action < 4);
    }
    // At T = 1e-6 the two maxima share all the mass.
    let policy = Softmax::constant(1e-6).unwrap();
    let mut probabilities = [0.0; 4];
    policy.probabilities(&values, &mut probabilities);
    assert_eq!(probabilities, [0.5, 0.0, 0.5, 0.0]);
    // The smallest positive temperature: 1/T overflows, the division does not.
    let policy = Softmax::constant(f64::MIN_POSITIVE * f64::EPSILON).unwrap();
    policy.probabilities(&values, &mut probabilities);
    assert_eq!(probabilities, [0.5, 0.0, 0.5, 0.0]);
}

#[test]
fn policies_follow_their_schedules_per_episode() {
    let mut epsilon = EpsilonGreedy::decreasing(0.95, 0.95, 0.0).unwrap();
    let mut softmax = Softmax::annealed(0.1, 0.95, 0.01).unwrap();
    assert_eq!(epsilon.epsilon(), 0.95);
    assert_eq!(softmax.temperature(), 0.1);
    epsilon.begin_episode(1);
    softmax.begin_episode(1);
    assert_eq!(epsilon.epsilon(), 0.95 * 0.95);
    assert_eq!(softmax.temperature(), 0.1 * 0.95);
    softmax.begin_episode(45);
    assert_eq!(softmax.temperature(), 0.01);
    softmax.begin_episode(44);
    assert!(softmax.temperature() > 0.01);
    epsilon.begin_episode(200);
    assert!((epsilon.epsilon() - 0.95 * 0.95_f64.powi(200)).abs() < 1e-15);
}

#[test]
fn coins_clamp_their_probability() {
    assert_eq!(Coin::new(f64::NAN), Coin::new(0.0));
    assert_eq!(Coin::new(-1.0), Coin::new(0.0));
    assert_eq!(Coin::new(2.0), Coin::new(1.0));
    assert_ne!(Coin::new(0.5), Coin::new(1.0));
}
