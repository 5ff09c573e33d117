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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::cli::{KeepTrajectories, Readings, ReproduceArgs, ReproduceCommand, RunModeArgs};

    fn workspace() -> (tempfile::TempDir, Workspace) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("fixtures")).unwrap();
        let root = dir.path().canonicalize().unwrap();
        (
            dir,
            Workspace {
                current_dir: root.clone(),
                root,
            },
        )
    }

    fn plan() -> ReproduceArgs {
        ReproduceArgs {
            seeds: Some(2),
            tasks: vec![crate::cli::Task::Task1],
            methods: vec!["ea-madm".to_owned(), "softmax".to_owned()],
            config: None,
            out: Some("out".into()),
            quick: true,
            wait: false,
            keep_trajectories: KeepTrajectories::Figures,
            readings: Readings::None,
            pretrained_cache: None,
            suites: vec![],
            family_size: None,
        }
    }

    fn verify_all(ws: &Workspace) -> Result<(), Failure> {
        verify(
            &VerifyArgs {
                plan: plan(),
                sample: None,
                all: true,
                sample_seed: 0,
            },
            ws,
        )
    }

    /// Rewrites the bundle `path` with `edit` applied to its lines (without newlines).
    fn edit_bundle(path: &Path, edit: impl Fn(usize, String) -> String) {
        let bytes = std::fs::read(path).unwrap();
        let text = String::from_utf8(eamadm_runs::frames::decompress(&bytes).unwrap()).unwrap();
        let lines: String = text
            .lines()
            .enumerate()
            .map(|(i, line)| edit(i, line.to_owned()) + "\n")
            .collect();
        std::fs::write(
            path,
            eamadm_runs::frames::compress(lines.as_bytes()).unwrap(),
        )
        .unwrap();
    }

    /// A record whose numbers were forged (every step count halved) and whose checksum was
    /// recomputed opens as a valid store; `verify` recomputes it and names it (9dc06af had no
    /// way to tell).
    #[test]
    fn verify_finds_a_forged_record_and_a_poisoned_artefact() {
        let (_dir, ws) = workspace();
        crate::reproduce::reproduce_paper(
            &ReproduceCommand {
                plan: plan(),
                mode: RunModeArgs::default(),
            },
            &ws,
        )
        .unwrap();
        verify_all(&ws).unwrap();
        let bundle = ws.root.join("out/runs/task1.jsonl.zst");
        edit_bundle(&bundle, |i, line| {
            if i != 0 {
                return line;
            }
            let start = line.find("\"steps\":[").unwrap() + "\"steps\":[".len();
            let end = start + line[start..].find(']').unwrap();
            let halved: Vec<String> = line[start..end]
                .split(',')
                .map(|n| (n.parse::<u64>().unwrap() / 2).to_string())
                .collect();
            let forged = format!("{}{}{}", &line[..start], halved.join(","), &line[end..]);
            String::from_utf8(
                eamadm_runs::store::with_checksum_recomputed(forged.as_bytes()).unwrap(),
            )
            .unwrap()
        });
        let store = RunStore::open(&ws.root.join("out"), &mut |w| panic!("{w}")).unwrap();
        assert_eq!(store.len(), 4, "the forged line checks");
        let failure = verify_all(&ws).unwrap_err();
        assert_eq!(failure.exit_code, 1);
        assert!(
            failure.message.contains("1 of the results"),
            "{}",
            failure.message
        );
        // Put the true line back; poison an artefact: one sub-task's learner swapped for the
        // same sub-task's of the other seed, its checksum recomputed.
        std::fs::remove_dir_all(ws.root.join("out")).unwrap();
        crate::reproduce::reproduce_paper(
            &ReproduceCommand {
                plan: plan(),
                mode: RunModeArgs::default(),
            },
            &ws,
        )
        .unwrap();
        verify_all(&ws).unwrap();
        let cache = PretrainedStore::new(&ws.root.join("target/pretrained-cache"));
        let mut by_subtask: std::collections::BTreeMap<String, Vec<_>> = Default::default();
        for key in cache.keys().unwrap() {
            let (description, subtask) = cache.load_any(&key).unwrap().unwrap();
            let value: serde_json::Value = serde_json::from_str(&description).unwrap();
            by_subtask
                .entry(value["subtask"].to_string())
                .or_default()
                .push((key, value, subtask));
        }
        let same_subtask = by_subtask.values().find(|found| found.len() >= 2).unwrap();
        let (victim, _, _) = &same_subtask[0];
        let (_, _, other_seed) = &same_subtask[1];
        let (description, _) = cache.load_any(victim).unwrap().unwrap();
        let description: eamadm_runs::PretrainingDescription = {
            // Rebuilt from the plan: the description whose canonical JSON is stored.
            let (plan, experiments) = prepare(&plan(), &ws).unwrap();
            let _ = plan;
            experiments
                .iter()
                .flat_map(|planned| {
                    let methods: Vec<_> = planned.config().methods.iter().collect();
                    planned
                        .config()
                        .seed_values()
                        .flat_map(|seed| artefacts_of(&planned.experiment, &methods, seed).unwrap())
                        .map(|(description, _, _)| description)
                        .collect::<Vec<_>>()
                })
                .find(|candidate| eamadm_runs::canonical_json(candidate).unwrap() == description)
                .unwrap()
        };
        std::fs::write(
            cache.path(victim),
            eamadm_runs::pretrained::artefact_file(&description, other_seed).unwrap(),
        )
        .unwrap();
        assert!(
            cache.load(&description).unwrap().is_some(),
            "the poisoned artefact checks"
        );
        let failure = verify_all(&ws).unwrap_err();
        assert!(
            failure.message.contains("1 of the results"),
            "{}",
            failure.message
        );
    }

    #[test]
    fn the_sample_is_a_seeded_fraction_of_at_least_one() {
        let keys: Vec<eamadm_runs::RunKey> = (0..100_u64)
            .map(|i| eamadm_runs::RunKey::of(&i).unwrap())
            .collect();
        let pick = |fraction, seed| sample(keys.clone(), |key| key, fraction, seed);
        assert_eq!(pick(Some(0.05), 0).len(), 5);
        assert_eq!(pick(Some(0.05), 0), pick(Some(0.05), 0));
        assert_ne!(pick(Some(0.05), 0), pick(Some(0.05), 1));
        assert_eq!(pick(Some(0.001), 3).len(), 1);
        assert_eq!(pick(None, 0), keys);
        // In the given order.
        let five = pick(Some(0.05), 7);
        let mut sorted = five.clone();
        sorted.sort_by_key(|key| keys.iter().position(|k| k == key));
        assert_eq!(five, sorted);
    }
}
