//! `cargo xtask gc`: removes from an output folder and the artefact cache what no plan needs
//! ([`eamadm_runs::gc`] decides; this module takes the folder's lock and prints).

use std::collections::HashSet;

use eamadm_runs::gc::{
    move_legacy_artefacts, remove_artefacts_except, remove_set_aside_older_than,
};
use eamadm_runs::output_folder::OutputFolder;
use eamadm_runs::verify::artefacts_of;
use eamadm_runs::{PretrainedStore, RunKey, RunStore};

use crate::Failure;
use crate::cli::GcArgs;
use crate::jobs::plan_jobs;
use crate::plan::Workspace;
use crate::reproduce::{prepare, warn_on_stderr};

/// Runs `gc`.
pub(crate) fn gc(args: &GcArgs, workspace: &Workspace) -> Result<(), Failure> {
    let (plan, experiments) = prepare(&args.plan, workspace)?;
    let jobs = plan_jobs(&experiments, &plan.methods).map_err(Failure::failed)?;
    let folder = OutputFolder::open(&plan.out, args.plan.wait).map_err(Failure::failed)?;
    let cache = PretrainedStore::new(&plan.pretrained_cache);
    let mut removed = move_legacy_artefacts(folder.root(), &cache, &mut warn_on_stderr)
        .map_err(Failure::failed)?;
    let store = RunStore::open(folder.root(), &mut warn_on_stderr).map_err(Failure::failed)?;
    let stale = store.stale_runs().map_err(Failure::failed)?;
    for key in &stale {
        println!("removed run {key}: stored by another results format or crate version");
    }
    let keys: Vec<RunKey> = jobs.iter().map(|job| job.key.clone()).collect();
    store
        .pack_dropping(&folder, &[], &keys, &stale, &mut warn_on_stderr)
        .map_err(Failure::failed)?;
    let age = std::time::Duration::from_secs(args.older_than.saturating_mul(86_400));
    removed.extend(remove_set_aside_older_than(folder.root(), age).map_err(Failure::failed)?);
    let mut needed = HashSet::new();
    for planned in &experiments {
        let methods: Vec<_> = planned.config().methods.iter().collect();
        for seed in planned.config().seed_values() {
            for (_, key, _) in
                artefacts_of(&planned.experiment, &methods, seed).map_err(Failure::failed)?
            {
                needed.insert(key);
            }
        }
    }
    removed.extend(remove_artefacts_except(&cache, &needed).map_err(Failure::failed)?);
    let temporary = cache
        .remove_stale_temporary_files()
        .map_err(Failure::failed)?;
    for entry in &removed {
        println!("removed {}: {}", entry.path.display(), entry.why);
    }
    println!(
        "gc: removed {} runs, {} files and {temporary} temporary files; kept the {} runs and \
         {} artefacts the plan needs",
        stale.len(),
        removed.len(),
        jobs.len(),
        needed.len()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::{KeepTrajectories, Readings, ReproduceArgs, ReproduceCommand, RunModeArgs};

    fn plan(methods: &[&str]) -> ReproduceArgs {
        ReproduceArgs {
            seeds: Some(2),
            tasks: vec![crate::cli::Task::Task1],
            methods: methods.iter().map(|m| (*m).to_owned()).collect(),
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

    #[test]
    fn gc_removes_stale_runs_old_set_aside_entries_and_other_plans_artefacts() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("fixtures")).unwrap();
        let root = dir.path().canonicalize().unwrap();
        let ws = Workspace {
            current_dir: root.clone(),
            root: root.clone(),
        };
        let run = |methods: &[&str]| {
            crate::reproduce::reproduce_paper(
                &ReproduceCommand {
                    plan: plan(methods),
                    mode: RunModeArgs::default(),
                },
                &ws,
            )
            .unwrap();
        };
        // Two plans pre-train in the cache (the second on Task II, into another folder); the
        // folder keeps both of its plans' runs.
        run(&["ea-madm"]);
        run(&["softmax"]);
        crate::reproduce::reproduce_paper(
            &ReproduceCommand {
                plan: ReproduceArgs {
                    tasks: vec![crate::cli::Task::Task2],
                    out: Some("other".into()),
                    ..plan(&["ea-madm"])
                },
                mode: RunModeArgs::default(),
            },
            &ws,
        )
        .unwrap();
        let cache = PretrainedStore::new(&root.join("target/pretrained-cache"));
        let before = cache.keys().unwrap();
        let out = root.join("out");
        // A run of an earlier results format, an entry set aside long ago and one just now, and
        // artefacts an earlier version kept in the folder.
        let (_, experiments) = prepare(&plan(&["ea-madm"]), &ws).unwrap();
        let store = RunStore::open(&out, &mut |w| panic!("{w}")).unwrap();
        let method = experiments[0].config().method("ea-madm").unwrap();
        let mut old = eamadm_runs::RunDescription::new(&experiments[0].experiment, method, 0);
        old.results_format -= 1;
        let old_key = RunKey::of(&old).unwrap();
        let record = experiments[0].experiment.run(method, 0).unwrap();
        store
            .append(&old_key, &old, &record, KeepTrajectories::Figures)
            .unwrap();
        let aside = out.join("runs/.set-aside");
        std::fs::create_dir_all(&aside).unwrap();
        std::fs::write(aside.join("old.at-0"), b"x").unwrap();
        let file = std::fs::File::options()
            .write(true)
            .open(aside.join("old.at-0"))
            .unwrap();
        file.set_modified(
            std::time::SystemTime::now() - std::time::Duration::from_secs(40 * 86_400),
        )
        .unwrap();
        std::fs::write(aside.join("new.at-0"), b"y").unwrap();
        let legacy = PretrainedStore::legacy(&out);
        legacy.adopt(&cache, &mut |w| panic!("{w}")).unwrap();
        gc(
            &GcArgs {
                plan: plan(&["ea-madm"]),
                older_than: 30,
            },
            &ws,
        )
        .unwrap();
        let store = RunStore::open(&out, &mut |w| panic!("{w}")).unwrap();
        assert!(!store.line_exists(&old_key));
        assert_eq!(store.len(), 4, "both plans' runs stay");
        assert!(!aside.join("old.at-0").exists());
        assert!(aside.join("new.at-0").exists());
        assert!(!legacy.folder().exists());
        // Only the artefacts of the plan given stay (Task II's go).
        let after = cache.keys().unwrap();
        assert!(
            after.len() < before.len(),
            "{} of {}",
            after.len(),
            before.len()
        );
        assert!(after.iter().all(|key| before.contains(key)));
        // The plan still resumes whole: nothing it needs was removed.
        run(&["ea-madm"]);
    }
}
