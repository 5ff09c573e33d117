//! `cargo xtask reproduce-paper`, `run-job` and `merge`: check everything (arguments, config,
//! tasks) before touching the output folder, run (resuming) the plan's runs — all, one shard, or
//! one job — into the run store, then write the results, figures and `REPORT.md` from the store.

use std::path::Path;
use std::time::Instant;

use crate::Failure;
use crate::cli::{KeepTrajectories, MergeArgs, ReproduceArgs, ReproduceCommand, RunJobArgs};
use crate::experiments::{PlannedExperiment, load_config_file, plan_experiments};
use crate::finish::{Outputs, write_outputs};
use crate::jobs::{Shard, plan_arguments, plan_jobs, run_jobs};
use crate::plan::{QUICK_SEEDS, ReproducePlan, Workspace, default_methods};
use crate::progress::Progress;
use eamadm_runs::output_folder::OutputFolder;
use eamadm_runs::{PretrainedStore, RunKey, RunStore};

/// Prints a warning (a damaged run that will be recomputed, a line a merge ignores).
#[expect(
    clippy::print_stderr,
    reason = "a command-line tool reports warnings on stderr"
)]
pub(crate) fn warn_on_stderr(message: &str) {
    eprintln!("warning: {message}");
}

/// The checked plan of `args` and its loaded experiments. Touches nothing on disk.
pub(crate) fn prepare(
    args: &ReproduceArgs,
    workspace: &Workspace,
) -> Result<(ReproducePlan, Vec<PlannedExperiment>), Failure> {
    // Everything is checked before the output folder is created: a bad config writes nothing.
    let custom = match &args.config {
        Some(path) => {
            Some(load_config_file(&workspace.current_dir.join(path)).map_err(Failure::invalid)?)
        }
        None => None,
    };
    let known: Vec<String> = match &custom {
        Some(config) => config.methods.iter().map(|m| m.label.clone()).collect(),
        None => default_methods(),
    };
    if let (Some(config), None) = (&custom, args.seeds)
        && config.seeds > crate::cli::MAX_SEEDS
    {
        return Err(Failure::invalid(format!(
            "{}: `seeds` = {} is more than a plan may run ({}, as for --seeds); lower it, or \
             pass --seeds",
            args.config
                .as_deref()
                .unwrap_or(Path::new("config"))
                .display(),
            config.seeds,
            crate::cli::MAX_SEEDS
        )));
    }
    let mut plan = ReproducePlan::from_args(args, &known, workspace).map_err(Failure::invalid)?;
    if let (Some(config), None) = (&custom, args.seeds) {
        plan.seeds = if plan.quick {
            QUICK_SEEDS.min(config.seeds)
        } else {
            config.seeds
        };
    }
    let config_file = plan.config.as_deref().zip(custom.as_ref());
    let mut experiments = plan_experiments(
        &plan.tasks,
        !args.tasks.is_empty(),
        config_file,
        plan.seeds,
        plan.quick,
        plan.readings,
    )
    .map_err(Failure::invalid)?;
    let family = args.suites.contains(&crate::cli::Suite::Family);
    match (family, args.family_size) {
        (false, Some(_)) => {
            return Err(Failure::invalid(
                "--family-size: only with --suite family (it sets how many layouts the family \
                 runs); add --suite family or drop --family-size",
            ));
        }
        (true, size) => experiments.extend(crate::experiments::family_experiments(
            size.unwrap_or(eamadm::family::DEFAULT_FAMILY_SIZE),
            args.seeds,
            plan.quick,
        )?),
        (false, None) => {}
    }
    let stage1 =
        crate::tuning_suite::stage1(&args.suites, &experiments, &plan.methods, plan.quick)?;
    experiments.extend(stage1);
    Ok((plan, experiments))
}

