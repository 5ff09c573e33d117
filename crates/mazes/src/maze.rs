//! The maze: a grid of free and obstacle tiles with one start and one target.

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::geometry::{Action, Pos};
use crate::reward::Event;

/// The largest number of tiles a maze may have (4096 × 4096). State indices and the
/// environment's transition table then fit comfortably in `u32`.
pub const MAX_TILES: usize = 1 << 24;

/// A rectangular grid maze: obstacle tiles, a start and a reachable target.
///
/// Invariants (checked by every constructor): the grid is non-empty and has at most
/// [`MAX_TILES`] tiles; start and target are distinct free tiles inside the grid; the
/// target can be reached from the start by up/down/left/right moves over free tiles.
///
/// A tile's *state index* is `y * width + x` (row-major, `y` growing downwards; see
/// [`Pos`]). It serialises (serde) as its text map ([`Maze::to_text`]).
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct Maze {
    width: usize,
    height: usize,
    /// `obstacle[y * width + x]` is `true` for an obstacle tile.
    obstacle: Vec<bool>,
    start: Pos,
    target: Pos,
}

impl Maze {
    /// Builds a maze from its obstacle tiles (repeats are the same tile).
    ///
    /// # Errors
    ///
    /// A [`MazeError`] naming the offending parameter when the size is zero or above
    /// [`MAX_TILES`], a tile lies outside the grid, start and target coincide or sit on
    /// an obstacle, or the target is unreachable.
    pub fn new(
        width: usize,
        height: usize,
        obstacles: impl IntoIterator<Item = Pos>,
        start: Pos,
        target: Pos,
    ) -> Result<Self, MazeError> {
        check_size(width, height)?;
        let mut obstacle = vec![false; width * height];
        for pos in obstacles {
            if pos.x >= width || pos.y >= height {
                return Err(MazeError::OutOfBounds {
                    what: "obstacle",
                    pos,
                    width,
                    height,
                });
            }
            obstacle[pos.y * width + pos.x] = true;
        }
        check_markers(width, height, &obstacle, start, target)?;
        let maze = Self::from_parts_unchecked(width, height, obstacle, start, target);
        if maze.target_reachable() {
            Ok(maze)
        } else {
            Err(MazeError::UnreachableTarget { start, target })
        }
    }

    /// Assembles a maze whose size and markers the caller has already checked; the
    /// reachability of the target is *not* implied and must be checked next.
    pub(crate) fn from_parts_unchecked(
        width: usize,
        height: usize,
        obstacle: Vec<bool>,
        start: Pos,
        target: Pos,
    ) -> Self {
        debug_assert_eq!(obstacle.len(), width * height);
        Self {
            width,
            height,
            obstacle,
            start,
            target,
        }
    }

    /// Number of columns.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of rows.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// Number of tiles, `width × height` (also the number of states of the task).
    #[must_use]
    pub fn n_tiles(&self) -> usize {
        self.obstacle.len()
    }

    /// The start tile.
    #[must_use]
    pub fn start(&self) -> Pos {
        self.start
    }

    /// The target tile.
    #[must_use]
    pub fn target(&self) -> Pos {
        self.target
    }

    /// `true` for a tile inside the grid.
    #[must_use]
    pub fn contains(&self, pos: Pos) -> bool {
        pos.x < self.width && pos.y < self.height
    }

    /// `true` for an obstacle tile inside the grid.
    #[must_use]
    pub fn is_obstacle(&self, pos: Pos) -> bool {
        self.state_of(pos).is_some_and(|state| self.obstacle[state])
    }

    /// `true` for a tile inside the grid that is not an obstacle.
    #[must_use]
    pub fn is_free(&self, pos: Pos) -> bool {
        self.state_of(pos)
            .is_some_and(|state| !self.obstacle[state])
    }

    /// Number of obstacle tiles.
    #[must_use]
    pub fn obstacle_count(&self) -> usize {
        self.obstacle.iter().filter(|&&blocked| blocked).count()
    }

