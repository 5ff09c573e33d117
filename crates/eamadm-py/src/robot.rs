//! The robot cores: the wheeled robot of a scenario (TOML text), with optional overrides of its
//! state discretisation and step cap, stepped from Python one at a time (`RobotCore`) or as N
//! copies in one call (`RobotVecCore`, with Gymnasium's next-step autoreset). Both render the
//! arena as text and as an RGB frame (`wmr_model::render_rgb`); a `RobotCore` pickles (its
//! scenario as TOML and `wmr_model::EpisodeSnapshot` as JSON: pose, noise stream, metrics), so a
//! pickled or deep-copied environment continues bit for bit.

use eamadm::dql::Environment;
use eamadm::wmr_model::{
    Action, EpisodeSnapshot, EpisodeStatus, FRAME_PIXELS_PER_METRE, Scenario, WmrEnv, render_rgb,
};
use numpy::{IntoPyArray, PyArray1, PyArray3, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};

use crate::error::{guard, type_error, value_error};
use crate::maze::frame_array;

/// The arena of `env` as an RGB frame: the robot at its pose, the episode's path.
fn frame_of<'py>(py: Python<'py>, env: &WmrEnv) -> PyResult<Bound<'py, PyArray3<u8>>> {
    guard("render", || {
        frame_array(
            py,
            render_rgb(
                env.scenario(),
                env.pose(),
                env.path(),
                FRAME_PIXELS_PER_METRE,
            ),
        )
    })
}

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
        Err(type_error(
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
                .map_err(|_| type_error("state", "keys must be strings"))?;
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

fn status_name(status: EpisodeStatus) -> &'static str {
    match status {
        EpisodeStatus::Running => "running",
        EpisodeStatus::Reached => "reached",
        EpisodeStatus::Hit => "hit",
        EpisodeStatus::LostTarget => "lost_target",
        EpisodeStatus::Truncated => "truncated",
    }
}

/// `action` as an index of `wmr_model::Action::ALL`, or a `ValueError` naming `argument`.
fn action_index(argument: &str, action: i64) -> PyResult<usize> {
    usize::try_from(action)
        .ok()
        .filter(|&index| index < Action::COUNT)
        .ok_or_else(|| {
            value_error(
                argument,
                format!("expected an action in 0..{}, got {action}", Action::COUNT),
            )
        })
}

/// The robot's pose `(x, y, heading)` in metres and radians.
fn pose_of(env: &WmrEnv) -> (f64, f64, f64) {
    let pose = env.pose();
    (
        pose.translation.vector.x,
        pose.translation.vector.y,
        pose.rotation.angle(),
    )
}

/// The episode's metrics so far as a dict (Sec. VI.B).
fn metrics_of<'py>(py: Python<'py>, env: &WmrEnv) -> PyResult<Bound<'py, PyDict>> {
    let m = env.metrics();
    let dict = PyDict::new(py);
    dict.set_item("steps", m.steps)?;
    dict.set_item("time", m.time)?;
    dict.set_item("task_return", m.task_return)?;
    dict.set_item("subtask_returns", m.subtask_returns.to_vec())?;
    dict.set_item("outcome", status_name(m.status))?;
    dict.set_item("time_to_reach", m.time_to_reach)?;
    dict.set_item("retention_time", m.retention_time)?;
    dict.set_item("path_length", m.path_length)?;
    dict.set_item("average_reward", m.average_reward())?;
    Ok(dict)
}

