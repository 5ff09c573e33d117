//! The outputs of a plan, made from run stores as a stream: one run at a time is read (in job
//! order), written to the CSV tables, added to the
//! experiment's figures ([`eamadm_present::figures::ExperimentFigures`]: per-episode bands) and
//! its report facts ([`ReportFacts`]: one small final-score row per run, which the verdicts'
//! per-seed bootstrap needs, and the robot's behaviour sums), then dropped. No run is held past its turn, so memory does not
//! grow with the number of seeds.
//!
//! `reproduce-paper` (unsharded, `--shard`, `--runs-only`) and `merge` all end here, so a merge
//! of shards writes the bytes an unsharded run writes: the same runs, read in the same order, go
//! through the same code. The run store's bundles are packed before (`RunStore::pack`, in job
//! order), so their bytes do not depend on which process, thread or shard ran a run, nor in
//! which order runs completed.

use std::path::Path;

use eamadm::ReportFacts;
use eamadm::results::{CurvesCsv, ResultsError, TrajectoriesCsv};
use eamadm::scores::{FinalScore, ScoresError};
use eamadm::sensitivity::ReadingRuns;
use thiserror::Error;

use crate::claims_report::{ClaimsReportError, write_claim_outputs};
use crate::cli::KeepTrajectories;
use crate::experiments::PlannedExperiment;
use crate::jobs::Job;
use crate::oracle_tables::{OracleTablesError, oracle_rows, write_oracle_tables};
use crate::outputs::{OutputError, experiment_figures, write_figures};
use eamadm::verdicts::Verdicts;
use eamadm_runs::atomic::{AtomicFile, AtomicWriteError};
use eamadm_runs::store::{RunStore, StoreError, StoredRun};

/// Each experiment's per-episode table, compressed at `eamadm_runs::gzip`'s table level (reals
/// at single precision, `eamadm::results::CurveRow`); pandas, R and `zcat` read it as it is.
pub(crate) const CURVES_FILE: &str = eamadm_runs::names::CURVES;

/// What to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Outputs<'a> {
    /// Only the run store (`runs/<experiment>.jsonl.zst`), compacted into job order: a shard's or
    /// `--runs-only`'s output.
    StoreOnly,
    /// The run store, the CSV tables, the figures and `REPORT.md`.
    Everything {
        /// Whether the plan is a `--quick` smoke run (the report says so).
        quick: bool,
        /// The cache of pre-trained sub-tasks (`--pretrained-cache`), from which the oracle
        /// analysis takes the plan's pre-trained sub-tasks rather than training them again.
        pretrained_cache: &'a Path,
    },
}

