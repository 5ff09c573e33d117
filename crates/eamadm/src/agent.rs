//! The EA-MADM action policy (Sec. IV.C, Algorithm 2): ε-greedy whose exploitation step is a
//! multi-attribute decision over the sub-tasks' prior experience and the source task's own
//! values.

use dql::{
    DoubleQ, DqlError, EpsilonGreedy, ExplorationPolicy, Learner, Schedule, argmax_random_tie,
};
use madm_owa::{ColumnSummary, MadmDecider, MadmError, Normalisation, Weighting};
use rand::Rng;

use crate::prior::PriorTable;
use crate::record::{AgreementCounts, AgreementRecord};

/// The EA-MADM policy of the source task (Algorithm 2, lines 16–22).
///
/// With probability ε (a per-episode [`Schedule`]) it takes a uniformly random action.
/// Otherwise it builds the decision matrix of Eq. 13 for the current state, one row per
/// action `a_j`:
///
/// ```text
/// ( Q⁽¹⁾(s, a_j), …, Q⁽ᵐ⁾(s, a_j), Q(s, a_j) )
/// ```
///
/// where `Q⁽ᵏ⁾` is sub-task `k`'s prior experience (a [`PriorTable`] answer: the EA tree's
/// cluster mean `(Q1 + Q2) / 2`) and `Q` is the source task's own `(Q1 + Q2) / 2` (the
/// action values the episode driver passes in, Algorithm 2 line 20). Each row is valued by
/// the visibility-weighted OWA of Eq. 14–16 ([`MadmDecider`] with the configured
/// [`Weighting`]); the action with the largest value wins, ties uniformly at random.
///
/// # No prior experience
///
/// When sub-task `k` has no experience of `(s, a_j)` (its tree has no matching cluster, or
/// its learner never tried `a_j` in `s`), that sub-task **abstains** for that row: the row is
/// aggregated over the attributes that exist, at least the source task's own value. With no
/// experience at all the decision is the plain greedy choice on the source task's own values.
/// Inventing a value instead would not be neutral: 0 claims "harmless" in the "do not hit"
/// sub-task, and copying the source task's value creates an exact tie, which the paper's
/// support `x·y/|x − y|²` rewards with a near-infinite weight.
///
/// Each row's value is kept with the own value it was computed from and recomputed only when
/// that changes (the prior experience is frozen), which gives the same values as evaluating
/// the whole matrix at every step at about a third of the cost.
///
/// Draws: one [`dql::Coin`] flip per step (one `u32`, heads with probability ε, as
/// [`EpsilonGreedy`] does), then one action index when exploring, or one tie-break index only
/// on a tie. After construction nothing is allocated.
#[derive(Debug, Clone)]
pub struct EaMadmPolicy {
    prior: PriorTable,
    /// The ε-greedy half: its schedule, ε and coin (the exploitation rule is ours).
    exploration: EpsilonGreedy,
    decider: MadmDecider,
    /// How each attribute is scaled over the state's rows before OWA (the paper: not at all).
    normalisation: Normalisation,
    /// Per column (sub-tasks, then the own value): its summary (extremes, mean, SD) in the
    /// state being evaluated, for `normalisation`.
    column_summary: Vec<ColumnSummary>,
    /// One column's values in the state being evaluated (scratch, `n_actions` long).
    column: Vec<f64>,
    /// One row of the decision matrix: the attributes present, then the own value.
    row: Vec<f64>,
    /// Per `(state, action)`: the bits of the own value its `Eq` was last computed with
    /// (a NaN pattern, never a learner's value, before the first time).
    cached_own: Vec<u64>,
    /// Per `(state, action)`: that `Eq`.
    cached_value: Vec<f64>,
    /// Counts of agreement with the sub-tasks' own greedy choices, when asked for
    /// ([`with_agreement`](Self::with_agreement)).
    agreement: Option<AgreementTally>,
    /// The first decision that could not be made (a row with a non-finite value), if any.
    failure: Option<MadmError>,
}

