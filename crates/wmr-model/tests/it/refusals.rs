//! Scenarios that cannot be run, solved or held in memory are refused at load time with a typed
//! error naming the field, instead of panicking or aborting later (issue 12, item 5; issue 14,
//! item 2). Each case here used to panic, abort or produce non-finite rewards.

use wmr_model::{
    MAX_STATES, PlanError, PlannerParams, Scenario, ScenarioError, WmrEnv, shortest_plan,
};

use crate::scenarios::MINIMAL;

fn refused(extra: &str) -> ScenarioError {
    Scenario::from_toml_str(&format!("{MINIMAL}\n{extra}\n")).expect_err("must be refused")
}

fn out_of_range_field(error: &ScenarioError) -> &str {
    match error {
        ScenarioError::OutOfRange { field, .. } | ScenarioError::NotFinite { field, .. } => field,
        other => panic!("expected a field error, got {other}"),
    }
}

#[test]
fn a_huge_arena_is_refused_naming_the_field() {
    // 1e17 m used to overflow the planner's grid (index out of bounds).
    let error = Scenario::from_toml_str(&MINIMAL.replace("width = 1.0", "width = 1e17"))
        .expect_err("must be refused");
    assert_eq!(out_of_range_field(&error), "arena.width");
    assert!(error.to_string().contains("at most 20 m"), "{error}");
}

#[test]
fn the_largest_arena_allowed_is_planned_on_a_coarser_grid() {
    // A 20 m × 20 m arena passes validation; the planner coarsens its grid instead of
    // overflowing it, and still finds the straight route.
    let text = MINIMAL
        .replace("width = 1.0", "width = 20.0")
        .replace("height = 0.6", "height = 20.0");
    let scenario = Scenario::from_toml_str(&text).expect("valid");
    let plan = shortest_plan(&scenario, &PlannerParams::default()).expect("a route");
    // 0.8 m less the 5 cm reach radius, at 2.5 cm per full-speed step.
    assert_eq!(plan.actions.len(), 30);
}

#[test]
fn a_huge_step_cap_is_refused_naming_the_field() {
    // 4294967295 used to abort allocating a 64 GB path buffer.
    let error = Scenario::from_toml_str(&format!("step_cap = 4294967295\n{MINIMAL}"))
        .expect_err("must be refused");
    assert_eq!(out_of_range_field(&error), "step_cap");
    let ok = Scenario::from_toml_str(&format!("step_cap = 100000\n{MINIMAL}")).expect("valid");
    assert!(WmrEnv::new(ok).is_ok());
    let error = Scenario::from_toml_str(&format!("step_cap = 100001\n{MINIMAL}"))
        .expect_err("must be refused");
    assert_eq!(out_of_range_field(&error), "step_cap");
}

#[test]
fn bin_counts_whose_table_cannot_fit_are_refused() {
    // 2147483647 distance bins used to abort allocating the state table.
    let error = refused("[state]\ndistance_bins = 2147483647");
    assert_eq!(out_of_range_field(&error), "state.distance_bins");
    let error = refused("[state]\ntarget_bins = 4294967295");
    assert_eq!(out_of_range_field(&error), "state.target_bins");
    // Each count within its bound, the product beyond MAX_STATES.
    let error = refused("[state]\ndistance_bins = 1000\ntarget_bins = 1000\nimage_bins = 2");
    match error {
        ScenarioError::TooManyStates { count } => {
            assert_eq!(count, 1000 * 1000 * (2 * 6 + 1));
            assert!(count > u128::from(MAX_STATES));
        }
        other => panic!("expected TooManyStates, got {other}"),
    }
    assert!(
        error_text("[state]\ndistance_bins = 1000\ntarget_bins = 1000\nimage_bins = 2")
            .contains("state.target_bins")
    );
}

fn error_text(extra: &str) -> String {
    refused(extra).to_string()
}

#[test]
fn sensor_noise_and_reward_constants_that_overflow_are_refused() {
    // Issue 14, item 2: noise 1e308 made the rewards infinite.
    let error = refused("[sensors]\nnoise = 1e308");
    assert_eq!(out_of_range_field(&error), "sensors.noise");
    for (field, extra) in [
        ("reward.k", "[reward]\nk = 1e308"),
        ("reward.f", "[reward]\nf = -1e300"),
        ("reward.hit", "[reward]\nhit = -1e307"),
        ("reward.target_kept", "[reward]\ntarget_kept = 1e7"),
        ("reward.target_lost", "[reward]\ntarget_lost = -1e7"),
        ("reward.goal_bonus", "[reward]\ngoal_bonus = 1e308"),
        ("reward.p", "[reward]\np = 1e-300"),
    ] {
        assert_eq!(out_of_range_field(&refused(extra)), field, "{extra}");
    }
}

