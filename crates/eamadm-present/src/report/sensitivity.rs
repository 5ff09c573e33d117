//! The report's section "Sensitivity to the readings of the paper" (issue 20 item 4): each
//! verdict judged again under the other readings of the paper ([`eamadm_eval::sensitivity`]), laid
//! out; the readings' descriptions come in as data ([`ReadingFacts`](super::ReadingFacts)).

use std::fmt::Write as _;

use super::ReportContext;
use super::format::{Align, MarkdownTable, decimals_for, format_fixed};
use eamadm_eval::paper_claims::method_title;
use eamadm_eval::sensitivity::{self, SensitivityRow};

/// A number with `significant` digits (none after the point from 10^significant up).
fn number(value: f64, significant: i32) -> String {
    format_fixed(value, decimals_for(value, significant))
}

/// The deciding number of a row under its reading, in words.
fn deciding(row: &SensitivityRow) -> String {
    let (Some(estimate), Some(p)) = (row.estimate, row.p_holm) else {
        return "nothing decides (untestable)".to_owned();
    };
    let p = if p < 0.001 {
        "< 0.001".to_owned()
    } else {
        format_fixed(p, 3)
    };
    let versus = method_title(&row.versus);
    let interval = match (row.ci_low, row.ci_high) {
        (Some(low), Some(high)) => {
            // Two significant digits of the interval's width, and at least one of each
            // non-zero end (as the verdict table rounds).
            let by_width = decimals_for(high - low, 2);
            let decimals = [estimate, low, high]
                .into_iter()
                .filter(|x| *x != 0.0)
                .map(|x| decimals_for(x, 1))
                .fold(by_width, usize::max);
            format!(
                "{} [{}, {}]",
                format_fixed(estimate, decimals),
                format_fixed(low, decimals),
                format_fixed(high, decimals)
            )
        }
        _ => number(estimate, 2),
    };
    match row.statistic {
        "reached_share_difference" => {
            format!("vs {versus}: Δ share of seeds reaching = {interval}, sign test Holm p {p}")
        }
        "stable_reaching_share_difference" => format!(
            "vs {versus}: Δ share of stable-reaching seeds (every greedy evaluation of the \
             second half reaches) = {interval}, sign test Holm p {p}"
        ),
        _ => format!(
            "vs {versus}: paired Δ mean `{}` = {interval}, Holm p {p}",
            row.metric
        ),
    }
}

/// The report's section on the readings (nothing when no reading ran).
pub(crate) fn write_sensitivity(
    text: &mut String,
    context: &ReportContext,
    rows: &[SensitivityRow],
) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "### Sensitivity to the readings of the paper\n\n\
         Each reading below takes one thing the paper leaves open, or says two ways, the other \
         way. Only the methods it changes run again, with the same seeds (so the same random \
         streams); every other run is the base experiment's own, and the same rule judges the \
         claim again. A verdict **holds** when it is the same under the reading and **flips** \
         otherwise. Every row is in [sensitivity.csv](sensitivity.csv).\n"
    );
    for reading in &context.readings {
        if !rows.iter().any(|row| row.reading == reading.name) {
            continue;
        }
        let reruns: Vec<String> = reading
            .methods
            .iter()
            .map(|label| method_title(label))
            .collect();
        let _ = writeln!(
            text,
            "- `{}`: {}; reruns {}. {}",
            reading.name,
            reading.change,
            reruns.join(", "),
            reading.source
        );
    }
    // Per task the readings under which every verdict holds, in one line; a table of the
    // rows that flip.
    let survival = sensitivity::survival(rows);
    let mut tasks: Vec<&str> = Vec::new();
    for row in rows {
        if !tasks.contains(&row.task.as_str()) {
            tasks.push(&row.task);
        }
    }
    let holds: Vec<String> = tasks
        .iter()
        .filter_map(|task| {
            let mut readings: Vec<&str> = Vec::new();
            for row in rows.iter().filter(|r| r.task == *task) {
                if !readings.contains(&row.reading.as_str()) {
                    readings.push(&row.reading);
                }
            }
            let holding: Vec<String> = readings
                .into_iter()
                .filter(|reading| {
                    rows.iter()
                        .filter(|r| r.task == *task && r.reading == *reading)
                        .all(|r| r.change == sensitivity::Change::Holds)
                })
                .map(|reading| format!("`{reading}`"))
                .collect();
            (!holding.is_empty()).then(|| {
                format!(
                    "on {} under {}",
                    context.task_title(task),
                    super::format::list(&holding)
                )
            })
        })
        .collect();
    let flipping: Vec<String> = survival
        .iter()
        .filter(|e| !e.survives)
        .map(|e| {
            let by: Vec<String> = e.flipped_by.iter().map(|r| format!("`{r}`")).collect();
            format!(
                "{} on {} under {}",
                e.claim,
                context.task_title(&e.task),
                by.join(", ")
            )
        })
        .collect();
    if !holds.is_empty() {
        let _ = writeln!(text, "\nEvery verdict holds {}.", holds.join("; "));
    }
    if flipping.is_empty() {
        let _ = writeln!(text, "\nNo reading flips a verdict.\n");
        return;
    }
    let _ = writeln!(
        text,
        "\nA verdict flips: {}. The rows that flip:\n",
        flipping.join("; ")
    );
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("task", Align::Left),
        ("reading", Align::Left),
        ("verdict → under the reading", Align::Left),
        ("holds or flips", Align::Left),
        ("the number that decides it under the reading", Align::Left),
    ]);
    for row in rows
        .iter()
        .filter(|r| r.change == sensitivity::Change::Flips)
    {
        let _ = table.push_row([
            row.claim.to_owned(),
            context.task_title(&row.task),
            format!("`{}`", row.reading),
            format!("{} → {}", row.base_verdict.name(), row.verdict.name()),
            if row.change == sensitivity::Change::Flips {
                "**flips**".to_owned()
            } else {
                "holds".to_owned()
            },
            deciding(row),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
}
