//! The verdict table (the README's verdict block is the same table), the claims, the verdicts
//! of EA-MADM's ablations and variants (methods that score as another on every seed listed
//! once, rows that say the same merged), and the rule they are judged by (the appendix's).

use std::fmt::Write as _;

use eamadm_eval::findings::{Findings, TaskFindings, VariantVerdict};
use eamadm_eval::paper_claims::CLAIMS;
use eamadm_eval::verdicts::Verdicts;

use super::format::{Align, MarkdownTable, list, number, role_text};
use super::words::{self, deciding_or_reason};

/// The strongest control of a claim on a task with its kind, and EA-MADM's verdict against it
/// with the number that decides it; "none run" when the task has no control.
fn strongest_cells(task: &TaskFindings, claim: &str) -> (String, String) {
    task.strongest
        .iter()
        .find(|s| s.claim == claim)
        .map_or_else(
            || ("none run".to_owned(), "—".to_owned()),
            |s| {
                (
                    format!(
                        "`{}` ({}; IQM `{}` {})",
                        s.control,
                        words::family(s.family),
                        s.metric,
                        number(s.control_iqm)
                    ),
                    format!(
                        "{}: {}",
                        s.verdict.name(),
                        deciding_or_reason(s.deciding.as_ref(), &s.reason, &task.method, false)
                    ),
                )
            },
        )
}

/// Whether the claim × task's verdict survives every reading of the paper run: `yes`, `no`,
/// or `not run` when none was run.
fn survives_cell(task: &TaskFindings, claim: &str) -> &'static str {
    match &task.readings {
        None => "not run",
        Some(r) if r.flips.iter().any(|(c, _)| c == claim) => "no",
        Some(r) if r.holds.iter().any(|(c, _)| c == claim) => "yes",
        Some(_) => "not run",
    }
}

/// The verdict table: per claim and task, EA-MADM's verdict against the paper's competitors
/// with its deciding number, the strongest control and the verdict against it, and whether
/// it survives the readings; `None` without findings.
fn verdict_table(findings: &Findings) -> Option<String> {
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("task", Align::Left),
        ("verdict (EA-MADM vs the paper's competitors)", Align::Left),
        ("the number that decides it", Align::Left),
        ("strongest control", Align::Left),
        ("verdict vs the strongest control", Align::Left),
        ("survives the readings", Align::Left),
    ]);
    let mut rows = 0;
    for claim in &CLAIMS {
        for task in &findings.tasks {
            let Some(v) = task.verdicts.iter().find(|v| v.claim == claim.id) else {
                continue;
            };
            let (control, control_verdict) = strongest_cells(task, claim.id);
            let _ = table.push_row([
                claim.id.to_owned(),
                task.title.clone(),
                format!("**{}**", v.verdict.name()),
                deciding_or_reason(v.deciding.as_ref(), &v.reason, &task.method, true),
                control,
                control_verdict,
                survives_cell(task, claim.id).to_owned(),
            ]);
            rows += 1;
        }
    }
    (rows > 0).then(|| table.render())
}

/// One line per claim: its id, words and place in the paper.
fn claims_lines() -> String {
    let mut text = String::new();
    for claim in &CLAIMS {
        let _ = writeln!(
            text,
            "- **{}**: {}. {}.",
            claim.id, claim.words, claim.location
        );
    }
    text
}

/// The README's verdict block: the verdict table, then one line per claim.
///
/// # Errors
/// A message when the findings hold no verdict (the README states the default run's).
pub fn readme_verdicts(findings: &Findings) -> Result<String, String> {
    let table = verdict_table(findings)
        .ok_or_else(|| "the findings hold no verdict on the paper's claims".to_owned())?;
    Ok(format!("{table}\n{}", claims_lines()))
}

/// The verdicts section: the table, the claims with the metrics that test them, and the
/// variants' verdicts.
pub(crate) fn write_verdicts(text: &mut String, titles: &[String], findings: &Findings) {
    let _ = writeln!(text, "{VERDICTS_HEADING}\n");
    match verdict_table(findings) {
        Some(table) => {
            text.push_str(&table);
            text.push('\n');
        }
        None => {
            let _ = writeln!(
                text,
                "None of the paper's claims is made on the tasks of this run, or the paper's \
                 EA-MADM was not run on them (the claims are about {}).\n",
                list(titles)
            );
        }
    }
    let _ = writeln!(
        text,
        "The claims (each judged by the rule in the appendix):\n"
    );
    for claim in &CLAIMS {
        let metrics: Vec<String> = claim
            .metrics
            .iter()
            .map(|m| format!("`{}` ({} is better)", m.column, m.direction.name()))
            .collect();
        let _ = writeln!(
            text,
            "- **{}** ({}): {}. Tested on {}.",
            claim.id,
            claim.location,
            claim.words,
            metrics.join(", ")
        );
    }
    text.push('\n');
    write_variants(text, findings);
}

