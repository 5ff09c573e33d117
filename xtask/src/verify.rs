//! `cargo xtask verify` and `merge --verify`: a seeded sample of the plan's stored runs and
//! pre-trained artefacts recomputed and compared byte for byte ([`eamadm_runs::verify`] does
//! the work; this module picks the sample, runs it in parallel and prints).

use eamadm_runs::verify::{Mismatch, artefacts_of, sample, verify_artefact, verify_run};
use eamadm_runs::{PretrainedStore, RunStore};
use rayon::prelude::*;

use crate::Failure;
use crate::cli::VerifyArgs;
use crate::experiments::PlannedExperiment;
use crate::jobs::{Job, plan_jobs};
use crate::plan::Workspace;
use crate::reproduce::{prepare, warn_on_stderr};

/// The fraction `verify` checks when neither `--sample` nor `--all` is given.
const DEFAULT_SAMPLE: f64 = 0.05;

/// Runs `verify`.
pub(crate) fn verify(args: &VerifyArgs, workspace: &Workspace) -> Result<(), Failure> {
    let (plan, experiments) = prepare(&args.plan, workspace)?;
    let jobs = plan_jobs(&experiments, &plan.methods).map_err(Failure::failed)?;
    let store =
        RunStore::open_read_only(&plan.out, &mut warn_on_stderr).map_err(Failure::invalid)?;
    let fraction = if args.all {
        None
    } else {
        Some(args.sample.unwrap_or(DEFAULT_SAMPLE))
    };
    check_or_fail(
        &experiments,
        &jobs,
        std::slice::from_ref(&store),
        &PretrainedStore::new(&plan.pretrained_cache),
        fraction,
        args.sample_seed,
    )
}

/// Recomputes the sample (`fraction` of them, `None` for all, picked by `seed`) of the runs of
/// `jobs` that `stores` hold and of the artefacts of `cache` the plan pre-trains; prints what it
/// checked and each mismatch, and fails if there is any.
pub(crate) fn check_or_fail(
    experiments: &[PlannedExperiment],
    jobs: &[Job<'_>],
    stores: &[RunStore],
    cache: &PretrainedStore,
    fraction: Option<f64>,
    seed: u64,
) -> Result<(), Failure> {
    let stored: Vec<(&Job<'_>, &RunStore)> = jobs
        .iter()
        .filter_map(|job| {
            let store = stores.iter().find(|store| store.line_exists(&job.key))?;
            Some((job, store))
        })
        .collect();
    let held = stored.len();
    let runs = sample(stored, |(job, _)| &job.key, fraction, seed);
    let mut artefacts = Vec::new();
    for planned in experiments {
        let methods: Vec<_> = planned.config().methods.iter().collect();
        for seed in planned.config().seed_values() {
            for (description, key, method) in
                artefacts_of(&planned.experiment, &methods, seed).map_err(Failure::failed)?
            {
                if cache.path(&key).is_file() {
                    artefacts.push((planned, description, key, method));
                }
            }
        }
    }
    let cached = artefacts.len();
    let artefacts = sample(artefacts, |(_, _, key, _)| key, fraction, seed);
    let checked_runs = runs.len();
    let checked_artefacts = artefacts.len();
    let mut mismatches: Vec<Mismatch> = runs
        .par_iter()
        .map(|(job, store)| {
            verify_run(
                store,
                &experiments[job.experiment].experiment,
                job.method,
                job.seed,
                &job.key,
            )
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(Failure::failed)?
        .into_iter()
        .flatten()
        .collect();
    mismatches.extend(
        artefacts
            .par_iter()
            .map(|(planned, description, _, method)| {
                verify_artefact(cache, &planned.experiment, method, description)
            })
            .collect::<Result<Vec<_>, _>>()
            .map_err(Failure::failed)?
            .into_iter()
            .flatten(),
    );
    println!(
        "verify: recomputed {checked_runs} of {held} stored runs and {checked_artefacts} of \
         {cached} cached artefacts ({}, seed {seed}); {} differ",
        fraction.map_or_else(|| "all".to_owned(), |f| format!("sample {f}")),
        mismatches.len()
    );
    for mismatch in &mismatches {
        println!("  MISMATCH {mismatch}");
    }
    if mismatches.is_empty() {
        Ok(())
    } else {
        Err(Failure::failed(format!(
            "{} of the results checked are not what their configs compute (see MISMATCH \
             above): someone or something changed them with their checksums",
            mismatches.len()
        )))
    }
}
