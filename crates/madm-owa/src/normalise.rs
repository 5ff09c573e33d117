//! Per-attribute (column) normalisation of a decision matrix before OWA: standard MADM practice
//! (Hwang and Yoon 1981), which the paper does not do (paper-notes §6). Without it, an
//! attribute on a large scale (a sub-task whose values are in the tens) decides every row's
//! aggregate, whatever the other attributes say.

use serde::{Deserialize, Serialize};

/// How each attribute of a decision matrix is scaled before its rows are aggregated.
/// TOML: `normalisation = "none"` (the paper) or `"min_max"`.
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
}

impl Normalisation {
    /// `x` of a column whose values span `[min, max]`, scaled. Finite for finite input;
    /// the result of [`MinMax`](Self::MinMax) lies in `[0, 1]`.
    #[must_use]
    pub fn scale(self, x: f64, min: f64, max: f64) -> f64 {
        match self {
            Self::None => x,
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
        for col in 0..cols {
            let column = || matrix.iter().skip(col).step_by(cols).copied();
            let min = column().fold(f64::INFINITY, f64::min);
            let max = column().fold(f64::NEG_INFINITY, f64::max);
            for value in matrix.iter_mut().skip(col).step_by(cols) {
                *value = self.scale(*value, min, max);
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
    }
}
