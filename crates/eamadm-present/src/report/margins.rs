//! The equivalence margins the verdicts were judged with: one line per task × metric, with
//! the reason its task gives (`eamadm::Task::equivalence_margins`).

use std::fmt::Write as _;

use super::format::{decimals_for, format_fixed};
use super::{ReportContext, Verdicts};
use eamadm_eval::claims;
use eamadm_eval::paper_claims::CLAIMS;
use eamadm_eval::scores;

/// The margins list under the rule: per task of the run a claim is judged on (in run
/// order), one line per margin and reason with the metrics sharing it; or a sentence that
/// there is none.
pub(crate) fn write_margins(text: &mut String, context: &ReportContext, verdicts: &Verdicts) {
    let judged = |task: &str, column: &str| {
        CLAIMS.iter().any(|claim| {
            claim.tasks.contains(&task)
                && claim
                    .metrics
                    .iter()
                    .chain(claim.secondary)
                    .any(|m| m.column == column)
        })
    };
    let mut lines: Vec<String> = Vec::new();
    for task in claims::tasks(&verdicts.scores) {
        // (value, reason) → the metrics sharing it, in the task's order.
        let mut groups: Vec<(f64, &str, Vec<&str>)> = Vec::new();
        for (_, margin) in verdicts
            .options
            .margins
            .iter()
            .filter(|(t, m)| *t == task && judged(task, &m.column))
        {
            match groups
                .iter_mut()
                .find(|(v, r, _)| *v == margin.value && *r == margin.reason)
            {
                Some((_, _, columns)) => columns.push(&margin.column),
                None => groups.push((margin.value, &margin.reason, vec![&margin.column])),
            }
        }
        for (value, reason, columns) in groups {
            let unit = scores::COLUMNS
                .iter()
                .find(|c| c.name == columns[0])
                .and_then(|c| c.unit)
                .map_or_else(String::new, |u| format!(" {u}"));
            let columns: Vec<String> = columns.iter().map(|c| format!("`{c}`")).collect();
            lines.push(format!(
                "- {}, {}: ±{}{unit}, {reason}.",
                context.task_title(task),
                columns.join(", "),
                short_number(value)
            ));
        }
    }
    if lines.is_empty() {
        let _ = writeln!(
            text,
            "### The margins\n\nNo task of this run defines an equivalence margin, so no \
             comparison can be judged equivalent and \"favours\" needs no effect size.\n"
        );
        return;
    }
    let _ = writeln!(
        text,
        "### The margins\n\nThe regions of practical equivalence (a difference within ± the \
         margin is no difference in practice), derived from each task's rewards and control \
         period before any run was judged (docs/paper-notes.md §10.1a):\n"
    );
    for line in lines {
        let _ = writeln!(text, "{line}");
    }
    text.push('\n');
}

/// A margin as the list prints it: four significant digits without trailing zeros (`2`,
/// `0.8`, `1.796`, `0.008081`), so that it reads as the reason states it.
pub(crate) fn short_number(value: f64) -> String {
    let text = format_fixed(value, decimals_for(value, 4));
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::short_number;

    #[test]
    fn margins_print_without_trailing_zeros() {
        assert_eq!(short_number(2.0), "2");
        assert_eq!(short_number(0.8), "0.8");
        assert_eq!(short_number(1.795_665), "1.796");
        assert_eq!(short_number(0.8 / 99.0), "0.008081");
        assert_eq!(short_number(100.0), "100");
    }
}
