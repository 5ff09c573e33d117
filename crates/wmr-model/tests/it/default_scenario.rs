//! The embedded default scenario is valid, sized as documented, and solvable: by the planner,
//! by a scripted controller, and by a deterministic table over the discrete state.

use dql::Environment;
use nalgebra::Vector2;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wmr_model::{
    Action, EpisodeStatus, PlannerParams, Scenario, StateParams, TaskReward, WmrEnv, shortest_plan,
    tabular_policy,
};

#[test]
fn default_scenario_is_valid_and_sized_as_documented() {
    let scenario = Scenario::default_scenario();
    scenario.validate().unwrap();
    assert_eq!(scenario.obstacles.len(), 5);
    let env = WmrEnv::default();
    // 10 distance × 7 target bins × (4 × 6 obstacle bins + "none in view").
    assert_eq!(env.n_states(), 1750);
    let mut paper = scenario.clone();
    paper.state = StateParams::paper();
    assert_eq!(WmrEnv::new(paper).unwrap().n_states(), 250);
    assert_eq!(env.n_actions(), 5);
    assert_eq!(env.n_subtasks(), 3);
    assert_eq!(
        env.subtask_names(),
        [
            "reach_target_faster",
            "avoid_obstacles",
            "keep_target_in_view"
        ]
    );
    // The start sees the target and no obstacle is closer than the planner's route needs.
    assert!(env.camera_view().target_in_view);
    assert_eq!(env.status(), EpisodeStatus::Running);
}

/// Replays `actions` from a fresh episode and returns the final outcome, checking the
/// episode does not end early.
fn replay(env: &mut WmrEnv, actions: &[Action]) -> EpisodeStatus {
    env.reset(Some(11));
    for (i, action) in actions.iter().enumerate() {
        let step = env.step(action.index());
        assert!(step.reward.is_finite());
        let last = i + 1 == actions.len();
        assert_eq!(step.done(), last, "step {i}: {:?}", env.status());
    }
    env.status()
}

#[test]
fn the_planner_route_reaches_the_target_in_the_environment() {
    let scenario = Scenario::default_scenario();
    let plan = shortest_plan(&scenario, &PlannerParams::default()).expect("solvable");
    assert_eq!(plan.actions.len(), 34);
    let mut env = WmrEnv::default();
    assert_eq!(replay(&mut env, &plan.actions), EpisodeStatus::Reached);
    let metrics = env.metrics();
    assert_eq!(metrics.steps, 34);
    assert!((metrics.time_to_reach.expect("reached") - 34.0 * 0.2).abs() < 1e-9);
    // The environment's poses are the planner's poses.
    for (pose, planned) in env.path().iter().zip(&plan.poses) {
        assert!((pose.coords - planned.translation.vector).norm() < 1e-12);
    }
    assert!(metrics.average_reward() > 0.0);
}

#[test]
fn a_scripted_waypoint_controller_reaches_the_target() {
    // Pass the first cylinder above, go through the gate, pass the last cylinder above. Steer
    // towards the next waypoint whenever it is more than 10° off the heading.
    let waypoints = [
        Vector2::new(0.24, 0.57),
        Vector2::new(0.36, 0.595),
        Vector2::new(0.47, 0.535),
        Vector2::new(0.60, 0.51),
        Vector2::new(0.74, 0.55),
        Vector2::new(0.90, 0.50),
    ];
    let tolerance = 10.0_f64.to_radians();
    let mut env = WmrEnv::default();
    env.reset(Some(3));
    let mut next = 0;
    loop {
        let position = env.pose().translation.vector;
        while next + 1 < waypoints.len()
            && ((waypoints[next] - position).norm() < 0.03 || waypoints[next].x < position.x)
        {
            next += 1;
        }
        let local = env.pose().rotation.inverse() * (waypoints[next] - position);
        let bearing = local.y.atan2(local.x);
        let action = if bearing > tolerance {
            Action::LeftForward
        } else if bearing < -tolerance {
            Action::RightForward
        } else {
            Action::Forward
        };
        if env.step(action.index()).done() {
            break;
        }
    }
    assert_eq!(env.status(), EpisodeStatus::Reached);
    assert!(env.metrics().steps <= 40, "{}", env.metrics().steps);
}

#[test]
fn a_deterministic_table_over_the_discrete_state_solves_the_task() {
    // Over the paper's literal state (no target feature), the harder case.
    let mut scenario = Scenario::default_scenario();
    scenario.state = StateParams::paper();
    let table = tabular_policy(&scenario, 200, 1_000_000).expect("a table exists");
    let mut env = WmrEnv::new(scenario).unwrap();
    env.reset(Some(5));
    let mut steps = 0;
    loop {
        let action = table.actions[env.state()].expect("the run only visits tabled states");
        steps += 1;
        if env.step(action.index()).done() {
            break;
        }
    }
    assert_eq!(env.status(), EpisodeStatus::Reached);
    assert_eq!(steps, table.plan.actions.len());
}

