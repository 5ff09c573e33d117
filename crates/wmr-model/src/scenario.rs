//! Scenarios: the arena, start, target, obstacles and every parameter, in TOML, validated.
//!
//! A scenario file needs `[arena]`, `[start]`, `[target]` and usually some `[[obstacles]]`;
//! every other section (`[robot]`, `[actions]`, `[sensors]`, `[camera]`, `[state]`,
//! `[reward]`, `[metrics]`) and field may be left out and takes its documented default.
//! Lengths are in metres, angles in radians, times in seconds. Unknown fields are errors.
//!
//! [`Scenario::validate`] turns every mistake it can detect into a [`ScenarioError`] naming
//! the field (`obstacles[2].radius`, `camera.horizontal_fov`, …) and the offending value.
//! [`Scenario::check`] validates once and returns a [`CheckedScenario`]: what has passed, which
//! [`WmrEnv::from_checked`](crate::WmrEnv::from_checked) and [`CheckedScenario::check_route`]
//! take without validating again (the linfa pattern: checked once, then it cannot fail on the
//! same value).
//!
//! # Bounds
//!
//! Besides being finite and of the right sign, numbers are bounded so that every scenario that
//! passes validation can be run without a panic, an abort or a non-finite reward:
//!
//! | field | bound | why |
//! |---|---|---|
//! | `arena.width`, `arena.height` | ≤ [`MAX_ARENA_SIDE`] (20 m) | the planner's grid and the robot's scale |
//! | `step_cap` | ≤ [`MAX_STEP_CAP`] (100 000) | each episode keeps its path (16 bytes a step) |
//! | `control_period` | ≤ [`MAX_CONTROL_PERIOD`] (10 s) | one step stays one manoeuvre |
//! | `state.*_bins` | ≤ [`MAX_BINS`] | with the state count ≤ [`MAX_STATES`], the tables fit |
//! | `sensors.noise` | in `[0, 1]` | sensor values lie in `[0, 1]`; more noise is meaningless |
//! | `reward.*` constants | magnitude ≤ [`MAX_REWARD_MAGNITUDE`] (10⁶) | sums over an episode stay finite |
//! | `reward.p` | in `[0.01, 100]` | Eq. 6–7 divide by `p` |
//!
//! Solvability is a separate, costlier check: [`Scenario::check_route`] runs the planner and
//! refuses a target no route reaches (e.g. walled off).

use nalgebra::Point2;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::action::ActionSet;
use crate::camera::{Camera, CameraParams};
use crate::geometry::{Circle, Rect};
use crate::kinematics::RobotParams;
use crate::metrics::MetricsParams;
use crate::planner::{Plan, PlanError, PlannerParams, search};
use crate::reward::{RewardParams, SubtaskRepairs, TaskReward};
use crate::sensors::SensorParams;
use crate::state::{MAX_BINS, MAX_STATES, StateParams};
use crate::world::{Obstacle, World};

/// The embedded default scenario (the analogue of the paper's Fig. 12), as TOML text.
pub const DEFAULT_SCENARIO_TOML: &str = include_str!("../scenarios/fig12.toml");

/// Largest arena side (m).
pub const MAX_ARENA_SIDE: f64 = 20.0;

/// Largest `step_cap`.
pub const MAX_STEP_CAP: u32 = 100_000;

/// Largest control period (s).
pub const MAX_CONTROL_PERIOD: f64 = 10.0;

/// Largest magnitude of a reward constant.
pub const MAX_REWARD_MAGNITUDE: f64 = 1e6;

/// The walled arena `[0, width] × [0, height]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArenaSpec {
    /// Extent along x (m).
    pub width: f64,
    /// Extent along y (m).
    pub height: f64,
}

/// The robot's start pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartSpec {
    /// Centre x (m).
    pub x: f64,
    /// Centre y (m).
    pub y: f64,
    /// Heading (rad, 0 = +x, counter-clockwise positive).
    pub heading: f64,
}

