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

use super::answer::{converged, converged_count, rank};
use super::format::{format_fixed, list, number};
use super::verdicts::deciding_number;
use eamadm_eval::verdicts::{ControlVerdict, Verdicts, control_family};

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