/// Making the outputs failed.
#[derive(Debug, Error)]
pub(crate) enum FinishError {
    /// Runs of the plan that no store holds.
    #[error(
        "{} of the plan's {total} runs are in none of the stores; run the missing shards (or \
         `cargo xtask run-job --key KEY` with the plan's options) and merge again. Missing:\n{}",
        missing.len(),
        missing.join("\n")
    )]
    Missing {
        /// One line per missing run: experiment, method, seed and key.
        missing: Vec<String>,
        /// The plan's number of runs.
        total: usize,
    },
    /// Reading a store failed.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// A CSV table failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Writing a file failed.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
    /// A run's final scores could not be computed.
    #[error("final-scores.csv: {0}")]
    Scores(#[from] ScoresError),
    /// The verdicts or their files failed.
    #[error(transparent)]
    Claims(#[from] ClaimsReportError),
    /// `oracle.csv` or `pretraining.csv` failed.
    #[error(transparent)]
    Oracle(#[from] OracleTablesError),
    /// Scoring the tuning suite's trials failed.
    #[error(transparent)]
    Tuning(#[from] eamadm::tuning::TuningError),
}

/// The runs of `jobs` that none of `stores` holds (keeping `keep`'s trajectories), one line
/// each, in job order.
pub(crate) fn missing_runs(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    stores: &[RunStore],
    keep: KeepTrajectories,
) -> Vec<String> {
    jobs.iter()
        .filter(|job| !stores.iter().any(|store| store.has(&job.key, keep)))
        .map(|job| {
            format!(
                "  {} {} seed {} (key {})",
                experiments[job.experiment].name, job.method.label, job.seed, job.key
            )
        })
        .collect()
}

/// Removes what earlier versions wrote and this one replaces: `results.json` (every record, now
/// in the store), the one-file-per-run store `runs/<64 hex digits>.json` (format 1, whose
/// runs carry no checksum) and the uncompressed bundles `runs/<experiment>.jsonl` of
/// `experiments` (their runs are recomputed, not converted). Left in place they would sit beside
/// the new outputs as a second, stale set. (The uncompressed `curves.csv` of an earlier set goes
/// with the output folder's swap, which removes what the previous manifest listed.)
fn remove_legacy_files(out: &Path, experiments: &[PlannedExperiment]) -> Result<(), FinishError> {
    let remove = |path: &Path| -> Result<(), FinishError> {
        match std::fs::remove_file(path) {
            Ok(()) => Ok(()),
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(source) => Err(FinishError::Write(AtomicWriteError {
                path: path.to_path_buf(),
                source,
            })),
        }
    };
    remove(&out.join(eamadm_runs::names::LEGACY_RESULTS))?;
    for planned in experiments {
        remove(&out.join("runs").join(format!("{}.jsonl", planned.name)))?;
    }
    let Ok(entries) = std::fs::read_dir(out.join("runs")) else {
        return Ok(());
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let is_legacy_run = name
            .strip_suffix(".json")
            .is_some_and(|stem| stem.len() == 64 && stem.bytes().all(|b| b.is_ascii_hexdigit()));
        if is_legacy_run {
            remove(&entry.path())?;
        }
    }
    Ok(())
}

/// Writes the table `file` under `folder`, made by `make` into bytes, atomically.
pub(crate) fn write_table<E: std::error::Error + Send + Sync + 'static>(
    folder: &Path,
    file: &str,
    make: impl FnOnce(&mut Vec<u8>) -> Result<(), E>,
) -> Result<(), AtomicWriteError> {
    let path = folder.join(file);
    let mut bytes = Vec::new();
    make(&mut bytes).map_err(|error| AtomicWriteError {
        path: path.clone(),
        source: std::io::Error::other(error),
    })?;
    eamadm_runs::atomic::write_atomic(&path, &bytes)
}

/// Run `job` from the first store holding it.
fn load(
    stores: &[RunStore],
    job: &Job<'_>,
    keep: KeepTrajectories,
) -> Result<Option<StoredRun>, StoreError> {
    for store in stores {
        if let Some(run) = store.load(&job.key, keep)? {
            return Ok(Some(run));
        }
    }
    Ok(None)
}

/// The reruns of the reading experiment `index` (of `reading` on the base experiment `base`):
/// the methods its jobs ran and their final scores, read in job order.
fn reading_runs(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    stores: &[RunStore],
    keep: KeepTrajectories,
    index: usize,
    reading: eamadm::paper::Reading,
    base: usize,
) -> Result<ReadingRuns, FinishError> {
    let planned = &experiments[index];
    let mut runs = ReadingRuns {
        reading: reading.name().to_owned(),
        task: experiments[base].name.clone(),
        methods: Vec::new(),
        scores: Vec::new(),
    };
    for job in jobs.iter().filter(|job| job.experiment == index) {
        let run = load(stores, job, keep)?.ok_or_else(|| FinishError::Missing {
            missing: missing_runs(experiments, std::slice::from_ref(job), stores, keep),
            total: jobs.len(),
        })?;
        if !runs.methods.contains(&job.method.label) {
            runs.methods.push(job.method.label.clone());
        }
        runs.scores.push(eamadm::scores::final_score_of(
            &run.record,
            &planned.experiment,
        )?);
    }
    Ok(runs)
}

/// Writes `outputs` for `jobs` (in job order), reading every run from the first of `stores`
/// that holds it: the CSV tables, figures, `final-scores.csv`, `claims.csv` and `REPORT.md`
/// under `out` (the staging folder that is swapped into the output folder whole); files of
/// earlier versions' stores are removed from `store_out/runs/`. Fails listing every missing run before
/// writing anything. Returns the number of runs written.
pub(crate) fn write_outputs(
    store_out: &Path,
    out: &Path,
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    stores: &[RunStore],
    keep: KeepTrajectories,
    outputs: Outputs<'_>,
) -> Result<usize, FinishError> {
    let missing = missing_runs(experiments, jobs, stores, keep);
    if !missing.is_empty() {
        return Err(FinishError::Missing {
            missing,
            total: jobs.len(),
        });
    }
    let mut facts = Vec::with_capacity(experiments.len());
    // Every run's final scores (the verdicts bootstrap over seeds), and the first run whose
    // scores failed, reported after the figures as when all runs were scored at the end.
    let mut scores: Result<Vec<FinalScore>, ScoresError> = Ok(Vec::new());
    // The final scores of each reading's reruns, judged against the base's at the end.
    let mut readings: Vec<ReadingRuns> = Vec::new();
    // Each sub-task's pre-training in every run of the base experiments (`pretraining.csv`).
    let mut pretraining = Vec::new();
    // The final scores of the tuning suite's runs (`--suite tuning`).
    let mut tuned: Vec<FinalScore> = Vec::new();
    // The final scores of the maze family's runs (`--suite family`).
    let mut family: Vec<FinalScore> = Vec::new();
    for (index, planned) in experiments.iter().enumerate() {
        let everything = matches!(outputs, Outputs::Everything { .. });
        // Tuning trials and family layouts feed their own tables, not an experiment folder.
        let side_scores = if planned.tuning.is_some() {
            Some(&mut tuned)
        } else if planned.family.is_some() {
            Some(&mut family)
        } else {
            None
        };
        if let Some(scores) = side_scores {
            if everything {
                for job in jobs.iter().filter(|job| job.experiment == index) {
                    let run = load(stores, job, keep)?.ok_or_else(|| FinishError::Missing {
                        missing: missing_runs(experiments, std::slice::from_ref(job), stores, keep),
                        total: jobs.len(),
                    })?;
                    scores.push(eamadm::scores::final_score_of(
                        &run.record,
                        &planned.experiment,
                    )?);
                }
            }
            continue;
        }
        if let Some((reading, base)) = planned.reading {
            if everything {
                readings.push(reading_runs(
                    experiments,
                    jobs,
                    stores,
                    keep,
                    index,
                    reading,
                    base,
                )?);
            }
            continue;
        }
        let folder = out.join(&planned.name);
        let mut tables = if everything {
            Some((
                eamadm_runs::gzip::table_encoder(AtomicFile::create(&folder.join(CURVES_FILE))?),
                eamadm_runs::gzip::table_encoder(AtomicFile::create(
                    &folder.join(eamadm_runs::names::TRAJECTORIES),
                )?),
            ))
        } else {
            None
        };
        // The report's facts and final scores, and the figures, gathered run by run.
        let mut collected = everything.then(|| {
            let facts = ReportFacts::new(&planned.experiment, &planned.name);
            (experiment_figures(planned, facts.facts()), facts)
        });
        {
            let mut csv = tables
                .as_mut()
                .map(|(curves, paths)| (CurvesCsv::new(curves), TrajectoriesCsv::new(paths)));
            for job in jobs.iter().filter(|job| job.experiment == index) {
                let run = load(stores, job, keep)?.ok_or_else(|| FinishError::Missing {
                    missing: missing_runs(experiments, std::slice::from_ref(job), stores, keep),
                    total: jobs.len(),
                })?;
                if let Some((curves, paths)) = csv.as_mut() {
                    let table = |file: &str| {
                        let file = format!("{}/{file}", planned.name);
                        move |source: ResultsError| OutputError::Results { file, source }
                    };
                    curves.push(&run.record).map_err(table(CURVES_FILE))?;
                    // The figures draw the paths of the first seed; the other seeds' paths
                    // (up to the step cap each on a looping greedy policy) are kept only when
                    // asked for, so a default run's tables stay small.
                    if keep == KeepTrajectories::All || job.seed == planned.config().base_seed {
                        paths
                            .push(&run.record)
                            .map_err(table(eamadm_runs::names::TRAJECTORIES))?;
                    }
                }
                if let Some((experiment_figures, facts)) = collected.as_mut() {
                    pretraining.extend(eamadm::oracle::pretraining_rows(&run.record));
                    experiment_figures.push(&run.record);
                    facts.push(&run.record);
                }
            }
            if let Some((curves, paths)) = csv {
                let table = |file: &str| {
                    let file = format!("{}/{file}", planned.name);
                    move |source: ResultsError| OutputError::Results { file, source }
                };
                curves.finish().map_err(table(CURVES_FILE))?;
                paths
                    .finish()
                    .map_err(table(eamadm_runs::names::TRAJECTORIES))?;
            }
        }
        if let Some((curves, paths)) = tables {
            let curves_path = folder.join(CURVES_FILE);
            curves
                .finish()
                .map_err(|source| AtomicWriteError {
                    path: curves_path,
                    source,
                })?
                .commit()?;
            let paths_path = folder.join(eamadm_runs::names::TRAJECTORIES);
            paths
                .finish()
                .map_err(|source| AtomicWriteError {
                    path: paths_path,
                    source,
                })?
                .commit()?;
        }
        if let Some((experiment_figures, gathered)) = collected {
            let figures = write_figures(out, &planned.name, experiment_figures)?;
            match gathered.finish() {
                Ok((mut experiment, rows)) => {
                    experiment.figures = figures;
                    experiment.tables_written = true;
                    facts.push(experiment);
                    if let Ok(all) = scores.as_mut() {
                        all.extend(rows);
                    }
                }
                Err(error) => {
                    if scores.is_ok() {
                        scores = Err(error);
                    }
                }
            }
        }
    }
    remove_legacy_files(store_out, experiments)?;
    if let Outputs::Everything {
        quick,
        pretrained_cache,
    } = outputs
    {
        let scores = scores?;
        let mut context = eamadm::paper::report_context(quick);
        context.experiments = facts;
        let options = context.claim_options().map_err(ClaimsReportError::from)?;
        let mut verdicts =
            Verdicts::compute(scores, &options, &context).map_err(ClaimsReportError::from)?;
        let rows = eamadm::sensitivity::sensitivity(&verdicts.scores, &readings, &verdicts.options)
            .map_err(ClaimsReportError::from)?;
        verdicts = verdicts.with_sensitivity(rows);
        // The oracle and the reach sub-tasks' pre-training enter the findings (and the
        // report) through the context, so that `eamadm.report(dir)` renders them from
        // `report-context.toml` too.
        let oracle = oracle_rows(pretrained_cache, experiments, jobs)?;
        context.oracle = eamadm::oracle::oracle_findings(&oracle, &verdicts.scores);
        context.pretraining = eamadm::oracle::reach_pretraining(&pretraining);
        write_oracle_tables(out, &oracle, &pretraining)?;
        let tuning = crate::tuning_suite::outcome(experiments, &tuned)?;
        if let Some(tuning) = &tuning {
            write_table(out, eamadm::output_names::TUNING, |bytes| {
                eamadm::tuning::write_tuning_csv(&tuning.rows, bytes)
            })?;
        }
        crate::family_suite::write_layouts(out, experiments)?;
        let (pooled, found) = crate::family_suite::judge(out, experiments, &family)?;
        let findings = write_claim_outputs(out, &context, &verdicts, tuning.as_ref(), found)?;
        crate::family_suite::write_family_outputs(out, &family, &pooled, &findings)?;
    }
    Ok(jobs.len())
}
