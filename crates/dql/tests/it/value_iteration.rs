//! Value iteration against an independent exact answer: on tiny deterministic models, every
//! stationary deterministic policy evaluated in closed form (a path into a terminal step or a
//! cycle) and the best one taken per state.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use dql::{DeterministicModel, Transition, value_iteration};
use proptest::prelude::*;

/// `V^π(s)` of the deterministic policy `policy` (one action per state), exactly: follow the
/// path until a terminal step (a finite sum) or a state seen before (a discounted cycle, summed
/// as a geometric series).
fn policy_value(model: &DeterministicModel, policy: &[usize], start: usize, gamma: f64) -> f64 {
    let mut seen = vec![None; model.n_states()];
    let mut rewards = Vec::new();
    let mut state = start;
    loop {
        if let Some(first) = seen[state] {
            // rewards[first..] repeat forever.
            let head: f64 = rewards[..first]
                .iter()
                .enumerate()
                .map(|(i, r)| gamma.powi(i as i32) * r)
                .sum();
            let cycle: f64 = rewards[first..]
                .iter()
                .enumerate()
                .map(|(j, r)| gamma.powi(j as i32) * r)
                .sum();
            let length = (rewards.len() - first) as i32;
            return head + gamma.powi(first as i32) * cycle / (1.0 - gamma.powi(length));
        }
        seen[state] = Some(rewards.len());
        let step = model.transition(state, policy[state]);
        rewards.push(step.reward);
        if step.terminal {
            return rewards
                .iter()
                .enumerate()
                .map(|(i, r)| gamma.powi(i as i32) * r)
                .sum();
        }
        state = step.next;
    }
}

/// `Q*` by enumerating every deterministic stationary policy (an optimal one exists among them).
fn brute_force_q(model: &DeterministicModel, gamma: f64) -> Vec<f64> {
    let (n, m) = (model.n_states(), model.n_actions());
    let mut best = vec![f64::NEG_INFINITY; n];
    let mut policy = vec![0; n];
    loop {
        for (s, value) in best.iter_mut().enumerate() {
            *value = value.max(policy_value(model, &policy, s, gamma));
        }
        // the next policy, counting in base m
        let mut i = 0;
        while i < n && policy[i] + 1 == m {
            policy[i] = 0;
            i += 1;
        }
        if i == n {
            break;
        }
        policy[i] += 1;
    }
    (0..n * m)
        .map(|i| {
            let step = model.transition(i / m, i % m);
            step.reward
                + if step.terminal {
                    0.0
                } else {
                    gamma * best[step.next]
                }
        })
        .collect()
}

fn any_model() -> impl Strategy<Value = DeterministicModel> {
    (1..=4_usize, 1..=3_usize).prop_flat_map(|(n, m)| {
        proptest::collection::vec((0..n, -10..=10_i32, proptest::bool::weighted(0.3)), n * m)
            .prop_map(move |cells| {
                let transitions = cells
                    .into_iter()
                    .map(|(next, reward, terminal)| Transition {
                        next,
                        reward: f64::from(reward),
                        terminal,
                    })
                    .collect();
                DeterministicModel::new(n, m, transitions).unwrap()
            })
    })
}

proptest! {
    /// Value iteration is within its reported error bound (at most the tolerance) of the best
    /// policy's exact values, on every pair.
    #[test]
    fn value_iteration_equals_the_best_policy(
        model in any_model(),
        gamma in prop_oneof![Just(0.0), 0.0..0.99_f64],
    ) {
        let tolerance = 1e-9;
        let solved = value_iteration(&model, gamma, tolerance).unwrap();
        prop_assert!(solved.error_bound <= tolerance);
        let exact = brute_force_q(&model, gamma);
        for (i, (&got, &want)) in solved.q.as_slice().iter().zip(&exact).enumerate() {
            // rounding of the closed forms themselves: a few ulps of the largest value
            let slack = tolerance + 1e-12 * want.abs().max(1.0) / (1.0 - gamma);
            prop_assert!((got - want).abs() <= slack, "pair {i}: {got} vs {want}");
        }
    }

    /// The result is a fixed point of the Bellman optimality operator to within (1 + γ) times
    /// its error bound.
    #[test]
    fn value_iteration_is_a_bellman_fixed_point(
        model in any_model(),
        gamma in 0.0..0.99_f64,
    ) {
        let solved = value_iteration(&model, gamma, 1e-10).unwrap();
        let q = &solved.q;
        for s in 0..model.n_states() {
            for a in 0..model.n_actions() {
                let step = model.transition(s, a);
                let backup = step.reward + if step.terminal { 0.0 } else { gamma * q.max(step.next) };
                prop_assert!((backup - q.get(s, a)).abs() <= (1.0 + gamma) * solved.error_bound + 1e-12);
            }
        }
    }
}
