//! Scenario files: parsing, defaults, and the layout errors a proptest cannot easily aim at.

use wmr_model::{
    CameraParams, DEFAULT_SCENARIO_TOML, ObstacleSpec, RewardParams, RobotParams, Scenario,
    ScenarioError, SensorParams, StateParams, TaskReward,
};

/// The smallest valid scenario: an arena, a start and a target (every other section defaulted).
pub(crate) const MINIMAL: &str = r#"
[arena]
width = 1.0
height = 0.6

[start]
x = 0.1
y = 0.3
heading = 0.0

[target]
x = 0.9
y = 0.3
"#;

#[test]
fn omitted_sections_take_the_documented_defaults() {
    let scenario = Scenario::from_toml_str(MINIMAL).unwrap();
    assert_eq!(scenario.control_period, 0.2);
    assert_eq!(scenario.step_cap, 500);
    assert_eq!(scenario.target.reach_radius, 0.05);
    assert!(scenario.obstacles.is_empty());
    assert_eq!(scenario.robot, RobotParams::default());
    assert_eq!(scenario.sensors, SensorParams::default());
    assert_eq!(scenario.camera, CameraParams::default());
    assert_eq!(scenario.state, StateParams::default());
    assert_eq!(scenario.reward, RewardParams::default());
    // The default scenario only spells out geometry, so it uses the same defaults.
    let default = Scenario::from_toml_str(DEFAULT_SCENARIO_TOML).unwrap();
    assert_eq!(default.camera, CameraParams::default());
    assert_eq!(default.reward, RewardParams::default());
}

#[test]
fn partial_sections_keep_the_other_defaults() {
    let text = format!(
        "{MINIMAL}\n[camera]\nhorizontal_fov = 1.2\n\n[reward]\nrad_penalty = \"facing\"\n"
    );
    let scenario = Scenario::from_toml_str(&text).unwrap();
    assert_eq!(scenario.camera.horizontal_fov, 1.2);
    assert_eq!(scenario.camera.height, CameraParams::default().height);
    assert_eq!(scenario.reward.rad_penalty, wmr_model::RadPenalty::Facing);
    assert_eq!(scenario.reward.k, 1.0);
}

fn error_of(text: &str) -> ScenarioError {
    Scenario::from_toml_str(text).expect_err("must be rejected")
}

#[test]
fn malformed_toml_and_unknown_fields_are_parse_errors_with_a_line() {
    let error = error_of("[arena\nwidth = 1");
    assert!(matches!(error, ScenarioError::Parse(_)));
    let error = error_of(&MINIMAL.replace("heading = 0.0", "heading = 0.0\nspeed = 3"));
    let message = error.to_string();
    assert!(message.contains("speed"), "{message}");
    assert!(message.contains("line"), "{message}");
    let error = error_of(&format!(
        "{MINIMAL}\n[[obstacles]]\nshape = \"triangle\"\nx = 0.5\ny = 0.3\n"
    ));
    assert!(error.to_string().contains("triangle"), "{error}");
}

fn with_obstacle(obstacle: &str) -> String {
    format!("{MINIMAL}\n[[obstacles]]\n{obstacle}\n")
}

#[test]
fn obstacles_outside_the_arena_are_rejected() {
    let error = error_of(&with_obstacle(
        "shape = \"circle\"\nx = 0.98\ny = 0.3\nradius = 0.05",
    ));
    assert!(
        matches!(error, ScenarioError::ObstacleOutsideArena { index: 0 }),
        "{error}"
    );
    let error = error_of(&with_obstacle(
        "shape = \"rectangle\"\nx = 0.5\ny = 0.58\nwidth = 0.1\nheight = 0.1",
    ));
    assert!(
        matches!(error, ScenarioError::ObstacleOutsideArena { index: 0 }),
        "{error}"
    );
    assert_eq!(
        error.to_string(),
        "`obstacles[0]` reaches outside the arena"
    );
}

#[test]
fn obstacles_on_the_start_or_the_target_are_rejected() {
    let error = error_of(&with_obstacle(
        "shape = \"circle\"\nx = 0.15\ny = 0.3\nradius = 0.02",
    ));
    assert!(
        matches!(
            error,
            ScenarioError::ObstacleOverlapsBody {
                index: 0,
                place: "start"
            }
        ),
        "{error}"
    );
    let error = error_of(&with_obstacle(
        "shape = \"rectangle\"\nx = 0.9\ny = 0.35\nwidth = 0.1\nheight = 0.06",
    ));
    assert!(
        matches!(
            error,
            ScenarioError::ObstacleOverlapsBody {
                index: 0,
                place: "target"
            }
        ),
        "{error}"
    );
    // Touching is fine: a body at the start exactly touching the cylinder.
    let touching = with_obstacle("shape = \"circle\"\nx = 0.1\ny = 0.4\nradius = 0.063");
    Scenario::from_toml_str(&touching).unwrap();
}

#[test]
fn bodies_in_the_walls_and_hidden_targets_are_rejected() {
    let error = error_of(&MINIMAL.replace("x = 0.1", "x = 0.02"));
    assert!(
        matches!(
            error,
            ScenarioError::BodyOutsideArena { place: "start", .. }
        ),
        "{error}"
    );
    let error = error_of(&MINIMAL.replace("x = 0.9", "x = 1.2"));
    assert!(
        matches!(
            error,
            ScenarioError::BodyOutsideArena {
                place: "target",
                ..
            }
        ),
        "{error}"
    );
    let error = error_of(&MINIMAL.replace("heading = 0.0", "heading = 1.0"));
    assert!(
        matches!(error, ScenarioError::TargetNotInViewAtStart),
        "{error}"
    );
    let error = error_of(&MINIMAL.replace("x = 0.9", "x = 0.13"));
    assert!(matches!(error, ScenarioError::StartAtTarget), "{error}");
}

