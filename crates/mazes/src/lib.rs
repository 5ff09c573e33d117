//! Grid-maze tasks (Task I and Task II of the EA-MADM paper, Sec. VI.A) for tabular
//! reinforcement learning.
//!
//! A [`Maze`] is a `width × height` grid of free and obstacle tiles with one start and one
//! reachable target. The agent moves up, down, left or right; a move into an obstacle or
//! the outer wall is a *bump* and the agent stays. [`MazeEnv`] turns a maze and a
//! [`TaskSpec`] (rewards as data, sub-tasks, step cap) into a [`dql::Environment`].
//! Around it: a plain-text map format ([`Maze::parse`], [`Maze::to_text`]), seeded
//! generation ([`generate`], [`generate_seeded`]; structured layouts with [`LayoutSpec`]),
//! the paper's two tasks as [`Preset`]s
//! frozen under `fixtures/mazes/`, BFS shortest paths ([`Maze::shortest_path`], the
//! optimum every learning curve is compared with), and rendering as text
//! ([`render_text`]) and SVG ([`render_svg`], the analogue of the paper's Fig. 6 and 9).
//!
//! # Coordinates, states and actions
//!
//! A tile is a [`Pos`] `{ x, y }`: `x` is the column (0 at the left), `y` the row (0 at
//! the **top**, growing downwards, like the lines of the text map and SVG's y axis). The
//! state index of a tile is `y * width + x`; [`dql::Environment::state_features`] is
//! `[x, y]`. Actions are `0` up (`y − 1`), `1` down (`y + 1`), `2` left (`x − 1`) and
//! `3` right (`x + 1`) ([`Action`]). Every tile is a state, obstacles included; the agent
//! never stands on one.
//!
//! # Map format
//!
//! One character per tile, one line per row, top row first:
//!
//! | character | tile |
//! |---|---|
//! | `.` | free |
//! | `#` | obstacle |
//! | `S` | the start (free), exactly once |
//! | `T` | the target (free), exactly once, reachable from `S` |
//!
//! A line whose first character is `;` is a comment and is skipped wherever it appears
//! (the fixture files use this for their header). Lines end in `\n` (`\r\n` is accepted);
//! the final newline is optional. All rows must have the same, non-zero length; blank
//! lines are errors. [`Maze::to_text`] writes the canonical form — `\n` after every row,
//! so the text ends with a newline, and no comments — and [`Maze::parse`] inverts it
//! exactly: `parse(to_text(m)) == m`, and `to_text(parse(t)) == t` for canonical `t`.
//! Errors ([`ParseError`]) carry the line and column (1-based, comment lines counted):
//! unknown character, ragged row, empty row, empty map, missing or repeated `S`/`T`, map
//! too large, unreachable target. A [`Maze`] serialises (serde) as its map text.
//!
//! # Rewards
//!
//! Every transition is one [`Event`], judged by the Euclidean distance between tile
//! centres (compared exactly, as squared integers): *target* (the move reached the
//! target; the episode terminates), *bump* (the move was blocked; the agent stays),
//! *closer* (the distance to the target shrank), *farther* (it did not; a one-tile move
//! always changes the distance). A [`RewardScheme`] gives one reward per event:
//!
//! | scheme | closer | farther | bump | target |
//! |---|---|---|---|---|
//! | Task I ([`RewardScheme::TASK_I`]) | +1 | −1 | −100 | +100 |
//! | Task II ([`RewardScheme::TASK_II`]) | −1 | −1 | −1 | +10 |
//! | reach faster, Task I ([`RewardScheme::REACH_FASTER_TASK_I`]) | +1 | −1 | −1 | +100 |
//! | reach faster, Task II ([`RewardScheme::REACH_FASTER_TASK_II`]) | +1 | −1 | −1 | +10 |
//! | do not hit ([`RewardScheme::DO_NOT_HIT`], both tasks) | 0 | 0 | −100 | 0 |
//!
//! Task I is the paper's rule read literally: +1 if the Euclidean distance shrinks, −1
//! otherwise, −100 (instead of −1) for a bump, +100 (instead of +1) at the target. Task II
//! says "+10 at the target, otherwise −1"; read literally, a bump is an "otherwise" step
//! and pays −1 too.
//!
//! The paper decomposes both tasks into the sub-tasks "reach the target faster" and "do
//! not hit obstacles" without giving their rewards. Ours ([`TaskSpec::task1`],
//! [`TaskSpec::task2`]; the order of [`dql::Environment::subtask_rewards`]):
//!
//! * **reach the target faster** — the distance shaping alone: +1 closer, −1 otherwise
//!   (a bump leaves the distance unchanged, so it pays −1), plus the task's own target
//!   bonus (+100 in Task I, +10 in Task II). Without the −100 a learner of this sub-task
//!   is not taught anything about obstacles beyond "a wasted step", which is the point.
//! * **do not hit obstacles** — −100 for a bump, 0 for every other step (the paper's only
//!   bump penalty, Task I's, also used by the robot's Eq. 7). Its learned values mark
//!   exactly which actions bump (≈ −100) and leave every other action at 0.
//!
//! Each is learnable on its own in the same environment (same dynamics, same
//! termination at the target): on both presets, the optimal policy of "reach the target
//! faster" (value iteration, γ = 0.95) walks a BFS-shortest path without a bump, and the
//! optimal values of "do not hit obstacles" are exactly −100 on the bumping actions and 0
//! on all others (`tests/subtasks.rs`). In Task I the two add up to the task's reward on every
//! event except a bump, where the sum is −101 instead of −100. All schemes are plain data
//! (serde), so any other decomposition is one config away.
//!
//! # Episodes
//!
//! Episodes start on `S`. Reaching `T` *terminates* the episode; the step cap (default
//! 2000, Sec. VI.A) *truncates* it. The task is deterministic: the seed of `reset` is
//! ignored. A step allocates nothing: [`MazeEnv`] precomputes each tile's successor and
//! event per action.
//!
//! # Presets
//!
//! [`Preset::Task1`]: 30 × 30, 100 obstacles (the paper); [`Preset::Task2`]: 39 × 36, 156
//! obstacles (the paper gives no count; 156 keeps Task I's density of 1/9). Start in the
//! top-left corner, target in the bottom-right one. Layouts are generated with fixed
//! seeds and frozen as `fixtures/mazes/task1.map` and `task2.map`
//! ([`Preset::fixture_text`] writes their exact content).
//!
//! The positive control of the reproduction, `aggregation-control`, is a hand-designed map
//! ([`AGGREGATION_CONTROL_MAP`]): the target in a walled box whose only door faces away from
//! the start, so that distance shaping alone walks into the wall (BFS 64 moves against a
//! Manhattan distance of 24).
//!
//! # Exact values
//!
//! A maze is small and deterministic, so its exact optimal action values are computable:
//! [`MazeEnv::model`] gives the task as a [`dql::DeterministicModel`] paying any
//! [`RewardScheme`] (the task's, [`MazeEnv::task_model`], or a sub-task's,
//! [`MazeEnv::subtask_model`]), and [`dql::value_iteration`] solves it. The learners converge
//! to those values (`tests/it/model.rs`).
//!
//! # Example
//!
//! ```
//! use dql::Environment;
//! use mazes::{Action, Event, Maze, MazeEnv, TaskSpec, render_text};
//!
//! let maze = Maze::parse(
//!     "S.#\n\
//!      .#.\n\
//!      ..T\n",
//! )?;
//! assert_eq!(maze.shortest_path_len(), 4);
//!
//! let mut env = MazeEnv::new(maze.clone(), TaskSpec::task1())?;
//! let state = env.reset(None);
//! assert_eq!(env.state_features(state), vec![0, 0]);
//!
//! // Up from the top-left corner bumps the outer wall: the agent stays, −100.
//! let step = env.step(Action::Up.index());
//! assert_eq!((step.next_state, step.reward), (state, -100.0));
//! assert_eq!(env.subtask_rewards(), &[-1.0, -100.0]);
//!
//! // Down, down, right, right: closer, closer, closer, target.
//! let mut trajectory = vec![maze.start()];
//! for action in [Action::Down, Action::Down, Action::Right, Action::Right] {
//!     let step = env.step(action.index());
//!     trajectory.push(env.position());
//!     if step.terminated {
//!         assert_eq!(env.last_event(), Some(Event::Target));
//!         assert_eq!(step.reward, 100.0);
//!     }
//! }
//! assert_eq!(render_text(&maze, &trajectory), "S.#\n*#.\n**T\n");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Layouts with structure
//!
//! The paper's layouts are uniform random obstacles, and both of ours sit at the Manhattan
//! bound: some shortest path only ever moves towards the target, so distance shaping alone is
//! optimal there. A [`LayoutSpec`] also makes layouts where it is not, each from a seed and
//! the same on every platform: a perfect maze ([`PerfectMazeParams`], corridors and dead ends
//! drawn by the recursive backtracker or Wilson's algorithm, optionally braided), rooms joined
//! by doors ([`RoomsParams`]) and a trap ([`TrapParams`]: walls across the direct route whose
//! gaps lie at the far end). Every spec promises an exact obstacle count
//! ([`LayoutSpec::obstacle_count`]) and a reachable target; bad parameters are a
//! [`LayoutError`] naming the field. A layout is described by its detour ratio,
//! [`Maze::detour_ratio`]: the BFS optimum over the Manhattan distance.
//!
//! ```
//! use mazes::{LayoutSpec, MazeAlgorithm, PerfectMazeParams, RoomsParams, TrapParams};
//!
//! let perfect = PerfectMazeParams::corner_to_corner(9, 9, MazeAlgorithm::Wilson, 0);
//! let maze = LayoutSpec::PerfectMaze(perfect).generate(7)?;
//! // 25 cells joined by 24 open walls; every other tile is an obstacle.
//! assert_eq!(maze.obstacle_count(), 81 - 49);
//! assert_eq!(maze.manhattan_distance(), 16);
//!
//! let rooms = LayoutSpec::Rooms(RoomsParams::new(11, 11, 2, 2, 0, 5));
//! assert_eq!(rooms.obstacle_count(), Some(11 + 11 - 1 - 3 + 5));
//! assert_eq!(rooms.generate(1)?.obstacle_count(), 23);
//!
//! // A wall down from the top row with its gap at the bottom: the trap's route goes round it.
//! let trap = LayoutSpec::Trap(TrapParams::new(5, 4, 1, 1, 0)).generate(0)?;
//! assert_eq!(trap.detour_ratio(), (4.0 + 2.0 * 3.0) / 4.0);
//!
//! // Parameters that cannot work are refused, naming the field.
//! let even = PerfectMazeParams::corner_to_corner(10, 9, MazeAlgorithm::Backtracker, 0);
//! let error = LayoutSpec::PerfectMaze(even).generate(0).unwrap_err();
//! assert!(error.to_string().starts_with("`width` = 10 is even"));
//! # Ok::<(), mazes::LayoutError>(())
//! ```
//!
//! # Paper references
//!
//! Sec. VI.A (Task I: 30 × 30 tiles, 100 obstacles, the ±1/−100/+100 reward, cap 2000;
//! Task II: 39 × 36, +10/−1; the sub-tasks "reach the target faster" and "do not hit
//! obstacles"; trajectories in Fig. 6 and 9).