/// The target: reached when the robot's centre comes within `reach_radius` of it. The target is
/// a marker the robot can drive over, not an obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetSpec {
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Reach radius (m). Default 0.05, a bit more than the body radius.
    #[serde(default = "default_reach_radius")]
    pub reach_radius: f64,
}

fn default_reach_radius() -> f64 {
    0.05
}

/// An obstacle as written in a scenario.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum ObstacleSpec {
    /// A cylinder.
    Circle {
        /// Centre x (m).
        x: f64,
        /// Centre y (m).
        y: f64,
        /// Radius (m).
        radius: f64,
    },
    /// An axis-aligned box.
    Rectangle {
        /// Centre x (m).
        x: f64,
        /// Centre y (m).
        y: f64,
        /// Extent along x (m).
        width: f64,
        /// Extent along y (m).
        height: f64,
    },
}

impl ObstacleSpec {
    /// The obstacle's geometry.
    #[must_use]
    pub fn obstacle(&self) -> Obstacle {
        match *self {
            Self::Circle { x, y, radius } => {
                Obstacle::Circle(Circle::new(Point2::new(x, y), radius))
            }
            Self::Rectangle {
                x,
                y,
                width,
                height,
            } => Obstacle::Rect(Rect::from_centre(Point2::new(x, y), width, height)),
        }
    }
}

fn default_control_period() -> f64 {
    0.2
}

fn default_step_cap() -> u32 {
    500
}

/// A complete task description. See the module docs for the file format.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// A short name for reports.
    #[serde(default)]
    pub name: String,
    /// Control period Δt (s): each action is held this long. Default 0.2.
    #[serde(default = "default_control_period")]
    pub control_period: f64,
    /// Episodes are truncated after this many steps. Default 500 (100 s).
    #[serde(default = "default_step_cap")]
    pub step_cap: u32,
    /// The arena.
    pub arena: ArenaSpec,
    /// Start pose.
    pub start: StartSpec,
    /// Target.
    pub target: TargetSpec,
    /// Obstacles.
    #[serde(default)]
    pub obstacles: Vec<ObstacleSpec>,
    /// Body and drive.
    #[serde(default)]
    pub robot: RobotParams,
    /// Wheel speeds of the five actions.
    #[serde(default)]
    pub actions: ActionSet,
    /// Distance sensors.
    #[serde(default)]
    pub sensors: SensorParams,
    /// Camera.
    #[serde(default)]
    pub camera: CameraParams,
    /// State discretisation.
    #[serde(default)]
    pub state: StateParams,
    /// Reward constants.
    #[serde(default)]
    pub reward: RewardParams,
    /// Metric definitions.
    #[serde(default)]
    pub metrics: MetricsParams,
}