/// One line of text: time, pose, state, proximity values and outcome.
fn render_of(env: &WmrEnv) -> String {
    let (x, y, heading) = pose_of(env);
    let m = env.metrics();
    let sensor_values: Vec<String> = env
        .sensor_values()
        .iter()
        .map(|r| format!("{r:.2}"))
        .collect();
    format!(
        "t={:.1}s x={x:.3} y={y:.3} heading={heading:.3} state={} proximity=[{}] outcome={}\n",
        m.time,
        env.state(),
        sensor_values.join(" "),
        status_name(m.status)
    )
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
        guard("RobotCore", || {
            let scenario = build_scenario(scenario, state, step_cap)?;
            let env = WmrEnv::new(scenario).map_err(|error| value_error("scenario", error))?;
            Ok(Self { env })
        })
    }

    /// The arguments to make it again (pickling): the scenario in use, overrides applied.
    fn __getnewargs__(&self) -> PyResult<(String,)> {
        Ok((self.scenario_toml()?,))
    }

    /// The episode and the noise stream, as JSON (pickling).
    fn __getstate__(&self) -> PyResult<String> {
        guard("state", || {
            serde_json::to_string(&self.env.snapshot()).map_err(|error| value_error("state", error))
        })
    }

    /// Puts back what `__getstate__` saved; a `ValueError` naming `state` when it is not a
    /// snapshot of this scenario's robot.
    fn __setstate__(&mut self, state: &str) -> PyResult<()> {
        guard("state", || {
            let snapshot: EpisodeSnapshot =
                serde_json::from_str(state).map_err(|error| value_error("state", error))?;
            self.env
                .restore(&snapshot)
                .map_err(|error| value_error("state", error))
        })
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
        guard("step", || {
            let step = self.env.step(action_index("action", action)?);
            Ok((
                step.next_state,
                step.reward,
                step.terminated,
                step.truncated,
            ))
        })
    }

    /// The last step's reward of each sub-task (zeros right after a reset).
    fn subtask_rewards<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.env.subtask_rewards())
    }

    /// The robot's pose `(x, y, heading)` in metres and radians.
    fn pose(&self) -> (f64, f64, f64) {
        pose_of(&self.env)
    }

    /// The episode's metrics so far (Sec. VI.B): steps, time, returns, outcome, time to reach,
    /// retention time, path length, average reward.
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        metrics_of(py, &self.env)
    }

    /// One line of text: time, pose, state, proximity values and outcome.
    fn render(&self) -> String {
        render_of(&self.env)
    }

    /// The arena as an RGB frame (`uint8`, height × width × 3): obstacles, target, the
    /// episode's path and the robot.
    fn render_rgb<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<u8>>> {
        frame_of(py, &self.env)
    }
}

/// One vector step: states, rewards, terminated and truncated, one entry per copy.
type RobotVecStep<'py> = (
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<bool>>,
);

/// N copies of the wheeled robot of one scenario, stepped in one call. Autoreset is
/// Gymnasium's `NEXT_STEP`: a copy that ended on the previous step is reset (continuing its
/// noise stream) instead of stepped, with reward 0 and neither flag set.
#[pyclass(module = "eamadm._native")]
pub(crate) struct RobotVecCore {
    envs: Vec<WmrEnv>,
    /// Copies that ended on the last step and reset on the next.
    ended: Vec<bool>,
}

impl RobotVecCore {
    fn env(&self, index: usize) -> PyResult<&WmrEnv> {
        self.envs.get(index).ok_or_else(|| {
            value_error(
                "index",
                format!("expected a copy in 0..{}, got {index}", self.envs.len()),
            )
        })
    }
}

#[pymethods]
impl RobotVecCore {
    /// `num_envs` copies of the robot `RobotCore(scenario, state, step_cap)` makes.
    #[new]
    #[pyo3(signature = (num_envs, scenario=None, state=None, step_cap=None))]
    fn new(
        num_envs: usize,
        scenario: Option<&str>,
        state: Option<&Bound<'_, PyDict>>,
        step_cap: Option<u32>,
    ) -> PyResult<Self> {
        guard("RobotVecCore", || {
            if num_envs == 0 {
                return Err(value_error("num_envs", "expected a positive int, got 0"));
            }
            let scenario = build_scenario(scenario, state, step_cap)?;
            let envs = (0..num_envs)
                .map(|_| {
                    WmrEnv::new(scenario.clone()).map_err(|error| value_error("scenario", error))
                })
                .collect::<PyResult<Vec<_>>>()?;
            Ok(Self {
                envs,
                ended: vec![false; num_envs],
            })
        })
    }

