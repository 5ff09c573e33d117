//! The obstacle-avoidance task as a `dql` environment.
//!
//! One step: hold the chosen action's wheel speeds for the control period (stopping at contact
//! on a hit), read the eight sensors (with noise), look through the camera, compute the three
//! sub-task rewards (Eq. 6–8) and the task reward, and discretise the new state.
//!
//! The episode *terminates* on a hit, on reaching the target (the robot's centre within the
//! reach radius), or on losing the target from the camera's view, with that precedence when
//! several happen on one step; it is *truncated* by the step cap.
//!
//! A step's move and what is sensed after it (everything but the noise and what depends on
//! it) are a pure function of the start pose and the action, and poses repeat bit for bit
//! from episode to episode (every episode starts from one pose, and the actions' arcs are
//! fixed), so the environment remembers steps by start pose and action (`StepMemo`). The memo
//! changes what a step costs, never what it returns.

use dql::{Environment, Step};
use nalgebra::{Isometry2, Point2};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::action::Action;
use crate::camera::{Camera, CameraView};
use crate::kinematics::FixedArc;
use crate::metrics::{EpisodeMetrics, EpisodeStatus};
use crate::reward::{RewardInputs, SUBTASK_COUNT, SUBTASK_NAMES, TaskStep};
use crate::scenario::{CheckedScenario, Scenario, ScenarioError};
use crate::sensors::{DistanceSensors, SENSOR_COUNT};
use crate::state::{Discretiser, StateBins};
use crate::world::{Motion, World};

/// Seed of a fresh environment's random stream (sensor noise), as if reset with `Some(0)`.
pub const DEFAULT_SEED: u64 = 0;

/// Everything the robot senses from one pose, without noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// Noise-free proximity values `C_1 … C_8` in `[0, 1]`.
    pub proximities: [f64; SENSOR_COUNT],
    /// What the camera sees.
    pub view: CameraView,
    /// Distance from the robot's centre to the target (m).
    pub target_distance: f64,
    /// Signed angle from the heading to the robot→target line (rad, in `(−π, π]`). Not part
    /// of the state; for scripted controllers and plots.
    pub target_bearing: f64,
    /// The state's bins.
    pub bins: StateBins,
    /// The state index.
    pub state: usize,
}

/// What `WmrEnv` senses from one pose before the noise, and the state it makes: a pure function
/// of the pose (the world, sensors, camera, target and bins are fixed), so it is kept to be
/// reused whenever the robot is at the very same pose again.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sensed {
    /// The pose's translation and rotation (`cos`, `sin`), bit for bit.
    pose_bits: [u64; 4],
    /// Noise-free proximities.
    proximities: [f64; SENSOR_COUNT],
    view: CameraView,
    /// From the robot's centre to the target.
    target_distance: f64,
    /// The state index.
    state: usize,
}

/// The bits of `pose`: two poses with the same bits sense the same.
fn pose_bits(pose: &Isometry2<f64>) -> [u64; 4] {
    let rotation = pose.rotation.complex();
    [
        pose.translation.vector.x.to_bits(),
        pose.translation.vector.y.to_bits(),
        rotation.re.to_bits(),
        rotation.im.to_bits(),
    ]
}

/// One step remembered: the move of `action` from the pose whose bits are `from`, and what is
/// sensed where it ends.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RememberedStep {
    from: [u64; 4],
    action: Action,
    motion: Motion,
    sensed: Sensed,
}

/// Steps remembered by their start pose and action, one per slot, a newer one replacing an
/// older in its slot.
///
/// A step's move and what is sensed after it (everything but the noise and what depends on
/// it) are a pure function of the start pose and the action, and poses repeat exactly: every
/// episode starts from the same pose, and the few arcs of the five actions lead from it to
/// the same poses, bit for bit, in every episode that takes the same actions (a learner's
/// greedy choices, `stop`). A remembered step is the value it would be computed as, so what
/// the memo holds changes the cost of a step, never its result.
#[derive(Clone)]
struct StepMemo {
    slots: Vec<Option<RememberedStep>>,
}

impl std::fmt::Debug for StepMemo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let filled = self.slots.iter().filter(|slot| slot.is_some()).count();
        f.debug_struct("StepMemo")
            .field("slots", &self.slots.len())
            .field("filled", &filled)
            .finish()
    }
}

impl StepMemo {
    /// log₂ of the slot count: 1024 slots of 280 bytes, 280 KB an environment. 4096 slots
    /// timed the same on the ratios bench's random walk and on the robot tasks (within the
    /// noise), and cost 1.1 MB an environment, which a vector environment of many robots
    /// multiplies.
    const SLOT_BITS: u32 = 10;

