//! A task section's sentences on the strongest control of each claim: the control's IQM of
//! the deciding metric against EA-MADM's, the seeds each converges on, the environment steps
//! per run, EA-MADM's verdict against it by the same rule, and what that says of the verdict
//! against the paper's competitors. All of it is in the findings
//! ([`StrongestControl`](eamadm_eval::findings::StrongestControl)).

use std::fmt::Write as _;

use eamadm_eval::findings::{StrongestControl, TaskFindings};

use super::format::{format_fixed, list, number};
use super::words::{self, deciding_or_reason};

/// The sentences of `task`'s strongest controls, one per control.
pub(crate) fn strongest_sentences(task: &TaskFindings) -> Vec<String> {
    let mut by_control: Vec<(&str, Vec<&StrongestControl>)> = Vec::new();
    for s in &task.strongest {
        match by_control.iter_mut().find(|(name, _)| *name == s.control) {
            Some((_, group)) => group.push(s),
            None => by_control.push((s.control.as_str(), vec![s])),
        }
    }
    let mut sentences = Vec::new();
    for (control, group) in by_control {
        let Some(first) = group.first() else {
            continue;
        };
        let claims: Vec<String> = group.iter().map(|s| s.claim.clone()).collect();
        let own = first
            .method_iqm
            .map_or_else(|| "none (no seed has a value)".to_owned(), number);
        let against: Vec<String> = group
            .iter()
            .map(|s| {
                format!(
                    "{} {} ({})",
                    s.claim,
                    s.verdict.name(),
                    deciding_or_reason(s.deciding.as_ref(), &s.reason, &task.method, true)
                )
            })
            .collect();
        let thousands = |steps: f64| format!("{} k", format_fixed(steps / 1000.0, 0));
        let mut text = format!(
            "The strongest control on {} is `{control}` ({}): IQM `{}` {} against EA-MADM's \
             {own}; it converges on {} of {} seeds, EA-MADM on {} of {}; {} environment steps \
             per run against {}. Judged against it by the same rule, EA-MADM's {} {}.",
            list(&claims),
            words::family(first.family),
            first.metric,
            number(first.control_iqm),
            first.converged.hits,
            first.converged.seeds,
            task.converged.hits,
            task.converged.seeds,
            thousands(first.env_steps[0]),
            thousands(first.env_steps[1]),
            if against.len() == 1 {
                "verdict is"
            } else {
                "verdicts are"
            },
            list(&against)
        );
        if first.converged.hits < task.converged.hits {
            let _ = write!(
                text,
                " It converges on fewer seeds than EA-MADM, so its better `{}` does not come \
                 from reaching the target more often.",
                first.metric
            );
        }
        let overturned: Vec<String> = group
            .iter()
            .filter(|s| s.overturns)
            .map(|s| s.claim.clone())
            .collect();
        if !overturned.is_empty() {
            let _ = write!(
                text,
                " So on {} the verdict against the paper's competitors does not hold against \
                 a {} control.",
                list(&overturned),
                words::family(first.family)
            );
        }
        sentences.push(text);
    }
    sentences
}
