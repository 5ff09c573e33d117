//! `oracle.csv` and `pretraining.csv` (issue 32): the rows are computed by `eamadm::oracle`
//! (the decision step on exact or converged sub-task values, each sub-task's pre-training);
//! this module only feeds it the run store's pre-trained sub-tasks and writes the files.

use std::path::Path;

use eamadm::RunError;
use eamadm::oracle::{OracleError, OracleRow, PretrainingRow};
use eamadm_runs::PretrainedStore;
use eamadm_runs::pretrained::ReadOnlyCache;
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};
use crate::experiments::PlannedExperiment;

/// Making or writing the oracle tables failed.
#[derive(Debug, Error)]
pub(crate) enum OracleTablesError {
    /// A run repeated for its learned values, or a pre-training, failed.
    #[error("oracle.csv: experiment {experiment}: {source}")]
    Run {
        /// The experiment's name.
        experiment: String,
        /// The failure, naming method and seed.
        #[source]
        source: RunError,
    },
    /// A table could not be written as CSV.
    #[error(transparent)]
    Csv(#[from] OracleError),
    /// Writing a file failed.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
}

/// The oracle rows of every base experiment of the plan (a reading's experiment has none: it
/// reruns methods under another reading), in plan order, taking pre-trained sub-tasks from the
/// artefact cache `pretrained_cache`, read only ([`ReadOnlyCache`]).
pub(crate) fn oracle_rows(
    pretrained_cache: &Path,
    experiments: &[PlannedExperiment],
) -> Result<Vec<OracleRow>, OracleTablesError> {
    let cache = ReadOnlyCache(PretrainedStore::new(pretrained_cache));
    let mut rows = Vec::new();
    for planned in experiments
        .iter()
        .filter(|planned| planned.reading.is_none())
    {
        rows.extend(
            eamadm::oracle::oracle_rows(&planned.experiment, &cache).map_err(|source| {
                OracleTablesError::Run {
                    experiment: planned.name.clone(),
                    source,
                }
            })?,
        );
    }
    Ok(rows)
}

/// Writes `oracle.csv` and `pretraining.csv` into `out`.
pub(crate) fn write_oracle_tables(
    out: &Path,
    oracle: &[OracleRow],
    pretraining: &[PretrainingRow],
) -> Result<(), OracleTablesError> {
    let mut csv = Vec::new();
    eamadm::oracle::write_csv(oracle, &mut csv)?;
    write_atomic(&out.join(eamadm::output_names::ORACLE), &csv)?;
    let mut csv = Vec::new();
    eamadm::oracle::write_pretraining_csv(pretraining, &mut csv)?;
    write_atomic(&out.join(eamadm::output_names::PRETRAINING), &csv)?;
    Ok(())
}
