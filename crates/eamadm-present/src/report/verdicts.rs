//! The verdict table, the claims, the rule they are judged by, and the verdicts of EA-MADM's
//! ablations and variants; the README's verdict block is the same table.

use std::fmt::Write as _;

use super::format::{Align, MarkdownTable, interval, number, p_value, role_text};
use super::{ReportContext, Verdicts};
use eamadm_eval::claims::{self, Comparison, Judgement, ReachingComparison};
use eamadm_eval::paper_claims::{CLAIMS, method_title};
use eamadm_eval::verdicts::control_family;

/// The number that decides `judgement`'s verdict, in words with the competitor it is against.
pub(crate) fn deciding_number(judgement: &Judgement) -> String {
    deciding_words(judgement, true)
}

/// [`deciding_number`] for the verdict table: a verdict decided on per-seed reaching states the
/// test alone (why the claim's metrics could not be compared is in the rule below the table
/// and in the task's section).
fn table_deciding_number(judgement: &Judgement) -> String {
    match (judgement.deciding, reason_test(judgement)) {
        (None, Some(test)) => claims::per_seed_reason(&judgement.method, test),
        _ => deciding_number(judgement),
    }
}

/// The per-seed test (C3: stable-reaching) against the deciding comparison's competitor, when
/// it came nearer to settling than that comparison (a smaller Holm p): an inconclusive C3
/// whose greedy SDs are all 0 is decided by who reaches stably, not by the 0 [0, 0].
fn deciding_per_seed_test(judgement: &Judgement) -> Option<&ReachingComparison> {
    let c = judgement.deciding_comparison()?;
    (judgement.verdict == claims::Verdict::Inconclusive)
        .then(|| {
            judgement
                .reaching
                .iter()
                .find(|t| t.versus == c.versus && t.p_holm < c.p_holm)
        })
        .flatten()
}

/// The per-seed test a verdict without a deciding comparison is decided by: the one its
/// reason states.
fn reason_test(judgement: &Judgement) -> Option<&ReachingComparison> {
    judgement.reaching.iter().find(|t| {
        judgement
            .reason
            .starts_with(&claims::per_seed_reason(&judgement.method, t))
    })
}

/// A per-seed test without the names (a column that names both sides already): "reaches on
/// 0/20 seeds against 20/20; exact paired sign test, Holm p < 0.001".
fn per_seed_short(test: &ReachingComparison) -> String {
    format!(
        "{} on {}/{n} seeds against {}/{n}; exact paired sign test, Holm p {}",
        claims::per_seed_words(test.metric),
        test.reached.0,
        test.reached.1,
        p_value(test.p_holm),
        n = test.n
    )
}

/// [`deciding_number`]; without `versus` (a column that names the one competitor already),
/// a metric comparison leaves out "vs <competitor>: ".
pub(crate) fn deciding_words(judgement: &Judgement, versus: bool) -> String {
    if let Some(test) = deciding_per_seed_test(judgement) {
        return if versus {
            claims::per_seed_reason(&judgement.method, test)
        } else {
            per_seed_short(test)
        };
    }
    if !versus
        && judgement.deciding.is_none()
        && let Some(test) = reason_test(judgement)
    {
        return per_seed_short(test);
    }
    let comparison_in_words = |c: &Comparison| {
        if versus {
            comparison_in_words(c)
        } else {
            difference_in_words(c)
        }
    };
    match judgement.deciding_comparison() {
        Some(c) if judgement.verdict == claims::Verdict::Equivalent => match &c.paired {
            Some(p) => format!(
                "vs {}: paired Δ mean `{}` = {} within ±{}, TOST Holm p {}",
                method_title(&c.versus),
                c.metric.column,
                interval(&p.difference),
                c.margin
                    .map_or_else(|| "—".to_owned(), super::margins::short_number),
                p_value(p.p_equivalence_holm.unwrap_or(1.0))
            ),
            None => comparison_in_words(c),
        },
        Some(c) => comparison_in_words(c),
        None => judgement.reason.clone(),
    }
}

fn comparison_in_words(c: &Comparison) -> String {
    format!("vs {}: {}", method_title(&c.versus), difference_in_words(c))
}

fn difference_in_words(c: &Comparison) -> String {
    format!(
        "Δ IQM `{}` = {}, Holm p {}",
        c.metric.column,
        interval(&c.difference),
        p_value(c.p_holm)
    )
}

