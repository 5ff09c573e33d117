//! `REPORT.md`, `final-scores.csv` and `claims.csv`: the verdicts on the paper's claims first,
//! then per task the numbers behind them. Every number comes from [`eamadm::scores`] and
//! [`eamadm::claims`]; this module only lays them out, and every sentence that states a result
//! is chosen by the numbers (tests flip the numbers and watch the sentence flip).
//!
//! The text is a pure function of the scores (no paths, dates or timings), so an interrupted
//! and resumed run writes the same bytes as an uninterrupted one.

use std::fmt::Write as _;
use std::path::Path;

use eamadm::Role;
use eamadm::claims::{
    self, ClaimOptions, ClaimsError, Comparison, ControlComparison, Estimate, Judgement,
    MethodOverview, Outcome,
};
use eamadm::paper::{self, CLAIMS, PaperTask, method_title};
use eamadm::scores::{self, FinalScore, ScoresError};
use eamadm::sensitivity::SensitivityRow;
use eamadm::stats::Interval;
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};
use crate::experiments::PlannedExperiment;
use crate::outputs::WrittenFigures;
use crate::report::{Align, MarkdownTable, decimals_for, format_fixed};

/// Writing the claim outputs failed.
#[derive(Debug, Error)]
pub(crate) enum ClaimsReportError {
    /// `final-scores.csv`.
    #[error("final-scores.csv: {0}")]
    Scores(#[from] ScoresError),
    /// `claims.csv` or a statistic.
    #[error(transparent)]
    Claims(#[from] ClaimsError),
    /// Writing a file.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
}

/// Everything the report states: the per-seed scores and what eamadm computes from them.
#[derive(Debug, Clone)]
pub(crate) struct Verdicts {
    /// One row per task, method and seed.
    pub(crate) scores: Vec<FinalScore>,
    /// One per claim × task × method under test.
    pub(crate) judgements: Vec<Judgement>,
    /// IQM with interval per task × method × claim metric.
    pub(crate) estimates: Vec<Estimate>,
    /// Success shares, distributions and step budgets per task × method.
    pub(crate) overviews: Vec<MethodOverview>,
    /// The paper's EA-MADM against each control.
    pub(crate) controls: Vec<ControlComparison>,
    /// The settings the comparisons were made with.
    pub(crate) options: ClaimOptions,
    /// The paper's EA-MADM judged again under each reading of the paper (filled by the caller
    /// when readings ran; empty otherwise).
    pub(crate) sensitivity: Vec<SensitivityRow>,
}

impl Verdicts {
    /// Judges the claims on `scores`.
    pub(crate) fn compute(
        scores: Vec<FinalScore>,
        options: &ClaimOptions,
    ) -> Result<Self, ClaimsError> {
        Ok(Self {
            judgements: claims::judge(&scores, options)?,
            estimates: claims::estimates(&scores, options)?,
            overviews: claims::overview(&scores)?,
            controls: claims::control_comparisons(&scores, options)?,
            scores,
            options: *options,
            sensitivity: Vec::new(),
        })
    }

    fn estimate(&self, task: &str, method: &str, metric: &str) -> Option<&Estimate> {
        self.estimates
            .iter()
            .find(|e| e.task == task && e.method == method && e.metric == metric)
    }

    /// The paper's EA-MADM on `task`: the first method under test with role `paper`.
    fn paper_ea_madm(&self, task: &str) -> Option<&str> {
        claims::methods(&self.scores, task)
            .into_iter()
            .find(|&(_, role, kind)| role == Role::Paper && claims::is_under_test(kind))
            .map(|(method, _, _)| method)
    }
}

/// Writes `final-scores.csv`, `claims.csv` and `REPORT.md` into `out`. `figures` holds, per
/// experiment, the figure files written for it; `behaviour`, per experiment, the markdown that
/// explains each method's behaviour (empty where there is none).
pub(crate) fn write_claim_outputs(
    out: &Path,
    experiments: &[PlannedExperiment],
    figures: &[WrittenFigures],
    behaviour: &[String],
    verdicts: &Verdicts,
    quick: bool,
) -> Result<(), ClaimsReportError> {
    let mut scores_csv = Vec::new();
    scores::write_csv(&verdicts.scores, &mut scores_csv)?;
    write_atomic(&out.join("final-scores.csv"), &scores_csv)?;
    let mut claims_csv = Vec::new();
    let mut rows = claims::rows(&verdicts.judgements, &verdicts.estimates);
    rows.extend(claims::outcome_rows(&verdicts.scores)?);
    claims::write_csv(&rows, &mut claims_csv)?;
    write_atomic(&out.join("claims.csv"), &claims_csv)?;
    crate::sensitivity_report::write_sensitivity_csv(out, &verdicts.sensitivity)?;
    let report = render_report(experiments, figures, behaviour, verdicts, quick);
    let report = with_answer(
        report,
        &String::from_utf8_lossy(&claims_csv),
        &String::from_utf8_lossy(&scores_csv),
    );
    write_atomic(&out.join("REPORT.md"), report.as_bytes())?;
    Ok(())
}

/// `report` with the answer paragraph the README states
/// ([`readme::answer_from_csv`](crate::readme::answer_from_csv)) on top, before the verdict
/// table, computed from the same `claims.csv` and `final-scores.csv`. A plan
/// without EA-MADM's verdicts (a config of one's own) has no such answer: the report then opens
/// with the table, as before.
fn with_answer(report: String, claims_csv: &str, scores_csv: &str) -> String {
    const VERDICTS: &str = "## Verdicts on the paper's claims";
    let (Ok(answer), Some(at)) = (
        crate::readme::answer_from_csv(claims_csv, scores_csv),
        report.find(VERDICTS),
    ) else {
        return report;
    };
    format!(
        "{}## The answer\n\n{answer}\n\n{}",
        &report[..at],
        &report[at..]
    )
}

/// A number to three significant digits (no decimals from 100 up).
fn number(value: f64) -> String {
    format_fixed(value, decimals_for(value, 3))
}

/// `estimate [low, high]`, rounded to two significant digits of the interval's width, and
/// finer where that would round a non-zero number to 0 (each keeps at least one significant
/// digit): a difference of 0.39 [0.31, 12.7] that decides a verdict must not read "0 [0, 13]".
fn interval(i: &Interval) -> String {
    let width = i.high - i.low;
    let by_width = if width > 1e-9 * i.estimate.abs().max(1.0) {
        // The nudge keeps a width like 73.1 − 73.0 = 0.0999… at the precision of 0.1.
        decimals_for(width * (1.0 + 1e-9), 2)
    } else {
        decimals_for(i.estimate, 3)
    };
    let decimals = [i.estimate, i.low, i.high]
        .into_iter()
        .filter(|&x| x != 0.0)
        .map(|x| decimals_for(x, 1))
        .fold(by_width, usize::max);
    format!(
        "{} [{}, {}]",
        format_fixed(i.estimate, decimals),
        format_fixed(i.low, decimals),
        format_fixed(i.high, decimals)
    )
}

/// A p-value: three decimals, or `< 0.001`.
fn p_value(p: f64) -> String {
    if p < 0.001 {
        "< 0.001".to_owned()
    } else {
        format_fixed(p, 3)
    }
}

/// A share as a percentage with its Wilson interval: `62% [55, 69]`.
fn share(s: &claims::Share) -> String {
    format!(
        "{}/{} = {}% [{}, {}]",
        s.successes,
        s.trials,
        format_fixed(s.wilson.estimate * 100.0, 0),
        format_fixed(s.wilson.low * 100.0, 0),
        format_fixed(s.wilson.high * 100.0, 0)
    )
}

fn task_title(task: &str, experiments: &[PlannedExperiment]) -> String {
    experiments
        .iter()
        .find(|p| p.name == task)
        .map(|p| p.title.clone())
        .or_else(|| PaperTask::from_name(task).map(|t| t.title().to_owned()))
        .unwrap_or_else(|| task.to_owned())
}

/// The one number a verdict rests on, in words.
fn deciding_number(judgement: &Judgement) -> String {
    match judgement.deciding_comparison() {
        Some(c) if judgement.verdict == claims::Verdict::Equivalent => match &c.paired {
            Some(p) => format!(
                "vs {}: paired Δ mean `{}` = {} within ±{}, TOST Holm p {}",
                method_title(&c.versus),
                c.metric.column,
                interval(&p.difference),
                p.margin.map_or_else(|| "—".to_owned(), number),
                p_value(p.p_equivalence_holm.unwrap_or(1.0))
            ),
            None => comparison_in_words(c),
        },
        Some(c) => comparison_in_words(c),
        None => judgement.reason.clone(),
    }
}

fn comparison_in_words(c: &Comparison) -> String {
    format!(
        "vs {}: Δ IQM `{}` = {}, Holm p {}",
        method_title(&c.versus),
        c.metric.column,
        interval(&c.difference),
        p_value(c.p_holm)
    )
}

/// Renders `REPORT.md`.
pub(crate) fn render_report(
    experiments: &[PlannedExperiment],
    figures: &[WrittenFigures],
    behaviour: &[String],
    verdicts: &Verdicts,
    quick: bool,
) -> String {
    let mut text = String::from("# EA-MADM reproduction report\n\n");
    let _ = writeln!(
        text,
        "Made by `cargo xtask reproduce-paper`{}. Do not edit: rerun the command. The per-seed \
         scores are in [final-scores.csv](final-scores.csv), every estimate and comparison in \
         [claims.csv](claims.csv).\n",
        if quick {
            " --quick (a smoke run: few seeds and episodes; these numbers mean little)"
        } else {
            ""
        }
    );
    write_verdicts(&mut text, experiments, verdicts);
    crate::sensitivity_report::write_sensitivity(&mut text, experiments, &verdicts.sensitivity);
    write_method(&mut text, verdicts);
    for (index, planned) in experiments.iter().enumerate() {
        write_task(
            &mut text,
            planned,
            figures.get(index),
            behaviour.get(index).map_or("", String::as_str),
            verdicts,
        );
    }
    write_paper_numbers(&mut text, experiments, verdicts);
    text
}

fn write_verdicts(text: &mut String, experiments: &[PlannedExperiment], verdicts: &Verdicts) {
    let _ = writeln!(text, "## Verdicts on the paper's claims\n");
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("task", Align::Left),
        ("verdict (EA-MADM)", Align::Left),
        ("the number that decides it", Align::Left),
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
                |j| (format!("**{}**", j.verdict.name()), deciding_number(j)),
            );
            let _ = table.push_row([
                claim.id.to_owned(),
                task_title(task, experiments),
                verdict,
                number,
            ]);
        }
    }
    if verdicts.judgements.is_empty() {
        let _ = writeln!(
            text,
            "None of the paper's claims is made on the tasks of this run (the claims are about \
             {}).\n",
            PaperTask::ALL.map(PaperTask::title).join(", ")
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
         excludes 0 and, for a metric with an equivalence margin (2 steps for `final_steps` \
         and `fluctuation_steps`: the shortest detour on a grid), the difference exceeds the \
         margin. Runs of one seed share their random streams, so each comparison is also \
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
         (claims.csv: metric `reached`). The deciding number is the weakest comparison of a \
         supported or equivalent claim, the strongest against a contradicted one, and the \
         weakest non-favourable one of an inconclusive one.\n",
        verdicts.options.bootstrap.resamples,
        verdicts.options.permutation.resamples,
        verdicts.options.sign_flip.resamples,
        alpha = verdicts.options.alpha
    );

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
             marked: they are not in the paper).\n"
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
                task_title(&j.task, experiments),
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

