//! A maze as a small RGB picture: what Gymnasium's `rgb_array` render mode returns (a frame
//! per step for `RecordVideo` or a notebook).
//!
//! Each tile is a square of `tile_pixels` pixels in the colours of [`render_svg`](crate::render_svg):
//! obstacles gray, the start green, the target red, free tiles white; the tiles the episode has
//! visited are light blue and the agent's tile (the last of the trajectory) dark blue, inset
//! by a pixel so the tile's colour shows around it.

use dql::RgbFrame;

use crate::geometry::Pos;
use crate::maze::Maze;

/// Pixels per tile of the frames the Python environments render: Task I (30 × 30 tiles) is
/// 240 × 240 pixels.
pub const TILE_PIXELS: usize = 8;

const FREE: [u8; 3] = [0xff, 0xff, 0xff];
const OBSTACLE: [u8; 3] = [0x80, 0x80, 0x80];
const START: [u8; 3] = [0x7f, 0xc9, 0x7f];
const TARGET: [u8; 3] = [0xf2, 0x8e, 0x8e];
const VISITED: [u8; 3] = [0xb3, 0xd7, 0xf0];
const AGENT: [u8; 3] = [0x00, 0x72, 0xb2];

/// `maze` as an RGB frame of `tile_pixels` pixels per tile, the tiles of `trajectory` marked
/// and its last tile drawn as the agent. Tiles outside the grid are ignored.
#[must_use]
pub fn render_rgb(maze: &Maze, trajectory: &[Pos], tile_pixels: usize) -> RgbFrame {
    let tile = tile_pixels.max(1);
    let mut frame = RgbFrame::filled(maze.width() * tile, maze.height() * tile, FREE);
    let mut visited = vec![false; maze.n_tiles()];
    for &pos in trajectory {
        if let Some(state) = maze.state_of(pos) {
            visited[state] = true;
        }
    }
    let fill = |frame: &mut RgbFrame, pos: Pos, inset: usize, colour: [u8; 3]| {
        // At least one pixel stays inside the inset.
        let inset = inset.min((tile - 1) / 2);
        for y in pos.y * tile + inset..(pos.y + 1) * tile - inset {
            for x in pos.x * tile + inset..(pos.x + 1) * tile - inset {
                frame.set(x, y, colour);
            }
        }
    };
    for y in 0..maze.height() {
        for x in 0..maze.width() {
            let pos = Pos::new(x, y);
            let colour = if pos == maze.start() {
                START
            } else if pos == maze.target() {
                TARGET
            } else if maze.is_obstacle(pos) {
                OBSTACLE
            } else if visited[y * maze.width() + x] {
                VISITED
            } else {
                continue;
            };
            fill(&mut frame, pos, 0, colour);
        }
    }
    if let Some(&agent) = trajectory.last()
        && maze.state_of(agent).is_some()
    {
        fill(&mut frame, agent, 1, AGENT);
    }
    frame
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_tile_has_its_colour_and_the_agent_its_inset() {
        let maze = Maze::parse("S.#\n..T\n").expect("a valid map");
        let path = [Pos::new(0, 0), Pos::new(0, 1), Pos::new(1, 1)];
        let frame = render_rgb(&maze, &path, 4);
        assert_eq!((frame.width, frame.height), (12, 8));
        assert_eq!(frame.pixels.len(), 12 * 8 * 3);
        assert_eq!(frame.get(0, 0), Some(START));
        assert_eq!(frame.get(9, 1), Some(OBSTACLE));
        assert_eq!(frame.get(10, 6), Some(TARGET));
        assert_eq!(frame.get(5, 1), Some(FREE));
        assert_eq!(frame.get(1, 5), Some(VISITED));
        // The agent on (1, 1): its tile's border keeps the tile's colour.
        assert_eq!(frame.get(5, 5), Some(AGENT));
        assert_eq!(frame.get(4, 4), Some(VISITED));
        assert_eq!(frame.get(12, 0), None);
    }

    #[test]
    fn a_one_pixel_tile_still_shows_the_agent() {
        let maze = Maze::parse("S.\n.T\n").expect("a valid map");
        let frame = render_rgb(&maze, &[Pos::new(1, 0)], 1);
        assert_eq!(frame.get(1, 0), Some(AGENT));
        assert_eq!(frame.get(0, 0), Some(START));
    }
}
