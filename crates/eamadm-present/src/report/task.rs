//! Per task: the scores table, the controls and EA-MADM against them, EA-MADM against each
//! competitor, bimodal distributions, the sentences that explain odd numbers, and the figures.

use std::fmt::Write as _;

use super::format::{
    Align, MarkdownTable, format_fixed, interval, number, p_value, paired_interval, role_text,
    share,
};
use super::{ExperimentFacts, Figures, FinalEpsilon, ReportContext, Verdicts};
use eamadm_eval::Role;
use eamadm_eval::claims::{
    self, ComparisonOutcome, ControlComparison, Estimate, Judgement, MethodOverview,
};
use eamadm_eval::facts::ControlFamily;
use eamadm_eval::findings::TaskFindings;
use eamadm_eval::paper_claims::method_title;

/// The metrics of the scores table's interval columns: every method's, judged or not, so each
/// is one of the estimates the verdicts state for every method
/// (`claims::OVERVIEW_COLUMNS`; the test below).
const SCORES_TABLE_METRICS: [&str; 4] = [
    "final_steps",
    "final_return",
    "fluctuation_steps",
    "fluctuation_return",
];

pub(crate) fn estimate_cell(verdicts: &Verdicts, task: &str, method: &str, metric: &str) -> String {
    match verdicts.estimate(task, method, metric) {
        Some(Estimate { iqm: Some(i), .. }) => interval(i),
        Some(_) => "never reaches".to_owned(),
        None => "—".to_owned(),
    }
}

pub(crate) fn write_task(
    text: &mut String,
    context: &ReportContext,
    experiment: &ExperimentFacts,
    verdicts: &Verdicts,
    found: Option<&TaskFindings>,
) {
    let task = experiment.name.as_str();
    // A method that scores as an earlier one on every seed is one row: its group's.
    let shown = |o: &&&MethodOverview| {
        found.is_none_or(|f| !f.identical.iter().any(|i| i.method == o.method))
    };
    let _ = writeln!(text, "## {} (`{task}`)\n", experiment.title);
    let overviews: Vec<&MethodOverview> = verdicts
        .overviews
        .iter()
        .filter(|o| o.task == task)
        .collect();
    let step_cap = overviews.iter().find_map(|o| o.step_cap);
    let optimum = verdicts
        .scores
        .iter()
        .find(|s| s.task == task)
        .and_then(|s| s.optimum_steps);
    let _ = writeln!(
        text,
        "{} episodes, {} seeds per method{}{}.\n",
        experiment.episodes,
        experiment.seeds,
        step_cap.map_or_else(String::new, |cap| format!(", step cap {cap}")),
        optimum.map_or_else(String::new, |o| format!(", optimum route {o} steps")),
    );
    let columns = [
        ("method", Align::Left),
        ("role", Align::Left),
        ("final steps", Align::Right),
        ("final return", Align::Right),
        ("fluctuation steps", Align::Right),
        ("fluctuation return", Align::Right),
        ("training success", Align::Right),
        ("greedy reached", Align::Right),
        ("env steps (pre-training)", Align::Right),
    ];
    let row = |o: &MethodOverview| {
        [
            method_title(&o.method),
            role_text(o.role).to_owned(),
            estimate_cell(verdicts, task, &o.method, SCORES_TABLE_METRICS[0]),
            estimate_cell(verdicts, task, &o.method, SCORES_TABLE_METRICS[1]),
            estimate_cell(verdicts, task, &o.method, SCORES_TABLE_METRICS[2]),
            estimate_cell(verdicts, task, &o.method, SCORES_TABLE_METRICS[3]),
            share(&o.training_success),
            share(&o.greedy_success),
            format!(
                "{} ({})",
                format_fixed(o.env_steps_total, 0),
                format_fixed(o.pretrain_env_steps, 0)
            ),
        ]
    };
    let mut table = MarkdownTable::new(columns);
    for o in overviews
        .iter()
        .filter(|o| o.role != Role::Control)
        .filter(|o| shown(o))
    {
        let _ = table.push_row(row(o));
    }
    let _ = writeln!(
        text,
        "IQM over seeds [bootstrap 95% interval]; shares with Wilson 95% intervals; mean \
         environment steps per run (of which sub-task pre-training):\n"
    );
    text.push_str(&table.render());
    text.push('\n');

    let controls: Vec<&&MethodOverview> = overviews
        .iter()
        .filter(|o| o.role == Role::Control)
        .filter(|o| shown(o))
        .collect();
    if !controls.is_empty() {
        let _ = writeln!(
            text,
            "### Controls (control, not in the paper)\n\n\
             Comparisons the paper does not run; they explain the result and never enter the \
             paper's verdicts.\n"
        );
        let mut table = MarkdownTable::new(columns);
        for o in &controls {
            let _ = table.push_row(row(o));
        }
        text.push_str(&table.render());
        text.push('\n');
        write_control_comparisons(text, task, verdicts, found);
        for sentence in found
            .map(super::strongest::strongest_sentences)
            .unwrap_or_default()
        {
            let _ = writeln!(text, "{sentence}\n");
        }
    }

    write_comparisons(text, task, verdicts);
    let distinct: Vec<&MethodOverview> = overviews.iter().filter(|o| shown(o)).copied().collect();
    write_distributions(text, &distinct);
    super::outcomes::write_outcomes(text, task, context, verdicts, found);
    let robot = context.paper_task(task).is_some_and(|t| t.robot)
        || verdicts
            .scores
            .iter()
            .any(|s| s.task == task && s.reach_time.is_some());
    for sentence in explanations(context, experiment, robot, &overviews, verdicts, found) {
        let _ = writeln!(text, "- {sentence}");
    }
    text.push('\n');
    if let Some(found) = found {
        text.push_str(&super::outcomes::equalities(found));
    }
    if robot {
        super::robot::write_robot(text, experiment, &overviews, verdicts, found);
    }
    super::robot::write_robot_behaviour(
        text,
        experiment,
        &overviews,
        &context.action_names,
        verdicts.paper_ea_madm(task),
        found,
    );
    if !experiment.figures.files.is_empty() || !experiment.figures.not_drawn.is_empty() {
        text.push_str(&gallery(task, &experiment.figures));
    }
    if experiment.tables_written {
        let _ = writeln!(
            text,
            "Tables: [curves]({task}/{}) (gzip), [trajectories]({task}/{}).\n",
            context.curves_file, context.trajectories_file
        );
    } else {
        // A report of runs rendered outside an output folder (`eamadm.report` of
        // `eamadm.run`'s results in Python) has no tables to link.
        let _ = writeln!(
            text,
            "No tables were written for `{task}`: only `cargo xtask reproduce-paper` writes \
             them, into its output folder (`eamadm.run` returns the curves).\n"
        );
    }
}

