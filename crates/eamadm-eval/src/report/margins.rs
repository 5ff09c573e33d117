//! The equivalence margins the verdicts were judged with: one line per task × metric, with
//! the reason its task gives (`eamadm::Task::equivalence_margins`).

use std::fmt::Write as _;

use super::format::{decimals_for, format_fixed};
use super::{ReportContext, Verdicts};
use crate::claims;
use crate::scores;

/// The margins list under the rule: per task of the run (in run order) each metric's margin,
/// its unit and why; or a sentence that there is none.
pub(crate) fn write_margins(text: &mut String, context: &ReportContext, verdicts: &Verdicts) {
    let tasks = claims::tasks(&verdicts.scores);
    let lines: Vec<String> = verdicts
        .options
        .margins
        .iter()
        .filter(|(task, _)| tasks.contains(task))
        .map(|(task, margin)| {
            let unit = scores::COLUMNS
                .iter()
                .find(|c| c.name == margin.column)
                .and_then(|c| c.unit)
                .map_or_else(String::new, |u| format!(" {u}"));
            format!(
                "- {}, `{}`: ±{}{unit}: {}.",
                context.task_title(task),
                margin.column,
                short_number(margin.value),
                margin.reason
            )
        })
        .collect();
    if lines.is_empty() {
        let _ = writeln!(
            text,
            "**The margins.** No task of this run defines an equivalence margin, so no \
             comparison can be judged equivalent and \"favours\" needs no effect size.\n"
        );
        return;
    }
    let _ = writeln!(
        text,
        "**The margins** (regions of practical equivalence: a difference within ± the margin is \
         no difference in practice), derived from each task's rewards and control period \
         before any run was judged (docs/paper-notes.md §10.1a):\n"
    );
    for line in lines {
        let _ = writeln!(text, "{line}");
    }
    text.push('\n');
}

/// A margin as the list prints it: four significant digits without trailing zeros (`2`,
/// `0.8`, `1.796`, `0.008081`), so that it reads as the reason states it.
fn short_number(value: f64) -> String {
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
