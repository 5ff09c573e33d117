//! `--suite family`'s outputs: the glue from the family's final scores to the files of
//! `family/` (the verdicts are `eamadm_eval::family`'s, the figure and text
//! `eamadm_present::family`'s).

use std::path::Path;

use eamadm::eamadm_eval::family::{family_verdicts, write_effects_csv, write_pooled_csv};
use eamadm::scores::FinalScore;
use eamadm::stats::hierarchical::HierarchicalBootstrap;
use eamadm::verdicts::Verdicts;
use eamadm_present::family::{LayoutPoint, effect_figure, family_report};
use eamadm_runs::atomic::{AtomicWriteError, write_atomic};

use crate::experiments::PlannedExperiment;

/// The folder of the family's outputs.
pub(crate) const FOLDER: &str = "family";

/// Writes `family/`: `layouts.csv` (the family's layouts and the paper's two), `final-scores.csv`
/// (the family's runs), `verdicts.csv` (pooled), `effects.csv` (per layout), `effect-C1.svg`,
/// `effect-C2.svg` and `REPORT.md`. Nothing when the plan has no family layout.
pub(crate) fn write_family_outputs(
    out: &Path,
    experiments: &[PlannedExperiment],
    scores: &[FinalScore],
    paper: &Verdicts,
) -> Result<(), AtomicWriteError> {
    let family: Vec<&PlannedExperiment> =
        experiments.iter().filter(|p| p.family.is_some()).collect();
    let Some(first) = family.first() else {
        return Ok(());
    };
    let folder = out.join(FOLDER);
    let error = |file: &str| {
        let path = folder.join(file);
        move |source: std::io::Error| AtomicWriteError {
            path: path.clone(),
            source,
        }
    };
    let mut rows: Vec<eamadm::family::LayoutRow> = eamadm::family::paper_layout_rows();
    rows.extend(family.iter().filter_map(|p| p.family.clone()));
    let mut bytes = Vec::new();
    eamadm::family::write_layouts_csv(&rows, &mut bytes)
        .map_err(|e| error("layouts.csv")(std::io::Error::other(e)))?;
    write_atomic(&folder.join("layouts.csv"), &bytes)?;

    let mut bytes = Vec::new();
    eamadm::scores::write_csv(scores, &mut bytes)
        .map_err(|e| error("final-scores.csv")(std::io::Error::other(e)))?;
    write_atomic(&folder.join("final-scores.csv"), &bytes)?;

    // The family runs Task II's rewards on every layout: its margins are the first layout's.
    let margins = first.experiment.task().equivalence_margins();
    let verdicts = family_verdicts(scores, &margins, &HierarchicalBootstrap::default())
        .map_err(|e| error("verdicts.csv")(std::io::Error::other(e)))?;
    let mut bytes = Vec::new();
    write_pooled_csv(&verdicts.pooled, &mut bytes)
        .map_err(|e| error("verdicts.csv")(std::io::Error::other(e)))?;
    write_atomic(&folder.join("verdicts.csv"), &bytes)?;
    let mut bytes = Vec::new();
    write_effects_csv(&verdicts.layouts, &mut bytes)
        .map_err(|e| error("effects.csv")(std::io::Error::other(e)))?;
    write_atomic(&folder.join("effects.csv"), &bytes)?;

    let points: Vec<LayoutPoint> = family
        .iter()
        .filter_map(|p| p.family.as_ref())
        .map(|row| LayoutPoint {
            layout: row.layout.clone(),
            kind: row.kind.name().to_owned(),
            detour_ratio: row.detour_ratio,
        })
        .collect();
    for claim in ["C1", "C2"] {
        if let Some(svg) = effect_figure(&verdicts, &points, claim) {
            write_atomic(&folder.join(format!("effect-{claim}.svg")), svg.as_bytes())?;
        }
    }
    let paper_verdicts: Vec<(String, String, String)> = paper
        .judgements
        .iter()
        .filter(|j| j.method == "ea-madm" && (j.task == "task1" || j.task == "task2"))
        .filter(|j| j.claim.id == "C1" || j.claim.id == "C2")
        .map(|j| {
            (
                j.task.clone(),
                j.claim.id.to_owned(),
                j.verdict.name().to_owned(),
            )
        })
        .collect();
    let config = first.config();
    let text = family_report(
        &verdicts,
        &points,
        &paper_verdicts,
        config.episodes,
        config.seeds,
    );
    write_atomic(&folder.join("REPORT.md"), text.as_bytes())
}