/// Markdown for `REPORT.md`: each figure that has a caption, in the captions' order, as an
/// inline image (a relative path, so the report shows it wherever the folder is) with its
/// one-line caption; then links to the other figures.
pub(crate) fn gallery(task: &str, figures: &Figures) -> String {
    let Figures {
        files,
        captions,
        not_drawn,
    } = figures;
    let mut text = String::new();
    for (file, caption) in captions {
        if files.iter().any(|f| f == file) {
            let _ = writeln!(
                text,
                "![{}]({task}/{file})\n\n*{caption}*\n",
                file.trim_end_matches(".svg")
            );
        }
    }
    let others: Vec<String> = files
        .iter()
        .filter(|f| !captions.iter().any(|(c, _)| c == *f))
        .map(|f| format!("[{}]({task}/{f})", f.trim_end_matches(".svg")))
        .collect();
    if !others.is_empty() {
        let _ = writeln!(text, "More figures: {}.\n", others.join(", "));
    }
    if !not_drawn.is_empty() {
        let _ = writeln!(text, "{}\n", super::not_drawn_sentence(not_drawn));
    }
    text
}

fn write_control_comparisons(
    text: &mut String,
    task: &str,
    verdicts: &Verdicts,
    found: Option<&TaskFindings>,
) {
    // A control that scores as an earlier method on every seed is compared as that one.
    let rows: Vec<&ControlComparison> = verdicts
        .controls
        .iter()
        .filter(|c| c.task == task)
        .filter(|c| {
            found.is_none_or(|f| !f.identical.iter().any(|i| i.method == c.comparison.versus))
        })
        .collect();
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "EA-MADM against each control, paired by seed (Δ = mean over seeds of EA-MADM − the \
         control, exact sign-flip 95% interval; p that Δ lies beyond the margin, raw, not \
         adjusted, since these comparisons enter no verdict; Δ IQM descriptive):\n"
    );
    let mut table = MarkdownTable::new([
        ("control", Align::Left),
        ("metric", Align::Left),
        ("Δ mean [95%]", Align::Right),
        ("p", Align::Right),
        ("P(EA-MADM better)", Align::Right),
        ("Δ IQM [95%]", Align::Right),
    ]);
    for c in &rows {
        let _ = table.push_row([
            format!("`{}`", c.comparison.versus),
            format!("`{}`", c.comparison.metric.column),
            paired_interval(&c.comparison.paired),
            p_value(c.comparison.p_value),
            format_fixed(c.comparison.p_improvement, 2),
            interval(&c.comparison.iqm_difference),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
}

fn write_comparisons(text: &mut String, task: &str, verdicts: &Verdicts) {
    let Some(method) = verdicts.paper_ea_madm(task) else {
        return;
    };
    let judgements: Vec<&Judgement> = verdicts
        .judgements
        .iter()
        .filter(|j| j.task == task && j.method == method)
        .collect();
    if judgements
        .iter()
        .all(|j| j.comparisons.is_empty() && j.untested.is_empty())
    {
        return;
    }
    let _ = writeln!(
        text,
        "EA-MADM against each competitor, paired by seed (Δ = mean over seeds of EA-MADM − the \
         competitor, exact sign-flip 95% interval; p that Δ lies beyond the margin; Δ IQM \
         descriptive):\n"
    );
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("metric", Align::Left),
        ("versus", Align::Left),
        ("Δ mean [95%]", Align::Right),
        ("p", Align::Right),
        ("Holm p", Align::Right),
        ("P(EA-MADM better)", Align::Right),
        ("settles", Align::Left),
        ("Δ IQM [95%]", Align::Right),
    ]);
    for j in &judgements {
        for c in &j.comparisons {
            let _ = table.push_row([
                j.claim.id.to_owned(),
                format!("`{}`", c.metric.column),
                method_title(&c.versus),
                paired_interval(&c.paired),
                p_value(c.p_value),
                if c.informative {
                    p_value(c.p_holm)
                } else {
                    "—".to_owned()
                },
                format_fixed(c.p_improvement, 2),
                match c.outcome {
                    _ if !c.informative => "nothing: one value on both sides".to_owned(),
                    ComparisonOutcome::FavoursMethod => "EA-MADM better".to_owned(),
                    ComparisonOutcome::FavoursCompetitor => {
                        format!("{} better", method_title(&c.versus))
                    }
                    ComparisonOutcome::Unsettled
                        if claims::is_equivalent(c, verdicts.options.alpha) =>
                    {
                        "equivalent".to_owned()
                    }
                    ComparisonOutcome::Unsettled => "nothing".to_owned(),
                },
                interval(&c.iqm_difference),
            ]);
        }
        for u in &j.untested {
            let _ = table.push_row([
                j.claim.id.to_owned(),
                format!("`{}`", u.metric),
                method_title(&u.versus),
                "—".to_owned(),
                "—".to_owned(),
                "—".to_owned(),
                "—".to_owned(),
                format!("untestable: {}", u.reason),
                "—".to_owned(),
            ]);
        }
    }
    text.push_str(&table.render());
    text.push('\n');
}

