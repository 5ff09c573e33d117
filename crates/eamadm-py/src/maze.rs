//! The maze cores: one maze stepped from Python (`MazeCore`), and N mazes stepped in one call
//! on numpy arrays (`MazeVecCore`, Gymnasium's next-step autoreset). Both render the maze as
//! text and as an RGB frame (`mazes::render_rgb`); a `MazeCore` pickles (its task arguments and
//! where its episode stands, `MazeEnv::episode`), so a pickled or deep-copied environment
//! continues exactly.

use eamadm::dql::Environment;
use eamadm::dql::RgbFrame;
use eamadm::mazes::{
    Event, Maze, MazeCursor, MazeEnv, Pos, Preset, SpecError, TILE_PIXELS, render_rgb, render_text,
};
use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::error::{guard, internal_error, value_error};

/// An RGB frame as a numpy `uint8` array of shape `(height, width, 3)`.
pub(crate) fn frame_array(py: Python<'_>, frame: RgbFrame) -> PyResult<Bound<'_, PyArray3<u8>>> {
    Array3::from_shape_vec((frame.height, frame.width, 3), frame.pixels)
        .map(|array| array.into_pyarray(py))
        .map_err(|error| internal_error("render", &error.to_string()))
}

/// The pickled state of a `MazeCore`: the agent's tile, steps, last event and the episode's
/// visited tiles.
type MazeState = ((usize, usize), u32, Option<String>, Vec<(usize, usize)>);

/// The preset called `name` (`"task1"` or `"task2"`), or a `ValueError` naming `argument`.
fn preset(argument: &str, name: &str) -> PyResult<Preset> {
    Preset::ALL
        .into_iter()
        .find(|preset| preset.id() == name)
        .ok_or_else(|| {
            value_error(
                argument,
                format!("expected \"task1\" or \"task2\", got {name:?}"),
            )
        })
}

/// The maze env of `task`'s preset, or of the text `map` with `rewards`' rewards and
/// sub-tasks (default: `task`'s), with an optional step cap.
fn build_env(
    task: &str,
    map: Option<&str>,
    rewards: Option<&str>,
    step_cap: Option<u32>,
) -> PyResult<MazeEnv> {
    let task = preset("task", task)?;
    let maze = match map {
        Some(text) => Maze::parse(text).map_err(|error| value_error("map", error))?,
        None => task.maze(),
    };
    let mut spec = match rewards {
        Some(name) => preset("rewards", name)?.task_spec(),
        None => task.task_spec(),
    };
    if let Some(cap) = step_cap {
        spec.step_cap = cap;
    }
    MazeEnv::new(maze, spec).map_err(|error| match error {
        SpecError::StepCapOutOfRange { .. } => value_error("step_cap", error),
        other => value_error("rewards", other),
    })
}

/// An action from Python, checked against the maze's four actions.
fn action_index(argument: &str, action: i64) -> PyResult<usize> {
    usize::try_from(action)
        .ok()
        .filter(|&index| index < eamadm::mazes::N_ACTIONS)
        .ok_or_else(|| {
            value_error(
                argument,
                format!("expected an action in 0..4, got {action}"),
            )
        })
}

fn xy(pos: Pos) -> (usize, usize) {
    (pos.x, pos.y)
}

/// One maze task, stepped from Python. States are tiles `y * width + x`; actions 0 up,
/// 1 down, 2 left, 3 right.
#[pyclass(module = "eamadm._native")]
pub(crate) struct MazeCore {
    env: MazeEnv,
    /// Tiles visited in the current episode (for the renderings).
    path: Vec<Pos>,
    /// The arguments it was made with (to pickle it).
    arguments: (String, Option<String>, Option<String>, Option<u32>),
}

#[pymethods]
impl MazeCore {
    /// `task`: "task1" or "task2" (the preset); `map`: a text map replacing the preset's layout;
    /// `rewards`: whose rewards and sub-tasks ("task1" or "task2", default `task`);
    /// `step_cap`: episode truncation in steps.
    #[new]
    #[pyo3(signature = (task, map=None, rewards=None, step_cap=None))]
    fn new(
        task: &str,
        map: Option<&str>,
        rewards: Option<&str>,
        step_cap: Option<u32>,
    ) -> PyResult<Self> {
        guard("MazeCore", || {
            let mut env = build_env(task, map, rewards, step_cap)?;
            env.reset(None);
            let path = vec![env.position()];
            Ok(Self {
                env,
                path,
                arguments: (
                    task.to_owned(),
                    map.map(str::to_owned),
                    rewards.map(str::to_owned),
                    step_cap,
                ),
            })
        })
    }

    /// The arguments to make it again (pickling).
    fn __getnewargs__(&self) -> (String, Option<String>, Option<String>, Option<u32>) {
        self.arguments.clone()
    }

    /// Where the episode stands (pickling).
    fn __getstate__(&self) -> MazeState {
        let (position, steps, event) = self.env.episode();
        (
            xy(position),
            steps,
            event.map(|event| event.name().to_owned()),
            self.path.iter().map(|&pos| xy(pos)).collect(),
        )
    }

    /// Puts the episode back where `__getstate__` saw it; a `ValueError` naming `state` when
    /// it cannot stand on this maze.
    fn __setstate__(&mut self, state: MazeState) -> PyResult<()> {
        guard("state", || {
            let ((x, y), steps, event, path) = state;
            let event = match event {
                None => None,
                Some(name) => Some(
                    Event::ALL
                        .into_iter()
                        .find(|event| event.name() == name)
                        .ok_or_else(|| value_error("state", format!("no event named {name:?}")))?,
                ),
            };
            let path: Vec<Pos> = path.into_iter().map(|(x, y)| Pos::new(x, y)).collect();
            if path.last() != Some(&Pos::new(x, y)) {
                return Err(value_error(
                    "state",
                    "the visited tiles must end on the agent's tile",
                ));
            }
            self.env
                .set_episode(Pos::new(x, y), steps, event)
                .map_err(|error| value_error("state", error))?;
            self.path = path;
            Ok(())
        })
    }

    /// Number of states (tiles, obstacles included).
    #[getter]
    fn n_states(&self) -> usize {
        self.env.n_states()
    }

    /// Number of actions (4).
    #[getter]
    fn n_actions(&self) -> usize {
        self.env.n_actions()
    }

    /// The sub-tasks' names, in the order of `subtask_rewards`.
    #[getter]
    fn subtask_names(&self) -> Vec<String> {
        self.env.subtask_names()
    }

    /// The step cap.
    #[getter]
    fn step_cap(&self) -> u32 {
        self.env.spec().step_cap
    }

    /// Puts the agent on the start tile and returns its state (the maze has no randomness).
    fn reset(&mut self) -> usize {
        let state = self.env.reset(None);
        self.path.clear();
        self.path.push(self.env.position());
        state
    }

    /// One step: `(state, reward, terminated, truncated)`.
    fn step(&mut self, action: i64) -> PyResult<(usize, f64, bool, bool)> {
        guard("step", || {
            let step = self.env.step(action_index("action", action)?);
            self.path.push(self.env.position());
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

    /// The agent's tile `(x, y)`: column, row from the top.
    fn position(&self) -> (usize, usize) {
        xy(self.env.position())
    }

    /// What the last step was ("closer", "farther", "bump", "target"), or `None` after a reset.
    fn last_event(&self) -> Option<&'static str> {
        self.env.last_event().map(eamadm::mazes::Event::name)
    }

    /// The maze as text, the episode's path marked.
    fn render(&self) -> String {
        render_text(self.env.maze(), &self.path)
    }

    /// The maze as an RGB frame (`uint8`, height × width × 3), the episode's path and the agent
    /// marked.
    fn render_rgb<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<u8>>> {
        guard("render", || {
            frame_array(py, render_rgb(self.env.maze(), &self.path, TILE_PIXELS))
        })
    }
}

/// N copies of one maze task stepped together: one maze (its tables shared) and one
/// [`MazeCursor`] per copy. After an episode ends, the next `step` resets that copy instead of
/// stepping it (Gymnasium's `AutoresetMode.NEXT_STEP`): it returns the start state, reward 0,
/// not terminated, not truncated, and ignores that copy's action.
#[pyclass(module = "eamadm._native")]
pub(crate) struct MazeVecCore {
    env: MazeEnv,
    cursors: Vec<MazeCursor>,
    /// Copy `i` ended its episode on the last step and resets on the next.
    needs_reset: Vec<bool>,
}

/// The arrays of one vector step: states, rewards, terminated, truncated, sub-task rewards
/// (N × m) and positions (N × 2).
type VecStep<'py> = (
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray1<bool>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<i64>>,
);

/// One vector step's columns, filled copy by copy.
struct Columns {
    states: Vec<i64>,
    rewards: Vec<f64>,
    terminated: Vec<bool>,
    truncated: Vec<bool>,
    subtask: Vec<f64>,
    positions: Vec<i64>,
}

impl Columns {
    fn with_capacity(n: usize, n_subtasks: usize) -> Self {
        Self {
            states: Vec::with_capacity(n),
            rewards: Vec::with_capacity(n),
            terminated: Vec::with_capacity(n),
            truncated: Vec::with_capacity(n),
            subtask: Vec::with_capacity(n * n_subtasks),
            positions: Vec::with_capacity(n * 2),
        }
    }

    /// Appends one copy's row: its step and where its cursor now stands.
    fn push(
        &mut self,
        env: &MazeEnv,
        cursor: &MazeCursor,
        reward: f64,
        terminated: bool,
        truncated: bool,
    ) {
        let state = cursor.state();
        let width = env.maze().width();
        self.states.push(state_i64(state));
        self.rewards.push(reward);
        self.terminated.push(terminated);
        self.truncated.push(truncated);
        self.subtask
            .extend_from_slice(env.cursor_subtask_rewards(cursor));
        self.positions.push(state_i64(state % width));
        self.positions.push(state_i64(state / width));
    }

    fn into_arrays(self, py: Python<'_>, n_subtasks: usize) -> PyResult<VecStep<'_>> {
        let n = self.states.len();
        let shape_error = |error: numpy::ndarray::ShapeError| value_error("num_envs", error);
        let subtask = Array2::from_shape_vec((n, n_subtasks), self.subtask).map_err(shape_error)?;
        let positions = Array2::from_shape_vec((n, 2), self.positions).map_err(shape_error)?;
        Ok((
            self.states.into_pyarray(py),
            self.rewards.into_pyarray(py),
            self.terminated.into_pyarray(py),
            self.truncated.into_pyarray(py),
            subtask.into_pyarray(py),
            positions.into_pyarray(py),
        ))
    }
}

#[pymethods]
impl MazeVecCore {
    /// `num_envs` copies of the task `MazeCore(task, map, rewards, step_cap)` describes.
    #[new]
    #[pyo3(signature = (num_envs, task, map=None, rewards=None, step_cap=None))]
    fn new(
        num_envs: usize,
        task: &str,
        map: Option<&str>,
        rewards: Option<&str>,
        step_cap: Option<u32>,
    ) -> PyResult<Self> {
        guard("MazeVecCore", || {
            if num_envs == 0 {
                return Err(value_error("num_envs", "expected at least 1, got 0"));
            }
            let env = build_env(task, map, rewards, step_cap)?;
            Ok(Self {
                cursors: vec![env.start_cursor(); num_envs],
                needs_reset: vec![false; num_envs],
                env,
            })
        })
    }

    /// Number of copies.
    #[getter]
    fn num_envs(&self) -> usize {
        self.cursors.len()
    }

    /// Number of states of one copy.
    #[getter]
    fn n_states(&self) -> usize {
        self.env.n_states()
    }

    /// The sub-tasks' names.
    #[getter]
    fn subtask_names(&self) -> Vec<String> {
        self.env.subtask_names()
    }

    /// Resets every copy; returns the arrays of a step (rewards 0, nothing ended).
    fn reset<'py>(&mut self, py: Python<'py>) -> PyResult<VecStep<'py>> {
        let n_subtasks = self.env.n_subtasks();
        let mut columns = Columns::with_capacity(self.cursors.len(), n_subtasks);
        for cursor in &mut self.cursors {
            *cursor = self.env.start_cursor();
            columns.push(&self.env, cursor, 0.0, false, false);
        }
        self.needs_reset.fill(false);
        columns.into_arrays(py, n_subtasks)
    }

    /// Steps every copy with its action (`actions`: int64, one per copy, each in 0..4).
    #[expect(
        clippy::needless_pass_by_value,
        reason = "pyo3 hands extracted arguments over by value"
    )]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray1<'py, i64>,
    ) -> PyResult<VecStep<'py>> {
        guard("step", || self.step_all(py, &actions))
    }

    /// The maze as text with copy `index`'s agent marked.
    fn render(&self, index: usize) -> PyResult<String> {
        let cursor = self.cursor(index)?;
        Ok(render_text(
            self.env.maze(),
            &[self.env.cursor_position(cursor)],
        ))
    }

    /// The maze as an RGB frame with copy `index`'s agent marked.
    fn render_rgb<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let cursor = self.cursor(index)?;
        guard("render", || {
            frame_array(
                py,
                render_rgb(
                    self.env.maze(),
                    &[self.env.cursor_position(cursor)],
                    TILE_PIXELS,
                ),
            )
        })
    }
}

