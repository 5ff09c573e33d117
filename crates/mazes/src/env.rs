//! The maze as a [`dql::Environment`]: task reward, sub-task rewards, termination, step cap.
//!
//! Construction precomputes, for every tile and action, the successor state and the
//! [`Event`] of the move, packed in one `u32`; the task's reward per event; and one row
//! of sub-task rewards per event, plus an all-zero row for "no step yet". A step is then
//! two table loads and two comparisons: it copies no rewards and allocates nothing, and
//! `subtask_rewards()` returns the row of the last step's event.

use dql::{DeterministicModel, Environment, Step, Transition};

use crate::geometry::{Action, N_ACTIONS, Pos};
use crate::maze::Maze;
use crate::reward::{Event, RewardScheme, SpecError, TaskSpec};

/// The low bits of a packed transition hold the event.
const EVENT_BITS: u32 = 2;
const EVENT_MASK: u32 = (1 << EVENT_BITS) - 1;
/// `last_event` before the first step of an episode (the index of the all-zero row).
const NO_EVENT: u32 = Event::COUNT as u32;

/// A saved episode that cannot be put back on a maze ([`MazeEnv::set_episode`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EpisodeError {
    /// The position is outside the grid or on an obstacle.
    #[error("the agent cannot stand on ({x}, {y}): not a free tile of this maze")]
    Position {
        /// Column.
        x: usize,
        /// Row from the top.
        y: usize,
    },
    /// A last event without a step, or steps without a last event.
    #[error("{steps} steps and the last event disagree (an event needs a step, a step an event)")]
    Steps {
        /// The steps given.
        steps: u32,
    },
}

/// A maze task: states are tiles (`y * width + x`), actions are [`Action`] indices
/// (0 up, 1 down, 2 left, 3 right; `y` grows downwards).
///
/// * Every episode starts on the maze's start tile; the task is deterministic, so the
///   seed passed to [`reset`](Environment::reset) is ignored (there is no random stream).
/// * A move into an obstacle or the outer wall is a bump: the agent stays.
/// * Reaching the target *terminates* the episode; the step cap *truncates* it.
/// * [`subtask_rewards`](Environment::subtask_rewards) holds one reward per sub-task of
///   the [`TaskSpec`], in its order (for the presets: "reach the target faster", then
///   "do not hit obstacles"); before the first step of an episode, all zeros.
/// * `n_states()` counts every tile, obstacles included (the agent never occupies them).
/// * `state_features(s)` is `[x, y]`.
#[derive(Clone)]
pub struct MazeEnv {
    maze: Maze,
    spec: TaskSpec,
    /// `transitions[state][action] = next_state << 2 | event index`.
    transitions: Vec<[u32; N_ACTIONS]>,
    /// The task's reward, by event index.
    task_rewards: [f64; Event::COUNT],
    /// Row `event` (length `n_subtasks`) holds each sub-task's reward for that event;
    /// row [`NO_EVENT`] is all zeros.
    subtask_rows: Vec<f64>,
    n_subtasks: usize,
    step_cap: u32,
    start: u32,
    /// Where the current episode stands.
    cursor: MazeCursor,
}

/// Where one episode of a maze stands: the agent's tile, the steps taken and the last step's
/// event. [`MazeEnv`] keeps one for its own episode; a batch of episodes on the same maze (a
/// vector environment) keeps one each and steps them with [`MazeEnv::step_cursor`], sharing
/// the maze's tables instead of copying them per episode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MazeCursor {
    position: u32,
    steps: u32,
    /// Event index of the last step, or [`NO_EVENT`].
    last_event: u32,
}

impl MazeCursor {
    /// The agent's state index (`y * width + x`).
    #[must_use]
    pub fn state(&self) -> usize {
        self.position as usize
    }

    /// Steps taken in the episode.
    #[must_use]
    pub fn steps(&self) -> u32 {
        self.steps
    }
}

impl MazeEnv {
    /// A maze task with the given rewards, sub-tasks and step cap.
    ///
    /// # Errors
    ///
    /// [`SpecError`] when `spec` fails [`TaskSpec::validate`].
    pub fn new(maze: Maze, spec: TaskSpec) -> Result<Self, SpecError> {
        spec.validate()?;
        let transitions = (0..maze.n_tiles())
            .map(|state| {
                let from = maze.pos_of(state).expect("state < n_tiles");
                Action::ALL.map(|action| {
                    let (next, event) = maze.transition(from, action);
                    let next = maze
                        .state_of(next)
                        .expect("successors stay inside the grid");
                    // `next < MAX_TILES = 2^24`, so shifting by 2 bits cannot overflow.
                    (next as u32) << EVENT_BITS | event.index() as u32
                })
            })
            .collect();
        let subtask_rows = Event::ALL
            .iter()
            .flat_map(|&event| {
                spec.subtasks
                    .iter()
                    .map(move |sub| sub.reward.reward(event))
            })
            .chain(spec.subtasks.iter().map(|_| 0.0))
            .collect();
        let start = maze
            .state_of(maze.start())
            .expect("the start is inside the grid") as u32;
        Ok(Self {
            transitions,
            task_rewards: spec.reward.by_event(),
            subtask_rows,
            n_subtasks: spec.subtasks.len(),
            step_cap: spec.step_cap,
            start,
            cursor: MazeCursor {
                position: start,
                steps: 0,
                last_event: NO_EVENT,
            },
            maze,
            spec,
        })
    }