    /// Number of states of one copy.
    #[getter]
    fn n_states(&self) -> usize {
        self.envs.first().map_or(0, WmrEnv::n_states)
    }

    /// Number of actions of one copy (5).
    #[getter]
    fn n_actions(&self) -> usize {
        self.envs.first().map_or(0, WmrEnv::n_actions)
    }

    /// Resets every copy; `seeds[i]` re-seeds copy `i`'s sensor noise (`None` continues its
    /// stream). Returns the states.
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seeds: Vec<Option<u64>>,
    ) -> PyResult<Bound<'py, PyArray1<i64>>> {
        if seeds.len() != self.envs.len() {
            return Err(value_error(
                "seed",
                format!("expected {} seeds, got {}", self.envs.len(), seeds.len()),
            ));
        }
        let states: Vec<i64> = self
            .envs
            .iter_mut()
            .zip(seeds)
            .map(|(env, seed)| env.reset(seed) as i64)
            .collect();
        self.ended.fill(false);
        Ok(states.into_pyarray(py))
    }

    /// Steps every copy (or resets one that ended on the last step): arrays `(states, rewards,
    /// terminated, truncated)`.
    #[expect(
        clippy::needless_pass_by_value,
        reason = "pyo3 hands extracted arguments over by value"
    )]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray1<'py, i64>,
    ) -> PyResult<RobotVecStep<'py>> {
        guard("step", || self.step_all(py, &actions))
    }

    /// Copy `index`'s last sub-task rewards (zeros right after a reset).
    fn subtask_rewards<'py>(
        &self,
        py: Python<'py>,
        index: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(py, self.env(index)?.subtask_rewards()))
    }

    /// Copy `index`'s pose `(x, y, heading)`.
    fn pose(&self, index: usize) -> PyResult<(f64, f64, f64)> {
        Ok(pose_of(self.env(index)?))
    }

    /// Copy `index`'s episode metrics so far.
    fn metrics<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        metrics_of(py, self.env(index)?)
    }

    /// Copy `index` as one line of text.
    fn render(&self, index: usize) -> PyResult<String> {
        Ok(render_of(self.env(index)?))
    }

    /// Copy `index`'s arena as an RGB frame.
    fn render_rgb<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyArray3<u8>>> {
        frame_of(py, self.env(index)?)
    }
}

impl RobotVecCore {
    fn step_all<'py>(
        &mut self,
        py: Python<'py>,
        actions: &PyReadonlyArray1<'py, i64>,
    ) -> PyResult<RobotVecStep<'py>> {
        let actions = actions
            .as_slice()
            .map_err(|error| value_error("actions", error))?;
        if actions.len() != self.envs.len() {
            return Err(value_error(
                "actions",
                format!(
                    "expected {} actions, got {}",
                    self.envs.len(),
                    actions.len()
                ),
            ));
        }
        let indices = actions
            .iter()
            .map(|&action| action_index("actions", action))
            .collect::<PyResult<Vec<_>>>()?;
        let n = self.envs.len();
        let (mut states, mut rewards) = (Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut terminated, mut truncated) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for ((env, ended), index) in self.envs.iter_mut().zip(&mut self.ended).zip(indices) {
            if *ended {
                states.push(env.reset(None) as i64);
                rewards.push(0.0);
                terminated.push(false);
                truncated.push(false);
                *ended = false;
            } else {
                let step = env.step(index);
                states.push(step.next_state as i64);
                rewards.push(step.reward);
                terminated.push(step.terminated);
                truncated.push(step.truncated);
                *ended = step.terminated || step.truncated;
            }
        }
        Ok((
            states.into_pyarray(py),
            rewards.into_pyarray(py),
            terminated.into_pyarray(py),
            truncated.into_pyarray(py),
        ))
    }
}
