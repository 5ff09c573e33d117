//! Experiments from Python: the paper's presets as TOML text, configs checked and converted,
//! and runs on the Rust runner (GIL released) returned as column dicts.

use eamadm::config::{
    PAPER_ROBOT_PAPER_STATE_TOML, PAPER_ROBOT_TOML, PAPER_TASK1_TOML, PAPER_TASK2_TOML,
};
use eamadm::results::{CURVE_COLUMNS, curve_rows};
use eamadm::summary::final_window_summary;
use eamadm::{Experiment, RunRecord};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rayon::prelude::*;

use crate::error::value_error;

/// The embedded paper preset `name` ("task1", "task2", "robot" or "robot-paper-state") as TOML
/// text.
#[pyfunction]
pub(crate) fn paper_config_toml(name: &str) -> PyResult<&'static str> {
    match name {
        "task1" => Ok(PAPER_TASK1_TOML),
        "task2" => Ok(PAPER_TASK2_TOML),
        "robot" => Ok(PAPER_ROBOT_TOML),
        "robot-paper-state" => Ok(PAPER_ROBOT_PAPER_STATE_TOML),
        other => Err(value_error(
            "name",
            format!(
                "expected \"task1\", \"task2\", \"robot\" or \"robot-paper-state\", got {other:?}"
            ),
        )),
    }
}

/// Parses, validates and loads the experiment config `toml_text`; a `ValueError` naming
/// `config` and the field when it cannot be used.
#[pyfunction]
pub(crate) fn check_config(toml_text: &str) -> PyResult<()> {
    Experiment::from_toml_str(toml_text)
        .map(drop)
        .map_err(|error| value_error("config", error))
}

/// A config given as JSON (a Python dict of the TOML schema, dumped) as TOML text, so that
/// both forms go through the same parser and checks.
#[pyfunction]
pub(crate) fn json_to_toml(json_text: &str) -> PyResult<String> {
    let value: serde_json::Value =
        serde_json::from_str(json_text).map_err(|error| value_error("config", error))?;
    let table = toml::Table::try_from(value).map_err(|error| {
        value_error(
            "config",
            format!("not expressible as TOML (no None values; a dict at the top): {error}"),
        )
    })?;
    toml::to_string(&table).map_err(|error| value_error("config", error))
}

/// The TOML text `toml_text` as JSON (for `paper_config(..., as_dict=True)`).
#[pyfunction]
pub(crate) fn toml_to_json(toml_text: &str) -> PyResult<String> {
    let table: toml::Table =
        toml::from_str(toml_text).map_err(|error| value_error("config", error))?;
    serde_json::to_string(&table).map_err(|error| value_error("config", error))
}

/// Runs the experiment `toml_text`: every method in `methods` (labels; default all, in the
/// config's order) with every seed in `seeds` (default the config's `base_seed + i`), on
/// `threads` threads (default rayon's), with the GIL released. Returns
/// `{"curves": columns, "finals": columns, "report_input": (facts, scores)}`: one row per
/// (run, episode) with the columns of the Rust runner's `curves.csv.gz`, one row per run with
/// its final scores (means over the last `window` training episodes, as in the report), and
/// what `report_of_runs` needs of these runs.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "pyo3 hands extracted arguments over by value"
)]
#[pyo3(signature = (toml_text, seeds=None, methods=None, threads=None, window=eamadm::DEFAULT_FINAL_WINDOW))]
pub(crate) fn run_config<'py>(
    py: Python<'py>,
    toml_text: &str,
    seeds: Option<Vec<u64>>,
    methods: Option<Vec<String>>,
    threads: Option<usize>,
    window: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let experiment =
        Experiment::from_toml_str(toml_text).map_err(|error| value_error("config", error))?;
    let config = experiment.config();
    let specs = match &methods {
        None => config.methods.iter().collect::<Vec<_>>(),
        Some(labels) => {
            if labels.is_empty() {
                return Err(value_error("methods", "expected at least one label"));
            }
            labels
                .iter()
                .map(|label| {
                    config.method(label).ok_or_else(|| {
                        let known: Vec<&str> =
                            config.methods.iter().map(|m| m.label.as_str()).collect();
                        value_error(
                            "methods",
                            format!("no method labelled {label:?}; the config has {known:?}"),
                        )
                    })
                })
                .collect::<PyResult<_>>()?
        }
    };
    let seeds = match seeds {
        Some(seeds) if seeds.is_empty() => {
            return Err(value_error("seeds", "expected at least one seed"));
        }
        Some(seeds) => seeds,
        None => config.seed_values().collect(),
    };
    if window == 0 {
        return Err(value_error("window", "expected at least 1, got 0"));
    }
    let pool = match threads {
        Some(0) => return Err(value_error("threads", "expected at least 1, got 0")),
        Some(n) => rayon::ThreadPoolBuilder::new().num_threads(n),
        None => rayon::ThreadPoolBuilder::new(),
    }
    .build()
    .map_err(|error| value_error("threads", error))?;
    // Job order (method-major, then seed), whatever thread finishes first.
    let jobs: Vec<_> = specs
        .iter()
        .flat_map(|&spec| seeds.iter().map(move |&seed| (spec, seed)))
        .collect();
    let records: Vec<RunRecord> = py
        .detach(|| {
            pool.install(|| {
                jobs.par_iter()
                    .map(|&(spec, seed)| experiment.run(spec, seed))
                    .collect::<Result<Vec<_>, _>>()
            })
        })
        .map_err(|error| value_error("config", error))?;
    let result = PyDict::new(py);
    result.set_item("curves", curve_columns(py, &records)?)?;
    result.set_item("finals", final_columns(py, &records, window)?)?;
    result.set_item(
        "report_input",
        crate::report::report_input(&experiment, &records, seeds.len())?,
    )?;
    Ok(result)
}

