//! Each task's equivalence margins (regions of practical equivalence, issue 20): for every
//! metric a claim tests on the task, the difference that is no difference in practice,
//! derived from the task's own reward scheme and control period (docs/paper-notes.md
//! §10.1a). [`Task::equivalence_margins`] computes them; the main job stores them in the
//! experiment's facts and judges with them ([`ClaimOptions::margins`](crate::claims::ClaimOptions::margins)).
//!
//! - **Mazes.** Step metrics (`final_steps`, `fluctuation_steps`,
//!   `fluctuation_greedy_steps`): [`DETOUR_STEPS`] = 2 steps, the shortest detour on a
//!   4-connected grid (one step off a shortest route and one back). Return metrics
//!   (`final_return`, `fluctuation_return`, `fluctuation_greedy_return`): what that detour
//!   changes the return by, `|closer + farther|` (one farther step and one more closer step);
//!   where it costs nothing (`closer + farther = 0`, Task I: a bump-free reaching episode
//!   returns the same at any length) the smallest difference one step's reward makes,
//!   `|closer − farther|`.
//! - **Robot** (C4, over reaching episodes; `T` the control period, `n*` the planner's
//!   route in steps): `reach_time` ± `2T` (the same 2-step detour in time);
//!   `reach_average_reward` ± what that detour takes off the route's average reward,
//!   `R*/(n*·T) − (R* + closer + farther)/((n*+2)·T)` with `R* = (n*−1)·closer + goal bonus`
//!   (the task reward `Progress`; none under `SubtaskSum`); `retention_decay` ± `2T` spread
//!   over the span of the paper's 100 reaching episodes, `2T / 99` per episode.
//!
//! ```
//! let task = eamadm::paper::task2().task.check()?;
//! let margins = task.equivalence_margins();
//! let of = |column: &str| margins.iter().find(|m| m.column == column).map(|m| m.value);
//! assert_eq!(of("final_steps"), Some(2.0)); // the shortest detour
//! assert_eq!(of("final_return"), Some(2.0)); // Task II pays −1 per step, so it costs 2
//! assert_eq!(of("reach_time"), None); // a robot metric
//! # Ok::<(), eamadm::ConfigError>(())
//! ```

use crate::claims::Margin;
use crate::rounding::{decimals_for, format_fixed};
use crate::scores::REACHING_EPISODES;
use crate::task::{Task, TaskKind};
use crate::wmr_model::TaskReward;

/// The shortest detour on a 4-connected grid, in steps: one step off a shortest route and one
/// back. Every step margin is this many steps, and the robot's margins are this many control
/// periods.
pub const DETOUR_STEPS: f64 = 2.0;

impl Task {
    /// The equivalence margin of each metric a claim tests on this task, with its reason
    /// (see the [module docs](crate::margins)). Metrics without one are never judged
    /// equivalent.
    #[must_use]
    pub fn equivalence_margins(&self) -> Vec<Margin> {
        match self.kind() {
            TaskKind::Maze(env) => maze_margins(env.spec().reward),
            TaskKind::Robot(env) => robot_margins(
                env.scenario().control_period,
                env.scenario().reward.goal_bonus,
                env.scenario().reward.task,
                self.optimum_steps(),
            ),
        }
    }
}

fn margin(column: &str, value: f64, reason: String) -> Margin {
    Margin {
        column: column.to_owned(),
        value,
        reason,
    }
}

/// A reward with its sign, as the reasons print it: `+1`, `−100`.
fn signed(value: f64) -> String {
    if value < 0.0 {
        format!("−{}", -value)
    } else {
        format!("+{value}")
    }
}

