//! Grid coordinates and the four moves.
//!
//! Coordinates follow the text map: `x` is the column (0 at the left, growing to the
//! right) and `y` is the row (0 at the top, growing **downwards**, like the lines of a
//! text file and like SVG's y axis). So [`Action::Up`] decreases `y`.

use std::fmt;

use serde::{Deserialize, Serialize};

/// A tile of the grid: column `x` (0 = left) and row `y` (0 = top; `y` grows downwards).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Pos {
    /// Column, 0 at the left edge.
    pub x: usize,
    /// Row, 0 at the top edge; grows downwards.
    pub y: usize,
}

impl Pos {
    /// The tile at column `x`, row `y`.
    #[must_use]
    pub const fn new(x: usize, y: usize) -> Self {
        Self { x, y }
    }

    /// Squared Euclidean distance between tile centres (exact, no rounding).
    #[must_use]
    pub const fn distance_squared(self, other: Self) -> usize {
        let dx = self.x.abs_diff(other.x);
        let dy = self.y.abs_diff(other.y);
        dx * dx + dy * dy
    }

    /// Manhattan (city-block) distance: the fewest moves between the tiles on an empty grid.
    #[must_use]
    pub const fn manhattan(self, other: Self) -> usize {
        self.x.abs_diff(other.x) + self.y.abs_diff(other.y)
    }
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {})", self.x, self.y)
    }
}

/// Number of actions of a maze task.
pub const N_ACTIONS: usize = 4;

/// One move of the agent. The discriminant is the action index used by
/// [`dql::Environment`]: 0 up, 1 down, 2 left, 3 right.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Action {
    /// Towards the top edge: `y − 1`.
    Up = 0,
    /// Towards the bottom edge: `y + 1`.
    Down = 1,
    /// Towards the left edge: `x − 1`.
    Left = 2,
    /// Towards the right edge: `x + 1`.
    Right = 3,
}

impl Action {
    /// All actions, in index order.
    pub const ALL: [Self; N_ACTIONS] = [Self::Up, Self::Down, Self::Left, Self::Right];

    /// The action's index in `0..4`.
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The action with index `index`, or `None` outside `0..4`.
    #[must_use]
    pub const fn from_index(index: usize) -> Option<Self> {
        match index {
            0 => Some(Self::Up),
            1 => Some(Self::Down),
            2 => Some(Self::Left),
            3 => Some(Self::Right),
            _ => None,
        }
    }

    /// Lower-case name: `"up"`, `"down"`, `"left"` or `"right"`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Up => "up",
            Self::Down => "down",
            Self::Left => "left",
            Self::Right => "right",
        }
    }

    /// The tile this action leads to from `from` on a `width × height` grid, ignoring
    /// obstacles; `None` when the move would leave the grid.
    #[must_use]
    pub const fn apply(self, from: Pos, width: usize, height: usize) -> Option<Pos> {
        match self {
            Self::Up if from.y > 0 => Some(Pos::new(from.x, from.y - 1)),
            Self::Down if from.y + 1 < height => Some(Pos::new(from.x, from.y + 1)),
            Self::Left if from.x > 0 => Some(Pos::new(from.x - 1, from.y)),
            Self::Right if from.x + 1 < width => Some(Pos::new(from.x + 1, from.y)),
            _ => None,
        }
    }

    /// The action that moves from `from` to the 4-neighbour `to`, if they are neighbours.
    #[must_use]
    pub const fn between(from: Pos, to: Pos) -> Option<Self> {
        if from.x == to.x && from.y == to.y + 1 {
            Some(Self::Up)
        } else if from.x == to.x && to.y == from.y + 1 {
            Some(Self::Down)
        } else if from.y == to.y && from.x == to.x + 1 {
            Some(Self::Left)
        } else if from.y == to.y && to.x == from.x + 1 {
            Some(Self::Right)
        } else {
            None
        }
    }
}

impl fmt::Display for Action {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
