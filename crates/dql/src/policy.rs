//! Exploration policies: how an action is chosen from action values (Sec. II.C,
//! Eq. 4, and the paper's competitors in Sec. VI).

use rand::{Rng, RngExt};

use crate::draw::Coin;
use serde::{Deserialize, Serialize};

use crate::error::DqlError;
use crate::schedule::{Domain, Schedule};
use crate::table::{argmax_random_tie, max_value};

/// Chooses an action in a state from the learner's action values.
///
/// The trait is open: besides [`Greedy`], [`EpsilonGreedy`] and [`Softmax`], a
/// caller can implement its own (the facade's multi-attribute policy looks up
/// other tasks' values for `state`). The episode driver
/// ([`run_episode`](crate::run_episode)) calls [`begin_episode`](Self::begin_episode)
/// before the episode's first step and [`end_episode`](Self::end_episode) after
/// its last, with the episode's 0-based index, so per-episode schedules advance.
pub trait ExplorationPolicy {
    /// Prepares episode `episode` (0-based), e.g. sets the scheduled parameter.
    fn begin_episode(&mut self, episode: u64) {
        let _ = episode;
    }

    /// Called after episode `episode` has ended.
    fn end_episode(&mut self, episode: u64) {
        let _ = episode;
    }

    /// The action to take in `state`, given the learner's `action_values` for it
    /// (one per action, never empty). Every random draw comes from `rng`; the
    /// result must be in `0..action_values.len()`. Should not allocate.
    fn select<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action_values: &[f64],
        rng: &mut R,
    ) -> usize;
}

/// Always the greedy action; ties broken uniformly at random.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Greedy;

impl ExplorationPolicy for Greedy {
    #[inline]
    fn select<R: Rng + ?Sized>(
        &mut self,
        _state: usize,
        action_values: &[f64],
        rng: &mut R,
    ) -> usize {
        argmax_random_tie(action_values, rng)
    }
}

/// ε-greedy (Eq. 4): with probability ε a uniformly random action, otherwise the
/// greedy one (ties at random). With an exponential schedule it is ε-decreasing.
///
/// Each selection flips one [`Coin`] (one `u32`) with probability ε, then draws
/// either a uniform action index or, only on a tie, a tie-break index.
///
/// Serialised as its schedule: `{"epsilon": {"constant": 0.1}}`; deserialising
/// validates it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "EpsilonGreedyRepr", into = "EpsilonGreedyRepr")]
pub struct EpsilonGreedy {
    schedule: Schedule,
    epsilon: f64,
    /// The episode `epsilon` is the schedule's value of (0 before any episode).
    episode: u64,
    /// Heads with probability `epsilon`.
    explore: Coin,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct EpsilonGreedyRepr {
    epsilon: Schedule,
}

impl TryFrom<EpsilonGreedyRepr> for EpsilonGreedy {
    type Error = DqlError;
    fn try_from(repr: EpsilonGreedyRepr) -> Result<Self, DqlError> {
        Self::new(repr.epsilon)
    }
}

impl From<EpsilonGreedy> for EpsilonGreedyRepr {
    fn from(policy: EpsilonGreedy) -> Self {
        Self {
            epsilon: policy.schedule,
        }
    }
}

impl EpsilonGreedy {
    /// ε-greedy whose ε follows `schedule`; ε starts at the schedule's episode-0 value.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] naming `epsilon` (or `epsilon.start`,
    /// `epsilon.factor`, `epsilon.floor`) when a value is outside [0, 1], the
    /// factor outside (0, 1], or the floor above the start.
    pub fn new(schedule: Schedule) -> Result<Self, DqlError> {
        schedule.validate("epsilon", Domain::Probability)?;
        Ok(Self {
            schedule,
            epsilon: schedule.start(),
            episode: 0,
            explore: Coin::new(schedule.start()),
        })
    }

    /// ε-greedy with a fixed ε.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn constant(epsilon: f64) -> Result<Self, DqlError> {
        Self::new(Schedule::Constant(epsilon))
    }

    /// ε-decreasing: ε = `start` in episode 0, multiplied by `factor` after every
    /// episode, never below `floor`.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn decreasing(start: f64, factor: f64, floor: f64) -> Result<Self, DqlError> {
        Self::new(Schedule::Exponential {
            start,
            factor,
            floor,
        })
    }

    /// The ε in force (set by the last [`begin_episode`](ExplorationPolicy::begin_episode)).
    #[must_use]
    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }

    /// The schedule.
    #[must_use]
    pub fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    /// The exploration half of a step: with probability ε a uniformly random action
    /// in `0..n_actions`, otherwise `None` (exploit). Policies that exploit by another
    /// rule than the greedy argmax (EA-MADM's decision) reuse it, so their draws match
    /// this policy's: one coin flip, then one action index when exploring.
    #[inline(always)]
    pub fn explore_action<R: Rng + ?Sized>(&self, n_actions: usize, rng: &mut R) -> Option<usize> {
        self.explore
            .flip(rng)
            .then(|| rng.random_range(0..n_actions))
    }
}

