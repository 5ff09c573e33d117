//! Experiments from Python: the paper's presets as TOML text, configs checked and converted,
//! and runs on the Rust runner returned as numpy columns and the text of `final-scores.csv`.
//!
//! A run holds the GIL only between runs: the jobs go to a rayon pool of their own, and the
//! calling thread waits for each finished run with the GIL released, at most
//! [`SIGNAL_CHECK`] at a time, then checks for signals (Ctrl-C) and reports progress. A signal
//! or a failing progress callback stops the call at once (the jobs not started are dropped; a
//! run already started finishes on its thread and is discarded); nothing is written.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::time::Duration;

use eamadm::config::{
    AGGREGATION_CONTROL_TOML, PAPER_ROBOT_PAPER_STATE_TOML, PAPER_ROBOT_TOML, PAPER_TASK1_TOML,
    PAPER_TASK2_TOML,
};
use eamadm::paper::PaperTask;
use eamadm::results::{CURVE_COLUMNS, CurveRow, curve_rows};
use eamadm::scores::{final_scores, write_csv};
use eamadm::{
    Experiment, ExperimentConfig, MethodSpec, QUICK_SEEDS, RunError, RunRecord, Shortening,
};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::error::{guard, internal_error, panic_message, value_error};

/// How long the calling thread waits, GIL released, before it checks for signals again.
const SIGNAL_CHECK: Duration = Duration::from_millis(50);

/// The embedded paper preset `name` ("task1", "task2", "robot", "robot-paper-state" or the
/// positive control "aggregation-control") as TOML text.
#[pyfunction]
pub(crate) fn paper_config_toml(name: &str) -> PyResult<&'static str> {
    match name {
        "task1" => Ok(PAPER_TASK1_TOML),
        "task2" => Ok(PAPER_TASK2_TOML),
        "robot" => Ok(PAPER_ROBOT_TOML),
        "robot-paper-state" => Ok(PAPER_ROBOT_PAPER_STATE_TOML),
        "aggregation-control" => Ok(AGGREGATION_CONTROL_TOML),
        other => Err(value_error(
            "name",
            format!(
                "expected \"task1\", \"task2\", \"robot\", \"robot-paper-state\" or \"aggregation-control\", got {other:?}"
            ),
        )),
    }
}

/// The paper's experiments in the order the main job runs them (`eamadm::paper::PaperTask::ALL`).
#[pyfunction]
pub(crate) fn paper_tasks() -> Vec<&'static str> {
    PaperTask::ALL.iter().map(|task| task.name()).collect()
}

/// Parses, validates and loads the experiment config `toml_text`; a `ValueError` naming
/// `config` and the field when it cannot be used.
#[pyfunction]
pub(crate) fn check_config(toml_text: &str) -> PyResult<()> {
    guard("config", || {
        Experiment::from_toml_str(toml_text)
            .map(drop)
            .map_err(|error| value_error("config", error))
    })
}

/// A config given as JSON (a Python dict of the TOML schema, dumped) checked as the TOML text
/// is, and returned as TOML text. Its errors name the key the user wrote (`methods[2].epsilon`),
/// never a position in the JSON or TOML the package generated.
#[pyfunction]
pub(crate) fn config_from_json(json_text: &str) -> PyResult<String> {
    guard("config", || {
        let value: serde_json::Value =
            serde_json::from_str(json_text).map_err(|error| value_error("config", error))?;
        // Deserialised from the value, not the text: serde_json then reports no line and
        // column, only what is wrong; `serde_path_to_error` adds where.
        let config: ExperimentConfig =
            serde_path_to_error::deserialize(value).map_err(|error| {
                let path = error.path().to_string();
                let inner = error.into_inner();
                if path == "." || path.is_empty() {
                    value_error("config", inner)
                } else {
                    value_error("config", format!("`{path}`: {inner}"))
                }
            })?;
        let text = config
            .to_toml_string()
            .map_err(|error| value_error("config", error))?;
        Experiment::new(config).map_err(|error| value_error("config", error))?;
        Ok(text)
    })
}

