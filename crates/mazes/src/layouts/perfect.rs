//! Perfect mazes: a spanning tree of cells carved into a solid grid, optionally braided.
//!
//! Cells are the tiles with both coordinates even; the tile between two neighbouring cells is
//! their *edge wall*, open when the tree (or an opening) joins them; tiles with both
//! coordinates odd are always obstacles. A spanning tree joins every cell by exactly one route,
//! so the layout has corridors one tile wide and dead ends; `openings` then opens that many of
//! the remaining edge walls, each adding a loop (and shortening some routes).

use serde::{Deserialize, Serialize};

use super::draw::Draws;
use super::{LayoutError, LayoutKind, check_layout_size};
use crate::geometry::Pos;
use crate::maze::{Maze, check_markers};

/// How the spanning tree of a perfect maze is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MazeAlgorithm {
    /// Randomised depth-first search from the top-left cell (the "recursive backtracker",
    /// with an explicit stack): from the cell on top of the stack, move to an unvisited
    /// neighbour drawn uniformly among them (in the order up, down, left, right), or pop when
    /// there is none. Long winding corridors, few branches: large detours.
    Backtracker,
    /// Wilson's algorithm (*Generating random spanning trees more quickly than the cover
    /// time*, 1996): from each cell not yet in the tree (row-major order; the top-left cell
    /// starts the tree), a random walk (each step to a neighbour drawn uniformly) until it
    /// meets the tree, loop-erased and added. A *uniform* spanning tree: more branching and
    /// shorter routes than the backtracker's.
    Wilson,
}

impl MazeAlgorithm {
    /// `backtracker` or `wilson` (the serde form).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Backtracker => "backtracker",
            Self::Wilson => "wilson",
        }
    }
}

/// A perfect maze ([`LayoutSpec::PerfectMaze`](super::LayoutSpec::PerfectMaze)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerfectMazeParams {
    /// Columns: odd, so that cells sit in the first and the last column.
    pub width: usize,
    /// Rows: odd.
    pub height: usize,
    /// How the spanning tree is drawn.
    pub algorithm: MazeAlgorithm,
    /// Edge walls opened after the tree (0: a perfect maze; each one adds a loop).
    #[serde(default)]
    pub openings: usize,
    /// The start: a cell (both coordinates even).
    pub start: Pos,
    /// The target: a cell.
    pub target: Pos,
}

impl PerfectMazeParams {
    /// A `width × height` maze from the top-left cell to the bottom-right one.
    #[must_use]
    pub const fn corner_to_corner(
        width: usize,
        height: usize,
        algorithm: MazeAlgorithm,
        openings: usize,
    ) -> Self {
        Self {
            width,
            height,
            algorithm,
            openings,
            start: Pos::new(0, 0),
            target: Pos::new(width.saturating_sub(1), height.saturating_sub(1)),
        }
    }

    /// Cells per row and per column: `⌈width/2⌉`, `⌈height/2⌉`.
    const fn cells(&self) -> (usize, usize) {
        (self.width.div_ceil(2), self.height.div_ceil(2))
    }

    /// Edge walls a spanning tree leaves closed: all edges between neighbouring cells minus
    /// (cells − 1). The most `openings` can be.
    #[must_use]
    pub const fn max_openings(&self) -> usize {
        let (cols, rows) = self.cells();
        let edges = (cols.saturating_sub(1)) * rows + cols * (rows.saturating_sub(1));
        (edges + 1).saturating_sub(cols * rows)
    }

    /// `width · height − (2 · cells − 1) − openings`: every tile but the cells, the tree's
    /// `cells − 1` edges and the openings.
    pub(super) const fn obstacle_count(&self) -> usize {
        let (cols, rows) = self.cells();
        self.width * self.height - (2 * cols * rows - 1) - self.openings
    }

