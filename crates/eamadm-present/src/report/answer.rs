//! The answer on top of `REPORT.md` (and in the README): per task at most three sentences that
//! answer "does EA-MADM beat its competitors, and why?", every sentence chosen by the numbers:
//! the verdicts against the paper's competitors with the seeds each converges on; the strongest
//! control (which can overturn a verdict, and shows when the sub-task alone does as well) and the
//! readings of the paper; and EA-MADM's characteristic failure — its collapsed seeds, and whether
//! they decide a verdict, or why it never reaches the target. The details behind each sentence
//! (per-method counts, the paired count with the sub-task alone, the strongest control's numbers)
//! stand in the task's own section.

use std::fmt::Write as _;

use super::format::list;
use super::outcomes::outcomes;
use super::verdicts::VERDICTS_HEADING;
use super::{ControlVerdict, ReportContext, Verdicts};
use eamadm_eval::claims::{self, Judgement, Verdict};
use eamadm_eval::scores::RunOutcome;
use eamadm_eval::sensitivity::Change;
use eamadm_eval::verdicts::control_family;

/// The heading of the answer in `REPORT.md`.
pub(crate) const ANSWER_HEADING: &str = "## The answer";

/// How good a verdict is for EA-MADM, to tell whether another comparison overturns it.
pub(crate) fn rank(verdict: Verdict) -> u8 {
    match verdict {
        Verdict::Contradicted => 0,
        Verdict::Inconclusive | Verdict::Untestable => 1,
        Verdict::Equivalent => 2,
        Verdict::Supported => 3,
    }
}

/// Seeds of `method` on `task` that converged, and the seeds it ran.
pub(crate) fn converged_count(verdicts: &Verdicts, task: &str, method: &str) -> (usize, usize) {
    let seeds = outcomes(&verdicts.scores, task, method);
    let hits = seeds
        .iter()
        .filter(|(_, o)| *o == RunOutcome::Converged)
        .count();
    (hits, seeds.len())
}

/// `18/20` seeds converged of `method` on `task`.
pub(crate) fn converged(verdicts: &Verdicts, task: &str, method: &str) -> String {
    let (hits, seeds) = converged_count(verdicts, task, method);
    format!("{hits}/{seeds}")
}