fn role_text(role: Role) -> &'static str {
    match role {
        Role::Paper => "paper",
        Role::Ablation => "ablation",
        Role::Control => "control, not in the paper",
    }
}

fn write_method(text: &mut String, verdicts: &Verdicts) {
    let _ = writeln!(
        text,
        "## How the scores are made\n\n\
         - **Final** steps and return: per seed the mean over the last {} training episodes; \
         tables show the IQM over seeds with its bootstrap 95% interval.\n\
         - **Fluctuation** (C3): per seed the sample standard deviation of steps and of return \
         over the second half of training. These are training curves, so exploration is in \
         them: a fixed-ε method (ε-greedy, ε = 0.1) keeps exploring to the end, while the \
         decreasing schedules of ε-decreasing and EA-MADM hardly explore in the second half.\n\
         - **Robot** (C4): over a run's first {} training episodes that reach the target (the \
         paper's \"100 episodes that are to reach the target\"): mean average reward (return \
         per second), mean time to reach, and the least-squares slope of retention time over \
         the reaching-episode index (`retention_decay`, seconds per reaching episode; more \
         negative falls faster). A seed with no reaching episode has no C4 value; a method \
         whose seeds never reach is shown as \"never reaches\" and is never ranked.\n\
         - **Success**: final-window training episodes that reached the target, pooled over \
         seeds, with a Wilson 95% interval (episodes of one seed are not independent, so it is \
         too narrow); **greedy reached**: seeds whose greedy episode after training reached \
         it, with a Wilson interval over seeds.\n\
         - **Environment steps** count every step of a run, sub-task pre-training included.\n\
         - Bootstrap and permutations are seeded (seed {}), so the report is reproducible bit \
         for bit.\n",
        scores::FINAL_WINDOW,
        scores::REACHING_EPISODES,
        verdicts.options.bootstrap.seed
    );
}

