//! Obstacles scattered uniformly over a structure's free tiles, keeping the target reachable.

use super::LayoutError;
use super::draw::Draws;
use crate::geometry::Pos;
use crate::maze::{Maze, MazeError};

/// Places exactly `count` obstacles on the free tiles of `obstacle` other than `start` and
/// `target`, uniformly, and returns the first layout (of at most `max_attempts`) whose target
/// stays reachable. The structure must already join start and target.
///
/// # Errors
/// [`MazeError::TooManyObstacles`] when `count` exceeds the free tiles off one shortest route
/// (more cannot leave a route open: any route has at least as many tiles as the shortest),
/// [`MazeError::ZeroAttempts`], [`MazeError::NoReachableLayout`].
pub(super) fn scatter(
    structure: Maze,
    count: usize,
    max_attempts: u32,
    draws: &mut Draws,
) -> Result<Maze, LayoutError> {
    if count == 0 {
        return Ok(structure);
    }
    if max_attempts == 0 {
        return Err(MazeError::ZeroAttempts.into());
    }
    let (width, height) = (structure.width(), structure.height());
    let (start, target) = (structure.start(), structure.target());
    let mut candidates: Vec<u32> = (0..width * height)
        .filter(|&state| {
            let pos = Pos::new(state % width, state / width);
            structure.is_free(pos) && pos != start && pos != target
        })
        .map(|state| state as u32)
        .collect();
    let max = candidates.len() + 1 - structure.shortest_path_len();
    if count > max {
        return Err(MazeError::TooManyObstacles {
            requested: count,
            max,
        }
        .into());
    }
    let base: Vec<bool> = (0..width * height)
        .map(|state| structure.is_obstacle(Pos::new(state % width, state / width)))
        .collect();
    for _ in 0..max_attempts {
        draws.choose_front(&mut candidates, count);
        let mut obstacle = base.clone();
        for &state in &candidates[..count] {
            obstacle[state as usize] = true;
        }
        let maze = Maze::from_parts_unchecked(width, height, obstacle, start, target);
        if maze.target_reachable() {
            return Ok(maze);
        }
    }
    Err(MazeError::NoReachableLayout {
        attempts: max_attempts,
    }
    .into())
}