/// What [`EaMadmPolicy::with_agreement`] counts with.
#[derive(Debug, Clone)]
struct AgreementTally {
    /// Per `(sub-task k, state)`: the actions at which sub-task `k`'s behaviour values in that
    /// state reach their maximum, as bits of `words` `u64`s starting at
    /// `(k · n_states + state) · words`. The sub-tasks are frozen while the source task learns,
    /// so these sets are found once here instead of scanning a row at every decision.
    best: Vec<u64>,
    /// `u64` words per `(sub-task, state)`: `ceil(n_actions / 64)`.
    words: usize,
    n_states: usize,
    /// First episode of the final window.
    final_from: u64,
    /// The current episode is in the final window.
    in_final: bool,
    training: AgreementCounts,
    final_window: AgreementCounts,
}

impl AgreementTally {
    /// The tally of `values` (sub-task `k`'s behaviour values at
    /// `(k · n_states + s) · n_actions + a`), counting from episode `final_from` on in the
    /// final window.
    fn new(values: &[f64], m: usize, n_states: usize, n_actions: usize, final_from: u64) -> Self {
        let words = n_actions.div_ceil(64).max(1);
        let mut best = vec![0_u64; m * n_states * words];
        for (row, bits) in values
            .chunks_exact(n_actions.max(1))
            .zip(best.chunks_exact_mut(words))
        {
            // The same maximum and comparison the per-decision scan made: NaN never agrees.
            let max = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            for (action, &value) in row.iter().enumerate() {
                if value == max {
                    bits[action / 64] |= 1 << (action % 64);
                }
            }
        }
        let counts = AgreementCounts {
            agrees: vec![0; m],
            ..AgreementCounts::default()
        };
        Self {
            best,
            words,
            n_states,
            final_from,
            in_final: false,
            training: counts.clone(),
            final_window: counts,
        }
    }

    /// Counts one exploitation decision: `action` in `state`, taken `missing` some prior
    /// experience there.
    #[inline]
    fn count(&mut self, state: usize, action: usize, missing: bool) {
        let m = self.training.agrees.len();
        let (word, bit) = (action / 64, action % 64);
        let mut agrees_with_all = true;
        for k in 0..m {
            // Ties: agreeing with any of the tied maxima is agreeing.
            let agrees =
                (self.best[(k * self.n_states + state) * self.words + word] >> bit) & 1 == 1;
            agrees_with_all &= agrees;
            self.training.agrees[k] += u64::from(agrees);
            if self.in_final {
                self.final_window.agrees[k] += u64::from(agrees);
            }
        }
        let add = |counts: &mut AgreementCounts| {
            counts.decisions += 1;
            counts.agrees_with_all += u64::from(agrees_with_all);
            counts.missing_experience += u64::from(missing);
        };
        add(&mut self.training);
        if self.in_final {
            add(&mut self.final_window);
        }
    }
}

/// The bits of a NaN: no finite own value has them, so a fresh cache entry never matches.
const NOT_COMPUTED: u64 = u64::MAX;

/// Why an [`EaMadmPolicy`] cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PolicyError {
    /// The ε schedule is invalid.
    #[error(transparent)]
    Epsilon(#[from] DqlError),
    /// The weighting is invalid.
    #[error(transparent)]
    Weighting(#[from] MadmError),
    /// The weighting gives fixed weights (`given`), which cannot follow decision-matrix rows
    /// whose length changes when a sub-task has no experience.
    #[error(
        "weighting `given` ({found} weights) cannot serve EA-MADM, whose decision-matrix rows vary in length (up to {max_columns}); use visibility, uniform or maximum_entropy"
    )]
    GivenWeights {
        /// Number of weights given.
        found: usize,
        /// The longest row: one column per sub-task plus the source task's own.
        max_columns: usize,
    },
}

