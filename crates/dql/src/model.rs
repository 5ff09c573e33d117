//! A deterministic tabular model of a task and its exact action values by value iteration.
//!
//! A [`DeterministicModel`] says, for every state `s` and action `a`, where the step goes, what
//! it pays and whether it ends the episode ([`Transition`]). [`value_iteration`] computes the
//! optimal action values of that model,
//!
//! ```text
//! Q*(s, a) = r(s, a) + γ · [not terminal(s, a)] · max_a' Q*(s'(s, a), a'),
//! ```
//!
//! the fixed point the learners of this crate approach when every pair keeps being visited
//! (Watkins and Dayan 1992; van Hasselt 2010). The model is the infinite-horizon one: a step
//! cap that *truncates* an episode is not part of it, exactly as the learners bootstrap on a
//! truncated step ([`Step`](crate::Step)). Only a *terminal* transition stops the sum.
//!
//! Value iteration applies the Bellman optimality operator `T` to the whole table at once
//! (Jacobi sweeps) starting from `Q₀ = 0`. `T` is a γ-contraction in the sup norm, so after a
//! sweep that changed no value by more than `δ`, `‖Q − Q*‖∞ ≤ γ δ / (1 − γ)` (Puterman 1994,
//! Thm. 6.3.1); the iteration stops as soon as that bound is at most the caller's tolerance,
//! and reports the bound it reached ([`ValueIteration::error_bound`]).
//!
//! ```
//! use dql::{DeterministicModel, Transition, value_iteration};
//!
//! // A corridor 0 → 1 → 2 (goal): "right" costs 1, entering the goal pays 10 and ends the
//! // episode; "left" bumps the wall in 0 and walks back elsewhere, costing 1.
//! let model = DeterministicModel::from_fn(3, 2, |s, a| match (s, a) {
//!     (1, 1) => Transition { next: 2, reward: 10.0, terminal: true },
//!     (_, 1) => Transition { next: (s + 1).min(2), reward: -1.0, terminal: false },
//!     (_, _) => Transition { next: s.saturating_sub(1), reward: -1.0, terminal: false },
//! })?;
//! let solved = value_iteration(&model, 0.9, 1e-12)?;
//! // From 0: one step of −1, then the goal: −1 + 0.9 · 10.
//! assert!((solved.q.get(0, 1) - 8.0).abs() < 1e-12);
//! assert!((solved.q.get(1, 1) - 10.0).abs() < 1e-12);
//! assert!(solved.error_bound <= 1e-12);
//! # Ok::<(), dql::DqlError>(())
//! ```

use serde::{Deserialize, Serialize};

use crate::error::{DqlError, check_param};
use crate::table::QTable;

/// One step of a [`DeterministicModel`]: taking an action in a state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Transition {
    /// The state the step leads to.
    pub next: usize,
    /// What the step pays.
    pub reward: f64,
    /// Whether the step ends the episode (no value follows it).
    pub terminal: bool,
}

/// A deterministic tabular task: one [`Transition`] per `(state, action)`, row-major.
///
/// Checked at construction: at least one state and one action, a successor inside the state
/// range for every pair, and finite rewards; so [`value_iteration`] always returns finite values
/// for `γ < 1`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeterministicModel {
    n_states: usize,
    n_actions: usize,
    transitions: Vec<Transition>,
}

impl DeterministicModel {
    /// The model with `transitions[s · n_actions + a]` for every pair.
    ///
    /// # Errors
    /// [`DqlError::InvalidShape`] for an empty or overflowing shape, [`DqlError::DataLength`]
    /// when there are not `n_states · n_actions` transitions, [`DqlError::IndexOutOfRange`]
    /// (`next_state`) for a successor outside the states, [`DqlError::InvalidParameter`] naming
    /// the state and action of a NaN or infinite reward.
    pub fn new(
        n_states: usize,
        n_actions: usize,
        transitions: Vec<Transition>,
    ) -> Result<Self, DqlError> {
        // The table's own shape check (both at least 1, no overflow).
        QTable::zeros(n_states, n_actions)?;
        if transitions.len() != n_states * n_actions {
            return Err(DqlError::DataLength {
                len: transitions.len(),
                n_states,
                n_actions,
            });
        }
        for (index, transition) in transitions.iter().enumerate() {
            if transition.next >= n_states {
                return Err(DqlError::IndexOutOfRange {
                    argument: "next_state",
                    index: transition.next,
                    len: n_states,
                });
            }
            if !transition.reward.is_finite() {
                return Err(DqlError::InvalidParameter {
                    name: format!(
                        "reward of state {}, action {}",
                        index / n_actions,
                        index % n_actions
                    ),
                    value: transition.reward,
                    expected: "a finite reward",
                });
            }
        }
        Ok(Self {
            n_states,
            n_actions,
            transitions,
        })
    }

