//! Random streams: every draw of a run comes from a `ChaCha8` generator keyed by the run's seed
//! and a stream number naming its purpose, so no two purposes share draws and none depends on
//! the order in which threads run.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// What a random stream is for. Its number is the `ChaCha` stream id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stream {
    /// Initial values of the source task's tables.
    SourceInit,
    /// The source task's exploration, tie-breaks and estimator choices.
    SourceTraining,
    /// The seeds handed to the environment's `reset` in training episodes.
    SourceEnvironment,
    /// The greedy evaluation episode's tie-breaks.
    Evaluation,
    /// The seed handed to the environment's `reset` in the evaluation episode.
    EvaluationEnvironment,
    /// A competitor's warm-up episodes before its recorded ones (budget-matched control).
    Warmup,
    /// The seeds handed to the environment's `reset` in warm-up episodes.
    WarmupEnvironment,
    /// The tie-breaks of the periodic greedy evaluation after `n` training episodes (one
    /// stream per evaluation, so each is the same whichever others are made).
    PeriodicEvaluation(u64),
    /// The seed handed to the environment's `reset` in the periodic greedy evaluation after
    /// `n` training episodes.
    PeriodicEvaluationEnvironment(u64),
    /// Sub-task `k`'s learner: initial values, exploration, tie-breaks.
    Pretrain(usize),
    /// The seeds handed to the environment's `reset` in sub-task `k`'s episodes.
    PretrainEnvironment(usize),
    /// The tie-breaks of sub-task `k`'s convergence checks (the stopping rule; the same at
    /// every check, so an unchanged policy plays the same check episode).
    PretrainCheck(usize),
    /// The seed handed to the environment's `reset` in sub-task `k`'s convergence checks.
    PretrainCheckEnvironment(usize),
}

impl Stream {
    fn id(self) -> u64 {
        let wide = |k: usize| u64::try_from(k).unwrap_or(u64::MAX >> 8) & 0xFFFF_FFFF;
        match self {
            Self::SourceInit => 1,
            Self::SourceTraining => 2,
            Self::SourceEnvironment => 3,
            Self::Evaluation => 4,
            Self::EvaluationEnvironment => 5,
            Self::Warmup => 6,
            Self::WarmupEnvironment => 7,
            Self::Pretrain(k) => 1 << 32 | wide(k),
            Self::PretrainEnvironment(k) => 2 << 32 | wide(k),
            Self::PeriodicEvaluation(n) => 3 << 32 | (n & 0xFFFF_FFFF),
            Self::PeriodicEvaluationEnvironment(n) => 4 << 32 | (n & 0xFFFF_FFFF),
            Self::PretrainCheck(k) => 5 << 32 | wide(k),
            Self::PretrainCheckEnvironment(k) => 6 << 32 | wide(k),
        }
    }
}

/// The generator of `stream` in the run with seed `seed`.
pub(crate) fn stream_rng(seed: u64, stream: Stream) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream.id());
    rng
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::RngExt;

    #[test]
    fn streams_differ_and_repeat() {
        let draw = |seed, stream| stream_rng(seed, stream).random::<u64>();
        let all = [
            Stream::SourceInit,
            Stream::SourceTraining,
            Stream::SourceEnvironment,
            Stream::Evaluation,
            Stream::EvaluationEnvironment,
            Stream::Warmup,
            Stream::WarmupEnvironment,
            Stream::PeriodicEvaluation(1),
            Stream::PeriodicEvaluation(2),
            Stream::PeriodicEvaluationEnvironment(1),
            Stream::PeriodicEvaluationEnvironment(2),
            Stream::Pretrain(0),
            Stream::Pretrain(1),
            Stream::PretrainEnvironment(0),
            Stream::PretrainEnvironment(1),
            Stream::PretrainCheck(0),
            Stream::PretrainCheck(1),
            Stream::PretrainCheckEnvironment(0),
            Stream::PretrainCheckEnvironment(1),
        ];
        let mut seen = std::collections::HashSet::new();
        for stream in all {
            assert_eq!(draw(7, stream), draw(7, stream));
            assert!(
                seen.insert(draw(7, stream)),
                "{stream:?} repeats another stream"
            );
            assert_ne!(draw(7, stream), draw(8, stream));
        }
    }
}
