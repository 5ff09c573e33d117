//! `cargo xtask reproduce-paper`, `run-job` and `merge`: check everything (arguments, config,
//! tasks) before touching the output folder, run (resuming) the plan's runs — all, one shard, or
//! one job — into the run store, then write the results, figures and `REPORT.md` from the store.

use std::path::Path;
use std::time::Instant;

use crate::Failure;
use crate::cli::{KeepTrajectories, MergeArgs, ReproduceArgs, ReproduceCommand, RunJobArgs};
use crate::execute::run_jobs;
use crate::experiments::{PlannedExperiment, load_config_file, plan_experiments};
use crate::finish::{Outputs, write_outputs};
use crate::jobs::{JobLine, Shard, plan_arguments, plan_jobs};
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
    let mut counts = crate::execute::RunCounts::default();
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
            let mut run = vec![
                "run-job".to_owned(),
                "--key".to_owned(),
                job.key.to_string(),
            ];
            run.extend(arguments.iter().cloned());
            let line = JobLine {
                key: job.key.as_str(),
                experiment: &experiments[job.experiment].name,
                task: task_name(args, plan, experiments, job.experiment),
                method: &job.method.label,
                seed: job.seed,
                run,
            };
            serde_json::to_string(&line).map_err(Failure::failed)
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
fn describe_pretraining(counts: &crate::execute::RunCounts, cache: &PretrainedStore) -> String {
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

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::cli::RunModeArgs;

    fn args(config: Option<&str>, out: &str) -> ReproduceArgs {
        ReproduceArgs {
            seeds: Some(1),
            tasks: vec![],
            methods: vec!["epsilon-greedy".to_owned()],
            config: config.map(Into::into),
            out: Some(out.into()),
            quick: true,
            wait: false,
            keep_trajectories: KeepTrajectories::Figures,
            readings: crate::cli::Readings::All,
            pretrained_cache: None,
            suites: vec![],
            family_size: None,
        }
    }

    fn command(plan: ReproduceArgs, mode: RunModeArgs) -> ReproduceCommand {
        ReproduceCommand { plan, mode }
    }

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

    /// Every file under `folder` (relative path → bytes).
    fn tree(folder: &Path) -> BTreeMap<String, Vec<u8>> {
        let mut files = BTreeMap::new();
        let mut stack = vec![folder.to_path_buf()];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                } else {
                    let name = path.strip_prefix(folder).unwrap().display().to_string();
                    files.insert(name, std::fs::read(&path).unwrap());
                }
            }
        }
        files
    }

    fn assert_same_tree(a: &Path, b: &Path) {
        let (a, b) = (tree(a), tree(b));
        assert_eq!(
            a.keys().collect::<Vec<_>>(),
            b.keys().collect::<Vec<_>>(),
            "the same files"
        );
        for (name, bytes) in &a {
            assert!(b[name] == *bytes, "{name} differs");
        }
    }

    /// The lines of a bundle (any framing), without their newlines.
    fn bundle_lines(bytes: &[u8]) -> Vec<String> {
        String::from_utf8(eamadm_runs::frames::decompress(bytes).unwrap())
            .unwrap()
            .lines()
            .map(str::to_owned)
            .collect()
    }

    /// Runs per seed of the readings [`small`] plans on Task I (the readings change no robot
    /// task): γ (EA-MADM and softmax), pre-training half, double and fixed (EA-MADM) and the
    /// temperature floor (softmax).
    const SMALL_READING_RUNS_PER_SEED: usize = 6;

    /// A small plan: two methods, two seeds, Task I and the robot, shortened by a config-free
    /// --quick.
    fn small(out: &str) -> ReproduceArgs {
        ReproduceArgs {
            seeds: Some(2),
            tasks: vec![crate::cli::Task::Task1, crate::cli::Task::Robot],
            methods: vec!["ea-madm".to_owned(), "softmax".to_owned()],
            config: None,
            out: Some(out.into()),
            quick: true,
            wait: false,
            keep_trajectories: KeepTrajectories::Figures,
            readings: crate::cli::Readings::All,
            pretrained_cache: None,
            suites: vec![],
            family_size: None,
        }
    }

    #[test]
    fn an_invalid_config_names_the_field_and_writes_nothing() {
        let (_dir, ws) = workspace();
        let text = eamadm::PAPER_TASK2_TOML.replace("gamma = 0.95", "gamma = 1.5");
        std::fs::write(ws.root.join("bad.toml"), text).unwrap();
        let failure = reproduce_paper(
            &command(args(Some("bad.toml"), "out"), RunModeArgs::default()),
            &ws,
        )
        .unwrap_err();
        assert_eq!(failure.exit_code, 2);
        assert!(
            failure.message.contains("`learner.gamma` = 1.5"),
            "{}",
            failure.message
        );
        assert!(!ws.root.join("out").exists());
    }

    #[test]
    fn a_valid_config_runs_and_writes_every_output() {
        let (_dir, ws) = workspace();
        let mut config = eamadm::paper::task1();
        config.name = "mine".to_owned();
        config.episodes = 3;
        std::fs::write(ws.root.join("mine.toml"), config.to_toml_string().unwrap()).unwrap();
        reproduce_paper(
            &command(args(Some("mine.toml"), "out"), RunModeArgs::default()),
            &ws,
        )
        .unwrap();
        for file in [
            "REPORT.md",
            "runs/mine.jsonl.zst",
            "mine/curves.csv.gz",
            "mine/trajectories.csv.gz",
            "mine/steps.svg",
            "mine/return.svg",
            "mine/trajectories.svg",
        ] {
            assert!(ws.root.join("out").join(file).is_file(), "{file}");
        }
        let report = std::fs::read_to_string(ws.root.join("out/REPORT.md")).unwrap();
        assert!(report.contains("## mine (`mine`)"), "{report}");
        // Every visible top-level entry but the experiment's folder is a name configs may not
        // take, so no experiment can overwrite it.
        for entry in std::fs::read_dir(ws.root.join("out")).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            if name.starts_with('.') || name == "mine" {
                continue;
            }
            assert!(
                eamadm::RESERVED_NAMES
                    .iter()
                    .any(|reserved| reserved.eq_ignore_ascii_case(&name)),
                "{name} is not reserved"
            );
        }
    }

    fn write_config(ws: &Workspace, file: &str, name: &str) {
        let mut config = eamadm::paper::task1();
        config.name = name.to_owned();
        config.episodes = 3;
        std::fs::write(ws.root.join(file), config.to_toml_string().unwrap()).unwrap();
    }

    #[test]
    fn a_run_of_other_arguments_leaves_no_stale_outputs() {
        let (_dir, ws) = workspace();
        write_config(&ws, "first.toml", "first");
        write_config(&ws, "second.toml", "second");
        reproduce_paper(
            &command(args(Some("first.toml"), "out"), RunModeArgs::default()),
            &ws,
        )
        .unwrap();
        assert!(ws.root.join("out/first/curves.csv.gz").is_file());
        reproduce_paper(
            &command(args(Some("second.toml"), "out"), RunModeArgs::default()),
            &ws,
        )
        .unwrap();
        let out = ws.root.join("out");
        assert!(
            !out.join("first").exists(),
            "the first run's outputs are gone"
        );
        assert!(out.join("second/curves.csv.gz").is_file());
        let manifest = std::fs::read_to_string(out.join(".outputs")).unwrap();
        assert!(
            manifest.lines().all(|line| !line.starts_with("first/")),
            "{manifest}"
        );
        assert!(manifest.contains("REPORT.md\n"), "{manifest}");
        assert!(!out.join(".staging").exists() && !out.join(".committed").exists());
        // The run store is not part of the set: both runs' records stay for resuming.
        let bundles = std::fs::read_dir(out.join("runs"))
            .unwrap()
            .filter(|e| {
                let name = e.as_ref().unwrap().file_name();
                name.to_string_lossy().ends_with(".jsonl.zst")
            })
            .count();
        assert_eq!(bundles, 2);
    }

    #[test]
    fn names_that_would_escape_the_output_folder_are_refused_before_writing() {
        let (_dir, ws) = workspace();
        for name in ["..", "runs", "REPORT.md"] {
            let text = eamadm::PAPER_TASK1_TOML.replacen(
                "name = \"task1\"",
                &format!("name = {name:?}"),
                1,
            );
            std::fs::write(ws.root.join("bad.toml"), text).unwrap();
            let failure = reproduce_paper(
                &command(args(Some("bad.toml"), "out/sub"), RunModeArgs::default()),
                &ws,
            )
            .unwrap_err();
            assert_eq!(failure.exit_code, 2, "{name}: {}", failure.message);
            assert!(failure.message.contains("`name`"), "{}", failure.message);
            assert!(!ws.root.join("out").exists(), "{name}");
        }
    }

    #[test]
    fn a_busy_output_folder_is_refused_with_a_clear_message() {
        let (_dir, ws) = workspace();
        write_config(&ws, "mine.toml", "mine");
        let held = OutputFolder::open(&ws.root.join("out"), false).unwrap();
        let failure = reproduce_paper(
            &command(args(Some("mine.toml"), "out"), RunModeArgs::default()),
            &ws,
        )
        .unwrap_err();
        assert_eq!(failure.exit_code, 1);
        assert!(
            failure
                .message
                .contains("another reproduce-paper is using this output folder"),
            "{}",
            failure.message
        );
        assert!(!ws.root.join("out/REPORT.md").exists());
        drop(held);
        reproduce_paper(
            &command(args(Some("mine.toml"), "out"), RunModeArgs::default()),
            &ws,
        )
        .unwrap();
    }

    /// Splits a line of a CSV without quoted fields (the claim and score tables have none).
    fn cells(line: &str) -> Vec<&str> {
        line.split(',').collect()
    }

    #[test]
    fn claims_csv_can_be_recomputed_from_final_scores_csv() {
        use eamadm::stats::{self, Bootstrap, Statistic};
        let (_dir, ws) = workspace();
        let args = ReproduceArgs {
            seeds: Some(3),
            tasks: vec![crate::cli::Task::Task1],
            methods: vec![
                "ea-madm".to_owned(),
                "softmax".to_owned(),
                "epsilon-greedy".to_owned(),
            ],
            config: None,
            out: Some("out".into()),
            quick: true,
            wait: false,
            keep_trajectories: KeepTrajectories::Figures,
            readings: crate::cli::Readings::All,
            pretrained_cache: None,
            suites: vec![],
            family_size: None,
        };
        reproduce_paper(&command(args, RunModeArgs::default()), &ws).unwrap();
        let out = ws.root.join("out");
        let scores =
            eamadm::scores::read_csv(std::fs::File::open(out.join("final-scores.csv")).unwrap())
                .unwrap();
        assert_eq!(scores.len(), 9);
        let claims = std::fs::read_to_string(out.join("claims.csv")).unwrap();
        let mut lines = claims.lines();
        let header = cells(lines.next().unwrap());
        let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
        // Per seed (in seed order) the value of `metric`, where the cell is not empty.
        let seeded = |method: &str, metric: &str| -> Vec<(u64, f64)> {
            let mut v: Vec<(u64, f64)> = scores
                .iter()
                .filter(|s| s.method == method)
                .filter_map(|s| Some((s.seed, s.value(metric)?)))
                .collect();
            v.sort_by_key(|&(seed, _)| seed);
            v
        };
        let of = |method: &str, metric: &str| -> Vec<f64> {
            seeded(method, metric).into_iter().map(|(_, v)| v).collect()
        };
        let number = |cell: &str| cell.parse::<f64>().unwrap();
        let (mut singles, mut comparisons, mut outcomes, mut per_seed) = (0, 0, 0, 0);
        // Holm groups: (claim, method, what): the deciding comparisons with C3's per-seed tests
        // (one family), and the secondary ones (empty verdict); uninformative comparisons
        // take no part.
        type HolmGroup<'a> = (String, String, &'a str);
        let mut raw_p: std::collections::BTreeMap<HolmGroup<'_>, Vec<(f64, f64)>> =
            std::collections::BTreeMap::new();
        for line in lines {
            let row = cells(line);
            let (method, metric, versus) = (
                row[column("method")],
                row[column("metric")],
                row[column("versus")],
            );
            if row[column("claim")] == "outcome" {
                // The per-run outcome rows: converged share, and the exact sign test paired by
                // seed, recomputed from final-scores.csv's `outcome` column.
                let converged = |m: &str| -> Vec<(u64, bool)> {
                    let mut v: Vec<(u64, bool)> = scores
                        .iter()
                        .filter(|s| s.method == m)
                        .map(|s| (s.seed, s.outcome == eamadm::scores::RunOutcome::Converged))
                        .collect();
                    v.sort_unstable();
                    v
                };
                let mine = converged(method);
                if versus.is_empty() {
                    let hits = mine.iter().filter(|(_, c)| *c).count() as f64;
                    assert_eq!(number(row[column("estimate")]), hits / mine.len() as f64);
                } else {
                    let theirs = converged(versus);
                    let wins = mine
                        .iter()
                        .zip(&theirs)
                        .filter(|(a, b)| a.1 && !b.1)
                        .count();
                    let losses = mine
                        .iter()
                        .zip(&theirs)
                        .filter(|(a, b)| b.1 && !a.1)
                        .count();
                    assert_eq!(
                        number(row[column("p_value")]),
                        stats::sign_test(wins as u64, losses as u64),
                        "{line}"
                    );
                }
                outcomes += 1;
                continue;
            }
            if metric == "stable_reaching" || metric == "reached" {
                // A per-seed test, paired by seed: the exact sign test on the discordant seeds,
                // recomputed from the `stable_reaching` column (or, for `reached`, from
                // `greedy_reached` and `reaching_episodes`); an empty cell is not stable.
                let flag = |m: &str| -> Vec<(u64, bool)> {
                    let mut v: Vec<(u64, bool)> = scores
                        .iter()
                        .filter(|s| s.method == m)
                        .map(|s| {
                            let yes = if metric == "stable_reaching" {
                                s.stable_reaching == Some(true)
                            } else {
                                s.greedy_reached || s.reaching_episodes > 0
                            };
                            (s.seed, yes)
                        })
                        .collect();
                    v.sort_unstable();
                    v
                };
                let (mine, theirs) = (flag(method), flag(versus));
                let wins = mine
                    .iter()
                    .zip(&theirs)
                    .filter(|(a, b)| a.1 && !b.1)
                    .count();
                let losses = mine
                    .iter()
                    .zip(&theirs)
                    .filter(|(a, b)| b.1 && !a.1)
                    .count();
                let hits = |v: &[(u64, bool)]| v.iter().filter(|(_, y)| *y).count() as f64;
                let p = stats::sign_test(wins as u64, losses as u64);
                assert_eq!(number(row[column("p_value")]), p, "{line}");
                assert_eq!(
                    number(row[column("estimate")]),
                    (hits(&mine) - hits(&theirs)) / mine.len() as f64,
                    "{line}"
                );
                // C3's stable-reaching tests share one Holm family with its deciding
                // comparisons (issue 34).
                raw_p
                    .entry((
                        row[column("claim")].to_owned(),
                        method.to_owned(),
                        "deciding",
                    ))
                    .or_default()
                    .push((p, number(row[column("p_holm")])));
                per_seed += 1;
                continue;
            }
            let x = of(method, metric);
            if versus.is_empty() && x.is_empty() {
                // No seed has a value (e.g. no stable-reaching seed): an empty estimate.
                assert_eq!(row[column("estimate")], "", "{line}");
                singles += 1;
            } else if versus.is_empty() {
                // A single-method row: the IQM over seeds and its bootstrap interval.
                let interval = Bootstrap::default().interval(&x, Statistic::Iqm).unwrap();
                assert_eq!(
                    number(row[column("estimate")]),
                    stats::iqm(&x).unwrap(),
                    "{line}"
                );
                assert_eq!(number(row[column("ci_low")]), interval.low, "{line}");
                assert_eq!(number(row[column("ci_high")]), interval.high, "{line}");
                singles += 1;
            } else {
                let y = of(versus, metric);
                // Descriptive: the IQM difference with its bootstrap interval.
                let difference = Bootstrap::default()
                    .difference(&x, &y, Statistic::Iqm)
                    .unwrap();
                assert_eq!(
                    number(row[column("iqm_difference")]),
                    stats::iqm(&x).unwrap() - stats::iqm(&y).unwrap(),
                    "{line}"
                );
                assert_eq!(number(row[column("iqm_ci_low")]), difference.low, "{line}");
                assert_eq!(
                    number(row[column("iqm_ci_high")]),
                    difference.high,
                    "{line}"
                );
                // Deciding: paired by seed, the seeds where both have a value; the mean
                // difference with its exact sign-flip interval and beyond-margin p.
                let theirs = seeded(versus, metric);
                let (px, py): (Vec<f64>, Vec<f64>) = seeded(method, metric)
                    .into_iter()
                    .filter_map(|(seed, a)| {
                        theirs
                            .iter()
                            .find(|(s, _)| *s == seed)
                            .map(|&(_, b)| (a, b))
                    })
                    .unzip();
                let paired = eamadm::stats::paired::differences(&px, &py).unwrap();
                let means = eamadm::stats::SignFlipMeans::exact(&paired).unwrap();
                let margin = row[column("margin")].parse::<f64>().unwrap_or(0.0);
                assert_eq!(
                    number(row[column("estimate")]),
                    stats::mean(&paired).unwrap(),
                    "{line}"
                );
                let (low, high) = means.interval(0.95).unwrap();
                let cell = |name: &str| row[column(name)].parse::<f64>().ok();
                assert_eq!((cell("ci_low"), cell("ci_high")), (low, high), "{line}");
                let p = means.beyond_margin(margin).unwrap();
                assert_eq!(number(row[column("p_value")]), p, "{line}");
                assert_eq!(
                    number(row[column("paired_p_value")]),
                    eamadm::stats::SignFlipTest::default()
                        .p_value(
                            &paired,
                            Statistic::Mean,
                            eamadm::stats::Alternative::TwoSided
                        )
                        .unwrap(),
                    "{line}"
                );
                if row[column("informative")] == "false" {
                    // Left out of Holm.
                    assert_eq!(row[column("p_holm")], "", "{line}");
                    comparisons += 1;
                    continue;
                }
                let group = if row[column("verdict")].is_empty() {
                    "secondary"
                } else {
                    "deciding"
                };
                raw_p
                    .entry((row[column("claim")].to_owned(), method.to_owned(), group))
                    .or_default()
                    .push((p, number(row[column("p_holm")])));
                comparisons += 1;
            }
        }
        // C1, C2: one metric; C3: two deciding and two secondary. Three methods, one under
        // test, two competitors.
        assert_eq!(singles, 3 * (1 + 1 + 2 + 2));
        // C3's greedy fluctuation is compared with a competitor when both sides have 2 or
        // more stable-reaching seeds (and the method under test must have them to be compared
        // at all).
        let greedy = |m: &str| of(m, "fluctuation_greedy_steps").len() >= 2;
        let c3 = if greedy("ea-madm") {
            2 * ["softmax", "epsilon-greedy"]
                .iter()
                .filter(|m| greedy(m))
                .count()
        } else {
            0
        };
        assert_eq!(comparisons, 2 * (1 + 1 + 2) + c3);
        // C3's stable-reaching test against each competitor.
        assert_eq!(per_seed, 2);
        // One share per method, and the method under test against each competitor.
        assert_eq!(outcomes, 3 + 2);
        for ((claim, method, group), pairs) in raw_p {
            let raw: Vec<f64> = pairs.iter().map(|(p, _)| *p).collect();
            let holm: Vec<f64> = pairs.iter().map(|(_, h)| *h).collect();
            assert_eq!(stats::holm(&raw).unwrap(), holm, "{claim} {method} {group}");
        }
        let report = std::fs::read_to_string(out.join("REPORT.md")).unwrap();
        assert!(
            report.contains("## Verdicts on the paper's claims"),
            "{report}"
        );
    }

    #[test]
    fn three_shards_merged_equal_the_unsharded_run_byte_for_byte() {
        let (_dir, ws) = workspace();
        reproduce_paper(&command(small("whole"), RunModeArgs::default()), &ws).unwrap();
        let mut shards = Vec::new();
        for k in 1..=3 {
            let out = format!("shard{k}");
            let mode = RunModeArgs {
                shard: Some(format!("{k}/3")),
                ..RunModeArgs::default()
            };
            reproduce_paper(&command(small(&out), mode), &ws).unwrap();
            assert!(!ws.root.join(&out).join("REPORT.md").exists(), "no report");
            shards.push(std::path::PathBuf::from(out));
        }
        // Merging two of three shards names what is missing and writes nothing.
        let failure = merge(
            &MergeArgs {
                plan: small("merged"),
                stores: shards[..2].to_vec(),
                verify: None,
            },
            &ws,
        )
        .unwrap_err();
        assert!(
            failure.message.contains("are in none of the stores"),
            "{}",
            failure.message
        );
        assert!(failure.message.contains("seed"), "{}", failure.message);
        assert!(!ws.root.join("merged").exists());

        merge(
            &MergeArgs {
                plan: small("merged"),
                stores: shards.clone(),
                // The merge recomputes a third of the shards' runs and artefacts first.
                verify: Some(0.3),
            },
            &ws,
        )
        .unwrap();
        assert_same_tree(&ws.root.join("whole"), &ws.root.join("merged"));
    }

    #[test]
    fn run_job_over_the_job_list_rebuilds_the_same_store() {
        let (_dir, ws) = workspace();
        reproduce_paper(&command(small("whole"), RunModeArgs::default()), &ws).unwrap();
        let (plan, experiments) = prepare(&small("jobs"), &ws).unwrap();
        let jobs = plan_jobs(&experiments, &plan.methods).unwrap();
        // In reverse, so the appended order differs from job order.
        for job in jobs.iter().rev() {
            run_job(
                &RunJobArgs {
                    key: job.key.to_string(),
                    plan: small("jobs"),
                },
                &ws,
            )
            .unwrap();
        }
        let failure = run_job(
            &RunJobArgs {
                key: "0".repeat(64),
                plan: small("jobs"),
            },
            &ws,
        )
        .unwrap_err();
        assert_eq!(failure.exit_code, 2);
        assert!(
            failure.message.contains("--list-jobs"),
            "{}",
            failure.message
        );
        // Resuming everything (nothing left to run) compacts the store into job order.
        let mode = RunModeArgs {
            runs_only: true,
            ..RunModeArgs::default()
        };
        reproduce_paper(&command(small("jobs"), mode), &ws).unwrap();
        assert_same_tree(&ws.root.join("whole/runs"), &ws.root.join("jobs/runs"));
        merge(
            &MergeArgs {
                plan: small("merged"),
                stores: vec!["jobs".into()],
                verify: None,
            },
            &ws,
        )
        .unwrap();
        assert_same_tree(&ws.root.join("whole"), &ws.root.join("merged"));
    }

    #[test]
    fn each_listed_job_parses_back_to_the_plan_and_its_key() {
        use clap::Parser as _;
        let (_dir, ws) = workspace();
        let args = small("listed");
        let (plan, experiments) = prepare(&args, &ws).unwrap();
        let jobs = plan_jobs(&experiments, &plan.methods).unwrap();
        let lines = job_lines(&args, &plan, &experiments, &jobs, &ws).unwrap();
        assert_eq!(lines.len(), 2 * 2 * 2 + 2 * SMALL_READING_RUNS_PER_SEED);
        let mut keys = std::collections::BTreeSet::new();
        for (line, job) in lines.iter().zip(&jobs) {
            let value: serde_json::Value = serde_json::from_str(line).unwrap();
            assert_eq!(value["key"], job.key.as_str());
            assert_eq!(value["method"], job.method.label.as_str());
            assert_eq!(value["seed"], job.seed);
            assert!(["task1", "robot"].contains(&value["task"].as_str().unwrap()));
            keys.insert(job.key.to_string());
            let run: Vec<String> = serde_json::from_value(value["run"].clone()).unwrap();
            let cli =
                crate::cli::Cli::try_parse_from(std::iter::once("xtask".to_owned()).chain(run))
                    .unwrap();
            let crate::cli::Command::RunJob(parsed) = cli.command else {
                panic!("not a run-job command: {line}");
            };
            assert_eq!(parsed.key, job.key.as_str());
            let expected = ReproduceArgs {
                out: Some(ws.root.join("listed")),
                ..small("listed")
            };
            assert_eq!(parsed.plan, expected);
        }
        assert_eq!(keys.len(), lines.len(), "keys are unique");
    }

    #[test]
    fn an_interrupted_or_damaged_store_resumes_to_the_same_bytes() {
        let (_dir, ws) = workspace();
        reproduce_paper(&command(small("whole"), RunModeArgs::default()), &ws).unwrap();
        let copy = ws.root.join("resumed");
        std::fs::create_dir_all(copy.join("runs")).unwrap();
        let bundle = std::fs::read(ws.root.join("whole/runs/task1.jsonl.zst")).unwrap();
        let lines = bundle_lines(&bundle);
        assert_eq!(lines.len(), 4);
        // As an earlier version (one gzip member a run) killed mid-append left it: one run
        // whole, one edited, one torn, one never written.
        let line = |i: usize| lines[i].clone();
        let member =
            |text: &str| eamadm_runs::gzip::compress(format!("{text}\n").as_bytes()).unwrap();
        let edited = line(1).replacen("\"steps\":", "\"steps\":1", 1);
        let torn = member(&line(2));
        std::fs::write(
            copy.join("runs/task1.jsonl.gz"),
            [
                member(&line(0)).as_slice(),
                &member(&edited),
                &torn[..torn.len() / 2],
            ]
            .concat(),
        )
        .unwrap();
        // What an earlier version left: results.json and a one-file-per-run store.
        std::fs::write(copy.join("results.json"), "[]").unwrap();
        let legacy = copy.join("runs").join(format!("{}.json", "ab".repeat(32)));
        std::fs::write(&legacy, "{}").unwrap();
        // And an uncompressed bundle (format 2 before the store was compressed).
        let uncompressed = copy.join("runs/task1.jsonl");
        std::fs::write(&uncompressed, line(0)).unwrap();
        std::fs::write(copy.join("runs/notes.json"), "mine").unwrap();
        reproduce_paper(&command(small("resumed"), RunModeArgs::default()), &ws).unwrap();
        assert!(!legacy.exists());
        assert!(!uncompressed.exists());
        // Only files of ours are removed.
        assert_eq!(
            std::fs::read(copy.join("runs/notes.json")).unwrap(),
            b"mine"
        );
        std::fs::remove_file(copy.join("runs/notes.json")).unwrap();
        // The edited and the torn entry are set aside, not deleted.
        let aside = copy.join("runs/.set-aside");
        assert_eq!(std::fs::read_dir(&aside).unwrap().count(), 2);
        std::fs::remove_dir_all(&aside).unwrap();
        // The earlier version's bundle was read, its good run kept, and replaced.
        assert!(!copy.join("runs/task1.jsonl.gz").exists());
        assert_same_tree(&ws.root.join("whole"), &copy);
    }

    fn shard(k: u64, n: u64) -> RunModeArgs {
        RunModeArgs {
            shard: Some(format!("{k}/{n}")),
            ..RunModeArgs::default()
        }
    }

    /// The keys of the verified runs stored in `out`, and with which trajectories.
    fn stored_runs(out: &Path) -> BTreeMap<String, bool> {
        let store = RunStore::open(out, &mut |w| panic!("{w}")).unwrap();
        let mut runs = BTreeMap::new();
        for bundle in std::fs::read_dir(out.join("runs")).unwrap() {
            let bundle = bundle.unwrap().path();
            if !bundle.to_string_lossy().ends_with(".jsonl.zst") {
                continue;
            }
            let bytes = std::fs::read(&bundle).unwrap();
            for line in bundle_lines(&bytes) {
                let header: serde_json::Value =
                    serde_json::from_str(line.split('\t').next().unwrap()).unwrap();
                let key = header["key"].as_str().unwrap().to_owned();
                let all = header["trajectories"] == "all";
                assert!(
                    store.has(
                        &eamadm_runs::RunKey::from_verified_hex(key.clone()),
                        KeepTrajectories::Figures
                    ),
                    "{key}"
                );
                assert!(runs.insert(key, all).is_none(), "each run once");
            }
        }
        runs
    }

    #[test]
    fn shards_into_one_folder_in_every_order_merge_to_the_unsharded_run() {
        let (_dir, ws) = workspace();
        reproduce_paper(&command(small("whole"), RunModeArgs::default()), &ws).unwrap();
        let whole = stored_runs(&ws.root.join("whole"));
        assert_eq!(whole.len(), 8 + 2 * SMALL_READING_RUNS_PER_SEED);
        for (n, order) in [[3, 1, 2], [2, 3, 1], [1, 2, 3]].iter().enumerate() {
            let out = format!("one{n}");
            for &k in order {
                reproduce_paper(&command(small(&out), shard(k, 3)), &ws).unwrap();
            }
            // Each shard added its runs; none removed another's (4dc0c45: 5 of 8 missing).
            assert_eq!(stored_runs(&ws.root.join(&out)), whole, "order {order:?}");
            let merged = format!("merged{n}");
            merge(
                &MergeArgs {
                    plan: small(&merged),
                    stores: vec![out.into()],
                    verify: None,
                },
                &ws,
            )
            .unwrap();
            assert_same_tree(&ws.root.join("whole"), &ws.root.join(&merged));
        }
    }

    #[test]
    fn readings_none_runs_only_the_presets_and_its_jobs_say_so() {
        let (_dir, ws) = workspace();
        let none = ReproduceArgs {
            readings: crate::cli::Readings::None,
            ..small("out")
        };
        reproduce_paper(&command(none.clone(), RunModeArgs::default()), &ws).unwrap();
        // 2 tasks × 2 methods × 2 seeds, and none of the readings' reruns that `small` plans
        // by default (`SMALL_READING_RUNS_PER_SEED` per seed).
        let runs = stored_runs(&ws.root.join("out"));
        assert_eq!(runs.len(), 8, "{runs:?}");
        let sensitivity =
            std::fs::read_to_string(ws.root.join("out").join(eamadm::output_names::SENSITIVITY))
                .unwrap();
        assert_eq!(
            sensitivity.lines().count(),
            1,
            "only the header: {sensitivity}"
        );
        // Every listed job carries the option, so `run-job` plans the same runs.
        let (plan, experiments) = prepare(&none, &ws).unwrap();
        let jobs = plan_jobs(&experiments, &plan.methods).unwrap();
        assert_eq!(jobs.len(), 8);
        let lines = job_lines(&none, &plan, &experiments, &jobs, &ws).unwrap();
        for line in &lines {
            assert!(line.contains(r#""--readings","none""#), "{line}");
        }
    }

    #[test]
    fn a_narrower_plan_or_a_method_a_task_lacks_keeps_every_stored_run() {
        let (_dir, ws) = workspace();
        reproduce_paper(&command(small("out"), RunModeArgs::default()), &ws).unwrap();
        let before = stored_runs(&ws.root.join("out"));
        // What a kill during a bundle rewrite leaves: a hidden temporary file, removed by the
        // next holder of the lock (4dc0c45 kept it for ever).
        let leftover = ws.root.join("out/runs/.task1.jsonl.zst.Ab12Cd.tmp");
        std::fs::write(&leftover, b"half a bundle").unwrap();
        let narrow = ReproduceArgs {
            methods: vec!["softmax".to_owned()],
            ..small("out")
        };
        reproduce_paper(&command(narrow, RunModeArgs::default()), &ws).unwrap();
        assert_eq!(stored_runs(&ws.root.join("out")), before);
        assert!(!leftover.exists());
        // The robot has no tree-threshold control (those are the mazes'): its plan there is
        // empty (4dc0c45 emptied the robot's store).
        let lacking = ReproduceArgs {
            tasks: vec![crate::cli::Task::Robot],
            methods: vec!["ea-madm-tau0.5".to_owned()],
            ..small("out")
        };
        let _ = reproduce_paper(&command(lacking, RunModeArgs::default()), &ws);
        assert_eq!(stored_runs(&ws.root.join("out")), before);
        // A wider plan runs only what is missing.
        let wider = ReproduceArgs {
            seeds: Some(3),
            ..small("out")
        };
        reproduce_paper(&command(wider, RunModeArgs::default()), &ws).unwrap();
        let after = stored_runs(&ws.root.join("out"));
        assert_eq!(after.len(), 12 + 3 * SMALL_READING_RUNS_PER_SEED);
        assert!(before.keys().all(|key| after.contains_key(key)));
    }

    #[test]
    fn keep_trajectories_switched_both_ways_keeps_the_richer_runs_once() {
        let (_dir, ws) = workspace();
        let all = || ReproduceArgs {
            keep_trajectories: KeepTrajectories::All,
            ..small("out")
        };
        reproduce_paper(&command(small("out"), RunModeArgs::default()), &ws).unwrap();
        // Needing more: recomputed once (4dc0c45 failed every time, appending each time).
        for _ in 0..2 {
            reproduce_paper(&command(all(), RunModeArgs::default()), &ws).unwrap();
            let runs = stored_runs(&ws.root.join("out"));
            assert_eq!(runs.len(), 8 + 2 * SMALL_READING_RUNS_PER_SEED);
            assert!(runs.values().all(|&all| all), "{runs:?}");
        }
        // Needing less: served by the richer runs, which stay (4dc0c45 stripped them).
        reproduce_paper(&command(small("out"), RunModeArgs::default()), &ws).unwrap();
        let runs = stored_runs(&ws.root.join("out"));
        assert_eq!(runs.len(), 8 + 2 * SMALL_READING_RUNS_PER_SEED);
        assert!(runs.values().all(|&all| all), "{runs:?}");
    }

    #[cfg(unix)]
    #[test]
    fn links_and_fifos_at_store_and_output_paths_are_refused_by_name() {
        use std::os::unix::fs::symlink;
        let (_dir, ws) = workspace();
        let elsewhere = ws.root.join("elsewhere");
        std::fs::create_dir(&elsewhere).unwrap();
        std::fs::write(elsewhere.join("keep.txt"), b"not ours").unwrap();
        let fifo = |path: &Path| {
            assert!(
                std::process::Command::new("mkfifo")
                    .arg(path)
                    .status()
                    .unwrap()
                    .success()
            );
        };
        type Plant<'a> = (&'a str, &'a dyn Fn(&Path));
        let plant: [Plant<'_>; 10] = [
            ("runs", &|p| symlink(&elsewhere, p).unwrap()),
            ("runs/task1.jsonl.zst", &|p| {
                symlink(elsewhere.join("keep.txt"), p).unwrap();
            }),
            ("runs/loose", &|p| symlink(&elsewhere, p).unwrap()),
            ("task1", &|p| symlink(&elsewhere, p).unwrap()),
            (".committed", &|p| symlink(&elsewhere, p).unwrap()),
            (".reproduce-paper.lock", &|p| fifo(p)),
            ("runs/task1.jsonl.zst", &|p| fifo(p)),
            // 9dc06af waited for ever on this FIFO, holding the folder's lock.
            (".outputs", &|p| fifo(p)),
            ("runs/.writers.lock", &|p| fifo(p)),
            (".reproduce-paper.lock", &|p| {
                symlink(elsewhere.join("keep.txt"), p).unwrap();
            }),
        ];
        for (n, (path, make)) in plant.iter().enumerate() {
            let out = ws.root.join(format!("out{n}"));
            let target = out.join(path);
            std::fs::create_dir_all(target.parent().unwrap()).unwrap();
            make(&target);
            let result = reproduce_paper(
                &command(small(&format!("out{n}")), RunModeArgs::default()),
                &ws,
            );
            if let Err(failure) = &result {
                assert!(
                    failure.message.contains(&*target.to_string_lossy())
                        || failure.message.contains(path),
                    "{path}: {}",
                    failure.message
                );
            }
            // Nothing outside the output folder was written, moved or removed.
            let names: Vec<_> = std::fs::read_dir(&elsewhere)
                .unwrap()
                .map(|e| e.unwrap().file_name())
                .collect();
            assert_eq!(names, ["keep.txt"], "{path}");
            assert_eq!(
                std::fs::read(elsewhere.join("keep.txt")).unwrap(),
                b"not ours",
                "{path}"
            );
            assert!(
                result.is_err() || path.ends_with(".jsonl.zst"),
                "{path}: accepted"
            );
        }
    }

    #[test]
    fn a_config_with_more_seeds_than_the_cap_is_refused_before_planning() {
        let (_dir, ws) = workspace();
        let mut config = eamadm::paper::task1();
        config.name = "many".to_owned();
        config.seeds = 100_000;
        std::fs::write(ws.root.join("many.toml"), config.to_toml_string().unwrap()).unwrap();
        let mut plan = args(Some("many.toml"), "out");
        plan.seeds = None;
        let failure = reproduce_paper(&command(plan, RunModeArgs::default()), &ws).unwrap_err();
        assert_eq!(failure.exit_code, 2);
        assert!(
            failure.message.contains("`seeds` = 100000"),
            "{}",
            failure.message
        );
        assert!(!ws.root.join("out").exists());
    }
}