impl ExplorationPolicy for EpsilonGreedy {
    fn begin_episode(&mut self, episode: u64) {
        self.epsilon = self
            .schedule
            .value_from(self.episode, self.epsilon, episode);
        self.episode = episode;
        self.explore = Coin::new(self.epsilon);
    }

    #[inline(always)]
    fn select<R: Rng + ?Sized>(
        &mut self,
        _state: usize,
        action_values: &[f64],
        rng: &mut R,
    ) -> usize {
        match self.explore_action(action_values.len(), rng) {
            Some(action) => action,
            None => argmax_random_tie(action_values, rng),
        }
    }
}

/// Softmax (Boltzmann) exploration: `P(a) ∝ exp(Q(s, a) / T)`, with the
/// temperature `T` on a schedule (Table 1 anneals it from 0.1 to 0.01 by 0.95 per
/// episode).
///
/// Computed stably: the maximum is subtracted before `exp` (log-sum-exp), so the
/// largest weight is exactly 1, the normaliser is at least 1, and probabilities
/// are finite for any finite values and any `T > 0` (rewards of ±100 at T = 0.01
/// would overflow a naive `exp`). Each selection draws one `f64`.
///
/// Serialised as its schedule: `{"temperature": {"constant": 0.1}}`;
/// deserialising validates it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "SoftmaxRepr", into = "SoftmaxRepr")]
pub struct Softmax {
    schedule: Schedule,
    temperature: f64,
    /// The episode `temperature` is the schedule's value of (0 before any episode).
    episode: u64,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SoftmaxRepr {
    temperature: Schedule,
}

impl TryFrom<SoftmaxRepr> for Softmax {
    type Error = DqlError;
    fn try_from(repr: SoftmaxRepr) -> Result<Self, DqlError> {
        Self::new(repr.temperature)
    }
}

impl From<Softmax> for SoftmaxRepr {
    fn from(policy: Softmax) -> Self {
        Self {
            temperature: policy.schedule,
        }
    }
}

impl Softmax {
    /// Softmax whose temperature follows `schedule`.
    ///
    /// # Errors
    /// [`DqlError::InvalidParameter`] naming `temperature` (or `temperature.start`,
    /// `.factor`, `.floor`) when a temperature is not finite and positive, the
    /// factor outside (0, 1], or the floor above the start.
    pub fn new(schedule: Schedule) -> Result<Self, DqlError> {
        schedule.validate("temperature", Domain::Positive)?;
        Ok(Self {
            schedule,
            temperature: schedule.start(),
            episode: 0,
        })
    }

    /// Softmax with a fixed temperature.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn constant(temperature: f64) -> Result<Self, DqlError> {
        Self::new(Schedule::Constant(temperature))
    }

    /// Annealed softmax: `T = start` in episode 0, multiplied by `factor` after
    /// every episode, never below `floor`.
    ///
    /// # Errors
    /// As [`new`](Self::new).
    pub fn annealed(start: f64, factor: f64, floor: f64) -> Result<Self, DqlError> {
        Self::new(Schedule::Exponential {
            start,
            factor,
            floor,
        })
    }

    /// The temperature in force.
    #[must_use]
    pub fn temperature(&self) -> f64 {
        self.temperature
    }

    /// The schedule.
    #[must_use]
    pub fn schedule(&self) -> &Schedule {
        &self.schedule
    }

    /// Unnormalised weight `exp((value − max) / T)` in [0, 1]. Dividing (rather
    /// than multiplying by `1/T`) keeps `0/T = 0` even when `1/T` overflows.
    #[inline]
    fn weight(&self, value: f64, max: f64) -> f64 {
        ((value - max) / self.temperature).exp()
    }

    /// Writes the selection probabilities for `action_values` at the current
    /// temperature into `out`. For finite values they are finite, in [0, 1], and
    /// sum to 1 up to rounding.
    ///
    /// # Panics
    /// If `out.len() != action_values.len()`.
    pub fn probabilities(&self, action_values: &[f64], out: &mut [f64]) {
        assert_eq!(out.len(), action_values.len(), "probability buffer length");
        let max = max_value(action_values);
        let mut total = 0.0;
        for (probability, &value) in out.iter_mut().zip(action_values) {
            *probability = self.weight(value, max);
            total += *probability;
        }
        for probability in out.iter_mut() {
            *probability /= total;
        }
    }
}

