//! EA-MADM judged against the strongest control, and against the competitors without its
//! collapsed seeds: the two readings of the verdicts the answer and the verdict table give
//! beside the verdict against the paper's competitors.
//!
//! The **strongest control** of a claim on a task is the control (role `control`, not an
//! EA-MADM variant) with the best IQM of the claim's deciding metric there: the metric of the
//! comparison that decides EA-MADM's verdict against the paper's competitors, else the claim's
//! first metric. EA-MADM is judged against it alone by the very rule of the verdicts
//! ([`claims::judge_against_competitors`]).

use std::fmt::Write as _;

use super::Verdicts;
use super::answer::{converged, converged_count, rank};
use super::format::{format_fixed, list, number};
use super::verdicts::deciding_number;
use crate::Role;
use crate::claims::{self, ClaimOptions, ClaimsError, Estimate, Judgement};
use crate::paper_claims::{Claim, Direction};
use crate::scores::{FinalScore, RunOutcome};

/// EA-MADM's verdict on a claim × task against the strongest control there.
#[derive(Debug, Clone, PartialEq)]
pub struct ControlVerdict {
    /// The control's label.
    pub control: String,
    /// The metric it is the strongest on.
    pub metric: &'static str,
    /// Its IQM of that metric.
    pub control_iqm: f64,
    /// EA-MADM judged against it alone.
    pub judgement: Judgement,
}

/// What kind of control `label` is, by the facade's naming of the controls
/// (`eamadm::paper::controls`): `*-shaped*` learn from EA-MADM's shaped sub-task rewards
/// (standardised, summed or repaired), `*-budget` get EA-MADM's pre-training steps as warm-up,
/// `subtask*-alone*` are one pre-trained sub-task acting alone (frozen or learning).
#[must_use]
pub fn control_family(label: &str) -> Option<&'static str> {
    if label.contains("-shaped") {
        Some("reward-matched")
    } else if label.ends_with("-budget") {
        Some("budget-matched")
    } else if label.starts_with("subtask") && label.contains("-alone") {
        Some("sub-task alone")
    } else {
        None
    }
}

/// The claim's deciding metric in `judgement`: the deciding comparison's, else the first.
fn deciding_metric(claim: &Claim, judgement: &Judgement) -> &'static str {
    judgement
        .deciding_comparison()
        .map_or(claim.metrics[0].column, |c| c.metric.column)
}

/// The control of `task` with the best IQM of `metric` (the earlier one on a tie), with that
/// IQM.
#[must_use]
pub fn strongest_control<'a>(
    scores: &'a [FinalScore],
    estimates: &[Estimate],
    task: &str,
    metric: &str,
    direction: Direction,
) -> Option<(&'a str, f64)> {
    let mut best: Option<(&str, f64)> = None;
    for (method, role, kind) in claims::methods(scores, task) {
        if role != Role::Control || claims::is_under_test(kind) || control_family(method).is_none()
        {
            continue;
        }
        let Some(value) = estimates
            .iter()
            .find(|e| e.task == task && e.method == method && e.metric == metric)
            .and_then(|e| e.iqm.as_ref())
            .map(|i| i.estimate)
        else {
            continue;
        };
        let better = match best {
            None => true,
            Some((_, b)) => match direction {
                Direction::LowerIsBetter => value < b,
                Direction::HigherIsBetter => value > b,
            },
        };
        if better {
            best = Some((method, value));
        }
    }
    best
}

/// EA-MADM's (each paper-role method under test's) verdict against the strongest control of
/// every claim × task it is judged on.
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn against_strongest_controls(
    scores: &[FinalScore],
    judgements: &[Judgement],
    estimates: &[Estimate],
    options: &ClaimOptions,
) -> Result<Vec<ControlVerdict>, ClaimsError> {
    let mut out = Vec::new();
    for judgement in judgements.iter().filter(|j| j.role == Role::Paper) {
        let claim = judgement.claim;
        let metric = deciding_metric(claim, judgement);
        let direction = claim
            .metrics
            .iter()
            .find(|m| m.column == metric)
            .map_or(Direction::LowerIsBetter, |m| m.direction);
        let Some((control, control_iqm)) =
            strongest_control(scores, estimates, &judgement.task, metric, direction)
        else {
            continue;
        };
        let against = claims::judge_against_competitors(
            scores,
            claim,
            &judgement.task,
            &judgement.method,
            judgement.role,
            &[control],
            options,
        )?;
        out.push(ControlVerdict {
            control: control.to_owned(),
            metric,
            control_iqm,
            judgement: against,
        });
    }
    Ok(out)
}