    fn new() -> Self {
        Self {
            slots: vec![None; 1 << Self::SLOT_BITS],
        }
    }

    /// The slot of the step of `action` from the pose whose bits are `from`.
    fn slot(from: &[u64; 4], action: Action) -> usize {
        let mixed = from[0]
            ^ from[1].rotate_left(16)
            ^ from[2].rotate_left(32)
            ^ from[3].rotate_left(48)
            ^ action.index() as u64;
        // Fibonacci hashing: the top bits of the product depend on every bit of `mixed`.
        (mixed.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - Self::SLOT_BITS)) as usize
    }
}

/// What the sensors and the camera measure from `pose` before the noise, the distance to
/// `target` and the state they make.
fn measure(
    world: &World,
    sensors: &DistanceSensors,
    camera: &Camera,
    discretiser: &Discretiser,
    scenario: &Scenario,
    target: &Point2<f64>,
    pose: &Isometry2<f64>,
) -> Sensed {
    let view = camera.observe(world, pose, target);
    let target_distance = (target - Point2::from(pose.translation.vector)).norm();
    Sensed {
        pose_bits: pose_bits(pose),
        proximities: sensors.proximities(world, pose, scenario.robot.body_radius),
        state: discretiser.index(discretiser.bins(
            target_distance,
            view.target_ratio,
            view.obstacle.as_ref(),
        )),
        view,
        target_distance,
    }
}

/// The robot among its obstacles, as a discrete episodic task with three sub-tasks.
#[derive(Debug, Clone)]
pub struct WmrEnv {
    scenario: CheckedScenario,
    world: World,
    sensors: DistanceSensors,
    camera: Camera,
    discretiser: Discretiser,
    /// Each action's arc over one control period.
    arcs: [FixedArc; Action::COUNT],
    /// The clearance of the body at `pose`, when known (from the last move).
    clearance: Option<f64>,
    /// What is sensed at `pose`, before the noise.
    sensed: Sensed,
    /// What is sensed at the start pose, before the noise: every episode starts there.
    start_sensed: Sensed,
    /// The body's clearance at the start pose.
    start_clearance: f64,
    /// Steps already computed, by start pose and action.
    memo: StepMemo,
    target: Point2<f64>,
    retention_progress: f64,
    rng: ChaCha8Rng,
    pose: Isometry2<f64>,
    state: usize,
    sensor_values: [f64; SENSOR_COUNT],
    subtask_rewards: [f64; SUBTASK_COUNT],
    metrics: EpisodeMetrics,
    path: Vec<Point2<f64>>,
}

/// Where an episode of a [`WmrEnv`] stands, with the sensor-noise stream: what
/// [`WmrEnv::snapshot`] saves and [`WmrEnv::restore`] puts back, so that a saved environment
/// (a pickled Python env, a checkpoint) continues bit for bit as the original would. Opaque
/// apart from serde: the scenario is not in it (restore into an environment of the same
/// scenario).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EpisodeSnapshot {
    rng: ChaCha8Rng,
    pose: Isometry2<f64>,
    clearance: Option<f64>,
    state: usize,
    #[serde(alias = "readings")]
    sensor_values: [f64; SENSOR_COUNT],
    subtask_rewards: [f64; SUBTASK_COUNT],
    metrics: EpisodeMetrics,
    path: Vec<Point2<f64>>,
}

/// A snapshot that cannot be restored ([`WmrEnv::restore`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SnapshotError {
    /// The state index is not one of this environment's.
    #[error("state {state} is not below the environment's {n_states} states")]
    State {
        /// The snapshot's state.
        state: usize,
        /// The environment's state count.
        n_states: usize,
    },
    /// A number of the snapshot is NaN or infinite.
    #[error("`{field}` is not finite")]
    NotFinite {
        /// Which part of the snapshot.
        field: &'static str,
    },
    /// The path does not end at the pose, or is empty.
    #[error("the path must be non-empty and end at the robot's position")]
    Path,
}

impl Default for WmrEnv {
    /// The environment of the embedded default scenario.
    fn default() -> Self {
        Self::new(Scenario::default_scenario()).expect("the embedded scenario is valid")
    }
}

impl WmrEnv {
    /// An environment for `scenario`, validated first, reset with [`DEFAULT_SEED`].
    ///
    /// # Errors
    /// The scenario's first validation error.
    pub fn new(scenario: Scenario) -> Result<Self, ScenarioError> {
        Ok(Self::from_checked(scenario.check()?))
    }