/// The TOML text `toml_text` as JSON (for `Config.to_dict`).
#[pyfunction]
pub(crate) fn toml_to_json(toml_text: &str) -> PyResult<String> {
    guard("config", || {
        let table: toml::Table =
            toml::from_str(toml_text).map_err(|error| value_error("config", error))?;
        serde_json::to_string(&table).map_err(|error| value_error("config", error))
    })
}

/// The config `toml_text` shortened as `eamadm.run(..., episodes=, quick=)` shortens it, as
/// TOML text ([`shortening_of`]).
#[pyfunction]
#[pyo3(signature = (toml_text, episodes=None, quick=false))]
pub(crate) fn shortened_config(
    toml_text: &str,
    episodes: Option<u64>,
    quick: bool,
) -> PyResult<String> {
    guard("config", || {
        let config = ExperimentConfig::from_toml_str(toml_text)
            .map_err(|error| value_error("config", error))?;
        let shortening = shortening_of(&config, episodes, quick)?;
        config
            .shortened(&shortening)
            .to_toml_string()
            .map_err(|error| value_error("config", error))
    })
}

/// The [`Shortening`] of `episodes=` and `quick=`: `quick` is `--quick`'s
/// ([`Shortening::QUICK`]), `episodes` at most that many episodes (with `quick`, the smaller
/// of the two). `episodes` above the config's own is refused: the shortcut only shortens.
fn shortening_of(
    config: &ExperimentConfig,
    episodes: Option<u64>,
    quick: bool,
) -> PyResult<Shortening> {
    if let Some(episodes) = episodes {
        if episodes == 0 {
            return Err(value_error("episodes", "expected at least 1, got 0"));
        }
        if episodes > config.episodes {
            return Err(value_error(
                "episodes",
                format!(
                    "{episodes} is more than the config's {} episodes: the shortcut only \
                     shortens (set the config's `episodes` to train longer)",
                    config.episodes
                ),
            ));
        }
    }
    let mut shortening = if quick {
        Shortening::QUICK
    } else {
        Shortening::default()
    };
    if let Some(episodes) = episodes {
        shortening.episodes = Some(shortening.episodes.map_or(episodes, |q| q.min(episodes)));
    }
    Ok(shortening)
}

/// One finished job, sent from the pool to the waiting caller: its index in job order and its
/// record, its error, or its panic's message.
type Finished = (usize, Result<Result<RunRecord, RunError>, String>);

/// The keyword arguments of [`run_config`].
struct RunArguments {
    seeds: Option<Vec<u64>>,
    seed_count: Option<u32>,
    methods: Option<Vec<String>>,
    threads: Option<usize>,
    episodes: Option<u64>,
    quick: bool,
}

/// Runs the experiment `toml_text`: every method in `methods` (labels; default all, in the
/// config's order) with every seed in `seeds` (default the config's `base_seed + i`; or
/// `seed_count` seeds from `base_seed`), shortened by `episodes` and `quick`
/// ([`shortening_of`]; `quick` also runs `min(3, config seeds)` seeds unless seeds are given,
/// as `--quick` does), on `threads` threads (default rayon's). `progress`, if given, is called
/// with `(done, total)` after each finished run. Returns `{"curves": columns, "final_scores":
/// text, "report_input": (facts, scores), "figure_files": [(path, svg)]}`: one row per (run,
/// episode) with the columns of the Rust runner's `curves.csv.gz` (numpy arrays; a column with
/// blank cells is `float64` with NaN, text columns are lists), `final-scores.csv` of the runs as
/// the main job writes it, what `report_of_runs` needs of these runs, and their figures as the
/// main job draws them.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    clippy::too_many_arguments,
    reason = "pyo3 hands extracted arguments over by value, one per keyword"
)]
#[pyo3(signature = (toml_text, seeds=None, methods=None, threads=None, episodes=None, quick=false, seed_count=None, progress=None))]
pub(crate) fn run_config<'py>(
    py: Python<'py>,
    toml_text: &str,
    seeds: Option<Vec<u64>>,
    methods: Option<Vec<String>>,
    threads: Option<usize>,
    episodes: Option<u64>,
    quick: bool,
    seed_count: Option<u32>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let arguments = RunArguments {
        seeds,
        seed_count,
        methods,
        threads,
        episodes,
        quick,
    };
    guard("run", || run(py, toml_text, arguments, progress.as_ref()))
}

