//! The answer in one paragraph: what `REPORT.md` opens with and the README states, every
//! sentence computed from a run's `claims.csv` and `final-scores.csv` text.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use serde::Deserialize;

use super::ReportContext;
use super::verdicts::VERDICTS_HEADING;
use crate::claims::{REACHED, STABLE_REACHING};
use crate::paper_claims::{CLAIMS, Direction, method_title};

/// The method whose verdicts the answer states.
const METHOD: &str = "ea-madm";

/// One row of `claims.csv` (the columns the README needs).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct ClaimsCsvRow {
    /// `C1` … `C4`.
    pub claim: String,
    /// The task.
    pub task: String,
    /// The method judged or estimated.
    pub method: String,
    /// Its role: `paper`, `ablation` or `control`.
    pub role: String,
    /// The metric column.
    pub metric: String,
    /// Empty on a method's own row (its IQM), a competitor on a comparison row.
    pub versus: String,
    /// Seeds with a value.
    pub n: u32,
    /// The IQM (own row) or the IQM difference method − versus (comparison row).
    pub estimate: Option<f64>,
    /// The interval's low end.
    pub ci_low: Option<f64>,
    /// The interval's high end.
    pub ci_high: Option<f64>,
    /// The Holm-adjusted p-value of a comparison.
    pub p_holm: Option<f64>,
    /// `favours_method`, `favours_competitor`, `unsettled` on comparison rows.
    pub outcome: String,
    /// The verdict of the claim × task × method (empty on rows that carry none).
    pub verdict: String,
}

/// One row of `final-scores.csv` (the columns the README needs).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct ScoresCsvRow {
    /// The task.
    pub task: String,
    /// The method's label.
    pub method: String,
    /// Its role: `paper`, `ablation` or `control`.
    pub role: String,
    /// The method's kind (`ea_madm`, `softmax`, …).
    pub kind: String,
    /// The seed.
    pub seed: u64,
    /// Final-window success rate.
    pub success_rate: Option<f64>,
    /// Environment steps of the run, pre-training included.
    pub env_steps_total: f64,
}

/// The answer paragraph ([`answer_paragraph`]) of a run from the text of its `claims.csv` and
/// `final-scores.csv`: what `REPORT.md` opens with, the same words the README states.
pub fn answer_from_csv(
    claims_csv: &str,
    scores_csv: &str,
    context: &ReportContext,
) -> Result<String, String> {
    answer_paragraph(
        &parse_csv(claims_csv, "claims.csv")?,
        &parse_csv(scores_csv, "final-scores.csv")?,
        context,
    )
}

fn parse_csv<T: for<'de> Deserialize<'de>>(text: &str, name: &str) -> Result<Vec<T>, String> {
    csv::Reader::from_reader(text.as_bytes())
        .deserialize()
        .collect::<Result<Vec<T>, _>>()
        .map_err(|error| format!("{name}: {error}"))
}

/// A number for people: three significant figures at most, no trailing zeros' noise.
fn number(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude >= 100.0 {
        format!("{value:.0}")
    } else if magnitude >= 10.0 {
        format!("{value:.1}")
    } else {
        format!("{value:.2}")
    }
}

fn p_value(p: Option<f64>) -> String {
    match p {
        Some(p) if p < 0.001 => "< 0.001".to_owned(),
        Some(p) => format!("= {p:.3}"),
        None => "not computed".to_owned(),
    }
}

fn task_title(task: &str, context: &ReportContext) -> String {
    context.paper_task(task).map_or_else(
        || format!("`{task}`"),
        |paper| paper.title_in_sentence.clone(),
    )
}

/// `a`, `a and b`, `a, b and c`.
fn list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

fn plural(count: usize, one: &str, many: &str) -> String {
    format!("{count} {}", if count == 1 { one } else { many })
}