/// The seeds of `method` on `task` whose run collapsed, with the collapse episode, by seed.
#[must_use]
pub fn collapsed_seeds(scores: &[FinalScore], task: &str, method: &str) -> Vec<(u64, Option<u64>)> {
    let mut seeds: Vec<(u64, Option<u64>)> = scores
        .iter()
        .filter(|s| s.task == task && s.method == method && s.outcome == RunOutcome::Collapsed)
        .map(|s| (s.seed, s.collapse_episode))
        .collect();
    seeds.sort_unstable();
    seeds
}

/// The paper EA-MADM's verdicts judged again with the seeds it collapsed on left out of every
/// method (so the comparisons stay paired), for the claims × tasks where it collapsed on some
/// seed and its verdict is neither supported nor equivalent: whether the collapses alone keep
/// it from a better verdict.
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn without_collapses(
    scores: &[FinalScore],
    judgements: &[Judgement],
    options: &ClaimOptions,
) -> Result<Vec<Judgement>, ClaimsError> {
    let mut out = Vec::new();
    for judgement in judgements.iter().filter(|j| {
        j.role == Role::Paper
            && matches!(
                j.verdict,
                claims::Verdict::Inconclusive | claims::Verdict::Contradicted
            )
    }) {
        let collapsed: Vec<u64> = collapsed_seeds(scores, &judgement.task, &judgement.method)
            .into_iter()
            .map(|(seed, _)| seed)
            .collect();
        if collapsed.is_empty() {
            continue;
        }
        let kept: Vec<FinalScore> = scores
            .iter()
            .filter(|s| !(s.task == judgement.task && collapsed.contains(&s.seed)))
            .cloned()
            .collect();
        out.push(claims::judge_one(
            &kept,
            judgement.claim,
            &judgement.task,
            &judgement.method,
            judgement.role,
            options,
        )?);
    }
    Ok(out)
}

/// Mean environment steps per run of `method` on `task`, in thousands (`599 k`).
fn env_steps(verdicts: &Verdicts, task: &str, method: &str) -> Option<String> {
    verdicts
        .overviews
        .iter()
        .find(|o| o.task == task && o.method == method)
        .map(|o| format!("{} k", format_fixed(o.env_steps_total / 1000.0, 0)))
}

/// The paper EA-MADM against the strongest control of each claim on `task`, a sentence per
/// control: the control's IQM of the deciding metric against EA-MADM's, the seeds each
/// converges on, the environment steps per run, and the verdict against it by the same rule
/// with its deciding number; then whether a better metric comes without converging more, and
/// which verdicts against the paper's competitors it overturns.
pub(crate) fn strongest_sentences(verdicts: &Verdicts, task: &str) -> Vec<String> {
    let Some(ea) = verdicts.paper_ea_madm(task) else {
        return Vec::new();
    };
    let mut by_control: Vec<(&str, Vec<&ControlVerdict>)> = Vec::new();
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
    let mut sentences = Vec::new();
    for (control, group) in by_control {
        let Some(first) = group.first() else {
            continue;
        };
        let claims_of: Vec<String> = group
            .iter()
            .map(|c| c.judgement.claim.id.to_owned())
            .collect();
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
            .map(|c| {
                format!(
                    "{} {} ({})",
                    c.judgement.claim.id,
                    c.judgement.verdict.name(),
                    deciding_number(&c.judgement)
                )
            })
            .collect();
        let mut text = format!(
            "The strongest control on {} is `{control}` ({}): IQM `{}` {} against EA-MADM's \
             {own_iqm}, converged on {} seeds against {}{steps}; judged against it by the same \
             rule, EA-MADM's {} {}.",
            list(&claims_of),
            control_family(control).unwrap_or("control"),
            first.metric,
            number(first.control_iqm),
            converged(verdicts, task, control),
            converged(verdicts, task, ea),
            if against.len() == 1 {
                "verdict is"
            } else {
                "verdicts are"
            },
            list(&against)
        );
        if converged_count(verdicts, task, control).0 < converged_count(verdicts, task, ea).0 {
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
                verdicts.judgements.iter().any(|b| {
                    b.task == task
                        && b.method == ea
                        && b.claim.id == c.judgement.claim.id
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
        sentences.push(text);
    }
    sentences
}