fn estimate_cell(verdicts: &Verdicts, task: &str, method: &str, metric: &str) -> String {
    match verdicts.estimate(task, method, metric) {
        Some(Estimate { iqm: Some(i), .. }) => interval(i),
        Some(_) => "never reaches".to_owned(),
        None => "—".to_owned(),
    }
}

fn write_task(
    text: &mut String,
    planned: &PlannedExperiment,
    figures: Option<&WrittenFigures>,
    behaviour: &str,
    verdicts: &Verdicts,
) {
    let task = planned.name.as_str();
    let config = planned.config();
    let _ = writeln!(text, "## {} (`{task}`)\n", planned.title);
    let overviews: Vec<&MethodOverview> = verdicts
        .overviews
        .iter()
        .filter(|o| o.task == task)
        .collect();
    let step_cap = overviews.iter().find_map(|o| o.step_cap);
    let optimum = verdicts
        .scores
        .iter()
        .find(|s| s.task == task)
        .and_then(|s| s.optimum_steps);
    let _ = writeln!(
        text,
        "{} episodes, {} seeds per method{}{}.\n",
        config.episodes,
        config.seeds,
        step_cap.map_or_else(String::new, |cap| format!(", step cap {cap}")),
        optimum.map_or_else(String::new, |o| format!(", optimum route {o} steps")),
    );
    let columns = [
        ("method", Align::Left),
        ("role", Align::Left),
        ("final steps", Align::Right),
        ("final return", Align::Right),
        ("fluctuation steps", Align::Right),
        ("fluctuation return", Align::Right),
        ("training success", Align::Right),
        ("greedy reached", Align::Right),
        ("env steps (pre-training)", Align::Right),
    ];
    let row = |o: &MethodOverview| {
        [
            method_title(&o.method),
            role_text(o.role).to_owned(),
            estimate_cell(verdicts, task, &o.method, "final_steps"),
            estimate_cell(verdicts, task, &o.method, "final_return"),
            estimate_cell(verdicts, task, &o.method, "fluctuation_steps"),
            estimate_cell(verdicts, task, &o.method, "fluctuation_return"),
            share(&o.training_success),
            share(&o.greedy_success),
            format!(
                "{} ({})",
                format_fixed(o.env_steps_total, 0),
                format_fixed(o.pretrain_env_steps, 0)
            ),
        ]
    };
    let mut table = MarkdownTable::new(columns);
    for o in overviews.iter().filter(|o| o.role != Role::Control) {
        let _ = table.push_row(row(o));
    }
    let _ = writeln!(
        text,
        "IQM over seeds [bootstrap 95% interval]; shares with Wilson 95% intervals; mean \
         environment steps per run (of which sub-task pre-training):\n"
    );
    text.push_str(&table.render());
    text.push('\n');

    let controls: Vec<&&MethodOverview> = overviews
        .iter()
        .filter(|o| o.role == Role::Control)
        .collect();
    if !controls.is_empty() {
        let _ = writeln!(
            text,
            "### Controls (control, not in the paper)\n\n\
             Comparisons the paper does not run; they explain the result and never enter the \
             paper's verdicts.\n"
        );
        let mut table = MarkdownTable::new(columns);
        for o in &controls {
            let _ = table.push_row(row(o));
        }
        text.push_str(&table.render());
        text.push('\n');
        write_control_comparisons(text, task, verdicts);
    }

    write_comparisons(text, task, verdicts);
    write_distributions(text, &overviews);
    for sentence in explanations(task, &overviews, verdicts) {
        let _ = writeln!(text, "- {sentence}");
    }
    text.push('\n');
    if matches!(
        PaperTask::from_name(task),
        Some(PaperTask::Robot | PaperTask::RobotPaperState)
    ) || verdicts
        .scores
        .iter()
        .any(|s| s.task == task && s.reach_time.is_some())
    {
        write_robot(text, task, &overviews, verdicts);
    }
    text.push_str(behaviour);
    if let Some(figures) = figures.filter(|f| !f.files.is_empty()) {
        text.push_str(&figures.gallery);
        let _ = writeln!(
            text,
            "Tables: [curves]({task}/{}) (gzip), [trajectories]({task}/trajectories.csv).\n",
            crate::finish::CURVES_FILE
        );
    }
}

