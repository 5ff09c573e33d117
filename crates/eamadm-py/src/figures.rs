//! The main job's figures from Python, drawn by its own code (`eamadm_present::figures`): of
//! an output folder, from its run store and `report-context.toml` (the same runs in the same
//! order, so the same bytes as the folder's SVG files; the maze family's effect figures from
//! `family/final-scores.csv` and `layouts.csv`), and of runs of
//! [`run_config`](crate::experiment::run_config), drawn beside them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use eamadm::facts::ExperimentFacts;
use eamadm::output_names::{REPORT_CONTEXT, RUNS_FOLDER};
use eamadm::task::Task;
use eamadm::{ExperimentConfig, RunRecord};
use eamadm_present::figures::{Arena, Drawing, ExperimentFigures, FigurePlan};
use eamadm_runs::{KeepTrajectories, RunStore};
use pyo3::prelude::*;

use crate::error::{guard, not_found, value_error};

/// The figures of an experiment's runs (`records`, in job order) on `task`: what the main
/// job draws for them, file by file, and what the report says of them.
pub(crate) fn draw(
    facts: &ExperimentFacts,
    task: &Task,
    records: &[RunRecord],
    argument: &str,
) -> PyResult<Drawing> {
    let plan = FigurePlan::new(facts, Arena::from_parts(task.maze(), task.scenario()));
    let mut figures = ExperimentFigures::new(plan);
    for record in records {
        figures.push(record);
    }
    figures.draw().map_err(|error| value_error(argument, error))
}

/// The config a stored run ran (with its one method), from its description.
fn described_config(description: &[u8]) -> Result<ExperimentConfig, serde_json::Error> {
    #[derive(serde::Deserialize)]
    struct Description {
        config: ExperimentConfig,
    }
    serde_json::from_slice::<Description>(description).map(|d| d.config)
}

/// `[(path, SVG text)]`: the figures of the output folder `folder` (paths relative to it,
/// `<experiment>/<file>.svg`), drawn from its run store's runs of each experiment its
/// `report-context.toml` names, in the plan's job order (its methods, then its seeds): the
/// bytes of the folder's own SVG files when one version wrote both.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "pyo3 hands extracted arguments over by value"
)]
pub(crate) fn figures_of_folder(
    py: Python<'_>,
    folder: PathBuf,
) -> PyResult<Vec<(String, String)>> {
    guard("dir", || folder_figures(py, &folder))
}

fn folder_figures(py: Python<'_>, folder: &Path) -> PyResult<Vec<(String, String)>> {
    let error = |message: String| value_error("dir", message);
    if !folder.exists() {
        return Err(not_found(
            "dir",
            format!("{} does not exist", folder.display()),
        ));
    }
    if !folder.is_dir() {
        return Err(error(format!("{} is not a folder", folder.display())));
    }
    // The figures are drawn from the runs, which only the main job keeps (`runs/`); a folder
    // of `python -m eamadm reproduce` has its figures already and no runs to draw them from.
    if !folder.join(RUNS_FOLDER).is_dir() {
        return Err(error(format!(
            "{} has no run store ({RUNS_FOLDER}/) to draw figures from: give the output folder \
             of `cargo xtask reproduce-paper` (its --out)",
            folder.display()
        )));
    }
    let context_path = folder.join(REPORT_CONTEXT);
    let context_text = std::fs::read_to_string(&context_path).map_err(|e| {
        error(format!(
            "cannot read {}: {e}; give the output folder of `cargo xtask reproduce-paper` \
             (its --out)",
            context_path.display()
        ))
    })?;
    let context = eamadm::paper::report_context_from_toml(&context_text)
        .map_err(|e| error(format!("{REPORT_CONTEXT} of {}: {e}", folder.display())))?;
    let store = RunStore::open_read_only(folder, &mut |_| {}).map_err(|e| error(e.to_string()))?;
    // Each experiment's runs of the plan, by (method's place, seed), and their configs.
    let mut runs: BTreeMap<(usize, usize, u64), RunRecord> = BTreeMap::new();
    let mut configs: BTreeMap<usize, Vec<(usize, ExperimentConfig)>> = BTreeMap::new();
    for (index, key) in store.keys().into_iter().enumerate() {
        // A large store takes seconds to read: Ctrl-C stops it between runs.
        if index % 64 == 63 {
            py.check_signals()?;
        }
        let Some(run) = store
            .load(key, KeepTrajectories::Figures)
            .map_err(|e| error(e.to_string()))?
        else {
            continue;
        };
        let record = run.record;
        let Some((index, facts)) = context
            .experiments
            .iter()
            .enumerate()
            .find(|(_, e)| e.name == record.experiment)
        else {
            continue;
        };
        let Some(place) = facts.methods.iter().position(|m| m.label == record.method) else {
            continue;
        };
        let seeds = facts.base_seed..facts.base_seed + u64::from(facts.seeds);
        if !seeds.contains(&record.seed) {
            continue;
        }
        let config = described_config(&run.description).map_err(|e| {
            error(format!(
                "run {} seed {} of {}: its stored description does not parse: {e}",
                record.method, record.seed, record.experiment
            ))
        })?;
        configs.entry(index).or_default().push((place, config));
        runs.insert((index, place, record.seed), record);
    }
    let mut files = Vec::new();
    for (index, facts) in context.experiments.iter().enumerate() {
        let Some((_, config)) = configs.get(&index).and_then(|c| c.first()) else {
            continue;
        };
        let task = config.task.check().map_err(|e| error(e.to_string()))?;
        // This experiment's runs, taken out in order (the later experiments' stay).
        let later = runs.split_off(&(index + 1, 0, 0));
        let records: Vec<RunRecord> = std::mem::replace(&mut runs, later).into_values().collect();
        let drawing = draw(facts, &task, &records, "dir")?;
        files.extend(
            drawing
                .files
                .into_iter()
                .map(|(file, svg)| (format!("{}/{file}", facts.name), svg)),
        );
    }
    // The maze family's effect figures, from its scores as the main job draws them.
    if let Some((verdicts, Some(family))) = crate::report::family_of_folder(folder)? {
        for claim in ["C1", "C2"] {
            if let Some(svg) =
                eamadm_present::family::effect_figure(&verdicts, &family.layouts, claim)
            {
                files.push((format!("family/effect-{claim}.svg"), svg));
            }
        }
    }
    Ok(files)
}
