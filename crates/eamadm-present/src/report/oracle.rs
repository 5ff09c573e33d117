//! The report's section on the oracle and the positive control (issue 32): per task what
//! EA-MADM's decision and the plain aggregators do with the best sub-task values available
//! (exact `Q*` on a maze, sub-tasks pre-trained to convergence on the robot), which part of the
//! method fails, the plain aggregators' runs against OWA with visibility weights, whether the
//! reach sub-task ever reached in pre-training, and the positive control's prediction against
//! its outcome. Rendered from the findings only.

use std::fmt::Write as _;

use eamadm_eval::findings::{Findings, PredictionOutcome, SeedCount, TaskFindings};
use eamadm_eval::oracle::{FailingPart, OracleFinding, OracleValues, PretrainingSummary};

use super::format::{Align, MarkdownTable, list, number};
use super::words::{capitalised, name};

/// The section's heading.
pub(crate) const ORACLE_HEADING: &str = "## Oracle sub-task values and the positive control";

/// `hits/seeds`.
fn of(count: SeedCount) -> String {
    format!("{}/{}", count.hits, count.seeds)
}

/// Where the values come from, in a few words.
pub(crate) fn values_words(values: OracleValues) -> &'static str {
    match values {
        OracleValues::Exact => "exact sub-task values (value iteration on the maze's model)",
        OracleValues::PretrainedToConvergence => {
            "sub-tasks pre-trained to convergence (the best estimate: the robot has no exact \
             model)"
        }
    }
}

/// Which part fails, as a clause.
pub(crate) fn failing_words(finding: &OracleFinding) -> String {
    match finding.failing_part {
        FailingPart::Neither => "neither the decision rule nor learning fails".to_owned(),
        FailingPart::Learning => format!(
            "the decision rule works with these values and learning fails (its runs reach \
             after training on {} of {} seeds)",
            finding.runs_converged.unwrap_or(0),
            finding.seeds
        ),
        FailingPart::DecisionRule => {
            "the decision rule fails even with these values (a sub-task alone reaches where it \
             does not)"
                .to_owned()
        }
        FailingPart::SubtaskValues => {
            "the sub-task values fail: neither the decision nor any sub-task alone reaches, so \
             the decision step has no route to combine"
                .to_owned()
        }
    }
}

/// The part's name in a table cell.
fn failing_cell(part: FailingPart) -> &'static str {
    match part {
        FailingPart::Neither => "neither",
        FailingPart::Learning => "learning",
        FailingPart::DecisionRule => "decision rule",
        FailingPart::SubtaskValues => "sub-task values",
    }
}

/// A median of steps: whole, or halfway between two.
fn steps(median: f64) -> String {
    if median.fract() == 0.0 {
        format!("{median:.0}")
    } else {
        format!("{median:.1}")
    }
}

/// A median of steps in a table cell.
fn steps_cell(median: Option<f64>) -> String {
    median.map_or_else(|| "–".to_owned(), steps)
}

/// The oracle's sentence for the first screen: what EA-MADM's decision does with the best
/// sub-task values, and which part fails.
pub(crate) fn oracle_sentence(task: &TaskFindings) -> Option<String> {
    let o = task.oracle.iter().find(|o| o.decision == task.method)?;
    let optimum = match (o.optimum_steps, o.manhattan_steps) {
        (Some(optimum), Some(manhattan)) => {
            format!(" (shortest path {optimum}, Manhattan distance {manhattan})")
        }
        (Some(optimum), None) => format!(" (the planner's route {optimum})"),
        _ => String::new(),
    };
    let steps = o.median_steps_initial.map_or_else(String::new, |m| {
        format!(" in a median of {} steps{optimum}", steps(m))
    });
    let follows = o
        .best_subtask_alone
        .as_ref()
        .map_or_else(String::new, |(alone, _)| {
            format!(
                ", the same episode as `{alone}` on {} of {}",
                o.equals_subtask_alone, o.seeds
            )
        });
    Some(format!(
        "**Oracle:** with {} its decision reaches on {} of {} seeds{steps}{follows}; with the \
         own values its runs learned, it reaches on {} of {}. So {}.",
        values_words(o.values),
        o.reaches_initial,
        o.seeds,
        o.reaches_learned,
        o.seeds,
        failing_words(o)
    ))
}