    /// The model whose pair `(s, a)` is `transition(s, a)`.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn from_fn(
        n_states: usize,
        n_actions: usize,
        transition: impl Fn(usize, usize) -> Transition,
    ) -> Result<Self, DqlError> {
        QTable::zeros(n_states, n_actions)?;
        let transitions = (0..n_states)
            .flat_map(|s| (0..n_actions).map(move |a| (s, a)))
            .map(|(s, a)| transition(s, a))
            .collect();
        Self::new(n_states, n_actions, transitions)
    }

    /// Number of states.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.n_states
    }

    /// Number of actions.
    #[must_use]
    pub fn n_actions(&self) -> usize {
        self.n_actions
    }

    /// What taking `action` in `state` does.
    ///
    /// # Panics
    /// If `state` or `action` is out of range.
    #[must_use]
    pub fn transition(&self, state: usize, action: usize) -> Transition {
        assert!(action < self.n_actions, "action out of range");
        self.transitions[state * self.n_actions + action]
    }

    /// Every transition, row-major (`s · n_actions + a`).
    #[must_use]
    pub fn transitions(&self) -> &[Transition] {
        &self.transitions
    }
}

/// What [`value_iteration`] computed.
#[derive(Debug, Clone, PartialEq)]
pub struct ValueIteration {
    /// The action values, within [`error_bound`](Self::error_bound) of `Q*` in every cell.
    pub q: QTable,
    /// Bellman sweeps made.
    pub sweeps: u64,
    /// The largest change of a value in the last sweep.
    pub last_change: f64,
    /// `γ · last_change / (1 − γ)`: an upper bound of `|Q(s, a) − Q*(s, a)|` for every pair
    /// (0 when the last sweep changed nothing).
    pub error_bound: f64,
}

/// Most sweeps [`value_iteration`] makes. A sweep shrinks the distance to `Q*` by the factor γ,
/// so this is only reached when rounding stops the last digits from settling; the result then
/// reports its (honest) [`ValueIteration::error_bound`].
pub const MAX_SWEEPS: u64 = 1_000_000;

