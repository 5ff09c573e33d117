//! `REPORT.md`: per experiment and method the final-window numbers (mean ± 95% CI over seeds,
//! from [`eamadm::summarise`]), the ablation table, and the paper's reported numbers beside ours
//! with a statement of where they differ — phrased from the numbers, never hard-coded.
//!
//! The text is a pure function of the records and configs (no paths, dates or timings), so an
//! interrupted and resumed run writes the same bytes as an uninterrupted one.

use std::fmt::Write as _;

use eamadm::mazes::Preset;
use eamadm::summary::{MethodSummary, SeedSummary, StatsError};
use eamadm::{DEFAULT_FINAL_WINDOW, RunRecord, summarise};

use crate::experiments::{MAIN_METHODS, PlannedExperiment, method_title};
use crate::report::{Align, MarkdownTable, format_fixed, format_mean_ci};

/// What the paper reports for EA-MADM on one maze (Sec. VI.A, read off Fig. 7/8 and 10/11).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PaperNumbers {
    /// Steps per episode at the end of training.
    pub(crate) steps: f64,
    /// Return per episode at the end of training.
    pub(crate) reward: f64,
}

/// The paper's numbers for a maze preset.
pub(crate) fn paper_numbers(preset: Preset) -> PaperNumbers {
    match preset {
        Preset::Task1 => PaperNumbers {
            steps: 80.0,
            reward: 155.0,
        },
        Preset::Task2 => PaperNumbers {
            steps: 86.0,
            reward: -71.0,
        },
    }
}

/// One experiment's records and summaries.
pub(crate) struct ExperimentResults<'a> {
    /// The experiment.
    pub(crate) planned: &'a PlannedExperiment,
    /// Its runs.
    pub(crate) records: &'a [RunRecord],
}

fn ci(summary: &SeedSummary) -> String {
    format_mean_ci(summary)
}

fn percent(summary: &SeedSummary) -> String {
    format!("{}%", format_fixed(summary.mean * 100.0, 0))
}

/// Whether the 95% intervals of `a` and `b` overlap (no interval: compare the means).
fn overlap(a: &SeedSummary, b: &SeedSummary) -> bool {
    let half = |s: &SeedSummary| s.ci95_half_width.unwrap_or(0.0);
    (a.mean - b.mean).abs() <= half(a) + half(b)
}

