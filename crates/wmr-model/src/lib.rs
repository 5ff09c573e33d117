//! A 2D wheeled mobile robot (e-puck class) and its obstacle-avoidance task, as a `dql`
//! environment.
//!
//! The paper's third experiment (Sec. III.A–B and VI.B, Table 2, Fig. 12) runs an e-puck-class
//! robot in Webots: differential drive, eight distance sensors, a camera, and a task split into
//! three sub-tasks with the rewards of Eq. 6, 7 and 8. This crate replaces Webots with a fast,
//! deterministic 2D model of that robot and task: [`WmrEnv`] implements
//! [`dql::Environment`] with 5 actions, `N_D · max(N_T, 1) · (N_O · N_A + 1)` states (1750 by
//! default; 250 with the paper's literal state, `N_T = 0`) and
//! three sub-task rewards, at about two million steps per second on one core.
//!
//! # Example
//!
//! ```
//! use dql::Environment;
//! use wmr_model::{EpisodeStatus, PlannerParams, RenderedPath, Scenario, WmrEnv, render_svg, shortest_plan};
//!
//! // The embedded default scenario, the analogue of Fig. 12.
//! let scenario = Scenario::default_scenario();
//! let mut env = WmrEnv::new(scenario.clone())?;
//! assert_eq!((env.n_states(), env.n_actions(), env.n_subtasks()), (1750, 5, 3));
//!
//! // The shortest route the planner finds, replayed through the environment.
//! let plan = shortest_plan(&scenario, &PlannerParams::default()).expect("solvable");
//! env.reset(Some(7));
//! for action in &plan.actions {
//!     let step = env.step(action.index());
//!     // Eq. 6 (reach faster), Eq. 7 (do not hit), Eq. 8 (+2: the target stays in view).
//!     let rewards = env.subtask_rewards();
//!     assert!(rewards[0] < 0.0 && rewards[2] == 2.0);
//!     // The task reward (TaskReward::Progress): +1 for every step that gets closer, +100 on
//!     // reaching; the shortest route never steps away.
//!     assert!(step.reward == 1.0 || step.reward == 100.0);
//! }
//! assert_eq!(env.status(), EpisodeStatus::Reached);
//! let metrics = env.metrics();
//! assert_eq!(metrics.task_return, 33.0 + 100.0);
//! println!(
//!     "reached in {:.1} s, average reward {:.2} per s, retention {:.1} s",
//!     metrics.time_to_reach.unwrap_or(f64::NAN),
//!     metrics.average_reward(),
//!     metrics.retention_time,
//! );
//!
//! // A picture of the run.
//! let svg = render_svg(&scenario, &[RenderedPath { points: env.path(), label: "planner" }]);
//! assert!(svg.starts_with("<svg"));
//! # Ok::<(), wmr_model::ScenarioError>(())
//! ```
//!
//! # What the paper's pieces became
//!
//! | paper | here |
//! |---|---|
//! | e-puck, differential drive | [`kinematics`]: exact arcs; [`RobotParams`] defaults are the Webots e-puck's |
//! | forward, backward, stop, left-forward, right-forward (Sec. III.B) | [`Action`], wheel speeds in [`ActionSet`] |
//! | 8 distance sensors (Table 2) | [`sensors`]: rays at the e-puck headings, proximity values, noise `C_noise` |
//! | RGB-D camera, feature point, Eq. 5 | [`camera`]: [`image_ratio`] is Eq. 5; [`Camera::observe`] |
//! | state `N_D × N_O × N_A` (Sec. III.B) | [`state`]: [`Discretiser`], plus the target's image position (`N_T` bins, not in the paper) |
//! | Eq. 6, 7, 8 and the task reward | [`reward`]: [`RewardParams`], [`TaskReward`] |
//! | average reward, time to reach, retention time (Sec. VI.B) | [`metrics`]: [`EpisodeMetrics`] |
//! | Fig. 12 | `scenarios/fig12.toml`, [`Scenario::default_scenario`] |
//! | "we find an optimal path through experiments" | [`planner`]: [`shortest_plan`], [`tabular_policy`] |
//!
//! # What is modelled and what is not
//!
//! Modelled: kinematics (wheel speeds are reached instantly and held for the control period,
//! integrated exactly along the arc); a round body colliding with walls, cylinders and
//! axis-aligned boxes (no rotated boxes), checked along the whole move so that fast steps
//! cannot tunnel; ray-cast sensors with a linear proximity model and bounded Gaussian-like
//! noise; a range camera reduced to its geometry (field of view, feature point, Eq. 5).
//!
//! Not modelled: dynamics (mass, acceleration limits, wheel slip, friction), the e-puck IR
//! sensors' non-linear, reflectance-dependent response, camera images and their noise,
//! occlusion (the target is a beacon seen over obstacles; the nearest obstacle in view is
//! reported even if another hides part of it), and anything 3D beyond the camera's height.
//!
//! # What a table learner can and cannot do here
//!
//! The paper's state (distance bin × obstacle image bin × angle bin, [`StateParams::paper`]) has
//! no bearing to the target, and losing the target from the 87° view ends the episode. A table
//! over those states must take the same action every time it meets a state, however far it has
//! turned: the planner's 34-step route asks for two different actions in the same state three
//! times, and the shortest tables [`tabular_policy`] finds take about 60 steps, with reversing.
//! With the default camera, tabular Q-learning (α = 0.1, γ = 0.95, ε = 0.1) did not reach the
//! target in any of 2000 episodes on 5 seeds, nor with only the first cylinder in the arena, and
//! hardly ever (2 %) with one cylinder 2 cm beside the straight route; in an empty arena, or
//! with a 150° view among the default obstacles, it does (23 % and 13 % of the last 500
//! episodes). The example `learnability` reproduces these numbers (it sets the paper's state).
//!
//! The default state therefore adds one feature the paper does not have: the target's
//! horizontal position in the camera image, Eq. 5 in its horizontal form
//! `δ_T = ½ (tan β_T / tan β₁ʰ + 1)`, in `N_T = 7` bins ([`DEFAULT_TARGET_BINS`],
//! [`CameraView::target_ratio`]). The camera must see the target anyway (Eq. 8). With it the
//! annealed double-Q competitors learn the default scenario: in the last 20 of 200 episodes over
//! 20 seeds ε-decreasing reached the target in 20 % and softmax in 25 % of the episodes (3 bins:
//! 5 % and 17 %; 9 bins: 16 % and 26 %; none without the feature); per seed the outcome is
//! bimodal. `state.target_bins = 0` restores the paper's state (docs/paper-notes.md §8.1).
//!
//! # Decisions the paper leaves open
//!
//! * **Control period** 0.2 s: a full-speed step covers 2.5 cm, a third of the body's width;
//!   the default route takes 34 steps, close to the paper's ~80-step grid episodes.
//! * **Actions**: forward `(1, 1)`, backward `(−1, −1)`, stop `(0, 0)`, left-forward
//!   `(0.5, 1)`, right-forward `(1, 0.5)` × the maximum wheel speed: turns of about 14° per
//!   step on a 7.8 cm radius.
//! * **Collisions**: a hit is reported when the body would overlap a wall or an obstacle during
//!   the step; the robot stops at the contact (never left overlapping) and the step is terminal.
//! * **Sensors**: value `C_i = 1 − distance / range` in `[0, 1]` plus `C_noise · ξ`, clamped;
//!   range 7 cm from the rim, `C_noise = 0.02`.
//! * **Eq. 5 is a side view**: δ is the feature point's height in the image, so it encodes the
//!   obstacle's distance, and the angle feature its bearing ([`DeltaAxis::Vertical`]; the
//!   top-view reading, which would duplicate the angle, is [`DeltaAxis::Horizontal`]). An
//!   obstacle closer than the image's bottom edge is still in view, with δ = 1.
//! * **Camera**: an 87° × 58° depth camera (`RealSense` D435 class) 5 cm up, 3 cm ahead of the
//!   centre, seeing obstacles up to 0.5 m away. The wide view leaves room to sidestep without
//!   losing the target; the e-puck's own 0.84 rad camera also solves the default scenario, with
//!   less slack.
//! * **State**: `N_D = 10` distance bins over 1 m, `N_O = 4` δ bins, `N_A = 6` angle bins over
//!   the field of view; with no obstacle in view, one state per distance bin: 250 states; times
//!   `N_T = 7` target image-position bins by default (1750 states).
//! * **Bounds**: scenarios that could not be run, solved or held in memory are refused with an
//!   error naming the field (see [`scenario`]'s bounds table; [`Scenario::check`] validates
//!   once into a [`CheckedScenario`], whose [`CheckedScenario::check_route`] refuses a target
//!   no route reaches and which [`WmrEnv::from_checked`] takes without failing).
//! * **Eq. 6/7 sum**: `Σ_{i=1}^{8} |i − p| · C_i / p` with `n` read as the sensor index `i`;
//!   `p = 4.5` weights the front sensors most. `k = 1` per metre, `f = 0.1` (Table 1).
//! * **`Rad`** is the unsigned angle to the obstacle in view (π when none). Literally, `−f·Rad`
//!   rewards facing obstacles; that is the default, and [`RadPenalty::Facing`] charges
//!   `−f·(π − Rad)` instead.
//! * **Task reward** (what the competitors learn from; the paper leaves it unstated for the
//!   robot): [`TaskReward::Progress`] by default, the mazes' Task I reward carried over: +1 when
//!   the step got closer to the target, −1 otherwise (`stop` included), and instead Eq. 7's
//!   −100 on a hit, +100 on reaching, Eq. 8's −10 on losing the target.
//!   [`TaskReward::SubtaskSum`] (`r₁ + r₂ + r₃ + 100 · [reached]`) is kept but pays about +1.2
//!   per step for merely surviving, so standing still is worth about as much as reaching (see
//!   [`reward`]).
//! * **Episodes** end on a hit, on reaching the target (centre within 5 cm), or on losing the
//!   target from the field of view, in that precedence; 500 steps truncate.
//! * **Retention time**: time in steps that end with an obstacle's feature point in view within
//!   15 cm of the camera while the distance to the target shrank by less than a quarter of a
//!   full-speed step.
//! * **Noise** comes from the environment's own `ChaCha8Rng`, seeded by `reset(Some(seed))`
//!   ([`DEFAULT_SEED`] for a fresh environment). Sensor noise only enters the rewards; the
//!   dynamics and the state are deterministic.
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
pub use env::{DEFAULT_SEED, EpisodeSnapshot, Observation, SnapshotError, WmrEnv};
pub use geometry::{Circle, Rect};
pub use kinematics::{
    FixedArc, RobotParams, Twist, WheelSpeeds, integrate_arc, integrate_arc_centre,
};
pub use metrics::{EpisodeMetrics, EpisodeStatus, MetricsParams};
pub use planner::{
    Plan, PlanError, PlannerParams, TabularPolicy, search, shortest_plan, tabular_policy,
};
pub use render::{FRAME_PIXELS_PER_METRE, RenderedPath, render_rgb, render_svg};
pub use reward::{
    RadPenalty, ReferenceEpisode, ReferenceValues, RewardInputs, RewardParams, SUBTASK_COUNT,
    SUBTASK_NAMES, SubtaskRepairs, TaskReward, TaskStep,
};
pub use scenario::{
    ArenaSpec, CheckedScenario, DEFAULT_SCENARIO_TOML, MAX_ARENA_SIDE, MAX_CONTROL_PERIOD,
    MAX_REWARD_MAGNITUDE, MAX_STEP_CAP, ObstacleSpec, Scenario, ScenarioError, StartSpec,
    TargetSpec,
};
pub use sensors::{DistanceSensors, SENSOR_COUNT, SensorParams};
pub use state::{DEFAULT_TARGET_BINS, Discretiser, MAX_BINS, MAX_STATES, StateBins, StateParams};
pub use world::{Motion, Obstacle, World};