    /// The maze.
    #[must_use]
    pub fn maze(&self) -> &Maze {
        &self.maze
    }

    /// The rewards, sub-tasks and step cap.
    #[must_use]
    pub fn spec(&self) -> &TaskSpec {
        &self.spec
    }

    /// The agent's tile.
    #[must_use]
    pub fn position(&self) -> Pos {
        self.cursor_position(&self.cursor)
    }

    /// The agent's state index (`y * width + x`).
    #[must_use]
    pub fn state(&self) -> usize {
        self.cursor.state()
    }

    /// Steps taken in the current episode.
    #[must_use]
    pub fn steps(&self) -> u32 {
        self.cursor.steps
    }

    /// What the last step was (`None` before the first step of an episode). Counting
    /// [`Event::Bump`]s gives an episode's collisions.
    #[must_use]
    pub fn last_event(&self) -> Option<Event> {
        self.cursor_last_event(&self.cursor)
    }

    /// The maze as a [`dql::DeterministicModel`] paying `scheme` for each step's [`Event`]:
    /// the same states (every tile), actions and successors as the environment, each step
    /// paying `scheme.reward(event)`, and a step onto the target terminal (reaching it ends the
    /// episode). The step cap is not part of it: it truncates, and the learners bootstrap on a
    /// truncated step, so their fixed point is this model's infinite-horizon `Q*`
    /// ([`dql::value_iteration`]). Tiles the agent never stands on (obstacles, the target)
    /// keep the environment's moves out of them, so their values are those of starting there.
    ///
    /// # Errors
    /// [`SpecError`] when `scheme` has a reward that is not finite or too large
    /// ([`RewardScheme::validate`], field `scheme`).
    pub fn model(&self, scheme: &RewardScheme) -> Result<DeterministicModel, SpecError> {
        scheme.validate("scheme")?;
        let rewards = scheme.by_event();
        let transitions = self
            .transitions
            .iter()
            .flat_map(|row| row.iter())
            .map(|&packed| {
                let event = (packed & EVENT_MASK) as usize;
                Transition {
                    next: (packed >> EVENT_BITS) as usize,
                    reward: rewards[event],
                    terminal: event == Event::Target.index(),
                }
            })
            .collect();
        Ok(
            DeterministicModel::new(self.maze.n_tiles(), N_ACTIONS, transitions)
                .expect("successors are tiles and the validated rewards are finite"),
        )
    }

    /// The model of the task's own reward ([`model`](Self::model) of `spec().reward`).
    #[must_use]
    pub fn task_model(&self) -> DeterministicModel {
        self.model(&self.spec.reward)
            .expect("the spec was validated when the environment was made")
    }

    /// The model of sub-task `k`'s reward ([`model`](Self::model) of its scheme); `None` when
    /// the task has no sub-task `k`.
    #[must_use]
    pub fn subtask_model(&self, k: usize) -> Option<DeterministicModel> {
        self.spec.subtasks.get(k).map(|subtask| {
            self.model(&subtask.reward)
                .expect("the spec was validated when the environment was made")
        })
    }

    /// A new episode's cursor: on the start tile, no step taken.
    #[must_use]
    pub fn start_cursor(&self) -> MazeCursor {
        MazeCursor {
            position: self.start,
            steps: 0,
            last_event: NO_EVENT,
        }
    }

    /// One step of the episode `cursor` on this maze: what [`Environment::step`] does to the
    /// environment's own episode (which it implements), for an episode kept outside.
    ///
    /// # Panics
    ///
    /// When `action >= 4` (a caller bug, as the trait allows).
    #[inline]
    pub fn step_cursor(&self, cursor: &mut MazeCursor, action: usize) -> Step {
        let packed = self.transitions[cursor.position as usize][action];
        let event = packed & EVENT_MASK;
        cursor.position = packed >> EVENT_BITS;
        cursor.last_event = event;
        cursor.steps = cursor.steps.saturating_add(1);
        let terminated = event == Event::Target as u32;
        Step {
            next_state: cursor.position as usize,
            reward: self.task_rewards[event as usize],
            terminated,
            truncated: !terminated && cursor.steps >= self.step_cap,
        }
    }

    /// Where the current episode stands: the agent's tile, the steps taken and the last
    /// step's event (to save an episode; [`set_episode`](Self::set_episode) puts it back).
    #[must_use]
    pub fn episode(&self) -> (Pos, u32, Option<Event>) {
        (self.position(), self.steps(), self.last_event())
    }

