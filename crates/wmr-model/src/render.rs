//! SVG pictures of a scenario and of runs through it.
//!
//! The picture is drawn at 500 px per metre with y pointing up (the SVG is flipped), and shows
//! the arena with axes in metres and a scale bar, the obstacles, the start pose (body disc and
//! heading, labelled "start"), the target (reach radius, labelled "target"), and any number of
//! paths, each in its own colour and ending in a dot; a path that never leaves the start
//! body's disc (a robot standing still) is drawn as a ring marker so it stays visible.

use std::fmt::Write as _;

use nalgebra::Point2;
use svg::Document;
use svg::node::element::{Circle, Line, Polyline, Rectangle, Text, Title};

use crate::scenario::{ObstacleSpec, Scenario};

/// Pixels per metre.
pub const PIXELS_PER_METRE: f64 = 500.0;

/// Colours given to successive paths.
pub const PATH_COLOURS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf",
];

/// A path to draw: the robot centre's positions and a label (shown as a tooltip).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderedPath<'a> {
    /// Positions, in order.
    pub points: &'a [Point2<f64>],
    /// Label.
    pub label: &'a str,
}

/// Room left of and below the arena for the axes' labels (m).
const AXIS_MARGIN: f64 = 0.09;

/// A tick spacing of 1, 2 or 5 × 10ⁿ metres giving at most 10 intervals over `extent`.
fn tick_step(extent: f64) -> f64 {
    let raw = extent / 10.0;
    let decade = 10_f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&step| step >= raw)
        .unwrap_or(10.0 * decade)
}

/// A text label at world position `(x, y)` (m), `size` px, anchored as given.
fn label(x: f64, y: f64, text: &str, size: u32, anchor: &str) -> Text {
    Text::new(text)
        .set("x", px(x))
        .set("y", px(-y))
        .set("font-size", size)
        .set("font-family", "sans-serif")
        .set("text-anchor", anchor)
        .set("fill", "#333")
}

/// Rounds to a tenth of a pixel so that the SVG text is short and stable.
fn px(metres: f64) -> f64 {
    (metres * PIXELS_PER_METRE * 10.0).round() / 10.0
}

/// Renders `scenario` and `paths` as an SVG document.
#[must_use]
pub fn render_svg(scenario: &Scenario, paths: &[RenderedPath<'_>]) -> String {
    let (w, h) = (scenario.arena.width, scenario.arena.height);
    let margin = 0.02;
    let (left, bottom) = (AXIS_MARGIN, AXIS_MARGIN);
    // Flip y: world (x, y) is drawn at (x, −y); the view box starts at −(h + margin).
    let mut doc = Document::new()
        .set(
            "viewBox",
            (
                px(-left),
                px(-(h + margin)),
                px(w + left + margin),
                px(h + margin + bottom),
            ),
        )
        .set("width", px(w + left + margin))
        .set("height", px(h + margin + bottom))
        .add(Title::new(if scenario.name.is_empty() {
            "wmr-model scenario"
        } else {
            scenario.name.as_str()
        }))
        .add(
            Rectangle::new()
                .set("x", 0.0)
                .set("y", px(-h))
                .set("width", px(w))
                .set("height", px(h))
                .set("fill", "#fafafa")
                .set("stroke", "#333")
                .set("stroke-width", 4),
        );
    doc = axes(doc, w, h);
    for spec in &scenario.obstacles {
        doc = match *spec {
            ObstacleSpec::Circle { x, y, radius } => doc.add(
                Circle::new()
                    .set("cx", px(x))
                    .set("cy", px(-y))
                    .set("r", px(radius))
                    .set("fill", "#888"),
            ),
            ObstacleSpec::Rectangle {
                x,
                y,
                width,
                height,
            } => doc.add(
                Rectangle::new()
                    .set("x", px(x - width / 2.0))
                    .set("y", px(-(y + height / 2.0)))
                    .set("width", px(width))
                    .set("height", px(height))
                    .set("fill", "#888"),
            ),
        };
    }
    let target = &scenario.target;
    doc = doc.add(
        Circle::new()
            .set("cx", px(target.x))
            .set("cy", px(-target.y))
            .set("r", px(target.reach_radius))
            .set("fill", "#ffe08a")
            .set("stroke", "#c90")
            .set("stroke-width", 2),
    );
    let start = &scenario.start;
    let radius = scenario.robot.body_radius;
    doc = doc
        .add(
            Circle::new()
                .set("cx", px(start.x))
                .set("cy", px(-start.y))
                .set("r", px(radius))
                .set("fill", "none")
                .set("stroke", "#2a7")
                .set("stroke-width", 2),
        )
        .add(
            Line::new()
                .set("x1", px(start.x))
                .set("y1", px(-start.y))
                .set("x2", px(start.x + radius * start.heading.cos()))
                .set("y2", px(-(start.y + radius * start.heading.sin())))
                .set("stroke", "#2a7")
                .set("stroke-width", 2),
        )
        .add(label(
            start.x,
            start.y + radius + 0.012,
            "start",
            13,
            "middle",
        ))
        .add(label(
            target.x,
            target.y + target.reach_radius + 0.012,
            "target",
            13,
            "middle",
        ));
    let origin = Point2::new(start.x, start.y);
    for (i, path) in paths.iter().enumerate() {
        let colour = PATH_COLOURS[i % PATH_COLOURS.len()];
        let mut points = String::new();
        for p in path.points {
            // Writing to a String cannot fail.
            let _ = write!(points, "{},{} ", px(p.x), px(-p.y));
        }
        doc = doc.add(
            Polyline::new()
                .set("points", points.trim_end())
                .set("fill", "none")
                .set("stroke", colour)
                .set("stroke-width", 2)
                .add(Title::new(path.label)),
        );
        let Some(end) = path.points.last() else {
            continue;
        };
        let stood_still = path.points.iter().all(|p| (p - origin).norm() <= radius);
        doc = doc.add(if stood_still {
            // Ring markers of growing size, so several robots standing still all show.
            #[expect(
                clippy::cast_precision_loss,
                reason = "the path index is a small count"
            )]
            let ring = radius * (0.45 + 0.15 * i as f64);
            Circle::new()
                .set("cx", px(end.x))
                .set("cy", px(-end.y))
                .set("r", px(ring))
                .set("fill", "none")
                .set("stroke", colour)
                .set("stroke-width", 3)
                .add(Title::new(path.label))
        } else {
            Circle::new()
                .set("cx", px(end.x))
                .set("cy", px(-end.y))
                .set("r", 5)
                .set("fill", colour)
                .add(Title::new(path.label))
        });
    }
    doc.to_string()
}

