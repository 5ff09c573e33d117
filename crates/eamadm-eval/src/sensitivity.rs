//! Sensitivity of the verdicts to the readings of the paper (issue 20 item 4): the paper's
//! EA-MADM judged again after some methods were rerun under another reading of the paper, and
//! whether each verdict holds or flips; `sensitivity.csv`.
//!
//! A reading (the list is `eamadm::paper::readings()`) reruns only the methods it changes, on the
//! tasks it changes, with the same seeds (so the same random streams). Here the runs of those
//! methods replace the base experiment's runs of the same methods on that task; every other run
//! is the base experiment's own, and the same verdict computation ([`claims::judge_one`]) judges
//! each claim made on the task again. Pure: scores in, rows out.
//!
//! ```
//! use eamadm_eval::sensitivity::{Change, SensitivityRow, survival};
//!
//! let row = |reading: &str, change| SensitivityRow {
//!     claim: "C1",
//!     task: "task2".to_owned(),
//!     reading: reading.to_owned(),
//!     method: "ea-madm".to_owned(),
//!     base_verdict: eamadm_eval::claims::Verdict::Supported,
//!     verdict: eamadm_eval::claims::Verdict::Supported,
//!     change,
//!     versus: String::new(),
//!     metric: String::new(),
//!     statistic: "",
//!     estimate: None,
//!     ci_low: None,
//!     ci_high: None,
//!     p_holm: None,
//! };
//! let rows = [row("gamma-0.99", Change::Holds), row("epsilon-greedy-0.95", Change::Flips)];
//! let survival = survival(&rows);
//! assert_eq!(survival.len(), 1);
//! assert!(!survival[0].survives);
//! assert_eq!(survival[0].flipped_by, ["epsilon-greedy-0.95"]);
//! ```

use std::io::Write;

use rayon::prelude::*;
use serde::Serialize;

use crate::Role;
use crate::claims::{self, ClaimOptions, ClaimsError, Judgement, STABLE_REACHING, Verdict};
use crate::paper_claims::{CLAIMS, Claim};
use crate::scores::FinalScore;

/// The runs of one reading on one task: the final scores of the methods it reran.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadingRuns {
    /// The reading's name (`eamadm::paper::Reading::name`).
    pub reading: String,
    /// The base experiment's task the reading changes (`task1`, `task2`).
    pub task: String,
    /// The labels of the methods the reading reran; their base runs on `task` are replaced.
    pub methods: Vec<String>,
    /// The reruns' final scores (their `task` cell may name the reading's experiment: it is
    /// replaced by `task`).
    pub scores: Vec<FinalScore>,
}

/// Whether a verdict survives a reading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Change {
    /// The verdict under the reading equals the base verdict.
    Holds,
    /// It differs.
    Flips,
}

impl Change {
    /// `holds` or `flips`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Holds => "holds",
            Self::Flips => "flips",
        }
    }
}

/// One row of `sensitivity.csv`: one claim × task × reading, for the paper's EA-MADM.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SensitivityRow {
    /// `C1` … `C3`.
    pub claim: &'static str,
    /// The task.
    pub task: String,
    /// The reading's name.
    pub reading: String,
    /// The method under test (the paper's EA-MADM).
    pub method: String,
    /// The verdict of the base experiment (as in `claims.csv`).
    pub base_verdict: Verdict,
    /// The verdict under the reading.
    pub verdict: Verdict,
    /// `holds` or `flips`.
    pub change: Change,
    /// The competitor of the comparison that decides the verdict under the reading; empty when
    /// none decides (untestable).
    pub versus: String,
    /// Its metric: a column of `final-scores.csv`, or for a verdict decided by a per-seed test
    /// that test's column (`reached`, or C3's `stable_reaching`).
    pub metric: String,
    /// What `estimate` is: `paired_mean_difference` (the mean over paired seeds of EA-MADM −
    /// competitor, the verdict rule's estimand), `reached_share_difference` or
    /// `stable_reaching_share_difference` (for a verdict decided by a per-seed test: the share
    /// of paired seeds EA-MADM has the property on minus the competitor's); empty when nothing
    /// decides.
    pub statistic: &'static str,
    /// The deciding comparison's estimate under the reading (see `statistic`).
    pub estimate: Option<f64>,
    /// Lower end of its exact sign-flip 95 % interval (empty for a share difference, or when
    /// unbounded: fewer than 6 pairs).
    pub ci_low: Option<f64>,
    /// Upper end (empty as `ci_low`).
    pub ci_high: Option<f64>,
    /// Its Holm-adjusted p-value: that the mean paired difference lies beyond the margin, or
    /// within it for an `equivalent` verdict, or the exact sign test for a share difference.
    pub p_holm: Option<f64>,
}