/// A variant's row: who is judged against whom, the verdict and what decides it (the method
/// said as "it", so that rows differing only in the method merge).
fn variant_cells(variant: &VariantVerdict) -> (String, String) {
    let v = &variant.verdict;
    (
        v.verdict.name().to_owned(),
        deciding_or_reason(v.deciding.as_ref(), &v.reason, "it", true)
            .replace(&format!("{} ", variant.method), "it "),
    )
}

/// The verdicts of EA-MADM's ablations and variants: one row per claim × task × verdict ×
/// deciding number, listing every method it holds for; a method that scores as another on
/// every seed is left out with a sentence.
fn write_variants(text: &mut String, findings: &Findings) {
    if findings.tasks.iter().all(|t| t.variants.is_empty()) {
        return;
    }
    let _ = writeln!(
        text,
        "### The same claims for EA-MADM's ablations and variants\n\n\
         Each is judged against the paper's competitors by the same rule (controls are marked: \
         they are not in the paper); a repaired robot reading is judged a second time against \
         the competitors trained on its own sub-task rewards (claims.csv: `versus_set`). Rows \
         that say the same for several methods are one row.\n"
    );
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("task", Align::Left),
        ("methods", Align::Left),
        ("role", Align::Left),
        ("verdict", Align::Left),
        ("the number that decides it", Align::Left),
    ]);
    let mut left_out: Vec<String> = Vec::new();
    for claim in &CLAIMS {
        for task in &findings.tasks {
            // (role, verdict, deciding) → methods, in first-appearance order.
            let mut rows: Vec<(String, String, String, Vec<String>)> = Vec::new();
            for variant in task.variants.iter().filter(|v| v.verdict.claim == claim.id) {
                let same = task.identical.iter().find(|i| i.method == variant.method);
                if variant.versus_set == "paper" && same.is_some() {
                    continue;
                }
                let role = role_text(variant.role).to_owned();
                let (verdict, deciding) = variant_cells(variant);
                let label = format!("`{}`", variant.method);
                match rows
                    .iter_mut()
                    .find(|(r, v, d, _)| *r == role && *v == verdict && *d == deciding)
                {
                    Some((_, _, _, methods)) => methods.push(label),
                    None => rows.push((role, verdict, deciding, vec![label])),
                }
            }
            for (role, verdict, deciding, methods) in rows {
                let _ = table.push_row([
                    claim.id.to_owned(),
                    task.title.clone(),
                    methods.join(", "),
                    role,
                    verdict,
                    deciding,
                ]);
            }
        }
    }
    for task in &findings.tasks {
        let same: Vec<String> = task
            .identical
            .iter()
            .filter(|i| task.variants.iter().any(|v| v.method == i.method))
            .map(|i| {
                format!(
                    "`{}` (as {}, {} of {} seeds)",
                    i.method,
                    words::name(&i.same_as),
                    i.seeds,
                    i.seeds
                )
            })
            .collect();
        if !same.is_empty() {
            left_out.push(format!("on {}: {}", task.title, list(&same)));
        }
    }
    text.push_str(&table.render());
    text.push('\n');
    if !left_out.is_empty() {
        let _ = writeln!(
            text,
            "Not listed, since they score exactly as another method on every seed and so get \
             its verdicts: {}.\n",
            left_out.join("; ")
        );
    }
}

