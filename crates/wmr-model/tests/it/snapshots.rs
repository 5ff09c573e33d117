//! Pinned outputs: what the robot senses at fixed poses in the default scenario, and an SVG.

use std::fmt::Write as _;

use dql::Environment;
use nalgebra::{Isometry2, Point2, Vector2};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use wmr_model::{RenderedPath, RewardInputs, Scenario, WmrEnv, render_svg};

fn round(x: f64) -> f64 {
    let rounded = (x * 1e6).round() / 1e6;
    if rounded == 0.0 { 0.0 } else { rounded } // no "-0"
}

fn list(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{}", round(*v))).collect();
    format!("[{}]", items.join(", "))
}

fn describe(env: &WmrEnv, x: f64, y: f64, heading: f64) -> String {
    let pose = Isometry2::new(Vector2::new(x, y), heading);
    let seen = env.observe(&pose);
    let mut noisy = seen.proximities;
    env.sensors()
        .add_noise(&mut noisy, &mut ChaCha8Rng::seed_from_u64(42));
    let mut out = String::new();
    let _ = writeln!(out, "pose: x {x}, y {y}, heading {heading}");
    let _ = writeln!(out, "proximities: {}", list(&seen.proximities));
    let _ = writeln!(out, "noisy (seed 42): {}", list(&noisy));
    let _ = writeln!(
        out,
        "target: distance {}, bearing {}, in view {}",
        round(seen.target_distance),
        round(seen.target_bearing),
        seen.view.target_in_view
    );
    match seen.view.obstacle {
        Some(o) => {
            let _ = writeln!(
                out,
                "obstacle: index {}, feature ({}, {}), distance {}, delta {}, angle {}",
                o.index,
                round(o.feature.x),
                round(o.feature.y),
                round(o.distance),
                round(o.delta),
                round(o.angle)
            );
        }
        None => {
            let _ = writeln!(out, "obstacle: none in view");
        }
    }
    let _ = writeln!(out, "bins: {:?}", seen.bins);
    let _ = writeln!(
        out,
        "state: {} features {:?}",
        seen.state,
        env.state_features(seen.state)
    );
    let scenario = env.scenario();
    let inputs = RewardInputs {
        target_distance: seen.target_distance,
        sensor_values: &noisy,
        noise: scenario.sensors.noise,
        rad: seen
            .view
            .obstacle
            .map_or(std::f64::consts::PI, |o| o.angle.abs()),
        hit: false,
        lost: !seen.view.target_in_view,
        reached: false,
    };
    let _ = writeln!(
        out,
        "sub-task rewards (Eq. 6, 7, 8): {}",
        list(&scenario.reward.subtasks(&inputs))
    );
    out
}

#[test]
fn sensing_at_fixed_poses_in_the_default_scenario() {
    let env = WmrEnv::default();
    let mut text = String::new();
    // Close to the first cylinder, heading slightly right of it.
    text += &describe(&env, 0.26, 0.53, -0.15);
    text += "\n";
    // In front of the gate, angled towards the upper box.
    text += &describe(&env, 0.47, 0.52, 0.3);
    text += "\n";
    // At the start.
    text += &describe(&env, 0.1, 0.5, 0.0);
    insta::assert_snapshot!(text);
}

#[test]
fn svg_of_a_small_scenario_with_a_path() {
    let scenario = Scenario::from_toml_str(
        r#"
name = "tiny"
[arena]
width = 0.4
height = 0.2
[start]
x = 0.05
y = 0.1
heading = 0.0
[target]
x = 0.35
y = 0.1
[[obstacles]]
shape = "circle"
x = 0.2
y = 0.04
radius = 0.02
[[obstacles]]
shape = "rectangle"
x = 0.2
y = 0.17
width = 0.04
height = 0.02
"#,
    )
    .unwrap();
    let path = [
        Point2::new(0.05, 0.1),
        Point2::new(0.15, 0.11),
        Point2::new(0.25, 0.1),
        Point2::new(0.33, 0.1),
    ];
    let svg = render_svg(
        &scenario,
        &[RenderedPath {
            points: &path,
            label: "by hand",
        }],
    );
    insta::assert_snapshot!(svg);
}
