//! Test-only environments shared by the integration tests.

#![allow(
    dead_code,
    unreachable_pub,
    reason = "each test module uses part of these shared helpers"
)]

use dql::{Environment, Step};

/// A deterministic tabular MDP given by its transition table, with an optional
/// step cap (truncation) and two sub-task rewards per step.
///
/// Sub-task 0 is "progress" (the task reward without bump penalties), sub-task 1
/// is "bumps" (−5 per bump, else 0).
#[derive(Debug, Clone)]
pub struct TableMdp {
    pub n_states: usize,
    pub n_actions: usize,
    /// `next[s * n_actions + a]`.
    pub next: Vec<usize>,
    pub reward: Vec<f64>,
    pub terminal: Vec<bool>,
    pub bump: Vec<bool>,
    pub start: usize,
    pub cap: Option<u64>,
    state: usize,
    steps: u64,
    subtask: [f64; 2],
}

impl TableMdp {
    /// A 2 × 3 grid:
    ///
    /// ```text
    /// 0 1 2
    /// 3 4 5
    /// ```
    /// Start in 0. Actions 0 up, 1 down, 2 left, 3 right. Entering 5 (goal) pays
    /// +10 and terminates; entering 4 (pit) pays −10 and terminates; every other
    /// move costs 1; bumping the border costs 5 and stays.
    pub fn grid(cap: Option<u64>) -> Self {
        let (rows, cols) = (2_usize, 3_usize);
        let n_states = rows * cols;
        let n_actions = 4;
        let mut next = Vec::new();
        let mut reward = Vec::new();
        let mut terminal = Vec::new();
        let mut bump = Vec::new();
        for s in 0..n_states {
            let (r, c) = (s / cols, s % cols);
            for a in 0..n_actions {
                let target = match a {
                    0 if r > 0 => Some(s - cols),
                    1 if r + 1 < rows => Some(s + cols),
                    2 if c > 0 => Some(s - 1),
                    3 if c + 1 < cols => Some(s + 1),
                    _ => None,
                };
                match target {
                    None => {
                        next.push(s);
                        reward.push(-5.0);
                        terminal.push(false);
                        bump.push(true);
                    }
                    Some(5) => {
                        next.push(5);
                        reward.push(10.0);
                        terminal.push(true);
                        bump.push(false);
                    }
                    Some(4) => {
                        next.push(4);
                        reward.push(-10.0);
                        terminal.push(true);
                        bump.push(false);
                    }
                    Some(t) => {
                        next.push(t);
                        reward.push(-1.0);
                        terminal.push(false);
                        bump.push(false);
                    }
                }
            }
        }
        Self {
            n_states,
            n_actions,
            next,
            reward,
            terminal,
            bump,
            start: 0,
            cap,
            state: 0,
            steps: 0,
            subtask: [0.0; 2],
        }
    }

    /// States the agent acts from: reachable from the start through non-terminal
    /// transitions.
    pub fn live_states(&self) -> Vec<usize> {
        let mut live = vec![false; self.n_states];
        let mut stack = vec![self.start];
        live[self.start] = true;
        while let Some(s) = stack.pop() {
            for a in 0..self.n_actions {
                let i = s * self.n_actions + a;
                if !self.terminal[i] && !live[self.next[i]] {
                    live[self.next[i]] = true;
                    stack.push(self.next[i]);
                }
            }
        }
        (0..self.n_states).filter(|&s| live[s]).collect()
    }

    /// The task as a [`dql::DeterministicModel`] (its reward, its terminal transitions).
    pub fn model(&self) -> dql::DeterministicModel {
        dql::DeterministicModel::from_fn(self.n_states, self.n_actions, |s, a| {
            let i = s * self.n_actions + a;
            dql::Transition {
                next: self.next[i],
                reward: self.reward[i],
                terminal: self.terminal[i],
            }
        })
        .expect("the grid's table is a valid model")
    }

    /// Q* by [`dql::value_iteration`], row-major, to within 1e-13.
    pub fn optimal_q(&self, gamma: f64) -> Vec<f64> {
        dql::value_iteration(&self.model(), gamma, 1e-13)
            .expect("γ < 1 and a positive tolerance")
            .q
            .as_slice()
            .to_vec()
    }
}

impl Environment for TableMdp {
    fn n_states(&self) -> usize {
        self.n_states
    }
    fn n_actions(&self) -> usize {
        self.n_actions
    }
    fn n_subtasks(&self) -> usize {
        2
    }
    fn subtask_names(&self) -> Vec<String> {
        vec!["progress".into(), "bumps".into()]
    }
    fn reset(&mut self, _seed: Option<u64>) -> usize {
        self.state = self.start;
        self.steps = 0;
        self.state
    }
    fn step(&mut self, action: usize) -> Step {
        let i = self.state * self.n_actions + action;
        self.state = self.next[i];
        self.steps += 1;
        let terminated = self.terminal[i];
        let truncated = !terminated && self.cap.is_some_and(|cap| self.steps >= cap);
        let bump = self.bump[i];
        self.subtask = [
            if bump { 0.0 } else { self.reward[i] },
            if bump { -5.0 } else { 0.0 },
        ];
        Step {
            next_state: self.state,
            reward: self.reward[i],
            terminated,
            truncated,
        }
    }
    fn subtask_rewards(&self) -> &[f64] {
        &self.subtask
    }
}
