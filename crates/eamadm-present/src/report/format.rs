//! Text for `REPORT.md`: Markdown tables whose columns line up in the raw file, and numbers
//! rounded to the digits they can support.

use thiserror::Error;

use eamadm_eval::Role;
use eamadm_eval::claims::Share;
use eamadm_eval::stats::Interval;

/// A table row of the wrong length.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("table row {row} has {found} cells, the header has {expected}")]
pub struct RowLengthError {
    /// Index of the offending row (0-based, header excluded).
    pub row: usize,
    /// Number of cells in the row.
    pub found: usize,
    /// Number of columns in the header.
    pub expected: usize,
}

/// How a column's cells sit in their column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    /// Text columns.
    Left,
    /// Number columns.
    Right,
}

/// A Markdown table whose raw text is aligned too (cells padded to the column's width).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MarkdownTable {
    columns: Vec<(String, Align)>,
    rows: Vec<Vec<String>>,
}

impl MarkdownTable {
    /// A table with these column headers and alignments and no rows.
    pub fn new<S: Into<String>>(columns: impl IntoIterator<Item = (S, Align)>) -> Self {
        Self {
            columns: columns
                .into_iter()
                .map(|(header, align)| (header.into(), align))
                .collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row; it must have one cell per column.
    pub fn push_row<S: Into<String>>(
        &mut self,
        cells: impl IntoIterator<Item = S>,
    ) -> Result<(), RowLengthError> {
        let cells: Vec<String> = cells.into_iter().map(Into::into).collect();
        if cells.len() != self.columns.len() {
            return Err(RowLengthError {
                row: self.rows.len(),
                found: cells.len(),
                expected: self.columns.len(),
            });
        }
        self.rows.push(cells);
        Ok(())
    }

    /// The table as GitHub-flavoured Markdown, one line per row, ending in a newline.
    /// A `|` inside a cell is escaped so it cannot split the cell.
    pub fn render(&self) -> String {
        let escape = |cell: &str| cell.replace('|', "\\|");
        let header: Vec<String> = self.columns.iter().map(|(h, _)| escape(h)).collect();
        let body: Vec<Vec<String>> = self
            .rows
            .iter()
            .map(|row| row.iter().map(|c| escape(c)).collect())
            .collect();
        // Widths in characters (not bytes: "±" and "ε" are one character); at least 3 for `---`.
        let widths: Vec<usize> = (0..self.columns.len())
            .map(|column| {
                std::iter::once(&header[column])
                    .chain(body.iter().map(|row| &row[column]))
                    .map(|cell| cell.chars().count())
                    .max()
                    .unwrap_or(0)
                    .max(3)
            })
            .collect();
        let line = |cells: &[String]| {
            let padded: Vec<String> = cells
                .iter()
                .zip(&widths)
                .zip(&self.columns)
                .map(|((cell, &width), (_, align))| match align {
                    Align::Left => format!("{cell:<width$}"),
                    Align::Right => format!("{cell:>width$}"),
                })
                .collect();
            format!("| {} |\n", padded.join(" | "))
        };
        let rule: Vec<String> = widths
            .iter()
            .zip(&self.columns)
            .map(|(&width, (_, align))| match align {
                Align::Left => format!(":{}", "-".repeat(width - 1)),
                Align::Right => format!("{}:", "-".repeat(width - 1)),
            })
            .collect();
        let mut text = line(&header);
        text.push_str(&line(&rule));
        for row in &body {
            text.push_str(&line(row));
        }
        text
    }
}

pub use eamadm_eval::rounding::{decimals_for, format_fixed};

/// A number to three significant digits (no decimals from 100 up).
pub fn number(value: f64) -> String {
    format_fixed(value, decimals_for(value, 3))
}

/// `estimate [low, high]`, rounded to two significant digits of the interval's width, and
/// finer where that would round a non-zero number to 0 (each keeps at least one significant
/// digit): a difference of 0.39 [0.31, 12.7] that decides a verdict must not read "0 [0, 13]".
pub fn interval(i: &Interval) -> String {
    let width = i.high - i.low;
    let by_width = if width > 1e-9 * i.estimate.abs().max(1.0) {
        // The nudge keeps a width like 73.1 − 73.0 = 0.0999… at the precision of 0.1.
        decimals_for(width * (1.0 + 1e-9), 2)
    } else {
        decimals_for(i.estimate, 3)
    };
    let decimals = [i.estimate, i.low, i.high]
        .into_iter()
        .filter(|&x| x != 0.0)
        .map(|x| decimals_for(x, 1))
        .fold(by_width, usize::max);
    format!(
        "{} [{}, {}]",
        format_fixed(i.estimate, decimals),
        format_fixed(i.low, decimals),
        format_fixed(i.high, decimals)
    )
}

/// The mean paired difference of a comparison with its exact sign-flip interval, as
/// [`interval`] prints an interval; "unbounded" for an interval too few pairs leave open.
pub fn paired_interval(p: &eamadm_eval::claims::PairedComparison) -> String {
    mean_interval(
        p.estimate,
        p.low.zip(p.high).map(|(low, high)| [low, high]),
        p.n,
    )
}

/// A mean paired difference `estimate` with its `interval` as [`interval`] prints one, or
/// "`estimate` [unbounded: `pairs` pairs]" when it has none (too few pairs to bound it).
pub fn mean_interval(estimate: f64, interval_ends: Option<[f64; 2]>, pairs: usize) -> String {
    match interval_ends {
        Some([low, high]) => interval(&Interval {
            estimate,
            low,
            high,
        }),
        None => format!(
            "{} [unbounded: {pairs} pairs]",
            format_fixed(estimate, decimals_for(estimate, 3)),
        ),
    }
}

/// A p-value: three decimals, or `< 0.001`.
pub fn p_value(p: f64) -> String {
    if p < 0.001 {
        "< 0.001".to_owned()
    } else {
        format_fixed(p, 3)
    }
}

/// A share as a percentage with its Wilson interval: `62% [55, 69]`.
pub fn share(s: &Share) -> String {
    format!(
        "{}/{} = {}% [{}, {}]",
        s.successes,
        s.trials,
        format_fixed(s.wilson.estimate * 100.0, 0),
        format_fixed(s.wilson.low * 100.0, 0),
        format_fixed(s.wilson.high * 100.0, 0)
    )
}

/// `a`, `a and b`, `a, b and c`.
pub fn list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// How a method's role reads in a table.
pub fn role_text(role: Role) -> &'static str {
    match role {
        Role::Paper => "paper",
        Role::Ablation => "ablation",
        Role::Control => "control, not in the paper",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_never_prints_negative_zero() {
        assert_eq!(format_fixed(-0.0001, 2), "0.00");
        assert_eq!(format_fixed(-0.0, 0), "0");
        assert_eq!(format_fixed(-1.5, 1), "-1.5");
    }

    #[test]
    fn table_columns_line_up() {
        let mut table = MarkdownTable::new([
            ("task", Align::Left),
            ("method", Align::Left),
            ("final steps", Align::Right),
            ("ratio to BFS", Align::Right),
        ]);
        table
            .push_row(["Task I", "EA-MADM", "80.1 ± 3.5", "1.38"])
            .unwrap();
        table
            .push_row(["Task I", "ε-greedy", "155 ± 13", "2.67"])
            .unwrap();
        table
            .push_row(["Task II", "a|b", "-71.26 ± 0.83", "—"])
            .unwrap();
        insta::assert_snapshot!(table.render());
    }

    #[test]
    fn rows_of_the_wrong_length_are_refused() {
        let mut table = MarkdownTable::new([("a", Align::Left), ("b", Align::Right)]);
        table.push_row(["1", "2"]).unwrap();
        assert_eq!(
            table.push_row(["only one"]),
            Err(RowLengthError {
                row: 1,
                found: 1,
                expected: 2
            })
        );
        assert_eq!(
            table.render(),
            "| a   |   b |\n| :-- | --: |\n| 1   |   2 |\n"
        );
    }

    #[test]
    fn numbers_are_rounded_to_their_interval() {
        let i = Interval {
            estimate: 80.1234,
            low: 75.5,
            high: 90.25,
        };
        assert_eq!(interval(&i), "80 [76, 90]");
        let flat = Interval {
            estimate: 2000.0,
            low: 2000.0,
            high: 2000.0,
        };
        assert_eq!(interval(&flat), "2000 [2000, 2000]");
        let tenth = Interval {
            estimate: 73.0,
            low: 73.0,
            high: 73.1,
        };
        assert_eq!(interval(&tenth), "73.00 [73.00, 73.10]");
        // A small estimate in a wide interval keeps a significant digit.
        let small = Interval {
            estimate: 0.385,
            low: 0.307,
            high: 12.68,
        };
        assert_eq!(interval(&small), "0.4 [0.3, 12.7]");
        assert_eq!(p_value(0.0004), "< 0.001");
        assert_eq!(p_value(0.0312), "0.031");
    }
}