impl EaMadmPolicy {
    /// The policy deciding on `prior` with `weighting`, exploring with `epsilon`.
    ///
    /// # Errors
    /// [`PolicyError::Epsilon`] for an invalid schedule (named `epsilon.*`),
    /// [`PolicyError::Weighting`] for an invalid weighting, [`PolicyError::GivenWeights`] for a
    /// fixed-length (`given`) one.
    pub fn new(
        prior: PriorTable,
        epsilon: Schedule,
        weighting: Weighting,
    ) -> Result<Self, PolicyError> {
        let exploration = EpsilonGreedy::new(epsilon)?;
        if let Weighting::Given { weights } = &weighting {
            return Err(PolicyError::GivenWeights {
                found: weights.len(),
                max_columns: prior.n_subtasks() + 1,
            });
        }
        let decider = MadmDecider::new(weighting)?;
        let cols = prior.n_subtasks() + 1;
        let n_actions = prior.n_actions();
        let pairs = prior.n_states() * n_actions;
        Ok(Self {
            normalisation: Normalisation::None,
            column_summary: vec![ColumnSummary::of(&[0.0]); cols],
            column: Vec::with_capacity(n_actions),
            row: vec![0.0; cols],
            cached_own: vec![NOT_COMPUTED; pairs],
            cached_value: vec![0.0; pairs],
            agreement: None,
            failure: None,
            exploration,
            decider,
            prior,
        })
    }

    /// The same policy, counting how often its exploitation choice equals each sub-task's
    /// greedy argmax (see [`AgreementRecord`]), over all episodes and over those from
    /// `final_from` on. `subtasks` are the pre-trained sub-task learners in sub-task order.
    ///
    /// # Panics
    /// If the learners do not match the prior's sub-task count and shape.
    #[must_use]
    pub fn with_agreement(mut self, subtasks: &[&DoubleQ], final_from: u64) -> Self {
        let (n_states, n_actions) = (self.prior.n_states(), self.prior.n_actions());
        assert_eq!(
            subtasks.len(),
            self.prior.n_subtasks(),
            "one learner per sub-task"
        );
        let mut values = vec![0.0; subtasks.len() * n_states * n_actions];
        for (k, learner) in subtasks.iter().enumerate() {
            assert_eq!(
                (learner.n_states(), learner.n_actions()),
                (n_states, n_actions),
                "sub-task learners match the prior's shape"
            );
            for state in 0..n_states {
                let start = (k * n_states + state) * n_actions;
                learner.action_values(state, &mut values[start..start + n_actions]);
            }
        }
        self.agreement = Some(AgreementTally::new(
            &values,
            subtasks.len(),
            n_states,
            n_actions,
            final_from,
        ));
        self
    }

    /// The same policy scaling each attribute (column) of a state's decision matrix by
    /// `normalisation` before OWA, over the actions that have a value in it (a sub-task that
    /// abstains for an action does not count in that column's range). The paper does not
    /// normalise ([`Normalisation::None`], the default); [`Normalisation::MinMax`] is the
    /// repair of issue 21 (paper-notes §6, §8.6), [`Normalisation::ZScore`] the standardised
    /// columns of the plain aggregators (issue 32, paper-notes §21.3). Every row of the state
    /// then depends on every own value, so rows are recomputed at each decision instead of
    /// cached.
    #[must_use]
    pub fn with_normalisation(mut self, normalisation: Normalisation) -> Self {
        self.normalisation = normalisation;
        self
    }

    /// The agreement counted so far, if [`with_agreement`](Self::with_agreement) asked for it.
    #[must_use]
    pub fn agreement(&self) -> Option<AgreementRecord> {
        self.agreement.as_ref().map(|tally| AgreementRecord {
            final_window: tally.final_window.clone(),
            training: tally.training.clone(),
        })
    }

    /// The prior experience decided on.
    #[must_use]
    pub fn prior(&self) -> &PriorTable {
        &self.prior
    }

