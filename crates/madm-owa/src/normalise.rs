//! Per-attribute (column) normalisation of a decision matrix before OWA: standard MADM practice
//! (Hwang and Yoon 1981), which the paper does not do (paper-notes §6). Without it, an
//! attribute on a large scale (a sub-task whose values are in the tens) decides every row's
//! aggregate, whatever the other attributes say. Two scalings: min–max onto `[0, 1]`, and the
//! standard score (z-score) `(x − mean) / sd` over the column's rows.

use serde::{Deserialize, Serialize};

/// How each attribute of a decision matrix is scaled before its rows are aggregated.
/// TOML: `normalisation = "none"` (the paper), `"min_max"` or `"z_score"`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normalisation {
    /// The attributes as they are (the paper).
    #[default]
    None,
    /// Each attribute linearly onto `[0, 1]` over the rows: `(x − min) / (max − min)`, the
    /// column's best row 1 and its worst 0; a constant column (nothing to tell the rows apart)
    /// maps to ½.
    MinMax,
    /// Each attribute standardised over the rows: `(x − mean) / sd` with the population
    /// standard deviation (the column's standard score, as Eq. 11 standardises rewards across
    /// sub-tasks); a constant column maps to 0. The plain aggregators of the reproduction
    /// (issue 32) compare standardised columns this way.
    ZScore,
}

/// What a column's scaling needs: its smallest and largest value, its mean and its population
/// standard deviation, over the rows that have a value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColumnSummary {
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// The mean.
    pub mean: f64,
    /// The population standard deviation (0 for a constant column).
    pub sd: f64,
}

impl ColumnSummary {
    /// The summary of the finite `values` (at least one). Computed on the values divided by
    /// their largest magnitude, so no square overflows; the mean and SD are scaled back.
    ///
    /// # Panics
    /// If `values` is empty.
    #[must_use]
    pub fn of(values: &[f64]) -> Self {
        assert!(!values.is_empty(), "a column has at least one value");
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let magnitude = min.abs().max(max.abs());
        if magnitude == 0.0 || min == max {
            return Self {
                min,
                max,
                mean: min,
                sd: 0.0,
            };
        }
        let n = values.len() as f64;
        let mean_scaled = values.iter().map(|v| v / magnitude).sum::<f64>() / n;
        let variance_scaled = values
            .iter()
            .map(|v| (v / magnitude - mean_scaled).powi(2))
            .sum::<f64>()
            / n;
        Self {
            min,
            max,
            mean: mean_scaled * magnitude,
            sd: variance_scaled.sqrt() * magnitude,
        }
    }
}

impl Normalisation {
    /// `x` of a column summarised by `column`, scaled. Finite for finite input; the result of
    /// [`MinMax`](Self::MinMax) lies in `[0, 1]`, that of [`ZScore`](Self::ZScore) in
    /// `[−√(n−1), √(n−1)]` for a column of `n` rows.
    #[must_use]
    pub fn scale(self, x: f64, column: &ColumnSummary) -> f64 {
        let (min, max) = (column.min, column.max);
        match self {
            Self::None => x,
            Self::ZScore => {
                if column.sd > 0.0 && column.sd.is_finite() {
                    // halves: x − mean stays finite for columns spanning more than f64::MAX
                    (x / 2.0 - column.mean / 2.0) / (column.sd / 2.0)
                } else {
                    0.0
                }
            }
            Self::MinMax => {
                // halves: no overflow for columns spanning more than f64::MAX
                let range = max / 2.0 - min / 2.0;
                if range > 0.0 {
                    ((x / 2.0 - min / 2.0) / range).clamp(0.0, 1.0)
                } else {
                    0.5
                }
            }
        }
    }

