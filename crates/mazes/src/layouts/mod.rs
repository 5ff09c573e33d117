//! Layouts with structure: perfect mazes, rooms joined by doors and traps, beside the uniform
//! obstacles of [`generate`](crate::generate), as one seeded [`LayoutSpec`].
//!
//! | kind | what | start → target | obstacles (exact) |
//! |---|---|---|---|
//! | [`Uniform`](LayoutSpec::Uniform) | `obstacles` tiles drawn uniformly ([`generate`](crate::generate)) | as given | `obstacles` |
//! | [`PerfectMaze`](LayoutSpec::PerfectMaze) | corridors one tile wide, dead ends, one route between any two cells, then `openings` extra gaps (loops) | as given, on cells | `w·h − (2·cells − 1) − openings` |
//! | [`Rooms`](LayoutSpec::Rooms) | a `rooms_x × rooms_y` grid of rooms, walls one tile thick, one door per edge of a spanning tree of the rooms plus `extra_doors`, then `obstacles` scattered | top-left → bottom-right | walls − doors + `obstacles` |
//! | [`Trap`](LayoutSpec::Trap) | `walls` vertical walls whose gaps alternate bottom, top, …, so the straight approach along the top row ends at a wall at every other wall, then `obstacles` scattered | top-left → top-right | `walls·(h − gap) + obstacles` |
//!
//! Every layout is described by its **detour ratio**, [`Maze::detour_ratio`]: the BFS optimum
//! divided by the Manhattan distance from start to target (1 when some shortest path is
//! monotone, as in both of the paper's mazes).
//!
//! # Draws (the same layout on every platform)
//!
//! The structured kinds draw from `ChaCha8Rng::seed_from_u64(seed)`, one 32-bit word at a time,
//! with Lemire's multiply-and-reject method for an index below `k`; a choice of `m` out of a
//! list is a partial Fisher–Yates shuffle of the list (in row-major order of its tiles or
//! edges) with such indices. In order:
//!
//! * **Perfect maze** (cells at even coordinates, `⌈w/2⌉ × ⌈h/2⌉` of them): the spanning tree
//!   ([`MazeAlgorithm`]), then the `openings` among the walls between two cells that the tree
//!   left closed.
//! * **Rooms**: a uniform spanning tree of the rooms (Wilson's algorithm over the room grid),
//!   the `extra_doors` among the room pairs it left unjoined, one door tile per joined pair
//!   (in edge order: left–right pairs row by row, then top–bottom pairs), then the scatter.
//! * **Trap**: the wall columns (uniform over the sets of `walls` columns in `1..w−1` with a
//!   free column between any two), then the scatter.
//! * **Scatter**: for each attempt, `obstacles` of the free tiles other than start and target
//!   (partial Fisher–Yates over the same list, kept between attempts, as
//!   [`generate`](crate::generate) does), kept when the target stays reachable.
//!
//! The uniform kind is [`generate`](crate::generate) itself, unchanged, so that the paper's two
//! layouts ([`Preset`](crate::Preset)) are uniform layouts of this family too.
//!
//! # Example
//!
//! ```
//! use mazes::{LayoutSpec, MazeAlgorithm, PerfectMazeParams, TrapParams};
//!
//! let maze = LayoutSpec::PerfectMaze(PerfectMazeParams::corner_to_corner(
//!     9, 7, MazeAlgorithm::Backtracker, 0,
//! ))
//! .generate(3)?;
//! assert_eq!(maze.obstacle_count(), 9 * 7 - (2 * 5 * 4 - 1));
//! assert!(maze.detour_ratio() >= 1.0);
//!
//! // One wall with a one-tile gap at the bottom: down the whole height and back up.
//! let trap = LayoutSpec::Trap(TrapParams::new(7, 5, 1, 1, 0)).generate(0)?;
//! assert_eq!(trap.manhattan_distance(), 6);
//! assert_eq!(trap.shortest_path_len(), 6 + 2 * 4);
//! # Ok::<(), mazes::LayoutError>(())
//! ```

