//! `cargo xtask regen-fixtures [--check]`: the content of `fixtures/`, made by code only.
//!
//! - `mazes/task1.map`, `mazes/task2.map`: the frozen maze layouts ([`Preset::fixture_text`]);
//!   `mazes/aggregation-control.map`: the positive control's hand-designed map
//!   (`mazes::aggregation_control_fixture_text`);
//! - `robot/fig12.toml`: the default robot scenario;
//! - `reference/<task>/curves.csv` and `reference/<task>/evaluation-paths.csv`: per-episode
//!   curves and the greedy evaluation path of [`FIXTURE_SEED`] for every method of the task's
//!   preset, shortened to [`FIXTURE_EPISODES`] episodes so that they are cheap to recompute.
//!
//! It also writes the README's generated parts and its figure from the default run
//! ([`crate::readme`]): the verdict table, the claims and the answer paragraph between marker
//! comments in `README.md`, and `docs/figures/task1-steps.svg`.
//!
//! Floats are rounded to [`SIGNIFICANT_DIGITS`] significant digits. The same content is
//! compared with the committed files by `--check` and by the tests, so any change of numeric
//! behaviour shows up as a reviewable diff.

use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};

use eamadm::mazes::Preset;
use eamadm::wmr_model::DEFAULT_SCENARIO_TOML;
use eamadm::{Experiment, ExperimentConfig, RunRecord};
use rayon::prelude::*;

use crate::Failure;
use crate::atomic::write_atomic;
use crate::cli::Task;
use crate::plan::{Workspace, describe_regen_fixtures};
use crate::readme;
use eamadm_present::generated::first_difference;

/// The seed of every reference run.
pub(crate) const FIXTURE_SEED: u64 = 0;
/// Training (and pre-training) episodes of the reference runs.
pub(crate) const FIXTURE_EPISODES: u64 = 15;
/// Step cap of the reference runs on the mazes.
pub(crate) const FIXTURE_MAZE_STEP_CAP: u32 = 300;
/// Step cap of the reference runs of the robot.
pub(crate) const FIXTURE_ROBOT_STEP_CAP: u32 = 150;
/// Significant digits kept of every float.
pub(crate) const SIGNIFICANT_DIGITS: usize = 6;

/// One fixture file: its path under `fixtures/` and its content.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct FixtureFile {
    /// Path relative to `fixtures/`, with `/` separators.
    pub(crate) path: String,
    /// The full text.
    pub(crate) content: String,
}

/// A reference run that could not be made.
#[derive(Debug, thiserror::Error)]
pub(crate) enum FixtureError {
    /// The shortened preset is not a valid config (a bug of this module).
    #[error("reference config of {task}: {source}")]
    Config {
        /// The task.
        task: &'static str,
        /// The problem.
        #[source]
        source: Box<eamadm::ConfigError>,
    },
    /// A reference run failed.
    #[error("reference run of {task}: {source}")]
    Run {
        /// The task.
        task: &'static str,
        /// The failure.
        #[source]
        source: eamadm::RunError,
    },
}

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

/// The reference config of `task`: its preset with one seed ([`FIXTURE_SEED`]), shortened.
pub(crate) fn fixture_config(task: Task) -> ExperimentConfig {
    let mut config = task.paper().config();
    config.seeds = 1;
    config.base_seed = FIXTURE_SEED;
    config.shortened(&eamadm::Shortening {
        episodes: Some(FIXTURE_EPISODES),
        maze_step_cap: Some(FIXTURE_MAZE_STEP_CAP),
        robot_step_cap: Some(FIXTURE_ROBOT_STEP_CAP),
        max_warmup_env_steps: None,
    })
}

/// Every fixture file, in a fixed order.
pub(crate) fn generate() -> Result<Vec<FixtureFile>, FixtureError> {
    let mut files = Vec::new();
    for preset in [Preset::Task1, Preset::Task2] {
        let path = preset.fixture_path();
        let path = path.strip_prefix("fixtures/").unwrap_or(&path).to_owned();
        files.push(FixtureFile {
            path,
            content: preset.fixture_text(),
        });
    }
    files.push(FixtureFile {
        path: format!("mazes/{}", eamadm::mazes::AGGREGATION_CONTROL_FIXTURE),
        content: eamadm::mazes::aggregation_control_fixture_text(),
    });
    files.push(FixtureFile {
        path: "robot/fig12.toml".to_owned(),
        content: format!(
            "# Generated by `cargo xtask regen-fixtures` from wmr_model::DEFAULT_SCENARIO_TOML \
             (crates/wmr-model/scenarios/fig12.toml).\n# Do not edit by hand: edit the crate's \
             scenario and rerun the command.\n\n{DEFAULT_SCENARIO_TOML}"
        ),
    });
    let runs: Vec<(Task, Vec<RunRecord>)> = Task::ALL
        .par_iter()
        .map(|&task| {
            let config = fixture_config(task);
            let experiment = Experiment::new(config).map_err(|source| FixtureError::Config {
                task: task.name(),
                source: Box::new(source),
            })?;
            let records = experiment.run_all().map_err(|source| FixtureError::Run {
                task: task.name(),
                source,
            })?;
            Ok((task, records))
        })
        .collect::<Result<_, _>>()?;
    for (task, records) in &runs {
        let header = header(*task);
        files.push(FixtureFile {
            path: format!("reference/{}/curves.csv", task.name()),
            content: format!("{header}{}", curves_csv(records)),
        });
        files.push(FixtureFile {
            path: format!("reference/{}/evaluation-paths.csv", task.name()),
            content: format!("{header}{}", paths_csv(records)),
        });
    }
    Ok(files)
}

