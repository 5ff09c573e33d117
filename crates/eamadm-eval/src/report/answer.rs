//! The answer on top of `REPORT.md` (and in the README): one short paragraph per task that
//! answers "does EA-MADM beat its competitors, and why?", every sentence chosen by the numbers:
//! the verdicts against the paper's competitors, how the seeds ended (the collapses the IQM
//! hides), whether the collapses alone keep a verdict from a better one, the paired comparison
//! with the sub-task alone, and the strongest control, which can overturn a verdict.

use std::fmt::Write as _;

use super::format::{format_fixed, list, number};
use super::outcomes::{collapsed_list, discordant, outcomes};
use super::strongest::control_family;
use super::verdicts::{VERDICTS_HEADING, deciding_number};
use super::{ReportContext, Verdicts};
use crate::claims::{self, SUBTASK_ALONE, Verdict};
use crate::paper_claims::method_title;
use crate::scores::RunOutcome;

/// The heading of the answer in `REPORT.md`.
pub(crate) const ANSWER_HEADING: &str = "## The answer";

/// How good a verdict is for EA-MADM, to tell whether another comparison overturns it.
fn rank(verdict: Verdict) -> u8 {
    match verdict {
        Verdict::Contradicted => 0,
        Verdict::Inconclusive | Verdict::Untestable => 1,
        Verdict::Equivalent => 2,
        Verdict::Supported => 3,
    }
}

/// `18/20` seeds converged of `method` on `task`.
fn converged(verdicts: &Verdicts, task: &str, method: &str) -> String {
    let seeds = outcomes(&verdicts.scores, task, method);
    let hits = seeds
        .iter()
        .filter(|(_, o)| *o == RunOutcome::Converged)
        .count();
    format!("{hits}/{}", seeds.len())
}

/// Mean environment steps per run of `method` on `task`, in thousands (`599 k`).
fn env_steps(verdicts: &Verdicts, task: &str, method: &str) -> Option<String> {
    verdicts
        .overviews
        .iter()
        .find(|o| o.task == task && o.method == method)
        .map(|o| format!("{} k", format_fixed(o.env_steps_total / 1000.0, 0)))
}