mod draw;
mod perfect;
mod rooms;
mod scatter;
mod trap;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::generate::{DEFAULT_MAX_ATTEMPTS, GeneratorParams, generate_seeded};
use crate::geometry::Pos;
use crate::maze::{Maze, MazeError, check_markers, check_size};

pub use perfect::{MazeAlgorithm, PerfectMazeParams};
pub use rooms::RoomsParams;
pub use trap::TrapParams;

/// The most tiles a structured layout (perfect maze, rooms, trap) may have: 2²⁰, a
/// 1024 × 1024 grid. Generation is linear in the tiles except Wilson's walks, which this cap
/// keeps to a few seconds at worst.
pub const MAX_LAYOUT_TILES: usize = 1 << 20;

/// A layout to generate: its kind and parameters. With a seed it makes one [`Maze`]
/// ([`generate`](Self::generate)); the same spec and seed make the same maze on every platform.
///
/// Serialised with a `kind` tag beside the parameters, e.g.
/// `{"kind": "trap", "width": 30, "height": 30, "walls": 3, "gap": 1, "obstacles": 0}`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LayoutSpec {
    /// Uniform random obstacles ([`generate`](crate::generate)): the paper's layouts.
    Uniform(GeneratorParams),
    /// A perfect maze (corridors and dead ends), optionally braided by `openings`.
    PerfectMaze(PerfectMazeParams),
    /// Rooms joined by doors.
    Rooms(RoomsParams),
    /// Walls across the direct route, each a dead end for the straight approach.
    Trap(TrapParams),
}

/// The kind of a [`LayoutSpec`], as data (the `kind` tag and the family tables' `kind`
/// column).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LayoutKind {
    /// [`LayoutSpec::Uniform`].
    Uniform,
    /// [`LayoutSpec::PerfectMaze`].
    PerfectMaze,
    /// [`LayoutSpec::Rooms`].
    Rooms,
    /// [`LayoutSpec::Trap`].
    Trap,
}

impl LayoutKind {
    /// Every kind, in table order.
    pub const ALL: [Self; 4] = [Self::Uniform, Self::PerfectMaze, Self::Rooms, Self::Trap];

    /// The kind's name: `uniform`, `perfect_maze`, `rooms`, `trap` (its serde form).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Uniform => "uniform",
            Self::PerfectMaze => "perfect_maze",
            Self::Rooms => "rooms",
            Self::Trap => "trap",
        }
    }

    /// The kind for people: `uniform`, `perfect maze`, `rooms`, `trap` (what reports and
    /// figures print; [`name`](Self::name) is the data's).
    #[must_use]
    pub const fn title(self) -> &'static str {
        match self {
            Self::PerfectMaze => "perfect maze",
            other => other.name(),
        }
    }

    /// The kind whose [`name`](Self::name) is `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|kind| kind.name() == name)
    }
}

impl LayoutSpec {
    /// The kind of layout.
    #[must_use]
    pub const fn kind(&self) -> LayoutKind {
        match self {
            Self::Uniform(_) => LayoutKind::Uniform,
            Self::PerfectMaze(_) => LayoutKind::PerfectMaze,
            Self::Rooms(_) => LayoutKind::Rooms,
            Self::Trap(_) => LayoutKind::Trap,
        }
    }

    /// Columns and rows of the grid.
    #[must_use]
    pub const fn size(&self) -> (usize, usize) {
        match self {
            Self::Uniform(p) => (p.width, p.height),
            Self::PerfectMaze(p) => (p.width, p.height),
            Self::Rooms(p) => (p.width, p.height),
            Self::Trap(p) => (p.width, p.height),
        }
    }

    /// The start tile.
    #[must_use]
    pub const fn start(&self) -> Pos {
        match self {
            Self::Uniform(p) => p.start,
            Self::PerfectMaze(p) => p.start,
            Self::Rooms(_) | Self::Trap(_) => Pos::new(0, 0),
        }
    }

