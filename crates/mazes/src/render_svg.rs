//! A maze with one or more trajectories as SVG: the analogue of the paper's Fig. 6 and 9.
//!
//! Obstacles are gray squares, the start a green `S` tile, the target a red `T` tile;
//! each trajectory is a polyline through tile centres in its own colour, nudged
//! diagonally by a fraction of a tile so overlapping paths of different methods stay
//! visible side by side, with a dot where it ends. The `S` and `T` letters are drawn
//! last, above every path. A legend below the maze names each
//! trajectory and its number of steps (tiles in the path − 1; a bump is a step).

use serde::{Deserialize, Serialize};
use svg::Document;
use svg::node::element::{Circle, Group, Line, Path, Polyline, Rectangle, Text, Title};

use crate::geometry::Pos;
use crate::maze::Maze;

/// Colour-blind-safe colours (Okabe–Ito) given to trajectories without their own colour,
/// in order, cycling.
pub const PALETTE: [&str; 6] = [
    "#0072B2", "#E69F00", "#CC79A7", "#56B4E9", "#000000", "#D55E00",
];

const OBSTACLE_FILL: &str = "#808080";
const START_FILL: &str = "#7fc97f";
const TARGET_FILL: &str = "#f28e8e";
const GRID_STROKE: &str = "#d9d9d9";
const FONT: &str = "sans-serif";
const LEGEND_FONT_PX: f64 = 12.0;

/// One trajectory to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SvgTrajectory<'a> {
    /// Legend text, e.g. the method's name.
    pub label: &'a str,
    /// The visited tiles in order (start included).
    pub path: &'a [Pos],
    /// Any SVG colour; `None` takes the next colour of [`PALETTE`].
    pub color: Option<&'a str>,
}

/// How to draw.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SvgOptions {
    /// Side of a tile in pixels (values below 4 are drawn as 4).
    pub tile_px: u32,
    /// Optional title above the maze.
    pub title: Option<String>,
    /// Draw light grid lines between tiles.
    pub grid_lines: bool,
}

impl Default for SvgOptions {
    fn default() -> Self {
        Self {
            tile_px: 16,
            title: None,
            grid_lines: true,
        }
    }
}

