//! The maze family (issue 33): held-out layouts beyond the paper's two, with structure.
//!
//! Both of the paper's mazes sit at the Manhattan bound (detour ratio 1: some shortest path
//! only ever moves towards the target), so the "reach the target faster" sub-task's distance
//! shaping alone is optimal there. The family asks whether EA-MADM's verdicts hold on layouts
//! where it is not: [`maze_family`]`(n)` gives `n` layouts ([`DEFAULT_FAMILY_SIZE`] = 24 by
//! default), cycling through [`RECIPES`] — six each of uniform obstacles (11 % to 40 %),
//! perfect mazes (recursive backtracker and Wilson's, braided by 0 to 64 openings), rooms
//! joined by doors (2 × 2 to 5 × 5 rooms) and traps (1 to 5 walls) — interleaved by kind, so
//! that any prefix mixes the kinds. Layout `i` uses recipe `i mod 24` and the generator seed
//! [`FAMILY_SEED_BASE`]` + i`: the first 24 layouts of every family are the default family,
//! and a larger family only adds layouts. Each layout is a [`FamilyLayout`] with its kind,
//! parameters, seed, detour ratio and the maze task config it is run as
//! ([`FamilyLayout::experiment`]).
//!
//! **Rewards: Task II's** (−1 per step, +10 at the target; sub-tasks "reach the target faster"
//! with Task II's bonus, and "do not hit obstacles"). Under Task I's rule the task return of a
//! bump-free episode that reaches is the same however long the route (every farther step is
//! paid back by one more closer step: docs/paper-notes.md §10.1a), so C2 could not see a
//! detour; under Task II's it is `10 − (steps − 1)`, the route's length. And Task I's task
//! reward is itself distance-shaped, so every competitor would learn from the same shaping
//! the family is built to mislead; Task II's leaves the shaping to the sub-task alone, which
//! is the comparison the family is for (docs/paper-notes.md §7.1).
//!
//! ```
//! use eamadm::family::{DEFAULT_FAMILY_SIZE, maze_family};
//! use eamadm::mazes::LayoutKind;
//!
//! let family = maze_family(DEFAULT_FAMILY_SIZE)?;
//! assert_eq!(family.len(), 24);
//! assert_eq!(family[0].name, "f00-uniform");
//! assert_eq!(family[3].kind(), LayoutKind::Trap);
//! // Every layout is a maze experiment of its own, judged like Task I and II.
//! let config = family[3].experiment();
//! assert_eq!(config.name, "family-f03-trap");
//! assert!(family[3].detour_ratio() > 2.0);
//! # Ok::<(), eamadm::family::FamilyError>(())
//! ```

use std::io::Write;

