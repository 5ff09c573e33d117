//! Text for `REPORT.md`: Markdown tables whose columns line up in the raw file, and numbers
//! rounded to the digits they can support.

use thiserror::Error;

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
pub(crate) fn decimals_for(value: f64, significant: i32) -> usize {
    if value == 0.0 || !value.is_finite() {
        return 0;
    }
    let magnitude = value.abs().log10().floor() as i32;
    (significant - 1 - magnitude).clamp(0, MAX_DECIMALS) as usize
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
}