/// Ticks and labels in metres along the arena's bottom and left edges, and a scale bar.
fn axes(mut doc: Document, w: f64, h: f64) -> Document {
    let step = tick_step(w.max(h));
    let decimals = if step >= 1.0 {
        0
    } else {
        1 + usize::from(step < 0.1)
    };
    let tick = 0.012;
    for (along_x, extent) in [(true, w), (false, h)] {
        let mut k = 0_u32;
        loop {
            let at = f64::from(k) * step;
            if at > extent + 1e-9 {
                break;
            }
            let text = format!("{at:.decimals$}");
            doc = if along_x {
                doc.add(
                    Line::new()
                        .set("x1", px(at))
                        .set("y1", 0.0)
                        .set("x2", px(at))
                        .set("y2", px(tick))
                        .set("stroke", "#333")
                        .set("stroke-width", 1.5),
                )
                .add(label(at, -tick - 0.03, &text, 13, "middle"))
            } else {
                doc.add(
                    Line::new()
                        .set("x1", px(-tick))
                        .set("y1", px(-at))
                        .set("x2", 0.0)
                        .set("y2", px(-at))
                        .set("stroke", "#333")
                        .set("stroke-width", 1.5),
                )
                .add(label(-tick - 0.006, at - 0.009, &text, 13, "end"))
            };
            k += 1;
        }
    }
    // Axis names and a scale bar of one tick step below the arena's right end.
    let bar = format!("{}", (step * 100.0).round());
    doc.add(label(w / 2.0, -0.08, "x (m)", 14, "middle"))
        .add(label(-0.085, h - step / 2.0 - 0.005, "y (m)", 14, "start"))
        .add(
            Line::new()
                .set("x1", px(w - step))
                .set("y1", px(0.075))
                .set("x2", px(w))
                .set("y2", px(0.075))
                .set("stroke", "#333")
                .set("stroke-width", 3),
        )
        .add(label(
            w - step / 2.0,
            -0.068,
            &format!("{bar} cm"),
            12,
            "middle",
        ))
}

/// Pixels per metre of the frames the Python environment renders: the default 1 m × 1 m arena
/// is 200 × 200 pixels.
pub const FRAME_PIXELS_PER_METRE: f64 = 200.0;

const FRAME_FLOOR: [u8; 3] = [0xfa, 0xfa, 0xfa];
const FRAME_OBSTACLE: [u8; 3] = [0x88, 0x88, 0x88];
const FRAME_TARGET: [u8; 3] = [0xff, 0xe0, 0x8a];
const FRAME_PATH: [u8; 3] = [0x1f, 0x77, 0xb4];
const FRAME_ROBOT: [u8; 3] = [0xd6, 0x27, 0x28];
const FRAME_HEADING: [u8; 3] = [0xff, 0xff, 0xff];

