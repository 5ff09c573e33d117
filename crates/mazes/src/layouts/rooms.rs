//! Rooms joined by doors: a grid of rectangular rooms with walls one tile thick between them,
//! a door (one free wall tile) between the rooms of each edge of a uniform spanning tree of
//! the rooms and of `extra_doors` more pairs, then obstacles scattered inside.
//!
//! Room sizes: the `width − (rooms_x − 1)` tiles left by the walls are shared out as evenly as
//! possible, the first rooms one tile wider when they do not divide (likewise down the
//! height). The start is the top-left tile, the target the bottom-right tile.

use serde::{Deserialize, Serialize};

use super::draw::Draws;
use super::perfect::{CellGrid, MazeAlgorithm};
use super::scatter::scatter;
use super::{LayoutError, LayoutKind, check_layout_size, default_max_attempts};
use crate::generate::DEFAULT_MAX_ATTEMPTS;
use crate::geometry::Pos;
use crate::maze::Maze;

/// Rooms joined by doors ([`LayoutSpec::Rooms`](super::LayoutSpec::Rooms)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoomsParams {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Rooms across (at least 1; each at least 2 tiles wide inside).
    pub rooms_x: usize,
    /// Rooms down (at least 1; each at least 2 tiles high inside).
    pub rooms_y: usize,
    /// Doors beyond the spanning tree's `rooms − 1` (each adds a loop between rooms).
    #[serde(default)]
    pub extra_doors: usize,
    /// Obstacles scattered over the rooms' free tiles after the doors.
    #[serde(default)]
    pub obstacles: usize,
    /// Scatter attempts before giving up.
    #[serde(default = "default_max_attempts")]
    pub max_attempts: u32,
}

impl RoomsParams {
    /// `rooms_x × rooms_y` rooms on a `width × height` grid, `extra_doors` beyond the tree,
    /// `obstacles` scattered, [`DEFAULT_MAX_ATTEMPTS`] attempts.
    #[must_use]
    pub const fn new(
        width: usize,
        height: usize,
        rooms_x: usize,
        rooms_y: usize,
        extra_doors: usize,
        obstacles: usize,
    ) -> Self {
        Self {
            width,
            height,
            rooms_x,
            rooms_y,
            extra_doors,
            obstacles,
            max_attempts: DEFAULT_MAX_ATTEMPTS,
        }
    }

    /// Neighbouring room pairs the spanning tree leaves without a door: the most
    /// `extra_doors` can be.
    #[must_use]
    pub fn max_extra_doors(&self) -> usize {
        let grid = CellGrid {
            cols: self.rooms_x.max(1),
            rows: self.rooms_y.max(1),
        };
        (grid.edges() + 1).saturating_sub(grid.cols * grid.rows)
    }

    /// Wall tiles (`(rooms_x − 1)` columns and `(rooms_y − 1)` rows, crossings counted once)
    /// minus the doors, plus the scatter.
    pub(super) fn obstacle_count(&self) -> usize {
        let walls = (self.rooms_x - 1) * self.height + (self.rooms_y - 1) * self.width
            - (self.rooms_x - 1) * (self.rooms_y - 1);
        let doors = self.rooms_x * self.rooms_y - 1 + self.extra_doors;
        walls - doors + self.obstacles
    }

    pub(super) fn validate(&self) -> Result<(), LayoutError> {
        check_layout_size(LayoutKind::Rooms, self.width, self.height)?;
        for (field, rooms, size) in [
            ("rooms_x", self.rooms_x, self.width),
            ("rooms_y", self.rooms_y, self.height),
        ] {
            // r rooms need 2r inside tiles and r − 1 walls: 3r − 1 ≤ size.
            let max = (size + 1) / 3;
            if rooms == 0 || rooms > max {
                return Err(LayoutError::RoomsDoNotFit {
                    field,
                    rooms,
                    size,
                    max,
                });
            }
        }
        if self.rooms_x * self.rooms_y < 2 {
            return Err(LayoutError::TooFewRooms {
                rooms: self.rooms_x * self.rooms_y,
            });
        }
        if self.extra_doors > self.max_extra_doors() {
            return Err(LayoutError::TooManyDoors {
                requested: self.extra_doors,
                max: self.max_extra_doors(),
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
        let (xs, wall_xs) = split(width, self.rooms_x);
        let (ys, wall_ys) = split(height, self.rooms_y);
        let mut obstacle = vec![false; width * height];
        for &x in &wall_xs {
            for y in 0..height {
                obstacle[y * width + x] = true;
            }
        }
        for &y in &wall_ys {
            for x in 0..width {
                obstacle[y * width + x] = true;
            }
        }

        let mut draws = Draws::seeded(seed);
        let grid = CellGrid {
            cols: self.rooms_x,
            rows: self.rooms_y,
        };
        let mut open = grid.spanning_tree(MazeAlgorithm::Wilson, &mut draws);
        let mut closed: Vec<u32> = (0..open.len() as u32)
            .filter(|&edge| !open[edge as usize])
            .collect();
        draws.choose_front(&mut closed, self.extra_doors);
        for &edge in &closed[..self.extra_doors] {
            open[edge as usize] = true;
        }
        for (edge, &is_open) in open.iter().enumerate() {
            if !is_open {
                continue;
            }
            let (a, _) = grid.ends(edge);
            let (ax, ay) = (a % grid.cols, a / grid.cols);
            let door = if edge < grid.horizontal_edges() {
                // Left–right pair: a tile of the wall column beside room a, in room a's rows.
                let (y0, rows) = ys[ay];
                Pos::new(wall_xs[ax], y0 + draws.below(rows as u32) as usize)
            } else {
                // Top–bottom pair: a tile of the wall row below room a, in room a's columns.
                let (x0, cols) = xs[ax];
                Pos::new(x0 + draws.below(cols as u32) as usize, wall_ys[ay])
            };
            obstacle[door.y * width + door.x] = false;
        }
        let structure = Maze::from_parts_unchecked(
            width,
            height,
            obstacle,
            Pos::new(0, 0),
            Pos::new(width - 1, height - 1),
        );
        debug_assert!(structure.target_reachable(), "the doors join every room");
        scatter(structure, self.obstacles, self.max_attempts, &mut draws)
    }
}

/// The rooms along one axis of `size` tiles: each room's first tile and extent, and the wall
/// after each room but the last. The `size − (rooms − 1)` inside tiles are shared out evenly,
/// the first `remainder` rooms one tile larger.
fn split(size: usize, rooms: usize) -> (Vec<(usize, usize)>, Vec<usize>) {
    let inside = size - (rooms - 1);
    let (base, extra) = (inside / rooms, inside % rooms);
    let mut spans = Vec::with_capacity(rooms);
    let mut walls = Vec::with_capacity(rooms - 1);
    let mut at = 0;
    for room in 0..rooms {
        let extent = base + usize::from(room < extra);
        spans.push((at, extent));
        at += extent;
        if room + 1 < rooms {
            walls.push(at);
            at += 1;
        }
    }
    (spans, walls)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rooms_share_the_axis_evenly() {
        assert_eq!(
            split(30, 3),
            (vec![(0, 10), (11, 9), (21, 9)], vec![10, 20])
        );
        assert_eq!(split(5, 2), (vec![(0, 2), (3, 2)], vec![2]));
        assert_eq!(split(7, 1), (vec![(0, 7)], vec![]));
    }
}
