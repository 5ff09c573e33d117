//! Fuzz target: maze text maps through the parser, BFS and a few environment steps with
//! Task I's rewards. Any panic is a bug.
#![no_main]

use eamadm::dql::Environment as _;
use eamadm::mazes::{Maze, MazeEnv, TaskSpec};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(maze) = Maze::parse(text) else {
        return;
    };
    let _ = maze.shortest_path_len();
    let Ok(mut env) = MazeEnv::new(maze, TaskSpec::task1()) else {
        return;
    };
    env.reset(Some(1));
    for step in 0..8 {
        if env.step(step % env.n_actions()).done() {
            break;
        }
    }
});