mod control;
mod env;
mod generate;
mod geometry;
pub mod layouts;
pub mod map_text;
mod maze;
mod path;
mod presets;
mod render_rgb;
mod render_svg;
mod render_text;
mod reward;

pub use control::{
    AGGREGATION_CONTROL_FIXTURE, AGGREGATION_CONTROL_MAP, aggregation_control_fixture_text,
    aggregation_control_maze,
};
pub use env::{EpisodeError, MazeCursor, MazeEnv};
pub use generate::{DEFAULT_MAX_ATTEMPTS, GeneratorParams, generate, generate_seeded};
pub use geometry::{Action, N_ACTIONS, Pos};
pub use layouts::{
    LayoutError, LayoutKind, LayoutSpec, MAX_LAYOUT_TILES, MazeAlgorithm, PerfectMazeParams,
    RoomsParams, TrapParams,
};
pub use map_text::{Marker, ParseError};
pub use maze::{MAX_TILES, Maze, MazeError};
pub use presets::{FIXTURE_DIR, Preset};
pub use render_rgb::{TILE_PIXELS, render_rgb};
pub use render_svg::{PALETTE, SvgOptions, SvgTrajectory, render_svg};
pub use render_text::{PATH_MARK, render_text};
pub use reward::{
    DEFAULT_STEP_CAP, DO_NOT_HIT_NAME, Event, MAX_ABS_REWARD, MAX_STEP_CAP, REACH_FASTER_NAME,
    RewardScheme, SpecError, Subtask, TaskSpec,
};