/// The task name of an experiment for `--list-jobs` (a reading's experiment runs its base's
/// task).
fn task_name(
    args: &ReproduceArgs,
    plan: &ReproducePlan,
    experiments: &[PlannedExperiment],
    experiment: usize,
) -> &'static str {
    if experiments
        .get(experiment)
        .is_some_and(|planned| planned.family.is_some())
    {
        return "family";
    }
    let experiment = experiments.get(experiment).map_or(experiment, |planned| {
        planned
            .reading
            .map(|(_, base)| base)
            .or_else(|| planned.tuning.as_ref().map(|run| run.base))
            .unwrap_or(experiment)
    });
    if args.config.is_some() {
        "config"
    } else {
        plan.tasks
            .get(experiment)
            .map_or("config", |task| task.name())
    }
}

/// Runs `reproduce-paper`.
pub(crate) fn reproduce_paper(
    command: &ReproduceCommand,
    workspace: &Workspace,
) -> Result<(), Failure> {
    let args = &command.plan;
    let shard = match &command.mode.shard {
        Some(text) => Some(Shard::parse(text).map_err(Failure::invalid)?),
        None => None,
    };
    let (plan, mut experiments) = prepare(args, workspace)?;
    if command.mode.list_jobs {
        // Stage 2 of a tuning suite is listed once stage 1 is in --out's store.
        let stores = existing_store(&plan.out)?;
        if let Some((missing, of)) = crate::tuning_suite::extend_with_stage2(
            &mut experiments,
            &plan.methods,
            &stores,
            args.keep_trajectories,
        )? {
            warn_on_stderr(&crate::tuning_suite::pending_message(missing, of));
        }
        let jobs = plan_jobs(&experiments, &plan.methods).map_err(Failure::failed)?;
        return print_lines(
            &mut std::io::stdout().lock(),
            &job_lines(args, &plan, &experiments, &jobs, workspace)?,
        );
    }
    // One process per output folder; what a killed earlier invocation left is repaired here.
    let folder = OutputFolder::open(&plan.out, args.wait).map_err(Failure::failed)?;
    let started = Instant::now();
    let keep = args.keep_trajectories;
    let mut store = RunStore::open(folder.root(), &mut warn_on_stderr).map_err(Failure::failed)?;
    // A rerun after stage 1 of a tuning suite completed plans its stage 2 now.
    let mut pending = crate::tuning_suite::extend_with_stage2(
        &mut experiments,
        &plan.methods,
        std::slice::from_ref(&store),
        keep,
    )?;
    let mut jobs = plan_jobs(&experiments, &plan.methods).map_err(Failure::failed)?;
    let planned_runs = jobs.len();
    if let Some(shard) = shard {
        jobs.retain(|job| shard.holds(&job.key));
    }
    print!("{}", plan.describe());
    // The bound above counts every method for every task; this is what will run.
    println!(
        "  runs:     {planned_runs} planned (each task's own methods × seeds, the readings' \
         reruns included)"
    );
    print!(
        "{}",
        crate::sensitivity_report::describe_readings(&experiments, &jobs)
    );
    if let Some(shard) = shard {
        println!(
            "  shard:    {shard}: {} of the runs; the report is made by `cargo xtask merge`",
            jobs.len()
        );
    }
    print!(
        "{}",
        crate::tuning_suite::describe(&experiments, &jobs, pending)
    );

    let artefacts = PretrainedStore::new(&plan.pretrained_cache);
    let mut counts = crate::jobs::RunCounts::default();
    // Stage 2 of a tuning suite is planned once stage 1's runs are stored: after this loop's
    // first pass in an unsharded run.
    let mut first_new = 0;
    loop {
        let executed = run_jobs(
            &experiments,
            &jobs[first_new..],
            &store,
            &artefacts,
            keep,
            &Progress::for_stdout(),
            &warn_on_stderr,
        )
        .map_err(Failure::failed)?;
        counts.ran += executed.counts.ran;
        counts.resumed += executed.counts.resumed;
        counts.pretrained += executed.counts.pretrained;
        counts.pretrained_loaded += executed.counts.pretrained_loaded;
        // Reopened, with the runs stored above (its damaged entries were reported by the first
        // open), and packed below: every run stored in the folder, this plan's in job order.
        // The runs stored above are indexed from their receipts while their files hold the
        // bytes written, and what the first open checked is not read again (the folder's lock,
        // held since, keeps other packers out).
        store = store
            .reopen(&executed.receipts, &mut |_| {})
            .map_err(Failure::failed)?;
        drop(executed);
        if shard.is_some() || pending.is_none() {
            break;
        }
        first_new = jobs.len();
        drop(jobs);
        pending = crate::tuning_suite::extend_with_stage2(
            &mut experiments,
            &plan.methods,
            std::slice::from_ref(&store),
            keep,
        )?;
        jobs = plan_jobs(&experiments, &plan.methods).map_err(Failure::failed)?;
        if pending.is_some() || jobs.len() == first_new {
            break;
        }
        println!(
            "  tuning:   stage 1 complete; stage 2: {} runs (each method's chosen trial on the \
             held-out seeds)",
            jobs.len() - first_new
        );
    }
    if let Some((missing, of)) = pending {
        warn_on_stderr(&crate::tuning_suite::pending_message(missing, of));
    }
    let reporting = shard.is_none() && !command.mode.runs_only && pending.is_none();
    let keys: Vec<RunKey> = jobs.iter().map(|job| job.key.clone()).collect();
    let store = store
        .pack(&folder, &[], &keys, &mut warn_on_stderr)
        .map_err(Failure::failed)?;
    if reporting {
        // The set of outputs is written aside and swapped in whole (see `output_folder`); the
        // run store was packed above.
        let staging = folder.staging().map_err(Failure::failed)?;
        write_outputs(
            folder.root(),
            &staging,
            &experiments,
            &jobs,
            &[store],
            keep,
            Outputs::Everything {
                quick: plan.quick,
                pretrained_cache: &plan.pretrained_cache,
            },
        )
        .map_err(Failure::failed)?;
        folder.commit().map_err(Failure::failed)?;
    } else {
        write_outputs(
            folder.root(),
            folder.root(),
            &experiments,
            &jobs,
            &[store],
            keep,
            Outputs::StoreOnly,
        )
        .map_err(Failure::failed)?;
    }
    // Temporary files of artefact writers that are gone (coordinated: writers of other
    // output folders may be at work in the cache).
    artefacts
        .remove_stale_temporary_files()
        .map_err(Failure::failed)?;
    println!(
        "done in {:.1} s: {} runs ({} resumed from an earlier invocation); {}",
        started.elapsed().as_secs_f64(),
        jobs.len(),
        counts.resumed,
        describe_pretraining(&counts, &artefacts),
    );
    if reporting {
        println!("report: {}", plan.out.join("REPORT.md").display());
    } else {
        println!("run store: {}", plan.out.join("runs").display());
    }
    Ok(())
}

