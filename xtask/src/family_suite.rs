//! The maze layouts of a run and `--suite family`'s outputs: the glue from the plan and the
//! family's final scores to `layouts.csv` and the files of `family/` (the table is
//! `eamadm::family`'s, the verdicts and findings `eamadm_eval::family`'s through
//! `eamadm::family::judge_family`, the figure and text `eamadm_present::family`'s).

use std::path::Path;

use eamadm::eamadm_eval::family::{
    FamilyFindings, FamilyVerdicts, write_effects_csv, write_pooled_csv,
};
use eamadm::findings::Findings;
use eamadm::scores::FinalScore;
use eamadm_present::family::{effect_figure, family_report};
use eamadm_runs::atomic::{AtomicWriteError, write_atomic};

use crate::experiments::PlannedExperiment;
use crate::finish::write_table;

/// Writes the top-level `layouts.csv`: the paper's two layouts, then every other maze layout
/// the plan's experiments play (`eamadm::family::layouts_table`).
pub(crate) fn write_layouts(
    out: &Path,
    experiments: &[PlannedExperiment],
) -> Result<(), AtomicWriteError> {
    let rows = eamadm::family::layouts_table(
        experiments
            .iter()
            .map(|planned| (&planned.experiment, planned.family.as_ref())),
    );
    write_table(out, eamadm::output_names::LAYOUTS, |bytes| {
        eamadm::family::write_layouts_csv(&rows, bytes)
    })
}

/// The family's verdicts and findings from its runs' `scores` (no findings without them).
pub(crate) fn judge(
    out: &Path,
    experiments: &[PlannedExperiment],
    scores: &[FinalScore],
) -> Result<(FamilyVerdicts, Option<FamilyFindings>), AtomicWriteError> {
    let rows: Vec<_> = experiments
        .iter()
        .filter_map(|p| p.family.clone())
        .collect();
    eamadm::family::judge_family(scores, &rows).map_err(|error| AtomicWriteError {
        path: out.join(eamadm::output_names::FAMILY),
        source: std::io::Error::other(error),
    })
}

/// Writes `family/`: `final-scores.csv` (the family's runs), `verdicts.csv` (pooled),
/// `effects.csv` (per layout), `effect-C1.svg`, `effect-C2.svg` and `REPORT.md` (rendered
/// from `findings`, the run's); nothing when the findings have no family.
pub(crate) fn write_family_outputs(
    out: &Path,
    scores: &[FinalScore],
    verdicts: &FamilyVerdicts,
    findings: &Findings,
) -> Result<(), AtomicWriteError> {
    let (Some(family), Some(text)) = (&findings.family, family_report(findings)) else {
        return Ok(());
    };
    let folder = out.join(eamadm::output_names::FAMILY);
    write_table(&folder, eamadm::output_names::FINAL_SCORES, |bytes| {
        eamadm::scores::write_csv(scores, bytes)
    })?;
    write_table(&folder, "verdicts.csv", |bytes| {
        write_pooled_csv(&verdicts.pooled, bytes)
    })?;
    write_table(&folder, "effects.csv", |bytes| {
        write_effects_csv(&verdicts.layouts, bytes)
    })?;
    for claim in ["C1", "C2"] {
        if let Some(svg) = effect_figure(verdicts, &family.layouts, claim) {
            write_atomic(&folder.join(format!("effect-{claim}.svg")), svg.as_bytes())?;
        }
    }
    write_atomic(&folder.join(eamadm::output_names::REPORT), text.as_bytes())
}