/// Draws `maze` with `trajectories` as a standalone SVG document.
#[must_use]
pub fn render_svg(maze: &Maze, trajectories: &[SvgTrajectory<'_>], options: &SvgOptions) -> String {
    let tile = f64::from(options.tile_px.max(4));
    let margin = tile.max(LEGEND_FONT_PX);
    let title_height = if options.title.is_some() {
        LEGEND_FONT_PX * 2.0
    } else {
        0.0
    };
    let grid_width = tile * maze.width() as f64;
    let grid_height = tile * maze.height() as f64;
    let legend_row = LEGEND_FONT_PX * 1.5;
    let legend_height = legend_row * trajectories.len() as f64;
    let width = grid_width + 2.0 * margin;
    let height = title_height + grid_height + 2.0 * margin + legend_height;
    let (left, top) = (margin, margin + title_height);

    let mut document = Document::new()
        .set("xmlns", "http://www.w3.org/2000/svg")
        .set("width", fmt(width))
        .set("height", fmt(height))
        .set("viewBox", format!("0 0 {} {}", fmt(width), fmt(height)))
        .add(
            Rectangle::new()
                .set("width", fmt(width))
                .set("height", fmt(height))
                .set("fill", "white"),
        );
    if let Some(title) = &options.title {
        document = document.add(Title::new(title.as_str())).add(
            Text::new(title.as_str())
                .set("x", fmt(width / 2.0))
                .set("y", fmt(margin + LEGEND_FONT_PX))
                .set("text-anchor", "middle")
                .set("font-family", FONT)
                .set("font-size", fmt(LEGEND_FONT_PX * 1.2)),
        );
    }

    document = document.add(grid_group(maze, tile, left, top, options.grid_lines));
    for (index, trajectory) in trajectories.iter().enumerate() {
        let color = trajectory.color.unwrap_or(PALETTE[index % PALETTE.len()]);
        let nudge = nudge(index, trajectories.len()) * tile;
        document = document.add(trajectory_group(
            trajectory.path,
            color,
            tile,
            left + nudge,
            top + nudge,
        ));
        let y = top + grid_height + margin * 0.5 + legend_row * (index as f64 + 0.5);
        document = document.add(legend_entry(trajectory, color, left, y));
    }
    document
        .add(marker_letters(maze, tile, left, top))
        .to_string()
}

/// Fraction of a tile by which trajectory `index` of `count` is shifted (centred on 0,
/// at most ±0.3 tiles).
fn nudge(index: usize, count: usize) -> f64 {
    if count <= 1 {
        return 0.0;
    }
    let spacing = (0.6 / (count - 1) as f64).min(0.15);
    (index as f64 - (count - 1) as f64 / 2.0) * spacing
}

fn grid_group(maze: &Maze, tile: f64, left: f64, top: f64, grid_lines: bool) -> Group {
    let mut group = Group::new().add(
        Rectangle::new()
            .set("x", fmt(left))
            .set("y", fmt(top))
            .set("width", fmt(tile * maze.width() as f64))
            .set("height", fmt(tile * maze.height() as f64))
            .set("fill", "white"),
    );
    if grid_lines {
        let mut d = String::new();
        for x in 1..maze.width() {
            let at = left + tile * x as f64;
            d.push_str(&format!(
                "M{} {}V{}",
                fmt(at),
                fmt(top),
                fmt(top + tile * maze.height() as f64)
            ));
        }
        for y in 1..maze.height() {
            let at = top + tile * y as f64;
            d.push_str(&format!(
                "M{} {}H{}",
                fmt(left),
                fmt(at),
                fmt(left + tile * maze.width() as f64)
            ));
        }
        if !d.is_empty() {
            group = group.add(
                Path::new()
                    .set("d", d)
                    .set("stroke", GRID_STROKE)
                    .set("stroke-width", 0.5)
                    .set("fill", "none"),
            );
        }
    }
    let tile_rect = |pos: Pos, fill: &str| {
        Rectangle::new()
            .set("x", fmt(left + tile * pos.x as f64))
            .set("y", fmt(top + tile * pos.y as f64))
            .set("width", fmt(tile))
            .set("height", fmt(tile))
            .set("fill", fill.to_owned())
    };
    for pos in maze.obstacles() {
        group = group.add(tile_rect(pos, OBSTACLE_FILL));
    }
    for (pos, fill) in [(maze.start(), START_FILL), (maze.target(), TARGET_FILL)] {
        group = group.add(tile_rect(pos, fill));
    }
    group.add(
        Rectangle::new()
            .set("x", fmt(left))
            .set("y", fmt(top))
            .set("width", fmt(tile * maze.width() as f64))
            .set("height", fmt(tile * maze.height() as f64))
            .set("fill", "none")
            .set("stroke", "black"),
    )
}

/// The `S` and `T` letters, drawn above the trajectories so paths never hide them.
fn marker_letters(maze: &Maze, tile: f64, left: f64, top: f64) -> Group {
    let mut group = Group::new();
    for (pos, letter) in [(maze.start(), "S"), (maze.target(), "T")] {
        group = group.add(
            Text::new(letter)
                .set("x", fmt(left + tile * (pos.x as f64 + 0.5)))
                .set("y", fmt(top + tile * (pos.y as f64 + 0.5)))
                .set("dy", "0.35em")
                .set("text-anchor", "middle")
                .set("font-family", FONT)
                .set("font-weight", "bold")
                .set("font-size", fmt(tile * 0.75))
                .set("stroke", "white")
                .set("stroke-width", fmt(tile * 0.1))
                .set("paint-order", "stroke"),
        );
    }
    group
}

fn trajectory_group(path: &[Pos], color: &str, tile: f64, left: f64, top: f64) -> Group {
    let centre = |pos: &Pos| {
        (
            left + tile * (pos.x as f64 + 0.5),
            top + tile * (pos.y as f64 + 0.5),
        )
    };
    let mut group = Group::new();
    if path.len() >= 2 {
        let points = path
            .iter()
            .map(|pos| {
                let (x, y) = centre(pos);
                format!("{},{}", fmt(x), fmt(y))
            })
            .collect::<Vec<_>>()
            .join(" ");
        group = group.add(
            Polyline::new()
                .set("points", points)
                .set("fill", "none")
                .set("stroke", color.to_owned())
                .set("stroke-width", fmt((tile * 0.18).max(1.0)))
                .set("stroke-linejoin", "round")
                .set("stroke-linecap", "round")
                .set("stroke-opacity", 0.85),
        );
    }
    if let Some(last) = path.last() {
        let (x, y) = centre(last);
        group = group.add(
            Circle::new()
                .set("cx", fmt(x))
                .set("cy", fmt(y))
                .set("r", fmt((tile * 0.2).max(1.5)))
                .set("fill", color.to_owned()),
        );
    }
    group
}

fn legend_entry(trajectory: &SvgTrajectory<'_>, color: &str, left: f64, y: f64) -> Group {
    let steps = trajectory.path.len().saturating_sub(1);
    Group::new()
        .add(
            Line::new()
                .set("x1", fmt(left))
                .set("y1", fmt(y))
                .set("x2", fmt(left + 2.0 * LEGEND_FONT_PX))
                .set("y2", fmt(y))
                .set("stroke", color.to_owned())
                .set("stroke-width", 3),
        )
        .add(
            Text::new(format!("{} ({steps} steps)", trajectory.label))
                .set("x", fmt(left + 2.5 * LEGEND_FONT_PX))
                .set("y", fmt(y))
                .set("dy", "0.35em")
                .set("font-family", FONT)
                .set("font-size", fmt(LEGEND_FONT_PX)),
        )
}

/// Coordinates with at most two decimals and no trailing zeros, so output is short and stable.
fn fmt(value: f64) -> String {
    let text = format!("{value:.2}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}