/// The columns of `sensitivity.csv`, in order.
pub const SENSITIVITY_COLUMNS: [&str; 14] = [
    "claim",
    "task",
    "reading",
    "method",
    "base_verdict",
    "verdict",
    "change",
    "versus",
    "metric",
    "statistic",
    "estimate",
    "ci_low",
    "ci_high",
    "p_holm",
];

/// `base` with the runs of `runs.methods` on `runs.task` replaced by `runs.scores` (relabelled
/// to `runs.task`), in the base's order: each replaced method keeps its place, with the reruns
/// in their own (seed) order.
#[must_use]
pub fn substitute(base: &[FinalScore], runs: &ReadingRuns) -> Vec<FinalScore> {
    let rerun = |row: &FinalScore| row.task == runs.task && runs.methods.contains(&row.method);
    let mut out = Vec::with_capacity(base.len());
    let mut placed: Vec<&str> = Vec::new();
    for row in base {
        if !rerun(row) {
            out.push(row.clone());
        } else if !placed.contains(&row.method.as_str()) {
            placed.push(&row.method);
            out.extend(
                runs.scores
                    .iter()
                    .filter(|new| new.method == row.method)
                    .map(|new| FinalScore {
                        task: runs.task.clone(),
                        ..new.clone()
                    }),
            );
        }
    }
    out
}

/// The paper's EA-MADM on `task`: the first method of kind `ea_madm` with role `paper`.
fn paper_ea_madm<'a>(scores: &'a [FinalScore], task: &str) -> Option<&'a str> {
    claims::methods(scores, task)
        .into_iter()
        .find(|&(_, role, kind)| role == Role::Paper && claims::is_under_test(kind))
        .map(|(label, _, _)| label)
}

/// Fills `row`'s deciding cells from `judgement` (the verdict under the reading): its deciding
/// comparison (the mean paired difference with its exact interval, and the Holm p of the
/// test that decides: within the margin for an `equivalent` verdict, beyond it otherwise), or
/// for a verdict on per-seed tests the strongest such test (smallest Holm p, the first on
/// ties), named by its own column (`reached` or `stable_reaching`); left empty when nothing
/// decides (untestable).
fn fill_deciding(row: &mut SensitivityRow, judgement: &Judgement) {
    if let Some(c) = judgement.deciding_comparison() {
        row.versus.clone_from(&c.versus);
        c.metric.column.clone_into(&mut row.metric);
        row.statistic = PAIRED_MEAN_DIFFERENCE;
        row.estimate = Some(c.paired.estimate);
        row.ci_low = c.paired.low;
        row.ci_high = c.paired.high;
        row.p_holm = Some(if judgement.verdict == Verdict::Equivalent {
            c.paired.p_equivalence_holm.unwrap_or(1.0)
        } else {
            c.p_holm
        });
    } else if let Some(t) = judgement
        .reaching
        .iter()
        .reduce(|best, t| if t.p_holm < best.p_holm { t } else { best })
    {
        row.versus.clone_from(&t.versus);
        t.metric.clone_into(&mut row.metric);
        row.statistic = share_difference_statistic(t.metric);
        row.estimate = Some(claims::reaching_difference(t));
        row.p_holm = Some(t.p_holm);
    }
}

/// The `statistic` of a row decided by a comparison: the mean paired difference.
pub const PAIRED_MEAN_DIFFERENCE: &str = "paired_mean_difference";

