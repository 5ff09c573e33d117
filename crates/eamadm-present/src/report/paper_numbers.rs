//! The paper's numbers beside ours, for the tasks the paper reports numbers on.

use std::fmt::Write as _;

use super::format::{Align, MarkdownTable, format_fixed};
use super::task::estimate_cell;
use super::{ReportContext, Verdicts};
use eamadm_eval::claims;
use eamadm_eval::paper_claims::ReportedNumbers;

pub(crate) fn write_paper_numbers(text: &mut String, context: &ReportContext, verdicts: &Verdicts) {
    let rows: Vec<(ReportedNumbers, &str)> = claims::tasks(&verdicts.scores)
        .into_iter()
        .filter_map(|task| {
            context
                .paper_task(task)
                .and_then(|t| t.reported)
                .map(|reported| (reported, task))
        })
        .collect();
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(text, "## The paper's numbers beside ours\n");
    let mut table = MarkdownTable::new([
        ("task", Align::Left),
        ("paper: EA-MADM steps", Align::Right),
        ("paper: EA-MADM return", Align::Right),
        ("ours: EA-MADM final steps", Align::Right),
        ("ours: EA-MADM final return", Align::Right),
        ("our optimum", Align::Right),
    ]);
    for (reported, task) in rows {
        let ea = verdicts.paper_ea_madm(task).unwrap_or("ea-madm");
        let optimum = verdicts
            .scores
            .iter()
            .find(|s| s.task == task)
            .and_then(|s| s.optimum_steps);
        let _ = table.push_row([
            context.task_title(task),
            format_fixed(reported.steps, 0),
            format_fixed(reported.task_return, 0),
            estimate_cell(verdicts, task, ea, "final_steps"),
            estimate_cell(verdicts, task, ea, "final_return"),
            optimum.map_or_else(|| "—".to_owned(), |o| o.to_string()),
        ]);
    }
    text.push_str(&table.render());
    let _ = writeln!(
        text,
        "\nThe paper does not publish its mazes; ours are generated with the paper's sizes and \
         obstacle counts (crate `mazes`), so step counts and returns are not directly \
         comparable. The paper shows single runs; we report {} seeds. The robot runs in a 2D \
         model (crate `wmr-model`), not in Webots, and the paper gives no robot numbers.\n",
        context
            .experiments
            .first()
            .map_or(context.preset_seeds, |p| p.seeds)
    );
}