    /// The target tile.
    #[must_use]
    pub const fn target(&self) -> Pos {
        match self {
            Self::Uniform(p) => p.target,
            Self::PerfectMaze(p) => p.target,
            Self::Rooms(p) => Pos::new(p.width.saturating_sub(1), p.height.saturating_sub(1)),
            Self::Trap(p) => Pos::new(p.width.saturating_sub(1), 0),
        }
    }

    /// The exact number of obstacle tiles every layout of this spec has (whatever the seed),
    /// or `None` when the spec is invalid ([`validate`](Self::validate) says why).
    #[must_use]
    pub fn obstacle_count(&self) -> Option<usize> {
        self.validate().ok()?;
        Some(match self {
            Self::Uniform(p) => p.obstacles,
            Self::PerfectMaze(p) => p.obstacle_count(),
            Self::Rooms(p) => p.obstacle_count(),
            Self::Trap(p) => p.obstacle_count(),
        })
    }

    /// Checks everything that does not depend on the seed: sizes (at least one row and column,
    /// at most [`MAX_TILES`](crate::MAX_TILES) for the uniform kind and
    /// [`MAX_LAYOUT_TILES`] for the others), start and target, and each kind's own parameters.
    /// What depends on the seed (a reachable target after the scatter, the scatter's feasible
    /// most on a structure that the seed draws) is checked by [`generate`](Self::generate).
    ///
    /// # Errors
    /// The first problem found, as a [`LayoutError`] naming the parameter.
    pub fn validate(&self) -> Result<(), LayoutError> {
        match self {
            Self::Uniform(p) => {
                check_size(p.width, p.height)?;
                check_markers(
                    p.width,
                    p.height,
                    &vec![false; p.width * p.height],
                    p.start,
                    p.target,
                )?;
                if p.obstacles > p.max_obstacles() {
                    return Err(MazeError::TooManyObstacles {
                        requested: p.obstacles,
                        max: p.max_obstacles(),
                    }
                    .into());
                }
                if p.max_attempts == 0 {
                    return Err(MazeError::ZeroAttempts.into());
                }
                Ok(())
            }
            Self::PerfectMaze(p) => p.validate(),
            Self::Rooms(p) => p.validate(),
            Self::Trap(p) => p.validate(),
        }
    }

    /// The layout of this spec for `seed`: a [`Maze`] with the spec's size, start and target,
    /// exactly [`obstacle_count`](Self::obstacle_count) obstacles and a reachable target.
    ///
    /// # Errors
    /// [`validate`](Self::validate)'s errors; for a scatter, more obstacles than the drawn
    /// structure can take while a route stays open ([`MazeError::TooManyObstacles`], inside
    /// [`LayoutError::Maze`]) or no reachable layout within the attempts
    /// ([`MazeError::NoReachableLayout`]).
    pub fn generate(&self, seed: u64) -> Result<Maze, LayoutError> {
        self.validate()?;
        match self {
            Self::Uniform(p) => Ok(generate_seeded(p, seed)?),
            Self::PerfectMaze(p) => Ok(p.generate(seed)),
            Self::Rooms(p) => p.generate(seed),
            Self::Trap(p) => p.generate(seed),
        }
    }
}

impl Maze {
    /// The Manhattan distance from the start to the target: the fewest moves on an empty grid
    /// (at least 1, since they differ).
    #[must_use]
    pub fn manhattan_distance(&self) -> usize {
        self.start().manhattan(self.target())
    }

    /// The **detour ratio**: the BFS optimum ([`shortest_path_len`](Self::shortest_path_len))
    /// divided by the [`manhattan_distance`](Self::manhattan_distance). It is at least 1, and
    /// exactly 1 when a shortest path only ever moves towards the target (both of the paper's
    /// mazes); 3 means the best route is three times the straight-line walk.
    #[must_use]
    pub fn detour_ratio(&self) -> f64 {
        self.shortest_path_len() as f64 / self.manhattan_distance() as f64
    }
}

