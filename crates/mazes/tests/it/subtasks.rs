//! The sub-task decomposition is sound: each sub-task's optimal policy (value iteration,
//! γ = 0.95 as in Table 1) achieves that sub-task's goal on the preset mazes, and the
//! task's own optimal policy reaches the target without bumping.

use mazes::{Action, Event, Maze, MazeEnv, Pos, Preset, RewardScheme, TaskSpec};

const GAMMA: f64 = 0.95;

/// Optimal action values under `scheme` on `maze`'s dynamics, the target terminal: the
/// library's model and value iteration.
fn optimal_q(maze: &Maze, scheme: &RewardScheme) -> Vec<[f64; 4]> {
    let env = MazeEnv::new(maze.clone(), TaskSpec::task1()).expect("task I's spec is valid");
    let model = env.model(scheme).expect("the presets' schemes are valid");
    let q = dql::value_iteration(&model, GAMMA, 1e-10).expect("γ < 1").q;
    (0..maze.n_tiles())
        .map(|s| [q.get(s, 0), q.get(s, 1), q.get(s, 2), q.get(s, 3)])
        .collect()
}

/// Follows the greedy policy (first best action) from the start for at most `limit`
/// steps: the tiles visited and the number of bumps.
fn greedy_rollout(maze: &Maze, q: &[[f64; 4]], limit: usize) -> (Vec<Pos>, usize) {
    let mut at = maze.start();
    let mut path = vec![at];
    let mut bumps = 0;
    while at != maze.target() && path.len() <= limit {
        let row = q[maze.state_of(at).expect("the agent stays on the grid")];
        let best = (0..4).fold(0, |best, a| if row[a] > row[best] { a } else { best });
        let (next, event) = maze.transition(at, Action::ALL[best]);
        bumps += usize::from(event == Event::Bump);
        at = next;
        path.push(at);
    }
    (path, bumps)
}

#[test]
fn reach_faster_alone_leads_to_the_target() {
    for preset in Preset::ALL {
        let maze = preset.maze();
        let spec = preset.task_spec();
        let q = optimal_q(&maze, &spec.subtasks[0].reward);
        let (path, bumps) = greedy_rollout(&maze, &q, 2000);
        assert_eq!(path.last(), Some(&maze.target()), "{preset:?}");
        assert_eq!(bumps, 0, "{preset:?}");
        assert_eq!(path.len() - 1, maze.shortest_path_len(), "{preset:?}");
    }
}

#[test]
fn do_not_hit_alone_marks_exactly_the_bumping_actions() {
    for preset in Preset::ALL {
        let maze = preset.maze();
        let q = optimal_q(&maze, &preset.task_spec().subtasks[1].reward);
        let reachable = maze.distances_from(maze.start());
        for state in 0..maze.n_tiles() {
            let from = maze.pos_of(state).unwrap();
            // Enclosed free tiles (every move bumps) are never visited; skip them.
            if reachable[state].is_none() || from == maze.target() {
                continue;
            }
            for action in Action::ALL {
                let bumps = maze.transition(from, action).1 == Event::Bump;
                let expected = if bumps { -100.0 } else { 0.0 };
                assert_eq!(
                    q[state][action.index()],
                    expected,
                    "{preset:?} {from} {action}"
                );
            }
        }
    }
}

#[test]
fn the_task_itself_is_solved_by_a_shortest_path() {
    for preset in Preset::ALL {
        let maze = preset.maze();
        let q = optimal_q(&maze, &preset.task_spec().reward);
        let (path, bumps) = greedy_rollout(&maze, &q, 2000);
        assert_eq!(path.last(), Some(&maze.target()), "{preset:?}");
        assert_eq!(bumps, 0, "{preset:?}");
        assert_eq!(path.len() - 1, maze.shortest_path_len(), "{preset:?}");
    }
}
