//! `eamadm._native`: the Rust half of the Python package `eamadm`.
//!
//! The paper's three tasks (the mazes of Task I and Task II, Sec. VI.A, and the wheeled robot
//! of Sec. III and VI.B with its sub-task rewards, Eq. 6–8) as step-by-step cores that the
//! Python classes in `python/eamadm/` wrap into Gymnasium environments; vector cores that
//! step N mazes or N robots in one call on numpy arrays; and the experiment runner (EA-MADM, Algorithm 2,
//! with its decision of Eq. 13–16 and the standardised reward of Eq. 10–12, against the
//! double-Q competitors of Eq. 9) with the GIL released; and the readers of what the main job
//! writes (the run store through `eamadm-runs`, the data package of `final-scores.csv` and
//! `claims.csv`).
//!
//! This layer is thin on purpose: every rule lives in the `eamadm` crates; here arguments are
//! checked, Rust's typed errors become `ValueError`s (`TypeError`s, `FileNotFoundError`s) that
//! name the Python argument, a panic becomes a `RuntimeError` (never pyo3's `PanicException`),
//! long calls release the GIL and stop on Ctrl-C, and results become Python objects. Python users read the package's docs; from Python:
//!
//! ```python
//! import gymnasium as gym
//! import eamadm  # registers eamadm/MazeTaskI-v0, eamadm/MazeTaskII-v0, eamadm/Robot-v0
//!
//! env = gym.make("eamadm/MazeTaskI-v0")
//! observation, info = env.reset(seed=0)
//! observation, reward, terminated, truncated, info = env.step(3)
//! print(info["subtask_rewards"], info["position"])
//! ```

mod error;
mod experiment;
mod figures;
mod maze;
mod outputs;
mod report;
mod robot;

use pyo3::prelude::*;

/// The native module: the env cores, the vector core and the runner.
#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    // The crate's version is the package's (maturin takes the wheel's version from Cargo.toml).
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // numpy's C API is loaded now, not on the first array made: loaded lazily it imports
    // numpy, and a signal pending then (Ctrl-C during a long call) made that import fail
    // inside a conversion, which rust-numpy can only report as a panic.
    error::guard("import eamadm._native (numpy's C API)", || {
        let _ = numpy::PyArray1::<f64>::zeros(module.py(), 0, false);
        Ok(())
    })?;
    module.add_class::<maze::MazeCore>()?;
    module.add_class::<maze::MazeVecCore>()?;
    module.add_class::<robot::RobotCore>()?;
    module.add_class::<robot::RobotVecCore>()?;
    module.add_function(wrap_pyfunction!(experiment::run_config, module)?)?;
    module.add_function(wrap_pyfunction!(experiment::paper_config_toml, module)?)?;
    module.add_function(wrap_pyfunction!(experiment::check_config, module)?)?;
    module.add_function(wrap_pyfunction!(experiment::config_from_json, module)?)?;
    module.add_function(wrap_pyfunction!(experiment::shortened_config, module)?)?;
    module.add_function(wrap_pyfunction!(experiment::paper_tasks, module)?)?;
    module.add_function(wrap_pyfunction!(experiment::toml_to_json, module)?)?;
    module.add_function(wrap_pyfunction!(outputs::load_runs, module)?)?;
    module.add_function(wrap_pyfunction!(outputs::data_package_json, module)?)?;
    module.add_function(wrap_pyfunction!(report::report_of_folder, module)?)?;
    module.add_function(wrap_pyfunction!(report::report_of_runs, module)?)?;
    module.add_function(wrap_pyfunction!(figures::figures_of_folder, module)?)?;
    Ok(())
}