    /// The obstacle tiles in row-major order.
    pub fn obstacles(&self) -> impl Iterator<Item = Pos> + '_ {
        self.obstacle
            .iter()
            .enumerate()
            .filter(|&(_, &blocked)| blocked)
            .map(|(state, _)| self.pos_unchecked(state))
    }

    /// The state index `y * width + x` of `pos`, or `None` outside the grid.
    #[must_use]
    pub fn state_of(&self, pos: Pos) -> Option<usize> {
        self.contains(pos).then(|| pos.y * self.width + pos.x)
    }

    /// The tile of state index `state`, or `None` when `state >= n_tiles()`.
    #[must_use]
    pub fn pos_of(&self, state: usize) -> Option<Pos> {
        (state < self.n_tiles()).then(|| self.pos_unchecked(state))
    }

    fn pos_unchecked(&self, state: usize) -> Pos {
        Pos::new(state % self.width, state / self.width)
    }

    /// Where `action` takes an agent standing on `from`: the neighbouring tile, or `from`
    /// itself when the move is blocked by an obstacle or the outer wall (a bump).
    #[must_use]
    pub fn successor(&self, from: Pos, action: Action) -> Pos {
        match action.apply(from, self.width, self.height) {
            Some(next) if self.is_free(next) => next,
            _ => from,
        }
    }

    /// The reference dynamics: the successor of `(from, action)` and the [`Event`] the
    /// move is (target, bump, closer or farther, in that order of precedence).
    #[must_use]
    pub fn transition(&self, from: Pos, action: Action) -> (Pos, Event) {
        let next = self.successor(from, action);
        let event = if next == self.target {
            Event::Target
        } else if next == from {
            Event::Bump
        } else if next.distance_squared(self.target) < from.distance_squared(self.target) {
            Event::Closer
        } else {
            Event::Farther
        };
        (next, event)
    }

    /// The free 4-neighbours of `pos`, in action order (up, down, left, right).
    pub fn free_neighbours(&self, pos: Pos) -> impl Iterator<Item = (Action, Pos)> + '_ {
        Action::ALL.into_iter().filter_map(move |action| {
            action
                .apply(pos, self.width, self.height)
                .filter(|&next| self.is_free(next))
                .map(|next| (action, next))
        })
    }

    /// The text map of this maze (see the crate docs for the format): one line per row,
    /// each ending in `\n`, no comments. [`Maze::parse`] inverts it exactly.
    #[must_use]
    pub fn to_text(&self) -> String {
        let mut text = String::with_capacity((self.width + 1) * self.height);
        for y in 0..self.height {
            for x in 0..self.width {
                let pos = Pos::new(x, y);
                text.push(if pos == self.start {
                    crate::map_text::START
                } else if pos == self.target {
                    crate::map_text::TARGET
                } else if self.obstacle[y * self.width + x] {
                    crate::map_text::OBSTACLE
                } else {
                    crate::map_text::FREE
                });
            }
            text.push('\n');
        }
        text
    }
}

impl std::fmt::Display for Maze {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.to_text())
    }
}

impl std::str::FromStr for Maze {
    type Err = crate::map_text::ParseError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::parse(text)
    }
}

impl TryFrom<String> for Maze {
    type Error = crate::map_text::ParseError;

    fn try_from(text: String) -> Result<Self, Self::Error> {
        Self::parse(&text)
    }
}

impl From<Maze> for String {
    fn from(maze: Maze) -> Self {
        maze.to_text()
    }
}

pub(crate) fn check_size(width: usize, height: usize) -> Result<(), MazeError> {
    if width == 0 || height == 0 {
        return Err(MazeError::EmptyGrid { width, height });
    }
    match width.checked_mul(height) {
        Some(tiles) if tiles <= MAX_TILES => Ok(()),
        _ => Err(MazeError::TooLarge { width, height }),
    }
}

/// Start and target inside the grid, distinct, and (given a grid) not on obstacles.
pub(crate) fn check_markers(
    width: usize,
    height: usize,
    obstacle: &[bool],
    start: Pos,
    target: Pos,
) -> Result<(), MazeError> {
    for (what, pos) in [("start", start), ("target", target)] {
        if pos.x >= width || pos.y >= height {
            return Err(MazeError::OutOfBounds {
                what,
                pos,
                width,
                height,
            });
        }
        if obstacle[pos.y * width + pos.x] {
            return Err(MazeError::OnObstacle { what, pos });
        }
    }
    if start == target {
        return Err(MazeError::StartIsTarget { pos: start });
    }
    Ok(())
}

/// A maze (or a request to generate one) that cannot exist.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum MazeError {
    /// `width` or `height` is 0.
    #[error("a maze needs at least one row and one column, got width {width} and height {height}")]
    EmptyGrid {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
    },
    /// More than [`MAX_TILES`] tiles.
    #[error("a {width}×{height} maze has more than the {MAX_TILES} tiles allowed")]
    TooLarge {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
    },
    /// A tile lies outside the grid.
    #[error("the {what} {pos} lies outside the {width}×{height} grid")]
    OutOfBounds {
        /// `"start"`, `"target"` or `"obstacle"`.
        what: &'static str,
        /// The offending tile.
        pos: Pos,
        /// Grid width.
        width: usize,
        /// Grid height.
        height: usize,
    },
    /// The start or the target is an obstacle tile.
    #[error("the {what} {pos} is an obstacle tile")]
    OnObstacle {
        /// `"start"` or `"target"`.
        what: &'static str,
        /// The offending tile.
        pos: Pos,
    },
    /// Start and target are the same tile.
    #[error("start and target are the same tile {pos}")]
    StartIsTarget {
        /// The shared tile.
        pos: Pos,
    },
    /// No path of free tiles leads from the start to the target.
    #[error("the target {target} cannot be reached from the start {start}")]
    UnreachableTarget {
        /// The start tile.
        start: Pos,
        /// The target tile.
        target: Pos,
    },
    /// Generation: more obstacles than can be placed while keeping the target reachable.
    #[error(
        "`obstacles` = {requested} is more than the {max} that fit while keeping a path \
         from start to target open"
    )]
    TooManyObstacles {
        /// Requested obstacle count.
        requested: usize,
        /// The most obstacles any layout with a reachable target can hold:
        /// tiles − (Manhattan distance from start to target + 1).
        max: usize,
    },
    /// Generation: `max_attempts` is 0.
    #[error("`max_attempts` must be at least 1, got 0")]
    ZeroAttempts,
    /// Generation: every attempt left the target unreachable.
    #[error(
        "no layout with a reachable target after {attempts} attempts; lower `obstacles` or \
         raise `max_attempts`"
    )]
    NoReachableLayout {
        /// Attempts made.
        attempts: u32,
    },
}