use mazes::{
    GeneratorParams, LayoutError, LayoutKind, LayoutSpec, Maze, MazeAlgorithm, PerfectMazeParams,
    Preset, RoomsParams, TrapParams,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::columns::{Column, FieldType};
use crate::config::{
    EvaluationConfig, ExperimentConfig, MethodSpec, TaskConfig, TrajectoryConfig, table1_learner,
};
use crate::paper;

/// Layouts in the default family.
pub const DEFAULT_FAMILY_SIZE: usize = 24;

/// The most layouts a family may have.
pub const MAX_FAMILY_SIZE: usize = 10_000;

/// Layout `i` of a family is generated with seed `FAMILY_SEED_BASE + i`: far from the paper's
/// layout seeds (1 and 2), so no family layout is one of the paper's.
pub const FAMILY_SEED_BASE: u64 = 33_000;

/// Training episodes of every method on every family layout (docs/paper-notes.md §22): fixed
/// before any verdict by a pilot of the paper's ε-greedy on pilot seeds. At the paper's 200
/// every method stays at the floor on most layouts, so no comparison could tell them apart.
pub const FAMILY_EPISODES: u64 = 6400;

/// Held-out seeds per method and layout (docs/paper-notes.md §22): the pooled verdicts average
/// over layouts first, so layouts, not seeds, carry the family's evidence; 10 seeds halves the
/// cost of the paper's 20.
pub const FAMILY_SEEDS: u32 = 10;

/// The first seed of the held-out runs (the pilot used 1000 to 1002, which no run reaches).
pub const FAMILY_BASE_SEED: u64 = 0;

/// The prefix of a family layout's experiment name: `family-<layout>`.
pub const EXPERIMENT_PREFIX: &str = "family-";

/// The recipes of the family, in the order layouts take them (layout `i` takes recipe
/// `i mod 24`): kinds interleaved (uniform, perfect maze, rooms, trap), each kind from mild
/// to severe. Sizes are the paper's scale: 30 × 30 (31 × 31 for perfect mazes, which need odd
/// sides). The detour ratios these give on the default seeds span 1 to 6 (the table in
/// docs/paper-notes.md §7.1).
pub const RECIPES: [LayoutSpec; 24] = {
    const fn uniform(obstacles: usize) -> LayoutSpec {
        LayoutSpec::Uniform(GeneratorParams::corner_to_corner(30, 30, obstacles))
    }
    const fn perfect(algorithm: MazeAlgorithm, openings: usize) -> LayoutSpec {
        LayoutSpec::PerfectMaze(PerfectMazeParams::corner_to_corner(
            31, 31, algorithm, openings,
        ))
    }
    const fn rooms(per_side: usize, extra_doors: usize, obstacles: usize) -> LayoutSpec {
        LayoutSpec::Rooms(RoomsParams::new(
            30,
            30,
            per_side,
            per_side,
            extra_doors,
            obstacles,
        ))
    }
    const fn trap(walls: usize, gap: usize, obstacles: usize) -> LayoutSpec {
        LayoutSpec::Trap(TrapParams::new(30, 30, walls, gap, obstacles))
    }
    use MazeAlgorithm::{Backtracker, Wilson};
    [
        uniform(100),
        perfect(Wilson, 64),
        rooms(2, 0, 0),
        trap(1, 15, 0),
        uniform(180),
        perfect(Wilson, 16),
        rooms(3, 3, 60),
        trap(1, 1, 0),
        uniform(225),
        perfect(Backtracker, 64),
        rooms(3, 0, 0),
        trap(2, 8, 40),
        uniform(270),
        perfect(Wilson, 0),
        rooms(4, 4, 60),
        trap(3, 8, 80),
        uniform(315),
        perfect(Backtracker, 16),
        rooms(4, 0, 0),
        trap(3, 1, 0),
        uniform(360),
        perfect(Backtracker, 0),
        rooms(5, 2, 30),
        trap(5, 4, 0),
    ]
};

/// One layout of the family.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyLayout {
    /// Its name, `f<index>-<kind>` (`f07-trap`): the `layout` of its rows, and after
    /// [`EXPERIMENT_PREFIX`] its experiment's name.
    pub name: String,
    /// Its position in the family (0-based).
    pub index: usize,
    /// What was generated: kind and parameters ([`RECIPES`]` [index mod 24]`).
    pub spec: LayoutSpec,
    /// The generator seed, [`FAMILY_SEED_BASE`]` + index`.
    pub seed: u64,
    /// The layout.
    pub maze: Maze,
}

impl FamilyLayout {
    /// The kind of layout.
    #[must_use]
    pub fn kind(&self) -> LayoutKind {
        self.spec.kind()
    }

    /// The BFS optimum in steps.
    #[must_use]
    pub fn optimum(&self) -> usize {
        self.maze.shortest_path_len()
    }

    /// The BFS optimum divided by the Manhattan distance ([`Maze::detour_ratio`]).
    #[must_use]
    pub fn detour_ratio(&self) -> f64 {
        self.maze.detour_ratio()
    }

    /// The task: this map inline, with Task II's rewards, sub-tasks and step cap (2000).
    #[must_use]
    pub fn task(&self) -> TaskConfig {
        TaskConfig::MazeText {
            map: self.maze.to_text(),
            rewards: Preset::Task2,
            step_cap: None,
        }
    }

    /// The experiment this layout is run as: `family-<name>`, [`task`](Self::task),
    /// [`FAMILY_EPISODES`] episodes, [`FAMILY_SEEDS`] seeds from [`FAMILY_BASE_SEED`], and what
    /// the paper's maze presets use — Table 1's learner, the periodic greedy evaluation — with
    /// [`methods`]. No training trajectory is
    /// kept (the greedy evaluation's always is): a family is many runs, and its figures are
    /// drawn from scores.
    #[must_use]
    pub fn experiment(&self) -> ExperimentConfig {
        ExperimentConfig {
            name: format!("{EXPERIMENT_PREFIX}{}", self.name),
            task: self.task(),
            episodes: FAMILY_EPISODES,
            seeds: FAMILY_SEEDS,
            base_seed: FAMILY_BASE_SEED,
            learner: table1_learner(),
            trajectories: TrajectoryConfig {
                first: false,
                last: false,
                episodes: Vec::new(),
            },
            evaluation: EvaluationConfig::default(),
            methods: methods(),
        }
    }

