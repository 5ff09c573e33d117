//! Loading a task config into an environment, and what the runner needs from environments
//! beyond [`dql::Environment`]: collisions, reaching the target, positions, robot metrics.

use std::path::Path;
use std::sync::Arc;

use dql::{Environment, Step, Trajectory};
use mazes::{Event, Maze, MazeEnv, Preset};
use wmr_model::{EpisodeStatus, PlannerParams, Scenario, WmrEnv};

use crate::config::{ConfigError, DEFAULT_SCENARIO, TaskConfig, read_input_file};
use crate::record::RobotEpisodeMetrics;

/// A loaded task: the environment every run of an experiment starts from (each run clones it).
#[derive(Debug, Clone)]
pub struct Task {
    kind: TaskKind,
    /// The optimal route's length, computed once at loading.
    optimum_steps: Option<u64>,
    /// The text of the file the config names (a maze map, a robot scenario), as read once at
    /// loading: the task was built from exactly these bytes.
    input: Option<Arc<str>>,
}

#[derive(Debug, Clone)]
pub(crate) enum TaskKind {
    Maze(Box<MazeEnv>),
    Robot(Box<WmrEnv>),
}

impl Task {
    /// Builds the task a config names: generates a preset maze, reads a map file or parses an
    /// inline map, and applies the step cap override.
    ///
    /// A file the config names (`task.path`, `task.scenario`) is read once, here, and the task
    /// is built from those bytes, which [`Task::input_text`] keeps: whoever keys results by
    /// the file's content (a run store) hashes them rather than reading the file again, so a
    /// file that changes afterwards changes neither what this task computes nor the keys its
    /// results are stored under.
    ///
    /// # Errors
    /// [`ConfigError::Read`] for a file that cannot be read, [`ConfigError::Maze`] for a map
    /// that does not parse (both naming the field), [`ConfigError::Invalid`] for a zero step
    /// cap.
    pub fn load(config: &TaskConfig) -> Result<Self, ConfigError> {
        match config {
            TaskConfig::Maze {
                preset,
                rewards,
                step_cap,
            } => Self::from_maze(
                preset.maze(),
                rewards.unwrap_or(*preset),
                *step_cap,
                "task.preset",
            ),
            TaskConfig::MazeFile {
                path,
                rewards,
                step_cap,
            } => {
                let text = read_input_file(path, "task.path")?;
                let maze = Maze::parse(&text).map_err(|source| ConfigError::Maze {
                    field: "task.path".to_owned(),
                    source,
                })?;
                let mut task = Self::from_maze(maze, *rewards, *step_cap, "task.rewards")?;
                task.input = Some(Arc::from(text));
                Ok(task)
            }
            TaskConfig::MazeText {
                map,
                rewards,
                step_cap,
            } => {
                let maze = Maze::parse(map).map_err(|source| ConfigError::Maze {
                    field: "task.map".to_owned(),
                    source,
                })?;
                Self::from_maze(maze, *rewards, *step_cap, "task.rewards")
            }
            TaskConfig::Robot {
                scenario,
                step_cap,
                target_bins,
                control_period,
                reach_radius,
                distance_bins,
            } => {
                let scenario_error = |source| ConfigError::Scenario {
                    field: "task.scenario".to_owned(),
                    source,
                };
                let mut input = None;
                let mut scenario = if scenario == DEFAULT_SCENARIO {
                    Scenario::default_scenario()
                } else {
                    let text = read_input_file(Path::new(scenario), "task.scenario")?;
                    let parsed = Scenario::from_toml_str(&text).map_err(scenario_error)?;
                    input = Some(Arc::from(text));
                    parsed
                };
                if let Some(cap) = step_cap {
                    scenario.step_cap = *cap;
                }
                if let Some(bins) = target_bins {
                    scenario.state.target_bins = *bins;
                }
                if let Some(period) = control_period {
                    scenario.control_period = *period;
                }
                if let Some(radius) = reach_radius {
                    scenario.target.reach_radius = *radius;
                }
                if let Some(bins) = distance_bins {
                    scenario.state.distance_bins = *bins;
                }
                // Validates the overrides too, then proves the target reachable: a scenario
                // whose target no route reaches is refused here, not trained on in vain. The
                // shortest route found is the robot's analogue of a BFS optimum.
                let plan = scenario
                    .check_route(&PlannerParams::default())
                    .map_err(scenario_error)?;
                let optimum_steps = Some(plan.actions.len() as u64);
                let env = WmrEnv::new(scenario).map_err(scenario_error)?;
                Ok(Self {
                    kind: TaskKind::Robot(Box::new(env)),
                    optimum_steps,
                    input,
                })
            }
        }
    }