/// Renders `REPORT.md`.
pub(crate) fn render_report(
    experiments: &[ExperimentResults<'_>],
    quick: bool,
) -> Result<String, StatsError> {
    let mut text = String::from("# EA-MADM reproduction report\n\n");
    let _ = writeln!(
        text,
        "Made by `cargo xtask reproduce-paper`{}. Do not edit: rerun the command.\n",
        if quick {
            " --quick (a smoke run: few seeds and episodes; these numbers mean little)"
        } else {
            ""
        }
    );
    let _ = writeln!(
        text,
        "\"Final\" numbers are, per seed, the mean over the last {DEFAULT_FINAL_WINDOW} training \
         episodes, then the mean ± the half-width of the 95% confidence interval over seeds \
         (Student t). Success is the share of final-window episodes that reached the target; \
         \"greedy reached\" the share of seeds whose greedy evaluation episode after training \
         did. Environment steps count every step of the run, sub-task pre-training included.\n"
    );
    let mut summaries = Vec::new();
    for experiment in experiments {
        let summary = summarise(experiment.records, DEFAULT_FINAL_WINDOW)?;
        write_experiment(&mut text, experiment, &summary);
        summaries.push(summary);
    }
    write_paper_comparison(&mut text, experiments, &summaries);
    Ok(text)
}

fn write_experiment(
    text: &mut String,
    experiment: &ExperimentResults<'_>,
    summary: &[MethodSummary],
) {
    let planned = experiment.planned;
    let config = planned.config();
    let _ = writeln!(text, "## {} (`{}`)\n", planned.title, planned.name);
    let optimum = summary.first().and_then(|s| s.optimum_steps);
    let is_robot = planned.experiment.task().scenario().is_some();
    let _ = writeln!(
        text,
        "{} episodes, {} seeds per method, step cap {}{}.\n",
        config.episodes,
        config.seeds,
        config
            .task
            .step_cap()
            .map_or_else(|| "of the task".to_owned(), |cap| cap.to_string()),
        optimum.map_or_else(String::new, |o| format!(
            ", {} optimum {o} steps",
            if is_robot { "planner" } else { "BFS" }
        )),
    );
    let mut table = MarkdownTable::new([
        ("method", Align::Left),
        ("final steps", Align::Right),
        ("final return", Align::Right),
        ("steps / optimum", Align::Right),
        ("success", Align::Right),
        ("greedy reached", Align::Right),
        ("env steps (total)", Align::Right),
        ("of which pre-training", Align::Right),
    ]);
    for s in summary {
        let _ = table.push_row([
            method_title(&s.method),
            ci(&s.final_steps),
            ci(&s.final_return),
            s.final_steps_to_optimum
                .as_ref()
                .map_or_else(|| "—".to_owned(), ci),
            percent(&s.final_reached),
            format!("{}%", format_fixed(s.evaluation_reached * 100.0, 0)),
            ci(&s.total_env_steps),
            ci(&s.pretrain_env_steps),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');

    if is_robot {
        let mut robot = MarkdownTable::new([
            ("method", Align::Left),
            ("average reward", Align::Right),
            ("time to reach (s)", Align::Right),
            ("retention time (s)", Align::Right),
        ]);
        for s in summary {
            if let Some(r) = &s.robot {
                let _ = robot.push_row([
                    method_title(&s.method),
                    ci(&r.average_reward),
                    r.time_to_reach
                        .as_ref()
                        .map_or_else(|| "never reached".to_owned(), ci),
                    ci(&r.retention_time),
                ]);
            }
        }
        let _ = writeln!(
            text,
            "Robot metrics (Fig. 13–15 analogues), final window:\n"
        );
        text.push_str(&robot.render());
        text.push('\n');
    }

    let base = summary.iter().find(|s| s.method == "ea-madm");
    let ablations: Vec<&MethodSummary> = summary
        .iter()
        .filter(|s| !MAIN_METHODS.contains(&s.method.as_str()))
        .collect();
    if let (Some(base), false) = (base, ablations.is_empty()) {
        let _ = writeln!(text, "Ablations (EA-MADM with one switch flipped):\n");
        let mut table = MarkdownTable::new([
            ("variant", Align::Left),
            ("final steps", Align::Right),
            ("Δ steps vs EA-MADM", Align::Right),
            ("final return", Align::Right),
            ("success", Align::Right),
            ("intervals overlap EA-MADM's", Align::Left),
        ]);
        for s in std::iter::once(base).chain(ablations) {
            let is_base = std::ptr::eq(s, base);
            let _ = table.push_row([
                method_title(&s.method),
                ci(&s.final_steps),
                if is_base {
                    "—".to_owned()
                } else {
                    format_fixed(s.final_steps.mean - base.final_steps.mean, 1)
                },
                ci(&s.final_return),
                percent(&s.final_reached),
                if is_base {
                    "—".to_owned()
                } else if overlap(&s.final_steps, &base.final_steps) {
                    "yes: no clear difference".to_owned()
                } else if s.final_steps.mean < base.final_steps.mean {
                    "no: the variant is shorter".to_owned()
                } else {
                    "no: EA-MADM is shorter".to_owned()
                },
            ]);
        }
        text.push_str(&table.render());
        text.push('\n');
    }
    let mut figures = vec!["steps", "return"];
    if !summary
        .iter()
        .all(|s| MAIN_METHODS.contains(&s.method.as_str()))
    {
        figures.push("ablations-steps");
    }
    if is_robot {
        figures.extend(["average-reward", "reaching-time", "retention-time"]);
    }
    figures.push("trajectories");
    let links: Vec<String> = figures
        .iter()
        .map(|f| format!("[{f}]({}/{f}.svg)", planned.name))
        .collect();
    let _ = writeln!(
        text,
        "Figures: {}; tables: [curves]({name}/curves.csv), [trajectories]({name}/trajectories.csv).\n",
        links.join(", "),
        name = planned.name
    );
}

fn write_paper_comparison(
    text: &mut String,
    experiments: &[ExperimentResults<'_>],
    summaries: &[Vec<MethodSummary>],
) {
    let _ = writeln!(text, "## The paper's numbers beside ours\n");
    let mut table = MarkdownTable::new([
        ("task", Align::Left),
        ("paper: EA-MADM steps", Align::Right),
        ("paper: EA-MADM return", Align::Right),
        ("ours: EA-MADM steps", Align::Right),
        ("ours: EA-MADM return", Align::Right),
        ("our optimum", Align::Right),
        ("ours: best of the four methods (criterion)", Align::Left),
    ]);
    let mut statements = Vec::new();
    for (experiment, summary) in experiments.iter().zip(summaries) {
        let planned = experiment.planned;
        let paper = planned.paper_maze.map(paper_numbers);
        let ea = summary.iter().find(|s| s.method == "ea-madm");
        let best = best_main_method(planned, summary);
        let optimum = summary.first().and_then(|s| s.optimum_steps);
        let _ = table.push_row([
            planned.title.clone(),
            paper.map_or_else(|| "not given".to_owned(), |p| format_fixed(p.steps, 0)),
            paper.map_or_else(|| "not given".to_owned(), |p| format_fixed(p.reward, 0)),
            ea.map_or_else(|| "not run".to_owned(), |s| ci(&s.final_steps)),
            ea.map_or_else(|| "not run".to_owned(), |s| ci(&s.final_return)),
            optimum.map_or_else(|| "—".to_owned(), |o| o.to_string()),
            best.map_or_else(String::new, |s| {
                format!(
                    "{} ({})",
                    method_title(&s.method),
                    criterion_value(planned, s)
                )
            }),
        ]);
        statements.push(statement(planned, summary, paper, ea, best, optimum));
    }
    text.push_str(&table.render());
    text.push('\n');
    let _ = writeln!(text, "### Where and why ours differ\n");
    let _ = writeln!(
        text,
        "- **Layouts.** The paper does not publish its mazes; ours are generated with the paper's \
         sizes and obstacle counts (crate `mazes`), so step counts and returns are not directly \
         comparable: the paper's optimum path lengths are unknown.\n\
         - **Seeds.** The paper shows single runs; we report the mean and 95% interval over seeds.\n\
         - **Simulator.** The paper gives no numbers for the robot; ours runs in a 2D model of the \
         robot (crate `wmr-model`), not in Webots."
    );
    for statement in statements {
        let _ = writeln!(text, "- {statement}");
    }
    text.push('\n');
}

/// Whether the experiment's best method is the one with the fewest final-window steps (mazes,
/// where every episode ends at the target or the cap) rather than the highest success rate
/// (the robot, whose episodes also end early on a collision, so few steps can mean failure).
fn ranks_by_steps(planned: &PlannedExperiment) -> bool {
    planned.experiment.task().maze().is_some()
}

/// The best method of an experiment (see [`ranks_by_steps`]); ties go to the earlier label in
/// alphabetical order, so the choice is deterministic.
fn best_method<'a>(
    planned: &PlannedExperiment,
    summary: &'a [MethodSummary],
) -> Option<&'a MethodSummary> {
    best_of(planned, summary.iter())
}

/// The best of the paper's four methods that were run (the paper's claim is about them; the
/// ablations have their own table), or of all methods when none of the four was.
fn best_main_method<'a>(
    planned: &PlannedExperiment,
    summary: &'a [MethodSummary],
) -> Option<&'a MethodSummary> {
    let is_main = |s: &&MethodSummary| MAIN_METHODS.contains(&s.method.as_str());
    if summary.iter().any(|s| is_main(&s)) {
        best_of(planned, summary.iter().filter(is_main))
    } else {
        best_method(planned, summary)
    }
}

fn best_of<'a>(
    planned: &PlannedExperiment,
    summary: impl Iterator<Item = &'a MethodSummary>,
) -> Option<&'a MethodSummary> {
    if ranks_by_steps(planned) {
        summary.min_by(|a, b| {
            a.final_steps
                .mean
                .total_cmp(&b.final_steps.mean)
                .then_with(|| a.method.cmp(&b.method))
        })
    } else {
        summary.min_by(|a, b| {
            b.final_reached
                .mean
                .total_cmp(&a.final_reached.mean)
                .then_with(|| b.final_return.mean.total_cmp(&a.final_return.mean))
                .then_with(|| a.method.cmp(&b.method))
        })
    }
}