/// The rule the verdicts are judged by, as a list (the appendix).
pub(crate) fn write_rule(text: &mut String, verdicts: &Verdicts) {
    let alpha = verdicts.options.alpha;
    let _ = writeln!(
        text,
        "### The rule\n\n\
         - Each method under test is compared with each of the paper's competitors (the \
         methods with role `paper` that are not EA-MADM) on every metric of the claim, \
         **paired by seed** (runs of one seed share their random streams).\n\
         - One estimand decides: the **mean paired difference** (EA-MADM − competitor over the \
         seeds where both have a value). Every seed counts, so a seed that collapsed to the \
         step cap counts against its method.\n\
         - Its **exact sign-flip 95% interval** inverts the sign-flip test: every one of the \
         2ⁿ sign vectors is counted up to 24 pairs ({} drawn beyond), so there is no \
         resampling and no Monte-Carlo error. It holds the mean with 95% confidence when the \
         paired differences are symmetric about it, the sign-flip test's own assumption, which \
         capped, bimodal differences only approach.\n\
         - Two p-values come from the same distribution: that the mean lies **beyond the \
         margin** on one side (at most α exactly when the interval does) and that it lies \
         **within** it (two one-sided tests at α/2: the 95% interval inside the margin). The \
         margins are listed below.\n\
         - A comparison **favours** a side when its Holm-adjusted beyond-margin p is below \
         {alpha} (its interval then lies beyond the margin on that side), and is \
         **equivalent** when its Holm-adjusted within-margin p is below {alpha}.\n\
         - A comparison in which every paired value of both sides is one and the same number \
         (e.g. greedy SD 0 on every seed) is **uninformative**: left out of Holm, it settles \
         nothing and is never equivalent.\n\
         - The IQM difference (bootstrap interval, {} resamples) and P(EA-MADM better) are \
         descriptive.\n\
         - The verdict is **supported** when every comparison favours EA-MADM, \
         **contradicted** when any favours a competitor, **equivalent** when every comparison \
         is equivalent, **inconclusive** otherwise, and **untestable** when no competitor has \
         2 seeds with a value.\n\
         - **Multiplicity**: Holm covers one family per claim × task × method under test — \
         every metric × competitor of the claim, and for C3 its stable-reaching tests too — \
         since that family makes the verdict. Supported and equivalent need every member \
         (intersection-union tests, which need no adjustment; Holm is applied all the same so \
         that each row can be read alone). The verdicts of different claims, tasks, ablations, \
         controls and readings are separate questions, each stated with its own family, and \
         are not adjusted across each other.\n\
         - A method with fewer than 2 seeds with a value (it seldom or never reaches the \
         target) is judged on per-seed reaching instead: a seed reaches when its greedy \
         episode or any training episode does. Against each competitor the exact paired sign \
         test on the seeds only one of the two reaches on (McNemar), Holm-adjusted across the \
         competitors, decides: **contradicted** when a competitor reaches on more seeds with \
         a Holm p below {alpha}, **inconclusive** when one reaches on 2 or more seeds but not \
         significantly more, **untestable** when none does (claims.csv: metric `reached`).\n\
         - **C3** (\"the minimum fluctuation\") is judged on the greedy policy, evaluated every \
         few training episodes without exploration or learning, and reads as \
         **reliability**. A seed is stable-reaching when each such evaluation in the second \
         half of training reaches the target, and only those seeds have a greedy fluctuation \
         (`fluctuation_greedy_*`), so a seed stuck at the step cap counts as a failure, never \
         as stability. Against each competitor the stable-reaching seeds are compared by the \
         exact paired sign test (claims.csv: metric `stable_reaching`) and the greedy \
         fluctuation by the rule above, all in one Holm family; the comparison favours a side \
         when either favours it and the other does not favour the other side, and is \
         equivalent when the greedy fluctuations are and the same seeds stable-reach on both \
         sides. Where the greedy fluctuation is 0 on every stable-reaching seed of both sides \
         it is uninformative, and C3 can then be decided only by reliability.\n\
         - The fair comparison is ε-decreasing, which uses EA-MADM's ε schedule; a fixed-ε \
         method (ε-greedy) enters C3 on its greedy policy, without its exploration. The \
         training curves' SDs (`fluctuation_steps`, `fluctuation_return`) are secondary rows \
         with no verdict.\n\
         - The deciding number is the weakest comparison of a supported or equivalent claim, \
         the strongest against a contradicted one, and the weakest non-favourable one of an \
         inconclusive one (or the per-seed test when it comes nearer to settling it).\n",
        verdicts.options.sign_flip.resamples, verdicts.options.bootstrap.resamples,
    );
}

/// The heading in `REPORT.md` above the verdict table.
pub(crate) const VERDICTS_HEADING: &str = "## Verdicts on the paper's claims";
