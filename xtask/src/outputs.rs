//! The figures of an output folder, written atomically: per experiment the SVG files that
//! [`eamadm_present::figures`] draws from the runs it was given one at a time
//! ([`ExperimentFigures`]), under `<name>/`. The CSV tables and the run store are streamed by
//! [`crate::finish`].

use std::path::Path;

use eamadm::facts::{ExperimentFacts, Figures};
use eamadm::results;
use eamadm_present::chart::FigureError;
use eamadm_present::figures::{Arena, ExperimentFigures, FigurePlan};
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};
use crate::experiments::PlannedExperiment;

/// Writing an output failed.
#[derive(Debug, Error)]
pub(crate) enum OutputError {
    /// Serialising results failed.
    #[error("{file}: {source}")]
    Results {
        /// The file being made.
        file: String,
        /// Why.
        #[source]
        source: results::ResultsError,
    },
    /// A figure failed.
    #[error(transparent)]
    Figure(#[from] FigureError),
    /// Writing failed.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
}

/// A collector of the figures of `planned` (whose report facts are `facts`), without runs.
pub(crate) fn experiment_figures(
    planned: &PlannedExperiment,
    facts: &ExperimentFacts,
) -> ExperimentFigures {
    let task = planned.experiment.task();
    ExperimentFigures::new(FigurePlan::new(
        facts,
        Arena::from_parts(task.maze(), task.scenario()),
    ))
}

/// Draws the figures of `figures` and writes them under `<out>/<name>/`; returns their file
/// names and the key figures' captions, which the report shows.
pub(crate) fn write_figures(
    out: &Path,
    name: &str,
    figures: ExperimentFigures,
) -> Result<Figures, OutputError> {
    let drawing = figures.draw()?;
    let folder = out.join(name);
    for (file, svg) in &drawing.files {
        write_atomic(&folder.join(file), svg.as_bytes())?;
    }
    Ok(drawing.figures)
}
