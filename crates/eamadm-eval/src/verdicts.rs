//! The verdicts a run's per-seed scores give: each claim × task × method under test against
//! the paper's competitors ([`claims`]), the paper's EA-MADM against the strongest control of
//! each claim × task and again without the seeds it collapsed on, and whether each verdict
//! survives the readings of the paper ([`crate::sensitivity`]). [`Verdicts`] holds them with
//! the scores they were judged on; [`crate::findings`] states what they say.
//!
//! The **strongest control** of a claim on a task is the control (role `control`, not an
//! EA-MADM variant) with the best IQM of the claim's deciding metric there: the metric of the
//! comparison that decides EA-MADM's verdict against the paper's competitors, else the claim's
//! first metric. EA-MADM is judged against it alone by the very rule of the verdicts
//! ([`claims::judge_against_competitors`]).

use crate::Role;
use crate::claims::{
    self, ClaimOptions, ClaimsError, ControlComparison, Estimate, Judgement, MethodOverview,
};
use crate::facts::ReportContext;
use crate::paper_claims::{Claim, Direction};
use crate::scores::{self, FinalScore, RunOutcome, ScoresError};

/// Everything the report states: the per-seed scores and what [`claims`] computes from them.
#[derive(Debug, Clone)]
pub struct Verdicts {
    /// One row per task, method and seed.
    pub scores: Vec<FinalScore>,
    /// One per claim × task × method under test.
    pub judgements: Vec<Judgement>,
    /// IQM with interval per task × method × claim metric that a verdict or the report
    /// states ([`claims::stated_estimates`]).
    pub estimates: Vec<Estimate>,
    /// Success shares, distributions and step budgets per task × method.
    pub overviews: Vec<MethodOverview>,
    /// The paper's EA-MADM against each control.
    pub controls: Vec<ControlComparison>,
    /// The paper's EA-MADM judged against the strongest control of each claim × task.
    pub against_strongest: Vec<ControlVerdict>,
    /// The paper's EA-MADM judged again without the seeds it collapsed on (see
    /// [`without_collapses`]).
    pub without_collapses: Vec<Judgement>,
    /// Whether each claim × task's verdict survives every reading of the paper the
    /// sensitivity runs try; empty when none was run (the table then says "not run").
    pub survives_readings: Vec<SurvivesReadings>,
    /// The settings the comparisons were made with.
    pub options: ClaimOptions,
    /// The paper's EA-MADM judged again under each reading of the paper (filled by the caller
    /// when readings ran: [`crate::sensitivity::sensitivity`]; empty otherwise).
    pub sensitivity: Vec<crate::sensitivity::SensitivityRow>,
}

/// Whether the paper EA-MADM's verdict on a claim × task holds under every alternative
/// reading of the paper that was run.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SurvivesReadings {
    /// `C1` … `C4`.
    pub claim: String,
    /// The task.
    pub task: String,
    /// True when no reading flips the verdict.
    pub holds: bool,
}

impl Verdicts {
    /// These verdicts with the rows of the readings of the paper (`sensitivity.csv`) and,
    /// from them, whether each claim × task survives every reading (the verdict table's
    /// column).
    #[must_use]
    pub fn with_sensitivity(mut self, rows: Vec<crate::sensitivity::SensitivityRow>) -> Self {
        self.survives_readings = crate::sensitivity::survival(&rows)
            .into_iter()
            .map(|s| SurvivesReadings {
                claim: s.claim.to_owned(),
                task: s.task,
                holds: s.survives,
            })
            .collect();
        self.sensitivity = rows;
        self
    }

    /// Judges the claims on `scores` with `options`; `context` tells which methods are the
    /// controls that can be the strongest (by their configs, [`ReportContext::method`]).
    ///
    /// # Errors
    /// [`ClaimsError`] when a statistic fails.
    pub fn compute(
        scores: Vec<FinalScore>,
        options: &ClaimOptions,
        context: &ReportContext,
    ) -> Result<Self, ClaimsError> {
        let judgements = claims::judge(&scores, options)?;
        let estimates = claims::stated_estimates(&scores, &judgements, options)?;
        Ok(Self {
            against_strongest: against_strongest_controls(
                &scores,
                &judgements,
                &estimates,
                options,
                context,
            )?,
            without_collapses: without_collapses(&scores, &judgements, options)?,
            survives_readings: Vec::new(),
            judgements,
            estimates,
            overviews: claims::overview(&scores)?,
            controls: claims::control_comparisons(&scores, options)?,
            scores,
            options: options.clone(),
            sensitivity: Vec::new(),
        })
    }

    /// The IQM estimate of `metric` for `method` on `task`, if one was computed.
    #[must_use]
    pub fn estimate(&self, task: &str, method: &str, metric: &str) -> Option<&Estimate> {
        self.estimates
            .iter()
            .find(|e| e.task == task && e.method == method && e.metric == metric)
    }

    /// The paper's EA-MADM on `task`: the first method under test with role `paper`.
    #[must_use]
    pub fn paper_ea_madm(&self, task: &str) -> Option<&str> {
        claims::methods(&self.scores, task)
            .into_iter()
            .find(|&(_, role, kind)| role == Role::Paper && claims::is_under_test(kind))
            .map(|(method, _, _)| method)
    }
}

impl Verdicts {
    /// `final-scores.csv`: one row per task, method and seed.
    pub fn scores_csv(&self) -> Result<String, ScoresError> {
        let mut bytes = Vec::new();
        scores::write_csv(&self.scores, &mut bytes)?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// `claims.csv`: every estimate and comparison, and each method's outcome rows.
    pub fn claims_csv(&self) -> Result<String, ClaimsError> {
        let mut bytes = Vec::new();
        let mut rows = claims::rows(&self.judgements, &self.estimates);
        rows.extend(claims::outcome_rows(&self.scores)?);
        claims::write_csv(&rows, &mut bytes)?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }
}

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

/// The claim's deciding metric in `judgement`: the deciding comparison's, else the first.
fn deciding_metric(claim: &Claim, judgement: &Judgement) -> &'static str {
    judgement
        .deciding_comparison()
        .map_or(claim.metrics[0].column, |c| c.metric.column)
}

/// The control of `task` with the best IQM of `metric` (the earlier one on a tie), with that
/// IQM: among the methods with role `control` that `context` knows as a reward-matched,
/// budget-matched or sub-task-alone control (from their configs).
#[must_use]
pub fn strongest_control<'a>(
    scores: &'a [FinalScore],
    estimates: &[Estimate],
    task: &str,
    metric: &str,
    direction: Direction,
    context: &ReportContext,
) -> Option<(&'a str, f64)> {
    let mut best: Option<(&str, f64)> = None;
    for (method, role, kind) in claims::methods(scores, task) {
        let is_control = context
            .method(task, method)
            .is_some_and(|m| m.control.is_some());
        if role != Role::Control || claims::is_under_test(kind) || !is_control {
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
    context: &ReportContext,
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
        let Some((control, control_iqm)) = strongest_control(
            scores,
            estimates,
            &judgement.task,
            metric,
            direction,
            context,
        ) else {
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
