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
