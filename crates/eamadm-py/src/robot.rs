//! The robot core: the wheeled robot of a scenario (TOML text), with optional overrides of its
//! state discretisation and step cap, stepped from Python.

use eamadm::dql::Environment;
use eamadm::wmr_model::{Action, Outcome, Scenario, WmrEnv};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};

use crate::error::value_error;

/// A Python scalar as a TOML value, or a `ValueError` naming `argument`.
fn toml_value(argument: &str, value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if value.is_instance_of::<PyBool>() {
        Ok(toml::Value::Boolean(value.extract()?))
    } else if value.is_instance_of::<PyInt>() {
        Ok(toml::Value::Integer(value.extract().map_err(|_| {
            value_error(argument, "an integer does not fit in 64 bits")
        })?))
    } else if value.is_instance_of::<PyFloat>() {
        Ok(toml::Value::Float(value.extract()?))
    } else if value.is_instance_of::<PyString>() {
        Ok(toml::Value::String(value.extract()?))
    } else {
        Err(value_error(
            argument,
            format!(
                "expected an int, float, bool or str, got {}",
                value.get_type().name()?
            ),
        ))
    }
}

/// The scenario of `text` (the embedded default when `None`), with `state` entries overriding
/// its `[state]` table and `step_cap` its step cap. Each stage's errors name its argument.
fn build_scenario(
    text: Option<&str>,
    state: Option<&Bound<'_, PyDict>>,
    step_cap: Option<u32>,
) -> PyResult<Scenario> {
    let base = match text {
        Some(text) => Scenario::from_toml_str(text),
        None => Ok(Scenario::default_scenario()),
    };
    let mut scenario = base
        .and_then(|scenario| scenario.validate().map(|()| scenario))
        .map_err(|error| value_error("scenario", error))?;
    if let Some(state) = state {
        let mut table =
            toml::Table::try_from(scenario.state).map_err(|error| value_error("state", error))?;
        for (key, value) in state.iter() {
            let key: String = key
                .extract()
                .map_err(|_| value_error("state", "keys must be strings"))?;
            table.insert(key, toml_value("state", &value)?);
        }
        let mut whole =
            toml::Table::try_from(&scenario).map_err(|error| value_error("scenario", error))?;
        whole.insert("state".to_owned(), toml::Value::Table(table));
        let text = toml::to_string(&whole).map_err(|error| value_error("state", error))?;
        scenario = Scenario::from_toml_str(&text)
            .and_then(|scenario| scenario.validate().map(|()| scenario))
            .map_err(|error| value_error("state", error))?;
    }
    if let Some(cap) = step_cap {
        if cap == 0 {
            return Err(value_error("step_cap", "expected at least 1, got 0"));
        }
        scenario.step_cap = cap;
    }
    Ok(scenario)
}

fn outcome_name(outcome: Outcome) -> &'static str {
    match outcome {
        Outcome::Running => "running",
        Outcome::Reached => "reached",
        Outcome::Hit => "hit",
        Outcome::LostTarget => "lost_target",
        Outcome::Truncated => "truncated",
    }
}

/// The wheeled robot of one scenario, stepped from Python. Actions are the five of
/// `wmr_model::Action::ALL`; the sensor noise comes from a `ChaCha8` stream seeded by `reset`.
#[pyclass(module = "eamadm._native")]
pub(crate) struct RobotCore {
    env: WmrEnv,
}

#[pymethods]
impl RobotCore {
    /// `scenario`: scenario TOML text (default: the embedded Fig. 12 analogue); `state`:
    /// entries overriding the scenario's `[state]` table (e.g. `{"distance_bins": 12}`);
    /// `step_cap`: episode truncation in steps.
    #[new]
    #[pyo3(signature = (scenario=None, state=None, step_cap=None))]
    fn new(
        scenario: Option<&str>,
        state: Option<&Bound<'_, PyDict>>,
        step_cap: Option<u32>,
    ) -> PyResult<Self> {
        let scenario = build_scenario(scenario, state, step_cap)?;
        let env = WmrEnv::new(scenario).map_err(|error| value_error("scenario", error))?;
        Ok(Self { env })
    }

    /// Number of states.
    #[getter]
    fn n_states(&self) -> usize {
        self.env.n_states()
    }

    /// Number of actions (5).
    #[getter]
    fn n_actions(&self) -> usize {
        self.env.n_actions()
    }

    /// The sub-tasks' names, in the order of `subtask_rewards`.
    #[getter]
    fn subtask_names(&self) -> Vec<String> {
        self.env.subtask_names()
    }

    /// The scenario actually used, as TOML text (overrides applied).
    #[getter]
    fn scenario_toml(&self) -> PyResult<String> {
        self.env
            .scenario()
            .to_toml_string()
            .map_err(|error| value_error("scenario", error))
    }

    /// Puts the robot at the start pose; `seed` re-seeds the sensor noise (`None` continues
    /// the current stream). Returns the state.
    #[pyo3(signature = (seed=None))]
    fn reset(&mut self, seed: Option<u64>) -> usize {
        self.env.reset(seed)
    }

    /// One step: `(state, reward, terminated, truncated)`.
    fn step(&mut self, action: i64) -> PyResult<(usize, f64, bool, bool)> {
        let index = usize::try_from(action)
            .ok()
            .filter(|&index| index < Action::COUNT)
            .ok_or_else(|| {
                value_error(
                    "action",
                    format!("expected an action in 0..{}, got {action}", Action::COUNT),
                )
            })?;
        let step = self.env.step(index);
        Ok((
            step.next_state,
            step.reward,
            step.terminated,
            step.truncated,
        ))
    }

    /// The last step's reward of each sub-task (zeros right after a reset).
    fn subtask_rewards<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.env.subtask_rewards())
    }

    /// The robot's pose `(x, y, heading)` in metres and radians.
    fn pose(&self) -> (f64, f64, f64) {
        let pose = self.env.pose();
        (
            pose.translation.vector.x,
            pose.translation.vector.y,
            pose.rotation.angle(),
        )
    }

    /// The episode's metrics so far (Sec. VI.B): steps, time, returns, outcome, time to reach,
    /// retention time, path length, average reward.
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let m = self.env.metrics();
        let dict = PyDict::new(py);
        dict.set_item("steps", m.steps)?;
        dict.set_item("time", m.time)?;
        dict.set_item("task_return", m.task_return)?;
        dict.set_item("subtask_returns", m.subtask_returns.to_vec())?;
        dict.set_item("outcome", outcome_name(m.outcome))?;
        dict.set_item("time_to_reach", m.time_to_reach)?;
        dict.set_item("retention_time", m.retention_time)?;
        dict.set_item("path_length", m.path_length)?;
        dict.set_item("average_reward", m.average_reward())?;
        Ok(dict)
    }

    /// One line of text: time, pose, state, proximity readings and outcome.
    fn render(&self) -> String {
        let (x, y, heading) = self.pose();
        let m = self.env.metrics();
        let readings: Vec<String> = self
            .env
            .readings()
            .iter()
            .map(|r| format!("{r:.2}"))
            .collect();
        format!(
            "t={:.1}s x={x:.3} y={y:.3} heading={heading:.3} state={} proximity=[{}] outcome={}\n",
            m.time,
            self.env.state(),
            readings.join(" "),
            outcome_name(m.outcome)
        )
    }
}