    /// An environment for a scenario already checked ([`Scenario::check`]), reset with
    /// [`DEFAULT_SEED`]; it cannot fail, and does not validate again.
    #[must_use]
    pub fn from_checked(scenario: CheckedScenario) -> Self {
        let world = scenario.world();
        let robot = scenario.robot;
        let twists = Action::ALL.map(|action| {
            robot.twist(scenario.actions.wheel_speeds(action, robot.max_wheel_speed))
        });
        let arcs = twists.map(|twist| FixedArc::new(twist, scenario.control_period));
        let camera = Camera::new(scenario.camera);
        let retention_progress = scenario.metrics.retention_progress
            * robot.max_linear_speed()
            * scenario.control_period;
        let sensors = DistanceSensors::new(scenario.sensors);
        let target = scenario.target_point();
        let start = scenario.start_pose();
        let discretiser = Discretiser::new(scenario.state, &scenario.camera);
        let start_sensed = measure(
            &world,
            &sensors,
            &camera,
            &discretiser,
            &scenario,
            &target,
            &start,
        );
        let start_clearance =
            world.clearance(&Point2::from(start.translation.vector), robot.body_radius);
        let mut env = Self {
            world,
            sensors,
            camera,
            discretiser,
            arcs,
            clearance: None,
            sensed: start_sensed,
            start_sensed,
            start_clearance,
            memo: StepMemo::new(),
            target,
            retention_progress,
            rng: ChaCha8Rng::seed_from_u64(DEFAULT_SEED),
            pose: start,
            state: 0,
            sensor_values: [0.0; SENSOR_COUNT],
            subtask_rewards: [0.0; SUBTASK_COUNT],
            metrics: EpisodeMetrics::default(),
            path: Vec::with_capacity(scenario.step_cap as usize + 1),
            scenario,
        };
        env.reset(Some(DEFAULT_SEED));
        env
    }

    /// The scenario.
    #[must_use]
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The scenario as checked when the environment was built: another environment of it
    /// (changed only in ways that keep it checked, [`CheckedScenario::with_repairs`]) is built
    /// without validating again.
    #[must_use]
    pub fn checked_scenario(&self) -> &CheckedScenario {
        &self.scenario
    }

    /// Walls and obstacles.
    #[must_use]
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The distance sensors.
    #[must_use]
    pub fn sensors(&self) -> &DistanceSensors {
        &self.sensors
    }

    /// The state discretiser.
    #[must_use]
    pub fn discretiser(&self) -> &Discretiser {
        &self.discretiser
    }

    /// The robot's current pose.
    #[must_use]
    pub fn pose(&self) -> &Isometry2<f64> {
        &self.pose
    }

    /// The current state index.
    #[must_use]
    pub fn state(&self) -> usize {
        self.state
    }

    /// The last (noisy) sensor values.
    #[must_use]
    pub fn sensor_values(&self) -> &[f64; SENSOR_COUNT] {
        &self.sensor_values
    }

    /// What the camera saw last.
    #[must_use]
    pub fn camera_view(&self) -> &CameraView {
        &self.sensed.view
    }

    /// The current episode's metrics.
    #[must_use]
    pub fn metrics(&self) -> &EpisodeMetrics {
        &self.metrics
    }

    /// How the current episode stands.
    #[must_use]
    pub fn status(&self) -> EpisodeStatus {
        self.metrics.status
    }

    /// Positions of the robot's centre this episode: the start, then one per step.
    #[must_use]
    pub fn path(&self) -> &[Point2<f64>] {
        &self.path
    }

    /// The current episode and noise stream, to [`restore`](Self::restore) later.
    #[must_use]
    pub fn snapshot(&self) -> EpisodeSnapshot {
        EpisodeSnapshot {
            rng: self.rng.clone(),
            pose: self.pose,
            clearance: self.clearance,
            state: self.state,
            sensor_values: self.sensor_values,
            subtask_rewards: self.subtask_rewards,
            metrics: self.metrics,
            path: self.path.clone(),
        }
    }