    /// The first decision that failed since the policy was made, if any: a row of the decision
    /// matrix with a non-finite value (the source task's own value overflowed). Such a row
    /// counts as the worst action, and the run that used the policy must report this error
    /// instead of its results.
    #[must_use]
    pub fn failure(&self) -> Option<&MadmError> {
        self.failure.as_ref()
    }

    /// The ε in force (set at the start of each episode).
    #[must_use]
    pub fn epsilon(&self) -> f64 {
        self.exploration.epsilon()
    }

    /// The same policy without exploration (ε = 0 in every episode): the trained agent's
    /// greedy behaviour, used for the evaluation episode.
    #[must_use]
    pub fn without_exploration(mut self) -> Self {
        self.exploration = EpsilonGreedy::constant(0.0).expect("ε = 0 is a valid exploration rate");
        self.agreement = None;
        self
    }

    /// `Eq(a_j)` for every action in `state`, given the source task's own values there.
    ///
    /// # Panics
    /// If `state` is out of range or `own_values` does not have one value per action.
    pub fn evaluations(&mut self, state: usize, own_values: &[f64]) -> &[f64] {
        let range = self.evaluate(state, own_values);
        &self.cached_value[range]
    }

    /// The exploitation step: the action with the largest `Eq(a_j)`, ties at random.
    ///
    /// # Panics
    /// As [`evaluations`](Self::evaluations).
    pub fn decide<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        own_values: &[f64],
        rng: &mut R,
    ) -> usize {
        let range = self.evaluate(state, own_values);
        argmax_random_tie(&self.cached_value[range], rng)
    }

    /// Brings `state`'s rows of the cache up to date; returns their range in it.
    fn evaluate(&mut self, state: usize, own_values: &[f64]) -> std::ops::Range<usize> {
        let n_actions = self.prior.n_actions();
        assert_eq!(own_values.len(), n_actions, "one own value per action");
        if self.normalisation != Normalisation::None {
            return self.evaluate_normalised(state, own_values);
        }
        let m = self.prior.n_subtasks();
        let (answers, present) = self.prior.state_block(state);
        let cached = state * n_actions..(state + 1) * n_actions;
        let cached_own = &mut self.cached_own[cached.clone()];
        let cached_value = &mut self.cached_value[cached.clone()];
        for (action, &own) in own_values.iter().enumerate() {
            // A row's value is a function of its attributes, and only the own value can
            // change: recompute only rows whose own value did (between two visits of a state
            // the learner updates one of its actions, so usually one row of n).
            if cached_own[action] != own.to_bits() {
                let mut len = 0;
                for k in 0..m {
                    let at = action * m + k;
                    if present[at] {
                        self.row[len] = answers[at];
                        len += 1;
                    }
                }
                self.row[len] = own;
                len += 1;
                match self.decider.evaluate_one(&self.row[..len]) {
                    Ok(value) => {
                        cached_value[action] = value;
                        cached_own[action] = own.to_bits();
                    }
                    Err(error) => {
                        // Validated configs bound initial values and rewards so that rows stay
                        // finite; should one not, the step goes on (a policy cannot fail) and
                        // the run reports the error when its episode ends.
                        cached_value[action] = f64::NEG_INFINITY;
                        cached_own[action] = NOT_COMPUTED;
                        if self.failure.is_none() {
                            self.failure = Some(error);
                        }
                    }
                }
            }
        }
        cached
    }
}

