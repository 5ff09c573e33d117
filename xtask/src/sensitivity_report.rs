//! The readings of the paper in a run's outputs: the plan printout's line and
//! `sensitivity.csv` (issue 20 item 4). The rows are computed by `eamadm::sensitivity` and the
//! report's section on them is written by `eamadm_present::report`; this module only writes files.

use std::path::Path;

use eamadm::sensitivity::{self, SensitivityRow};

use crate::atomic::write_atomic;
use crate::claims_report::ClaimsReportError;
use crate::experiments::PlannedExperiment;
use crate::jobs::Job;

/// The plan printout's line on the readings' runs (empty when the plan has none).
pub(crate) fn describe_readings(experiments: &[PlannedExperiment], jobs: &[Job<'_>]) -> String {
    let mut names: Vec<&str> = Vec::new();
    let mut runs = 0;
    for job in jobs {
        if let Some((reading, _)) = experiments[job.experiment].reading {
            runs += 1;
            if !names.contains(&reading.name()) {
                names.push(reading.name());
            }
        }
    }
    if runs == 0 {
        return String::new();
    }
    format!(
        "  readings: {} ({runs} runs of only the methods each changes; the others' runs are \
         reused; sensitivity.csv)\n",
        names.join(", ")
    )
}

/// Writes `sensitivity.csv` into `out` (only its header when no reading ran).
pub(crate) fn write_sensitivity_csv(
    out: &Path,
    rows: &[SensitivityRow],
) -> Result<(), ClaimsReportError> {
    let mut csv = Vec::new();
    sensitivity::write_csv(rows, &mut csv)?;
    write_atomic(&out.join(eamadm::output_names::SENSITIVITY), &csv)?;
    Ok(())
}