    /// Puts back an episode saved by [`snapshot`](Self::snapshot) on an environment of the
    /// same scenario: every later step, sensor value and metric equals the original's, bit for bit
    /// (what the robot senses at the pose is measured again; it is a pure function of the pose).
    ///
    /// # Errors
    /// [`SnapshotError`] (and nothing changes) when the snapshot cannot belong to this
    /// environment: a state out of range, a number not finite, a path not ending at the pose.
    pub fn restore(&mut self, snapshot: &EpisodeSnapshot) -> Result<(), SnapshotError> {
        let n_states = self.discretiser.n_states();
        if snapshot.state >= n_states {
            return Err(SnapshotError::State {
                state: snapshot.state,
                n_states,
            });
        }
        let pose = &snapshot.pose;
        let finite = |field, values: &[f64]| {
            if values.iter().all(|v| v.is_finite()) {
                Ok(())
            } else {
                Err(SnapshotError::NotFinite { field })
            }
        };
        let rotation = pose.rotation.complex();
        finite(
            "pose",
            &[
                pose.translation.vector.x,
                pose.translation.vector.y,
                rotation.re,
                rotation.im,
            ],
        )?;
        finite(
            "clearance",
            &snapshot.clearance.into_iter().collect::<Vec<_>>(),
        )?;
        finite("sensor_values", &snapshot.sensor_values)?;
        finite("subtask_rewards", &snapshot.subtask_rewards)?;
        let m = &snapshot.metrics;
        finite(
            "metrics",
            &[m.time, m.task_return, m.retention_time, m.path_length],
        )?;
        finite("metrics.subtask_returns", &m.subtask_returns)?;
        if snapshot.path.last() != Some(&Point2::from(pose.translation.vector))
            || snapshot
                .path
                .iter()
                .any(|point| !(point.x.is_finite() && point.y.is_finite()))
        {
            return Err(SnapshotError::Path);
        }
        let sensed = if pose_bits(pose) == self.start_sensed.pose_bits {
            self.start_sensed
        } else {
            self.measure(pose)
        };
        self.sensed = sensed;
        self.rng = snapshot.rng.clone();
        self.pose = snapshot.pose;
        self.clearance = snapshot.clearance;
        self.state = snapshot.state;
        self.sensor_values = snapshot.sensor_values;
        self.subtask_rewards = snapshot.subtask_rewards;
        self.metrics = snapshot.metrics;
        self.path.clone_from(&snapshot.path);
        Ok(())
    }

    /// What the robot would sense at `pose`, without noise (does not move the robot).
    #[must_use]
    pub fn observe(&self, pose: &Isometry2<f64>) -> Observation {
        let proximities =
            self.sensors
                .proximities(&self.world, pose, self.scenario.robot.body_radius);
        let view = self.camera.observe(&self.world, pose, &self.target);
        let to_target =
            pose.rotation.inverse() * (self.target - Point2::from(pose.translation.vector));
        let target_distance = to_target.norm();
        let bins =
            self.discretiser
                .bins(target_distance, view.target_ratio, view.obstacle.as_ref());
        Observation {
            proximities,
            view,
            target_distance,
            target_bearing: to_target.y.atan2(to_target.x),
            bins,
            state: self.discretiser.index(bins),
        }
    }

    /// What is sensed at `pose` before the noise.
    fn measure(&self, pose: &Isometry2<f64>) -> Sensed {
        measure(
            &self.world,
            &self.sensors,
            &self.camera,
            &self.discretiser,
            &self.scenario,
            &self.target,
            pose,
        )
    }

    /// Moves by `action`'s arc from the current pose and senses where the move ends (before
    /// the noise), or recalls both from the memo; sets the pose, its clearance and `sensed`.
    fn move_and_sense(&mut self, action: Action) -> Motion {
        let from = pose_bits(&self.pose);
        let slot = StepMemo::slot(&from, action);
        let motion = if let Some(step) = &self.memo.slots[slot]
            && step.from == from
            && step.action == action
        {
            self.sensed = step.sensed;
            step.motion
        } else {
            let motion = self.world.move_disc_along(
                &self.pose,
                &self.arcs[action.index()],
                self.scenario.robot.body_radius,
                self.clearance,
            );
            let to = pose_bits(&motion.pose);
            // A `stop` (or a move blocked at its start) senses from the same pose again.
            if to != self.sensed.pose_bits {
                self.sensed = if to == self.start_sensed.pose_bits {
                    self.start_sensed
                } else {
                    self.measure(&motion.pose)
                };
            }
            self.memo.slots[slot] = Some(RememberedStep {
                from,
                action,
                motion,
                sensed: self.sensed,
            });
            motion
        };
        self.pose = motion.pose;
        self.clearance = motion.clearance;
        motion
    }

    /// Reads the sensors (adding the noise to `sensed`) and sets the state.
    fn sense(&mut self) -> f64 {
        self.sensor_values = self.sensed.proximities;
        self.sensors
            .add_noise(&mut self.sensor_values, &mut self.rng);
        self.state = self.sensed.state;
        self.sensed.target_distance
    }