/// The positive control's prediction against its outcome, in one sentence.
pub(crate) fn prediction_sentence(p: &PredictionOutcome) -> String {
    let predicted = &p.predicted;
    let oracle = p.oracle_reaches.map_or_else(String::new, |o| {
        format!(", its decision with exact values reaching on {}", of(o))
    });
    format!(
        "**Predicted before any run** (docs/paper-notes.md {}): no verdict better than {}, \
         EA-MADM ending as `{}` on most seeds, its decision with exact values {}. **Outcome:** \
         best verdict {}, ending as `{}` on {}{oracle}: the prediction {}.",
        predicted.notes,
        predicted.best_verdict.name(),
        predicted.follows,
        if predicted.oracle_reaches {
            "reaching"
        } else {
            "never reaching"
        },
        p.best_verdict.map_or("none", |v| v.name()),
        predicted.follows,
        of(p.ends_as_followed),
        if p.held { "held" } else { "failed" }
    )
}

/// One pre-training summary as a clause.
fn pretraining_clause(p: &PretrainingSummary) -> String {
    let converged = p.converged_seeds.map_or_else(String::new, |c| {
        format!(
            ", the stopping rule finding it converged on {c} of {}",
            p.seeds
        )
    });
    format!(
        "{}: `{}` reached the target in {} pre-training episodes on {} of {} seeds \
         ({} episodes and {} steps per seed on mean{converged})",
        name(&p.method),
        p.name,
        p.reaching_episodes,
        p.seeds_reaching,
        p.seeds,
        number(p.mean_episodes),
        number(p.mean_env_steps),
    )
}