fn header(task: Task) -> String {
    let config = fixture_config(task);
    let cap = config
        .task
        .step_cap()
        .map_or_else(|| "the task's".to_owned(), |c| c.to_string());
    format!(
        "# Generated by `cargo xtask regen-fixtures`; do not edit by hand.\n\
         # {}: the `{}` preset (eamadm::ExperimentConfig), every method, seed {FIXTURE_SEED}, \
         shortened to {} episodes (pre-training {FIXTURE_EPISODES} episodes per sub-task), \
         step cap {cap}.\n\
         # Floats rounded to {SIGNIFICANT_DIGITS} significant digits. `cargo test -p xtask` \
         and `cargo xtask regen-fixtures --check` compare this file with the code's output.\n",
        task.description(),
        task.name(),
        config.episodes,
    )
}

/// `value` rounded to [`SIGNIFICANT_DIGITS`] significant digits, in its shortest form.
fn round_float(value: f64) -> String {
    eamadm::rounding::round_significant(value, SIGNIFICANT_DIGITS)
}

fn optional(value: Option<f64>) -> String {
    value.map_or_else(String::new, round_float)
}

fn curves_csv(records: &[RunRecord]) -> String {
    let robot = records
        .iter()
        .any(|r| r.episodes.iter().any(|e| e.robot.is_some()));
    let mut text = String::from(
        "method,episode,steps,task_return,learning_return,reached,collisions,env_steps",
    );
    if robot {
        text.push_str(",time,average_reward,time_to_reach,retention_time");
    }
    text.push('\n');
    for record in records {
        let evaluation = std::iter::once(&record.evaluation);
        for (index, episode) in record.episodes.iter().chain(evaluation).enumerate() {
            let label = if index == record.episodes.len() {
                "greedy evaluation".to_owned()
            } else {
                episode.episode.to_string()
            };
            let _ = write!(
                text,
                "{},{label},{},{},{},{},{},{}",
                record.method,
                episode.steps,
                round_float(episode.task_return),
                round_float(episode.learning_return),
                episode.reached,
                episode.collisions,
                episode.env_steps
            );
            if robot {
                let m = episode.robot.as_ref();
                let _ = write!(
                    text,
                    ",{},{},{},{}",
                    optional(m.map(|m| m.time)),
                    optional(m.map(|m| m.average_reward)),
                    optional(m.and_then(|m| m.time_to_reach)),
                    optional(m.map(|m| m.retention_time)),
                );
            }
            text.push('\n');
        }
    }
    let totals: String = records
        .iter()
        .map(|r| {
            format!(
                "# {}: {} environment steps in all, {} of them before the recorded episodes (sub-task pre-training or a warm-up); the row \
                 `greedy evaluation` is the greedy episode after training.\n",
                r.method, r.total_env_steps, r.pretrain_env_steps
            )
        })
        .collect();
    totals + &text
}

fn paths_csv(records: &[RunRecord]) -> String {
    let mut text = String::from("method,t,state,action,x,y\n");
    for record in records {
        let path = &record.evaluation_trajectory;
        for (t, (state, position)) in path.states.iter().zip(&path.positions).enumerate() {
            let action = path
                .actions
                .get(t)
                .map_or_else(String::new, ToString::to_string);
            let _ = writeln!(
                text,
                "{},{t},{state},{action},{},{}",
                record.method,
                round_float(position[0]),
                round_float(position[1])
            );
        }
    }
    text
}

/// The fixtures folder's files as committed, for the tests.
#[cfg(test)]
fn committed(path: &str) -> String {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    std::fs::read_to_string(root.join(path)).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_outputs_page_documents_every_column_the_code_writes() {
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(OUTPUTS_PAGE);
        let committed = std::fs::read_to_string(path).unwrap();
        assert_eq!(
            outputs_page_text(&committed).unwrap(),
            committed,
            "{OUTPUTS_PAGE} is stale: run `cargo xtask regen-fixtures`"
        );
        for column in eamadm::scores::COLUMNS
            .iter()
            .chain(eamadm::claims::CLAIM_COLUMNS)
        {
            assert!(committed.contains(&format!("| `{}` |", column.name)));
        }
    }

    /// The snapshot regression test: every fixture, recomputed, equals the committed file.
    #[test]
    fn committed_fixtures_match_the_code() {
        let files = generate().unwrap();
        let mut failures = String::new();
        for file in &files {
            if let Some(diff) = first_difference(&committed(&file.path), &file.content) {
                let _ = writeln!(failures, "fixtures/{}:\n{diff}", file.path);
            }
        }
        assert!(
            failures.is_empty(),
            "fixtures differ from the code's output; if the change is intended, run \
             `cargo xtask regen-fixtures` and review the diff:\n{failures}"
        );
    }
}
