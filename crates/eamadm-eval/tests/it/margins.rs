//! The margins the tests judge with: the paper's mazes' (2 steps, 2 reward), as
//! `eamadm::Task::equivalence_margins` derives them, written out here because this crate knows
//! no reward scheme.

use eamadm_eval::claims::{Margin, Margins};

/// The mazes' margins on `tasks`: 2 steps on the step metrics, 2 reward on the return metrics.
pub(crate) fn maze_margins(tasks: &[&str]) -> Margins {
    let mut margins = Margins::new();
    let table: Vec<Margin> = [
        "final_steps",
        "final_return",
        "fluctuation_greedy_steps",
        "fluctuation_greedy_return",
        "fluctuation_steps",
        "fluctuation_return",
    ]
    .into_iter()
    .map(|column| Margin {
        column: column.to_owned(),
        value: 2.0,
        reason: "the shortest detour".to_owned(),
    })
    .collect();
    for task in tasks {
        margins.insert(task, &table).unwrap();
    }
    margins
}