fn write_control_comparisons(text: &mut String, task: &str, verdicts: &Verdicts) {
    let rows: Vec<&ControlComparison> = verdicts
        .controls
        .iter()
        .filter(|c| c.task == task)
        .collect();
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "EA-MADM against each control (Δ = IQM of EA-MADM − IQM of the control; raw p, not \
         adjusted, since these comparisons enter no verdict):\n"
    );
    let mut table = MarkdownTable::new([
        ("control", Align::Left),
        ("metric", Align::Left),
        ("Δ IQM [95%]", Align::Right),
        ("p", Align::Right),
        ("P(EA-MADM better)", Align::Right),
    ]);
    for c in rows {
        let _ = table.push_row([
            format!("`{}`", c.comparison.versus),
            format!("`{}`", c.comparison.metric.column),
            interval(&c.comparison.difference),
            p_value(c.comparison.p_value),
            format_fixed(c.comparison.p_improvement, 2),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
}

fn write_comparisons(text: &mut String, task: &str, verdicts: &Verdicts) {
    let Some(method) = verdicts.paper_ea_madm(task) else {
        return;
    };
    let judgements: Vec<&Judgement> = verdicts
        .judgements
        .iter()
        .filter(|j| j.task == task && j.method == method)
        .collect();
    if judgements
        .iter()
        .all(|j| j.comparisons.is_empty() && j.untested.is_empty())
    {
        return;
    }
    let _ = writeln!(
        text,
        "EA-MADM against each competitor (Δ = IQM of EA-MADM − IQM of the competitor):\n"
    );
    let mut table = MarkdownTable::new([
        ("claim", Align::Left),
        ("metric", Align::Left),
        ("versus", Align::Left),
        ("Δ IQM [95%]", Align::Right),
        ("p", Align::Right),
        ("Holm p", Align::Right),
        ("P(EA-MADM better)", Align::Right),
        ("settles", Align::Left),
    ]);
    for j in &judgements {
        for c in &j.comparisons {
            let _ = table.push_row([
                j.claim.id.to_owned(),
                format!("`{}`", c.metric.column),
                method_title(&c.versus),
                interval(&c.difference),
                p_value(c.p_value),
                p_value(c.p_holm),
                format_fixed(c.p_improvement, 2),
                match c.outcome {
                    Outcome::FavoursMethod => "EA-MADM better".to_owned(),
                    Outcome::FavoursCompetitor => format!("{} better", method_title(&c.versus)),
                    Outcome::Unsettled => "nothing".to_owned(),
                },
            ]);
        }
        for u in &j.untested {
            let _ = table.push_row([
                j.claim.id.to_owned(),
                format!("`{}`", u.metric),
                method_title(&u.versus),
                "—".to_owned(),
                "—".to_owned(),
                "—".to_owned(),
                "—".to_owned(),
                format!("untestable: {}", u.reason),
            ]);
        }
    }
    text.push_str(&table.render());
    text.push('\n');
}

fn write_distributions(text: &mut String, overviews: &[&MethodOverview]) {
    let bimodal: Vec<&&MethodOverview> =
        overviews.iter().filter(|o| o.final_steps.bimodal).collect();
    if bimodal.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "Per-seed final steps are bimodal for these methods (an IQM hides this; seeds at the \
         step cap never finished an episode in the final window):\n"
    );
    let mut table = MarkdownTable::new([
        ("method", Align::Left),
        ("seeds", Align::Right),
        ("at the cap", Align::Right),
        ("min", Align::Right),
        ("q1", Align::Right),
        ("median", Align::Right),
        ("q3", Align::Right),
        ("max", Align::Right),
    ]);
    for o in bimodal {
        let d = &o.final_steps;
        let _ = table.push_row([
            method_title(&o.method),
            d.n.to_string(),
            d.at_cap.to_string(),
            number(d.min),
            number(d.q1),
            number(d.median),
            number(d.q3),
            number(d.max),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
}

/// Sentences on numbers that need explaining, each chosen by the numbers.
fn explanations(task: &str, overviews: &[&MethodOverview], verdicts: &Verdicts) -> Vec<String> {
    let mut sentences = Vec::new();
    for o in overviews.iter().filter(|o| o.role == Role::Paper) {
        if let Some(sentence) = training_versus_greedy(o) {
            sentences.push(sentence);
        }
    }
    if let Some(sentence) = step_budget(overviews) {
        sentences.push(sentence);
    }
    sentences.extend(identical_methods(task, verdicts));
    sentences
}

/// Whether training success and greedy success disagree, and how.
fn training_versus_greedy(o: &MethodOverview) -> Option<String> {
    let training = o.training_success.wilson;
    let greedy = o.greedy_success.wilson;
    if training.low > greedy.high {
        let looping = if o.greedy_at_cap > 0 {
            format!(
                "; in {} of the {} failing seeds the greedy episode runs to the step cap, so the \
                 frozen greedy policy loops where exploration had broken the loop",
                o.greedy_at_cap,
                o.greedy_success.trials - o.greedy_success.successes
            )
        } else {
            String::new()
        };
        Some(format!(
            "{} reaches the target in {} of its final-window training episodes but its greedy \
             policy after training only in {} seeds{looping}.",
            method_title(&o.method),
            share(&o.training_success),
            share(&o.greedy_success)
        ))
    } else if greedy.low > training.high {
        Some(format!(
            "{}'s greedy policy after training reaches the target more often ({} seeds) than \
             its final-window training episodes do ({}): exploration costs it episodes.",
            method_title(&o.method),
            share(&o.greedy_success),
            share(&o.training_success)
        ))
    } else {
        None
    }
}

/// The step budgets of EA-MADM and the competitors, when they differ.
fn step_budget(overviews: &[&MethodOverview]) -> Option<String> {
    let ea = overviews
        .iter()
        .find(|o| o.role == Role::Paper && claims::is_under_test(&o.kind))?;
    let competitors: Vec<&&MethodOverview> = overviews
        .iter()
        .filter(|o| claims::is_competitor(o.role, &o.kind))
        .collect();
    let most = competitors
        .iter()
        .map(|o| o.env_steps_total)
        .fold(f64::NAN, f64::max);
    if competitors.is_empty() || ea.env_steps_total <= most {
        return None;
    }
    Some(format!(
        "EA-MADM's runs use {} environment steps each, {} of them in sub-task pre-training \
         (on the sub-tasks' shaped rewards), against at most {} for a competitor: {}× the \
         budget. The controls (when run) ask what an equal budget or equal reward \
         information gives the competitors.",
        format_fixed(ea.env_steps_total, 0),
        format_fixed(ea.pretrain_env_steps, 0),
        format_fixed(most, 0),
        format_fixed(ea.env_steps_total / most, 1)
    ))
}

/// Methods whose per-seed scores equal the paper's EA-MADM's exactly.
fn identical_methods(task: &str, verdicts: &Verdicts) -> Option<String> {
    let ea = verdicts.paper_ea_madm(task)?;
    let rows_of = |method: &str| -> Vec<&FinalScore> {
        verdicts
            .scores
            .iter()
            .filter(|s| s.task == task && s.method == method)
            .collect()
    };
    let reference = rows_of(ea);
    let same_numbers = |a: &FinalScore, b: &FinalScore| {
        a.seed == b.seed
            && a.final_steps == b.final_steps
            && a.final_return == b.final_return
            && a.fluctuation_steps == b.fluctuation_steps
            && a.fluctuation_return == b.fluctuation_return
            && a.env_steps_total == b.env_steps_total
            && a.greedy_steps == b.greedy_steps
    };
    let same: Vec<String> = claims::methods(&verdicts.scores, task)
        .into_iter()
        .filter(|&(method, _, _)| method != ea)
        .filter(|&(method, _, _)| {
            let rows = rows_of(method);
            rows.len() == reference.len()
                && rows.iter().zip(&reference).all(|(a, b)| same_numbers(a, b))
        })
        .map(|(method, _, _)| format!("`{method}`"))
        .collect();
    (!same.is_empty()).then(|| {
        format!(
            "{} {} exactly EA-MADM's per-seed scores: {} sub-task experience answers every \
             lookup as EA-MADM's exact tree does (a table, or a tree whose thresholds merge no \
             two states), so {} not exercise the tree's aggregation.",
            same.join(", "),
            if same.len() == 1 { "gives" } else { "give" },
            if same.len() == 1 { "its" } else { "their" },
            if same.len() == 1 {
                "it does"
            } else {
                "they do"
            },
        )
    })
}

fn write_robot(text: &mut String, task: &str, overviews: &[&MethodOverview], verdicts: &Verdicts) {
    let _ = writeln!(
        text,
        "Robot metrics over reaching episodes (C4; Fig. 13–15 analogues), IQM over the seeds \
         that reach [95%]:\n"
    );
    let mut table = MarkdownTable::new([
        ("method", Align::Left),
        ("seeds reaching", Align::Right),
        ("average reward", Align::Right),
        ("reaching time (s)", Align::Right),
        ("retention decay (s / episode)", Align::Right),
    ]);
    for o in overviews {
        let _ = table.push_row([
            method_title(&o.method),
            format!("{}/{}", o.reaching_seeds, o.seeds),
            estimate_cell(verdicts, task, &o.method, "reach_average_reward"),
            estimate_cell(verdicts, task, &o.method, "reach_time"),
            estimate_cell(verdicts, task, &o.method, "retention_decay"),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
    let _ = writeln!(text, "{}\n", robot_ranking(task, overviews, verdicts));
}

/// Which method leads on the robot's average reward, among methods that reach the target in
/// at least two seeds; never a ranking of methods that do not reach it.
fn robot_ranking(task: &str, overviews: &[&MethodOverview], verdicts: &Verdicts) -> String {
    let reaching: Vec<(&MethodOverview, Interval)> = overviews
        .iter()
        .filter_map(|o| {
            verdicts
                .estimate(task, &o.method, "reach_average_reward")
                .filter(|e| e.n >= 2)
                .and_then(|e| e.iqm)
                .map(|i| (*o, i))
        })
        .collect();
    let never: Vec<String> = overviews
        .iter()
        .filter(|o| o.reaching_seeds == 0)
        .map(|o| method_title(&o.method))
        .collect();
    let never_text = if never.is_empty() {
        String::new()
    } else {
        format!(" Never reaches the target: {}.", never.join(", "))
    };
    match reaching
        .iter()
        .max_by(|a, b| a.1.estimate.total_cmp(&b.1.estimate))
    {
        None => format!(
            "No method reaches the target in two or more seeds, so the robot's methods are not \
             ranked and C4's metrics cannot be compared here.{never_text}"
        ),
        Some((best, i)) => format!(
            "Among the {} methods that reach the target in two or more seeds, {} has the \
             highest IQM average reward over its reaching episodes ({}).{never_text}",
            reaching.len(),
            method_title(&best.method),
            interval(i)
        ),
    }
}

fn write_paper_numbers(text: &mut String, experiments: &[PlannedExperiment], verdicts: &Verdicts) {
    let rows: Vec<(PaperTask, &str)> = claims::tasks(&verdicts.scores)
        .into_iter()
        .filter_map(|task| PaperTask::from_name(task).map(|t| (t, task)))
        .filter(|(t, _)| t.reported().is_some())
        .collect();
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(text, "## The paper's numbers beside ours\n");
    let mut table = MarkdownTable::new([
        ("task", Align::Left),
        ("paper: EA-MADM steps", Align::Right),
        ("paper: EA-MADM return", Align::Right),
        ("ours: EA-MADM final steps", Align::Right),
        ("ours: EA-MADM final return", Align::Right),
        ("our optimum", Align::Right),
    ]);
    for (paper_task, task) in rows {
        let Some(reported) = paper_task.reported() else {
            continue;
        };
        let ea = verdicts.paper_ea_madm(task).unwrap_or("ea-madm");
        let optimum = verdicts
            .scores
            .iter()
            .find(|s| s.task == task)
            .and_then(|s| s.optimum_steps);
        let _ = table.push_row([
            task_title(task, experiments),
            format_fixed(reported.steps, 0),
            format_fixed(reported.task_return, 0),
            estimate_cell(verdicts, task, ea, "final_steps"),
            estimate_cell(verdicts, task, ea, "final_return"),
            optimum.map_or_else(|| "—".to_owned(), |o| o.to_string()),
        ]);
    }
    text.push_str(&table.render());
    let _ = writeln!(
        text,
        "\nThe paper does not publish its mazes; ours are generated with the paper's sizes and \
         obstacle counts (crate `mazes`), so step counts and returns are not directly \
         comparable. The paper shows single runs; we report {} seeds. The robot runs in a 2D \
         model (crate `wmr-model`), not in Webots, and the paper gives no robot numbers.\n",
        experiments
            .first()
            .map_or(paper::SEEDS, |p| p.config().seeds)
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use eamadm::claims::{Share, Verdict};

    fn row(task: &str, method: &str, role: Role, kind: &str, seed: u64, steps: f64) -> FinalScore {
        FinalScore {
            task: task.to_owned(),
            method: method.to_owned(),
            role,
            kind: kind.to_owned(),
            seed,
            episodes: 200,
            final_window: 20,
            final_steps: steps,
            final_return: -steps,
            success_rate: 1.0,
            greedy_reached: true,
            greedy_steps: 80,
            outcome: eamadm::scores::RunOutcome::Converged,
            collapse_episode: None,
            fluctuation_steps: steps / 10.0,
            fluctuation_return: steps / 10.0,
            env_steps_total: 10_000,
            pretrain_env_steps: 0,
            step_cap: Some(2000),
            optimum_steps: Some(58),
            reaching_episodes: 100,
            reach_average_reward: None,
            reach_time: None,
            reach_retention_time: None,
            retention_decay: None,
        }
    }

    /// Task I with EA-MADM at `ea` steps and two competitors at 100 + seed noise.
    fn scores(ea: f64) -> Vec<FinalScore> {
        let mut rows = Vec::new();
        for seed in 0..8 {
            let noise = seed as f64;
            rows.push(row(
                "task1",
                "ea-madm",
                Role::Paper,
                "ea_madm",
                seed,
                ea + noise,
            ));
        }
        for method in ["epsilon-greedy", "softmax"] {
            for seed in 0..8 {
                let noise = seed as f64;
                let kind = if method == "softmax" {
                    "softmax"
                } else {
                    "epsilon_greedy"
                };
                rows.push(row("task1", method, Role::Paper, kind, seed, 100.0 + noise));
            }
        }
        rows
    }

    fn options() -> ClaimOptions {
        ClaimOptions {
            bootstrap: eamadm::stats::Bootstrap::new(2000, 0.95, 0).unwrap(),
            permutation: eamadm::stats::PermutationTest::new(2000, 0).unwrap(),
            sign_flip: eamadm::stats::SignFlipTest::new(2000, 0).unwrap(),
            alpha: 0.05,
        }
    }

    fn verdict_row(report: &str, claim: &str) -> String {
        report
            .lines()
            .find(|l| l.starts_with(&format!("| {claim} ")))
            .unwrap()
            .to_owned()
    }

    #[test]
    fn the_report_opens_with_the_readmes_answer_when_ea_madm_has_verdicts() {
        let report = "# R\n\nintro\n\n## Verdicts on the paper's claims\n\ntable\n".to_owned();
        let claims = "claim,task,method,role,metric,versus,n,estimate,ci_low,ci_high,p_holm,outcome,verdict\n\
                      C4,robot,ea-madm,paper,final_steps,,0,,,,,,untestable\n";
        let scores = "task,method,role,kind,seed,success_rate,env_steps_total\n\
                      robot,ea-madm,paper,ea_madm,0,0.0,1\n\
                      robot,ea-madm,paper,ea_madm,1,0.0,1\n\
                      robot,softmax,paper,softmax,0,0.25,1\n\
                      robot,softmax,paper,softmax,1,0.35,1\n";
        let answer = crate::readme::answer_from_csv(claims, scores).unwrap();
        assert_eq!(
            with_answer(report.clone(), claims, scores),
            format!(
                "# R\n\nintro\n\n## The answer\n\n{answer}\n\n## Verdicts on the paper's claims\n\ntable\n"
            )
        );
        // Without EA-MADM's verdicts (a config of one's own) the report is left as it was.
        let other = claims.replace("ea-madm", "my-method");
        assert_eq!(with_answer(report.clone(), &other, scores), report);
    }

    #[test]
    fn the_verdict_sentence_follows_the_numbers() {
        let better = Verdicts::compute(scores(60.0), &options()).unwrap();
        let report = render_report(&[], &[], &[], &better, false);
        assert!(!report.contains("control, not in the paper"), "{report}");
        assert!(
            verdict_row(&report, "C1").contains("**supported**"),
            "{report}"
        );
        // C2 is higher return: EA-MADM's return is −steps, so it is supported too.
        assert!(
            verdict_row(&report, "C2").contains("**supported**"),
            "{report}"
        );
        let worse = Verdicts::compute(scores(140.0), &options()).unwrap();
        let report = render_report(&[], &[], &[], &worse, false);
        assert!(
            verdict_row(&report, "C1").contains("**contradicted**"),
            "{report}"
        );
        // Identical per seed: equivalent within the 2-step margin on steps; return has no
        // margin and stays inconclusive.
        let same = Verdicts::compute(scores(100.0), &options()).unwrap();
        let report = render_report(&[], &[], &[], &same, false);
        assert!(
            verdict_row(&report, "C1").contains("**equivalent**"),
            "{report}"
        );
        assert!(
            verdict_row(&report, "C2").contains("**inconclusive**"),
            "{report}"
        );
        assert!(report.starts_with("# EA-MADM reproduction report"));
        // A control is judged nowhere but shown as one, with EA-MADM against it.
        let mut with_control = scores(60.0);
        for seed in 0..8 {
            let noise = seed as f64;
            with_control.push(row(
                "task1",
                "softmax-shaped",
                Role::Control,
                "softmax",
                seed,
                50.0 + noise,
            ));
        }
        let verdicts = Verdicts::compute(with_control, &options()).unwrap();
        assert!(verdicts.judgements.iter().all(|j| j.method == "ea-madm"));
        assert!(
            verdicts
                .judgements
                .iter()
                .flat_map(|j| &j.comparisons)
                .all(|c| c.versus != "softmax-shaped")
        );
        let planned =
            crate::experiments::plan_experiments(&[crate::cli::Task::Task1], false, None, 8, true)
                .unwrap();
        let report = render_report(&planned, &[], &[], &verdicts, false);
        assert!(
            report.contains("### Controls (control, not in the paper)"),
            "{report}"
        );
        assert!(
            report.contains("| `softmax-shaped` | `final_steps`"),
            "{report}"
        );
        assert!(report.find("## Verdicts").unwrap() < report.find("## How the scores").unwrap());
    }

    fn overview(training: (u64, u64), greedy: (u64, u64), at_cap: usize) -> MethodOverview {
        let share = |(s, t): (u64, u64)| Share {
            successes: s,
            trials: t,
            wilson: eamadm::stats::wilson(s, t, 0.95).unwrap(),
        };
        MethodOverview {
            task: "task2".into(),
            method: "ea-madm".into(),
            role: Role::Paper,
            kind: "ea_madm".into(),
            seeds: greedy.1 as usize,
            training_success: share(training),
            greedy_success: share(greedy),
            greedy_at_cap: at_cap,
            step_cap: Some(2000),
            final_steps: eamadm::stats::distribution(&[1.0, 2.0], None).unwrap(),
            reaching_seeds: 0,
            env_steps_total: 1.0,
            pretrain_env_steps: 0.0,
        }
    }

    #[test]
    fn training_and_greedy_success_are_explained_only_when_they_differ() {
        let loops = training_versus_greedy(&overview((250, 400), (0, 20), 20)).unwrap();
        assert!(loops.contains("only in 0/20"), "{loops}");
        assert!(loops.contains("in 20 of the 20 failing seeds"), "{loops}");
        let flipped = training_versus_greedy(&overview((0, 400), (20, 20), 0)).unwrap();
        assert!(flipped.contains("more often"), "{flipped}");
        assert_eq!(
            training_versus_greedy(&overview((200, 400), (10, 20), 0)),
            None
        );
    }

    #[test]
    fn the_robot_ranks_only_methods_that_reach() {
        let mut rows = Vec::new();
        for (method, kind, reward) in [("ea-madm", "ea_madm", None), ("softmax", "softmax", None)] {
            for seed in 0..4 {
                let mut r = row("robot", method, Role::Paper, kind, seed, 500.0);
                r.reaching_episodes = 0;
                r.greedy_reached = false;
                r.reach_average_reward = reward;
                rows.push(r);
            }
        }
        let none = Verdicts::compute(rows.clone(), &options()).unwrap();
        let overviews: Vec<&MethodOverview> = none.overviews.iter().collect();
        let sentence = robot_ranking("robot", &overviews, &none);
        assert!(sentence.starts_with("No method reaches"), "{sentence}");
        assert!(
            sentence.contains("Never reaches the target: EA-MADM, softmax"),
            "{sentence}"
        );
        // Neither reaches: C4 stays untestable, with the counts.
        let c4 = none
            .judgements
            .iter()
            .find(|j| j.claim.id == "C4" && j.method == "ea-madm")
            .unwrap();
        assert_eq!(c4.verdict, Verdict::Untestable);
        assert!(
            c4.reason.ends_with(
                "no competitor reaches on 2 or more seeds: EA-MADM reaches on 0/4, softmax 0/4"
            ),
            "{}",
            c4.reason
        );
        for r in rows.iter_mut().filter(|r| r.method == "softmax") {
            r.reaching_episodes = 3;
            r.reach_average_reward = Some(1.0 + r.seed as f64);
        }
        let some = Verdicts::compute(rows, &options()).unwrap();
        let overviews: Vec<&MethodOverview> = some.overviews.iter().collect();
        let sentence = robot_ranking("robot", &overviews, &some);
        assert!(sentence.contains("Among the 1 methods"), "{sentence}");
        assert!(sentence.contains("softmax has the highest"), "{sentence}");
        assert!(
            sentence.contains("Never reaches the target: EA-MADM."),
            "{sentence}"
        );
        // C4 for EA-MADM is judged on per-seed reaching: 0/4 against 4/4 is exact sign test
        // p = 2 / 2⁴ = 0.125 (scipy.stats.binomtest(0, 4, 0.5)), so inconclusive, with the
        // counts and the reason.
        let c4 = some
            .judgements
            .iter()
            .find(|j| j.claim.id == "C4" && j.method == "ea-madm")
            .unwrap();
        assert_eq!(c4.verdict, Verdict::Inconclusive);
        assert_eq!(
            deciding_number(c4),
            "EA-MADM reaches on 0/4 seeds, softmax on 4/4; exact paired sign test, Holm p \
             0.125; EA-MADM has a `reach_average_reward` value in 0 of 4 seeds (it needs a \
             reaching episode)"
        );
    }

    #[test]
    fn numbers_are_rounded_to_their_interval() {
        let i = Interval {
            estimate: 80.1234,
            low: 75.5,
            high: 90.25,
        };
        assert_eq!(interval(&i), "80 [76, 90]");
        let flat = Interval {
            estimate: 2000.0,
            low: 2000.0,
            high: 2000.0,
        };
        assert_eq!(interval(&flat), "2000 [2000, 2000]");
        let tenth = Interval {
            estimate: 73.0,
            low: 73.0,
            high: 73.1,
        };
        assert_eq!(interval(&tenth), "73.00 [73.00, 73.10]");
        // A small estimate in a wide interval keeps a significant digit.
        let small = Interval {
            estimate: 0.385,
            low: 0.307,
            high: 12.68,
        };
        assert_eq!(interval(&small), "0.4 [0.3, 12.7]");
        assert_eq!(p_value(0.0004), "< 0.001");
        assert_eq!(p_value(0.0312), "0.031");
    }
}