pub(crate) fn maze_margins(reward: crate::mazes::RewardScheme) -> Vec<Margin> {
    let steps_reason = || {
        "the shortest detour on a 4-connected grid (one step off a shortest route and one back)"
            .to_owned()
    };
    let detour = (reward.closer + reward.farther).abs();
    let (value, why) = if detour > 0.0 {
        (
            detour,
            format!(
                "what the shortest detour costs under this task's rewards (one farther step \
                 at {} and one more closer step at {})",
                signed(reward.farther),
                signed(reward.closer)
            ),
        )
    } else {
        (
            (reward.closer - reward.farther).abs(),
            format!(
                "a detour costs nothing here (its farther step at {} is undone by one more \
                 closer step at {}, so a reaching episode without a bump returns the same at \
                 any length), so the margin is the smallest difference one step's reward makes \
                 ({} instead of {}), far below one bump ({})",
                signed(reward.farther),
                signed(reward.closer),
                signed(reward.farther),
                signed(reward.closer),
                signed(reward.bump)
            ),
        )
    };
    // An SD shares its level metric's margin and reason (same unit, same detour).
    let mut margins: Vec<Margin> = [
        "final_steps",
        "fluctuation_greedy_steps",
        "fluctuation_steps",
    ]
    .into_iter()
    .map(|column| margin(column, DETOUR_STEPS, steps_reason()))
    .collect();
    // A scheme whose ordinary steps pay nothing (closer = farther = 0) has no return
    // difference to give: a margin of 0 could never be met, so it gets none.
    if value.is_finite() && value > 0.0 {
        margins.extend(
            [
                "final_return",
                "fluctuation_greedy_return",
                "fluctuation_return",
            ]
            .into_iter()
            .map(|column| margin(column, value, why.clone())),
        );
    }
    margins
}

