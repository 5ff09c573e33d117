//! BFS shortest paths against brute force, and `Maze::new`'s checks.

use crate::common;

use mazes::{Action, Maze, MazeError, Pos};
use proptest::prelude::*;

/// Fewest moves from start to target by exhaustive depth-first search over all simple
/// paths (no tile twice): exponential, fine on 16 tiles.
fn brute_force_len(maze: &Maze) -> Option<usize> {
    fn search(maze: &Maze, at: Pos, visited: &mut Vec<Pos>, best: &mut Option<usize>) {
        if at == maze.target() {
            let moves = visited.len() - 1;
            *best = Some(best.map_or(moves, |b| b.min(moves)));
            return;
        }
        for action in Action::ALL {
            let next = maze.successor(at, action);
            if next != at && !visited.contains(&next) {
                visited.push(next);
                search(maze, next, visited, best);
                visited.pop();
            }
        }
    }
    let mut best = None;
    search(maze, maze.start(), &mut vec![maze.start()], &mut best);
    best
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// BFS's length equals the exhaustive minimum.
    #[test]
    fn bfs_length_equals_brute_force(maze in common::small_maze(4)) {
        prop_assert_eq!(Some(maze.shortest_path_len()), brute_force_len(&maze));
    }

    /// The path is a walk of free neighbours from start to target, of the stated length,
    /// and agrees with `distances_from`.
    #[test]
    fn the_path_is_a_valid_walk(maze in common::small_maze(9)) {
        let path = maze.shortest_path();
        prop_assert_eq!(path.len(), maze.shortest_path_len() + 1);
        prop_assert_eq!(path[0], maze.start());
        prop_assert_eq!(*path.last().unwrap(), maze.target());
        for pair in path.windows(2) {
            let action = Action::between(pair[0], pair[1]);
            prop_assert!(action.is_some(), "{:?} is not a move", pair);
            prop_assert_eq!(maze.successor(pair[0], action.unwrap()), pair[1]);
        }
        let distances = maze.distances_from(maze.start());
        let target = maze.state_of(maze.target()).unwrap();
        prop_assert_eq!(distances[target], Some(maze.shortest_path_len()));
        for (state, distance) in distances.iter().enumerate() {
            let pos = maze.pos_of(state).unwrap();
            prop_assert_eq!(distance.is_some(), maze.shortest_path_between(maze.start(), pos).is_some());
        }
    }
}

#[test]
fn shortest_path_on_a_known_maze() {
    let maze = Maze::parse(
        "S.#..\n\
         .##.#\n\
         ....T\n",
    )
    .unwrap();
    assert_eq!(maze.shortest_path_len(), 6);
    assert_eq!(
        maze.shortest_path(),
        [(0, 0), (0, 1), (0, 2), (1, 2), (2, 2), (3, 2), (4, 2)].map(|(x, y)| Pos::new(x, y))
    );
    assert_eq!(
        maze.shortest_path_between(Pos::new(3, 0), Pos::new(2, 0)),
        None
    );
    assert_eq!(
        maze.shortest_path_between(Pos::new(9, 9), maze.target()),
        None
    );
    assert!(
        maze.distances_from(Pos::new(2, 0))
            .iter()
            .all(Option::is_none)
    );
}

#[test]
fn new_checks_every_invariant() {
    let (s, t) = (Pos::new(0, 0), Pos::new(2, 1));
    assert!(Maze::new(3, 2, [Pos::new(1, 0), Pos::new(1, 0)], s, t).is_ok());
    assert_eq!(
        Maze::new(3, 0, [], s, t),
        Err(MazeError::EmptyGrid {
            width: 3,
            height: 0
        })
    );
    assert_eq!(
        Maze::new(3, 2, [Pos::new(3, 1)], s, t),
        Err(MazeError::OutOfBounds {
            what: "obstacle",
            pos: Pos::new(3, 1),
            width: 3,
            height: 2
        })
    );
    assert_eq!(
        Maze::new(3, 2, [t], s, t),
        Err(MazeError::OnObstacle {
            what: "target",
            pos: t
        })
    );
    assert_eq!(
        Maze::new(3, 2, [s], s, t),
        Err(MazeError::OnObstacle {
            what: "start",
            pos: s
        })
    );
    assert_eq!(
        Maze::new(3, 2, [Pos::new(1, 0), Pos::new(1, 1)], s, t),
        Err(MazeError::UnreachableTarget {
            start: s,
            target: t
        })
    );
    assert_eq!(
        Maze::new(3, 2, [Pos::new(1, 0), Pos::new(1, 1)], s, t)
            .unwrap_err()
            .to_string(),
        "the target (2, 1) cannot be reached from the start (0, 0)"
    );
}
