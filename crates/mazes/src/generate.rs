//! Seeded random layouts: exactly the requested number of obstacles, a reachable target.
//!
//! Each attempt draws the obstacle tiles uniformly without replacement from the tiles
//! other than start and target (a partial Fisher–Yates shuffle with `u32` draws, so the
//! layout for a seed is the same on every platform) and keeps the first layout whose
//! target BFS reaches. Attempts are bounded by
//! [`max_attempts`](GeneratorParams::max_attempts).

use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::geometry::Pos;
use crate::maze::{Maze, MazeError, check_markers, check_size};

/// The default bound on generation attempts.
pub const DEFAULT_MAX_ATTEMPTS: u32 = 1000;

/// What to generate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeneratorParams {
    /// Number of columns.
    pub width: usize,
    /// Number of rows.
    pub height: usize,
    /// Exact number of obstacle tiles.
    pub obstacles: usize,
    /// The start tile.
    pub start: Pos,
    /// The target tile.
    pub target: Pos,
    /// How many random layouts to try before giving up.
    #[serde(default = "default_max_attempts")]
    pub max_attempts: u32,
}

fn default_max_attempts() -> u32 {
    DEFAULT_MAX_ATTEMPTS
}

impl GeneratorParams {
    /// A `width × height` maze with `obstacles` obstacles, start in the top-left corner
    /// `(0, 0)` and target in the bottom-right corner `(width − 1, height − 1)`,
    /// [`DEFAULT_MAX_ATTEMPTS`] attempts. (With a zero size the corners saturate at 0;
    /// generation then reports the size error.)
    #[must_use]
    pub const fn corner_to_corner(width: usize, height: usize, obstacles: usize) -> Self {
        Self {
            width,
            height,
            obstacles,
            start: Pos::new(0, 0),
            target: Pos::new(width.saturating_sub(1), height.saturating_sub(1)),
            max_attempts: DEFAULT_MAX_ATTEMPTS,
        }
    }

    /// The most obstacles a layout with these size, start and target can hold while the
    /// target stays reachable: tiles − (Manhattan distance + 1), the tiles of one
    /// monotone path. Every count up to it is feasible.
    #[must_use]
    pub fn max_obstacles(&self) -> usize {
        (self.width * self.height).saturating_sub(self.start.manhattan(self.target) + 1)
    }
}

/// Generates a maze from `params`, drawing from `rng`.
///
/// # Errors
///
/// [`MazeError`] for a zero or too large size, start/target outside the grid or equal,
/// more obstacles than [`GeneratorParams::max_obstacles`]
/// ([`MazeError::TooManyObstacles`]), `max_attempts == 0`, or no reachable layout within
/// `max_attempts` attempts ([`MazeError::NoReachableLayout`]).
pub fn generate<R: Rng + ?Sized>(params: &GeneratorParams, rng: &mut R) -> Result<Maze, MazeError> {
    let GeneratorParams {
        width,
        height,
        obstacles,
        start,
        target,
        max_attempts,
    } = *params;
    check_size(width, height)?;
    let n_tiles = width * height;
    check_markers(width, height, &vec![false; n_tiles], start, target)?;
    if obstacles > params.max_obstacles() {
        return Err(MazeError::TooManyObstacles {
            requested: obstacles,
            max: params.max_obstacles(),
        });
    }
    if max_attempts == 0 {
        return Err(MazeError::ZeroAttempts);
    }

    let start_state = start.y * width + start.x;
    let target_state = target.y * width + target.x;
    // `n_tiles <= MAX_TILES < u32::MAX`: every index fits in a u32.
    let mut candidates: Vec<u32> = (0..n_tiles as u32)
        .filter(|&state| state as usize != start_state && state as usize != target_state)
        .collect();
    let n_candidates = candidates.len() as u32;
    for _ in 0..max_attempts {
        for i in 0..obstacles as u32 {
            let j = rng.random_range(i..n_candidates);
            candidates.swap(i as usize, j as usize);
        }
        let mut grid = vec![false; n_tiles];
        for &state in &candidates[..obstacles] {
            grid[state as usize] = true;
        }
        let maze = Maze::from_parts_unchecked(width, height, grid, start, target);
        if maze.target_reachable() {
            return Ok(maze);
        }
    }
    Err(MazeError::NoReachableLayout {
        attempts: max_attempts,
    })
}

/// [`generate`] with a `ChaCha8Rng` seeded by `seed` (`SeedableRng::seed_from_u64`).
///
/// # Errors
///
/// As [`generate`].
pub fn generate_seeded(params: &GeneratorParams, seed: u64) -> Result<Maze, MazeError> {
    generate(params, &mut ChaCha8Rng::seed_from_u64(seed))
}