/// The arena of `scenario` as an RGB frame (Gymnasium's `rgb_array`), `pixels_per_metre`
/// pixels a metre, y up: the floor, the obstacles (gray), the target's reach disc (yellow),
/// `path` (the robot centre's positions, blue, joined), and the robot's body (red) at `pose`
/// with its heading as a white radius. Each pixel is painted by what covers its centre.
#[must_use]
pub fn render_rgb(
    scenario: &Scenario,
    pose: &nalgebra::Isometry2<f64>,
    path: &[Point2<f64>],
    pixels_per_metre: f64,
) -> dql::RgbFrame {
    let scale = if pixels_per_metre.is_finite() && pixels_per_metre > 0.0 {
        pixels_per_metre
    } else {
        FRAME_PIXELS_PER_METRE
    };
    // A validated arena is at most a few metres; the cast saturates for anything else.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "the arena's extent in pixels is small and positive"
    )]
    let pixels = |metres: f64| ((metres * scale).ceil().max(1.0) as usize).min(4096);
    let (width, height) = (pixels(scenario.arena.width), pixels(scenario.arena.height));
    let mut frame = dql::RgbFrame::filled(width, height, FRAME_FLOOR);
    // The world point at the centre of pixel (column, row).
    #[expect(clippy::cast_precision_loss, reason = "pixel indices are small")]
    let world = |column: usize, row: usize| {
        Point2::new(
            (column as f64 + 0.5) / scale,
            (height as f64 - row as f64 - 0.5) / scale,
        )
    };
    let body = scenario.robot.body_radius;
    let centre = Point2::from(pose.translation.vector);
    let target = Point2::new(scenario.target.x, scenario.target.y);
    let obstacles: Vec<_> = scenario
        .obstacles
        .iter()
        .map(ObstacleSpec::obstacle)
        .collect();
    for row in 0..height {
        for column in 0..width {
            let point = world(column, row);
            let colour = if (point - centre).norm() <= body {
                FRAME_ROBOT
            } else if obstacles
                .iter()
                .any(|obstacle| obstacle.distance_to(&point) <= 0.0)
            {
                FRAME_OBSTACLE
            } else if (point - target).norm() <= scenario.target.reach_radius {
                FRAME_TARGET
            } else {
                continue;
            };
            frame.set(column, row, colour);
        }
    }
    // The path and the heading, sampled every half pixel along each segment.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "points outside the frame are skipped by RgbFrame::set"
    )]
    let line = |frame: &mut dql::RgbFrame, from: Point2<f64>, to: Point2<f64>, colour| {
        let samples = (((to - from).norm() * scale * 2.0).ceil() as usize).clamp(1, 100_000);
        for i in 0..=samples {
            #[expect(clippy::cast_precision_loss, reason = "a small count")]
            let point = from + (to - from) * (i as f64 / samples as f64);
            let (x, y) = (point.x * scale, (scenario.arena.height - point.y) * scale);
            if x >= 0.0 && y >= 0.0 {
                frame.set(x as usize, y as usize, colour);
            }
        }
    };
    for pair in path.windows(2) {
        if (pair[0] - centre).norm() > body || (pair[1] - centre).norm() > body {
            line(&mut frame, pair[0], pair[1], FRAME_PATH);
        }
    }
    let heading = pose.rotation * nalgebra::Vector2::new(body, 0.0);
    line(&mut frame, centre, centre + heading, FRAME_HEADING);
    frame
}

#[cfg(test)]
mod frame_tests {
    use super::*;
    use crate::{Scenario, WmrEnv};

    #[test]
    fn the_default_arena_shows_robot_obstacles_and_target() {
        let scenario = Scenario::default_scenario();
        let env = WmrEnv::new(scenario.clone()).expect("the default scenario is valid");
        let frame = render_rgb(&scenario, env.pose(), env.path(), FRAME_PIXELS_PER_METRE);
        assert_eq!((frame.width, frame.height), (200, 200));
        assert_eq!(frame.pixels.len(), 200 * 200 * 3);
        let at = |x: f64, y: f64| {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "points inside the 1 m arena"
            )]
            frame
                .get((x * 200.0) as usize, ((1.0 - y) * 200.0) as usize)
                .expect("inside the frame")
        };
        let start = &scenario.start;
        // Just off the heading line, inside the body.
        assert_eq!(at(start.x, start.y - 0.01), FRAME_ROBOT);
        assert_eq!(at(scenario.target.x, scenario.target.y), FRAME_TARGET);
        let colours: std::collections::HashSet<_> = frame.pixels.chunks(3).collect();
        assert!(colours.contains(&FRAME_OBSTACLE[..]), "obstacles are drawn");
        assert!(colours.contains(&FRAME_HEADING[..]), "the heading is drawn");
        assert_eq!(at(0.005, 0.995), FRAME_FLOOR);
    }
}
