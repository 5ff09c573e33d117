//! Breadth-first search: shortest paths, the optimum every learning curve is compared with.
//!
//! Neighbours are expanded in action order (up, down, left, right), so among several
//! shortest paths the one returned is fixed by the layout alone.

use std::collections::VecDeque;

use crate::geometry::Pos;
use crate::maze::Maze;

/// Marks a tile BFS has not reached.
const UNSEEN: u32 = u32::MAX;

impl Maze {
    /// Number of moves of a shortest path from the start to the target.
    #[must_use]
    pub fn shortest_path_len(&self) -> usize {
        self.shortest_path().len() - 1
    }

    /// A shortest path from the start to the target, both included (so it has
    /// `shortest_path_len() + 1` tiles). Among equally short paths, BFS in action order
    /// decides, so the answer depends on the layout only.
    #[must_use]
    pub fn shortest_path(&self) -> Vec<Pos> {
        self.shortest_path_between(self.start(), self.target())
            .expect("a Maze's target is reachable by construction")
    }

    /// A shortest path of free tiles from `from` to `to`, both included, or `None` when
    /// either is not a free tile or `to` cannot be reached.
    #[must_use]
    pub fn shortest_path_between(&self, from: Pos, to: Pos) -> Option<Vec<Pos>> {
        let parent = self.bfs(from, Some(to))?;
        let goal = self.state_of(to)?;
        if parent[goal] == UNSEEN {
            return None;
        }
        let source = self.state_of(from)?;
        let mut path = vec![to];
        let mut state = goal;
        while state != source {
            state = parent[state] as usize;
            path.push(self.pos_of(state)?);
        }
        path.reverse();
        Some(path)
    }

    /// Fewest moves from `from` to every tile, indexed by state (`y * width + x`);
    /// `None` for obstacles and unreachable tiles. All `None` when `from` is not free.
    #[must_use]
    pub fn distances_from(&self, from: Pos) -> Vec<Option<usize>> {
        let mut distance = vec![None; self.n_tiles()];
        let Some(source) = self.state_of(from).filter(|_| self.is_free(from)) else {
            return distance;
        };
        distance[source] = Some(0);
        let mut queue = VecDeque::from([from]);
        while let Some(pos) = queue.pop_front() {
            let here = distance[pos.y * self.width() + pos.x].unwrap_or(0);
            for (_, next) in self.free_neighbours(pos) {
                let slot = &mut distance[next.y * self.width() + next.x];
                if slot.is_none() {
                    *slot = Some(here + 1);
                    queue.push_back(next);
                }
            }
        }
        distance
    }

    /// `true` when the target can be reached from the start.
    pub(crate) fn target_reachable(&self) -> bool {
        let target = self.target();
        self.bfs(self.start(), Some(target))
            .zip(self.state_of(target))
            .is_some_and(|(parent, goal)| parent[goal] != UNSEEN)
    }

    /// BFS from `from` (stopping early at `stop_at`): the parent state of every reached
    /// tile (`from` is its own parent), [`UNSEEN`] elsewhere. `None` if `from` is not free.
    fn bfs(&self, from: Pos, stop_at: Option<Pos>) -> Option<Vec<u32>> {
        let source = self.state_of(from).filter(|_| self.is_free(from))?;
        let mut parent = vec![UNSEEN; self.n_tiles()];
        // `n_tiles() <= MAX_TILES < u32::MAX`, so every state index fits in a u32.
        parent[source] = source as u32;
        let mut queue = VecDeque::from([from]);
        while let Some(pos) = queue.pop_front() {
            if Some(pos) == stop_at {
                break;
            }
            let here = (pos.y * self.width() + pos.x) as u32;
            for (_, next) in self.free_neighbours(pos) {
                let slot = &mut parent[next.y * self.width() + next.x];
                if *slot == UNSEEN {
                    *slot = here;
                    queue.push_back(next);
                }
            }
        }
        Some(parent)
    }
}
