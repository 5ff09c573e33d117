//! Per-episode schedules for policy parameters (ε, temperature).

use serde::{Deserialize, Serialize};

use crate::error::{DqlError, check_param};

/// How a policy parameter evolves over episodes (Table 1's annealing).
///
/// Schedules are values, not code paths: ε-decreasing is ε-greedy with an
/// exponential schedule, annealed softmax is softmax with one.
/// Serialised as `{"constant": 0.1}` or
/// `{"exponential": {"start": 0.95, "factor": 0.95, "floor": 0.0}}`; an unknown key is an
/// error that names it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Schedule {
    /// The same value in every episode.
    Constant(f64),
    /// `start` in episode 0, then multiplied by `factor` after every episode and
    /// never below `floor`: episode `k` uses `max(floor, start · factor^k)`, with
    /// the power computed by `k` successive multiplications, exactly as
    /// "ε ← ε · factor after every episode" would.
    Exponential {
        /// Value in episode 0.
        start: f64,
        /// Multiplier applied after every episode, in (0, 1].
        factor: f64,
        /// Lower bound, at most `start`.
        floor: f64,
    },
}

/// The admissible range of a scheduled parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Domain {
    /// A probability in [0, 1] (ε).
    Probability,
    /// A strictly positive finite value (temperature).
    Positive,
}

impl Domain {
    fn contains(self, value: f64) -> bool {
        match self {
            Self::Probability => (0.0..=1.0).contains(&value),
            Self::Positive => value > 0.0 && value.is_finite(),
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Self::Probability => "a probability in [0, 1]",
            Self::Positive => "a finite value > 0",
        }
    }
}

impl Schedule {
    /// The value used in episode `episode` (0-based).
    ///
    /// Exponential schedules cost at most `min(episode, n)` multiplications, `n`
    /// being the number of episodes until the floor is reached (45 for Table 1's
    /// temperature 0.1 → 0.01 with factor 0.95). A caller walking the episodes in order
    /// pays one multiplication per episode with [`value_from`](Self::value_from) (no
    /// closed form `start · factor^k` does: `powi` rounds once where this rounds `k` times,
    /// so it differs in the last bits).
    #[must_use]
    pub fn value(&self, episode: u64) -> f64 {
        match *self {
            Self::Constant(value) => value,
            Self::Exponential {
                start,
                factor,
                floor,
            } => {
                // Repeated multiplication is monotone in floating point (x·f ≤ x for
                // f ≤ 1), which a closed-form power does not guarantee.
                let mut value = start;
                if factor < 1.0 {
                    for _ in 0..episode {
                        if value <= floor || value == 0.0 {
                            break;
                        }
                        value *= factor;
                    }
                }
                value.max(floor)
            }
        }
    }

    /// The value in episode `episode + 1` given `value`, the value in episode `episode`
    /// (any episode): one multiplication, bit for bit what [`value`](Self::value) gives for
    /// the next episode.
    ///
    /// [`value`](Self::value) stops multiplying once the product is at or below `floor`, and
    /// returns `max(floor, product)`; so a value above `floor` is the product itself and the
    /// next one is `max(floor, value · factor)`, and a value at `floor` stays there.
    #[must_use]
    pub fn next_value(&self, value: f64) -> f64 {
        match *self {
            Self::Constant(value) => value,
            Self::Exponential { factor, floor, .. } => {
                if factor < 1.0 && value > floor {
                    (value * factor).max(floor)
                } else {
                    value
                }
            }
        }
    }

    /// The value in episode `episode`, knowing `known`, the value in episode `at`: O(1) when
    /// `episode` is `at` or `at + 1` (policies count episodes up one by one), else
    /// [`value`](Self::value). Bit for bit `self.value(episode)` whenever
    /// `known == self.value(at)`.
    #[must_use]
    pub fn value_from(&self, at: u64, known: f64, episode: u64) -> f64 {
        if episode == at {
            known
        } else if Some(episode) == at.checked_add(1) {
            self.next_value(known)
        } else {
            self.value(episode)
        }
    }

    /// The value in episode 0 (the largest value the schedule takes).
    #[must_use]
    pub fn start(&self) -> f64 {
        match *self {
            Self::Constant(value) => value,
            Self::Exponential { start, .. } => start,
        }
    }

    /// Checks the schedule for a parameter called `name` in `domain`: values in
    /// the domain, `factor ∈ (0, 1]`, `floor ≤ start`.
    pub(crate) fn validate(&self, name: &str, domain: Domain) -> Result<(), DqlError> {
        match *self {
            Self::Constant(value) => {
                check_param(name, value, domain.contains(value), domain.describe())
            }
            Self::Exponential {
                start,
                factor,
                floor,
            } => {
                check_param(
                    &format!("{name}.start"),
                    start,
                    domain.contains(start),
                    domain.describe(),
                )?;
                check_param(
                    &format!("{name}.factor"),
                    factor,
                    factor > 0.0 && factor <= 1.0,
                    "an annealing factor in (0, 1]",
                )?;
                check_param(
                    &format!("{name}.floor"),
                    floor,
                    domain.contains(floor),
                    domain.describe(),
                )?;
                check_param(
                    &format!("{name}.floor"),
                    floor,
                    floor <= start,
                    "a floor no larger than start",
                )
            }
        }
    }
}