/// Writes the section (nothing when no task has an oracle).
pub(crate) fn write_oracle(text: &mut String, findings: &Findings) {
    let tasks: Vec<&TaskFindings> = findings
        .tasks
        .iter()
        .filter(|t| !t.oracle.is_empty() || !t.reach_pretraining.is_empty())
        .collect();
    if tasks.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "{ORACLE_HEADING}\n\n\
         Does the decision step help when it is given the best sub-task values there are? \
         Each decision rule below (the paper's EA-MADM: OWA with visibility-graph weights; the \
         plain aggregators: the mean or the largest of the standardised columns) is fed, \
         exactly as a run feeds it, each sub-task's exact `Q*` (value iteration on a maze's \
         known model) or, on the robot, sub-tasks pre-trained to convergence, with the source \
         task's own column at its initial values (the decision as it first guides learning) \
         or at the values its run learned; its greedy episode is played from the run's \
         evaluation start ([oracle.csv](oracle.csv); each sub-task's pre-training: \
         [pretraining.csv](pretraining.csv)). *Reaches* counts seeds; *optimal share* is the \
         mean share of a maze's states whose decision is a shortest-path action; *as reach \
         alone* counts seeds whose episode is the reach sub-task's own.\n"
    );
    let mut table = MarkdownTable::new([
        ("task", Align::Left),
        ("decision", Align::Left),
        ("values", Align::Left),
        ("reaches (initial own)", Align::Right),
        ("median steps", Align::Right),
        ("optimum", Align::Right),
        ("optimal share", Align::Right),
        ("as reach alone", Align::Right),
        ("reaches (learned own)", Align::Right),
        ("runs reaching", Align::Right),
        ("what fails", Align::Left),
    ]);
    for task in &tasks {
        for o in &task.oracle {
            let optimum = match (o.optimum_steps, o.manhattan_steps) {
                (Some(optimum), Some(manhattan)) => format!("{optimum} (Manhattan {manhattan})"),
                (Some(optimum), None) => optimum.to_string(),
                _ => "–".to_owned(),
            };
            // A table row has as many cells as the header (a bug otherwise).
            let _ = table.push_row([
                task.title.clone(),
                name(&o.decision),
                match o.values {
                    OracleValues::Exact => "exact".to_owned(),
                    OracleValues::PretrainedToConvergence => {
                        "pre-trained to convergence".to_owned()
                    }
                },
                format!("{}/{}", o.reaches_initial, o.seeds),
                steps_cell(o.median_steps_initial),
                optimum,
                o.optimal_share_initial
                    .map_or_else(|| "–".to_owned(), |s| format!("{s:.3}")),
                format!("{}/{}", o.equals_subtask_alone, o.seeds),
                format!("{}/{}", o.reaches_learned, o.seeds),
                o.runs_converged
                    .map_or_else(|| "–".to_owned(), |r| format!("{r}/{}", o.seeds)),
                failing_cell(o.failing_part).to_owned(),
            ]);
        }
    }
    text.push_str(&table.render());
    text.push('\n');
    for task in &tasks {
        let mut sentences: Vec<String> = Vec::new();
        if let Some(o) = task.oracle.iter().find(|o| o.decision == task.method) {
            sentences.push(format!(
                "With {}, {}.",
                values_words(o.values),
                failing_words(o)
            ));
            if let Some(true) = o.at_manhattan_bound
                && let Some(optimum) = o.optimum_steps
            {
                sentences.push(format!(
                    "The layout is at the Manhattan bound (shortest path {optimum} = Manhattan \
                     distance): no obstacle forces a detour, so the distance-shaped reach \
                     sub-task alone is already optimal."
                ));
            }
        }
        if !task.aggregators.is_empty() {
            let parts: Vec<String> = task
                .aggregators
                .iter()
                .map(|a| {
                    format!(
                        "`{}` on {} (EA-MADM ends exactly as it on {})",
                        a.method,
                        of(a.converged),
                        of(a.ends_as_ea_madm)
                    )
                })
                .collect();
            let best = task.aggregators.iter().map(|a| a.converged.hits).max();
            let verdict = match best {
                Some(best) if task.converged.hits > best => {
                    "OWA with visibility weights reaches on more seeds than either plain aggregator"
                }
                Some(best) if task.converged.hits == best => {
                    "OWA with visibility weights reaches on no more seeds than the better plain \
                     aggregator"
                }
                _ => "a plain aggregator reaches on more seeds than OWA with visibility weights",
            };
            sentences.push(format!(
                "Plain aggregators against OWA: after training EA-MADM reaches on {}, {}; {verdict}.",
                of(task.converged),
                list(&parts)
            ));
        }
        if !task.reach_pretraining.is_empty() {
            let parts: Vec<String> = task
                .reach_pretraining
                .iter()
                .map(pretraining_clause)
                .collect();
            let never = task
                .reach_pretraining
                .iter()
                .filter(|p| p.seeds_reaching == 0)
                .count();
            let summary = if never == task.reach_pretraining.len() {
                "so for none of these methods does the reach sub-task ever reach in \
                 pre-training, and a reward paid for reaching (a goal bonus) is never paid"
                    .to_owned()
            } else if never == 0 {
                "so for every one of these methods the reach sub-task reaches in pre-training \
                 on some seed"
                    .to_owned()
            } else {
                format!(
                    "so for {never} of these {} methods the reach sub-task never reaches in \
                     pre-training",
                    task.reach_pretraining.len()
                )
            };
            sentences.push(format!(
                "Reach sub-task pre-training: {}; {summary}.",
                list(&parts)
            ));
        }
        if let Some(p) = &task.prediction {
            sentences.push(prediction_sentence(p));
        }
        if !sentences.is_empty() {
            let _ = writeln!(
                text,
                "- **{}.** {}",
                task.title,
                capitalised(&sentences.join(" "))
            );
        }
    }
    text.push('\n');
}