    /// Scales every column of the row-major `rows × cols` `matrix` in place.
    ///
    /// # Panics
    /// If `matrix.len() != rows * cols`.
    pub fn apply(self, matrix: &mut [f64], rows: usize, cols: usize) {
        assert_eq!(matrix.len(), rows * cols, "matrix is rows × cols");
        if self == Self::None {
            return;
        }
        let mut column = Vec::with_capacity(rows);
        for col in 0..cols {
            column.clear();
            column.extend(matrix.iter().skip(col).step_by(cols).copied());
            if column.is_empty() {
                continue;
            }
            let summary = ColumnSummary::of(&column);
            for value in matrix.iter_mut().skip(col).step_by(cols) {
                *value = self.scale(*value, &summary);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn min_max_puts_each_column_on_zero_one() {
        let mut matrix = [10.0, 0.25, 30.0, 0.75, 20.0, 0.5];
        Normalisation::MinMax.apply(&mut matrix, 3, 2);
        assert_eq!(matrix, [0.0, 0.0, 1.0, 1.0, 0.5, 0.5]);
        let mut constant = [4.0, 4.0];
        Normalisation::MinMax.apply(&mut constant, 2, 1);
        assert_eq!(constant, [0.5, 0.5]);
        let mut same = [10.0, -3.0];
        Normalisation::None.apply(&mut same, 2, 1);
        assert_eq!(same, [10.0, -3.0]);
    }

    #[test]
    fn z_score_standardises_each_column() {
        // column 0: 1, 2, 3 (mean 2, population sd √(2/3)); column 1 constant
        let mut matrix = [1.0, 7.0, 2.0, 7.0, 3.0, 7.0];
        Normalisation::ZScore.apply(&mut matrix, 3, 2);
        let z = 1.0 / (2.0_f64 / 3.0).sqrt();
        for (got, want) in matrix.iter().zip([-z, 0.0, 0.0, 0.0, z, 0.0]) {
            assert!((got - want).abs() < 1e-12, "{matrix:?}");
        }
        // the "do not hit" column of a state with one bumping action among four
        let mut column = [0.0, 0.0, -100.0, 0.0];
        Normalisation::ZScore.apply(&mut column, 4, 1);
        let third = 1.0 / 3.0_f64.sqrt();
        for (got, want) in column.iter().zip([third, third, -3.0 * third, third]) {
            assert!((got - want).abs() < 1e-12, "{column:?}");
        }
        let summary = ColumnSummary::of(&[f64::MAX, -f64::MAX]);
        assert_eq!(summary.mean, 0.0);
        assert!(summary.sd.is_finite());
        assert_eq!(Normalisation::ZScore.scale(f64::MAX, &summary), 1.0);
    }

    proptest! {
        /// Min–max scaling keeps each column's order and lands in [0, 1].
        #[test]
        fn min_max_is_monotone_and_bounded(
            values in prop::collection::vec(-1e300f64..1e300, 1..8),
            i in 0usize..8, j in 0usize..8,
        ) {
            let (i, j) = (i % values.len(), j % values.len());
            let mut column = values.clone();
            Normalisation::MinMax.apply(&mut column, values.len(), 1);
            prop_assert!(column.iter().all(|v| (0.0..=1.0).contains(v)));
            if values[i] < values[j] {
                prop_assert!(column[i] <= column[j]);
            }
        }

        /// The z-score keeps each column's order, is finite, and has mean 0 and (unless the
        /// column is constant) population SD 1.
        #[test]
        fn z_score_is_monotone_centred_and_unit(
            values in prop::collection::vec(-1e300f64..1e300, 1..8),
            i in 0usize..8, j in 0usize..8,
        ) {
            let (i, j) = (i % values.len(), j % values.len());
            let mut column = values.clone();
            Normalisation::ZScore.apply(&mut column, values.len(), 1);
            prop_assert!(column.iter().all(|v| v.is_finite()));
            if values[i] < values[j] {
                prop_assert!(column[i] <= column[j]);
            }
            let n = column.len() as f64;
            let mean = column.iter().sum::<f64>() / n;
            prop_assert!(mean.abs() < 1e-9, "{column:?}");
            let variance = column.iter().map(|z| (z - mean).powi(2)).sum::<f64>() / n;
            let constant = values.iter().all(|v| *v == values[0]);
            if constant {
                prop_assert!(column.iter().all(|z| *z == 0.0));
            } else {
                prop_assert!((variance - 1.0).abs() < 1e-9, "{variance}");
            }
        }
    }
}
