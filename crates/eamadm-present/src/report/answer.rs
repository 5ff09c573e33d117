//! The report's first screen: per task the answer to "does EA-MADM beat its competitors, and
//! why?" in a few short sentences (the verdicts with the seeds each side converges on, a
//! control that overturns a verdict, the readings of the paper, the collapses, and the one
//! cause [`findings`](eamadm_eval::findings) names), then every way this reproduction differs
//! from the paper that could change a verdict. Everything is rendered from the findings and
//! the context's facts; the README states the same answer ([`readme_answer`]).
//!
//! The cause is a slot: [`Cause`] holds what the numbers point at, and a new kind of cause
//! (an oracle's ceiling, shaping, pre-training) is a new variant with its sentence here.

use std::fmt::Write as _;

use eamadm_eval::claims::Verdict;
use eamadm_eval::facts::{ControlFamily, DeviationFacts, ReportContext};
use eamadm_eval::findings::{Cause, Collapses, Diagnosis, Findings, TaskFindings};
use eamadm_eval::paper_claims::method_title;

use super::format::list;
use super::words::{self, capitalised, family_clause, overall, verdict_groups};

/// The heading of the answer in `REPORT.md`.
pub(crate) const ANSWER_HEADING: &str = "## The answer";

/// The heading of the list of deviations.
pub(crate) const DEVIATIONS_HEADING: &str = "## How this reproduction differs from the paper";

/// The first sentence: the verdicts against the paper's competitors.
fn verdict_sentence(task: &TaskFindings) -> String {
    let items: Vec<(&str, Verdict)> = task
        .verdicts
        .iter()
        .map(|v| (v.claim.as_str(), v.verdict))
        .collect();
    let kinds: Vec<Verdict> = items.iter().map(|(_, v)| *v).collect();
    let names: Vec<String> = task
        .competitors
        .iter()
        .map(|c| method_title(&c.method))
        .collect();
    let against = if names.is_empty() {
        String::new()
    } else {
        format!(" ({})", list(&names))
    };
    format!(
        "EA-MADM {} the paper's competitors{against}: {}.",
        overall(&kinds),
        verdict_groups(&items)
    )
}

/// The seeds EA-MADM and the competitors converge on.
fn convergence_sentence(task: &TaskFindings) -> String {
    let hits: Vec<usize> = task.competitors.iter().map(|c| c.converged.hits).collect();
    let seeds = task
        .competitors
        .iter()
        .map(|c| c.converged.seeds)
        .max()
        .unwrap_or(task.converged.seeds);
    let theirs = match (hits.iter().min(), hits.iter().max()) {
        (Some(low), Some(high)) if low == high => format!(", each competitor on {low} of {seeds}"),
        (Some(low), Some(high)) => format!(", the competitors on {low} to {high} of {seeds}"),
        _ => String::new(),
    };
    format!(
        "Its greedy policy reaches the target after training on {} of {} seeds{theirs}.",
        task.converged.hits, task.converged.seeds
    )
}

/// A control that overturns a verdict, named with what it is (unless the cause names it).
fn overturn_sentence(task: &TaskFindings) -> Option<String> {
    let named = match &task.cause {
        Some(Cause::MatchedControl { control, .. } | Cause::SubtaskAlone { control, .. }) => {
            Some(control.as_str())
        }
        _ => None,
    };
    let mut groups: Vec<(&str, ControlFamily, Verdict, Vec<String>)> = Vec::new();
    for s in task
        .strongest
        .iter()
        .filter(|s| s.overturns && Some(s.control.as_str()) != named)
    {
        match groups
            .iter_mut()
            .find(|(c, _, v, _)| *c == s.control && *v == s.verdict)
        {
            Some((_, _, _, claims)) => claims.push(s.claim.clone()),
            None => groups.push((&s.control, s.family, s.verdict, vec![s.claim.clone()])),
        }
    }
    if groups.is_empty() {
        return None;
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(control, family, verdict, claims)| {
            format!(
                "against {} (`{control}`), {} {} {}",
                family_clause(*family),
                list(claims),
                if claims.len() == 1 { "is" } else { "are" },
                verdict.name()
            )
        })
        .collect();
    Some(format!("But {}.", list(&parts)))
}