/// The strongest control of a claim × task with its kind, and EA-MADM's verdict against it
/// with the number that decides it; "none run" when the task has no control.
fn strongest_cells(verdicts: &Verdicts, claim: &str, task: &str) -> (String, String) {
    verdicts
        .against_strongest
        .iter()
        .find(|c| c.judgement.claim.id == claim && c.judgement.task == task)
        .map_or_else(
            || ("none run".to_owned(), "—".to_owned()),
            |c| {
                (
                    format!(
                        "`{}` ({}; IQM `{}` {})",
                        c.control,
                        control_family(&c.control).unwrap_or("control"),
                        c.metric,
                        number(c.control_iqm)
                    ),
                    format!(
                        "{}: {}",
                        c.judgement.verdict.name(),
                        deciding_words(&c.judgement, false)
                    ),
                )
            },
        )
}

/// Whether the claim × task's verdict survives every reading of the paper run by the
/// sensitivity runs: `yes`, `no`, or `not run` when none was run.
fn survives_cell(verdicts: &Verdicts, claim: &str, task: &str) -> String {
    verdicts
        .survives_readings
        .iter()
        .find(|s| s.claim == claim && s.task == task)
        .map_or_else(
            || "not run".to_owned(),
            |s| if s.holds { "yes" } else { "no" }.to_owned(),
        )
}

