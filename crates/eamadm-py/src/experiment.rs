//! Experiments from Python: the paper's presets as TOML text, configs checked and converted,
//! and runs on the Rust runner (GIL released) returned as numpy columns and the text of
//! `final-scores.csv`.

use eamadm::config::{
    PAPER_ROBOT_PAPER_STATE_TOML, PAPER_ROBOT_TOML, PAPER_TASK1_TOML, PAPER_TASK2_TOML,
};
use eamadm::results::{CURVE_COLUMNS, CurveRow, curve_rows};
use eamadm::scores::{final_scores, write_csv};
use eamadm::{Experiment, RunRecord};
use numpy::IntoPyArray;
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
/// `{"curves": columns, "final_scores": text, "report_input": (facts, scores),
/// "figure_files": [(path, svg)]}`: one row per (run, episode) with the columns of the Rust
/// runner's `curves.csv.gz` (numpy arrays; a column with blank cells is `float64` with NaN, text
/// columns are lists), `final-scores.csv` of the runs as the main job writes it, what
/// `report_of_runs` needs of these runs, and their figures as the main job draws them.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "pyo3 hands extracted arguments over by value"
)]
#[pyo3(signature = (toml_text, seeds=None, methods=None, threads=None))]
pub(crate) fn run_config<'py>(
    py: Python<'py>,
    toml_text: &str,
    seeds: Option<Vec<u64>>,
    methods: Option<Vec<String>>,
    threads: Option<usize>,
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
    result.set_item("final_scores", final_scores_csv(&records, &experiment)?)?;
    let (report_input, figure_files) = crate::report::report_input(&experiment, &records)?;
    result.set_item("report_input", report_input)?;
    result.set_item("figure_files", figure_files)?;
    Ok(result)
}

/// One column per column of the curves table, in `CURVE_COLUMNS` order: text as lists,
/// numbers and flags as numpy arrays (`float64` with NaN where a cell is blank).
#[expect(
    clippy::cast_precision_loss,
    reason = "an optimum route is far shorter than 2^52 steps"
)]
fn curve_columns<'py>(py: Python<'py>, records: &[RunRecord]) -> PyResult<Bound<'py, PyDict>> {
    let rows: Vec<_> = records.iter().flat_map(curve_rows).collect();
    let text = |f: fn(&CurveRow) -> &str| PyList::new(py, rows.iter().map(f));
    let int = |f: fn(&CurveRow) -> u64| rows.iter().map(f).collect::<Vec<_>>().into_pyarray(py);
    let real = |f: fn(&CurveRow) -> f64| rows.iter().map(f).collect::<Vec<_>>().into_pyarray(py);
    let flag = |f: fn(&CurveRow) -> bool| rows.iter().map(f).collect::<Vec<_>>().into_pyarray(py);
    let dict = PyDict::new(py);
    for name in CURVE_COLUMNS {
        let column = match name {
            "experiment" => text(|r| &r.experiment)?.into_any(),
            "method" => text(|r| &r.method)?.into_any(),
            "seed" => int(|r| r.seed).into_any(),
            "episode" => int(|r| r.episode).into_any(),
            "steps" => int(|r| r.steps).into_any(),
            "task_return" => real(|r| r.task_return).into_any(),
            "learning_return" => real(|r| r.learning_return).into_any(),
            "terminated" => flag(|r| r.terminated).into_any(),
            "truncated" => flag(|r| r.truncated).into_any(),
            "reached" => flag(|r| r.reached).into_any(),
            "collisions" => int(|r| r.collisions).into_any(),
            "env_steps" => int(|r| r.env_steps).into_any(),
            "optimum_steps" => real(|r| nan_if_blank(r.optimum_steps.map(|s| s as f64))).into_any(),
            "time" => real(|r| nan_if_blank(r.time)).into_any(),
            "average_reward" => real(|r| nan_if_blank(r.average_reward)).into_any(),
            "time_to_reach" => real(|r| nan_if_blank(r.time_to_reach)).into_any(),
            "retention_time" => real(|r| nan_if_blank(r.retention_time)).into_any(),
            other => {
                return Err(value_error(
                    "curves",
                    format!("column {other:?} of the curves table has no conversion (a bug)"),
                ));
            }
        };
        dict.set_item(name, column)?;
    }
    Ok(dict)
}

/// A blank cell as NaN (numpy's missing value of a float column).
fn nan_if_blank(value: Option<f64>) -> f64 {
    value.unwrap_or(f64::NAN)
}

/// `final-scores.csv` of `records` as text, computed and written by `eamadm-eval`
/// (`final_scores`, `write_csv`): the same columns and numbers as the main job's file.
fn final_scores_csv(records: &[RunRecord], experiment: &Experiment) -> PyResult<String> {
    let rows = final_scores(records, experiment).map_err(|error| value_error("config", error))?;
    let mut bytes = Vec::new();
    write_csv(&rows, &mut bytes).map_err(|error| value_error("config", error))?;
    String::from_utf8(bytes).map_err(|error| value_error("config", error))
}