/// Whether the verdicts survive the readings of the paper.
fn readings_sentence(task: &TaskFindings) -> Option<String> {
    let readings = task.readings.as_ref()?;
    if readings.flips.is_empty() {
        let most = readings.holds.iter().map(|(_, n)| *n).max().unwrap_or(0);
        return Some(if most > 0 {
            format!(
                "Every verdict holds under the {most} other readings of the paper tried on \
                 {}.",
                task.title
            )
        } else {
            "Every verdict holds under the other readings of the paper.".to_owned()
        });
    }
    let mut by_readings: Vec<(Vec<String>, Vec<String>)> = Vec::new();
    for (claim, names) in &readings.flips {
        match by_readings.iter_mut().find(|(n, _)| n == names) {
            Some((_, claims)) => claims.push(claim.clone()),
            None => by_readings.push((names.clone(), vec![claim.clone()])),
        }
    }
    let flips: Vec<String> = by_readings
        .iter()
        .map(|(names, claims)| {
            let named: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
            format!(
                "{} {} under {}",
                list(claims),
                if claims.len() == 1 { "flips" } else { "flip" },
                if named.is_empty() {
                    "another reading of the paper".to_owned()
                } else {
                    format!(
                        "the reading{} {}",
                        if named.len() == 1 { "" } else { "s" },
                        list(&named)
                    )
                }
            )
        })
        .collect();
    let holds: Vec<String> = readings.holds.iter().map(|(c, _)| c.clone()).collect();
    let mut sentence = capitalised(&list(&flips));
    if !holds.is_empty() {
        let _ = write!(
            sentence,
            "; {} {} under every reading",
            list(&holds),
            if holds.len() == 1 { "holds" } else { "hold" }
        );
    }
    sentence.push('.');
    Some(sentence)
}

/// The collapsed seeds and whether they decide a verdict.
pub(crate) fn collapse_sentence(collapses: &Collapses) -> String {
    let names: Vec<u64> = collapses.seeds.iter().map(|(seed, _)| *seed).collect();
    let episodes: Vec<u64> = collapses.seeds.iter().filter_map(|(_, e)| *e).collect();
    // A collapse episode is the first episode of the non-reaching tail: the run last reached
    // one episode before it, so "from e on", not "after e" (one episode late).
    let from = match (episodes.iter().min(), episodes.iter().max()) {
        (Some(low), Some(high)) if low == high => format!(" from episode {low} on"),
        (Some(low), Some(high)) => format!(" from episodes {low} to {high} on"),
        _ => String::new(),
    };
    let mut sentence = format!(
        "EA-MADM collapsed on {} of {} seeds ({}): it never reached the target again{from}",
        names.len(),
        collapses.of,
        words::seeds(&names)
    );
    let better: Vec<(&str, Verdict)> = collapses
        .rejudged
        .iter()
        .filter(|r| eamadm_eval::findings::rank(r.now) > eamadm_eval::findings::rank(r.was))
        .map(|r| (r.claim.as_str(), r.now))
        .collect();
    if collapses.rejudged.is_empty() {
        sentence.push('.');
    } else if better.is_empty() {
        sentence.push_str("; judged again without those seeds, no verdict changes.");
    } else {
        let _ = write!(
            sentence,
            "; judged again without those seeds, {}, so the collapses decide {}.",
            verdict_groups(&better),
            if better.len() == 1 { "it" } else { "them" }
        );
    }
    sentence
}

/// How the report names a reading of the robot's sub-task rewards.
pub(crate) fn rewards_name(repairs: &[String]) -> String {
    if repairs.is_empty() {
        "the paper's sub-task rewards (Eq. 6–8)".to_owned()
    } else {
        format!("the sub-task rewards with {}", list(repairs))
    }
}

/// Why a method never reaches, in one sentence.
pub(crate) fn never_reaches_sentence(diagnosis: &Diagnosis) -> String {
    let paying = diagnosis.valuing_reaching();
    if paying == 0 {
        format!(
            "under {} no sub-task's reward values reaching the target above ending the episode \
             at once or idling, so no aggregation of their values leads to the target",
            rewards_name(&diagnosis.repairs)
        )
    } else {
        format!(
            "under {} only {paying} of {} sub-tasks value reaching most, and the aggregation of \
             their values still does not lead to the target",
            rewards_name(&diagnosis.repairs),
            diagnosis.subtasks.len()
        )
    }
}