impl MazeVecCore {
    fn cursor(&self, index: usize) -> PyResult<&MazeCursor> {
        self.cursors.get(index).ok_or_else(|| {
            value_error(
                "index",
                format!("expected a copy in 0..{}, got {index}", self.cursors.len()),
            )
        })
    }

    fn step_all<'py>(
        &mut self,
        py: Python<'py>,
        actions: &PyReadonlyArray1<'py, i64>,
    ) -> PyResult<VecStep<'py>> {
        let actions = actions
            .as_slice()
            .map_err(|error| value_error("actions", error))?;
        let n = self.cursors.len();
        if actions.len() != n {
            return Err(value_error(
                "actions",
                format!("expected {n} actions, got {}", actions.len()),
            ));
        }
        if let Some(&bad) = actions.iter().find(|&&a| !(0..4).contains(&a)) {
            return Err(value_error(
                "actions",
                format!("expected actions in 0..4, got {bad}"),
            ));
        }
        let n_subtasks = self.env.n_subtasks();
        let mut columns = Columns::with_capacity(n, n_subtasks);
        for ((cursor, needs_reset), &action) in self
            .cursors
            .iter_mut()
            .zip(&mut self.needs_reset)
            .zip(actions)
        {
            if *needs_reset {
                *needs_reset = false;
                *cursor = self.env.start_cursor();
                columns.push(&self.env, cursor, 0.0, false, false);
            } else {
                // Checked above: 0 <= action < 4.
                let step = self.env.step_cursor(cursor, action as usize);
                *needs_reset = step.terminated || step.truncated;
                columns.push(
                    &self.env,
                    cursor,
                    step.reward,
                    step.terminated,
                    step.truncated,
                );
            }
        }
        columns.into_arrays(py, n_subtasks)
    }
}

/// A state or coordinate as numpy's int64 (mazes have at most 2^24 tiles).
fn state_i64(value: usize) -> i64 {
    i64::try_from(value).unwrap_or(i64::MAX)
}
