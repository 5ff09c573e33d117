//! Text for `REPORT.md`: Markdown tables whose columns line up in the raw file, and
//! "mean ± 95% CI" numbers rounded to what the interval can support.

use thiserror::Error;

use eamadm::summary::SeedSummary;

/// A table row of the wrong length.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("table row {row} has {found} cells, the header has {expected}")]
pub(crate) struct RowLengthError {
    /// Index of the offending row (0-based, header excluded).
    pub(crate) row: usize,
    /// Number of cells in the row.
    pub(crate) found: usize,
    /// Number of columns in the header.
    pub(crate) expected: usize,
}

/// How a column's cells sit in their column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Align {
    /// Text columns.
    Left,
    /// Number columns.
    Right,
}

/// A Markdown table whose raw text is aligned too (cells padded to the column's width).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct MarkdownTable {
    columns: Vec<(String, Align)>,
    rows: Vec<Vec<String>>,
}

impl MarkdownTable {
    /// A table with these column headers and alignments and no rows.
    pub(crate) fn new<S: Into<String>>(columns: impl IntoIterator<Item = (S, Align)>) -> Self {
        Self {
            columns: columns
                .into_iter()
                .map(|(header, align)| (header.into(), align))
                .collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row; it must have one cell per column.
    pub(crate) fn push_row<S: Into<String>>(
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
    pub(crate) fn render(&self) -> String {
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

/// Most decimals any number in the report gets.
const MAX_DECIMALS: i32 = 6;

/// Formats `value` with `decimals` decimals, never printing a negative zero.
pub(crate) fn format_fixed(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_owned(),
        _ => text,
    }
}

/// Decimals that show `value` to `significant` significant digits (none for large values).
fn decimals_for(value: f64, significant: i32) -> usize {
    if value == 0.0 || !value.is_finite() {
        return 0;
    }
    let magnitude = value.abs().log10().floor() as i32;
    (significant - 1 - magnitude).clamp(0, MAX_DECIMALS) as usize
}

/// "mean ± half-width" of a 95% confidence interval, rounded to the interval's precision: the
/// half-width keeps two significant digits and the mean the same number of decimals
/// (`80.1234 ± 3.456` → `"80.1 ± 3.5"`, `155.3 ± 12.7` → `"155 ± 13"`).
///
/// Without an interval (a single seed) the mean keeps three significant digits and the text
/// says why: `"80.1 (1 seed)"`. A zero-width interval (all seeds equal) prints `"80.1 ± 0"`.
pub(crate) fn format_mean_ci(summary: &SeedSummary) -> String {
    // A half-width that is rounding noise of equal values (e.g. every seed hit the step cap)
    // prints as an exact zero.
    let noise = 1e-9 * summary.mean.abs().max(1.0);
    match summary.ci95_half_width {
        Some(half_width) if half_width > noise => {
            let decimals = decimals_for(half_width, 2);
            format!(
                "{} ± {}",
                format_fixed(summary.mean, decimals),
                format_fixed(half_width, decimals)
            )
        }
        Some(_) => format!(
            "{} ± 0",
            format_fixed(summary.mean, decimals_for(summary.mean, 3))
        ),
        None => format!(
            "{} ({} seed{})",
            format_fixed(summary.mean, decimals_for(summary.mean, 3)),
            summary.n,
            if summary.n == 1 { "" } else { "s" }
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use eamadm::summary::summarise_seeds;

    fn summary(mean: f64, half_width: Option<f64>) -> SeedSummary {
        SeedSummary {
            n: if half_width.is_some() { 10 } else { 1 },
            mean,
            sd: half_width,
            ci95_half_width: half_width,
        }
    }

    #[test]
    fn mean_ci_precision_follows_the_interval() {
        let cases = [
            (80.1234, Some(3.456), "80.1 ± 3.5"),
            (155.3, Some(12.7), "155 ± 13"),
            (-71.26, Some(0.834), "-71.26 ± 0.83"),
            (0.012_345, Some(0.001_23), "0.0123 ± 0.0012"),
            (15_321.0, Some(250.0), "15321 ± 250"),
            (-0.004, Some(0.3), "0.00 ± 0.30"),
            (80.1234, Some(0.0), "80.1 ± 0"),
            (6.849_315_068_493_151, Some(1e-15), "6.85 ± 0"),
            (80.1234, None, "80.1 (1 seed)"),
            (0.0, None, "0 (1 seed)"),
        ];
        for (mean, half_width, expected) in cases {
            assert_eq!(format_mean_ci(&summary(mean, half_width)), expected);
        }
    }

    #[test]
    fn mean_ci_of_a_real_summary() {
        let s = summarise_seeds(&[78.0, 82.0, 85.0, 79.0, 81.0]).unwrap();
        // mean 81, sd √7.5 ≈ 2.7386, half-width 2.776445 · 2.7386 / √5 ≈ 3.4004.
        assert_eq!(format_mean_ci(&s), "81.0 ± 3.4");
    }

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
}
