//! Traps: walls across the direct route, each leaving a gap at the far end.
//!
//! The start is the top-left tile and the target the top-right one, so the direct route runs
//! along the top row. `walls` vertical walls stand in distinct columns of `1..width − 1`,
//! with at least one free column between two of them; the first (leftmost) reaches down from
//! the top row and leaves its `gap` at the bottom, the second reaches up from the bottom row
//! and leaves its gap at the top, and so on. Walking straight at the target along the top
//! row (what a distance-shaped reward pays for) ends at the first wall, a dead end; the route
//! goes down to the gap and back up, and again at every other wall. With `gap = 1` and no
//! scatter the optimum is `(width − 1) + 2⌈walls/2⌉ (height − 1)`, a detour ratio of about
//! `1 + 2⌈walls/2⌉ (height − 1)/(width − 1)`.

use serde::{Deserialize, Serialize};

use super::draw::Draws;
use super::scatter::scatter;
use super::{LayoutError, LayoutKind, check_layout_size, default_max_attempts};
use crate::generate::DEFAULT_MAX_ATTEMPTS;
use crate::geometry::Pos;
use crate::maze::Maze;

/// A trap layout ([`LayoutSpec::Trap`](super::LayoutSpec::Trap)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrapParams {
    /// Columns (at least `2 · walls + 1`).
    pub width: usize,
    /// Rows (at least 2).
    pub height: usize,
    /// Walls across the route (at least 1).
    pub walls: usize,
    /// Free tiles at the open end of each wall, in `1..height`.
    pub gap: usize,
    /// Obstacles scattered over the free tiles after the walls.
    #[serde(default)]
    pub obstacles: usize,
    /// Scatter attempts before giving up.
    #[serde(default = "default_max_attempts")]
    pub max_attempts: u32,
}

impl TrapParams {
    /// `walls` walls with gaps of `gap` tiles on a `width × height` grid, `obstacles`
    /// scattered, [`DEFAULT_MAX_ATTEMPTS`] attempts.
    #[must_use]
    pub const fn new(
        width: usize,
        height: usize,
        walls: usize,
        gap: usize,
        obstacles: usize,
    ) -> Self {
        Self {
            width,
            height,
            walls,
            gap,
            obstacles,
            max_attempts: DEFAULT_MAX_ATTEMPTS,
        }
    }

    /// The most walls a width takes: `(width − 1) / 2` (columns `1..width − 1`, a free column
    /// between two walls).
    #[must_use]
    pub const fn max_walls(&self) -> usize {
        self.width.saturating_sub(1) / 2
    }

    /// `walls · (height − gap) + obstacles`.
    pub(super) const fn obstacle_count(&self) -> usize {
        self.walls * (self.height - self.gap) + self.obstacles
    }

    pub(super) fn validate(&self) -> Result<(), LayoutError> {
        check_layout_size(LayoutKind::Trap, self.width, self.height)?;
        if self.walls == 0 || self.walls > self.max_walls() {
            return Err(LayoutError::WallsDoNotFit {
                walls: self.walls,
                width: self.width,
                max: self.max_walls(),
            });
        }
        if self.gap == 0 || self.gap >= self.height {
            return Err(LayoutError::GapOutOfRange {
                gap: self.gap,
                height: self.height,
                max: self.height - 1,
            });
        }
        if self.obstacles > 0 && self.max_attempts == 0 {
            return Err(crate::maze::MazeError::ZeroAttempts.into());
        }
        Ok(())
    }

    /// The layout for `seed` (the params are valid).
    pub(super) fn generate(&self, seed: u64) -> Result<Maze, LayoutError> {
        let (width, height) = (self.width, self.height);
        let mut draws = Draws::seeded(seed);
        // Sets of `walls` columns in 1..=width−2, two apart at least, are in one-to-one
        // correspondence with sets of `walls` values in 0..slots (column = 1 + value + rank).
        let slots = width - 2 - (self.walls - 1);
        let mut values: Vec<u32> = (0..slots as u32).collect();
        draws.choose_front(&mut values, self.walls);
        let mut chosen = values[..self.walls].to_vec();
        chosen.sort_unstable();
        let mut obstacle = vec![false; width * height];
        for (rank, &value) in chosen.iter().enumerate() {
            let x = 1 + value as usize + rank;
            let rows = if rank % 2 == 0 {
                0..height - self.gap
            } else {
                self.gap..height
            };
            for y in rows {
                obstacle[y * width + x] = true;
            }
        }
        let structure = Maze::from_parts_unchecked(
            width,
            height,
            obstacle,
            Pos::new(0, 0),
            Pos::new(width - 1, 0),
        );
        debug_assert!(structure.target_reachable(), "every wall leaves a gap");
        scatter(structure, self.obstacles, self.max_attempts, &mut draws)
    }
}