/// Every value of the `statistic` column (empty: nothing decides).
pub const STATISTICS: [&str; 4] = [
    "",
    PAIRED_MEAN_DIFFERENCE,
    "reached_share_difference",
    "stable_reaching_share_difference",
];

/// The `statistic` of a row decided by a per-seed test on `column` ([`REACHED`](claims::REACHED) or
/// [`STABLE_REACHING`]): the difference of the shares of paired seeds with the property.
#[must_use]
pub fn share_difference_statistic(column: &str) -> &'static str {
    if column == STABLE_REACHING {
        "stable_reaching_share_difference"
    } else {
        "reached_share_difference"
    }
}

/// One row per claim × task × reading: every claim made on each reading's task, judged for the
/// paper's EA-MADM on `base` with the reading's reruns substituted ([`substitute`]), beside its
/// verdict on `base`. In the order of `readings`, then claim order. A task without the paper's
/// EA-MADM in `base` gives no rows.
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn sensitivity(
    base: &[FinalScore],
    readings: &[ReadingRuns],
    options: &ClaimOptions,
) -> Result<Vec<SensitivityRow>, ClaimsError> {
    let substituted: Vec<Vec<FinalScore>> =
        readings.iter().map(|runs| substitute(base, runs)).collect();
    // Every judgement needed, the base's once per claim × task: (reading index or `None` for
    // the base, claim, task, method). Judged in parallel; each is a pure function of its
    // scores, so the rows do not depend on the thread count.
    let mut jobs: Vec<(Option<usize>, &'static Claim, &str, &str)> = Vec::new();
    for (index, runs) in readings.iter().enumerate() {
        let task = runs.task.as_str();
        let Some(method) = paper_ea_madm(base, task) else {
            continue;
        };
        for claim in CLAIMS.iter().filter(|c| c.tasks.contains(&task)) {
            let base_job = (None, claim, task, method);
            if !jobs
                .iter()
                .any(|&(r, c, t, _)| r.is_none() && c.id == claim.id && t == task)
            {
                jobs.push(base_job);
            }
            jobs.push((Some(index), claim, task, method));
        }
    }
    let judged: Vec<Judgement> = jobs
        .par_iter()
        .map(|&(reading, claim, task, method)| {
            let scores = reading.map_or(base, |index| substituted[index].as_slice());
            claims::judge_one(scores, claim, task, method, Role::Paper, options)
        })
        .collect::<Result<_, _>>()?;
    let mut rows = Vec::new();
    for (&(reading, claim, task, method), after) in jobs.iter().zip(&judged) {
        let Some(index) = reading else {
            continue;
        };
        let Some(before) = jobs
            .iter()
            .zip(&judged)
            .find(|&(&(r, c, t, _), _)| r.is_none() && c.id == claim.id && t == task)
            .map(|(_, judgement)| judgement)
        else {
            continue;
        };
        let mut row = SensitivityRow {
            claim: claim.id,
            task: task.to_owned(),
            reading: readings[index].reading.clone(),
            method: method.to_owned(),
            base_verdict: before.verdict,
            verdict: after.verdict,
            change: if before.verdict == after.verdict {
                Change::Holds
            } else {
                Change::Flips
            },
            versus: String::new(),
            metric: String::new(),
            statistic: "",
            estimate: None,
            ci_low: None,
            ci_high: None,
            p_holm: None,
        };
        fill_deciding(&mut row, after);
        rows.push(row);
    }
    Ok(rows)
}

/// Whether one claim × task's verdict survives every reading run on its task.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Survival {
    /// The claim.
    pub claim: &'static str,
    /// The task.
    pub task: String,
    /// Readings run on the task.
    pub readings: usize,
    /// No reading flips the verdict.
    pub survives: bool,
    /// The readings that flip it, in row order.
    pub flipped_by: Vec<String>,
}