    /// Its row of the layout table.
    #[must_use]
    pub fn row(&self) -> LayoutRow {
        LayoutRow::new(&self.name, &self.spec, self.seed, &self.maze)
    }
}

/// The methods every family layout runs: the paper's four and EA-MADM's four ablations
/// ([`paper::methods`]), `subtask0-alone` (the sub-task EA-MADM's verdicts tie with on the
/// paper's mazes) and the three reward-matched competitors (`*-shaped`, the control that
/// overturns Task II's verdicts), all as the maze presets define them. The budget-matched
/// controls are left out: their warm-up budget is EA-MADM's pre-training steps on each
/// layout, which differ by layout.
#[must_use]
pub fn methods() -> Vec<MethodSpec> {
    let mut methods = paper::methods();
    methods.extend(
        paper::controls(0)
            .into_iter()
            .filter(|spec| spec.label == "subtask0-alone" || spec.label.ends_with("-shaped")),
    );
    methods
}

/// A family that cannot be made.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum FamilyError {
    /// A size outside `1..=MAX_FAMILY_SIZE`.
    #[error("a family of {size} layouts: expected 1 to {MAX_FAMILY_SIZE} layouts")]
    Size {
        /// The size asked for.
        size: usize,
    },
    /// A layout whose generator gave up.
    #[error("family layout {name} (recipe {recipe}, seed {seed}): {source}")]
    Layout {
        /// The layout's name.
        name: String,
        /// Its recipe's index in [`RECIPES`].
        recipe: usize,
        /// Its generator seed.
        seed: u64,
        /// Why.
        #[source]
        source: LayoutError,
    },
}

/// The first `n` layouts of the family (`n` in `1..=`[`MAX_FAMILY_SIZE`]).
///
/// # Errors
/// [`FamilyError::Size`] for `n` out of range; [`FamilyError::Layout`] if a generator gives up
/// (none of the default family's does; a test checks the first 200).
pub fn maze_family(n: usize) -> Result<Vec<FamilyLayout>, FamilyError> {
    if n == 0 || n > MAX_FAMILY_SIZE {
        return Err(FamilyError::Size { size: n });
    }
    (0..n).map(layout).collect()
}

/// Layout `index` of the family.
fn layout(index: usize) -> Result<FamilyLayout, FamilyError> {
    let recipe = index % RECIPES.len();
    let spec = RECIPES[recipe];
    let seed = FAMILY_SEED_BASE + index as u64;
    let name = format!("f{index:02}-{}", short_kind(spec.kind()));
    match spec.generate(seed) {
        Ok(maze) => Ok(FamilyLayout {
            name,
            index,
            spec,
            seed,
            maze,
        }),
        Err(source) => Err(FamilyError::Layout {
            name,
            recipe,
            seed,
            source,
        }),
    }
}

/// The name of the family layout whose experiment is `experiment` (`family-f07-trap` →
/// `f07-trap`); `None` for any other experiment.
#[must_use]
pub fn layout_of_experiment(experiment: &str) -> Option<&str> {
    experiment.strip_prefix(EXPERIMENT_PREFIX)
}

/// The kind in a layout's name: `uniform`, `perfect`, `rooms`, `trap`.
fn short_kind(kind: LayoutKind) -> &'static str {
    match kind {
        LayoutKind::PerfectMaze => "perfect",
        other => other.name(),
    }
}

/// The paper's two layouts as rows of the layout table (`task1`, `task2`: uniform, detour
/// ratio 1), so that a table or figure of the family can show them beside it.
#[must_use]
pub fn paper_layout_rows() -> Vec<LayoutRow> {
    Preset::ALL
        .into_iter()
        .map(|preset| {
            LayoutRow::new(
                preset.id(),
                &LayoutSpec::Uniform(preset.generator_params()),
                preset.seed(),
                &preset.maze(),
            )
        })
        .collect()
}

/// One row of `layouts.csv`: a layout, how it was made and what it is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LayoutRow {
    /// The layout's name (`f07-trap`, or `task1`, `task2` for the paper's).
    pub layout: String,
    /// `uniform`, `perfect_maze`, `rooms` or `trap`; `None` for a hand-designed map.
    pub kind: Option<LayoutKind>,
    /// The generator's parameters as JSON (the `LayoutSpec`, kind tag included); `None` for a
    /// hand-designed map.
    pub parameters: Option<String>,
    /// The generator seed; `None` for a hand-designed map.
    pub generator_seed: Option<u64>,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Start column.
    pub start_x: usize,
    /// Start row (0 at the top).
    pub start_y: usize,
    /// Target column.
    pub target_x: usize,
    /// Target row.
    pub target_y: usize,
    /// Obstacle tiles.
    pub obstacles: usize,
    /// Obstacles per tile.
    pub density: f64,
    /// Manhattan distance from start to target.
    pub manhattan_steps: usize,
    /// BFS optimum.
    pub optimum_steps: usize,
    /// `optimum_steps / manhattan_steps`.
    pub detour_ratio: f64,
    /// The map text (`.` free, `#` obstacle, `S`, `T`; one line per row).
    pub map: String,
}

