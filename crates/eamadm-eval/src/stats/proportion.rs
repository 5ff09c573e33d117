//! Success proportions: the Wilson score interval.

use super::normal::normal_quantile;
use super::{Interval, StatsError, check_confidence};

/// Wilson score interval for a proportion; estimate = successes / trials.
pub fn wilson(successes: u64, trials: u64, confidence: f64) -> Result<Interval, StatsError> {
    if trials == 0 {
        return Err(StatsError::InvalidParameter {
            name: "trials",
            value: "0".to_owned(),
            expected: "at least 1 trial",
        });
    }
    if successes > trials {
        return Err(StatsError::InvalidParameter {
            name: "successes",
            value: successes.to_string(),
            expected: "at most the number of trials",
        });
    }
    check_confidence(confidence)?;
    let z = normal_quantile(1.0 - (1.0 - confidence) / 2.0)?;
    let n = trials as f64;
    let proportion = successes as f64 / n;
    let z2 = z * z;
    let denominator = 1.0 + z2 / n;
    let centre = (proportion + z2 / (2.0 * n)) / denominator;
    let half = z * (proportion * (1.0 - proportion) / n + z2 / (4.0 * n * n)).sqrt() / denominator;
    Ok(Interval {
        estimate: proportion,
        low: (centre - half).clamp(0.0, proportion),
        high: (centre + half).clamp(proportion, 1.0),
    })
}