/// The answer in one paragraph, every sentence computed from the claim rows and final scores of
/// the default run: how many claim–task pairs each verdict has, and per task the facts that
/// decide them (the comparisons' outcomes, the deciding comparison of a contradiction, the
/// environment-step budget and the best control where EA-MADM wins, the seeds with a value and
/// the success rates where a claim is untestable).
pub fn answer_paragraph(
    claims: &[ClaimsCsvRow],
    scores: &[ScoresCsvRow],
    context: &ReportContext,
) -> Result<String, String> {
    // (claim, task) → verdict of EA-MADM, in claims.csv's order.
    let mut pairs: Vec<(String, String, String)> = Vec::new();
    for row in claims {
        if row.method == METHOD && row.versus.is_empty() && !row.verdict.is_empty() {
            let pair = (row.claim.clone(), row.task.clone(), row.verdict.clone());
            if !pairs.iter().any(|(c, t, _)| *c == pair.0 && *t == pair.1) {
                pairs.push(pair);
            }
        }
    }
    if pairs.is_empty() {
        return Err(format!("claims.csv has no verdict of `{METHOD}`"));
    }
    let seeds: BTreeSet<u64> = scores
        .iter()
        .filter(|s| s.method == METHOD)
        .map(|s| s.seed)
        .collect();
    let tasks: Vec<String> = pairs.iter().fold(Vec::new(), |mut tasks, (_, task, _)| {
        if !tasks.contains(task) {
            tasks.push(task.clone());
        }
        tasks
    });
    let claims_of = |task: &str, verdict: &str| -> Vec<String> {
        pairs
            .iter()
            .filter(|(_, t, v)| t == task && v == verdict)
            .map(|(c, _, _)| c.clone())
            .collect()
    };

    let mut text = String::new();
    let verdicts = ["supported", "contradicted", "inconclusive", "untestable"];
    let mut groups = Vec::new();
    for verdict in verdicts {
        let per_task: Vec<String> = tasks
            .iter()
            .filter_map(|task| {
                let ids = claims_of(task, verdict);
                (!ids.is_empty())
                    .then(|| format!("{} on {}", list(&ids), task_title(task, context)))
            })
            .collect();
        let count = pairs.iter().filter(|(_, _, v)| v == verdict).count();
        if count > 0 {
            groups.push(format!("{verdict} {count} ({})", list(&per_task)));
        }
    }
    let _ = write!(
        text,
        "Over {} claim–task pairs and {} per method, EA-MADM's verdicts are: {}.",
        pairs.len(),
        plural(seeds.len(), "seed", "seeds"),
        groups.join("; ")
    );

    // The comparisons that decide a verdict: a secondary metric's rows (C3's training-curve
    // SDs) carry no verdict and are left out.
    let comparisons = |task: &str, ids: &[String]| -> Vec<&ClaimsCsvRow> {
        claims
            .iter()
            .filter(|r| {
                r.method == METHOD
                    && r.task == task
                    && !r.versus.is_empty()
                    && !r.verdict.is_empty()
                    && ids.contains(&r.claim)
            })
            .collect()
    };
    let paper_mean = |task: &str, method: &str, value: fn(&ScoresCsvRow) -> Option<f64>| {
        let values: Vec<f64> = scores
            .iter()
            .filter(|s| s.task == task && s.method == method)
            .filter_map(value)
            .collect();
        (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
    };
    let competitors = |task: &str| -> Vec<String> {
        let mut labels: Vec<String> = scores
            .iter()
            .filter(|s| s.task == task && s.role == "paper" && s.method != METHOD)
            .map(|s| s.method.clone())
            .collect();
        labels.dedup();
        labels
    };

    for task in &tasks {
        let title = task_title(task, context);
        let supported = claims_of(task, "supported");
        if !supported.is_empty() {
            let rows = comparisons(task, &supported);
            let weakest = rows.iter().filter_map(|r| r.p_holm).fold(0.0_f64, f64::max);
            let favour = rows
                .iter()
                .filter(|r| r.outcome == "favours_method")
                .count();
            // C3 counts a comparison for EA-MADM when its greedy fluctuation or its
            // stable-reaching test does, so a supported claim can hold unsettled rows (never
            // one that favours a competitor).
            let how_many = if favour == rows.len() {
                format!("all {}", rows.len())
            } else {
                format!("{favour} (none against it) of {}", rows.len())
            };
            let _ = write!(
                text,
                " On {title}, {how_many} of EA-MADM's comparisons on {} favour it (the weakest at Holm p {}).",
                list(&supported),
                p_value(Some(weakest))
            );
            let own = paper_mean(task, METHOD, |s| Some(s.env_steps_total));
            let others: Vec<f64> = competitors(task)
                .iter()
                .filter_map(|m| paper_mean(task, m, |s| Some(s.env_steps_total)))
                .collect();
            if let (Some(own), false) = (own, others.is_empty()) {
                let others_mean = others.iter().sum::<f64>() / others.len() as f64;
                let _ = write!(
                    text,
                    " There EA-MADM used {:.1}× the environment steps of the paper's competitors \
                     (mean over seeds, its sub-tasks' pre-training included)",
                    own / others_mean
                );
                // The best control that is not an EA-MADM variant on the first supported claim.
                let kinds: BTreeMap<&str, &str> = scores
                    .iter()
                    .filter(|s| s.task == *task)
                    .map(|s| (s.method.as_str(), s.kind.as_str()))
                    .collect();
                let first = &supported[0];
                let own_row = claims.iter().find(|r| {
                    r.task == *task
                        && r.claim == *first
                        && r.method == METHOD
                        && r.versus.is_empty()
                });
                let controls: Vec<&ClaimsCsvRow> = claims
                    .iter()
                    .filter(|r| {
                        r.task == *task
                            && r.claim == *first
                            && r.versus.is_empty()
                            && r.role == "control"
                            && kinds.get(r.method.as_str()) != Some(&"ea_madm")
                            && r.estimate.is_some()
                    })
                    .collect();
                let lower = CLAIMS
                    .iter()
                    .find(|c| c.id == *first)
                    .and_then(|c| {
                        c.metrics
                            .iter()
                            .find(|m| own_row.is_some_and(|o| o.metric == m.column))
                    })
                    .is_some_and(|m| m.direction == Direction::LowerIsBetter);
                let best = controls.iter().min_by(|a, b| {
                    let (a, b) = (
                        a.estimate.unwrap_or(f64::NAN),
                        b.estimate.unwrap_or(f64::NAN),
                    );
                    if lower {
                        a.total_cmp(&b)
                    } else {
                        b.total_cmp(&a)
                    }
                });
                match (best, own_row.and_then(|o| o.estimate)) {
                    (Some(best), Some(own)) => {
                        let value = best.estimate.unwrap_or(f64::NAN);
                        let better = if lower { value < own } else { value > own };
                        let relation = if value == own {
                            "equal to"
                        } else if better {
                            "better than"
                        } else {
                            "worse than"
                        };
                        let _ = write!(
                            text,
                            "; of the {} controls there that are not EA-MADM variants, the best on \
                             {first} is `{}` with an IQM `{}` of {}, {relation} EA-MADM's {}.",
                            controls.len(),
                            best.method,
                            best.metric,
                            number(value),
                            number(own)
                        );
                    }
                    _ => text.push('.'),
                }
            }
        }
        for id in claims_of(task, "contradicted") {
            let rows = comparisons(task, std::slice::from_ref(&id));
            let against = rows
                .iter()
                .filter(|r| r.outcome == "favours_competitor")
                .min_by(|a, b| {
                    let key = |r: &ClaimsCsvRow| {
                        (r.p_holm.unwrap_or(1.0), -r.estimate.unwrap_or(0.0).abs())
                    };
                    key(a)
                        .partial_cmp(&key(b))
                        .unwrap_or(std::cmp::Ordering::Equal)
                });
            if let Some(row) = against.filter(|r| r.metric == STABLE_REACHING) {
                let _ = write!(
                    text,
                    " On {title}, {} beats EA-MADM on {id} by reaching the target in every \
                     greedy evaluation of the second half of training on more seeds: EA-MADM's \
                     share of such seeds minus {}'s is {} over {} paired seeds, exact paired sign \
                     test Holm p {}.",
                    method_title(&row.versus),
                    method_title(&row.versus),
                    number(row.estimate.unwrap_or(f64::NAN)),
                    row.n,
                    p_value(row.p_holm)
                );
            } else if let Some(row) = against.filter(|r| r.metric == REACHED) {
                // A method that cannot be compared on the claim's metrics is judged on
                // per-seed reaching (`crate::claims::judge_by_reaching`).
                let _ = write!(
                    text,
                    " On {title}, {} beats EA-MADM on {id} by reaching the target on more \
                     seeds: EA-MADM's share of seeds reaching minus {}'s is {} over {} paired \
                     seeds, exact paired sign test Holm p {}.",
                    method_title(&row.versus),
                    method_title(&row.versus),
                    number(row.estimate.unwrap_or(f64::NAN)),
                    row.n,
                    p_value(row.p_holm)
                );
            } else if let Some(row) = against {
                let _ = write!(
                    text,
                    " On {title}, {} beats EA-MADM on {id}: EA-MADM minus {} in IQM `{}` is {} \
                     [{}, {}], Holm p {}.",
                    method_title(&row.versus),
                    method_title(&row.versus),
                    row.metric,
                    number(row.estimate.unwrap_or(f64::NAN)),
                    number(row.ci_low.unwrap_or(f64::NAN)),
                    number(row.ci_high.unwrap_or(f64::NAN)),
                    p_value(row.p_holm)
                );
            }
        }
        let inconclusive = claims_of(task, "inconclusive");
        if !inconclusive.is_empty() {
            let rows = comparisons(task, &inconclusive);
            let count = |outcome: &str| rows.iter().filter(|r| r.outcome == outcome).count();
            let mut parts = vec![format!("{} favour EA-MADM", count("favours_method"))];
            if count("favours_competitor") > 0 {
                parts.push(format!("{} a competitor", count("favours_competitor")));
            }
            parts.push(format!(
                "{} are unsettled (an interval that holds 0 or Holm p ≥ 0.05)",
                count("unsettled")
            ));
            let _ = write!(
                text,
                " On {title}, {} {}: of EA-MADM's {} comparisons there, {}.",
                list(&inconclusive),
                if inconclusive.len() == 1 {
                    "is inconclusive"
                } else {
                    "are inconclusive"
                },
                rows.len(),
                list(&parts)
            );
        }
        for id in claims_of(task, "untestable") {
            let own = claims
                .iter()
                .filter(|r| {
                    r.task == *task && r.claim == id && r.method == METHOD && r.versus.is_empty()
                })
                .min_by_key(|r| r.n);
            if let Some(row) = own {
                let _ = write!(
                    text,
                    " {id} on {title} is untestable: EA-MADM has a `{}` value in {} of {} seeds.",
                    row.metric,
                    row.n,
                    seeds.len()
                );
            }
            let rate = |method: &str| paper_mean(task, method, |s| s.success_rate);
            let best = competitors(task)
                .into_iter()
                .filter_map(|m| rate(&m).map(|r| (m, r)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
            if let (Some(own), Some((best, best_rate))) = (rate(METHOD), best) {
                let _ = write!(
                    text,
                    " Its mean success rate over the final window there is {:.0}%, against {:.0}% \
                     for the best competitor, {}.",
                    own * 100.0,
                    best_rate * 100.0,
                    method_title(&best)
                );
            }
        }
    }
    Ok(text)
}

/// `report` with the answer paragraph ([`answer_from_csv`]) on top, before the verdict
/// table, computed from the same `claims.csv` and `final-scores.csv`. A plan without
/// EA-MADM's verdicts (a config of one's own) has no such answer: the report then opens with
/// the table, as before.
pub(crate) fn with_answer(
    report: String,
    claims_csv: &str,
    scores_csv: &str,
    context: &ReportContext,
) -> String {
    let (Ok(answer), Some(at)) = (
        answer_from_csv(claims_csv, scores_csv, context),
        report.find(VERDICTS_HEADING),
    ) else {
        return report;
    };
    format!(
        "{}## The answer\n\n{answer}\n\n{}",
        &report[..at],
        &report[at..]
    )
}

#[cfg(test)]
mod tests {
    use super::super::tests::context;
    use super::*;

    #[expect(
        clippy::too_many_arguments,
        reason = "one argument per claims.csv column the tests vary"
    )]
    fn claim(
        claim: &str,
        task: &str,
        method: &str,
        versus: &str,
        estimate: f64,
        p_holm: Option<f64>,
        outcome: &str,
        verdict: &str,
    ) -> ClaimsCsvRow {
        ClaimsCsvRow {
            claim: claim.to_owned(),
            task: task.to_owned(),
            method: method.to_owned(),
            role: if method.ends_with("-budget") {
                "control"
            } else {
                "paper"
            }
            .to_owned(),
            metric: "final_steps".to_owned(),
            versus: versus.to_owned(),
            n: 2,
            estimate: Some(estimate),
            ci_low: Some(estimate - 1.0),
            ci_high: Some(estimate + 1.0),
            p_holm,
            outcome: outcome.to_owned(),
            verdict: verdict.to_owned(),
        }
    }

    fn score(task: &str, method: &str, seed: u64, success: f64, env_steps: f64) -> ScoresCsvRow {
        ScoresCsvRow {
            task: task.to_owned(),
            method: method.to_owned(),
            role: if method.ends_with("-budget") {
                "control"
            } else {
                "paper"
            }
            .to_owned(),
            kind: if method == "ea-madm" {
                "ea_madm"
            } else {
                "softmax"
            }
            .to_owned(),
            seed,
            success_rate: Some(success),
            env_steps_total: env_steps,
        }
    }

    #[test]
    fn the_answer_states_counts_and_deciding_numbers_from_the_rows() {
        let claims = vec![
            claim("C1", "task1", "ea-madm", "", 60.0, None, "", "contradicted"),
            claim(
                "C1",
                "task1",
                "ea-madm",
                "softmax",
                5.0,
                Some(0.0004),
                "favours_competitor",
                "contradicted",
            ),
            claim("C1", "task2", "ea-madm", "", 80.0, None, "", "supported"),
            claim(
                "C1",
                "task2",
                "ea-madm",
                "softmax",
                -50.0,
                Some(0.02),
                "favours_method",
                "supported",
            ),
            claim("C1", "task2", "softmax-budget", "", 70.0, None, "", ""),
        ];
        let scores = vec![
            score("task1", "ea-madm", 0, 1.0, 300.0),
            score("task1", "ea-madm", 1, 1.0, 300.0),
            score("task1", "softmax", 0, 1.0, 100.0),
            score("task2", "ea-madm", 0, 0.5, 300.0),
            score("task2", "softmax", 0, 0.5, 200.0),
            score("task2", "softmax-budget", 0, 0.5, 300.0),
        ];
        let text = answer_paragraph(&claims, &scores, &context()).unwrap();
        assert_eq!(
            text,
            "Over 2 claim–task pairs and 2 seeds per method, EA-MADM's verdicts are: supported 1 \
             (C1 on Task II); contradicted 1 (C1 on Task I). On Task I, softmax beats EA-MADM on \
             C1: EA-MADM minus softmax in IQM `final_steps` is 5.00 [4.00, 6.00], Holm p < 0.001. \
             On Task II, all 1 of EA-MADM's comparisons on C1 favour it (the weakest at Holm p = \
             0.020). There EA-MADM used 1.5× the environment steps of the paper's competitors \
             (mean over seeds, its sub-tasks' pre-training included); of the 1 controls there \
             that are not EA-MADM variants, the best on C1 is `softmax-budget` with an IQM \
             `final_steps` of 70.0, better than EA-MADM's 80.0."
        );
        assert!(answer_paragraph(&[], &scores, &context()).is_err());
    }

    #[test]
    fn the_answer_of_an_untestable_claim_gives_seeds_and_success_rates() {
        let mut own = claim("C4", "robot", "ea-madm", "", 0.0, None, "", "untestable");
        own.n = 0;
        own.estimate = None;
        let scores = vec![
            score("robot", "ea-madm", 0, 0.0, 1.0),
            score("robot", "ea-madm", 1, 0.0, 1.0),
            score("robot", "softmax", 0, 0.25, 1.0),
            score("robot", "softmax", 1, 0.35, 1.0),
        ];
        let text = answer_paragraph(&[own], &scores, &context()).unwrap();
        assert!(
            text.ends_with(
                " C4 on the robot is untestable: EA-MADM has a `final_steps` value in 0 of 2 \
                 seeds. Its mean success rate over the final window there is 0%, against 30% for \
                 the best competitor, softmax."
            ),
            "{text}"
        );
    }

    #[test]
    fn a_claim_contradicted_by_reaching_states_the_share_and_the_sign_test() {
        let mut own = claim("C4", "robot", "ea-madm", "", 0.0, None, "", "contradicted");
        own.n = 0;
        own.estimate = None;
        let mut reached = claim(
            "C4",
            "robot",
            "ea-madm",
            "softmax",
            -0.55,
            Some(0.001_953_125),
            "favours_competitor",
            "contradicted",
        );
        reached.metric = REACHED.to_owned();
        reached.n = 20;
        reached.ci_low = None;
        reached.ci_high = None;
        let scores = vec![
            score("robot", "ea-madm", 0, 0.0, 1.0),
            score("robot", "softmax", 0, 0.5, 1.0),
        ];
        let text = answer_paragraph(&[own, reached], &scores, &context()).unwrap();
        assert!(
            text.contains(
                " On the robot, softmax beats EA-MADM on C4 by reaching the target on more \
                 seeds: EA-MADM's share of seeds reaching minus softmax's is -0.55 over 20 \
                 paired seeds, exact paired sign test Holm p = 0.002."
            ),
            "{text}"
        );
    }
}
