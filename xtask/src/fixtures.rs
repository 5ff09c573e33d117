//! `cargo xtask regen-fixtures [--check]`: writes (or compares) the content of `fixtures/`,
//! which [`eamadm::fixtures`] makes, naming the first file that differs.
//!
//! It also writes the README's generated parts and its figure from the default run
//! ([`crate::readme`]): the verdict table, the claims and the answer paragraph between marker
//! comments in `README.md`, and `docs/figures/task1-steps.svg`; and the column tables of
//! `docs/outputs.md`.

use std::path::Path;
use std::process::{Command, Stdio};

use eamadm::fixtures::generate;

use crate::Failure;
use crate::atomic::write_atomic;
use crate::plan::{Workspace, describe_regen_fixtures};
use crate::readme;
use eamadm_present::generated::first_difference;

/// Runs the command: writes every fixture, or with `check` compares them and fails naming the
/// first file that differs.
pub(crate) fn regen_fixtures(check: bool, workspace: &Workspace) -> Result<(), Failure> {
    print!("{}", describe_regen_fixtures(check, workspace));
    let files = generate().map_err(Failure::failed)?;
    let root = workspace.fixtures();
    if check {
        for file in &files {
            let committed = std::fs::read_to_string(root.join(&file.path)).unwrap_or_default();
            if let Some(diff) = first_difference(&committed, &file.content) {
                return Err(Failure::failed(format!(
                    "fixtures/{} differs from what the code produces now \
                     (run `cargo xtask regen-fixtures` and review the diff):\n{diff}",
                    file.path
                )));
            }
        }
        println!("fixtures/ is up to date ({} files)", files.len());
    } else {
        for file in &files {
            write_atomic(&root.join(&file.path), file.content.as_bytes())
                .map_err(Failure::failed)?;
            println!("wrote fixtures/{}", file.path);
        }
    }
    outputs_page(check, workspace)?;
    readme_parts(check, workspace)
}

/// The page that documents the output tables' columns.
pub(crate) const OUTPUTS_PAGE: &str = "docs/outputs.md";

/// `page` (the text of [`OUTPUTS_PAGE`]) with its generated column tables
/// ([`eamadm::data_package::markdown`], the same tables `datapackage.json` is made from).
pub(crate) fn outputs_page_text(page: &str) -> Result<String, String> {
    eamadm_present::generated::splice(page, "columns", &eamadm::data_package::markdown())
}

/// Writes (or with `check` compares) the generated column tables of [`OUTPUTS_PAGE`].
fn outputs_page(check: bool, workspace: &Workspace) -> Result<(), Failure> {
    let path = workspace.root.join(OUTPUTS_PAGE);
    let committed = std::fs::read_to_string(&path)
        .map_err(|error| Failure::failed(format!("cannot read {}: {error}", path.display())))?;
    let generated = outputs_page_text(&committed).map_err(Failure::failed)?;
    if check {
        if let Some(diff) = first_difference(&committed, &generated) {
            return Err(Failure::failed(format!(
                "{OUTPUTS_PAGE}'s column tables differ from the code's \
                 (`eamadm_eval::scores::COLUMNS`, `claims::CLAIM_COLUMNS`; run `cargo xtask \
                 regen-fixtures` and review the diff):\n{diff}"
            )));
        }
        println!("{OUTPUTS_PAGE}'s column tables are up to date");
    } else {
        write_atomic(&path, generated.as_bytes()).map_err(Failure::failed)?;
        println!("wrote {OUTPUTS_PAGE}'s column tables");
    }
    Ok(())
}

/// Makes the default run in a temporary folder with this binary, then writes (or with `check`
/// compares) the README's generated parts and its figure.
fn readme_parts(check: bool, workspace: &Workspace) -> Result<(), Failure> {
    println!(
        "  README:   the verdicts, claims and answer in {} and {}, from the default run \
         (`reproduce-paper` into a temporary folder)",
        readme::README,
        readme::FIGURE
    );
    let out = tempfile::tempdir().map_err(Failure::failed)?;
    let xtask = std::env::current_exe().map_err(Failure::failed)?;
    let status = Command::new(&xtask)
        .arg("reproduce-paper")
        .arg("--out")
        .arg(out.path())
        .stdout(Stdio::null())
        .status()
        .map_err(|error| Failure::failed(format!("cannot start {}: {error}", xtask.display())))?;
    if !status.success() {
        return Err(Failure::failed(format!(
            "the default run for the README failed ({status})"
        )));
    }
    check_footprint(out.path())?;
    let run = readme::read_run(out.path()).map_err(Failure::failed)?;
    let readme_path = workspace.root.join(readme::README);
    let figure_path = workspace.root.join(readme::FIGURE);
    let committed = std::fs::read_to_string(&readme_path).map_err(|error| {
        Failure::failed(format!("cannot read {}: {error}", readme_path.display()))
    })?;
    let generated = readme::generate(&committed, &run).map_err(Failure::failed)?;
    if check {
        if let Some(diff) = first_difference(&committed, &generated) {
            return Err(Failure::failed(format!(
                "README.md's generated parts differ from the default run's \
                 (run `cargo xtask regen-fixtures` and review the diff):\n{diff}"
            )));
        }
        if std::fs::read(&figure_path).ok().as_deref() != Some(run.figure.as_slice()) {
            return Err(Failure::failed(format!(
                "{} differs from the default run's task1/steps.svg (run `cargo xtask \
                 regen-fixtures` and review the figure)",
                readme::FIGURE
            )));
        }
        println!(
            "README.md's generated parts and {} are up to date",
            readme::FIGURE
        );
    } else {
        write_atomic(&readme_path, generated.as_bytes()).map_err(Failure::failed)?;
        println!("wrote README.md's generated parts");
        write_atomic(&figure_path, &run.figure).map_err(Failure::failed)?;
        println!("wrote {}", readme::FIGURE);
    }
    Ok(())
}

/// Issue 35's budget for the default run's output folder, as `du -sb` and `find -type f`
/// count it (docs/paper-notes.md §24.1).
const DEFAULT_RUN_MAX_BYTES: u64 = 25_000_000;
const DEFAULT_RUN_MAX_FILES: u64 = 100;

/// Fails when the default run's output folder `out` is over [`DEFAULT_RUN_MAX_BYTES`] or
/// [`DEFAULT_RUN_MAX_FILES`]; `regen-fixtures --check` (so `cargo xtask test` and CI) runs it.
fn check_footprint(out: &Path) -> Result<(), Failure> {
    let footprint = eamadm_runs::output_folder::footprint(out).map_err(Failure::failed)?;
    println!(
        "  default run's folder: {} B in {} files (at most {DEFAULT_RUN_MAX_BYTES} B and \
         {DEFAULT_RUN_MAX_FILES} files)",
        footprint.bytes, footprint.files
    );
    if footprint.bytes > DEFAULT_RUN_MAX_BYTES || footprint.files > DEFAULT_RUN_MAX_FILES {
        return Err(Failure::failed(format!(
            "the default run's output folder is {} B in {} files, over issue 35's budget of \
             {DEFAULT_RUN_MAX_BYTES} B in {DEFAULT_RUN_MAX_FILES} files (`du -sb`, `find -type \
             f | wc -l`): find the files that grew (docs/timings.md) and shrink them",
            footprint.bytes, footprint.files
        )));
    }
    Ok(())
}