/// Why a scenario was rejected.
#[derive(Debug, Error)]
pub enum ScenarioError {
    /// The text is not valid TOML for a scenario (the message has the line and column).
    #[error("invalid scenario TOML: {0}")]
    Parse(#[from] toml::de::Error),
    /// The scenario could not be written as TOML.
    #[error("cannot write the scenario as TOML: {0}")]
    Write(#[from] toml::ser::Error),
    /// A number is NaN or infinite.
    #[error("`{field}` must be finite, got {value}")]
    NotFinite {
        /// The field, e.g. `obstacles[1].radius`.
        field: String,
        /// Its value.
        value: f64,
    },
    /// A number lies outside its allowed range.
    #[error("`{field}` must be {expected}, got {value}")]
    OutOfRange {
        /// The field.
        field: String,
        /// Its value.
        value: f64,
        /// The allowed range, in words.
        expected: &'static str,
    },
    /// The bins make more than [`MAX_STATES`] states.
    #[error(
        "`state` bins make {count} states, more than {MAX_STATES}: lower `state.distance_bins`, \
         `state.image_bins`, `state.angle_bins` or `state.target_bins`"
    )]
    TooManyStates {
        /// `N_D · max(N_T, 1) · (N_O · N_A + 1)`.
        count: u128,
    },
    /// The planner finds no route from the start to the target (e.g. it is walled off).
    #[error(
        "`target` ({x}, {y}) cannot be reached from `start`: the planner found no route \
         without a hit or losing the target from view ({reason})"
    )]
    TargetUnreachable {
        /// Target x (m).
        x: f64,
        /// Target y (m).
        y: f64,
        /// Why the search ended.
        reason: PlanError,
    },
    /// An obstacle reaches beyond the walls.
    #[error("`obstacles[{index}]` reaches outside the arena")]
    ObstacleOutsideArena {
        /// Index in `obstacles`.
        index: usize,
    },
    /// The robot at the start pose or at the target would overlap a wall.
    #[error("the robot's body at `{place}` ({x}, {y}) overlaps the arena's walls")]
    BodyOutsideArena {
        /// `start` or `target`.
        place: &'static str,
        /// x (m).
        x: f64,
        /// y (m).
        y: f64,
    },
    /// An obstacle overlaps the robot's body at the start pose or at the target.
    #[error("`obstacles[{index}]` overlaps the robot's body at `{place}`")]
    ObstacleOverlapsBody {
        /// Index in `obstacles`.
        index: usize,
        /// `start` or `target`.
        place: &'static str,
    },
    /// The start is already within reach of the target.
    #[error("`start` is within `target.reach_radius` of the target")]
    StartAtTarget,
    /// The camera cannot see the target from the start pose: every episode would end at once.
    #[error("the target is outside the camera's view from `start` (check `start.heading`)")]
    TargetNotInViewAtStart,
}

impl ScenarioError {
    /// The scenario field the error is about, as written in the file (`step_cap`,
    /// `target.reach_radius`, `obstacles[2]`, `state` for too many states); `None` for TOML
    /// syntax and writing errors. A caller that set the field itself (an override) blames its
    /// own key for it.
    #[must_use]
    pub fn field(&self) -> Option<String> {
        match self {
            Self::Parse(_) | Self::Write(_) => None,
            Self::NotFinite { field, .. } | Self::OutOfRange { field, .. } => Some(field.clone()),
            Self::TooManyStates { .. } => Some("state".to_owned()),
            Self::TargetUnreachable { .. } => Some("target".to_owned()),
            Self::ObstacleOutsideArena { index } | Self::ObstacleOverlapsBody { index, .. } => {
                Some(format!("obstacles[{index}]"))
            }
            Self::BodyOutsideArena { place, .. } => Some((*place).to_owned()),
            Self::StartAtTarget => Some("target.reach_radius".to_owned()),
            Self::TargetNotInViewAtStart => Some("start.heading".to_owned()),
        }
    }
}

/// A scenario that passed [`Scenario::validate`], made only by [`Scenario::check`]: every
/// field lies within its bounds, so an environment of it cannot fail
/// ([`WmrEnv::from_checked`](crate::WmrEnv::from_checked)) and its route is searched without
/// validating again ([`check_route`](Self::check_route)). Read it through `Deref` (a
/// `&Scenario`); change it only through methods that keep it valid.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedScenario(Scenario);

impl std::ops::Deref for CheckedScenario {
    type Target = Scenario;

    fn deref(&self) -> &Scenario {
        &self.0
    }
}

impl CheckedScenario {
    /// The scenario, to change and check again.
    #[must_use]
    pub fn into_scenario(self) -> Scenario {
        self.0
    }

    /// The same scenario with these sub-task reward repairs. Still checked: the repairs are
    /// switches that no bound of [`Scenario::validate`] reads.
    #[must_use]
    pub fn with_repairs(mut self, repairs: SubtaskRepairs) -> Self {
        self.0.reward.repairs = repairs;
        self
    }