#[test]
fn random_policy_episodes_are_short_and_well_formed() {
    let mut env = WmrEnv::default();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut total_steps = 0;
    for episode in 0..200 {
        let state = env.reset(Some(episode));
        assert!(state < env.n_states());
        loop {
            let step = env.step(rng.random_range(0..5));
            assert!(step.next_state < env.n_states());
            assert!(step.reward.is_finite());
            assert!(env.subtask_rewards().iter().all(|r| r.is_finite()));
            assert!(!(step.terminated && step.truncated));
            if step.done() {
                break;
            }
        }
        assert!(env.status().is_done());
        total_steps += env.metrics().steps;
        // Stepping a finished episode is harmless.
        let after = env.step(0);
        assert_eq!(after.reward, 0.0);
        assert!(after.done());
    }
    // A random walk loses the target or hits something within a few dozen steps.
    let mean = total_steps as f64 / 200.0;
    assert!((5.0..60.0).contains(&mean), "{mean}");
}

#[test]
fn resets_with_the_same_seed_repeat_exactly() {
    let mut env = WmrEnv::default();
    let run = |env: &mut WmrEnv| {
        env.reset(Some(99));
        let mut rewards = Vec::new();
        for action in [0, 0, 3, 0, 4, 1, 2, 0] {
            let step = env.step(action);
            rewards.push((step.reward, env.subtask_rewards().to_vec()));
            if step.done() {
                break;
            }
        }
        rewards
    };
    let first = run(&mut env);
    let second = run(&mut env);
    assert_eq!(first, second);
    // A fresh environment is reset with seed 0.
    let mut fresh = WmrEnv::default();
    let mut reseeded = WmrEnv::default();
    reseeded.reset(Some(wmr_model::DEFAULT_SEED));
    assert_eq!(fresh.step(0), reseeded.step(0));
}

#[test]
fn the_planner_refuses_unusable_resolutions() {
    let scenario = Scenario::default_scenario();
    for params in [
        PlannerParams {
            cell: 0.0,
            ..PlannerParams::default()
        },
        PlannerParams {
            cell: f64::NAN,
            ..PlannerParams::default()
        },
        PlannerParams {
            heading_cells: 0,
            ..PlannerParams::default()
        },
        PlannerParams {
            cell: 1e-6,
            ..PlannerParams::default()
        },
    ] {
        assert_eq!(shortest_plan(&scenario, &params), None);
    }
    // A tiny budget gives up rather than searching on.
    let starved = PlannerParams {
        max_expansions: 10,
        ..PlannerParams::default()
    };
    assert_eq!(shortest_plan(&scenario, &starved), None);
    assert_eq!(tabular_policy(&scenario, 200, 10), None);
    assert_eq!(tabular_policy(&scenario, 20, 1_000_000), None);
}

/// Discounted return (γ = 0.95) of `actions` replayed from the start under `task`, and the
/// outcome.
fn discounted_return(task: TaskReward, actions: &[Action]) -> (f64, EpisodeStatus) {
    let mut scenario = Scenario::default_scenario();
    scenario.reward.task = task;
    let mut env = WmrEnv::new(scenario).expect("the default scenario is valid");
    env.reset(Some(3));
    let mut rewards = Vec::new();
    for action in actions {
        let step = env.step(action.index());
        rewards.push(step.reward);
        if step.done() {
            break;
        }
    }
    let value = rewards.iter().rev().fold(0.0, |acc, r| r + 0.95 * acc);
    (value, env.status())
}

#[test]
fn the_subtask_sum_pays_about_as_much_for_standing_still_as_for_reaching() {
    // Why TaskReward::Progress is the default. Three behaviours from the start: stop until the
    // step cap, the planner's 34-step route (no table over the states can follow it), and the
    // run of the first deterministic table over the paper's state the search finds within
    // 200 steps.
    let mut scenario = Scenario::default_scenario();
    scenario.state = StateParams::paper();
    let plan = shortest_plan(&scenario, &PlannerParams::default()).expect("solvable");
    let table = tabular_policy(&scenario, 200, 1_000_000).expect("a table exists");
    let stop = vec![Action::Stop; 500];
    let value = |task, actions: &[Action], outcome| {
        let (value, reached) = discounted_return(task, actions);
        assert_eq!(reached, outcome);
        value
    };
    let sum = TaskReward::SubtaskSum;
    let (stay, route, by_table) = (
        value(sum, &stop, EpisodeStatus::Truncated),
        value(sum, &plan.actions, EpisodeStatus::Reached),
        value(sum, &table.plan.actions, EpisodeStatus::Reached),
    );
    // Standing still is worth two thirds of the best route and as much as the table's run.
    assert!(stay > 20.0 && stay > 0.6 * route, "{stay} vs {route}");
    assert!(stay > 0.95 * by_table, "{stay} vs {by_table}");

    let progress = TaskReward::default();
    let (stay, route, by_table) = (
        value(progress, &stop, EpisodeStatus::Truncated),
        value(progress, &plan.actions, EpisodeStatus::Reached),
        value(progress, &table.plan.actions, EpisodeStatus::Reached),
    );
    assert!((stay + 20.0).abs() < 1e-3, "{stay}");
    assert!(route > 30.0 && by_table > 0.0, "{route}, {by_table}");
}
