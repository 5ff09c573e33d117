//! A maze with a trajectory as plain text, for terminals and snapshot tests.
//!
//! The same characters as the map format (`.` free, `#` obstacle, `S` start, `T`
//! target), one line per row, top row first, each line ending in `\n`; tiles the
//! trajectory visits are drawn as [`PATH_MARK`] (`S` and `T` keep their letters). With an
//! empty trajectory the output is exactly [`Maze::to_text`].

use crate::geometry::Pos;
use crate::map_text::{FREE, OBSTACLE, START, TARGET};
use crate::maze::Maze;

/// The character drawn on a visited free tile.
pub const PATH_MARK: char = '*';

/// Draws `maze` with the tiles of `trajectory` marked by [`PATH_MARK`]. Tiles outside the
/// grid are ignored; a trajectory passing over an obstacle (not a real one) marks it.
#[must_use]
pub fn render_text(maze: &Maze, trajectory: &[Pos]) -> String {
    let mut visited = vec![false; maze.n_tiles()];
    for &pos in trajectory {
        if let Some(state) = maze.state_of(pos) {
            visited[state] = true;
        }
    }
    let mut text = String::with_capacity((maze.width() + 1) * maze.height());
    for y in 0..maze.height() {
        for x in 0..maze.width() {
            let pos = Pos::new(x, y);
            text.push(if pos == maze.start() {
                START
            } else if pos == maze.target() {
                TARGET
            } else if visited[y * maze.width() + x] {
                PATH_MARK
            } else if maze.is_obstacle(pos) {
                OBSTACLE
            } else {
                FREE
            });
        }
        text.push('\n');
    }
    text
}