    fn from_maze(
        maze: Maze,
        rewards: Preset,
        step_cap: Option<u32>,
        field: &str,
    ) -> Result<Self, ConfigError> {
        let mut spec = rewards.task_spec();
        if let Some(cap) = step_cap {
            spec.step_cap = cap;
        }
        let env = MazeEnv::new(maze, spec).map_err(|source| ConfigError::MazeSpec {
            field: field.to_owned(),
            source,
        })?;
        Ok(Self {
            optimum_steps: u64::try_from(env.maze().shortest_path_len()).ok(),
            kind: TaskKind::Maze(Box::new(env)),
            input: None,
        })
    }

    /// The text of the file the task's config names (a maze map with `task.path`, a robot
    /// scenario with `task.scenario` other than `"default"`), exactly as read when the task was
    /// loaded and built; `None` for a task the config holds whole (a preset, an inline map,
    /// the embedded scenario). A run store keys results by the hash of these bytes.
    #[must_use]
    pub fn input_text(&self) -> Option<&str> {
        self.input.as_deref()
    }

    pub(crate) fn kind(&self) -> &TaskKind {
        &self.kind
    }

    /// Number of states.
    #[must_use]
    pub fn n_states(&self) -> usize {
        match &self.kind {
            TaskKind::Maze(env) => env.n_states(),
            TaskKind::Robot(env) => env.n_states(),
        }
    }

    /// Number of actions.
    #[must_use]
    pub fn n_actions(&self) -> usize {
        match &self.kind {
            TaskKind::Maze(env) => env.n_actions(),
            TaskKind::Robot(env) => env.n_actions(),
        }
    }

    /// Names of the sub-tasks, in order.
    #[must_use]
    pub fn subtask_names(&self) -> Vec<String> {
        match &self.kind {
            TaskKind::Maze(env) => env.subtask_names(),
            TaskKind::Robot(env) => env.subtask_names(),
        }
    }

    /// Length of the optimal route in steps, when known: the BFS shortest path of a maze; for
    /// the robot, the shortest route [`wmr_model::shortest_plan`] finds (with its default
    /// resolution; `None` if it finds none).
    #[must_use]
    pub fn optimum_steps(&self) -> Option<u64> {
        self.optimum_steps
    }

    /// Steps after which an episode is truncated: the maze's task spec's, or the robot
    /// scenario's (either with the config's `task.step_cap` applied).
    #[must_use]
    pub fn step_cap(&self) -> u64 {
        u64::from(match &self.kind {
            TaskKind::Maze(env) => env.spec().step_cap,
            TaskKind::Robot(env) => env.scenario().step_cap,
        })
    }

    /// The maze, for a maze task.
    #[must_use]
    pub fn maze(&self) -> Option<&Maze> {
        self.maze_env().map(MazeEnv::maze)
    }

    /// The maze environment, for a maze task.
    #[must_use]
    pub fn maze_env(&self) -> Option<&MazeEnv> {
        match &self.kind {
            TaskKind::Maze(env) => Some(env),
            TaskKind::Robot(_) => None,
        }
    }

    /// The robot's scenario, for the robot task.
    #[must_use]
    pub fn scenario(&self) -> Option<&Scenario> {
        self.robot_env().map(WmrEnv::scenario)
    }