/// The number the best method is chosen by, for the table.
fn criterion_value(planned: &PlannedExperiment, summary: &MethodSummary) -> String {
    if ranks_by_steps(planned) {
        format!("fewest final steps: {}", ci(&summary.final_steps))
    } else {
        format!(
            "highest success: {}, return {}",
            percent(&summary.final_reached),
            ci(&summary.final_return)
        )
    }
}

/// A sentence on one experiment, computed from its numbers.
fn statement(
    planned: &PlannedExperiment,
    summary: &[MethodSummary],
    paper: Option<PaperNumbers>,
    ea: Option<&MethodSummary>,
    best: Option<&MethodSummary>,
    optimum: Option<u64>,
) -> String {
    let mut parts = Vec::new();
    let title = &planned.title;
    let (quantity, pick): (&str, fn(&MethodSummary) -> &SeedSummary) = if ranks_by_steps(planned) {
        ("the fewest final-window steps", |s| &s.final_steps)
    } else {
        ("the highest final-window success rate", |s| {
            &s.final_reached
        })
    };
    let claim = if paper.is_some() {
        "as in the paper"
    } else {
        "the paper claims EA-MADM is best but gives no numbers"
    };
    let show = |s: &MethodSummary| {
        if ranks_by_steps(planned) {
            ci(&s.final_steps)
        } else {
            format!("{} success", percent(&s.final_reached))
        }
    };
    match (ea, best) {
        (Some(_), Some(best)) if !ranks_by_steps(planned) && best.final_reached.mean == 0.0 => {
            parts.push(format!(
                "**{title}.** No method reached the target in its final window, so these runs \
                 cannot support or contradict the paper's claim; by final return {} leads ({}).",
                method_title(&best.method),
                ci(&best.final_return)
            ));
        }
        (Some(ea), Some(best)) if best.method == ea.method => {
            let runner_up = best_of(
                planned,
                summary
                    .iter()
                    .filter(|s| s.method != ea.method && MAIN_METHODS.contains(&s.method.as_str())),
            );
            let caveat = runner_up.map_or_else(String::new, |next| {
                if overlap(pick(ea), pick(next)) {
                    format!(
                        "; but its 95% interval overlaps that of the runner-up {} ({}), so the \
                         lead is not clear",
                        method_title(&next.method),
                        show(next)
                    )
                } else {
                    format!(
                        "; its 95% interval does not overlap that of the runner-up {} ({})",
                        method_title(&next.method),
                        show(next)
                    )
                }
            });
            parts.push(format!(
                "**{title}.** Among the paper's four methods, EA-MADM has {quantity} ({}; \
                 {claim}){caveat}.",
                show(ea)
            ));
        }
        (Some(ea), Some(best)) => parts.push(format!(
            "**{title}.** Unlike the paper's claim, EA-MADM ({}) does not have {quantity} among \
             the paper's four methods: {} does ({}); their 95% intervals {}.",
            show(ea),
            method_title(&best.method),
            show(best),
            if overlap(pick(ea), pick(best)) {
                "overlap, so the difference is not clear"
            } else {
                "do not overlap"
            }
        )),
        _ => parts.push(format!("**{title}.** EA-MADM was not run.")),
    }
    // optimum far below 2^52
    if let (Some(ea), Some(optimum), Some(paper)) = (ea, optimum, paper) {
        let ratio = ea.final_steps.mean / optimum as f64;
        parts.push(format!(
            "On our layout the BFS optimum is {optimum} steps and EA-MADM ends at {}× it; the \
             paper's {} steps are on its own layout, whose optimum it does not give.",
            format_fixed(ratio, 2),
            format_fixed(paper.steps, 0)
        ));
        let sign_differs = (ea.final_return.mean < 0.0) != (paper.reward < 0.0);
        if sign_differs {
            parts.push(format!(
                "Our final return ({}) has the opposite sign of the paper's ({}): the return \
                 depends on the path length and the collisions on a given layout.",
                ci(&ea.final_return),
                format_fixed(paper.reward, 0)
            ));
        }
    }
    let greedy: Vec<String> = summary
        .iter()
        .filter(|s| MAIN_METHODS.contains(&s.method.as_str()))
        .map(|s| {
            format!(
                "{} {}%",
                method_title(&s.method),
                format_fixed(s.evaluation_reached * 100.0, 0)
            )
        })
        .collect();
    if greedy.len() > 1 {
        parts.push(format!(
            "The greedy policy after training reaches the target for {} of the seeds.",
            greedy.join(", ")
        ));
    }
    let never: Vec<String> = summary
        .iter()
        .filter(|s| s.final_reached.mean == 0.0)
        .map(|s| method_title(&s.method))
        .collect();
    if !never.is_empty() {
        parts.push(format!(
            "No final-window episode reached the target for: {} (degenerate within these \
             episodes).",
            never.join(", ")
        ));
    }
    if let Some(ea) = ea {
        let same: Vec<String> = summary
            .iter()
            .filter(|s| {
                s.method != ea.method
                    && s.final_steps == ea.final_steps
                    && s.final_return == ea.final_return
                    && s.total_env_steps == ea.total_env_steps
            })
            .map(|s| format!("`{}`", s.method))
            .collect();
        if !same.is_empty() {
            parts.push(format!(
                "{} gives exactly EA-MADM's numbers (with thresholds 1.0 the experience tree \
                 stores every pair exactly, so it answers as the table does).",
                same.join(", ")
            ));
        }
    }
    if let (Some(ea), Some(literal)) = (ea, summary.iter().find(|s| s.method == "ea-madm-literal"))
    {
        parts.push(format!(
            "The literal standardisation of Eq. 10–12 (`ea-madm-literal`) gives the source task a \
             zero learning signal; it ends at {} steps against EA-MADM's {}.",
            ci(&literal.final_steps),
            ci(&ea.final_steps)
        ));
    }
    parts.join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::Task;
    use crate::execute::run_experiments;
    use crate::experiments::{plan_experiments, shorten};
    use crate::progress::Progress;
    use crate::resume::RunStore;

    /// A tiny Task I run of three methods and two seeds.
    fn tiny() -> (PlannedExperiment, Vec<RunRecord>) {
        let mut planned = plan_experiments(&[Task::Task1], false, None, 2, true).unwrap();
        let mut config = planned[0].config().clone();
        shorten(&mut config, 6, Some(120), None);
        planned[0].experiment = eamadm::Experiment::new(config).unwrap();
        let methods: Vec<String> = ["ea-madm", "softmax", "ea-madm-table"]
            .map(str::to_owned)
            .to_vec();
        let dir = tempfile::tempdir().unwrap();
        let records = run_experiments(
            &planned,
            &methods,
            &RunStore::new(dir.path()),
            &Progress::hidden(),
        )
        .unwrap()
        .remove(0)
        .records;
        (planned.remove(0), records)
    }

    #[test]
    fn the_report_names_the_method_the_numbers_say_is_best() {
        let (planned, records) = tiny();
        let report = render_report(
            &[ExperimentResults {
                planned: &planned,
                records: &records,
            }],
            true,
        )
        .unwrap();
        let summary = summarise(&records, DEFAULT_FINAL_WINDOW).unwrap();
        let best = best_main_method(&planned, &summary).unwrap();
        // The claim is about the paper's four methods: the ablation is not a candidate.
        let fewest = summary
            .iter()
            .filter(|s| MAIN_METHODS.contains(&s.method.as_str()))
            .map(|s| s.final_steps.mean)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(best.final_steps.mean, fewest);
        let ea = summary.iter().find(|s| s.method == "ea-madm").unwrap();
        if best.method == "ea-madm" {
            assert!(
                report.contains("EA-MADM has the fewest final-window steps"),
                "{report}"
            );
        } else {
            assert!(
                report.contains(&format!(
                    "does not have the fewest final-window steps among the paper's four \
                     methods: {} does",
                    method_title(&best.method)
                )),
                "{report}"
            );
        }
        // The exact-tree ablation is recognised as identical, from the numbers.
        assert_eq!(
            summary
                .iter()
                .find(|s| s.method == "ea-madm-table")
                .unwrap()
                .final_steps,
            ea.final_steps
        );
        assert!(
            report.contains("`ea-madm-table` gives exactly EA-MADM's numbers"),
            "{report}"
        );
        for section in [
            "## Task I (`task1`)",
            "Ablations (EA-MADM with one switch flipped)",
            "## The paper's numbers beside ours",
            "### Where and why ours differ",
        ] {
            assert!(report.contains(section), "missing {section:?} in\n{report}");
        }
        let comparison = &report[report.find("## The paper's numbers").unwrap()..];
        let row: Vec<&str> = comparison
            .lines()
            .find(|line| line.starts_with("| Task I "))
            .unwrap()
            .split('|')
            .map(str::trim)
            .collect();
        assert_eq!(row[1..4], ["Task I", "80", "155"]);
    }

    #[test]
    fn paper_numbers_are_the_papers() {
        assert_eq!(
            paper_numbers(Preset::Task1),
            PaperNumbers {
                steps: 80.0,
                reward: 155.0
            }
        );
        assert_eq!(
            paper_numbers(Preset::Task2),
            PaperNumbers {
                steps: 86.0,
                reward: -71.0
            }
        );
    }
}