fn run<'py>(
    py: Python<'py>,
    toml_text: &str,
    arguments: RunArguments,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut config =
        ExperimentConfig::from_toml_str(toml_text).map_err(|error| value_error("config", error))?;
    let shortening = shortening_of(&config, arguments.episodes, arguments.quick)?;
    match arguments.seed_count {
        Some(0) => return Err(value_error("seeds", "expected at least 1 seed, got 0")),
        Some(count) => config.seeds = count,
        None if arguments.quick && arguments.seeds.is_none() => {
            config.seeds = QUICK_SEEDS.min(config.seeds);
        }
        None => {}
    }
    let experiment = Experiment::new(config.shortened(&shortening))
        .map_err(|error| value_error("config", error))?;
    let config = experiment.config();
    let specs: Vec<MethodSpec> = match &arguments.methods {
        None => config.methods.clone(),
        Some(labels) => {
            if labels.is_empty() {
                return Err(value_error("methods", "expected at least one label"));
            }
            labels
                .iter()
                .map(|label| {
                    config.method(label).cloned().ok_or_else(|| {
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
    let seeds = match arguments.seeds {
        Some(seeds) if seeds.is_empty() => {
            return Err(value_error("seeds", "expected at least one seed"));
        }
        Some(seeds) => seeds,
        None => config.seed_values().collect(),
    };
    let pool = match arguments.threads {
        Some(0) => return Err(value_error("threads", "expected at least 1, got 0")),
        Some(n) => rayon::ThreadPoolBuilder::new().num_threads(n),
        None => rayon::ThreadPoolBuilder::new(),
    }
    .build()
    .map_err(|error| value_error("threads", error))?;
    // Job order: method by method, seed by seed, whatever thread finishes first.
    let jobs: Vec<(MethodSpec, u64)> = specs
        .iter()
        .flat_map(|spec| seeds.iter().map(move |&seed| (spec.clone(), seed)))
        .collect();
    let total = jobs.len();
    let experiment = Arc::new(experiment);
    let stop = Arc::new(AtomicBool::new(false));
    let (sender, receiver) = mpsc::channel::<Finished>();
    for (index, (spec, seed)) in jobs.into_iter().enumerate() {
        let (experiment, stop, sender) =
            (Arc::clone(&experiment), Arc::clone(&stop), sender.clone());
        pool.spawn(move || {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                experiment.run(&spec, seed)
            }))
            .map_err(|payload| panic_message(&*payload));
            // The caller may have stopped waiting (an interrupt): then nobody wants the run.
            let _ = sender.send((index, outcome));
        });
    }
    drop(sender);
    // Stops the pending jobs when this call ends early (an error or an interrupt).
    struct StopOnDrop(Arc<AtomicBool>);
    impl Drop for StopOnDrop {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Relaxed);
        }
    }
    let _stop_pending = StopOnDrop(Arc::clone(&stop));
    let mut records: Vec<Option<RunRecord>> = (0..total).map(|_| None).collect();
    let mut done = 0;
    // Waited on with the GIL released, from this thread only: the mutex is never contended,
    // it only makes the receiver shareable with the closure `detach` takes.
    let receiver = Mutex::new(receiver);
    while done < total {
        let finished = py.detach(|| match receiver.lock() {
            Ok(receiver) => receiver.recv_timeout(SIGNAL_CHECK),
            Err(poisoned) => poisoned.into_inner().recv_timeout(SIGNAL_CHECK),
        });
        py.check_signals()?;
        match finished {
            Ok((index, Ok(Ok(record)))) => {
                records[index] = Some(record);
                done += 1;
                if let Some(callback) = progress {
                    callback.call1((done, total))?;
                }
            }
            Ok((_, Ok(Err(error)))) => return Err(value_error("config", error)),
            Ok((_, Err(message))) => {
                return Err(internal_error("run", &message));
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(internal_error(
                    "run",
                    &"a run ended without a record or an error",
                ));
            }
        }
    }
    let records: Vec<RunRecord> = records.into_iter().flatten().collect();
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
                return Err(internal_error(
                    "curves",
                    &format!("column {other:?} of the curves table has no conversion"),
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