    pub(super) fn validate(&self) -> Result<(), LayoutError> {
        check_layout_size(LayoutKind::PerfectMaze, self.width, self.height)?;
        for (field, value) in [("width", self.width), ("height", self.height)] {
            if value.is_multiple_of(2) {
                return Err(LayoutError::EvenSize { field, value });
            }
        }
        check_markers(
            self.width,
            self.height,
            &vec![false; self.width * self.height],
            self.start,
            self.target,
        )?;
        for (what, pos) in [("start", self.start), ("target", self.target)] {
            if !pos.x.is_multiple_of(2) || !pos.y.is_multiple_of(2) {
                return Err(LayoutError::NotOnCell { what, pos });
            }
        }
        if self.openings > self.max_openings() {
            return Err(LayoutError::TooManyOpenings {
                requested: self.openings,
                max: self.max_openings(),
            });
        }
        Ok(())
    }

    /// The maze for `seed` (the params are valid: [`validate`](Self::validate) ran).
    pub(super) fn generate(&self, seed: u64) -> Maze {
        let (cols, rows) = self.cells();
        let mut draws = Draws::seeded(seed);
        let grid = CellGrid { cols, rows };
        let mut open = grid.spanning_tree(self.algorithm, &mut draws);
        let mut closed: Vec<u32> = (0..open.len() as u32)
            .filter(|&edge| !open[edge as usize])
            .collect();
        draws.choose_front(&mut closed, self.openings);
        for &edge in &closed[..self.openings] {
            open[edge as usize] = true;
        }

        let mut obstacle = vec![true; self.width * self.height];
        for cy in 0..rows {
            for cx in 0..cols {
                obstacle[2 * cy * self.width + 2 * cx] = false;
            }
        }
        for (edge, &is_open) in open.iter().enumerate() {
            if is_open {
                let (a, b) = grid.ends(edge);
                let (ax, ay) = (a % cols, a / cols);
                let (bx, by) = (b % cols, b / cols);
                // The wall tile between two cells: the midpoint of their tiles.
                obstacle[(ay + by) * self.width + (ax + bx)] = false;
            }
        }
        let maze =
            Maze::from_parts_unchecked(self.width, self.height, obstacle, self.start, self.target);
        debug_assert!(maze.target_reachable(), "a spanning tree joins every cell");
        maze
    }
}

/// A `cols × rows` grid graph of cells (rooms use it too). Cell `c` is `(c % cols, c / cols)`;
/// edges are numbered left–right pairs first (row by row: `y · (cols − 1) + x` joins `(x, y)`
/// and `(x + 1, y)`), then top–bottom pairs (`H + y · cols + x` joins `(x, y)` and
/// `(x, y + 1)`, with `H = (cols − 1) · rows`).
#[derive(Clone, Copy, Debug)]
pub(super) struct CellGrid {
    pub(super) cols: usize,
    pub(super) rows: usize,
}

impl CellGrid {
    /// Number of left–right edges (they come first).
    pub(super) fn horizontal_edges(self) -> usize {
        (self.cols - 1) * self.rows
    }

    /// Number of edges.
    pub(super) fn edges(self) -> usize {
        self.horizontal_edges() + self.cols * (self.rows - 1)
    }

    /// The two cells an edge joins, the left or upper one first.
    pub(super) fn ends(self, edge: usize) -> (usize, usize) {
        let horizontal = self.horizontal_edges();
        if edge < horizontal {
            let (x, y) = (edge % (self.cols - 1), edge / (self.cols - 1));
            let cell = y * self.cols + x;
            (cell, cell + 1)
        } else {
            let cell = edge - horizontal;
            (cell, cell + self.cols)
        }
    }

    /// The neighbours of `cell` with the edges to them, in the order up, down, left, right.
    fn neighbours(self, cell: usize) -> impl Iterator<Item = (usize, usize)> {
        let (x, y) = (cell % self.cols, cell / self.cols);
        let horizontal = self.horizontal_edges();
        let up = (y > 0).then(|| (cell - self.cols, horizontal + cell - self.cols));
        let down = (y + 1 < self.rows).then(|| (cell + self.cols, horizontal + cell));
        let left = (x > 0).then(|| (cell - 1, y * (self.cols - 1) + x - 1));
        let right = (x + 1 < self.cols).then(|| (cell + 1, y * (self.cols - 1) + x));
        [up, down, left, right].into_iter().flatten()
    }