/// The optimal action values of `model` at discount `gamma`, to within `tolerance` in every cell
/// (see the module docs for the operator and the bound).
///
/// # Errors
/// [`DqlError::InvalidParameter`] naming `gamma` (it must lie in `[0, 1)`: at 1 a model with a
/// loop that never terminates has no finite values) or `tolerance` (finite and positive).
pub fn value_iteration(
    model: &DeterministicModel,
    gamma: f64,
    tolerance: f64,
) -> Result<ValueIteration, DqlError> {
    check_param(
        "gamma",
        gamma,
        (0.0..1.0).contains(&gamma),
        "a discount in [0, 1)",
    )?;
    check_param(
        "tolerance",
        tolerance,
        tolerance.is_finite() && tolerance > 0.0,
        "a finite tolerance above 0",
    )?;
    let n_actions = model.n_actions;
    let mut q = vec![0.0; model.transitions.len()];
    let mut best = vec![0.0; model.n_states];
    let mut sweeps = 0;
    loop {
        for (state, value) in best.iter_mut().enumerate() {
            *value = q[state * n_actions..(state + 1) * n_actions]
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
        }
        let mut change: f64 = 0.0;
        for (cell, transition) in q.iter_mut().zip(&model.transitions) {
            let future = if transition.terminal {
                0.0
            } else {
                gamma * best[transition.next]
            };
            let updated = transition.reward + future;
            change = change.max((updated - *cell).abs());
            *cell = updated;
        }
        sweeps += 1;
        // γ δ / (1 − γ) ≤ tolerance, written without dividing by a small 1 − γ.
        if gamma * change <= tolerance * (1.0 - gamma) || sweeps >= MAX_SWEEPS {
            let error_bound = gamma * change / (1.0 - gamma);
            let q = QTable::from_values(model.n_states, n_actions, q)?;
            return Ok(ValueIteration {
                q,
                sweeps,
                last_change: change,
                error_bound,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stay(reward: f64) -> DeterministicModel {
        DeterministicModel::from_fn(1, 1, |_, _| Transition {
            next: 0,
            reward,
            terminal: false,
        })
        .unwrap()
    }

    /// A self-loop paying r forever is worth the geometric series r / (1 − γ).
    #[test]
    fn a_self_loop_is_the_geometric_series() {
        for (reward, gamma) in [(1.0, 0.5), (-1.0, 0.95), (2.5, 0.0), (-100.0, 0.9)] {
            let solved = value_iteration(&stay(reward), gamma, 1e-10).unwrap();
            let exact = reward / (1.0 - gamma);
            assert!(
                (solved.q.get(0, 0) - exact).abs() <= solved.error_bound.max(1e-12),
                "{reward} {gamma}: {} vs {exact}",
                solved.q.get(0, 0)
            );
            assert!(solved.error_bound <= 1e-10);
        }
    }

    /// With γ = 0 one sweep is exact: Q* is the reward.
    #[test]
    fn gamma_zero_is_the_reward_after_one_sweep() {
        let model = DeterministicModel::from_fn(2, 2, |s, a| Transition {
            next: 1 - s,
            reward: (3 * s + a) as f64,
            terminal: false,
        })
        .unwrap();
        let solved = value_iteration(&model, 0.0, 1e-9).unwrap();
        assert_eq!(solved.sweeps, 1);
        assert_eq!(solved.q.as_slice(), &[0.0, 1.0, 3.0, 4.0]);
        assert_eq!(solved.error_bound, 0.0);
    }

    /// A terminal step contributes its reward and nothing after it; the values of a chain
    /// ending in a terminal step are exact once its length has been swept.
    #[test]
    fn a_terminal_chain_is_exact() {
        // 0 → 1 → 2 → 3 (terminal step from 3), each paying 1; the second action of every
        // state ends the episode at once paying 0.5.
        let model = DeterministicModel::from_fn(4, 2, |s, a| match a {
            0 => Transition {
                next: (s + 1).min(3),
                reward: 1.0,
                terminal: s == 3,
            },
            _ => Transition {
                next: s,
                reward: 0.5,
                terminal: true,
            },
        })
        .unwrap();
        let gamma = 0.5;
        let solved = value_iteration(&model, gamma, 1e-15).unwrap();
        // Q*(3, 0) = 1; Q*(2, 0) = 1 + γ·1; Q*(1, 0) = 1 + γ + γ²; Q*(0, 0) = 1 + γ + γ² + γ³.
        let mut expected = 1.0;
        for s in (0..4).rev() {
            assert_eq!(solved.q.get(s, 0), expected, "state {s}");
            assert_eq!(solved.q.get(s, 1), 0.5);
            expected = 1.0 + gamma * expected;
        }
        assert_eq!(solved.last_change, 0.0);
    }

    /// A choice: a detour with a bigger prize loses to a shorter route when the discount eats
    /// the difference, and wins when it does not.
    #[test]
    fn the_discount_decides_between_near_and_far_prizes() {
        // From 0: action 0 reaches a prize of 1 in one step; action 1 walks 1 → 2 → 3 and
        // collects 4 on leaving 3. Every other step pays 0; state 4 is a sink.
        let model = DeterministicModel::from_fn(5, 2, |s, a| match (s, a) {
            (0, 0) => Transition {
                next: 4,
                reward: 1.0,
                terminal: true,
            },
            (0, 1) => Transition {
                next: 1,
                reward: 0.0,
                terminal: false,
            },
            (3, _) => Transition {
                next: 4,
                reward: 4.0,
                terminal: true,
            },
            (4, _) => Transition {
                next: 4,
                reward: 0.0,
                terminal: false,
            },
            (s, _) => Transition {
                next: s + 1,
                reward: 0.0,
                terminal: false,
            },
        })
        .unwrap();
        for (gamma, far_wins) in [(0.5, false), (0.9, true)] {
            let q = value_iteration(&model, gamma, 1e-14).unwrap().q;
            let far: f64 = 4.0 * gamma * gamma * gamma;
            assert!((q.get(0, 1) - far).abs() < 1e-12);
            assert_eq!(q.get(0, 0), 1.0);
            assert_eq!(q.get(0, 1) > q.get(0, 0), far_wins, "γ = {gamma}");
        }
    }

    #[test]
    fn bad_parameters_and_models_are_named() {
        let model = stay(1.0);
        for gamma in [1.0, -0.1, f64::NAN] {
            assert!(matches!(
                value_iteration(&model, gamma, 1e-9),
                Err(DqlError::InvalidParameter { name, .. }) if name == "gamma"
            ));
        }
        for tolerance in [0.0, -1.0, f64::INFINITY] {
            assert!(matches!(
                value_iteration(&model, 0.5, tolerance),
                Err(DqlError::InvalidParameter { name, .. }) if name == "tolerance"
            ));
        }
        let leaves = DeterministicModel::from_fn(2, 1, |_, _| Transition {
            next: 2,
            reward: 0.0,
            terminal: false,
        });
        assert!(matches!(
            leaves,
            Err(DqlError::IndexOutOfRange {
                argument: "next_state",
                index: 2,
                len: 2
            })
        ));
        let nan = DeterministicModel::from_fn(1, 2, |_, a| Transition {
            next: 0,
            reward: if a == 1 { f64::NAN } else { 0.0 },
            terminal: true,
        });
        assert!(matches!(
            nan,
            Err(DqlError::InvalidParameter { name, .. }) if name == "reward of state 0, action 1"
        ));
        assert!(matches!(
            DeterministicModel::new(1, 2, Vec::new()),
            Err(DqlError::DataLength { len: 0, .. })
        ));
        assert!(matches!(
            DeterministicModel::new(0, 2, Vec::new()),
            Err(DqlError::InvalidShape { .. })
        ));
    }
}