/// A layout that cannot be made: what was wrong and what to change.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum LayoutError {
    /// A size, marker, obstacle count or attempt bound that no maze can have (shared with
    /// [`generate`](crate::generate)).
    #[error(transparent)]
    Maze(#[from] MazeError),
    /// A structured layout above [`MAX_LAYOUT_TILES`].
    #[error(
        "a {width}×{height} {kind} layout has more than the {max} tiles a structured layout may \
         have; lower `width` or `height`"
    )]
    TooLarge {
        /// The kind's name.
        kind: &'static str,
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
        /// [`MAX_LAYOUT_TILES`].
        max: usize,
    },
    /// A perfect maze with an even width or height: its cells sit on even coordinates, so an
    /// odd size puts a cell in every corner and a wall around none.
    #[error(
        "`{field}` = {value} is even: a perfect maze needs an odd {field} (cells sit on even coordinates)"
    )]
    EvenSize {
        /// `"width"` or `"height"`.
        field: &'static str,
        /// The value given.
        value: usize,
    },
    /// A perfect maze's start or target not on a cell (both coordinates even).
    #[error("the {what} {pos} is not a cell of the perfect maze: both coordinates must be even")]
    NotOnCell {
        /// `"start"` or `"target"`.
        what: &'static str,
        /// The tile given.
        pos: Pos,
    },
    /// More openings than closed walls between cells.
    #[error(
        "`openings` = {requested} is more than the {max} walls between cells that a spanning tree \
         leaves closed"
    )]
    TooManyOpenings {
        /// Requested openings.
        requested: usize,
        /// Closed walls between adjacent cells after the tree.
        max: usize,
    },
    /// Rooms too small for the grid, or zero rooms along an axis.
    #[error(
        "`{field}` = {rooms} rooms do not fit in {size} tiles: each room needs at least 2 tiles \
         inside and one wall tile between rooms ({field} at most {max})"
    )]
    RoomsDoNotFit {
        /// `"rooms_x"` or `"rooms_y"`.
        field: &'static str,
        /// Rooms requested along that axis.
        rooms: usize,
        /// Tiles along that axis (`width` or `height`).
        size: usize,
        /// The most rooms that fit (0 when even one does not).
        max: usize,
    },
    /// A rooms layout with fewer than two rooms.
    #[error("`rooms_x` × `rooms_y` = {rooms}: a rooms layout needs at least 2 rooms")]
    TooFewRooms {
        /// `rooms_x · rooms_y`.
        rooms: usize,
    },
    /// More extra doors than room pairs left unjoined by the spanning tree.
    #[error(
        "`extra_doors` = {requested} is more than the {max} pairs of neighbouring rooms a \
         spanning tree leaves without a door"
    )]
    TooManyDoors {
        /// Requested extra doors.
        requested: usize,
        /// Neighbouring room pairs minus (rooms − 1).
        max: usize,
    },
    /// A trap whose walls do not fit across its width.
    #[error(
        "`walls` = {walls} does not fit a width of {width}: walls stand in columns 1..width−1 with \
         a free column between two (walls in 1..={max})"
    )]
    WallsDoNotFit {
        /// Requested walls.
        walls: usize,
        /// The grid's width.
        width: usize,
        /// The most walls that fit (`(width − 1) / 2`).
        max: usize,
    },
    /// A trap gap outside `1..height`.
    #[error("`gap` = {gap} must be in 1..={max} (height {height}): a wall needs a gap and a tile")]
    GapOutOfRange {
        /// The gap given.
        gap: usize,
        /// The grid's height.
        height: usize,
        /// `height − 1`.
        max: usize,
    },
}

/// Size checks of the structured kinds: non-empty, at most [`MAX_LAYOUT_TILES`].
fn check_layout_size(kind: LayoutKind, width: usize, height: usize) -> Result<(), LayoutError> {
    check_size(width, height)?;
    if width * height > MAX_LAYOUT_TILES {
        return Err(LayoutError::TooLarge {
            kind: kind.name(),
            width,
            height,
            max: MAX_LAYOUT_TILES,
        });
    }
    Ok(())
}

fn default_max_attempts() -> u32 {
    DEFAULT_MAX_ATTEMPTS
}