impl LayoutRow {
    /// The row of `maze`, made from `spec` with `seed`, named `layout`.
    #[must_use]
    pub fn new(layout: &str, spec: &LayoutSpec, seed: u64, maze: &Maze) -> Self {
        Self {
            kind: Some(spec.kind()),
            // A LayoutSpec is plain numbers and enums: serialising it cannot fail.
            parameters: serde_json::to_string(spec).ok(),
            generator_seed: Some(seed),
            ..Self::hand_designed(layout, maze)
        }
    }

    /// The row of a map that no generator made (`aggregation-control`'s, a `--config`'s
    /// `maze_text` or `maze_file`), named `layout`: no kind, parameters or seed.
    #[must_use]
    pub fn hand_designed(layout: &str, maze: &Maze) -> Self {
        Self {
            layout: layout.to_owned(),
            kind: None,
            parameters: None,
            generator_seed: None,
            width: maze.width(),
            height: maze.height(),
            start_x: maze.start().x,
            start_y: maze.start().y,
            target_x: maze.target().x,
            target_y: maze.target().y,
            obstacles: maze.obstacle_count(),
            density: maze.obstacle_count() as f64 / maze.n_tiles() as f64,
            manhattan_steps: maze.manhattan_distance(),
            optimum_steps: maze.shortest_path_len(),
            detour_ratio: maze.detour_ratio(),
            map: maze.to_text(),
        }
    }
}

/// When a generator's column of `layouts.csv` is blank.
const HAND_DESIGNED: &str =
    "the map is hand-designed, not generated (`aggregation-control`, a config's own map)";

/// The columns of `layouts.csv`, in order (the fields of [`LayoutRow`]).
pub const LAYOUT_COLUMNS: &[Column] = &[
    Column::new("layout", FieldType::String, "The layout's name: `f<index>-<kind>` for a family layout (its experiment is `family-<layout>`), `task1` or `task2` for the paper's. The `layout` of `final-scores.csv`'s rows."),
    Column::new("kind", FieldType::String, "How the layout was made: uniform random obstacles, a perfect maze (corridors and dead ends, possibly braided), rooms joined by doors, or a trap (walls across the direct route with gaps at the far end).").values(&["uniform", "perfect_maze", "rooms", "trap"]).blank_when(HAND_DESIGNED),
    Column::new("parameters", FieldType::String, "The generator's parameters as JSON (`mazes::LayoutSpec`, with its `kind` tag): with `generator_seed` they make the layout again, bit for bit.").blank_when(HAND_DESIGNED),
    Column::new("generator_seed", FieldType::Integer, "The seed of the layout's generator (not a run seed).").blank_when(HAND_DESIGNED),
    Column::new("width", FieldType::Integer, "Columns of the grid.").unit("tiles"),
    Column::new("height", FieldType::Integer, "Rows of the grid.").unit("tiles"),
    Column::new("start_x", FieldType::Integer, "The start's column (0 at the left).").unit("tiles"),
    Column::new("start_y", FieldType::Integer, "The start's row (0 at the top).").unit("tiles"),
    Column::new("target_x", FieldType::Integer, "The target's column.").unit("tiles"),
    Column::new("target_y", FieldType::Integer, "The target's row.").unit("tiles"),
    Column::new("obstacles", FieldType::Integer, "Obstacle tiles (walls and scattered obstacles).").unit("tiles"),
    Column::new("density", FieldType::Number, "Obstacle tiles per tile, 0 to 1.").unit("fraction"),
    Column::new("manhattan_steps", FieldType::Integer, "The Manhattan distance from start to target: the fewest moves on an empty grid.").unit("steps"),
    Column::new("optimum_steps", FieldType::Integer, "The BFS shortest path from start to target (the `optimum_steps` of the layout's runs).").unit("steps"),
    Column::new("detour_ratio", FieldType::Number, "`optimum_steps / manhattan_steps`: 1 when a shortest path only moves towards the target (distance shaping alone is optimal), larger the more the best route turns away from it."),
    Column::new("map", FieldType::String, "The layout as a text map, one line per row: `.` free, `#` obstacle, `S` start, `T` target."),
];

