//! `oracle.csv` and `pretraining.csv` (issue 32), computed by `eamadm::oracle`; this module
//! only feeds it the plan's decisions and the cache's pre-trained sub-tasks, and writes them.

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

/// The oracle rows of the plan's base experiments (a reading's has none) for the decisions
/// `jobs` run, in plan order, with pre-trained sub-tasks read from `pretrained_cache`.
pub(crate) fn oracle_rows(
    pretrained_cache: &Path,
    experiments: &[PlannedExperiment],
    jobs: &[crate::jobs::Job<'_>],
) -> Result<Vec<OracleRow>, OracleTablesError> {
    let cache = ReadOnlyCache(PretrainedStore::new(pretrained_cache));
    let mut rows = Vec::new();
    for (index, planned) in experiments.iter().enumerate() {
        let runs = |label: &str| {
            let mut own = jobs.iter().filter(|job| job.experiment == index);
            planned.reading.is_none() && own.any(|job| job.method.label == label)
        };
        rows.extend(
            eamadm::oracle::oracle_rows_of(&planned.experiment, &cache, runs).map_err(
                |source| OracleTablesError::Run {
                    experiment: planned.name.clone(),
                    source,
                },
            )?,
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
