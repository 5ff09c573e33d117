//! The per-seed distribution a report prints: quartiles, values at the cap, bimodality.

use serde::{Deserialize, Serialize};

use super::location::{median, quantile_sorted};
use super::{StatsError, check_sample, sorted_copy};

/// The per-seed distribution in a form a report prints.
///
/// `bimodal` is true when either rule holds:
/// * **cap rule** (with a cap): at least 2 values at or above the cap and at least 2 below it
///   — some seeds are stuck at the step cap while others are not;
/// * **gap rule**: the sorted values split at one place into a lower and an upper group of at
///   least 2 values each, and the gap between the groups is wider than the two groups' ranges
///   added together — two clusters further apart than either is wide.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Distribution {
    /// Number of values.
    pub n: usize,
    /// Smallest value.
    pub min: f64,
    /// First quartile (type 7).
    pub q1: f64,
    /// Median.
    pub median: f64,
    /// Third quartile (type 7).
    pub q3: f64,
    /// Largest value.
    pub max: f64,
    /// How many values are at or above the cap (0 without a cap).
    pub at_cap: usize,
    /// Whether the values form two separated groups (see the type's docs).
    pub bimodal: bool,
}

/// The per-seed distribution of `x`; `cap` is the step cap, if the values have one.
pub fn distribution(x: &[f64], cap: Option<f64>) -> Result<Distribution, StatsError> {
    check_sample(x, "x")?;
    if let Some(cap) = cap.filter(|c| !c.is_finite()) {
        return Err(StatsError::InvalidParameter {
            name: "cap",
            value: cap.to_string(),
            expected: "a finite number",
        });
    }
    let sorted = sorted_copy(x);
    let n = sorted.len();
    let at_cap = cap.map_or(0, |cap| sorted.iter().filter(|&&v| v >= cap).count());
    let cap_rule = cap.is_some() && at_cap >= 2 && n - at_cap >= 2;
    let gap_rule = (2..=n.saturating_sub(2)).any(|k| {
        let gap = sorted[k] - sorted[k - 1];
        let spread = (sorted[k - 1] - sorted[0]) + (sorted[n - 1] - sorted[k]);
        gap > spread
    });
    Ok(Distribution {
        n,
        min: sorted[0],
        q1: quantile_sorted(&sorted, 0.25),
        median: median(x)?,
        q3: quantile_sorted(&sorted, 0.75),
        max: sorted[n - 1],
        at_cap,
        bimodal: cap_rule || gap_rule,
    })
}
