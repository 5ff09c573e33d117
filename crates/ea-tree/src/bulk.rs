//! Bulk building from a trained sub-task's table, and answers precomputed for a table.

use crate::cluster::ClusterId;
use crate::config::EaTreeConfig;
use crate::error::EaTreeError;
use crate::similarity::{Similarity, WeightedJaccard};
use crate::tree::{Answer, EaTree, Sample};

/// One visited `(s, a)` pair of a trained table with its final Q1, Q2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableEntry<'a> {
    /// The table's state index (orders the entries; the tree itself only sees `state`).
    pub state_id: usize,
    /// The state's feature bins.
    pub state: &'a [u32],
    /// The action.
    pub action: usize,
    /// Final Q1(s, a).
    pub q1: f64,
    /// Final Q2(s, a).
    pub q2: f64,
}

impl EaTree<WeightedJaccard> {
    /// A tree holding one sample per table entry (see [`insert_table`](Self::insert_table)).
    ///
    /// # Errors
    /// As [`EaTree::new`] and [`insert_table`](Self::insert_table).
    pub fn from_table<'a>(
        config: EaTreeConfig,
        entries: impl IntoIterator<Item = TableEntry<'a>>,
    ) -> Result<Self, EaTreeError> {
        let mut tree = Self::new(config)?;
        tree.insert_table(entries)?;
        Ok(tree)
    }
}

impl<S: Similarity> EaTree<S> {
    /// Bulk mode: inserts one sample per entry in ascending `(state_id, action)` order,
    /// whatever order the entries come in, so the tree is a function of the table alone.
    ///
    /// Every entry is checked before the first insert. Spare capacity is released at the
    /// end (see [`shrink_to_fit`](Self::shrink_to_fit)).
    ///
    /// # Errors
    /// [`EaTreeError::DuplicateTableEntry`] if a `(state_id, action)` pair repeats,
    /// [`EaTreeError::InconsistentStateFeatures`] if one `state_id` comes with two feature
    /// lists, or an error of [`insert`](Self::insert) for a bad sample (the tree is then
    /// unchanged). [`EaTreeError::TooManyClusters`] can stop it midway.
    pub fn insert_table<'a>(
        &mut self,
        entries: impl IntoIterator<Item = TableEntry<'a>>,
    ) -> Result<(), EaTreeError> {
        let mut entries: Vec<TableEntry<'a>> = entries.into_iter().collect();
        entries.sort_by_key(|e| (e.state_id, e.action));
        for pair in entries.windows(2) {
            let (before, after) = (&pair[0], &pair[1]);
            if before.state_id == after.state_id {
                if before.action == after.action {
                    return Err(EaTreeError::DuplicateTableEntry {
                        state_id: after.state_id,
                        action: after.action,
                    });
                }
                if before.state != after.state {
                    return Err(EaTreeError::InconsistentStateFeatures {
                        state_id: after.state_id,
                    });
                }
            }
        }
        for entry in &entries {
            crate::tree::check_sample(&entry.sample())?;
        }
        for entry in &entries {
            self.insert(entry.sample())?;
        }
        // A bulk-built tree is then mostly read: drop the slack of doubling growth.
        self.shrink_to_fit();
        Ok(())
    }

    /// Answers every `(state, action)` for `states` (indexed by position, e.g. a task's
    /// state ids) and actions `0..n_actions`, once, so that a training loop can read them
    /// with [`AnswerTable::get`] in constant time.
    #[must_use]
    pub fn answer_table<'s>(
        &self,
        states: impl IntoIterator<Item = &'s [u32]>,
        n_actions: usize,
    ) -> AnswerTable {
        let mut answers = Vec::new();
        let mut n_states = 0;
        let mut memo = Vec::new();
        for state in states {
            // `lookup` of each action, sharing the walk's state tests between the actions.
            self.lookup_each_action(state, n_actions, &mut memo, |answer| answers.push(answer));
            n_states += 1;
        }
        AnswerTable {
            n_states,
            n_actions,
            answers,
        }
    }
}

impl TableEntry<'_> {
    fn sample(&self) -> Sample<'_> {
        Sample {
            state: self.state,
            action: self.action,
            q1: self.q1,
            q2: self.q2,
        }
    }
}

/// Precomputed lookups of a finished tree (see [`EaTree::answer_table`]).
#[derive(Debug, Clone, PartialEq)]
pub struct AnswerTable {
    n_states: usize,
    n_actions: usize,
    answers: Vec<Option<Answer>>,
}

impl AnswerTable {
    /// The tree's answer for `(state_id, action)`; `None` for no prior experience, and also
    /// for a pair outside the table.
    #[must_use]
    pub fn get(&self, state_id: usize, action: usize) -> Option<Answer> {
        if action >= self.n_actions {
            return None;
        }
        let at = state_id.checked_mul(self.n_actions)?.checked_add(action)?;
        self.answers.get(at).copied().flatten()
    }

    /// Number of states the table covers.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.n_states
    }

    /// Number of actions the table covers.
    #[must_use]
    pub fn n_actions(&self) -> usize {
        self.n_actions
    }

    /// Number of distinct clusters the answers point to.
    #[must_use]
    pub fn distinct_clusters(&self) -> usize {
        let mut ids: Vec<ClusterId> = self.answers.iter().flatten().map(|a| a.cluster).collect();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }
}