#[test]
fn parameter_errors_name_the_field_and_value() {
    let error = error_of(&format!("{MINIMAL}\n[camera]\nhorizontal_fov = 3.2\n"));
    assert_eq!(
        error.to_string(),
        "`camera.horizontal_fov` must be in (0, π), got 3.2"
    );
    let error = error_of(&format!("{MINIMAL}\n[state]\nangle_bins = 0\n"));
    assert_eq!(
        error.to_string(),
        "`state.angle_bins` must be in [1, 1000], got 0"
    );
    let error = error_of(&format!(
        "{MINIMAL}\n[state]\ndistance_bins = 1000\nimage_bins = 1000\nangle_bins = 1000\n"
    ));
    assert!(
        matches!(error, ScenarioError::TooManyStates { .. }),
        "{error}"
    );
    let error = error_of(&format!(
        "{MINIMAL}\n[actions]\nforward = {{ left = 1.5, right = 1.0 }}\n"
    ));
    assert_eq!(
        error.to_string(),
        "`actions.forward.left` must be in [-1, 1], got 1.5"
    );
    let error = error_of(&format!("{MINIMAL}\n[camera]\noffset = 0.04\n"));
    assert!(error.to_string().starts_with("`camera.offset`"), "{error}");
    let error = error_of(&with_obstacle(
        "shape = \"rectangle\"\nx = 0.5\ny = 0.3\nwidth = -0.1\nheight = 0.1",
    ));
    assert_eq!(
        error.to_string(),
        "`obstacles[0].width` must be positive, got -0.1"
    );
    // TOML spells NaN `nan`.
    let error = error_of(&with_obstacle(
        "shape = \"circle\"\nx = 0.5\ny = nan\nradius = 0.1",
    ));
    assert_eq!(
        error.to_string(),
        "`obstacles[0].y` must be finite, got NaN"
    );
}

#[test]
fn obstacle_specs_build_their_shapes() {
    let scenario = Scenario::default_scenario();
    assert!(matches!(scenario.obstacles[0], ObstacleSpec::Circle { .. }));
    let world = scenario.world();
    assert_eq!(world.obstacles().len(), scenario.obstacles.len());
    let toml = scenario.to_toml_string().unwrap();
    assert!(toml.contains("shape = \"rectangle\""), "{toml}");
}

#[test]
fn the_task_reward_is_chosen_in_the_reward_section() {
    let sum = format!("{MINIMAL}\n[reward]\ntask = {{ kind = \"subtask_sum\" }}\n");
    let scenario = Scenario::from_toml_str(&sum).unwrap();
    assert_eq!(scenario.reward.task, TaskReward::SubtaskSum);
    let banded =
        format!("{MINIMAL}\n[reward]\ntask = {{ kind = \"progress\", min_progress = 0.005 }}\n");
    let scenario = Scenario::from_toml_str(&banded).unwrap();
    assert_eq!(
        scenario.reward.task,
        TaskReward::Progress {
            closer: 1.0,
            farther: -1.0,
            min_progress: 0.005
        }
    );
    // Round trip through TOML keeps the choice.
    let again = Scenario::from_toml_str(&scenario.to_toml_string().unwrap()).unwrap();
    assert_eq!(again.reward.task, scenario.reward.task);
    let negative =
        format!("{MINIMAL}\n[reward]\ntask = {{ kind = \"progress\", min_progress = -0.1 }}\n");
    let error = error_of(&negative);
    assert!(
        error.to_string().contains("reward.task.min_progress"),
        "{error}"
    );
    let unknown = format!("{MINIMAL}\n[reward]\ntask = {{ kind = \"progress\", closr = 2.0 }}\n");
    assert!(matches!(error_of(&unknown), ScenarioError::Parse(_)));
}

#[test]
fn end_penalty_repair_charges_every_sub_task_for_losing_the_target() {
    use dql::Environment;
    use wmr_model::{Action, EpisodeStatus, SubtaskRepairs, WmrEnv};
    let mut repaired = wmr_model::Scenario::default_scenario();
    repaired.reward.repairs = SubtaskRepairs {
        end_penalties: true,
        ..SubtaskRepairs::PAPER
    };
    let mut paper = WmrEnv::new(wmr_model::Scenario::default_scenario()).unwrap();
    let mut ended = WmrEnv::new(repaired).unwrap();
    paper.reset(Some(0));
    ended.reset(Some(0));
    // Turning on the spot's worth of left-forward steps swings the target out of view.
    for _ in 0..200 {
        paper.step_action(Action::LeftForward);
        ended.step_action(Action::LeftForward);
        if ended.status().is_done() {
            break;
        }
    }
    assert_eq!(ended.status(), EpisodeStatus::LostTarget);
    assert_eq!(paper.status(), EpisodeStatus::LostTarget);
    assert_eq!(ended.subtask_rewards(), &[-10.0; 3]);
    let literal = paper.subtask_rewards();
    assert_eq!(literal[2], -10.0);
    assert!(literal[0] > -10.0 && literal[1] > -10.0, "{literal:?}");
}
