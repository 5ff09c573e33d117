//! How the report says a finding in words: a method's name, a control's family, a verdict's
//! deciding comparison, claims grouped by verdict. Every module of the report says these the
//! same way through here.

use eamadm_eval::claims::{self, Verdict};
use eamadm_eval::facts::ControlFamily;
use eamadm_eval::findings::{Deciding, Estimand, Test};
use eamadm_eval::paper_claims::method_title;

use super::format::{list, mean_interval, p_value};
use super::margins::short_number;

/// A method as a sentence names it: the paper's methods by title, others by label in code.
pub(crate) fn name(method: &str) -> String {
    let title = method_title(method);
    if title == method {
        format!("`{method}`")
    } else {
        title
    }
}

/// What a control is, in two or three words.
pub(crate) fn family(family: ControlFamily) -> &'static str {
    match family {
        ControlFamily::RewardMatched => "reward-matched",
        ControlFamily::BudgetMatched => "budget-matched",
        ControlFamily::SubtaskAlone { .. } => "sub-task alone",
    }
}

/// What a control is, in a clause a first-time reader parses.
pub(crate) fn family_clause(family: ControlFamily) -> &'static str {
    match family {
        ControlFamily::RewardMatched => {
            "a competitor learning from the same shaped sub-task rewards as EA-MADM"
        }
        ControlFamily::BudgetMatched => {
            "a competitor given EA-MADM's pre-training steps as extra training"
        }
        ControlFamily::SubtaskAlone { learns: false, .. } => {
            "EA-MADM's pre-trained sub-task acting alone, without the MADM step"
        }
        ControlFamily::SubtaskAlone { learns: true, .. } => {
            "EA-MADM's pre-trained sub-task acting alone and still learning, without the MADM step"
        }
    }
}

/// `a`, `a and b` of verdicts grouped: `C1, C2 and C3 are inconclusive` / `C1 is supported and
/// C2 inconclusive`, in order of first appearance.
pub(crate) fn verdict_groups(items: &[(&str, Verdict)]) -> String {
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
pub(crate) fn overall(verdicts: &[Verdict]) -> &'static str {
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

/// A deciding comparison in words. `method` is the side under test; with `versus`, a metric
/// comparison names the other side first (`vs softmax: …`) and a per-seed test names both
/// sides, without it (a column that names them already) neither.
pub(crate) fn deciding(d: &Deciding, method: &str, versus: bool) -> String {
    let before = if versus {
        format!("vs {}: ", method_title(&d.versus))
    } else {
        String::new()
    };
    match d.estimand {
        Estimand::PairedMeanDifference => {
            let range = mean_interval(d.estimate, d.interval, d.pairs.unwrap_or(0));
            if d.test == Test::SignFlipWithinMargin {
                format!(
                    "{before}paired Δ mean `{}` = {range} within ±{}, equivalence Holm p {}",
                    d.metric,
                    d.margin.map_or_else(|| "—".to_owned(), short_number),
                    p_value(d.p_holm)
                )
            } else {
                format!(
                    "{before}paired Δ mean `{}` = {range}, Holm p {} (beyond {})",
                    d.metric,
                    p_value(d.p_holm),
                    d.margin
                        .map_or_else(|| "0".to_owned(), |m| format!("±{}", short_number(m)))
                )
            }
        }
        Estimand::SeedsReaching | Estimand::SeedsStableReaching => {
            let seeds = d.seeds.unwrap_or(eamadm_eval::findings::SeedPair {
                method: 0,
                versus: 0,
                of: 0,
            });
            let words = claims::per_seed_words(&d.metric);
            if versus {
                format!(
                    "{} {words} on {}/{n} seeds, {} on {}/{n}; exact paired sign test, Holm p {}",
                    method_title(method),
                    seeds.method,
                    method_title(&d.versus),
                    seeds.versus,
                    p_value(d.p_holm),
                    n = seeds.of
                )
            } else {
                format!(
                    "{words} on {}/{n} seeds against {}/{n}; exact paired sign test, Holm p {}",
                    seeds.method,
                    seeds.versus,
                    p_value(d.p_holm),
                    n = seeds.of
                )
            }
        }
    }
}

/// A verdict's deciding comparison in words, else its reason.
pub(crate) fn deciding_or_reason(
    deciding_comparison: Option<&Deciding>,
    reason: &str,
    method: &str,
    versus: bool,
) -> String {
    deciding_comparison.map_or_else(|| reason.to_owned(), |d| deciding(d, method, versus))
}

/// `14, 16` of seeds.
pub(crate) fn seeds(seeds: &[u64]) -> String {
    seeds
        .iter()
        .map(u64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// `first capital`: a phrase that opens a sentence.
pub(crate) fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map_or_else(String::new, |first| {
        first.to_uppercase().chain(chars).collect()
    })
}
