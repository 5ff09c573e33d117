//! SVG pictures of a scenario and of runs through it.
//!
//! The picture is drawn at 500 px per metre with y pointing up (the SVG is flipped), and shows
//! the arena, the obstacles, the start pose (body disc and heading), the target (reach
//! radius), and any number of paths, each in its own colour.

use std::fmt::Write as _;

use nalgebra::Point2;
use svg::Document;
use svg::node::element::{Circle, Line, Polyline, Rectangle, Title};

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

/// Rounds to a tenth of a pixel so that the SVG text is short and stable.
fn px(metres: f64) -> f64 {
    (metres * PIXELS_PER_METRE * 10.0).round() / 10.0
}

/// Renders `scenario` and `paths` as an SVG document.
#[must_use]
pub fn render_svg(scenario: &Scenario, paths: &[RenderedPath<'_>]) -> String {
    let (w, h) = (scenario.arena.width, scenario.arena.height);
    let margin = 0.02;
    // Flip y: world (x, y) is drawn at (x, −y); the view box starts at −(h + margin).
    let mut doc = Document::new()
        .set(
            "viewBox",
            (
                px(-margin),
                px(-(h + margin)),
                px(w + 2.0 * margin),
                px(h + 2.0 * margin),
            ),
        )
        .set("width", px(w + 2.0 * margin))
        .set("height", px(h + 2.0 * margin))
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
        );
    for (i, path) in paths.iter().enumerate() {
        let mut points = String::new();
        for p in path.points {
            // Writing to a String cannot fail.
            let _ = write!(points, "{},{} ", px(p.x), px(-p.y));
        }
        doc = doc.add(
            Polyline::new()
                .set("points", points.trim_end())
                .set("fill", "none")
                .set("stroke", PATH_COLOURS[i % PATH_COLOURS.len()])
                .set("stroke-width", 2)
                .add(Title::new(path.label)),
        );
    }
    doc.to_string()
}