    /// The robot environment, for the robot task.
    #[must_use]
    pub fn robot_env(&self) -> Option<&WmrEnv> {
        match &self.kind {
            TaskKind::Robot(env) => Some(env),
            TaskKind::Maze(_) => None,
        }
    }
}

/// What the runner reads from a task's environment besides [`Environment`].
pub(crate) trait TaskEnv:
    Environment + Clone + Send + Sync + crate::pretrain::SubtaskGoals
{
    /// The last step was a collision (a bump, a hit).
    fn collided(&self) -> bool;

    /// The episode that just ended reached the target (`terminated` is the driver's flag).
    fn reached(&self, terminated: bool) -> bool;

    /// Positions along the episode that just ended, one per state of `trajectory`.
    fn positions(&self, trajectory: &Trajectory) -> Vec<[f64; 2]>;

    /// The robot metrics of the episode that just ended (`None` for mazes).
    fn robot_metrics(&self) -> Option<RobotEpisodeMetrics> {
        None
    }
}

impl TaskEnv for MazeEnv {
    #[inline]
    fn collided(&self) -> bool {
        self.last_event() == Some(Event::Bump)
    }

    fn reached(&self, terminated: bool) -> bool {
        // Reaching the target is the maze's only terminal event.
        terminated
    }

    fn positions(&self, trajectory: &Trajectory) -> Vec<[f64; 2]> {
        let width = self.maze().width();
        trajectory
            .states
            .iter()
            .map(|&state| {
                // maze sides are far below 2^52
                [(state % width) as f64, (state / width) as f64]
            })
            .collect()
    }
}

impl TaskEnv for WmrEnv {
    #[inline]
    fn collided(&self) -> bool {
        self.status() == EpisodeStatus::Hit
    }

    fn reached(&self, _terminated: bool) -> bool {
        self.status() == EpisodeStatus::Reached
    }

    fn positions(&self, _trajectory: &Trajectory) -> Vec<[f64; 2]> {
        // The environment records the robot's centre at the reset and after every step.
        self.path().iter().map(|point| [point.x, point.y]).collect()
    }

    fn robot_metrics(&self) -> Option<RobotEpisodeMetrics> {
        let metrics = self.metrics();
        Some(RobotEpisodeMetrics {
            time: metrics.time,
            average_reward: metrics.average_reward(),
            time_to_reach: metrics.time_to_reach,
            retention_time: metrics.retention_time,
        })
    }
}

/// An environment that counts the collisions of the current episode.
#[derive(Debug, Clone)]
pub(crate) struct Counting<E> {
    pub(crate) inner: E,
    collisions: u64,
}

impl<E: TaskEnv> Counting<E> {
    pub(crate) fn new(inner: E) -> Self {
        Self {
            inner,
            collisions: 0,
        }
    }

    /// Collisions since the last `reset`.
    pub(crate) fn collisions(&self) -> u64 {
        self.collisions
    }
}

impl<E: TaskEnv> Environment for Counting<E> {
    fn n_states(&self) -> usize {
        self.inner.n_states()
    }

    fn n_actions(&self) -> usize {
        self.inner.n_actions()
    }

    fn n_subtasks(&self) -> usize {
        self.inner.n_subtasks()
    }

    fn subtask_names(&self) -> Vec<String> {
        self.inner.subtask_names()
    }

    fn reset(&mut self, seed: Option<u64>) -> usize {
        self.collisions = 0;
        self.inner.reset(seed)
    }

    #[inline]
    fn step(&mut self, action: usize) -> Step {
        let step = self.inner.step(action);
        self.collisions += u64::from(self.inner.collided());
        step
    }

    #[inline]
    fn subtask_rewards(&self) -> &[f64] {
        self.inner.subtask_rewards()
    }

    fn state_features(&self, state: usize) -> Vec<u32> {
        self.inner.state_features(state)
    }
}