/// The run store of the output folder `out` opened read-only, when it has one (none: empty).
fn existing_store(out: &Path) -> Result<Vec<RunStore>, Failure> {
    if !out.join(eamadm_runs::names::RUNS_FOLDER).is_dir() {
        return Ok(Vec::new());
    }
    let store = RunStore::open_read_only(out, &mut warn_on_stderr).map_err(Failure::failed)?;
    Ok(vec![store])
}

/// Writes `lines` to `out`, one a line; a reader that stops reading (`--list-jobs | head -1`)
/// ends the listing quietly (exit 0) instead of the panic `println!` raises on a closed pipe.
fn print_lines(out: &mut dyn std::io::Write, lines: &[String]) -> Result<(), Failure> {
    for line in lines {
        match writeln!(out, "{line}") {
            Ok(()) => {}
            Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => return Ok(()),
            Err(error) => return Err(Failure::failed(format!("cannot print the jobs: {error}"))),
        }
    }
    match out.flush() {
        Err(error) if error.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(Failure::failed(format!("cannot print the jobs: {error}")))
        }
        _ => Ok(()),
    }
}

/// The `--list-jobs` lines of `jobs`: one JSON object per run.
fn job_lines(
    args: &ReproduceArgs,
    plan: &ReproducePlan,
    experiments: &[PlannedExperiment],
    jobs: &[crate::jobs::Job<'_>],
    workspace: &Workspace,
) -> Result<Vec<String>, Failure> {
    let arguments = plan_arguments(args, &plan.out, &workspace.current_dir);
    jobs.iter()
        .map(|job| {
            let experiment = &experiments[job.experiment].name;
            let task = task_name(args, plan, experiments, job.experiment);
            serde_json::to_string(&job.line(experiment, task, &arguments)).map_err(Failure::failed)
        })
        .collect()
}

/// Runs `run-job`: exactly the run `--key` of the plan, into the run store of `--out`.
pub(crate) fn run_job(args: &RunJobArgs, workspace: &Workspace) -> Result<(), Failure> {
    let (plan, mut experiments) = prepare(&args.plan, workspace)?;
    let keep = args.plan.keep_trajectories;
    let store = RunStore::open(&plan.out, &mut warn_on_stderr).map_err(Failure::failed)?;
    // A stage-2 key of a tuning suite exists once stage 1 is in this store.
    let pending = crate::tuning_suite::extend_with_stage2(
        &mut experiments,
        &plan.methods,
        std::slice::from_ref(&store),
        keep,
    )?;
    let jobs = plan_jobs(&experiments, &plan.methods).map_err(Failure::failed)?;
    let Some(job) = jobs.iter().find(|job| job.key.as_str() == args.key) else {
        return Err(Failure::invalid(format!(
            "--key {}: no run of this plan has this key; list the keys with `cargo xtask \
             reproduce-paper --list-jobs` and the same options{}",
            args.key,
            pending.map_or_else(String::new, |(missing, of)| format!(
                " ({})",
                crate::tuning_suite::pending_message(missing, of)
            ))
        )));
    };
    let artefacts = PretrainedStore::new(&plan.pretrained_cache);
    let counts = run_jobs(
        &experiments,
        std::slice::from_ref(job),
        &store,
        &artefacts,
        keep,
        &Progress::hidden(),
        &warn_on_stderr,
    )
    .map_err(Failure::failed)?
    .counts;
    println!(
        "{} {} seed {}: {} ({}); {}",
        experiments[job.experiment].name,
        job.method.label,
        job.seed,
        if counts.ran == 1 {
            "ran"
        } else {
            "already stored"
        },
        store.folder().display(),
        describe_pretraining(&counts, &artefacts),
    );
    Ok(())
}

/// What a command did about pre-training, for its last line: how many sub-tasks it trained
/// and how many it loaded from the cache of artefacts, which another process, shard or earlier
/// invocation trained.
fn describe_pretraining(counts: &crate::jobs::RunCounts, cache: &PretrainedStore) -> String {
    format!(
        "sub-tasks pre-trained: {}, loaded from {}: {}",
        counts.pretrained,
        cache.folder().display(),
        counts.pretrained_loaded
    )
}

/// Runs `merge`: checks the given stores, then writes the plan's outputs from them.
pub(crate) fn merge(args: &MergeArgs, workspace: &Workspace) -> Result<(), Failure> {
    let (plan, mut experiments) = prepare(&args.plan, workspace)?;
    let keep: KeepTrajectories = args.plan.keep_trajectories;
    let mut stores = Vec::new();
    for path in &args.stores {
        let store =
            RunStore::open_read_only(&workspace.current_dir.join(path), &mut warn_on_stderr)
                .map_err(Failure::invalid)?;
        println!(
            "store {}: {} checked runs",
            store.folder().display(),
            store.len()
        );
        stores.push(store);
    }
    // Stage 2 of a tuning suite is planned once stage 1 is in the stores; while it is not,
    // its missing runs are listed below.
    let pending =
        crate::tuning_suite::extend_with_stage2(&mut experiments, &plan.methods, &stores, keep)?;
    let jobs = plan_jobs(&experiments, &plan.methods).map_err(Failure::failed)?;
    // Every run must be there, and the sample asked for recompute to what is stored, before
    // the output folder is touched.
    if let Some(fraction) = args.verify {
        crate::verify::check_or_fail(
            &experiments,
            &jobs,
            &stores,
            &PretrainedStore::new(&plan.pretrained_cache),
            Some(fraction),
            0,
        )?;
    }
    let missing = crate::finish::missing_runs(&experiments, &jobs, &stores, keep);
    let stage2_only = crate::tuning_suite::only_stage2_missing(&experiments, &jobs, &stores, keep);
    if !missing.is_empty() && !stage2_only {
        return Err(Failure::failed(crate::finish::FinishError::Missing {
            missing,
            total: jobs.len(),
        }));
    }
    debug_assert!(pending.is_none() || !missing.is_empty());
    let folder = OutputFolder::open(&plan.out, args.plan.wait).map_err(Failure::failed)?;
    if stage2_only {
        // The shards ran stage 1 of a tuning suite, which plans stage 2: stage 1 is packed
        // into this folder's store, where a rerun runs stage 2.
        let own = RunStore::open(folder.root(), &mut warn_on_stderr).map_err(Failure::failed)?;
        let keys: Vec<RunKey> = jobs
            .iter()
            .filter(|job| stores.iter().any(|store| store.has(&job.key, keep)))
            .map(|job| job.key.clone())
            .collect();
        own.pack(&folder, &stores, &keys, &mut warn_on_stderr)
            .map_err(Failure::failed)?;
        return Err(Failure::failed(format!(
            "--suite tuning: stage 1 is complete and now stored in {}; stage 2 ({} runs: each \
             method's chosen trial on the held-out seeds) could not be planned before it and is \
             not run yet. Run it there with the same plan options: `cargo xtask reproduce-paper \
             ... --out {}` (resumes stage 1, runs stage 2 and writes the report), or list its \
             jobs with `--list-jobs --out {}` and run them with `run-job`",
            plan.out.join(eamadm_runs::names::RUNS_FOLDER).display(),
            missing.len(),
            plan.out.display(),
            plan.out.display()
        )));
    }
    let started = Instant::now();
    // The output folder's store keeps what it holds and gains the plan's runs from the others.
    let own = RunStore::open(folder.root(), &mut warn_on_stderr).map_err(Failure::failed)?;
    let keys: Vec<RunKey> = jobs.iter().map(|job| job.key.clone()).collect();
    let own = own
        .pack(&folder, &stores, &keys, &mut warn_on_stderr)
        .map_err(Failure::failed)?;
    // Artefacts a shard of an earlier version kept in its own folder (`runs/pretrained/`)
    // join the cache, so a later plan loads rather than pre-trains them.
    let artefacts = PretrainedStore::new(&plan.pretrained_cache);
    for store in &stores {
        let legacy = PretrainedStore::new(&store.folder().join(eamadm_runs::names::PRETRAINED));
        artefacts
            .adopt(&legacy, &mut warn_on_stderr)
            .map_err(Failure::failed)?;
    }
    let staging = folder.staging().map_err(Failure::failed)?;
    let runs = write_outputs(
        folder.root(),
        &staging,
        &experiments,
        &jobs,
        &[own],
        keep,
        Outputs::Everything {
            quick: plan.quick,
            pretrained_cache: &plan.pretrained_cache,
        },
    )
    .map_err(Failure::failed)?;
    folder.commit().map_err(Failure::failed)?;
    println!(
        "merged {runs} runs in {:.1} s\nreport: {}",
        started.elapsed().as_secs_f64(),
        plan.out.join("REPORT.md").display()
    );
    Ok(())
}