/// A number as the reasons print it: four significant digits, no trailing zeros.
fn number(value: f64) -> String {
    let text = format_fixed(value, decimals_for(value, 4));
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

fn robot_margins(
    period: f64,
    goal_bonus: f64,
    task_reward: TaskReward,
    optimum_steps: Option<u64>,
) -> Vec<Margin> {
    let detour_time = DETOUR_STEPS * period;
    let span = (REACHING_EPISODES - 1) as f64;
    let mut margins = vec![
        margin(
            "reach_time",
            detour_time,
            format!(
                "two control periods ({DETOUR_STEPS} × {} s): the 2-step detour of the grids, in \
                 time",
                number(period)
            ),
        ),
        margin(
            "retention_decay",
            detour_time / span,
            format!(
                "two control periods of retention time ({} s) over the span of the paper's \
                 {REACHING_EPISODES} reaching episodes ({} s / {span})",
                number(detour_time),
                number(detour_time)
            ),
        ),
    ];
    if let (
        TaskReward::Progress {
            closer, farther, ..
        },
        Some(n),
    ) = (task_reward, optimum_steps)
    {
        let n = n as f64;
        let route_return = (n - 1.0) * closer + goal_bonus;
        let route = route_return / (n * period);
        let detoured = (route_return + closer + farther) / ((n + DETOUR_STEPS) * period);
        let value = route - detoured;
        if value.is_finite() && value > 0.0 {
            margins.insert(
                0,
                margin(
                    "reach_average_reward",
                    value,
                    format!(
                        "what a 2-step detour takes off the average reward of the planner's \
                         {n}-step route: return {} over {} s ({}/s) against {} over {} s \
                         ({}/s)",
                        number(route_return),
                        number(n * period),
                        number(route),
                        number(route_return + closer + farther),
                        number((n + DETOUR_STEPS) * period),
                        number(detoured)
                    ),
                ),
            );
        }
    }
    margins
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::TaskConfig;
    use crate::paper::{self, PaperTask};

    fn margins_of(task: PaperTask) -> Vec<Margin> {
        task.config().task.check().unwrap().equivalence_margins()
    }

    fn value(margins: &[Margin], column: &str) -> Option<f64> {
        margins.iter().find(|m| m.column == column).map(|m| m.value)
    }

    #[test]
    fn the_mazes_margins_are_the_shortest_detour_in_steps_and_in_return() {
        for task in [PaperTask::Task1, PaperTask::Task2] {
            let margins = margins_of(task);
            for column in [
                "final_steps",
                "fluctuation_greedy_steps",
                "fluctuation_steps",
            ] {
                assert_eq!(value(&margins, column), Some(2.0), "{task:?} {column}");
            }
            for column in [
                "final_return",
                "fluctuation_greedy_return",
                "fluctuation_return",
            ] {
                assert_eq!(value(&margins, column), Some(2.0), "{task:?} {column}");
            }
            assert_eq!(value(&margins, "reach_time"), None);
        }
        // Task II pays −1 per step, so the detour costs 2; Task I's detour costs nothing and
        // the reason says so.
        let reason = |task, column| {
            margins_of(task)
                .into_iter()
                .find(|m| m.column == column)
                .unwrap()
                .reason
        };
        assert!(
            reason(PaperTask::Task2, "final_return").contains("what the shortest detour costs")
        );
        assert!(reason(PaperTask::Task1, "final_return").contains("a detour costs nothing"));
        // A scheme whose steps pay nothing has no return margin (0 could never be met).
        let flat = maze_margins(crate::mazes::RewardScheme {
            closer: 0.0,
            farther: 0.0,
            bump: -1.0,
            target: 1.0,
        });
        assert_eq!(value(&flat, "final_return"), None);
        assert_eq!(value(&flat, "final_steps"), Some(2.0));
    }

    #[test]
    fn the_robots_margins_come_from_its_control_period_and_route() {
        let margins = margins_of(PaperTask::Robot);
        let TaskConfig::Robot {
            control_period: Some(period),
            ..
        } = paper::robot().task
        else {
            panic!("the robot preset sets its control period");
        };
        assert_eq!(value(&margins, "reach_time"), Some(2.0 * period));
        assert_eq!(
            value(&margins, "retention_decay"),
            Some(2.0 * period / 99.0)
        );
        // The planner's 17-step route returns 16 + 100 over 6.8 s; the same with a 2-step
        // detour (one step not closer, one more closer) returns 116 over 7.6 s.
        let route = paper::robot()
            .task
            .check()
            .unwrap()
            .optimum_steps()
            .unwrap();
        assert_eq!(route, 17);
        let expected = 116.0 / (17.0 * period) - 116.0 / (19.0 * period);
        let average = value(&margins, "reach_average_reward").unwrap();
        assert!((average - expected).abs() < 1e-12, "{average}");
        assert!((average - 1.7957).abs() < 1e-4, "{average}");
        // Under the sub-task sum the average reward has no derivable margin.
        let none = robot_margins(period, 100.0, TaskReward::SubtaskSum, Some(17));
        assert_eq!(value(&none, "reach_average_reward"), None);
        assert_eq!(value(&none, "reach_time"), Some(2.0 * period));
    }

    #[test]
    fn every_metric_a_claim_tests_has_a_margin_on_its_tasks_and_the_column_doc_states_it() {
        let doc = crate::claims::CLAIM_COLUMNS
            .iter()
            .find(|c| c.name == "margin")
            .unwrap()
            .description;
        for claim in &paper::CLAIMS {
            for &name in claim.tasks {
                let task = PaperTask::from_name(name).unwrap();
                let margins = margins_of(task);
                for metric in claim.metrics.iter().chain(claim.secondary) {
                    let margin = margins
                        .iter()
                        .find(|m| m.column == metric.column)
                        .unwrap_or_else(|| panic!("{} on {name} has no margin", metric.column));
                    assert!(margin.value > 0.0 && !margin.reason.is_empty());
                    // The column's documentation states the value as the report's margins
                    // list prints it (4 significant digits, no trailing zeros).
                    let shown = number(margin.value);
                    assert!(
                        doc.contains(&format!("±{shown} ")),
                        "the `margin` column doc does not state {} of `{}` on {name}: {doc}",
                        margin.value,
                        metric.column
                    );
                }
            }
        }
    }
}
