//! The sub-tasks' prior experience as the source task reads it: one value per
//! `(state, action, sub-task)`, or none.

use dql::{DoubleQ, Environment, Learner};
use ea_tree::{AnswerTable, EaTree, EaTreeError, TableEntry, TreeStats};

use crate::config::Storage;

/// The m sub-tasks' answers for every `(state, action)`, looked up once after pre-training.
///
/// The sub-tasks are frozen once trained, so their trees (or tables) can be asked every
/// question in advance: the answer of sub-task `k` for `(s, a)` is the matching cluster's
/// `(Q1 + Q2) / 2` (an EA tree, [`ea_tree::Answer::q_mean`]) or the sub-task's own
/// `(Q1 + Q2) / 2` (table storage), or *no prior experience*: no cluster matches, or the
/// sub-task never tried `a` in `s`. This gives exactly the answers per-step lookups would,
/// in one load per value (the tree's `answer_table` is the same lookup, done once).
///
/// Layout: `(s · n_actions + a) · m + k`, so a state's decision matrix is one contiguous run.
#[derive(Debug, Clone, PartialEq)]
pub struct PriorTable {
    n_states: usize,
    n_actions: usize,
    n_subtasks: usize,
    /// The answers (0 where there is none).
    values: Vec<f64>,
    /// Whether there is an answer.
    present: Vec<bool>,
    /// Per state: every action has an answer from every sub-task.
    complete: Vec<bool>,
}

impl PriorTable {
    /// A table for `n_states × n_actions` from `n_subtasks` answer functions
    /// (`answer(k, state, action)`).
    #[must_use]
    pub fn from_fn(
        n_states: usize,
        n_actions: usize,
        n_subtasks: usize,
        mut answer: impl FnMut(usize, usize, usize) -> Option<f64>,
    ) -> Self {
        let cells = n_states * n_actions * n_subtasks;
        let mut values = vec![0.0; cells];
        let mut present = vec![false; cells];
        let mut complete = vec![true; n_states];
        for (state, complete) in complete.iter_mut().enumerate() {
            for action in 0..n_actions {
                for k in 0..n_subtasks {
                    let at = (state * n_actions + action) * n_subtasks + k;
                    match answer(k, state, action) {
                        Some(value) => {
                            values[at] = value;
                            present[at] = true;
                        }
                        None => *complete = false,
                    }
                }
            }
        }
        Self {
            n_states,
            n_actions,
            n_subtasks,
            values,
            present,
            complete,
        }
    }

    /// Answers of EA trees (one [`AnswerTable`] per sub-task).
    #[must_use]
    pub fn from_answer_tables(n_states: usize, n_actions: usize, tables: &[AnswerTable]) -> Self {
        Self::from_fn(n_states, n_actions, tables.len(), |k, state, action| {
            tables[k].get(state, action).map(|answer| answer.q_mean())
        })
    }

    /// Answers of the sub-tasks' own tables: `(Q1 + Q2) / 2` of every pair updated at least
    /// once (computed as [`ea_tree::Answer::q_mean`] does, so an exact tree and the table agree
    /// bit for bit).
    #[must_use]
    pub fn from_learners(learners: &[&DoubleQ]) -> Self {
        let (n_states, n_actions) = learners
            .first()
            .map_or((0, 0), |l| (l.n_states(), l.n_actions()));
        Self::from_fn(n_states, n_actions, learners.len(), |k, state, action| {
            let learner = learners[k];
            (learner.update_count(state, action) > 0)
                .then(|| 0.5 * learner.q1(state, action) + 0.5 * learner.q2(state, action))
        })
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

    /// Number of sub-tasks.
    #[must_use]
    pub fn n_subtasks(&self) -> usize {
        self.n_subtasks
    }

    /// Sub-task `k`'s answer for `(state, action)`; `None` for no prior experience (or out of
    /// range).
    #[must_use]
    pub fn get(&self, state: usize, action: usize, k: usize) -> Option<f64> {
        if state >= self.n_states || action >= self.n_actions || k >= self.n_subtasks {
            return None;
        }
        let at = (state * self.n_actions + action) * self.n_subtasks + k;
        self.present[at].then(|| self.values[at])
    }

    /// Number of `(state, action)` pairs sub-task `k` has an answer for.
    #[must_use]
    pub fn answered_pairs(&self, k: usize) -> u64 {
        let m = self.n_subtasks;
        if k >= m {
            return 0;
        }
        self.present
            .iter()
            .skip(k)
            .step_by(m)
            .filter(|p| **p)
            .count() as u64
    }

    /// All of `state`'s answers, `n_actions × m` row-major, and whether each is present.
    #[inline]
    pub(crate) fn state_block(&self, state: usize) -> (&[f64], &[bool]) {
        let width = self.n_actions * self.n_subtasks;
        let range = state * width..(state + 1) * width;
        (&self.values[range.clone()], &self.present[range])
    }

    /// Every action of `state` has an answer from every sub-task (`false` out of range).
    #[must_use]
    pub fn is_complete(&self, state: usize) -> bool {
        self.complete.get(state).copied().unwrap_or(false)
    }
}

/// The prior table of trained sub-task learners stored as `storage` says, with each tree's
/// statistics (clusters, samples, estimated bytes; `None` for table storage).
///
/// # Errors
/// An [`EaTreeError`] from building a tree (e.g. a state with no features).
pub fn build_prior<E: Environment + ?Sized>(
    env: &E,
    learners: &[&DoubleQ],
    storage: &Storage,
) -> Result<(PriorTable, Vec<Option<TreeStats>>), EaTreeError> {
    match storage {
        Storage::Table => Ok((
            PriorTable::from_learners(learners),
            vec![None; learners.len()],
        )),
        Storage::Tree(tree_config) => {
            let n_states = env.n_states();
            let n_actions = env.n_actions();
            let features: Vec<Vec<u32>> = (0..n_states).map(|s| env.state_features(s)).collect();
            let mut tables = Vec::with_capacity(learners.len());
            let mut clusters = Vec::with_capacity(learners.len());
            for learner in learners {
                let tree = EaTree::from_table(
                    *tree_config,
                    learner.experience().map(|sample| TableEntry {
                        state_id: sample.state,
                        state: &features[sample.state],
                        action: sample.action,
                        q1: sample.q1,
                        q2: sample.q2,
                    }),
                )?;
                clusters.push(Some(tree.stats()));
                tables.push(tree.answer_table(features.iter().map(Vec::as_slice), n_actions));
            }
            Ok((
                PriorTable::from_answer_tables(n_states, n_actions, &tables),
                clusters,
            ))
        }
    }
}