/// The answer paragraph of one task, or `None` when the paper's EA-MADM has no verdict there.
pub(crate) fn task_answer(
    context: &ReportContext,
    verdicts: &Verdicts,
    task: &str,
) -> Option<String> {
    let ea = verdicts.paper_ea_madm(task)?;
    let judgements: Vec<_> = verdicts
        .judgements
        .iter()
        .filter(|j| j.task == task && j.method == ea)
        .collect();
    if judgements.is_empty() {
        return None;
    }
    let mut text = format!("**{}.** ", context.task_title(task));

    // The verdicts against the paper's competitors, with the deciding number of a supported or
    // contradicted one.
    let verdict_words: Vec<String> = judgements
        .iter()
        .map(|j| match j.verdict {
            Verdict::Supported | Verdict::Contradicted => format!(
                "{} {} ({})",
                j.claim.id,
                j.verdict.name(),
                deciding_number(j)
            ),
            _ => format!("{} {}", j.claim.id, j.verdict.name()),
        })
        .collect();
    let _ = write!(
        text,
        "Against the paper's competitors EA-MADM's verdicts are {}.",
        list(&verdict_words)
    );

    // How the seeds ended.
    let competitors: Vec<&str> = claims::methods(&verdicts.scores, task)
        .into_iter()
        .filter(|&(_, role, kind)| claims::is_competitor(role, kind))
        .map(|(m, _, _)| m)
        .collect();
    let converged_words: Vec<String> = std::iter::once(ea)
        .chain(competitors.iter().copied())
        .map(|m| format!("{} {}", method_title(m), converged(verdicts, task, m)))
        .collect();
    let _ = write!(
        text,
        " Seeds converged (greedy policy after training reaches the target): {}.",
        list(&converged_words)
    );
    let collapsed = super::strongest::collapsed_seeds(&verdicts.scores, task, ea);
    if !collapsed.is_empty() {
        let seeds = outcomes(&verdicts.scores, task, ea).len();
        let _ = write!(
            text,
            " EA-MADM collapsed on {} (seed, then the episode from which it never reached \
             again: {}){}.",
            if collapsed.len() == 1 {
                "1 seed".to_owned()
            } else {
                format!("{} seeds", collapsed.len())
            },
            collapsed_list(&verdicts.scores, task, ea),
            // The IQM trims a quarter of the seeds from each end.
            if 4 * collapsed.len() <= seeds {
                ", few enough for the IQM to trim away"
            } else {
                ""
            }
        );
        // Whether the collapses alone keep a verdict from a better one.
        let again: Vec<_> = verdicts
            .without_collapses
            .iter()
            .filter(|j| j.task == task && j.method == ea)
            .collect();
        let better: Vec<String> = again
            .iter()
            .filter_map(|j| {
                let before = judgements.iter().find(|b| b.claim.id == j.claim.id)?;
                (rank(j.verdict) > rank(before.verdict))
                    .then(|| format!("{} {}", j.claim.id, j.verdict.name()))
            })
            .collect();
        let same: Vec<String> = again
            .iter()
            .filter(|j| {
                judgements
                    .iter()
                    .any(|b| b.claim.id == j.claim.id && rank(j.verdict) <= rank(b.verdict))
            })
            .map(|j| j.claim.id.to_owned())
            .collect();
        if !better.is_empty() {
            let _ = write!(
                text,
                " Judged again without those seeds (left out of every method, so still \
                 paired) the verdicts would be {}: the collapses are what keep them there.",
                list(&better)
            );
        }
        if !same.is_empty() {
            let _ = write!(
                text,
                " Without those seeds {} would not improve, so the collapses do not decide \
                 {}.",
                list(&same),
                if same.len() == 1 { "it" } else { "them" }
            );
        }
    }

    // Paired with the sub-task alone: the same pre-trained learner without the MADM step.
    if claims::methods(&verdicts.scores, task)
        .iter()
        .any(|(m, _, _)| *m == SUBTASK_ALONE)
    {
        let d = discordant(&verdicts.scores, task, ea, SUBTASK_ALONE);
        let reverse = if d.only_method == 0 {
            "never the reverse".to_owned()
        } else {
            format!("the reverse on {}", d.only_method)
        };
        let _ = write!(
            text,
            " Paired by seed with `{SUBTASK_ALONE}` (its pre-trained sub-task acting alone), \
             EA-MADM fails to converge on {} of {} seeds where the sub-task alone converges \
             ({} of them collapsed), {reverse}.",
            d.only_versus, d.paired, d.method_collapsed
        );
    }

    // The strongest control, grouped by control.
    let mut by_control: Vec<(&str, Vec<&super::ControlVerdict>)> = Vec::new();
    for c in verdicts
        .against_strongest
        .iter()
        .filter(|c| c.judgement.task == task && c.judgement.method == ea)
    {
        match by_control.iter_mut().find(|(name, _)| *name == c.control) {
            Some((_, group)) => group.push(c),
            None => by_control.push((c.control.as_str(), vec![c])),
        }
    }
    for (control, group) in by_control {
        let claims_of: Vec<String> = group
            .iter()
            .map(|c| c.judgement.claim.id.to_owned())
            .collect();
        let first = group[0];
        let own_iqm = verdicts
            .estimate(task, ea, first.metric)
            .and_then(|e| e.iqm.as_ref())
            .map_or_else(
                || "none (no seed has a value)".to_owned(),
                |i| number(i.estimate),
            );
        let steps = match (
            env_steps(verdicts, task, control),
            env_steps(verdicts, task, ea),
        ) {
            (Some(theirs), Some(ours)) => {
                format!(", {theirs} environment steps per run against {ours}")
            }
            _ => String::new(),
        };
        let against: Vec<String> = group
            .iter()
            .map(|c| format!("{} {}", c.judgement.claim.id, c.judgement.verdict.name()))
            .collect();
        let _ = write!(
            text,
            " The strongest control on {} is `{control}` ({}): IQM `{}` {} against EA-MADM's \
             {own_iqm}, converged on {} seeds against {}{steps}; judged against it by the same \
             rule, EA-MADM's verdicts are {}.",
            list(&claims_of),
            control_family(control).unwrap_or("control"),
            first.metric,
            number(first.control_iqm),
            converged(verdicts, task, control),
            converged(verdicts, task, ea),
            list(&against)
        );
        let converged_count = |method: &str| {
            outcomes(&verdicts.scores, task, method)
                .iter()
                .filter(|(_, o)| *o == RunOutcome::Converged)
                .count()
        };
        if converged_count(control) < converged_count(ea) {
            let _ = write!(
                text,
                " It converges on fewer seeds than EA-MADM, so its better `{}` does not come \
                 from reaching the target better.",
                first.metric
            );
        }
        let overturned: Vec<String> = group
            .iter()
            .filter(|c| {
                judgements.iter().any(|b| {
                    b.claim.id == c.judgement.claim.id
                        && rank(c.judgement.verdict) < rank(b.verdict)
                })
            })
            .map(|c| c.judgement.claim.id.to_owned())
            .collect();
        if !overturned.is_empty() {
            let _ = write!(
                text,
                " So on {} the verdict against the paper's competitors does not hold against \
                 a {} control.",
                list(&overturned),
                control_family(control).unwrap_or("")
            );
        }
    }

    // The readings of the paper, when the sensitivity runs were made.
    let readings: Vec<_> = verdicts
        .survives_readings
        .iter()
        .filter(|s| s.task == task)
        .collect();
    if !readings.is_empty() {
        let holds: Vec<String> = readings
            .iter()
            .filter(|s| s.holds)
            .map(|s| s.claim.clone())
            .collect();
        let flips: Vec<String> = readings
            .iter()
            .filter(|s| !s.holds)
            .map(|s| s.claim.clone())
            .collect();
        let mut parts = Vec::new();
        if !holds.is_empty() {
            parts.push(format!("{} survive every reading", list(&holds)));
        }
        if !flips.is_empty() {
            parts.push(format!("{} flip under some reading", list(&flips)));
        }
        let _ = write!(
            text,
            " Under the other readings of the paper {}.",
            list(&parts)
        );
    }
    Some(text)
}

