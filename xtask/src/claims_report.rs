//! `REPORT.md`, `final-scores.csv` and `claims.csv`: the files of a run's verdicts. Their text
//! is made by [`eamadm_present::report`] (pure, tested there); this module only writes it, atomically.

use std::path::Path;

use eamadm::claims::ClaimsError;
use eamadm::facts::ReportContext;
use eamadm::findings::Findings;
use eamadm::output_names as names;
use eamadm::scores::ScoresError;
use eamadm::verdicts::Verdicts;
use eamadm_present::report::{self, ReportError};
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};

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
    /// The report's context as TOML.
    #[error("{file}: {0}", file = eamadm::output_names::REPORT_CONTEXT)]
    Context(#[from] toml::ser::Error),
    /// The findings as JSON.
    #[error("{file}: {0}", file = eamadm::output_names::FINDINGS)]
    Findings(#[from] serde_json::Error),
}

impl From<ReportError> for ClaimsReportError {
    fn from(error: ReportError) -> Self {
        match error {
            ReportError::Scores(error) => Self::Scores(error),
            ReportError::Claims(error) => Self::Claims(error),
        }
    }
}

/// Writes `final-scores.csv`, `claims.csv`, `findings.json`, `REPORT.md` and
/// `report-context.toml` into `out`; `context` holds the paper's tasks and, per experiment, the
/// figures written and the robot's behaviour. Returns the findings written.
pub(crate) fn write_claim_outputs(
    out: &Path,
    context: &ReportContext,
    verdicts: &Verdicts,
    tuning: Option<&crate::tuning_suite::TuningOutcome>,
    family: Option<eamadm::eamadm_eval::family::FamilyFindings>,
) -> Result<Findings, ClaimsReportError> {
    write_atomic(
        &out.join(names::FINAL_SCORES),
        verdicts.scores_csv()?.as_bytes(),
    )?;
    write_atomic(&out.join(names::CLAIMS), verdicts.claims_csv()?.as_bytes())?;
    crate::sensitivity_report::write_sensitivity_csv(out, &verdicts.sensitivity)?;
    // Every column of the two tables, typed and documented, beside them.
    write_atomic(
        &out.join(names::DATA_PACKAGE),
        if tuning.is_some() {
            eamadm::data_package::data_package_text_with_tuning()
        } else {
            eamadm::data_package::data_package_text()
        }
        .as_bytes(),
    )?;
    // What the report states, as data; the report and the README's blocks render from it.
    let mut findings = Findings::of(context, verdicts).with_family(family);
    if let Some(tuning) = tuning {
        // "Each at its best": a verdict set of its own beside the paper-setting verdicts.
        findings =
            findings.with_at_best(context, &tuning.at_best, &tuning.chosen, &verdicts.options)?;
    }
    write_atomic(&out.join(names::FINDINGS), findings.to_json()?.as_bytes())?;
    let report = report::render(context, verdicts, &findings);
    write_atomic(&out.join(names::REPORT), report.as_bytes())?;
    // What the report was made from beyond final-scores.csv, so that it can be made again from
    // the folder alone (`eamadm.report(dir)` in Python).
    let context_text = eamadm::paper::report_context_toml(context)?;
    write_atomic(
        &out.join(eamadm::output_names::REPORT_CONTEXT),
        context_text.as_bytes(),
    )?;
    Ok(findings)
}
