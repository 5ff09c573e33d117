//! Criterion benchmarks of the eamadm crates; the code is in `benches/benches/*.rs`, one file per
//! measured crate (`<crate>_<what>.rs`), run with `cargo bench -p eamadm-benches`.
//!
//! They live in their own package so that `cargo test` and `cargo test -p <crate>` never compile
//! criterion: a dev-dependency is built for every test target of the crate that declares it.
//!
//! The library holds one thing: [`reference_double_q`], the hand-written learning loop that
//! `benches/benches/ratios.rs` measures the project's end-to-end cost per step against
//! (issue 24), and [`reference_double_q_evaluated`], the same loop with the runner's periodic
//! greedy evaluations, so that the runner's work can be costed kind by kind (issue 33).
//!
//! ```
//! use eamadm::mazes::Preset;
//! let steps = eamadm_benches::reference_double_q(&Preset::Task1.env(), 3, 0.1, 7);
//! assert!(steps > 0);
//! ```

use eamadm::mazes::MazeEnv;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::{Duration, Instant};

/// Double Q-learning with ε-greedy exploration on `env`, written out by hand with nothing but
/// two flat tables, the maze's own transition lookup ([`MazeEnv::step_cursor`]) and one
/// `ChaCha8` stream: `episodes` episodes at a constant `epsilon`, α = 0.1, γ = 0.9 (Table 1's
/// learner). Returns the environment steps taken: the floor a step of the project's runner
/// is compared with.
#[must_use]
pub fn reference_double_q(env: &MazeEnv, episodes: u64, epsilon: f64, seed: u64) -> u64 {
    reference_double_q_evaluated(env, episodes, epsilon, seed, None).training_steps
}

/// What [`reference_double_q_evaluated`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReferenceRun {
    /// Environment steps of the learning episodes.
    pub training_steps: u64,
    /// Environment steps of the greedy evaluation episodes.
    pub greedy_steps: u64,
    /// Wall time spent in the greedy evaluation episodes (read around each one), so that the
    /// caller can cost a greedy step apart from a learning step.
    pub greedy_time: Duration,
}

/// [`reference_double_q`], and with `evaluate_every = Some(k)` also the runner's periodic
/// greedy evaluations written out by hand: after every `k`-th learning episode and once after
/// the last, one episode that follows `argmax (Q1 + Q2)` (first maximum) without learning and
/// without drawing from the stream, so the learning episodes are those of
/// [`reference_double_q`] step for step. The hand-written floor of the work a runner's
/// ε-greedy run does with `[evaluation] every = k` (`Some(0)`: only the one after the last).
///
/// ```
/// use eamadm::mazes::Preset;
/// let env = Preset::Task1.env();
/// let run = eamadm_benches::reference_double_q_evaluated(&env, 20, 0.1, 7, Some(10));
/// assert_eq!(run.training_steps, eamadm_benches::reference_double_q(&env, 20, 0.1, 7));
/// assert!(run.greedy_steps >= 3);
/// ```
#[must_use]
pub fn reference_double_q_evaluated(
    env: &MazeEnv,
    episodes: u64,
    epsilon: f64,
    seed: u64,
    evaluate_every: Option<u64>,
) -> ReferenceRun {
    const ACTIONS: usize = 4;
    const ALPHA: f64 = 0.1;
    const GAMMA: f64 = 0.9;
    let n_states = env.maze().n_tiles();
    let mut q1 = vec![0.0_f64; n_states * ACTIONS];
    let mut q2 = vec![0.0_f64; n_states * ACTIONS];
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let argmax = |q: &[f64], s: usize| {
        let row = &q[s * ACTIONS..(s + 1) * ACTIONS];
        let mut best = 0;
        for a in 1..ACTIONS {
            if row[a] > row[best] {
                best = a;
            }
        }
        best
    };
    let mut steps = 0;
    let (mut greedy_steps, mut greedy_time) = (0, Duration::ZERO);
    let mut greedy = |q1: &[f64], q2: &[f64]| {
        let start = Instant::now();
        let mut cursor = env.start_cursor();
        let mut state = cursor.state();
        loop {
            let row = s_sum(q1, q2, state);
            let mut best = 0;
            for a in 1..ACTIONS {
                if row[a] > row[best] {
                    best = a;
                }
            }
            let step = env.step_cursor(&mut cursor, best);
            greedy_steps += 1;
            if step.terminated || step.truncated {
                break;
            }
            state = step.next_state;
        }
        greedy_time += start.elapsed();
    };
    for episode in 0..episodes {
        let mut cursor = env.start_cursor();
        let mut state = cursor.state();
        loop {
            let action = if rng.random::<f64>() < epsilon {
                rng.random_range(0..ACTIONS)
            } else {
                let row = s_sum(&q1, &q2, state);
                let mut best = 0;
                for a in 1..ACTIONS {
                    if row[a] > row[best] {
                        best = a;
                    }
                }
                best
            };
            let step = env.step_cursor(&mut cursor, action);
            steps += 1;
            let next = step.next_state;
            let (update, other) = if rng.random::<bool>() {
                (&mut q1, &q2)
            } else {
                (&mut q2, &q1)
            };
            let target = if step.terminated {
                step.reward
            } else {
                step.reward + GAMMA * other[next * ACTIONS + argmax(update, next)]
            };
            let cell = &mut update[state * ACTIONS + action];
            *cell += ALPHA * (target - *cell);
            if step.terminated || step.truncated {
                break;
            }
            state = next;
        }
        if evaluate_every.is_some_and(|every| (episode + 1).is_multiple_of(every)) {
            greedy(&q1, &q2);
        }
    }
    if evaluate_every.is_some() {
        greedy(&q1, &q2);
    }
    ReferenceRun {
        training_steps: steps,
        greedy_steps,
        greedy_time,
    }
}

/// `q1 + q2` of `state`'s actions.
fn s_sum(q1: &[f64], q2: &[f64], state: usize) -> [f64; 4] {
    let at = state * 4;
    [0, 1, 2, 3].map(|a| q1[at + a] + q2[at + a])
}