pub(crate) fn write_verdicts(text: &mut String, context: &ReportContext, verdicts: &Verdicts) {
    let _ = writeln!(text, "## Verdicts on the paper's claims\n");
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("task", Align::Left),
        ("verdict (EA-MADM vs the paper's competitors)", Align::Left),
        ("the number that decides it", Align::Left),
        ("strongest control", Align::Left),
        ("verdict vs the strongest control", Align::Left),
        ("survives the readings", Align::Left),
    ]);
    for claim in &CLAIMS {
        for task in claims::tasks(&verdicts.scores) {
            if !claim.tasks.contains(&task) {
                continue;
            }
            let paper_method = verdicts.paper_ea_madm(task);
            let judgement = verdicts.judgements.iter().find(|j| {
                j.claim.id == claim.id && j.task == task && Some(j.method.as_str()) == paper_method
            });
            let (verdict, number) = judgement.map_or_else(
                || ("not run".to_owned(), "EA-MADM was not run".to_owned()),
                |j| {
                    (
                        format!("**{}**", j.verdict.name()),
                        table_deciding_number(j),
                    )
                },
            );
            let (control, control_verdict) = strongest_cells(verdicts, claim.id, task);
            let _ = table.push_row([
                claim.id.to_owned(),
                context.task_title(task),
                verdict,
                number,
                control,
                control_verdict,
                survives_cell(verdicts, claim.id, task),
            ]);
        }
    }
    if verdicts.judgements.is_empty() {
        let _ = writeln!(
            text,
            "None of the paper's claims is made on the tasks of this run (the claims are about \
             {}).\n",
            context
                .paper_tasks
                .iter()
                .map(|t| t.title.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );
    } else {
        text.push_str(&table.render());
        text.push('\n');
    }
    let _ = writeln!(text, "The claims:\n");
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
    let _ = writeln!(
        text,
        "\n**The rule.** Each method under test is compared with each of the paper's \
         competitors (the methods with role `paper` that are not EA-MADM) on every metric of \
         the claim: the difference of interquartile means (IQM) over seeds with a bootstrap \
         95% interval ({} resamples), a two-sided permutation p-value ({} permutations, exact \
         when fewer splits exist), Holm-adjusted across all comparisons of that claim, task and \
         method. A comparison favours one side when its Holm p is below {alpha}, its interval \
         excludes 0 and, for a metric with an equivalence margin on the task (the margins \
         are listed below), the difference exceeds the margin. Runs of one seed share their random streams, so each comparison is also \
         paired by seed: the mean paired difference with a paired bootstrap interval, a \
         sign-flip p-value ({} sign vectors, exact when fewer exist) and a TOST p-value of \
         equivalence within the margin (claims.csv: `paired_*`, `p_equivalence`). The \
         verdict is **supported** when every comparison favours EA-MADM, **contradicted** \
         when any favours a competitor, **equivalent** when every comparison is equivalent \
         (Holm-adjusted TOST p below {alpha}), **inconclusive** otherwise, and \
         **untestable** when no competitor has 2 seeds with a value. A method with fewer than \
         2 seeds with a value (it seldom or never reaches the target) is judged on per-seed \
         reaching instead (a seed reaches when its greedy episode or any training episode \
         does): against each competitor the exact paired sign test on the seeds only one of \
         the two reaches on (McNemar), Holm-adjusted across the competitors; \
         **contradicted** when a competitor reaches on more seeds with a Holm p below \
         {alpha}, **inconclusive** when one reaches on 2 or more seeds but not significantly \
         more, **untestable** when none does (neither reaches), each with the counts \
         (claims.csv: metric `reached`). **C3** is judged on the greedy policy evaluated \
         every few training episodes without exploration or learning: a seed is \
         stable-reaching when each such evaluation in the second half of training reaches the \
         target, and only those seeds have a greedy fluctuation (`fluctuation_greedy_*`), so a \
         seed stuck at the step cap counts as a failure, never as stability. Against each \
         competitor the stable-reaching seeds are compared by the exact paired sign test \
         (claims.csv: metric `stable_reaching`, Holm across competitors) and the greedy \
         fluctuation by the rule above; a comparison favours a side when either does and the \
         other does not favour the other side, and is equivalent when the greedy fluctuations \
         are and the same seeds stable-reach on both sides (the per-seed test has no margin). \
         The fair comparison is ε-decreasing, which uses \
         EA-MADM's ε schedule; a fixed-ε method (ε-greedy) enters on its greedy policy, \
         without its exploration. The training curves' SDs (`fluctuation_steps`, \
         `fluctuation_return`) are reported as secondary rows with no verdict. The deciding \
         number is the weakest comparison of a supported or equivalent claim, the strongest \
         against a contradicted one, and the weakest non-favourable one of an inconclusive \
         one (or the per-seed test when it alone decides).\n",
        verdicts.options.bootstrap.resamples,
        verdicts.options.permutation.resamples,
        verdicts.options.sign_flip.resamples,
        alpha = verdicts.options.alpha
    );
    super::margins::write_margins(text, context, verdicts);

    let variants: Vec<&Judgement> = verdicts
        .judgements
        .iter()
        .filter(|j| Some(j.method.as_str()) != verdicts.paper_ea_madm(&j.task))
        .collect();
    if !variants.is_empty() {
        let _ = writeln!(
            text,
            "### The same claims for EA-MADM's ablations and variants\n\n\
             Each is judged against the paper's competitors by the same rule (controls are \
             marked: they are not in the paper); a repaired robot reading is judged a second \
             time against the competitors trained on its own sub-task rewards, and its reason \
             then opens with those rewards (claims.csv: `versus_set`).\n"
        );
        let mut table = MarkdownTable::new([
            ("claim", Align::Left),
            ("task", Align::Left),
            ("method", Align::Left),
            ("role", Align::Left),
            ("verdict", Align::Left),
            ("the number that decides it", Align::Left),
        ]);
        for j in variants {
            let _ = table.push_row([
                j.claim.id.to_owned(),
                context.task_title(&j.task),
                format!("`{}`", j.method),
                role_text(j.role).to_owned(),
                j.verdict.name().to_owned(),
                deciding_number(j),
            ]);
        }
        text.push_str(&table.render());
        text.push('\n');
    }
}

/// The heading in `REPORT.md` above the verdict table.
pub(crate) const VERDICTS_HEADING: &str = "## Verdicts on the paper's claims";

/// The README's verdict block: the verdict table of `report` (the lines of its first table
/// under the verdicts heading), then one line per claim.
pub fn readme_verdicts(report: &str) -> Result<String, String> {
    let after = report
        .split_once(VERDICTS_HEADING)
        .map(|(_, rest)| rest)
        .ok_or_else(|| format!("REPORT.md has no `{VERDICTS_HEADING}` section"))?;
    let table: Vec<&str> = after
        .lines()
        .skip_while(|line| !line.starts_with('|'))
        .take_while(|line| line.starts_with('|'))
        .collect();
    if table.len() < 3 {
        return Err("REPORT.md's verdict section has no table".to_owned());
    }
    let mut text = table.join("\n");
    text.push_str("\n\n");
    for claim in &CLAIMS {
        let _ = writeln!(
            text,
            "- **{}**: {}. {}.",
            claim.id, claim.words, claim.location
        );
    }
    Ok(text)
}