#[test]
fn the_largest_allowed_constants_give_finite_rewards() {
    use dql::Environment;
    let text = format!(
        "{MINIMAL}\n[sensors]\nnoise = 1.0\n[reward]\nk = 1e6\nf = 1e6\nhit = -1e6\n\
         target_kept = 1e6\ntarget_lost = -1e6\ngoal_bonus = 1e6\np = 0.01\n"
    );
    let mut env = WmrEnv::new(Scenario::from_toml_str(&text).expect("valid")).expect("valid");
    env.reset(Some(1));
    for action in [0, 3, 4, 1, 2].iter().cycle().take(60) {
        let step = env.step(*action);
        assert!(step.reward.is_finite());
        assert!(env.subtask_rewards().iter().all(|r| r.is_finite()));
        if step.done() {
            break;
        }
    }
}

#[test]
fn a_walled_off_target_is_refused_by_the_route_check() {
    // A wall of boxes across the arena between start and target: valid geometry, no route.
    let wall = "[[obstacles]]\nshape = \"rectangle\"\nx = 0.5\ny = 0.3\nwidth = 0.04\nheight = 0.6";
    let scenario = Scenario::from_toml_str(&format!("{MINIMAL}\n{wall}\n")).expect("valid");
    let error = scenario
        .check_route(&PlannerParams::default())
        .expect_err("no route");
    match &error {
        ScenarioError::TargetUnreachable { reason, .. } => {
            assert!(matches!(reason, PlanError::NoRoute { .. }), "{reason}");
        }
        other => panic!("expected TargetUnreachable, got {other}"),
    }
    assert!(
        error.to_string().starts_with("`target` (0.9, 0.3)"),
        "{error}"
    );
    // The open arena has a route.
    let open = Scenario::from_toml_str(MINIMAL).expect("valid");
    assert!(open.check_route(&PlannerParams::default()).is_ok());
}

/// Checked once: `Scenario::check` is `validate` kept as a type; the environment built from a
/// checked scenario is the one `WmrEnv::new` builds, and a repaired copy stays checked.
#[test]
fn a_checked_scenario_builds_the_same_environment_without_failing() {
    use dql::Environment;
    let scenario = Scenario::from_toml_str(MINIMAL).expect("valid");
    let checked = scenario.clone().check().expect("valid");
    assert_eq!(*checked, scenario);
    let mut direct = WmrEnv::new(scenario.clone()).expect("valid");
    let mut built = WmrEnv::from_checked(checked.clone());
    assert_eq!(built.checked_scenario(), &checked);
    for (a, b) in [(&mut direct, &mut built)] {
        a.reset(Some(3));
        b.reset(Some(3));
        for action in [0, 3, 4, 0, 1] {
            assert_eq!(a.step(action), b.step(action));
        }
    }
    let repairs = wmr_model::SubtaskRepairs {
        reach_goal_bonus: true,
        end_penalties: true,
    };
    let repaired = checked.with_repairs(repairs);
    assert_eq!(repaired.reward.repairs, repairs);
    assert!(repaired.validate().is_ok());
    // What fails the check is what fails `validate`, naming the same field.
    let bad = MINIMAL.replace("width = 1.0", "width = -1.0");
    let parsed: Scenario = toml::from_str(&bad).expect("parses");
    let error = parsed.check().expect_err("refused");
    assert_eq!(error.field().as_deref(), Some("arena.width"));
}

/// `ScenarioError::field` names the field a caller would blame, for every kind of error that
/// is about one.
#[test]
fn every_refusal_about_a_field_names_it() {
    let cases = [
        ("step_cap = 0", "step_cap"),
        ("control_period = 20.0", "control_period"),
        ("[state]\ndistance_bins = 0", "state.distance_bins"),
        ("[state]\ndistance_bins = 1000\ntarget_bins = 1000", "state"),
    ];
    for (extra, field) in cases {
        // Top-level keys must come before the tables of MINIMAL.
        let text = if extra.starts_with('[') {
            format!("{MINIMAL}\n{extra}\n")
        } else {
            format!("{extra}\n{MINIMAL}")
        };
        let error = Scenario::from_toml_str(&text).expect_err("refused");
        assert_eq!(error.field().as_deref(), Some(field), "{error}");
    }
    // MINIMAL ends inside `[target]`.
    let near = format!("{MINIMAL}reach_radius = 5.0\n");
    let error = Scenario::from_toml_str(&near).expect_err("refused");
    assert_eq!(
        error.field().as_deref(),
        Some("target.reach_radius"),
        "{error}"
    );
}