    /// Runs the planner ([`search`] with `params`) and returns the shortest route it finds: the
    /// load-time proof that the target can be reached at all. The scenario is not validated
    /// again.
    ///
    /// # Errors
    /// [`ScenarioError::TargetUnreachable`] when the search ends without reaching the target
    /// (no route exists, or none within the planner's budget).
    pub fn check_route(&self, params: &PlannerParams) -> Result<Plan, ScenarioError> {
        search(&self.0, params).map_err(|reason| ScenarioError::TargetUnreachable {
            x: self.0.target.x,
            y: self.0.target.y,
            reason,
        })
    }
}

/// Collects the checks of one scenario.
struct Checker;

impl Checker {
    fn finite(field: impl Into<String>, value: f64) -> Result<f64, ScenarioError> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(ScenarioError::NotFinite {
                field: field.into(),
                value,
            })
        }
    }

    fn require(
        field: impl Into<String>,
        value: f64,
        ok: bool,
        expected: &'static str,
    ) -> Result<(), ScenarioError> {
        if ok {
            Ok(())
        } else {
            Err(ScenarioError::OutOfRange {
                field: field.into(),
                value,
                expected,
            })
        }
    }

    fn positive(field: &str, value: f64) -> Result<(), ScenarioError> {
        let value = Self::finite(field, value)?;
        Self::require(field, value, value > 0.0, "positive")
    }

    fn non_negative(field: &str, value: f64) -> Result<(), ScenarioError> {
        let value = Self::finite(field, value)?;
        Self::require(field, value, value >= 0.0, "non-negative")
    }

    fn open_angle(field: &str, value: f64) -> Result<(), ScenarioError> {
        let value = Self::finite(field, value)?;
        Self::require(
            field,
            value,
            value > 0.0 && value < std::f64::consts::PI,
            "in (0, π)",
        )
    }

    fn bins(field: &str, value: u32, min: u32) -> Result<(), ScenarioError> {
        let expected = if min == 0 {
            "in [0, 1000]"
        } else {
            "in [1, 1000]"
        };
        Self::require(
            field,
            f64::from(value),
            (min..=MAX_BINS).contains(&value),
            expected,
        )
    }

    fn magnitude(field: &str, value: f64) -> Result<(), ScenarioError> {
        let value = Self::finite(field, value)?;
        Self::require(
            field,
            value,
            value.abs() <= MAX_REWARD_MAGNITUDE,
            "at most 1e6 in magnitude",
        )
    }

    fn at_most(
        field: &str,
        value: f64,
        max: f64,
        expected: &'static str,
    ) -> Result<(), ScenarioError> {
        Self::require(field, value, value <= max, expected)
    }
}

impl Scenario {
    /// The embedded default scenario (validated by the crate's tests).
    #[must_use]
    pub fn default_scenario() -> Self {
        Self::from_toml_str(DEFAULT_SCENARIO_TOML).expect("the embedded scenario is valid")
    }

    /// Parses and validates a scenario.
    ///
    /// # Errors
    /// [`ScenarioError::Parse`] for malformed TOML or unknown fields, any other variant for a
    /// scenario that fails [`validate`](Self::validate).
    pub fn from_toml_str(text: &str) -> Result<Self, ScenarioError> {
        let scenario: Self = toml::from_str(text)?;
        scenario.validate()?;
        Ok(scenario)
    }

    /// Writes the scenario as TOML (every field, defaults included).
    ///
    /// # Errors
    /// [`ScenarioError::Write`] if serialisation fails (it does not for finite numbers).
    pub fn to_toml_string(&self) -> Result<String, ScenarioError> {
        Ok(toml::to_string(self)?)
    }

    /// The walls and obstacles.
    #[must_use]
    pub fn world(&self) -> World {
        World::new(
            self.arena.width,
            self.arena.height,
            self.obstacles.iter().map(ObstacleSpec::obstacle).collect(),
        )
    }

    /// The target's position.
    #[must_use]
    pub fn target_point(&self) -> Point2<f64> {
        Point2::new(self.target.x, self.target.y)
    }

