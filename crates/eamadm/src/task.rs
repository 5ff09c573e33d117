//! Loading a task config into an environment, and what the runner needs from environments
//! beyond [`dql::Environment`]: collisions, reaching the target, positions, robot metrics.

use std::path::Path;
use std::sync::Arc;

use dql::{Environment, Step, Trajectory};
use mazes::{Event, Maze, MazeEnv, Preset, SpecError};
use wmr_model::{
    DEFAULT_SCENARIO_TOML, EpisodeStatus, PlannerParams, Scenario, ScenarioError, WmrEnv,
};

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

impl TaskConfig {
    /// Checks the task config once and builds the task it names: generates a preset maze, reads
    /// a map file or parses an inline map, or builds the robot's scenario, applying the
    /// overrides (`step_cap`, …). This is the only place a task config is checked: the [`Task`]
    /// it returns holds a maze environment whose spec passed `mazes`' validation, or a robot
    /// environment built from a [`CheckedScenario`](wmr_model::CheckedScenario) (validated once, then its route planned and
    /// its environment built without validating again).
    ///
    /// A file the config names (`task.path`, `task.scenario`) is read once, here, and the task
    /// is built from those bytes, which [`Task::input_text`] keeps: whoever keys results by
    /// the file's content (a run store) hashes them rather than reading the file again, so a
    /// file that changes afterwards changes neither what this task computes nor the keys its
    /// results are stored under.
    ///
    /// Errors name the key the user wrote: an override's own key (`task.step_cap`,
    /// `task.control_period`, `task.reach_radius`, `task.distance_bins`, `task.target_bins`)
    /// when the value at fault is the override's, otherwise `task.scenario.<field>` for a field
    /// of the scenario file.
    ///
    /// # Errors
    /// [`ConfigError::Read`] for a file that cannot be read, [`ConfigError::Maze`] for a map
    /// that does not parse, [`ConfigError::Invalid`] for a value out of range,
    /// [`ConfigError::Scenario`] for any other scenario error (a target no route reaches).
    pub fn check(&self) -> Result<Task, ConfigError> {
        match self {
            Self::Maze {
                preset,
                rewards,
                step_cap,
            } => Task::from_maze(
                preset.maze(),
                rewards.unwrap_or(*preset),
                *step_cap,
                "task.preset",
            ),
            Self::MazeFile {
                path,
                rewards,
                step_cap,
            } => {
                let text = read_input_file(path, "task.path")?;
                let maze = Maze::parse(&text).map_err(|source| ConfigError::Maze {
                    field: "task.path".to_owned(),
                    source,
                })?;
                let mut task = Task::from_maze(maze, *rewards, *step_cap, "task.rewards")?;
                task.input = Some(Arc::from(text));
                Ok(task)
            }
            Self::MazeText {
                map,
                rewards,
                step_cap,
            } => {
                let maze = Maze::parse(map).map_err(|source| ConfigError::Maze {
                    field: "task.map".to_owned(),
                    source,
                })?;
                Task::from_maze(maze, *rewards, *step_cap, "task.rewards")
            }
            Self::Robot {
                scenario,
                step_cap,
                target_bins,
                control_period,
                reach_radius,
                distance_bins,
            } => {
                let (text, input) = if scenario == DEFAULT_SCENARIO {
                    (Arc::from(DEFAULT_SCENARIO_TOML), None)
                } else {
                    let text: Arc<str> =
                        Arc::from(read_input_file(Path::new(scenario), "task.scenario")?);
                    (text.clone(), Some(text))
                };
                // Parsed without validation: the scenario is validated once, below, with the
                // overrides applied (`Scenario::from_toml_str` would validate it twice).
                let mut scenario: Scenario =
                    toml::from_str(&text).map_err(|error| ConfigError::Scenario {
                        field: "task.scenario".to_owned(),
                        source: ScenarioError::Parse(error),
                    })?;
                let overrides = RobotOverrides {
                    step_cap: step_cap.is_some(),
                    target_bins: target_bins.is_some(),
                    control_period: control_period.is_some(),
                    reach_radius: reach_radius.is_some(),
                    distance_bins: distance_bins.is_some(),
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
                let checked = scenario.check().map_err(|error| overrides.blame(error))?;
                // The target must be reachable: a scenario whose target no route reaches is
                // refused here, not trained on in vain. The shortest route found is the
                // robot's analogue of a BFS optimum.
                let plan = checked
                    .check_route(&PlannerParams::default())
                    .map_err(|error| overrides.blame(error))?;
                Ok(Task {
                    kind: TaskKind::Robot(Box::new(WmrEnv::from_checked(checked))),
                    optimum_steps: Some(plan.actions.len() as u64),
                    input,
                })
            }
        }
    }
}

/// Which robot settings the task config overrides: an error about one of them is the
/// config's key, not the scenario's.
struct RobotOverrides {
    step_cap: bool,
    target_bins: bool,
    control_period: bool,
    reach_radius: bool,
    distance_bins: bool,
}

impl RobotOverrides {
    /// The config key to blame for a scenario error: the override's key when the scenario
    /// field at fault was overridden (for too many states, the bins the config set),
    /// otherwise `task.scenario.<field>`.
    fn key(&self, error: &ScenarioError) -> String {
        let field = error.field();
        let overridden = match field.as_deref() {
            Some("step_cap") if self.step_cap => Some("task.step_cap"),
            Some("control_period") if self.control_period => Some("task.control_period"),
            Some("target.reach_radius") if self.reach_radius => Some("task.reach_radius"),
            Some("state.distance_bins") if self.distance_bins => Some("task.distance_bins"),
            Some("state.target_bins") if self.target_bins => Some("task.target_bins"),
            Some("state") if self.distance_bins => Some("task.distance_bins"),
            Some("state") if self.target_bins => Some("task.target_bins"),
            _ => None,
        };
        match (overridden, field) {
            (Some(key), _) => key.to_owned(),
            (None, Some(field)) => format!("task.scenario.{field}"),
            (None, None) => "task.scenario".to_owned(),
        }
    }

    /// The scenario error as a config error naming [`key`](Self::key): a value out of range
    /// reads as any other config value out of range.
    fn blame(&self, error: ScenarioError) -> ConfigError {
        let field = self.key(&error);
        match error {
            ScenarioError::OutOfRange {
                value, expected, ..
            } => ConfigError::invalid(field, value, expected),
            ScenarioError::NotFinite { value, .. } => {
                ConfigError::invalid(field, value, "a finite number")
            }
            source => ConfigError::Scenario { field, source },
        }
    }
}

impl Task {
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
        // The preset's spec is valid: only the config's step cap can be at fault, and it is
        // blamed on its own key.
        let env = MazeEnv::new(maze, spec).map_err(|source| match source {
            SpecError::StepCapOutOfRange { value } => ConfigError::invalid(
                "task.step_cap",
                value,
                format!("a step cap in 1..={}", mazes::MAX_STEP_CAP),
            ),
            source => ConfigError::MazeSpec {
                field: field.to_owned(),
                source,
            },
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
    /// scenario's (either with the config's `task.step_cap` applied). `u32`, as everywhere a
    /// step cap is held (`task.step_cap`, the maze's spec, the scenario).
    #[must_use]
    pub fn step_cap(&self) -> u32 {
        match &self.kind {
            TaskKind::Maze(env) => env.spec().step_cap,
            TaskKind::Robot(env) => env.scenario().step_cap,
        }
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