/// One list per column of the curves table, in `CURVE_COLUMNS` order.
fn curve_columns<'py>(py: Python<'py>, records: &[RunRecord]) -> PyResult<Bound<'py, PyDict>> {
    let columns: Vec<Bound<'py, PyList>> =
        CURVE_COLUMNS.iter().map(|_| PyList::empty(py)).collect();
    for record in records {
        for row in curve_rows(record) {
            let cells: [Bound<'py, PyAny>; 17] = [
                row.experiment.into_pyobject(py)?.into_any(),
                row.method.into_pyobject(py)?.into_any(),
                row.seed.into_pyobject(py)?.into_any(),
                row.episode.into_pyobject(py)?.into_any(),
                row.steps.into_pyobject(py)?.into_any(),
                row.task_return.into_pyobject(py)?.into_any(),
                row.learning_return.into_pyobject(py)?.into_any(),
                row.terminated.into_pyobject(py)?.to_owned().into_any(),
                row.truncated.into_pyobject(py)?.to_owned().into_any(),
                row.reached.into_pyobject(py)?.to_owned().into_any(),
                row.collisions.into_pyobject(py)?.into_any(),
                row.env_steps.into_pyobject(py)?.into_any(),
                row.optimum_steps.into_pyobject(py)?.into_any(),
                row.time.into_pyobject(py)?.into_any(),
                row.average_reward.into_pyobject(py)?.into_any(),
                row.time_to_reach.into_pyobject(py)?.into_any(),
                row.retention_time.into_pyobject(py)?.into_any(),
            ];
            for (column, cell) in columns.iter().zip(cells) {
                column.append(cell)?;
            }
        }
    }
    let dict = PyDict::new(py);
    for (name, column) in CURVE_COLUMNS.iter().zip(columns) {
        dict.set_item(name, column)?;
    }
    Ok(dict)
}

/// The mean of `curve`'s last `window` values (all of them when shorter), by the report's rule.
fn final_mean(curve: Vec<f64>, window: usize) -> PyResult<f64> {
    final_window_summary(&[curve], window)
        .map(|summary| summary.mean)
        .map_err(|error| value_error("window", error))
}

/// One row per run: its final scores, evaluation and step counts.
#[expect(
    clippy::cast_precision_loss,
    reason = "episode counts and steps stay far below 2^52"
)]
fn final_columns<'py>(
    py: Python<'py>,
    records: &[RunRecord],
    window: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let mut experiment = Vec::new();
    let mut method = Vec::new();
    let mut seed = Vec::new();
    let mut final_steps = Vec::new();
    let mut final_return = Vec::new();
    let mut final_reached = Vec::new();
    let mut final_collisions = Vec::new();
    let mut evaluation_steps = Vec::new();
    let mut evaluation_reached = Vec::new();
    let mut pretrain_env_steps = Vec::new();
    let mut total_env_steps = Vec::new();
    let mut optimum_steps = Vec::new();
    for record in records {
        let curve = |value: fn(&eamadm::EpisodeRecord) -> f64| -> Vec<f64> {
            record.episodes.iter().map(value).collect()
        };
        experiment.push(record.experiment.clone());
        method.push(record.method.clone());
        seed.push(record.seed);
        final_steps.push(final_mean(curve(|e| e.steps as f64), window)?);
        final_return.push(final_mean(curve(|e| e.task_return), window)?);
        final_reached.push(final_mean(
            curve(|e| if e.reached { 1.0 } else { 0.0 }),
            window,
        )?);
        final_collisions.push(final_mean(curve(|e| e.collisions as f64), window)?);
        evaluation_steps.push(record.evaluation.steps);
        evaluation_reached.push(record.evaluation.reached);
        pretrain_env_steps.push(record.pretrain_env_steps);
        total_env_steps.push(record.total_env_steps);
        optimum_steps.push(record.optimum_steps);
    }
    let dict = PyDict::new(py);
    dict.set_item("experiment", experiment)?;
    dict.set_item("method", method)?;
    dict.set_item("seed", seed)?;
    dict.set_item("final_steps", final_steps)?;
    dict.set_item("final_return", final_return)?;
    dict.set_item("final_reached", final_reached)?;
    dict.set_item("final_collisions", final_collisions)?;
    dict.set_item("evaluation_steps", evaluation_steps)?;
    dict.set_item("evaluation_reached", evaluation_reached)?;
    dict.set_item("pretrain_env_steps", pretrain_env_steps)?;
    dict.set_item("total_env_steps", total_env_steps)?;
    dict.set_item("optimum_steps", optimum_steps)?;
    Ok(dict)
}