/// The cause in one sentence, opening with **Why:**.
fn cause_sentence(cause: &Cause) -> String {
    let text = match cause {
        Cause::SubtaskValues {
            reaches,
            follows,
            follows_on,
            optimum_steps,
            manhattan_steps,
        } => {
            let detour = match (optimum_steps, manhattan_steps) {
                (Some(optimum), Some(manhattan)) if optimum > manhattan => format!(
                    " (the shortest path, {optimum} steps, is a detour from the Manhattan \
                     distance {manhattan})"
                ),
                _ => String::new(),
            };
            format!(
                "even with exact sub-task values its decision reaches on {} of {} seeds and is \
                 the same episode as `{follows}` on {} of {}: the sub-tasks carry no route to \
                 the target{detour}, so the decision step has nothing to combine",
                reaches.hits, reaches.seeds, follows_on.hits, follows_on.seeds
            )
        }
        Cause::Pretraining { reach, diagnosis } => {
            let rewards = diagnosis.as_ref().map_or_else(String::new, |d| {
                format!("; besides, {}", never_reaches_sentence(d))
            });
            let converged = reach.converged_seeds.map_or_else(String::new, |c| {
                format!(
                    ", the stopping rule finding it converged on {c} of {}",
                    reach.seeds
                )
            });
            format!(
                "pre-training: its reach sub-task (`{}`) did not reach the target in a mean \
                 of {} pre-training episodes per seed on {} of {} seeds ({} reaching episodes \
                 in all{converged}), so a reward for reaching, such as a repaired reading's \
                 goal bonus, is never paid and neither the aggregation nor the tree has \
                 anything to pass on{rewards}",
                reach.name,
                super::format::number(reach.mean_episodes),
                reach.seeds - reach.seeds_reaching,
                reach.seeds,
                reach.reaching_episodes
            )
        }
        Cause::Ceiling {
            optimum_steps,
            follows,
            follows_on,
            reaches,
        } => format!(
            "a ceiling: the layout is at the Manhattan bound (shortest path {optimum_steps} = \
             Manhattan distance), so the distance-shaped reach sub-task alone is already \
             optimal; with exact sub-task values the decision reaches on {} of {} seeds and is \
             the same episode as `{follows}` on {} of {}: there is nothing for a second \
             attribute to add",
            reaches.hits, reaches.seeds, follows_on.hits, follows_on.seeds
        ),
        Cause::Rewards { diagnosis } => format!(
            "it never reaches the target: {}",
            never_reaches_sentence(diagnosis)
        ),
        Cause::MatchedControl {
            control,
            family,
            claims,
            verdict,
        } => {
            let does = if *verdict == Verdict::Contradicted {
                "does better than EA-MADM"
            } else {
                "is not shown worse than EA-MADM"
            };
            let source = match family {
                ControlFamily::BudgetMatched => "the extra training steps",
                _ => "the shaped sub-task rewards",
            };
            format!(
                "{} (`{control}`) {does} on {}, so EA-MADM's advantage over the competitors \
                 comes from {source}, not from the MADM step",
                capitalised(family_clause(*family)),
                list(claims)
            )
        }
        Cause::SubtaskAlone {
            control,
            claims,
            better,
            end_same,
        } => {
            let does = if *better {
                "does better"
            } else {
                "is not shown worse"
            };
            let same = end_same.map_or_else(String::new, |e| {
                format!(
                    ", and ends exactly as EA-MADM on {} of {} seeds",
                    e.hits, e.seeds
                )
            });
            format!(
                "without the MADM step, its pre-trained sub-task acting alone (`{control}`) \
                 {does} on {}{same}: the sub-task's own experience, not the aggregation, \
                 decides",
                list(claims)
            )
        }
    };
    format!("**Why:** {}.", capitalised(&text))
}

/// The answer paragraph of one task.
pub(crate) fn task_answer(task: &TaskFindings) -> String {
    let mut sentences = vec![verdict_sentence(task), convergence_sentence(task)];
    sentences.extend(overturn_sentence(task));
    sentences.extend(readings_sentence(task));
    sentences.extend(task.collapses.as_ref().map(collapse_sentence));
    sentences.extend(task.cause.as_ref().map(cause_sentence));
    sentences.extend(super::oracle::oracle_sentence(task));
    sentences.extend(
        task.prediction
            .as_ref()
            .map(super::oracle::prediction_sentence),
    );
    format!("**{}.** {}", task.title, sentences.join(" "))
}

/// The answer: a paragraph per task, blank lines between; `None` when the paper's EA-MADM
/// has no verdict in the run.
pub(crate) fn answer(findings: &Findings) -> Option<String> {
    let paragraphs: Vec<String> = findings.tasks.iter().map(task_answer).collect();
    (!paragraphs.is_empty()).then(|| paragraphs.join("\n\n"))
}