/// Writes `rows` as `layouts.csv`: a header of [`LAYOUT_COLUMNS`]' names, one row per layout.
///
/// # Errors
/// What the writer returns.
pub fn write_layouts_csv<W: Write>(rows: &[LayoutRow], writer: W) -> Result<(), csv::Error> {
    let mut csv = csv::Writer::from_writer(writer);
    if rows.is_empty() {
        csv.write_record(LAYOUT_COLUMNS.iter().map(|c| c.name))?;
    }
    for row in rows {
        csv.serialize(row)?;
    }
    csv.flush()?;
    Ok(())
}

/// Reads a `layouts.csv` written by [`write_layouts_csv`].
///
/// # Errors
/// Unreadable or malformed input (naming the line).
pub fn read_layouts_csv<R: std::io::Read>(reader: R) -> Result<Vec<LayoutRow>, csv::Error> {
    csv::Reader::from_reader(reader).deserialize().collect()
}

/// The `layout` of an experiment's rows ([`scores::MethodRoles::layout`](crate::scores::MethodRoles::layout)):
/// a paper preset's id (`task1`, `task2`: its readings and tuning trials play it too), a family
/// layout's name (`family-f07-trap` → `f07-trap`), the robot's scenario by its `name`
/// (`fig12`), and for any other map (`aggregation-control`, a config's own) the experiment's
/// name.
#[must_use]
pub fn layout_name(experiment: &crate::Experiment) -> String {
    let config = experiment.config();
    match (&config.task, experiment.task().scenario()) {
        (TaskConfig::Maze { preset, .. }, _) => preset.id().to_owned(),
        (_, Some(scenario)) => scenario.name.clone(),
        _ => layout_of_experiment(&config.name)
            .unwrap_or(&config.name)
            .to_owned(),
    }
}

/// The rows of the top-level `layouts.csv`: the paper's two layouts always, then the layout
/// of each experiment that plays a maze (a family layout's own row when given, so its
/// generator and seed are kept; a hand-designed row for any other map), each layout once, in
/// that order. The robot has no row.
#[must_use]
pub fn layouts_table<'a>(
    experiments: impl IntoIterator<Item = (&'a crate::Experiment, Option<&'a LayoutRow>)>,
) -> Vec<LayoutRow> {
    let mut rows = paper_layout_rows();
    for (experiment, family) in experiments {
        let row = match family {
            Some(row) => Some(row.clone()),
            None => experiment
                .task()
                .maze()
                .map(|maze| LayoutRow::hand_designed(&layout_name(experiment), maze)),
        };
        if let Some(row) = row
            && !rows.iter().any(|known| known.layout == row.layout)
        {
            rows.push(row);
        }
    }
    rows
}

/// The equivalence margins of the family's verdicts: Task II's rewards', which every family
/// layout plays.
#[must_use]
pub fn family_margins() -> Vec<crate::claims::Margin> {
    crate::margins::maze_margins(Preset::Task2.task_spec().reward)
}

/// The family's pooled verdicts and findings from its runs' `scores` (rows of other
/// experiments ignored) and the layout table `layouts` (kinds and detour ratios; rows of
/// layouts without runs ignored): judged with [`family_margins`] and the default two-level
/// bootstrap, the one path of the main job and of `eamadm.report(dir)`. `None` findings when
/// no family run is in `scores`.
///
/// # Errors
/// What the bootstrap returns (a non-finite value).
pub fn judge_family(
    scores: &[crate::scores::FinalScore],
    layouts: &[LayoutRow],
) -> Result<
    (
        eamadm_eval::family::FamilyVerdicts,
        Option<eamadm_eval::family::FamilyFindings>,
    ),
    crate::stats::StatsError,
> {
    let verdicts = eamadm_eval::family::family_verdicts(
        scores,
        &family_margins(),
        &crate::stats::hierarchical::HierarchicalBootstrap::default(),
    )?;
    let points: Vec<eamadm_eval::family::LayoutPoint> = layouts
        .iter()
        .filter_map(|row| {
            row.kind.map(|kind| eamadm_eval::family::LayoutPoint {
                layout: row.layout.clone(),
                kind: kind.name().to_owned(),
                detour_ratio: row.detour_ratio,
            })
        })
        .collect();
    let findings = eamadm_eval::family::family_findings(&verdicts, &points, scores);
    Ok((verdicts, findings))
}