    /// Puts the current episode where a saved one stood ([`episode`](Self::episode)): the
    /// agent on `position` after `steps` steps, the last of which was `last_event` (`None`
    /// for an episode without a step yet). The next steps are those the saved episode would
    /// have taken, bit for bit.
    ///
    /// # Errors
    ///
    /// [`EpisodeError`] (and nothing changes) when the agent cannot stand on `position` (not
    /// a tile of this maze, or an obstacle), or when `steps` and `last_event` disagree (a
    /// last event without a step, or steps without one).
    pub fn set_episode(
        &mut self,
        position: Pos,
        steps: u32,
        last_event: Option<Event>,
    ) -> Result<(), EpisodeError> {
        let state = self
            .maze
            .state_of(position)
            .filter(|_| !self.maze.is_obstacle(position))
            .ok_or(EpisodeError::Position {
                x: position.x,
                y: position.y,
            })?;
        if (steps == 0) != last_event.is_none() {
            return Err(EpisodeError::Steps { steps });
        }
        self.cursor = MazeCursor {
            // A tile index is below `MAX_TILES = 2^24`.
            position: state as u32,
            steps,
            last_event: last_event.map_or(NO_EVENT, |event| event.index() as u32),
        };
        Ok(())
    }

    /// The sub-task rewards of `cursor`'s last step (all zeros before its first).
    #[inline]
    #[must_use]
    pub fn cursor_subtask_rewards(&self, cursor: &MazeCursor) -> &[f64] {
        let start = cursor.last_event as usize * self.n_subtasks;
        &self.subtask_rows[start..start + self.n_subtasks]
    }

    /// The tile of `cursor`'s agent.
    #[must_use]
    pub fn cursor_position(&self, cursor: &MazeCursor) -> Pos {
        self.maze
            .pos_of(cursor.position as usize)
            .expect("the position is always a tile of the maze")
    }

    /// What `cursor`'s last step was (`None` before its first).
    #[must_use]
    pub fn cursor_last_event(&self, cursor: &MazeCursor) -> Option<Event> {
        Event::ALL.get(cursor.last_event as usize).copied()
    }
}

impl Environment for MazeEnv {
    fn n_states(&self) -> usize {
        self.maze.n_tiles()
    }

    fn n_actions(&self) -> usize {
        N_ACTIONS
    }

    fn n_subtasks(&self) -> usize {
        self.n_subtasks
    }

    fn subtask_names(&self) -> Vec<String> {
        self.spec
            .subtasks
            .iter()
            .map(|sub| sub.name.clone())
            .collect()
    }

    /// Puts the agent on the start tile; `seed` is ignored (the task is deterministic).
    fn reset(&mut self, _seed: Option<u64>) -> usize {
        self.cursor = self.start_cursor();
        self.start as usize
    }

    /// # Panics
    ///
    /// When `action >= 4` (a caller bug, as the trait allows).
    #[inline]
    fn step(&mut self, action: usize) -> Step {
        let mut cursor = self.cursor;
        let step = self.step_cursor(&mut cursor, action);
        self.cursor = cursor;
        step
    }

    #[inline]
    fn subtask_rewards(&self) -> &[f64] {
        self.cursor_subtask_rewards(&self.cursor)
    }

    /// `[x, y]`: the tile's column and row.
    fn state_features(&self, state: usize) -> Vec<u32> {
        let width = self.maze.width();
        [state % width, state / width]
            .map(|value| u32::try_from(value).unwrap_or(u32::MAX))
            .to_vec()
    }
}

impl std::fmt::Debug for MazeEnv {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MazeEnv")
            .field("width", &self.maze.width())
            .field("height", &self.maze.height())
            .field("spec", &self.spec)
            .field("position", &self.position())
            .field("steps", &self.cursor.steps)
            .field("last_event", &self.last_event())
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Preset;

    /// An episode kept in a cursor walks exactly like the environment's own episode.
    #[test]
    fn a_cursor_steps_like_the_environment() {
        let mut env = Preset::Task1.env();
        let shared = env.clone();
        let mut cursor = shared.start_cursor();
        env.reset(None);
        for i in 0..500_usize {
            let action = (i * 7 + i / 3) % N_ACTIONS;
            let own = env.step(action);
            let kept = shared.step_cursor(&mut cursor, action);
            assert_eq!(own, kept);
            assert_eq!(
                env.subtask_rewards(),
                shared.cursor_subtask_rewards(&cursor)
            );
            assert_eq!(env.position(), shared.cursor_position(&cursor));
            assert_eq!(env.last_event(), shared.cursor_last_event(&cursor));
            assert_eq!(env.steps(), cursor.steps());
            if own.done() {
                env.reset(None);
                cursor = shared.start_cursor();
            }
        }
    }
}