/// The answer: a paragraph per task of the run on which the paper's EA-MADM has verdicts;
/// `None` when it has none (a config of one's own).
pub(crate) fn answer(context: &ReportContext, verdicts: &Verdicts) -> Option<String> {
    let paragraphs: Vec<String> = claims::tasks(&verdicts.scores)
        .into_iter()
        .filter_map(|task| task_answer(context, verdicts, task))
        .collect();
    (!paragraphs.is_empty()).then(|| paragraphs.join("\n\n"))
}

/// The README's answer: the paragraphs under `REPORT.md`'s answer heading, up to the verdicts.
pub fn readme_answer(report: &str) -> Result<String, String> {
    let after = report
        .split_once(&format!("{ANSWER_HEADING}\n\n"))
        .map(|(_, rest)| rest)
        .ok_or_else(|| format!("REPORT.md has no `{ANSWER_HEADING}` section"))?;
    let end = after.find(VERDICTS_HEADING).unwrap_or(after.len());
    Ok(after[..end].trim_end().to_owned())
}

#[cfg(test)]
mod tests {
    use super::super::tests::{context, options, row};
    use super::super::{SurvivesReadings, render};
    use super::*;
    use crate::Role;
    use crate::scores::FinalScore;

    /// Task I, 8 seeds: EA-MADM at `ea` steps, collapsing on the seeds in `collapses`; two
    /// competitors at 100 + seed; `subtask0-alone` converging on every seed; a reward-matched
    /// control at `shaped` steps.
    fn scores(ea: f64, collapses: &[u64], shaped: f64, alone_fails: &[u64]) -> Vec<FinalScore> {
        let mut rows = Vec::new();
        for seed in 0..8 {
            let noise = seed as f64;
            let mut r = row("task1", "ea-madm", Role::Paper, "ea_madm", seed, ea + noise);
            if collapses.contains(&seed) {
                r.outcome = RunOutcome::Collapsed;
                r.collapse_episode = Some(60 + seed);
                r.greedy_reached = false;
                r.final_steps = 2000.0;
                r.final_return = -2000.0;
            }
            rows.push(r);
        }
        for (method, kind, role, base) in [
            ("epsilon-greedy", "epsilon_greedy", Role::Paper, 100.0),
            ("softmax", "softmax", Role::Paper, 100.0),
            ("subtask0-alone", "subtask_greedy", Role::Control, ea),
            ("softmax-shaped", "softmax", Role::Control, shaped),
        ] {
            for seed in 0..8 {
                let mut r = row("task1", method, role, kind, seed, base + seed as f64);
                if method == "subtask0-alone" && alone_fails.contains(&seed) {
                    r.outcome = RunOutcome::NeverReached;
                }
                rows.push(r);
            }
        }
        rows
    }