impl EaMadmPolicy {
    /// [`evaluate`](Self::evaluate) with every column scaled over the state's rows: all rows
    /// are recomputed (the cache of own values is left marked "not computed").
    fn evaluate_normalised(&mut self, state: usize, own_values: &[f64]) -> std::ops::Range<usize> {
        let n_actions = self.prior.n_actions();
        let m = self.prior.n_subtasks();
        let (answers, present) = self.prior.state_block(state);
        for k in 0..=m {
            self.column.clear();
            if k < m {
                self.column.extend(
                    (0..n_actions)
                        .map(|action| action * m + k)
                        .filter(|&at| present[at])
                        .map(|at| answers[at]),
                );
            } else {
                self.column.extend_from_slice(own_values);
            }
            if !self.column.is_empty() {
                self.column_summary[k] = ColumnSummary::of(&self.column);
            }
        }
        let cached = state * n_actions..(state + 1) * n_actions;
        for (action, &own) in own_values.iter().enumerate() {
            let mut len = 0;
            for k in 0..m {
                let at = action * m + k;
                if present[at] {
                    self.row[len] = self
                        .normalisation
                        .scale(answers[at], &self.column_summary[k]);
                    len += 1;
                }
            }
            self.row[len] = self.normalisation.scale(own, &self.column_summary[m]);
            len += 1;
            let slot = cached.start + action;
            self.cached_own[slot] = NOT_COMPUTED;
            match self.decider.evaluate_one(&self.row[..len]) {
                Ok(value) => self.cached_value[slot] = value,
                Err(error) => {
                    // as in `evaluate`: the run reports the error when its episode ends
                    self.cached_value[slot] = f64::NEG_INFINITY;
                    if self.failure.is_none() {
                        self.failure = Some(error);
                    }
                }
            }
        }
        cached
    }
}

impl ExplorationPolicy for EaMadmPolicy {
    fn begin_episode(&mut self, episode: u64) {
        self.exploration.begin_episode(episode);
        if let Some(tally) = self.agreement.as_mut() {
            tally.in_final = episode >= tally.final_from;
        }
    }

