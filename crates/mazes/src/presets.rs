//! The paper's two maze tasks (Sec. VI.A) with fixed seeds, and their frozen fixture files.
//!
//! | preset | size | obstacles | start | target | seed |
//! |---|---|---|---|---|---|
//! | [`Preset::Task1`] | 30 × 30 | 100 (paper) | (0, 0) top-left | (29, 29) bottom-right | 1 |
//! | [`Preset::Task2`] | 39 × 36 | 156 | (0, 0) top-left | (38, 35) bottom-right | 2 |
//!
//! The paper gives Task II's size but no obstacle count; 156 keeps Task I's density
//! (100 / 900 = 1/9 of the tiles, and 39 · 36 / 9 = 156 exactly). The paper's layouts are
//! only in its Fig. 6 and 9, which we do not have; start and target sit in opposite
//! corners so that the shortest path crosses the whole maze.
//!
//! The layouts are frozen under [`FIXTURE_DIR`] (e.g. `fixtures/mazes/task1.map`) with a
//! comment header naming the generator and seed; [`Preset::fixture_text`] produces the
//! exact file content, and a test checks that the seed still makes the committed file.

use serde::{Deserialize, Serialize};

use crate::env::MazeEnv;
use crate::generate::{DEFAULT_MAX_ATTEMPTS, GeneratorParams, generate_seeded};
use crate::geometry::Pos;
use crate::maze::Maze;
use crate::reward::TaskSpec;

/// Folder of the frozen maze layouts, relative to the repository root.
pub const FIXTURE_DIR: &str = "fixtures/mazes";

/// One of the paper's maze tasks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// Task I: 30 × 30 tiles, 100 obstacles, the ±1 / −100 / +100 reward.
    #[serde(rename = "task1")]
    Task1,
    /// Task II: 39 × 36 tiles, 156 obstacles, the −1 / +10 reward.
    #[serde(rename = "task2")]
    Task2,
}

impl Preset {
    /// Both presets, Task I first.
    pub const ALL: [Self; 2] = [Self::Task1, Self::Task2];

    /// Short identifier: `"task1"` or `"task2"` (also the serde form).
    #[must_use]
    pub const fn id(self) -> &'static str {
        match self {
            Self::Task1 => "task1",
            Self::Task2 => "task2",
        }
    }

    /// Display title: `"Task I"` or `"Task II"`.
    #[must_use]
    pub const fn title(self) -> &'static str {
        match self {
            Self::Task1 => "Task I",
            Self::Task2 => "Task II",
        }
    }

    /// The seed of the `ChaCha8Rng` that generates the layout.
    #[must_use]
    pub const fn seed(self) -> u64 {
        match self {
            Self::Task1 => 1,
            Self::Task2 => 2,
        }
    }

    /// Size, obstacle count, start and target of the layout.
    #[must_use]
    pub const fn generator_params(self) -> GeneratorParams {
        let (width, height, obstacles) = match self {
            Self::Task1 => (30, 30, 100),
            Self::Task2 => (39, 36, 156),
        };
        GeneratorParams {
            width,
            height,
            obstacles,
            start: Pos::new(0, 0),
            target: Pos::new(width - 1, height - 1),
            max_attempts: DEFAULT_MAX_ATTEMPTS,
        }
    }

    /// The task's rewards, sub-tasks and step cap.
    #[must_use]
    pub fn task_spec(self) -> TaskSpec {
        match self {
            Self::Task1 => TaskSpec::task1(),
            Self::Task2 => TaskSpec::task2(),
        }
    }

    /// The layout, generated from [`seed`](Self::seed) (equal to the frozen fixture).
    #[must_use]
    pub fn maze(self) -> Maze {
        generate_seeded(&self.generator_params(), self.seed())
            .expect("preset parameters are feasible and their first attempts succeed (tested)")
    }

    /// A ready environment: [`maze`](Self::maze) with [`task_spec`](Self::task_spec).
    #[must_use]
    pub fn env(self) -> MazeEnv {
        MazeEnv::new(self.maze(), self.task_spec()).expect("preset task specs are valid (tested)")
    }

    /// File name of the frozen layout inside [`FIXTURE_DIR`]: `"task1.map"` or `"task2.map"`.
    #[must_use]
    pub const fn fixture_file_name(self) -> &'static str {
        match self {
            Self::Task1 => "task1.map",
            Self::Task2 => "task2.map",
        }
    }

    /// Path of the frozen layout relative to the repository root, e.g. `fixtures/mazes/task1.map`.
    #[must_use]
    pub fn fixture_path(self) -> String {
        format!("{FIXTURE_DIR}/{}", self.fixture_file_name())
    }

    /// The exact content of the fixture file: a `;` comment header (what, generator,
    /// seed, BFS optimum, "do not edit by hand") followed by the canonical text map.
    /// [`Maze::parse`] reads it back to [`maze`](Self::maze).
    #[must_use]
    pub fn fixture_text(self) -> String {
        let maze = self.maze();
        let params = self.generator_params();
        format!(
            "; {title} maze of the EA-MADM paper (Sec. VI.A), frozen for the reproduction.\n\
             ; Made by mazes::Preset::{variant:?}: mazes::generate_seeded(width {width}, \
             height {height}, obstacles {obstacles}, start {start}, target {target}) \
             with ChaCha8Rng seed {seed}.\n\
             ; Shortest path (BFS): {optimum} moves.\n\
             ; Do not edit by hand: `cargo xtask regen-fixtures` rewrites this file.\n\
             ; Format: `.` free, `#` obstacle, `S` start, `T` target; `;` starts a comment line.\n\
             {map}",
            title = self.title(),
            variant = self,
            width = params.width,
            height = params.height,
            obstacles = params.obstacles,
            start = params.start,
            target = params.target,
            seed = self.seed(),
            optimum = maze.shortest_path_len(),
            map = maze.to_text(),
        )
    }
}