    fn last_cell(line: &str) -> &str {
        line.trim_end()
            .trim_end_matches('|')
            .rsplit('|')
            .next()
            .unwrap()
            .trim()
    }

    fn answer_of(scores: Vec<FinalScore>, survives: Vec<SurvivesReadings>) -> String {
        let mut verdicts = Verdicts::compute(scores, &options()).unwrap();
        verdicts.survives_readings = survives;
        answer(&context(), &verdicts).unwrap()
    }

    #[test]
    fn the_answer_states_verdicts_outcomes_and_the_sub_task_pairing() {
        let text = answer_of(scores(60.0, &[], 50.0, &[]), Vec::new());
        assert!(
            text.starts_with(
                "**Task I.** Against the paper's competitors EA-MADM's verdicts are C1 supported \
                 (vs "
            ),
            "{text}"
        );
        assert!(
            text.contains(
                " Seeds converged (greedy policy after training reaches the target): EA-MADM \
                 8/8, ε-greedy 8/8 and softmax 8/8."
            ),
            "{text}"
        );
        assert!(!text.contains("collapsed on"), "{text}");
        assert!(
            text.contains(
                "EA-MADM fails to converge on 0 of 8 seeds where the sub-task alone converges \
                 (0 of them collapsed), never the reverse."
            ),
            "{text}"
        );
        // The sub-task alone fails where EA-MADM converges: the reverse is counted.
        let text = answer_of(scores(60.0, &[], 50.0, &[1, 2]), Vec::new());
        assert!(
            text.contains("(0 of them collapsed), the reverse on 2."),
            "{text}"
        );
    }

    #[test]
    fn collapsed_seeds_are_named_with_their_episode_and_rejudged_without_them() {
        let text = answer_of(scores(100.0, &[3, 5], 200.0, &[]), Vec::new());
        assert!(
            text.contains(
                " EA-MADM collapsed on 2 seeds (seed, then the episode from which it never \
                 reached again: 3 (ep. 63), 5 (ep. 65)), few enough for the IQM to trim away."
            ),
            "{text}"
        );
        assert!(
            text.contains("EA-MADM fails to converge on 2 of 8 seeds where the sub-task alone converges (2 of them collapsed)"),
            "{text}"
        );
        assert!(
            text.contains(
                "Seeds converged (greedy policy after training reaches the target): EA-MADM 6/8"
            ),
            "{text}"
        );
        // EA-MADM equals the competitors but for the collapsed seeds: without them C1 and C2
        // are equivalent (within the 2-step and 2-reward margins).
        assert!(
            text.contains(
                " Judged again without those seeds (left out of every method, so still paired) \
                 the verdicts would be C1 equivalent and C2 equivalent: the collapses are what \
                 keep them there."
            ),
            "{text}"
        );
        // More than a quarter of the seeds: the IQM no longer trims them all.
        let text = answer_of(scores(100.0, &[1, 3, 5], 200.0, &[]), Vec::new());
        assert!(text.contains("3 (ep. 63), 5 (ep. 65))."), "{text}");
    }