/// Per claim × task (first-appearance order of `rows`): whether its verdict survives every
/// reading, and which readings flip it. A claim × task no reading touched has no entry.
#[must_use]
pub fn survival(rows: &[SensitivityRow]) -> Vec<Survival> {
    let mut out: Vec<Survival> = Vec::new();
    for row in rows {
        if !out
            .iter()
            .any(|s| s.claim == row.claim && s.task == row.task)
        {
            out.push(Survival {
                claim: row.claim,
                task: row.task.clone(),
                readings: 0,
                survives: true,
                flipped_by: Vec::new(),
            });
        }
        for entry in out
            .iter_mut()
            .filter(|s| s.claim == row.claim && s.task == row.task)
        {
            entry.readings += 1;
            if row.change == Change::Flips {
                entry.survives = false;
                entry.flipped_by.push(row.reading.clone());
            }
        }
    }
    out
}

/// The text cells of one `sensitivity.csv` row, as read.
#[derive(Debug, serde::Deserialize)]
struct RawRow {
    claim: String,
    task: String,
    reading: String,
    method: String,
    base_verdict: String,
    verdict: String,
    change: String,
    versus: String,
    metric: String,
    statistic: String,
    estimate: Option<f64>,
    ci_low: Option<f64>,
    ci_high: Option<f64>,
    p_holm: Option<f64>,
}

/// Reads `sensitivity.csv` as [`write_csv`] writes it: what re-renders a folder's report
/// (the Python package's `eamadm.report(dir)`).
///
/// # Errors
/// [`ClaimsError::Csv`] on malformed CSV, [`ClaimsError::BadCell`] on a claim, verdict,
/// change or statistic no writer writes.
pub fn read_csv<R: std::io::Read>(reader: R) -> Result<Vec<SensitivityRow>, ClaimsError> {
    const FILE: &str = "sensitivity.csv";
    let verdict = |row: usize, column: &'static str, value: &str| {
        [
            Verdict::Supported,
            Verdict::Contradicted,
            Verdict::Equivalent,
            Verdict::Inconclusive,
            Verdict::Untestable,
        ]
        .into_iter()
        .find(|v| v.name() == value)
        .ok_or_else(|| ClaimsError::BadCell {
            file: FILE,
            row,
            column,
            value: value.to_owned(),
        })
    };
    let mut rows = Vec::new();
    for (index, raw) in csv::Reader::from_reader(reader)
        .deserialize::<RawRow>()
        .enumerate()
    {
        let raw = raw?;
        let row = index + 1;
        let bad = |column: &'static str, value: &str| ClaimsError::BadCell {
            file: FILE,
            row,
            column,
            value: value.to_owned(),
        };
        let claim = CLAIMS
            .iter()
            .map(|c| c.id)
            .find(|id| *id == raw.claim)
            .ok_or_else(|| bad("claim", &raw.claim))?;
        let change = [Change::Holds, Change::Flips]
            .into_iter()
            .find(|c| c.name() == raw.change)
            .ok_or_else(|| bad("change", &raw.change))?;
        let statistic = STATISTICS
            .into_iter()
            .find(|s| *s == raw.statistic)
            .ok_or_else(|| bad("statistic", &raw.statistic))?;
        rows.push(SensitivityRow {
            claim,
            base_verdict: verdict(row, "base_verdict", &raw.base_verdict)?,
            verdict: verdict(row, "verdict", &raw.verdict)?,
            change,
            statistic,
            task: raw.task,
            reading: raw.reading,
            method: raw.method,
            versus: raw.versus,
            metric: raw.metric,
            estimate: raw.estimate,
            ci_low: raw.ci_low,
            ci_high: raw.ci_high,
            p_holm: raw.p_holm,
        });
    }
    Ok(rows)
}

/// Writes `sensitivity.csv` (header: [`SENSITIVITY_COLUMNS`]; empty cells for absent values).
///
/// # Errors
/// [`ClaimsError::Csv`] when writing fails.
pub fn write_csv<W: Write>(rows: &[SensitivityRow], writer: W) -> Result<(), ClaimsError> {
    let mut csv = csv::Writer::from_writer(writer);
    if rows.is_empty() {
        csv.write_record(SENSITIVITY_COLUMNS)?;
    }
    for row in rows {
        csv.serialize(row)?;
    }
    csv.flush().map_err(csv::Error::from)?;
    Ok(())
}