    /// The start pose.
    #[must_use]
    pub fn start_pose(&self) -> nalgebra::Isometry2<f64> {
        nalgebra::Isometry2::new(
            nalgebra::Vector2::new(self.start.x, self.start.y),
            self.start.heading,
        )
    }

    /// Validates a clone of the scenario and runs the planner on it
    /// ([`CheckedScenario::check_route`]); for a scenario already checked, call that instead.
    ///
    /// # Errors
    /// A validation error first if the scenario is invalid, then
    /// [`ScenarioError::TargetUnreachable`] when the search ends without reaching the target.
    pub fn check_route(&self, params: &PlannerParams) -> Result<Plan, ScenarioError> {
        self.clone().check()?.check_route(params)
    }

    /// Checks every field; the first problem found is returned.
    ///
    /// # Errors
    /// A [`ScenarioError`] naming the field and value at fault.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        self.validate_numbers()?;
        self.validate_layout()
    }

    /// Validates the scenario once and keeps it as a [`CheckedScenario`], which later layers
    /// take without validating again.
    ///
    /// # Errors
    /// As [`validate`](Self::validate).
    pub fn check(self) -> Result<CheckedScenario, ScenarioError> {
        self.validate()?;
        Ok(CheckedScenario(self))
    }

    fn validate_numbers(&self) -> Result<(), ScenarioError> {
        type C = Checker;
        C::positive("control_period", self.control_period)?;
        C::at_most(
            "control_period",
            self.control_period,
            MAX_CONTROL_PERIOD,
            "at most 10 s",
        )?;
        C::require(
            "step_cap",
            f64::from(self.step_cap),
            (1..=MAX_STEP_CAP).contains(&self.step_cap),
            "in [1, 100000]",
        )?;
        for (field, side) in [
            ("arena.width", self.arena.width),
            ("arena.height", self.arena.height),
        ] {
            C::positive(field, side)?;
            C::at_most(field, side, MAX_ARENA_SIDE, "at most 20 m")?;
        }
        C::finite("start.x", self.start.x)?;
        C::finite("start.y", self.start.y)?;
        C::finite("start.heading", self.start.heading)?;
        C::finite("target.x", self.target.x)?;
        C::finite("target.y", self.target.y)?;
        C::positive("target.reach_radius", self.target.reach_radius)?;
        for (i, spec) in self.obstacles.iter().enumerate() {
            match *spec {
                ObstacleSpec::Circle { x, y, radius } => {
                    C::finite(format!("obstacles[{i}].x"), x)?;
                    C::finite(format!("obstacles[{i}].y"), y)?;
                    C::positive(&format!("obstacles[{i}].radius"), radius)?;
                }
                ObstacleSpec::Rectangle {
                    x,
                    y,
                    width,
                    height,
                } => {
                    C::finite(format!("obstacles[{i}].x"), x)?;
                    C::finite(format!("obstacles[{i}].y"), y)?;
                    C::positive(&format!("obstacles[{i}].width"), width)?;
                    C::positive(&format!("obstacles[{i}].height"), height)?;
                }
            }
        }
        let robot = &self.robot;
        C::positive("robot.wheel_radius", robot.wheel_radius)?;
        C::positive("robot.axle_length", robot.axle_length)?;
        C::positive("robot.body_radius", robot.body_radius)?;
        C::positive("robot.max_wheel_speed", robot.max_wheel_speed)?;
        for (name, fractions) in self.actions.named() {
            for (side, value) in [("left", fractions.left), ("right", fractions.right)] {
                let field = format!("actions.{name}.{side}");
                let value = C::finite(field.clone(), value)?;
                C::require(field, value, (-1.0..=1.0).contains(&value), "in [-1, 1]")?;
            }
        }
        for (i, heading) in self.sensors.headings.iter().enumerate() {
            C::finite(format!("sensors.headings[{i}]"), *heading)?;
        }
        C::positive("sensors.range", self.sensors.range)?;
        C::non_negative("sensors.noise", self.sensors.noise)?;
        C::at_most("sensors.noise", self.sensors.noise, 1.0, "in [0, 1]")?;
        let camera = &self.camera;
        C::open_angle("camera.horizontal_fov", camera.horizontal_fov)?;
        C::open_angle("camera.vertical_fov", camera.vertical_fov)?;
        C::positive("camera.height", camera.height)?;
        C::non_negative("camera.offset", camera.offset)?;
        C::require(
            "camera.offset",
            camera.offset,
            camera.offset < robot.body_radius,
            "less than robot.body_radius (the camera is on the body)",
        )?;
        C::positive("camera.obstacle_range", camera.obstacle_range)?;
        let state = &self.state;
        C::bins("state.distance_bins", state.distance_bins, 1)?;
        C::positive("state.distance_max", state.distance_max)?;
        C::bins("state.image_bins", state.image_bins, 1)?;
        C::bins("state.angle_bins", state.angle_bins, 1)?;
        C::bins("state.target_bins", state.target_bins, 0)?;
        let count = state.state_count();
        if count > u128::from(MAX_STATES) {
            return Err(ScenarioError::TooManyStates { count });
        }
        let reward = &self.reward;
        C::magnitude("reward.k", reward.k)?;
        C::positive("reward.p", reward.p)?;
        C::require(
            "reward.p",
            reward.p,
            (0.01..=100.0).contains(&reward.p),
            "in [0.01, 100]",
        )?;
        C::magnitude("reward.f", reward.f)?;
        C::magnitude("reward.hit", reward.hit)?;
        C::magnitude("reward.target_kept", reward.target_kept)?;
        C::magnitude("reward.target_lost", reward.target_lost)?;
        C::magnitude("reward.goal_bonus", reward.goal_bonus)?;
        if let TaskReward::Progress {
            closer,
            farther,
            min_progress,
        } = reward.task
        {
            C::magnitude("reward.task.closer", closer)?;
            C::magnitude("reward.task.farther", farther)?;
            C::non_negative("reward.task.min_progress", min_progress)?;
        }
        C::non_negative(
            "metrics.retention_distance",
            self.metrics.retention_distance,
        )?;
        C::finite(
            "metrics.retention_progress",
            self.metrics.retention_progress,
        )?;
        Ok(())
    }

    fn validate_layout(&self) -> Result<(), ScenarioError> {
        let world = self.world();
        let arena = world.arena();
        for (index, obstacle) in world.obstacles().iter().enumerate() {
            let inside = match obstacle {
                Obstacle::Circle(c) => arena.inner_clearance(&c.centre) >= c.radius,
                Obstacle::Rect(r) => {
                    arena.inner_clearance(&r.min) >= 0.0 && arena.inner_clearance(&r.max) >= 0.0
                }
            };
            if !inside {
                return Err(ScenarioError::ObstacleOutsideArena { index });
            }
        }
        let radius = self.robot.body_radius;
        let target = self.target_point();
        let start = Point2::new(self.start.x, self.start.y);
        for (place, centre) in [("start", start), ("target", target)] {
            if arena.inner_clearance(&centre) < radius {
                return Err(ScenarioError::BodyOutsideArena {
                    place,
                    x: centre.x,
                    y: centre.y,
                });
            }
            if let Some(index) = world
                .obstacles()
                .iter()
                .position(|o| o.distance_to(&centre) < radius)
            {
                return Err(ScenarioError::ObstacleOverlapsBody { index, place });
            }
        }
        if (target - start).norm() <= self.target.reach_radius {
            return Err(ScenarioError::StartAtTarget);
        }
        if !Camera::new(self.camera).sees(&self.start_pose(), &target) {
            return Err(ScenarioError::TargetNotInViewAtStart);
        }
        Ok(())
    }
}