/// The README's answer block: the answer of the report's first screen.
///
/// # Errors
/// A message when the findings hold no task with EA-MADM's verdicts (the README states the
/// default run's answer, which has them).
pub fn readme_answer(findings: &Findings) -> Result<String, String> {
    answer(findings).ok_or_else(|| {
        "the findings hold no task on which the paper's EA-MADM was judged".to_owned()
    })
}

/// The tasks of `deviation` as a sentence names them; empty when it concerns every task.
fn deviation_tasks(context: &ReportContext, deviation: &DeviationFacts) -> String {
    if deviation.tasks.is_empty() {
        return String::new();
    }
    let titles: Vec<String> = deviation
        .tasks
        .iter()
        .map(|t| context.task_title(t))
        .collect();
    format!(" ({})", list(&titles))
}

/// What the readings of a deviation showed, from the findings: which verdicts flip under
/// them.
fn deviation_tested(findings: &Findings, deviation: &DeviationFacts) -> String {
    let mut parts = Vec::new();
    if !deviation.readings.is_empty() {
        let named: Vec<String> = deviation
            .readings
            .iter()
            .map(|r| format!("`{r}`"))
            .collect();
        let mut flipped: Vec<String> = Vec::new();
        let mut tried = false;
        for task in &findings.tasks {
            let Some(readings) = &task.readings else {
                continue;
            };
            tried = true;
            let claims: Vec<String> = readings
                .flips
                .iter()
                .filter(|(_, names)| names.iter().any(|n| deviation.readings.contains(n)))
                .map(|(claim, _)| claim.clone())
                .collect();
            if !claims.is_empty() {
                flipped.push(format!("{} on {}", list(&claims), task.title));
            }
        }
        parts.push(match (tried, flipped.is_empty()) {
            (false, _) => format!("rerun by {} (not run here)", list(&named)),
            (true, true) => format!("rerun by {}: no verdict flips", list(&named)),
            (true, false) => format!("rerun by {}: {} flip", list(&named), list(&flipped)),
        });
    }
    if !deviation.methods.is_empty() {
        let named: Vec<String> = deviation.methods.iter().map(|m| format!("`{m}`")).collect();
        parts.push(format!("other choices run as {}", list(&named)));
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" {}.", capitalised(&parts.join("; ")))
    }
}

/// The list of deviations, each on one line.
pub(crate) fn deviations(context: &ReportContext, findings: &Findings) -> Option<String> {
    if context.deviations.is_empty() {
        return None;
    }
    let mut text = String::from(
        "Each could change a verdict; a reading of the paper or an ablation reruns the other \
         choice where one could be run.\n\n",
    );
    for deviation in &context.deviations {
        let _ = writeln!(
            text,
            "- **{}**{}: {} ({}).{}",
            deviation.what,
            deviation_tasks(context, deviation),
            deviation.ours,
            deviation.notes,
            deviation_tested(findings, deviation)
        );
    }
    Some(text)
}

#[cfg(test)]
mod tests {
    use eamadm_eval::record::EpisodeRecord;
    use eamadm_eval::scores::RunOutcome;

    use super::super::tests::{judged, scores};
    use super::collapse_sentence;

    /// Issue 34 item 7: a collapse episode is the first episode that no longer reaches, so the
    /// sentence says "from episode e on", not "after episode e" (one episode late).
    #[test]
    fn the_collapse_sentence_names_the_first_episode_that_no_longer_reaches() {
        let episode = |reached| EpisodeRecord {
            episode: 0,
            steps: 1,
            task_return: 0.0,
            learning_return: 0.0,
            terminated: reached,
            truncated: !reached,
            reached,
            collisions: 0,
            env_steps: 1,
            robot: None,
        };
        // Episodes 0–62 reach, 63–199 do not.
        let episodes: Vec<_> = (0..200).map(|e| episode(e < 63)).collect();
        let (outcome, collapse) = RunOutcome::of(false, &episodes, 20);
        assert_eq!((outcome, collapse), (RunOutcome::Collapsed, Some(63)));
        let mut rows = scores(60.0, &[3], 10.0);
        for r in rows
            .iter_mut()
            .filter(|r| r.kind == "ea_madm" && r.seed == 3)
        {
            r.collapse_episode = collapse;
        }
        let (_, findings) = judged(rows);
        let text = collapse_sentence(findings.tasks[0].collapses.as_ref().unwrap());
        assert!(
            text.starts_with(
                "EA-MADM collapsed on 1 of 8 seeds (3): it never reached the target again from \
                 episode 63 on"
            ),
            "{text}"
        );
        assert!(!text.contains("after episode"), "{text}");
    }
}