    #[inline]
    fn select<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action_values: &[f64],
        rng: &mut R,
    ) -> usize {
        match self.exploration.explore_action(action_values.len(), rng) {
            Some(action) => action,
            None => {
                let action = self.decide(state, action_values, rng);
                if let Some(tally) = self.agreement.as_mut() {
                    let missing = !self.prior.is_complete(state);
                    tally.count(state, action, missing);
                }
                action
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use madm_owa::Support;
    use proptest::prelude::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn policy(prior: PriorTable, weighting: Weighting) -> EaMadmPolicy {
        EaMadmPolicy::new(prior, Schedule::Constant(0.0), weighting).unwrap()
    }

    #[test]
    fn without_experience_the_decision_is_greedy_on_the_own_values() {
        let prior = PriorTable::from_fn(3, 4, 2, |_, _, _| None);
        let mut policy = policy(prior, Weighting::default());
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let own = [0.5, -2.0, 3.0, 1.0];
        assert_eq!(policy.evaluations(1, &own), own);
        assert_eq!(policy.decide(1, &own, &mut rng), 2);
    }

    #[test]
    fn normalised_rows_are_the_madm_decision_on_the_min_max_scaled_matrix() {
        // sub-task values in the tens, own values in tenths: unscaled, the sub-tasks decide
        let prior = PriorTable::from_fn(2, 3, 2, |k, s, a| {
            Some(10.0 * ((k + 2 * s + 3 * a) as f64 - 2.5))
        });
        let own = [0.7, -0.1, 0.3];
        let mut matrix = Vec::new();
        for (a, &own) in own.iter().enumerate() {
            matrix.extend([
                prior.get(1, a, 0).unwrap(),
                prior.get(1, a, 1).unwrap(),
                own,
            ]);
        }
        Normalisation::MinMax.apply(&mut matrix, 3, 3);
        let mut expected = [0.0; 3];
        MadmDecider::new(Weighting::default())
            .unwrap()
            .evaluate(&matrix, 3, 3, &mut expected)
            .unwrap();
        let mut normalised =
            policy(prior.clone(), Weighting::default()).with_normalisation(Normalisation::MinMax);
        assert_eq!(normalised.evaluations(1, &own), expected);
        // a second call with other own values recomputes every row (no stale cache)
        let other = [0.1, 0.9, 0.3];
        let first = normalised.evaluations(1, &other).to_vec();
        let mut fresh =
            policy(prior, Weighting::default()).with_normalisation(Normalisation::MinMax);
        assert_eq!(first, fresh.evaluations(1, &other));
    }

    /// The plain aggregators (issue 32): uniform weights on standardised columns value each
    /// action by the mean of its standard scores, and the max operator (maximum entropy with
    /// orness 1) by the largest of them.
    #[test]
    fn the_plain_aggregators_are_the_mean_and_the_max_of_standard_scores() {
        let prior = PriorTable::from_fn(1, 4, 2, |k, _, a| {
            Some(if k == 0 {
                [5.0, 3.0, 4.0, 1.0][a]
            } else {
                [0.0, -100.0, 0.0, 0.0][a]
            })
        });
        let own = [0.2, 0.1, -0.3, 0.0];
        let mut matrix = Vec::new();
        for (a, &own) in own.iter().enumerate() {
            matrix.extend([
                prior.get(0, a, 0).unwrap(),
                prior.get(0, a, 1).unwrap(),
                own,
            ]);
        }
        Normalisation::ZScore.apply(&mut matrix, 4, 3);
        let rows: Vec<&[f64]> = matrix.chunks(3).collect();
        let mut mean =
            policy(prior.clone(), Weighting::Uniform).with_normalisation(Normalisation::ZScore);
        let mut max = policy(prior, Weighting::MaximumEntropy { orness: 1.0 })
            .with_normalisation(Normalisation::ZScore);
        let means = mean.evaluations(0, &own).to_vec();
        let maxes = max.evaluations(0, &own).to_vec();
        for (a, row) in rows.iter().enumerate() {
            let want_mean = row.iter().sum::<f64>() / 3.0;
            let want_max = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            assert!((means[a] - want_mean).abs() < 1e-12, "{means:?}");
            assert_eq!(maxes[a], want_max, "{maxes:?}");
        }
    }

    #[test]
    fn a_complete_state_is_the_madm_decision_on_eq_13() {
        let prior = PriorTable::from_fn(2, 3, 2, |k, s, a| Some((k + 2 * s + 3 * a) as f64 - 2.5));
        let mut policy = policy(prior.clone(), Weighting::default());
        let own = [0.7, -0.1, 0.3];
        let mut matrix = Vec::new();
        for (a, &own) in own.iter().enumerate() {
            matrix.extend([
                prior.get(1, a, 0).unwrap(),
                prior.get(1, a, 1).unwrap(),
                own,
            ]);
        }
        let mut expected = [0.0; 3];
        MadmDecider::new(Weighting::default())
            .unwrap()
            .evaluate(&matrix, 3, 3, &mut expected)
            .unwrap();
        assert_eq!(policy.evaluations(1, &own), expected);
    }

    #[test]
    fn a_sub_task_without_experience_abstains() {
        // Sub-task 1 knows nothing of action 0 in state 0.
        let prior = PriorTable::from_fn(1, 2, 2, |k, _, a| {
            (k == 0 || a == 1).then_some(if k == 0 { 4.0 } else { -100.0 })
        });
        assert!(!prior.is_complete(0));
        let mut policy = policy(prior, Weighting::Uniform);
        let values = policy.evaluations(0, &[1.0, 1.0]).to_vec();
        // Action 0: mean of (4, 1); action 1: mean of (4, −100, 1).
        assert_eq!(values[0], 2.5);
        assert!((values[1] - (-95.0 / 3.0)).abs() < 1e-12, "{values:?}");
    }

    #[test]
    fn exploration_follows_the_schedule() {
        let prior = PriorTable::from_fn(1, 4, 1, |_, _, a| Some(if a == 3 { 1.0 } else { 0.0 }));
        let schedule = Schedule::Exponential {
            start: 1.0,
            factor: 0.5,
            floor: 0.0,
        };
        let mut policy = EaMadmPolicy::new(prior, schedule, Weighting::default()).unwrap();
        policy.begin_episode(2);
        assert_eq!(policy.epsilon(), 0.25);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let own = [0.0; 4];
        let picks = (0..4000)
            .filter(|_| policy.select(0, &own, &mut rng) != 3)
            .count();
        // Non-greedy picks: 0.25 × 3/4 of the steps.
        assert!((600..900).contains(&picks), "{picks}");
        let mut greedy = policy.without_exploration();
        greedy.begin_episode(0);
        assert!((0..100).all(|_| greedy.select(0, &own, &mut rng) == 3));
    }

    /// A learner whose both tables hold `values` (`n_states × n_actions`, row-major).
    fn learner(n_states: usize, n_actions: usize, values: Vec<f64>) -> DoubleQ {
        let table = dql::QTable::from_values(n_states, n_actions, values).unwrap();
        DoubleQ::from_tables(dql::DoubleQParams::default(), &table, &table).unwrap()
    }

    #[test]
    fn agreement_counts_decisions_per_subtask_with_ties_agreeing() {
        // Sub-task 0 prefers action 1 everywhere; sub-task 1 ties actions 0 and 1 in state 0
        // and prefers action 0 in state 1. The prior makes action 1 the decision everywhere.
        let prior = PriorTable::from_fn(2, 2, 2, |_, _, a| Some(if a == 1 { 5.0 } else { 0.0 }));
        let first = learner(2, 2, vec![0.0, 1.0, 0.0, 1.0]);
        let second = learner(2, 2, vec![2.0, 2.0, 3.0, -1.0]);
        let mut policy = EaMadmPolicy::new(prior, Schedule::Constant(0.0), Weighting::Uniform)
            .unwrap()
            .with_agreement(&[&first, &second], 1);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        policy.begin_episode(0);
        assert_eq!(policy.select(0, &[0.0, 0.0], &mut rng), 1);
        policy.begin_episode(1);
        assert_eq!(policy.select(0, &[0.0, 0.0], &mut rng), 1);
        assert_eq!(policy.select(1, &[0.0, 0.0], &mut rng), 1);
        let agreement = policy.agreement().unwrap();
        assert_eq!(agreement.training.decisions, 3);
        // The tie in state 0 agrees; state 1's choice does not match sub-task 1's argmax.
        assert_eq!(agreement.training.agrees, [3, 2]);
        assert_eq!(agreement.training.agrees_with_all, 2);
        assert_eq!(agreement.final_window.decisions, 2);
        assert_eq!(agreement.final_window.agrees, [2, 1]);
        assert_eq!(agreement.final_window.missing_experience, 0);
        // The greedy evaluation policy counts nothing.
        assert!(policy.without_exploration().agreement().is_none());
    }

    #[test]
    fn fixed_weights_are_refused() {
        let prior = PriorTable::from_fn(1, 2, 2, |_, _, _| Some(0.0));
        let weights = madm_owa::OwaWeights::uniform(3).unwrap();
        let error = EaMadmPolicy::new(prior, Schedule::Constant(0.1), Weighting::Given { weights })
            .unwrap_err();
        assert_eq!(
            error,
            PolicyError::GivenWeights {
                found: 3,
                max_columns: 3
            }
        );
    }

    /// The per-decision scan the tally's precomputed sets replace, written plainly: sub-task
    /// `k` agrees when the action's value equals the largest of its row.
    fn plain_agreement(
        values: &[f64],
        n_states: usize,
        n_actions: usize,
        decisions: &[(usize, usize, bool, bool)],
        m: usize,
    ) -> (AgreementCounts, AgreementCounts) {
        let fresh = AgreementCounts {
            agrees: vec![0; m],
            ..AgreementCounts::default()
        };
        let (mut training, mut final_window) = (fresh.clone(), fresh);
        for &(state, action, missing, in_final) in decisions {
            let mut all = true;
            for k in 0..m {
                let start = (k * n_states + state) * n_actions;
                let row = &values[start..start + n_actions];
                let best = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let agrees = row[action] == best;
                all &= agrees;
                training.agrees[k] += u64::from(agrees);
                if in_final {
                    final_window.agrees[k] += u64::from(agrees);
                }
            }
            for (counts, counted) in [(&mut training, true), (&mut final_window, in_final)] {
                if counted {
                    counts.decisions += 1;
                    counts.agrees_with_all += u64::from(all);
                    counts.missing_experience += u64::from(missing);
                }
            }
        }
        (training, final_window)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        /// The tally's precomputed best-action sets count exactly what scanning each
        /// sub-task's row at every decision counts: ties (values drawn from a few levels, so
        /// they are frequent), NaN values (which never agree) and more than 64 actions
        /// included.
        #[test]
        fn precomputed_agreement_equals_the_plain_scan(
            m in 1..4_usize,
            n_states in 1..4_usize,
            n_actions in prop_oneof![1..6_usize, 63..67_usize],
            levels in proptest::collection::vec(0..4_u8, 4 * 4 * 67),
            picks in proptest::collection::vec((0..4_usize, 0..67_usize, any::<bool>(), any::<bool>()), 0..40),
        ) {
            let values: Vec<f64> = levels[..m * n_states * n_actions]
                .iter()
                .map(|&level| if level == 3 { f64::NAN } else { f64::from(level) })
                .collect();
            let decisions: Vec<(usize, usize, bool, bool)> = picks
                .into_iter()
                .map(|(s, a, missing, in_final)| (s % n_states, a % n_actions, missing, in_final))
                .collect();
            let mut tally = AgreementTally::new(&values, m, n_states, n_actions, 0);
            for &(state, action, missing, in_final) in &decisions {
                tally.in_final = in_final;
                tally.count(state, action, missing);
            }
            let (training, final_window) = plain_agreement(&values, n_states, n_actions, &decisions, m);
            prop_assert_eq!(tally.training, training);
            prop_assert_eq!(tally.final_window, final_window);
        }

        /// The per-row cache gives exactly what a fresh policy computes, however the own values
        /// change between decisions.
        #[test]
        fn cached_rows_equal_fresh_evaluations(
            answers in proptest::collection::vec(proptest::option::of(-100.0..100.0_f64), 2 * 3 * 2),
            visits in proptest::collection::vec((0..2_usize, proptest::collection::vec(-5.0..5.0_f64, 3)), 1..12),
        ) {
            let prior = PriorTable::from_fn(2, 3, 2, |k, s, a| answers[(s * 3 + a) * 2 + k]);
            let mut cached = policy(prior.clone(), Weighting::default());
            let mut own = [[0.0; 3]; 2];
            for (state, changes) in visits {
                // Change one or more own values, keep the others (as learning does).
                for (value, change) in own[state].iter_mut().zip(&changes) {
                    if *change > 0.0 {
                        *value = *change;
                    }
                }
                let fresh = policy(prior.clone(), Weighting::default())
                    .evaluations(state, &own[state])
                    .to_vec();
                prop_assert_eq!(cached.evaluations(state, &own[state]).to_vec(), fresh);
            }
        }

        /// Every action's value lies between the smallest and the largest attribute of its
        /// row (the attributes present), whichever weighting, and is finite.
        #[test]
        fn values_stay_within_their_rows(
            answers in proptest::collection::vec(proptest::option::of(-200.0..200.0_f64), 4 * 3),
            own in proptest::collection::vec(-50.0..50.0_f64, 4),
            support in prop_oneof![Just(Support::default()), Just(Support::Distance)],
        ) {
            let prior = PriorTable::from_fn(1, 4, 3, |k, _, a| answers[a * 3 + k]);
            let mut policy = policy(prior.clone(), Weighting::Visibility { support });
            let values = policy.evaluations(0, &own).to_vec();
            for (a, value) in values.iter().enumerate() {
                let row: Vec<f64> = (0..3)
                    .filter_map(|k| prior.get(0, a, k))
                    .chain([own[a]])
                    .collect();
                let lo = row.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                prop_assert!(value.is_finite());
                prop_assert!(*value >= lo - 1e-9 && *value <= hi + 1e-9, "{value} not in [{lo}, {hi}]");
            }
        }
    }
}