/// `C1, C2 and C3 are inconclusive` / `C1 is supported and C2 inconclusive`: claims grouped by
/// verdict, in order of first appearance.
fn verdict_groups(items: &[(&str, Verdict)]) -> String {
    let mut groups: Vec<(Verdict, Vec<String>)> = Vec::new();
    for &(claim, verdict) in items {
        match groups.iter_mut().find(|(v, _)| *v == verdict) {
            Some((_, claims)) => claims.push(claim.to_owned()),
            None => groups.push((verdict, vec![claim.to_owned()])),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .enumerate()
        .map(|(i, (verdict, claims))| match i {
            0 => format!(
                "{} {} {}",
                list(claims),
                if claims.len() == 1 { "is" } else { "are" },
                verdict.name()
            ),
            _ => format!("{} {}", list(claims), verdict.name()),
        })
        .collect();
    list(&parts)
}

/// What the verdicts against the paper's competitors say, as a verb phrase.
fn overall(verdicts: &[Verdict]) -> &'static str {
    let supported = verdicts
        .iter()
        .filter(|v| **v == Verdict::Supported)
        .count();
    let contradicted = verdicts.contains(&Verdict::Contradicted);
    match (supported, contradicted) {
        (n, false) if n == verdicts.len() => "beats",
        (0, true) => "loses to",
        (0, false) => "does not beat",
        (_, true) => "has mixed verdicts against",
        (_, false) => "partly beats",
    }
}

/// The first sentence: the verdicts against the paper's competitors and the seeds converged.
fn verdict_sentence(
    verdicts: &Verdicts,
    task: &str,
    ea: &str,
    judgements: &[&Judgement],
) -> String {
    let items: Vec<(&str, Verdict)> = judgements.iter().map(|j| (j.claim.id, j.verdict)).collect();
    let kinds: Vec<Verdict> = items.iter().map(|(_, v)| *v).collect();
    let competitors: Vec<(usize, usize)> = claims::methods(&verdicts.scores, task)
        .into_iter()
        .filter(|&(_, role, kind)| claims::is_competitor(role, kind))
        .map(|(m, _, _)| converged_count(verdicts, task, m))
        .collect();
    let theirs = match (
        competitors.iter().map(|c| c.0).min(),
        competitors.iter().map(|c| c.0).max(),
        competitors.iter().map(|c| c.1).max(),
    ) {
        (Some(low), Some(high), Some(seeds)) if low == high => {
            format!(", each competitor on {low}/{seeds}")
        }
        (Some(low), Some(high), Some(seeds)) => {
            format!(", the competitors on {low}–{high}/{seeds}")
        }
        _ => String::new(),
    };
    format!(
        "EA-MADM {} the paper's competitors: {}; it converges on {} seeds{theirs}.",
        overall(&kinds),
        verdict_groups(&items),
        converged(verdicts, task, ea)
    )
}

/// The second sentence: EA-MADM judged against the strongest control of each claim (grouped
/// by control and verdict; a control that overturns a verdict with the seeds it converges on),
/// whether the sub-task alone does as well, and the readings of the paper.
fn control_sentence(
    verdicts: &Verdicts,
    task: &str,
    ea: &str,
    judgements: &[&Judgement],
) -> Option<String> {
    let against: Vec<&ControlVerdict> = verdicts
        .against_strongest
        .iter()
        .filter(|c| c.judgement.task == task && c.judgement.method == ea)
        .collect();
    let overturns = |c: &ControlVerdict| {
        judgements.iter().any(|b| {
            b.claim.id == c.judgement.claim.id && rank(c.judgement.verdict) < rank(b.verdict)
        })
    };
    // Groups of (control, verdict against it, whether it overturns one of them) in order of
    // first appearance.
    let mut groups: Vec<(&str, Verdict, bool, Vec<String>)> = Vec::new();
    for c in &against {
        let claim = c.judgement.claim.id.to_owned();
        match groups.iter_mut().find(|(control, verdict, _, _)| {
            *control == c.control && *verdict == c.judgement.verdict
        }) {
            Some((_, _, over, claims)) => {
                *over |= overturns(c);
                claims.push(claim);
            }
            None => groups.push((&c.control, c.judgement.verdict, overturns(c), vec![claim])),
        }
    }
    let mut parts: Vec<String> = groups
        .iter()
        .enumerate()
        .map(|(i, (control, verdict, over, claims))| {
            // A verdict repeated from the group before goes without saying.
            let repeated = i > 0 && groups.get(i - 1).is_some_and(|g| g.1 == *verdict);
            format!(
                "{}on {} (`{control}`, {}{})",
                if repeated {
                    String::new()
                } else {
                    format!("{} ", verdict.name())
                },
                list(claims),
                control_family(control).unwrap_or("control"),
                if *over {
                    format!(", converging on {}", converged(verdicts, task, control))
                } else {
                    String::new()
                }
            )
        })
        .collect();
    let mut sentence = String::new();
    if !parts.is_empty() {
        let any_overturned = groups.iter().any(|g| g.2);
        let _ = write!(
            sentence,
            "{}gainst the strongest control it is {}",
            if any_overturned { "But a" } else { "A" },
            list(&std::mem::take(&mut parts))
        );
        // The sub-task alone is EA-MADM without the MADM step: where EA-MADM does not beat
        // it, the aggregation adds nothing the verdicts can see.
        let alone = |better: bool| -> Vec<String> {
            groups
                .iter()
                .filter(|(control, verdict, _, _)| {
                    control_family(control) == Some("sub-task alone")
                        && *verdict != Verdict::Supported
                        && (*verdict == Verdict::Contradicted) == better
                })
                .flat_map(|(_, _, _, claims)| claims.iter().cloned())
                .collect()
        };
        let (better, not_worse) = (alone(true), alone(false));
        if !better.is_empty() {
            let _ = write!(
                sentence,
                ": without the MADM step its sub-task alone is better on {}",
                list(&better)
            );
        }
        if !not_worse.is_empty() {
            let _ = write!(
                sentence,
                "{} without the MADM step its sub-task alone is not shown worse on {}",
                if better.is_empty() { ":" } else { ", and" },
                list(&not_worse)
            );
        }
    }
    if let Some(readings) = readings_clause(verdicts, task) {
        if sentence.is_empty() {
            let mut chars = readings.chars();
            if let Some(first) = chars.next() {
                sentence = first.to_uppercase().chain(chars).collect();
            }
        } else {
            let _ = write!(sentence, "; {readings}");
        }
    }
    (!sentence.is_empty()).then(|| format!("{sentence}."))
}

/// Which verdicts of `task` survive every reading of the paper the sensitivity runs tried,
/// and which flip under which reading; `None` when none was run.
fn readings_clause(verdicts: &Verdicts, task: &str) -> Option<String> {
    let survives: Vec<_> = verdicts
        .survives_readings
        .iter()
        .filter(|s| s.task == task)
        .collect();
    if survives.is_empty() {
        return None;
    }
    let holds: Vec<String> = survives
        .iter()
        .filter(|s| s.holds)
        .map(|s| s.claim.clone())
        .collect();
    let flips: Vec<String> = survives
        .iter()
        .filter(|s| !s.holds)
        .map(|s| s.claim.clone())
        .collect();
    let mut flipping: Vec<String> = Vec::new();
    for row in verdicts
        .sensitivity
        .iter()
        .filter(|r| r.task == task && r.change == Change::Flips)
    {
        let name = format!("`{}`", row.reading);
        if !flipping.contains(&name) {
            flipping.push(name);
        }
    }
    let mut parts = Vec::new();
    if flips.is_empty() {
        return Some("every verdict survives the other readings of the paper".to_owned());
    }
    if !holds.is_empty() {
        parts.push(format!(
            "{} {} every reading of the paper",
            list(&holds),
            if holds.len() == 1 {
                "survives"
            } else {
                "survive"
            }
        ));
    }
    if !flips.is_empty() {
        parts.push(format!(
            "{} under {}",
            if holds.is_empty() {
                "every verdict flips".to_owned()
            } else {
                format!(
                    "{} {}",
                    list(&flips),
                    if flips.len() == 1 { "flips" } else { "flip" }
                )
            },
            if flipping.is_empty() {
                "some reading of the paper".to_owned()
            } else {
                format!(
                    "the reading{} {}",
                    if flipping.len() == 1 { "" } else { "s" },
                    list(&flipping)
                )
            }
        ));
    }
    Some(list(&parts))
}

/// The third sentence: EA-MADM's characteristic failure. Its collapsed seeds, and whether they
/// alone keep a verdict from a better one (judged again without them); or, when it never
/// reaches the target, why (the robot's reward diagnosis).
fn failure_sentence(
    context: &ReportContext,
    verdicts: &Verdicts,
    task: &str,
    ea: &str,
    judgements: &[&Judgement],
) -> Option<String> {
    let collapsed = eamadm_eval::verdicts::collapsed_seeds(&verdicts.scores, task, ea);
    if collapsed.is_empty() {
        let never = outcomes(&verdicts.scores, task, ea)
            .iter()
            .all(|(_, o)| *o == RunOutcome::NeverReached);
        let experiment = context.experiments.iter().find(|e| e.name == task)?;
        return never
            .then(|| super::robot::why_never_short(experiment, ea))
            .flatten();
    }
    let seeds = outcomes(&verdicts.scores, task, ea).len();
    let names: Vec<String> = collapsed.iter().map(|(seed, _)| seed.to_string()).collect();
    let episodes: Vec<u64> = collapsed.iter().filter_map(|(_, e)| *e).collect();
    let from = match (episodes.iter().min(), episodes.iter().max()) {
        (Some(low), Some(high)) if low == high => {
            format!("; never reaching again after episode {low}")
        }
        (Some(low), Some(high)) => {
            format!("; never reaching again after episodes {low}–{high}")
        }
        _ => String::new(),
    };
    let mut sentence = format!(
        "It collapsed on {} of {seeds} seeds ({}{from})",
        collapsed.len(),
        names.join(", ")
    );
    let again: Vec<&Judgement> = verdicts
        .without_collapses
        .iter()
        .filter(|j| j.task == task && j.method == ea)
        .collect();
    let before = |j: &Judgement| judgements.iter().find(|b| b.claim.id == j.claim.id);
    let better: Vec<(&str, Verdict)> = again
        .iter()
        .filter(|j| before(j).is_some_and(|b| rank(j.verdict) > rank(b.verdict)))
        .map(|j| (j.claim.id, j.verdict))
        .collect();
    let same: Vec<String> = again
        .iter()
        .filter(|j| before(j).is_some_and(|b| rank(j.verdict) <= rank(b.verdict)))
        .map(|j| j.claim.id.to_owned())
        .collect();
    if !better.is_empty() {
        let _ = write!(
            sentence,
            "; without those seeds {}, so the collapses decide {}",
            verdict_groups(&better),
            if better.len() == 1 { "it" } else { "them" }
        );
    }
    if !same.is_empty() {
        let _ = if better.is_empty() && same.len() == judgements.len() {
            write!(sentence, ", which alone decide no verdict")
        } else {
            write!(
                sentence,
                "{} the collapses alone do not decide {}",
                if better.is_empty() { ";" } else { ", while" },
                list(&same)
            )
        };
    }
    Some(format!("{sentence}."))
}

/// The answer paragraph of one task, or `None` when the paper's EA-MADM has no verdict there.
pub(crate) fn task_answer(
    context: &ReportContext,
    verdicts: &Verdicts,
    task: &str,
) -> Option<String> {
    let ea = verdicts.paper_ea_madm(task)?;
    let judgements: Vec<&Judgement> = verdicts
        .judgements
        .iter()
        .filter(|j| j.task == task && j.method == ea)
        .collect();
    if judgements.is_empty() {
        return None;
    }
    let mut sentences = vec![verdict_sentence(verdicts, task, ea, &judgements)];
    sentences.extend(control_sentence(verdicts, task, ea, &judgements));
    sentences.extend(failure_sentence(context, verdicts, task, ea, &judgements));
    Some(format!(
        "**{}.** {}",
        context.task_title(task),
        sentences.join(" ")
    ))
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
    use super::super::outcomes::{collapses_rejudged, subtask_pairing};
    use super::super::strongest::strongest_sentences;
    use super::super::tests::{context, options, row};
    use super::super::{SurvivesReadings, render};
    use super::*;
    use eamadm_eval::Role;
    use eamadm_eval::scores::FinalScore;

    /// Task I, 8 seeds: EA-MADM at `ea` steps, collapsing on the seeds in `collapses`; two
    /// competitors at 100 + seed; `subtask0-alone` at EA-MADM's steps, converging on every
    /// seed but `alone_fails`; a reward-matched control at `shaped` steps.
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

    fn verdicts_of(scores: Vec<FinalScore>, survives: Vec<SurvivesReadings>) -> Verdicts {
        let mut verdicts = Verdicts::compute(scores, &options()).unwrap();
        verdicts.survives_readings = survives;
        verdicts
    }

    fn answer_of(scores: Vec<FinalScore>, survives: Vec<SurvivesReadings>) -> String {
        answer(&context(), &verdicts_of(scores, survives)).unwrap()
    }

    /// Sentences of a paragraph (a full stop followed by a space or the end).
    fn sentences(text: &str) -> usize {
        text.matches(". ").count() + usize::from(text.ends_with('.'))
    }

    #[test]
    fn claims_are_grouped_by_verdict_and_the_overall_word_follows_them() {
        assert_eq!(
            verdict_groups(&[
                ("C1", Verdict::Supported),
                ("C2", Verdict::Inconclusive),
                ("C3", Verdict::Supported),
            ]),
            "C1 and C3 are supported and C2 inconclusive"
        );
        assert_eq!(
            verdict_groups(&[("C4", Verdict::Contradicted)]),
            "C4 is contradicted"
        );
        use Verdict::{Contradicted, Equivalent, Inconclusive, Supported};
        assert_eq!(overall(&[Supported, Supported]), "beats");
        assert_eq!(overall(&[Supported, Inconclusive]), "partly beats");
        assert_eq!(
            overall(&[Supported, Contradicted]),
            "has mixed verdicts against"
        );
        assert_eq!(overall(&[Inconclusive, Contradicted]), "loses to");
        assert_eq!(overall(&[Inconclusive, Equivalent]), "does not beat");
    }

    #[test]
    fn the_answer_is_short_and_states_verdicts_and_converged_seeds() {
        let text = answer_of(scores(60.0, &[], 50.0, &[]), Vec::new());
        assert!(
            text.starts_with(
                "**Task I.** EA-MADM beats the paper's competitors: C1, C2 and C3 are \
                 supported; it converges on 8/8 seeds, each competitor on 8/8."
            ),
            "{text}"
        );
        assert!(!text.contains("collapsed on"), "{text}");
        // The details stand in the task's section, not in the answer.
        assert!(!text.contains("Paired by seed"), "{text}");
        assert!(!text.contains("environment steps"), "{text}");
        assert!(sentences(&text) <= 3, "{text}");
        // Competitors that converge on different counts are given as a range.
        let mut rows = scores(60.0, &[], 50.0, &[]);
        for r in rows
            .iter_mut()
            .filter(|r| r.method == "softmax" && r.seed < 3)
        {
            r.outcome = RunOutcome::NeverReached;
        }
        let text = answer_of(rows, Vec::new());
        assert!(text.contains(", the competitors on 5–8/8."), "{text}");
    }

    #[test]
    fn collapsed_seeds_are_named_and_said_whether_they_decide() {
        let text = answer_of(scores(100.0, &[3, 5], 200.0, &[]), Vec::new());
        // EA-MADM equals the competitors but for the collapsed seeds: without them C1 and C2
        // are equivalent (within the 2-step and 2-reward margins).
        assert!(
            text.contains(
                " It collapsed on 2 of 8 seeds (3, 5; never reaching again after episodes \
                 63–65); without those seeds C1 and C2 are equivalent, so the collapses decide \
                 them."
            ),
            "{text}"
        );
        assert!(text.contains("it converges on 6/8 seeds"), "{text}");
        assert!(sentences(&text) <= 3, "{text}");
        // The re-judgement in full stands in the outcomes section.
        let verdicts = verdicts_of(scores(100.0, &[3, 5], 200.0, &[]), Vec::new());
        let full = collapses_rejudged(&verdicts, "task1", "ea-madm").unwrap();
        assert!(
            full.starts_with(
                "Judged again without EA-MADM's collapsed seeds (left out of every method, \
                 so still paired; a diagnosis, never a verdict): C1 equivalent (was \
                 inconclusive)"
            ),
            "{full}"
        );
        // Collapses that decide every verdict they touch.
        let text = answer_of(scores(60.0, &[3], 200.0, &[]), Vec::new());
        assert!(
            text.contains(
                "It collapsed on 1 of 8 seeds (3; never reaching again after episode 63); \
                 without those seeds C1 and C2 are supported, so the collapses decide them."
            ),
            "{text}"
        );
        // Collapses that decide nothing: EA-MADM loses with or without them.
        let text = answer_of(scores(300.0, &[3], 200.0, &[]), Vec::new());
        assert!(
            text.contains(
                "It collapsed on 1 of 8 seeds (3; never reaching again after episode 63), \
                 which alone decide no verdict."
            ),
            "{text}"
        );
    }

    #[test]
    fn the_sub_task_pairing_says_what_is_true() {
        let paired = |alone_fails: &[u64], collapses: &[u64]| {
            subtask_pairing(
                &scores(60.0, collapses, 50.0, alone_fails),
                "task1",
                "ea-madm",
            )
            .unwrap()
        };
        assert_eq!(
            paired(&[], &[]),
            "EA-MADM and `subtask0-alone` (its pre-trained sub-task acting alone) converge on \
             the same 8 of 8 paired seeds."
        );
        assert_eq!(
            paired(&[1, 2], &[]),
            "Paired by seed with `subtask0-alone` (its pre-trained sub-task acting alone), \
             EA-MADM fails to converge on 0 of 8 seeds where the sub-task alone converges (0 \
             of them collapsed), the reverse on 2."
        );
        assert!(paired(&[], &[3, 5]).contains(
            "EA-MADM fails to converge on 2 of 8 seeds where the sub-task alone converges \
                 (2 of them collapsed), never the reverse."
        ));
        // Nobody converges: neither, never "fails on 0 … never the reverse".
        let mut rows = scores(60.0, &[], 50.0, &[]);
        for r in rows
            .iter_mut()
            .filter(|r| r.method == "ea-madm" || r.method == "subtask0-alone")
        {
            r.outcome = RunOutcome::NeverReached;
        }
        assert_eq!(
            subtask_pairing(&rows, "task1", "ea-madm").unwrap(),
            "Neither EA-MADM nor `subtask0-alone` (its pre-trained sub-task acting alone) \
             converges on any of the 8 paired seeds."
        );
        let without: Vec<FinalScore> = rows
            .into_iter()
            .filter(|r| r.method != "subtask0-alone")
            .collect();
        assert_eq!(subtask_pairing(&without, "task1", "ea-madm"), None);
    }

    #[test]
    fn the_strongest_control_can_overturn_a_verdict() {
        // The reward-matched control is far better than EA-MADM, which beats the competitors.
        let text = answer_of(scores(60.0, &[], 10.0, &[]), Vec::new());
        assert!(
            text.contains(
                " But against the strongest control it is contradicted on C1, C2 and C3 \
                 (`softmax-shaped`, reward-matched, converging on 8/8)."
            ),
            "{text}"
        );
        let verdicts = verdicts_of(scores(60.0, &[], 10.0, &[]), Vec::new());
        let details = strongest_sentences(&verdicts, "task1");
        assert_eq!(details.len(), 1, "{details:?}");
        assert!(
            details[0].starts_with(
                "The strongest control on C1, C2 and C3 is `softmax-shaped` (reward-matched): \
                 IQM `final_steps` 13.5 against EA-MADM's 63.5, converged on 8/8 seeds against \
                 8/8"
            ),
            "{details:?}"
        );
        assert!(
            details[0].contains("EA-MADM's verdicts are C1 contradicted (vs "),
            "{details:?}"
        );
        assert!(
            details[0].ends_with(
                "So on C1, C2 and C3 the verdict against the paper's competitors does not hold \
                 against a reward-matched control."
            ),
            "{details:?}"
        );
        assert!(
            !details[0].contains("does not come from reaching"),
            "{details:?}"
        );
        // A control that converges on fewer seeds cannot owe its better metric to reaching.
        let mut rows = scores(60.0, &[], 10.0, &[]);
        for r in rows
            .iter_mut()
            .filter(|r| r.method == "softmax-shaped" && r.seed < 4)
        {
            r.outcome = RunOutcome::NeverReached;
        }
        let details = strongest_sentences(&verdicts_of(rows, Vec::new()), "task1");
        assert!(
            details[0].contains(
                " It converges on fewer seeds than EA-MADM, so its better `final_steps` does \
                 not come from reaching the target better."
            ),
            "{details:?}"
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
        assert!(
            text.contains(
                " Against the strongest control it is supported on C1, C2 and C3 \
                 (`subtask0-alone`, sub-task alone)."
            ),
            "{text}"
        );
        assert!(!text.contains("MADM step"), "{text}");
    }

    #[test]
    fn a_sub_task_alone_as_good_as_ea_madm_is_named_as_the_explanation() {
        // The sub-task alone scores as EA-MADM seed for seed; the shaped control is worse.
        let text = answer_of(scores(60.0, &[], 150.0, &[]), Vec::new());
        assert!(text.contains("(`subtask0-alone`, sub-task alone"), "{text}");
        assert!(
            text.contains(": without the MADM step its sub-task alone is not shown worse on C"),
            "{text}"
        );
    }

    #[test]
    fn an_inconclusive_c3_shows_the_stable_reaching_test_that_decides_it() {
        // Every stable seed has greedy SD 0, so the SD comparisons read 0 [0, 0]; EA-MADM is
        // stable on 4 of 8 seeds, every other method on all 8.
        let mut rows = scores(60.0, &[], 50.0, &[]);
        for r in &mut rows {
            r.fluctuation_greedy_steps = Some(0.0);
            r.fluctuation_greedy_return = Some(0.0);
            if r.method == "ea-madm" && r.seed < 4 {
                r.stable_reaching = Some(false);
                r.fluctuation_greedy_steps = None;
                r.fluctuation_greedy_return = None;
            }
        }
        let verdicts = verdicts_of(rows, Vec::new());
        let c3 = verdicts
            .judgements
            .iter()
            .find(|j| j.claim.id == "C3" && j.method == "ea-madm")
            .unwrap();
        assert_eq!(c3.verdict, Verdict::Inconclusive);
        assert!(
            c3.deciding_comparison()
                .is_some_and(|c| c.difference.estimate == 0.0)
        );
        let deciding = super::super::verdicts::deciding_number(c3);
        assert!(
            deciding.starts_with(
                "EA-MADM reaches in every greedy evaluation of the second half on 4/8 seeds, \
                 ε-greedy on 8/8; exact paired sign test, Holm p 0.250"
            ),
            "{deciding}"
        );
        // Where the column names the competitor, the test goes without the names.
        assert_eq!(
            super::super::verdicts::deciding_words(c3, false),
            "reaches in every greedy evaluation of the second half on 4/8 seeds against 8/8; \
             exact paired sign test, Holm p 0.250"
        );
    }

    #[test]
    fn the_readings_are_stated_only_when_run_and_the_table_says_not_run() {
        let text = answer_of(scores(60.0, &[], 150.0, &[]), Vec::new());
        assert!(!text.contains("reading"), "{text}");
        let holds = |claim: &str, holds: bool| SurvivesReadings {
            claim: claim.to_owned(),
            task: "task1".to_owned(),
            holds,
        };
        let text = answer_of(
            scores(60.0, &[], 150.0, &[]),
            vec![holds("C1", true), holds("C2", true)],
        );
        assert!(
            text.contains("; every verdict survives the other readings of the paper."),
            "{text}"
        );
        let survives = vec![holds("C1", true), holds("C2", false)];
        let text = answer_of(scores(60.0, &[], 150.0, &[]), survives.clone());
        assert!(
            text.contains(
                "; C1 survives every reading of the paper and C2 flips under some reading of \
                 the paper."
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
