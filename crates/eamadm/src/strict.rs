//! Strict serde forms for parameter types of other crates whose own forms ignore unknown keys.
//!
//! `dql`'s [`Schedule`], [`Initialisation`] and [`DoubleQParams`] serialise without
//! `deny_unknown_fields`, and in `madm_owa`'s [`Weighting`] and [`Support`] the field-less
//! variants (`{ kind = "uniform" }`) are unit variants, which serde lets carry any extra key. A
//! misspelt key there would be silently dropped. Experiment configs use these modules
//! (`#[serde(with = "…")]`): the same data shape, but an unknown key is an error that names it.
//! Field-less variants are written as empty struct variants (`Zero {}`), which do reject
//! extra keys.

use dql::{BehaviourValues, DoubleQParams, Initialisation, Schedule};
use madm_owa::{DEFAULT_EPSILON, OwaWeights, Support, Weighting};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// [`Schedule`]: `{ constant = 0.1 }` or `{ exponential = { start, factor, floor } }`.
pub(crate) mod schedule {
    use super::{Deserialize, Deserializer, Schedule, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    #[serde(rename_all = "snake_case", deny_unknown_fields)]
    pub(super) enum Repr {
        Constant(f64),
        Exponential { start: f64, factor: f64, floor: f64 },
    }

    impl From<Repr> for Schedule {
        fn from(repr: Repr) -> Self {
            match repr {
                Repr::Constant(value) => Self::Constant(value),
                Repr::Exponential {
                    start,
                    factor,
                    floor,
                } => Self::Exponential {
                    start,
                    factor,
                    floor,
                },
            }
        }
    }

    impl From<Schedule> for Repr {
        fn from(schedule: Schedule) -> Self {
            match schedule {
                Schedule::Constant(value) => Self::Constant(value),
                Schedule::Exponential {
                    start,
                    factor,
                    floor,
                } => Self::Exponential {
                    start,
                    factor,
                    floor,
                },
            }
        }
    }

    pub(crate) fn serialize<S: Serializer>(
        schedule: &Schedule,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        Repr::from(*schedule).serialize(serializer)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        deserializer: D,
    ) -> Result<Schedule, D::Error> {
        Repr::deserialize(deserializer).map(Schedule::from)
    }
}

/// [`Initialisation`]: `{ kind = "zero" }`, `{ kind = "constant", value }` or
/// `{ kind = "uniform", low, high }`.
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum InitRepr {
    Zero {},
    Constant { value: f64 },
    Uniform { low: f64, high: f64 },
}

impl From<InitRepr> for Initialisation {
    fn from(repr: InitRepr) -> Self {
        match repr {
            InitRepr::Zero {} => Self::Zero,
            InitRepr::Constant { value } => Self::Constant { value },
            InitRepr::Uniform { low, high } => Self::Uniform { low, high },
        }
    }
}

impl From<Initialisation> for InitRepr {
    fn from(init: Initialisation) -> Self {
        match init {
            Initialisation::Zero => Self::Zero {},
            Initialisation::Constant { value } => Self::Constant { value },
            Initialisation::Uniform { low, high } => Self::Uniform { low, high },
        }
    }
}

fn default_init() -> InitRepr {
    InitRepr::Zero {}
}

fn default_xi() -> f64 {
    DoubleQParams::default().xi
}

/// [`DoubleQParams`]: `alpha`, `gamma`, and optionally `xi` (0.5), `init` (zero) and
/// `behaviour` (`"mean"`).
pub(crate) mod learner {
    use super::{
        BehaviourValues, Deserialize, Deserializer, DoubleQParams, InitRepr, Serialize, Serializer,
        default_init, default_xi,
    };

    #[derive(Serialize, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Repr {
        alpha: f64,
        gamma: f64,
        #[serde(default = "default_xi")]
        xi: f64,
        #[serde(default = "default_init")]
        init: InitRepr,
        #[serde(default)]
        behaviour: BehaviourValues,
    }

    pub(crate) fn serialize<S: Serializer>(
        params: &DoubleQParams,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        Repr {
            alpha: params.alpha,
            gamma: params.gamma,
            xi: params.xi,
            init: params.init.into(),
            behaviour: params.behaviour,
        }
        .serialize(serializer)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        deserializer: D,
    ) -> Result<DoubleQParams, D::Error> {
        let repr = Repr::deserialize(deserializer)?;
        Ok(DoubleQParams {
            alpha: repr.alpha,
            gamma: repr.gamma,
            xi: repr.xi,
            init: repr.init.into(),
            behaviour: repr.behaviour,
        })
    }
}

/// [`Support`]: `{ kind = "paper", epsilon = 1e-9 }` (`epsilon` optional) or
/// `{ kind = "distance" }`.
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum SupportRepr {
    Paper {
        #[serde(default = "default_epsilon")]
        epsilon: f64,
    },
    Distance {},
}

fn default_epsilon() -> f64 {
    DEFAULT_EPSILON
}

fn default_support() -> SupportRepr {
    SupportRepr::Paper {
        epsilon: DEFAULT_EPSILON,
    }
}

impl From<SupportRepr> for Support {
    fn from(repr: SupportRepr) -> Self {
        match repr {
            SupportRepr::Paper { epsilon } => Self::Paper { epsilon },
            SupportRepr::Distance {} => Self::Distance,
        }
    }
}

impl From<Support> for SupportRepr {
    fn from(support: Support) -> Self {
        match support {
            Support::Paper { epsilon } => Self::Paper { epsilon },
            Support::Distance => Self::Distance {},
        }
    }
}

/// [`Weighting`]: `{ kind = "visibility", support = … }` (`support` optional),
/// `{ kind = "uniform" }`, `{ kind = "given", weights = […] }` or
/// `{ kind = "maximum_entropy", orness = 0.7 }`.
pub(crate) mod weighting {
    use super::{
        Deserialize, Deserializer, OwaWeights, Serialize, Serializer, SupportRepr, Weighting,
        default_support,
    };

    #[derive(Serialize, Deserialize)]
    #[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
    enum Repr {
        Uniform {},
        Given {
            weights: OwaWeights,
        },
        MaximumEntropy {
            orness: f64,
        },
        Visibility {
            #[serde(default = "default_support")]
            support: SupportRepr,
        },
    }

    pub(crate) fn serialize<S: Serializer>(
        weighting: &Weighting,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        match weighting {
            Weighting::Uniform => Repr::Uniform {},
            Weighting::Given { weights } => Repr::Given {
                weights: weights.clone(),
            },
            Weighting::MaximumEntropy { orness } => Repr::MaximumEntropy { orness: *orness },
            Weighting::Visibility { support } => Repr::Visibility {
                support: (*support).into(),
            },
        }
        .serialize(serializer)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        deserializer: D,
    ) -> Result<Weighting, D::Error> {
        Ok(match Repr::deserialize(deserializer)? {
            Repr::Uniform {} => Weighting::Uniform,
            Repr::Given { weights } => Weighting::Given { weights },
            Repr::MaximumEntropy { orness } => Weighting::MaximumEntropy { orness },
            Repr::Visibility { support } => Weighting::Visibility {
                support: support.into(),
            },
        })
    }

    /// The default weighting, for `#[serde(default = …)]`.
    pub(crate) fn default() -> Weighting {
        Weighting::default()
    }
}