fn write_distributions(text: &mut String, overviews: &[&MethodOverview]) {
    let bimodal: Vec<&&MethodOverview> =
        overviews.iter().filter(|o| o.final_steps.bimodal).collect();
    if bimodal.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "Per-seed final steps are bimodal for these methods (an IQM hides this; seeds at the \
         step cap never finished an episode in the final window):\n"
    );
    let mut table = MarkdownTable::new([
        ("method", Align::Left),
        ("seeds", Align::Right),
        ("at the cap", Align::Right),
        ("min", Align::Right),
        ("q1", Align::Right),
        ("median", Align::Right),
        ("q3", Align::Right),
        ("max", Align::Right),
    ]);
    for o in bimodal {
        let d = &o.final_steps;
        let _ = table.push_row([
            method_title(&o.method),
            d.n.to_string(),
            d.at_cap.to_string(),
            number(d.min),
            number(d.q1),
            number(d.median),
            number(d.q3),
            number(d.max),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
}

/// Sentences on numbers that need explaining, each chosen by the numbers.
fn explanations(
    context: &ReportContext,
    experiment: &ExperimentFacts,
    robot: bool,
    overviews: &[&MethodOverview],
    verdicts: &Verdicts,
    found: Option<&TaskFindings>,
) -> Vec<String> {
    let task = experiment.name.as_str();
    let mut sentences = Vec::new();
    for o in overviews.iter().filter(|o| o.role == Role::Paper) {
        let epsilon = experiment
            .final_epsilon
            .iter()
            .find(|e| e.method == o.method);
        if let Some(sentence) = training_versus_greedy(o, epsilon) {
            sentences.push(sentence);
        }
    }
    if let Some(sentence) = step_budget(experiment, overviews) {
        sentences.push(sentence);
    }
    sentences.extend(super::outcomes::pretraining_shares(task, context, verdicts));
    sentences.extend(found.and_then(super::outcomes::identical));
    if !robot {
        // A robot state has more features than a maze cell's column and row.
        sentences.extend(super::outcomes::tau_caveat(task, context, verdicts, found));
    }
    sentences
}

/// Whether training success and greedy success disagree, and how. Where the greedy policy
/// loops, `epsilon` (the method's ε over the final window, if it explores ε-greedily) says
/// whether exploration can be what breaks the loops in training: below one expected random
/// action per final-window episode (ε × median final steps) it cannot, and online learning
/// does.
pub(crate) fn training_versus_greedy(
    o: &MethodOverview,
    epsilon: Option<&FinalEpsilon>,
) -> Option<String> {
    let training = o.training_success.wilson;
    let greedy = o.greedy_success.wilson;
    if training.low > greedy.high {
        let looping = if o.greedy_at_cap > 0 {
            let cause = match epsilon {
                Some(e) => {
                    let random_actions = e.first.max(e.last) * o.final_steps.median;
                    if random_actions < 1.0 {
                        format!(
                            "; ε over the final window is {} to {}, under {} random actions per \
                             episode of {} steps (median), so online learning, not exploration, \
                             breaks the loops of the frozen greedy policy during training",
                            scientific(e.first),
                            scientific(e.last),
                            format_fixed(random_actions, 2),
                            format_fixed(o.final_steps.median, 0)
                        )
                    } else {
                        format!(
                            "; ε over the final window is {} to {}, about {} random actions per \
                             episode of {} steps (median), so exploration and online learning \
                             both break the loops of the frozen greedy policy during training",
                            scientific(e.first),
                            scientific(e.last),
                            format_fixed(random_actions, 1),
                            format_fixed(o.final_steps.median, 0)
                        )
                    }
                }
                None => String::new(),
            };
            format!(
                "; in {} of the {} failing seeds the greedy episode runs to the step cap{cause}",
                o.greedy_at_cap,
                o.greedy_success.trials - o.greedy_success.successes
            )
        } else {
            String::new()
        };
        Some(format!(
            "{} reaches the target in {} of its final-window training episodes but its greedy \
             policy after training only in {} seeds{looping}.",
            method_title(&o.method),
            share(&o.training_success),
            share(&o.greedy_success)
        ))
    } else if greedy.low > training.high {
        Some(format!(
            "{}'s greedy policy after training reaches the target more often ({} seeds) than \
             its final-window training episodes do ({}): exploration costs it episodes.",
            method_title(&o.method),
            share(&o.greedy_success),
            share(&o.training_success)
        ))
    } else {
        None
    }
}

/// `9.0e-5`: two significant figures in scientific notation (a small ε).
fn scientific(value: f64) -> String {
    if value == 0.0 || (0.01..1000.0).contains(&value.abs()) {
        number(value)
    } else {
        format!("{value:.1e}")
    }
}

/// The step budgets of EA-MADM and the competitors, when they differ.
fn step_budget(experiment: &ExperimentFacts, overviews: &[&MethodOverview]) -> Option<String> {
    let ea = overviews
        .iter()
        .find(|o| o.role == Role::Paper && claims::is_under_test(&o.kind))?;
    let competitors: Vec<&&MethodOverview> = overviews
        .iter()
        .filter(|o| claims::is_competitor(o.role, &o.kind))
        .collect();
    let most = competitors
        .iter()
        .map(|o| o.env_steps_total)
        .fold(f64::NAN, f64::max);
    if competitors.is_empty() || ea.env_steps_total <= most {
        return None;
    }
    Some(format!(
        "EA-MADM's runs use {} environment steps each, {} of them in sub-task pre-training \
         (on the sub-tasks' shaped rewards), against at most {} for a competitor: {}× the \
         budget. {}",
        format_fixed(ea.env_steps_total, 0),
        format_fixed(ea.pretrain_env_steps, 0),
        format_fixed(most, 0),
        format_fixed(ea.env_steps_total / most, 1),
        controls_run(experiment, overviews)
    ))
}

/// Which of the controls that give the competitors EA-MADM's budget or reward information
/// ran, in words.
fn controls_run(experiment: &ExperimentFacts, overviews: &[&MethodOverview]) -> String {
    let family = |family: ControlFamily| -> Vec<String> {
        overviews
            .iter()
            .filter(|o| {
                o.role == Role::Control
                    && experiment
                        .method(&o.method)
                        .is_some_and(|m| m.control == Some(family))
            })
            .map(|o| format!("`{}`", o.method))
            .collect()
    };
    let (budget, reward) = (
        family(ControlFamily::BudgetMatched),
        family(ControlFamily::RewardMatched),
    );
    match (budget.is_empty(), reward.is_empty()) {
        (true, true) => "No control with an equal budget or equal reward information was run \
                         here, so whether either closes the gap is not tested."
            .to_owned(),
        (false, true) => format!(
            "The budget-matched controls ({}) give the competitors the same steps; no \
             reward-matched control was run here.",
            super::format::list(&budget)
        ),
        (true, false) => format!(
            "The reward-matched controls ({}) give the competitors the same reward \
             information; no budget-matched control was run here.",
            super::format::list(&reward)
        ),
        (false, false) => format!(
            "The budget-matched controls ({}) give the competitors the same steps, the \
             reward-matched ones ({}) the same reward information (the controls table above).",
            super::format::list(&budget),
            super::format::list(&reward)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::overview;
    use super::*;

    #[test]
    fn the_controls_sentence_names_the_controls_that_ran() {
        let control = |label: &str| {
            let mut o = overview((1, 2), (1, 2), 0);
            o.method = label.to_owned();
            o.role = Role::Control;
            o
        };
        // Their families come from their configs, whatever their labels.
        let (budget, shaped) = (control("softmax-budget"), control("my-shaped-control"));
        let mut facts = super::super::tests::experiment("task2", "Task II");
        facts.methods = vec![
            super::super::tests::method(
                "softmax-budget",
                Role::Control,
                "softmax",
                Some(ControlFamily::BudgetMatched),
            ),
            super::super::tests::method(
                "my-shaped-control",
                Role::Control,
                "softmax",
                Some(ControlFamily::RewardMatched),
            ),
        ];
        let controls_run = |overviews: &[&MethodOverview]| controls_run(&facts, overviews);
        assert!(controls_run(&[]).starts_with("No control with an equal budget"));
        assert!(controls_run(&[&budget]).starts_with(
            "The budget-matched controls (`softmax-budget`) give the competitors the same \
                 steps; no reward-matched control was run here."
        ));
        assert!(controls_run(&[&shaped]).ends_with("no budget-matched control was run here."));
        assert_eq!(
            controls_run(&[&budget, &shaped]),
            "The budget-matched controls (`softmax-budget`) give the competitors the same \
             steps, the reward-matched ones (`my-shaped-control`) the same reward information \
             (the controls table above)."
        );
    }

    #[test]
    fn the_scores_table_shows_only_estimates_stated_for_every_method() {
        for metric in SCORES_TABLE_METRICS
            .iter()
            .chain([&super::super::robot::RANKING_METRIC])
        {
            assert!(
                eamadm_eval::claims::OVERVIEW_COLUMNS.contains(metric),
                "{metric}"
            );
        }
    }
}