impl ExplorationPolicy for Softmax {
    fn begin_episode(&mut self, episode: u64) {
        self.temperature = self
            .schedule
            .value_from(self.episode, self.temperature, episode);
        self.episode = episode;
    }

    fn select<R: Rng + ?Sized>(
        &mut self,
        _state: usize,
        action_values: &[f64],
        rng: &mut R,
    ) -> usize {
        let max = max_value(action_values);
        let mut total = 0.0;
        for &value in action_values {
            total += self.weight(value, max);
        }
        let threshold = rng.random::<f64>() * total;
        // Weights are recomputed rather than buffered: no allocation, and the
        // cumulative sum below repeats `total`'s additions in the same order.
        // `exp` is pure, and the optimiser already shares its calls between the two
        // loops (callgrind counts one call per action); a stack buffer, with or
        // without skipping the maximum's `exp(0) = 1`, ran more instructions in all.
        let mut cumulative = 0.0;
        let mut last_positive = 0;
        for (index, &value) in action_values.iter().enumerate() {
            let weight = self.weight(value, max);
            if weight > 0.0 {
                last_positive = index;
            }
            cumulative += weight;
            if threshold < cumulative {
                return index;
            }
        }
        // Only reached when `threshold` rounded up to `total`.
        last_positive
    }
}

/// The built-in policies as one serialisable value, for configs that pick a
/// policy by name: `{"kind": "greedy"}`,
/// `{"kind": "epsilon_greedy", "epsilon": {"constant": 0.1}}`,
/// `{"kind": "softmax", "temperature": {"exponential": {"start": 0.1, "factor": 0.95, "floor": 0.01}}}`.
///
/// An unknown key is an error that names it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "BuiltinPolicyRepr", into = "BuiltinPolicyRepr")]
pub enum BuiltinPolicy {
    /// [`Greedy`].
    Greedy,
    /// [`EpsilonGreedy`] (ε-decreasing with an exponential schedule).
    EpsilonGreedy(EpsilonGreedy),
    /// [`Softmax`].
    Softmax(Softmax),
}

/// The serialised form of a [`BuiltinPolicy`]: the same shape, but `Greedy` is an empty struct
/// variant, which rejects extra keys (a unit variant of an internally tagged enum would not).
/// The other variants' reprs reject unknown keys themselves.
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum BuiltinPolicyRepr {
    Greedy {},
    EpsilonGreedy(EpsilonGreedy),
    Softmax(Softmax),
}

impl From<BuiltinPolicyRepr> for BuiltinPolicy {
    fn from(repr: BuiltinPolicyRepr) -> Self {
        match repr {
            BuiltinPolicyRepr::Greedy {} => Self::Greedy,
            BuiltinPolicyRepr::EpsilonGreedy(policy) => Self::EpsilonGreedy(policy),
            BuiltinPolicyRepr::Softmax(policy) => Self::Softmax(policy),
        }
    }
}

impl From<BuiltinPolicy> for BuiltinPolicyRepr {
    fn from(policy: BuiltinPolicy) -> Self {
        match policy {
            BuiltinPolicy::Greedy => Self::Greedy {},
            BuiltinPolicy::EpsilonGreedy(policy) => Self::EpsilonGreedy(policy),
            BuiltinPolicy::Softmax(policy) => Self::Softmax(policy),
        }
    }
}

impl ExplorationPolicy for BuiltinPolicy {
    fn begin_episode(&mut self, episode: u64) {
        match self {
            Self::Greedy => Greedy.begin_episode(episode),
            Self::EpsilonGreedy(policy) => policy.begin_episode(episode),
            Self::Softmax(policy) => policy.begin_episode(episode),
        }
    }

    fn end_episode(&mut self, episode: u64) {
        match self {
            Self::Greedy => Greedy.end_episode(episode),
            Self::EpsilonGreedy(policy) => policy.end_episode(episode),
            Self::Softmax(policy) => policy.end_episode(episode),
        }
    }

    #[inline]
    fn select<R: Rng + ?Sized>(
        &mut self,
        state: usize,
        action_values: &[f64],
        rng: &mut R,
    ) -> usize {
        match self {
            Self::Greedy => Greedy.select(state, action_values, rng),
            Self::EpsilonGreedy(policy) => policy.select(state, action_values, rng),
            Self::Softmax(policy) => policy.select(state, action_values, rng),
        }
    }
}

impl From<Greedy> for BuiltinPolicy {
    fn from(_: Greedy) -> Self {
        Self::Greedy
    }
}

impl From<EpsilonGreedy> for BuiltinPolicy {
    fn from(policy: EpsilonGreedy) -> Self {
        Self::EpsilonGreedy(policy)
    }
}

impl From<Softmax> for BuiltinPolicy {
    fn from(policy: Softmax) -> Self {
        Self::Softmax(policy)
    }
}
