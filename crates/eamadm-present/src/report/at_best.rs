//! The section "Each method at its best (same tuning budget)": per tuned task, the paper's
//! EA-MADM's verdicts when every method runs the trial its tuning chose, beside the
//! paper-setting verdicts, and the trials chosen (`--suite tuning`; docs/paper-notes.md §23).

use std::fmt::Write as _;

use eamadm_eval::findings::{AtBestFindings, Findings};
use eamadm_eval::paper_claims::CLAIMS;

use super::format::{Align, MarkdownTable, list, number};
use super::words::{self, deciding_or_reason};

/// The section's heading.
pub(crate) const AT_BEST_HEADING: &str = "## Each method at its best (same tuning budget)";

/// The objective's words.
fn objective_words(objective: &str) -> &'static str {
    match objective {
        "final_steps_iqm" => "IQM of final steps, lower is better",
        "success_rate_mean" => "mean success rate, higher is better",
        _ => "the task's objective",
    }
}

/// The paper-setting verdict of `claim` on `task`, `—` when it has none.
fn paper_verdict(findings: &Findings, task: &str, claim: &str) -> String {
    findings
        .task(task)
        .and_then(|t| t.verdicts.iter().find(|v| v.claim == claim))
        .map_or_else(|| "—".to_owned(), |v| v.verdict.name().to_owned())
}

fn write_task(text: &mut String, findings: &Findings, at_best: &AtBestFindings) {
    let _ = writeln!(text, "### {} at its best\n", at_best.title);
    let mut chosen = MarkdownTable::new([
        ("method", Align::Left),
        ("chosen trial", Align::Right),
        ("of", Align::Right),
        ("the paper's setting", Align::Left),
        ("objective on the tuning seeds", Align::Left),
        ("converged on held-out seeds", Align::Right),
    ]);
    for trial in &at_best.chosen {
        let converged = if trial.method == at_best.method {
            Some(at_best.converged)
        } else {
            at_best
                .competitors
                .iter()
                .find(|c| c.method == trial.method)
                .map(|c| c.converged)
        };
        let _ = chosen.push_row([
            words::name(&trial.method),
            trial.trial.to_string(),
            trial.trials.to_string(),
            if trial.paper_setting { "yes" } else { "no" }.to_owned(),
            format!(
                "{} ({})",
                number(trial.score),
                objective_words(&trial.objective)
            ),
            converged.map_or_else(|| "—".to_owned(), |c| format!("{}/{}", c.hits, c.seeds)),
        ]);
    }
    text.push_str(&chosen.render());
    text.push('\n');
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("paper setting", Align::Left),
        ("each at its best", Align::Left),
        ("the number that decides it (at its best)", Align::Left),
    ]);
    for claim in &CLAIMS {
        let Some(v) = at_best.verdicts.iter().find(|v| v.claim == claim.id) else {
            continue;
        };
        let _ = table.push_row([
            claim.id.to_owned(),
            paper_verdict(findings, &at_best.task, claim.id),
            format!("**{}**", v.verdict.name()),
            deciding_or_reason(v.deciding.as_ref(), &v.reason, &at_best.method, true),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
    if at_best.changed.is_empty() {
        let _ = writeln!(
            text,
            "No verdict on {} differs from the paper setting's.\n",
            at_best.title
        );
    } else {
        let _ = writeln!(
            text,
            "Verdicts that differ from the paper setting's on {}: {}.\n",
            at_best.title,
            list(&at_best.changed)
        );
    }
}

/// The section, when the run tuned (the findings have "at its best" verdicts).
pub(crate) fn write_at_best(text: &mut String, findings: &Findings) {
    let Some(first) = findings.at_best.first() else {
        return;
    };
    let (trials, seeds) = first
        .chosen
        .first()
        .map_or((0, 0), |c| (c.trials, c.tuning_seeds));
    let tasks: Vec<String> = findings.at_best.iter().map(|t| t.title.clone()).collect();
    let _ = writeln!(
        text,
        "{AT_BEST_HEADING}\n\n\
         Every method the claims compare had the same tuning budget on {}: {trials} trials \
         (trial 0 its setting in the paper's preset, the others drawn at random from the \
         ranges of docs/paper-notes.md §19), each run on {seeds} tuning seeds apart from the \
         held-out ones and scored by the task's objective; each method's best trial then ran \
         on the held-out seeds, and EA-MADM is judged against the competitors at their best by \
         the same rule and claims as above, paired by seed. The paper-setting verdicts above \
         do not change; every trial and its score is in [tuning.csv](tuning.csv). Tuning \
         counts trials, not environment steps, and EA-MADM searches five values against the \
         competitors' two to four.\n",
        list(&tasks)
    );
    for at_best in &findings.at_best {
        write_task(text, findings, at_best);
    }
}

#[cfg(test)]
mod tests {
    use eamadm_eval::findings::ChosenTrial;

    use super::super::tests::{context, judged, options, scores};
    use super::*;

    /// The paper-setting run of the shared test scores (EA-MADM better than the competitors)
    /// and an "at its best" run where the competitors were tuned to beat it: the section shows
    /// the chosen trials, both verdict columns, and names the claims that changed.
    #[test]
    fn the_section_reads_as_pinned() {
        let (_, findings) = judged(scores(60.0, &[3], 10.0));
        let paper_only = |rows: Vec<eamadm_eval::scores::FinalScore>| {
            rows.into_iter()
                .filter(|r| ["ea-madm", "epsilon-greedy", "softmax"].contains(&r.method.as_str()))
                .collect::<Vec<_>>()
        };
        // At their best the competitors end at 40 steps, EA-MADM at 60.
        let mut tuned = paper_only(scores(60.0, &[], 10.0));
        for row in &mut tuned {
            if row.method != "ea-madm" {
                row.final_steps = 40.0 + row.seed as f64;
                row.final_return = 200.0 - row.final_steps;
            }
        }
        let chosen = |method: &str, trial: u32, score: f64| ChosenTrial {
            task: "task1".to_owned(),
            method: method.to_owned(),
            trial,
            paper_setting: trial == 0,
            objective: "final_steps_iqm".to_owned(),
            score,
            trials: 16,
            tuning_seeds: 10,
        };
        let chosen = [
            chosen("ea-madm", 0, 61.5),
            chosen("epsilon-greedy", 7, 41.0),
            chosen("softmax", 12, 42.25),
        ];
        let findings = findings
            .with_at_best(&context(), &tuned, &chosen, &options())
            .unwrap();
        let [at_best] = &findings.at_best[..] else {
            panic!("{:?}", findings.at_best);
        };
        assert!(!at_best.changed.is_empty(), "{at_best:?}");
        let mut text = String::new();
        write_at_best(&mut text, &findings);
        insta::assert_snapshot!(text);
        // Without tuning, no section.
        let (_, plain) = judged(scores(60.0, &[3], 10.0));
        let mut none = String::new();
        write_at_best(&mut none, &plain);
        assert_eq!(none, "");
    }
}
