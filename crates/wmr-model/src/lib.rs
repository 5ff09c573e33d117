//! A 2D wheeled mobile robot (e-puck class) and its obstacle-avoidance task.
//!
//! TODO docs
#![forbid(unsafe_code)]

pub mod action;
pub mod camera;
pub mod env;
pub mod geometry;
pub mod kinematics;
pub mod metrics;
pub mod planner;
pub mod render;
pub mod reward;
pub mod scenario;
pub mod sensors;
pub mod state;
pub mod world;

pub use action::{Action, ActionSet, WheelFractions};
pub use camera::{Camera, CameraParams, CameraView, DeltaAxis, ObstacleSighting, image_ratio};
pub use env::{DEFAULT_SEED, Observation, WmrEnv};
pub use geometry::{Circle, Rect};
pub use kinematics::{RobotParams, Twist, WheelSpeeds, integrate_arc};
pub use metrics::{EpisodeMetrics, MetricsParams, Outcome};
pub use planner::{Plan, PlannerParams, shortest_plan};
pub use render::{RenderedPath, render_svg};
pub use reward::{RadPenalty, RewardInputs, RewardParams, SUBTASK_COUNT, SUBTASK_NAMES};
pub use scenario::{
    ArenaSpec, DEFAULT_SCENARIO_TOML, ObstacleSpec, Scenario, ScenarioError, StartSpec, TargetSpec,
};
pub use sensors::{DistanceSensors, SENSOR_COUNT, SensorParams};
pub use state::{Discretiser, StateBins, StateParams};
pub use world::{Motion, Obstacle, World};