    #[test]
    fn the_strongest_control_can_overturn_a_verdict() {
        // The reward-matched control is far better than EA-MADM, which beats the competitors.
        let text = answer_of(scores(60.0, &[], 10.0, &[]), Vec::new());
        assert!(
            text.contains(" The strongest control on C1, C2 and C3 is `softmax-shaped` (reward-matched): IQM `final_steps` 13.5 against EA-MADM's 63.5"),
            "{text}"
        );
        assert!(
            text.contains("EA-MADM's verdicts are C1 contradicted"),
            "{text}"
        );
        assert!(
            text.contains("So on C1, C2 and C3 the verdict against the paper's competitors does not hold against a reward-matched control."),
            "{text}"
        );
        assert!(!text.contains("does not come from reaching"), "{text}");
        // A control that converges on fewer seeds cannot owe its better metric to reaching.
        let mut rows = scores(60.0, &[], 10.0, &[]);
        for r in rows
            .iter_mut()
            .filter(|r| r.method == "softmax-shaped" && r.seed < 4)
        {
            r.outcome = RunOutcome::NeverReached;
        }
        let text = answer_of(rows, Vec::new());
        assert!(
            text.contains(
                " It converges on fewer seeds than EA-MADM, so its better `final_steps` does not \
                 come from reaching the target better."
            ),
            "{text}"
        );
        // Controls worse than EA-MADM overturn nothing.
        let mut rows = scores(60.0, &[], 150.0, &[]);
        for r in rows.iter_mut().filter(|r| r.method == "subtask0-alone") {
            *r = row(
                "task1",
                "subtask0-alone",
                Role::Control,
                "subtask_greedy",
                r.seed,
                140.0,
            );
        }
        let text = answer_of(rows, Vec::new());
        assert!(text.contains("The strongest control on C1, C2 and C3 is `subtask0-alone` (sub-task alone): IQM `final_steps` 140 against"), "{text}");
        assert!(
            text.contains(
                "judged against it by the same rule, EA-MADM's verdicts are C1 supported"
            ),
            "{text}"
        );
        assert!(!text.contains("does not hold against"), "{text}");
    }

    #[test]
    fn the_readings_are_stated_only_when_run_and_the_table_says_not_run() {
        let text = answer_of(scores(60.0, &[], 150.0, &[]), Vec::new());
        assert!(!text.contains("readings"), "{text}");
        let survives = vec![
            SurvivesReadings {
                claim: "C1".to_owned(),
                task: "task1".to_owned(),
                holds: true,
            },
            SurvivesReadings {
                claim: "C2".to_owned(),
                task: "task1".to_owned(),
                holds: false,
            },
        ];
        let text = answer_of(scores(60.0, &[], 150.0, &[]), survives.clone());
        assert!(
            text.ends_with(
                " Under the other readings of the paper C1 survive every reading and C2 flip \
                 under some reading."
            ),
            "{text}"
        );
        let mut verdicts = Verdicts::compute(scores(60.0, &[], 150.0, &[]), &options()).unwrap();
        let report = render(&context(), &verdicts).unwrap();
        let c1 = report.lines().find(|l| l.starts_with("| C1 ")).unwrap();
        assert_eq!(last_cell(c1), "not run", "{c1}");
        verdicts.survives_readings = survives;
        let report = render(&context(), &verdicts).unwrap();
        let c1 = report.lines().find(|l| l.starts_with("| C1 ")).unwrap();
        let c2 = report.lines().find(|l| l.starts_with("| C2 ")).unwrap();
        assert_eq!(last_cell(c1), "yes", "{c1}");
        assert_eq!(last_cell(c2), "no", "{c2}");
    }
}