    /// Which edges a spanning tree drawn by `algorithm` opens.
    pub(super) fn spanning_tree(self, algorithm: MazeAlgorithm, draws: &mut Draws) -> Vec<bool> {
        match algorithm {
            MazeAlgorithm::Backtracker => self.backtracker(draws),
            MazeAlgorithm::Wilson => self.wilson(draws),
        }
    }

    fn backtracker(self, draws: &mut Draws) -> Vec<bool> {
        let cells = self.cols * self.rows;
        let mut open = vec![false; self.edges()];
        let mut visited = vec![false; cells];
        visited[0] = true;
        let mut stack = vec![0_usize];
        while let Some(&cell) = stack.last() {
            let mut options = [(0, 0); 4];
            let mut count = 0;
            for (next, edge) in self.neighbours(cell) {
                if !visited[next] {
                    options[count] = (next, edge);
                    count += 1;
                }
            }
            if count == 0 {
                stack.pop();
                continue;
            }
            let (next, edge) = options[draws.below(count as u32) as usize];
            open[edge] = true;
            visited[next] = true;
            stack.push(next);
        }
        open
    }

    fn wilson(self, draws: &mut Draws) -> Vec<bool> {
        let cells = self.cols * self.rows;
        let mut open = vec![false; self.edges()];
        let mut in_tree = vec![false; cells];
        in_tree[0] = true;
        // The step each walked cell last left by: (next cell, edge). Overwriting it on a
        // revisit erases the loop the walk made since.
        let mut exit = vec![(0, 0); cells];
        for first in 0..cells {
            let mut cell = first;
            while !in_tree[cell] {
                let mut options = [(0, 0); 4];
                let mut count = 0;
                for step in self.neighbours(cell) {
                    options[count] = step;
                    count += 1;
                }
                exit[cell] = options[draws.below(count as u32) as usize];
                cell = exit[cell].0;
            }
            let mut cell = first;
            while !in_tree[cell] {
                in_tree[cell] = true;
                let (next, edge) = exit[cell];
                open[edge] = true;
                cell = next;
            }
        }
        open
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_join_neighbours_both_ways() {
        let grid = CellGrid { cols: 4, rows: 3 };
        for cell in 0..12 {
            for (next, edge) in grid.neighbours(cell) {
                let (a, b) = grid.ends(edge);
                assert_eq!((a.min(b), a.max(b)), (cell.min(next), cell.max(next)));
            }
        }
        assert_eq!(grid.edges(), 3 * 3 + 4 * 2);
    }

    #[test]
    fn both_algorithms_draw_spanning_trees() {
        for algorithm in [MazeAlgorithm::Backtracker, MazeAlgorithm::Wilson] {
            for seed in 0..20 {
                let grid = CellGrid { cols: 5, rows: 4 };
                let open = grid.spanning_tree(algorithm, &mut Draws::seeded(seed));
                // cells − 1 edges that join every cell: a spanning tree.
                assert_eq!(open.iter().filter(|&&o| o).count(), 19);
                let mut root: Vec<usize> = (0..20).collect();
                fn find(root: &mut [usize], c: usize) -> usize {
                    if root[c] == c {
                        c
                    } else {
                        let r = find(root, root[c]);
                        root[c] = r;
                        r
                    }
                }
                for (edge, _) in open.iter().enumerate().filter(|(_, o)| **o) {
                    let (a, b) = grid.ends(edge);
                    let (ra, rb) = (find(&mut root, a), find(&mut root, b));
                    assert_ne!(ra, rb, "{algorithm:?} seed {seed}: a cycle");
                    root[ra] = rb;
                }
            }
        }
    }
}
