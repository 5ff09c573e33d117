//! Reading what the main job writes: the runs of an output folder's store (through
//! `eamadm-runs`, every entry checked) and the data package that types `final-scores.csv` and
//! `claims.csv` (`eamadm::data_package`).

use std::path::PathBuf;

use eamadm::{ExperimentConfig, RunRecord};
use eamadm_runs::{KeepTrajectories, RunStore};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use eamadm::output_names::{BUNDLE_EXTENSION, LOOSE_RUNS, RUNS_FOLDER};

use crate::error::{guard, not_found, value_error};

/// The text of `datapackage.json`: every column of `final-scores.csv` and `claims.csv` with its
/// type, unit, meaning and when it is blank, as the main job writes it.
#[pyfunction]
pub(crate) fn data_package_json() -> String {
    eamadm::data_package::data_package_text()
}

/// The per-run columns of [`load_runs`], in order.
const RUN_COLUMNS: [&str; 12] = [
    "task",
    "method",
    "role",
    "kind",
    "seed",
    "episodes",
    "key",
    "pretrain_env_steps",
    "total_env_steps",
    "optimum_steps",
    "greedy_reached",
    "greedy_steps",
];

/// The per-episode curves of [`load_runs`]: one numpy array per run each.
const CURVES: [&str; 10] = [
    "steps",
    "task_return",
    "learning_return",
    "reached",
    "collisions",
    "env_steps",
    "time",
    "average_reward",
    "time_to_reach",
    "retention_time",
];

/// Every run of the store of `path` (an output folder, or its `runs/` folder), in storage
/// order (experiment by experiment, then job order). Returns `(columns, warnings)`: one entry
/// per run in each column, the per-run columns as lists, the curves as one numpy array per run
/// (`float64` with NaN for a robot metric a maze has not, or a time to reach of an episode that
/// did not reach), and the store's warnings about entries it set aside.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "pyo3 hands extracted arguments over by value"
)]
pub(crate) fn load_runs(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<(Bound<'_, PyDict>, Vec<String>)> {
    guard("dir", || load(py, &path))
}

/// Whether `folder` is a run store itself: it holds a bundle or the loose runs' folder.
fn is_store(folder: &std::path::Path) -> bool {
    folder.join(LOOSE_RUNS).is_dir()
        || std::fs::read_dir(folder).is_ok_and(|entries| {
            entries.flatten().any(|entry| {
                entry
                    .file_name()
                    .to_string_lossy()
                    .ends_with(&format!(".{BUNDLE_EXTENSION}"))
            })
        })
}

fn load<'py>(
    py: Python<'py>,
    path: &std::path::Path,
) -> PyResult<(Bound<'py, PyDict>, Vec<String>)> {
    if !path.exists() {
        return Err(not_found(
            "dir",
            format!("{} does not exist", path.display()),
        ));
    }
    if !path.is_dir() {
        return Err(value_error(
            "dir",
            format!(
                "{} is not a folder (give the main job's `--out` folder)",
                path.display()
            ),
        ));
    }
    if !path.join(RUNS_FOLDER).is_dir() && !is_store(path) {
        return Err(value_error(
            "dir",
            format!(
                "{} is not an output folder of `cargo xtask reproduce-paper` (it has no \
                 {RUNS_FOLDER}/ folder) nor a run store (no *.{BUNDLE_EXTENSION} bundle, no \
                 {LOOSE_RUNS}/ folder): give the main job's `--out` folder",
                path.display()
            ),
        ));
    }
    let mut warnings = Vec::new();
    let store = RunStore::open_read_only(path, &mut |warning| warnings.push(warning.to_owned()))
        .map_err(|error| value_error("dir", error))?;
    let columns: Vec<Bound<'_, PyList>> = RUN_COLUMNS
        .iter()
        .chain(&CURVES)
        .map(|_| PyList::empty(py))
        .collect();
    for (index, key) in store.keys().into_iter().enumerate() {
        // A large store takes seconds to read: Ctrl-C stops it between runs.
        if index % 64 == 63 {
            py.check_signals()?;
        }
        let Some(run) = store
            .load(key, KeepTrajectories::Figures)
            .map_err(|error| value_error("dir", error))?
        else {
            continue;
        };
        let (role, kind) = role_and_kind(&run.description, &run.record)?;
        let record = &run.record;
        let cells: [Bound<'_, PyAny>; 12] = [
            record.experiment.clone().into_pyobject(py)?.into_any(),
            record.method.clone().into_pyobject(py)?.into_any(),
            role.into_pyobject(py)?.into_any(),
            kind.into_pyobject(py)?.into_any(),
            record.seed.into_pyobject(py)?.into_any(),
            (record.episodes.len() as u64).into_pyobject(py)?.into_any(),
            key.as_str().into_pyobject(py)?.into_any(),
            record.pretrain_env_steps.into_pyobject(py)?.into_any(),
            record.total_env_steps.into_pyobject(py)?.into_any(),
            record.optimum_steps.into_pyobject(py)?.into_any(),
            record
                .evaluation
                .reached
                .into_pyobject(py)?
                .to_owned()
                .into_any(),
            record.evaluation.steps.into_pyobject(py)?.into_any(),
        ];
        for (column, cell) in columns
            .iter()
            .zip(cells.into_iter().chain(curves(py, record)))
        {
            column.append(cell)?;
        }
    }
    let dict = PyDict::new(py);
    for (name, column) in RUN_COLUMNS.iter().chain(&CURVES).zip(columns) {
        dict.set_item(name, column)?;
    }
    Ok((dict, warnings))
}

/// The curves of `record`, in [`CURVES`] order, one numpy array each.
fn curves<'py>(py: Python<'py>, record: &RunRecord) -> [Bound<'py, PyAny>; 10] {
    let episodes = &record.episodes;
    let int = |f: fn(&eamadm::EpisodeRecord) -> u64| {
        episodes
            .iter()
            .map(f)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .into_any()
    };
    let real = |f: &dyn Fn(&eamadm::EpisodeRecord) -> f64| {
        episodes
            .iter()
            .map(f)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .into_any()
    };
    let robot = |f: fn(&eamadm::RobotEpisodeMetrics) -> Option<f64>| {
        real(&move |e| e.robot.as_ref().and_then(f).unwrap_or(f64::NAN))
    };
    [
        int(|e| e.steps),
        real(&|e| e.task_return),
        real(&|e| e.learning_return),
        episodes
            .iter()
            .map(|e| e.reached)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .into_any(),
        int(|e| e.collisions),
        int(|e| e.env_steps),
        robot(|m| Some(m.time)),
        robot(|m| Some(m.average_reward)),
        robot(|m| m.time_to_reach),
        robot(|m| Some(m.retention_time)),
    ]
}

/// The role and kind of a stored run's method, from its description (the config it ran,
/// holding that one method).
fn role_and_kind(description: &[u8], record: &RunRecord) -> PyResult<(&'static str, &'static str)> {
    #[derive(serde::Deserialize)]
    struct Description {
        config: ExperimentConfig,
    }
    let described: Description = serde_json::from_slice(description).map_err(|error| {
        value_error(
            "dir",
            format!(
                "run {} seed {} of {}: its stored description does not parse: {error}",
                record.method, record.seed, record.experiment
            ),
        )
    })?;
    let spec = described.config.method(&record.method).ok_or_else(|| {
        value_error(
            "dir",
            format!(
                "run {} seed {} of {}: its stored description has no such method",
                record.method, record.seed, record.experiment
            ),
        )
    })?;
    Ok((spec.role.name(), spec.method.kind_name()))
}