    /// Applies `action` (see [`Environment::step`]).
    pub fn step_action(&mut self, action: Action) -> Step {
        let status = self.metrics.status;
        if status.is_done() {
            self.subtask_rewards = [0.0; SUBTASK_COUNT];
            return Step {
                next_state: self.state,
                reward: 0.0,
                terminated: status.is_terminal(),
                truncated: status == EpisodeStatus::Truncated,
            };
        }
        let dt = self.scenario.control_period;
        // `sense` measured it at this pose.
        let before = self.sensed.target_distance;
        let from = Point2::from(self.pose.translation.vector);
        let motion = self.move_and_sense(action);
        let to = Point2::from(self.pose.translation.vector);
        self.path.push(to);
        let distance = self.sense();

        let reached = distance <= self.scenario.target.reach_radius;
        let lost = !reached && !self.sensed.view.target_in_view;
        let reward = &self.scenario.reward;
        let inputs = RewardInputs {
            target_distance: distance,
            sensor_values: &self.sensor_values,
            noise: self.scenario.sensors.noise,
            rad: self
                .sensed
                .view
                .obstacle
                .map_or(std::f64::consts::PI, |seen| seen.angle.abs()),
            hit: motion.hit,
            lost,
            reached: reached && !motion.hit,
        };
        self.subtask_rewards = reward.subtasks(&inputs);
        let reached = reached && !motion.hit;
        let task_reward = reward.task(
            &self.subtask_rewards,
            &TaskStep {
                progress: before - distance,
                hit: motion.hit,
                reached,
                lost,
            },
        );

        let m = &mut self.metrics;
        m.steps += 1;
        // step counts stay far below 2⁵³
        let time = m.steps as f64 * dt;
        m.time = time;
        m.task_return += task_reward;
        for (sum, r) in m.subtask_returns.iter_mut().zip(self.subtask_rewards) {
            *sum += r;
        }
        m.path_length += (to - from).norm();
        let obstacle_in_front = self
            .sensed
            .view
            .obstacle
            .is_some_and(|seen| seen.distance <= self.scenario.metrics.retention_distance);
        if obstacle_in_front && before - distance < self.retention_progress {
            m.retention_steps += 1;
            let retention = m.retention_steps as f64 * dt;
            m.retention_time = retention;
        }
        m.status = if motion.hit {
            EpisodeStatus::Hit
        } else if reached {
            m.time_to_reach = Some(time);
            EpisodeStatus::Reached
        } else if lost {
            EpisodeStatus::LostTarget
        } else if m.steps >= self.scenario.step_cap as usize {
            EpisodeStatus::Truncated
        } else {
            EpisodeStatus::Running
        };
        Step {
            next_state: self.state,
            reward: task_reward,
            terminated: m.status.is_terminal(),
            truncated: m.status == EpisodeStatus::Truncated,
        }
    }
}

impl Environment for WmrEnv {
    fn n_states(&self) -> usize {
        self.discretiser.n_states()
    }

    fn n_actions(&self) -> usize {
        Action::COUNT
    }

    fn n_subtasks(&self) -> usize {
        SUBTASK_COUNT
    }

    fn subtask_names(&self) -> Vec<String> {
        SUBTASK_NAMES.iter().map(|&name| name.to_owned()).collect()
    }

    /// Puts the robot at the start pose; `Some(seed)` re-seeds the sensor noise.
    fn reset(&mut self, seed: Option<u64>) -> usize {
        if let Some(seed) = seed {
            self.rng = ChaCha8Rng::seed_from_u64(seed);
        }
        self.pose = self.scenario.start_pose();
        self.clearance = Some(self.start_clearance);
        self.metrics = EpisodeMetrics::default();
        self.subtask_rewards = [0.0; SUBTASK_COUNT];
        self.path.clear();
        self.path.push(Point2::from(self.pose.translation.vector));
        self.sensed = self.start_sensed;
        self.sense();
        self.state
    }

    /// Applies action `action` (`0..5`, in [`Action::ALL`] order).
    ///
    /// # Panics
    /// When `action` is not below 5 (a caller bug).
    fn step(&mut self, action: usize) -> Step {
        self.step_action(Action::ALL[action])
    }

    fn subtask_rewards(&self) -> &[f64] {
        &self.subtask_rewards
    }

    fn state_features(&self, state: usize) -> Vec<u32> {
        self.discretiser.features(state)
    }
}
