//! Structured layouts (issue 33): the laws every generated layout obeys, the layouts pinned
//! bit for bit (value stability), and impossible requests as typed errors.

use mazes::{
    GeneratorParams, LayoutError, LayoutKind, LayoutSpec, Maze, MazeAlgorithm, MazeError,
    PerfectMazeParams, Pos, Preset, RoomsParams, TrapParams, generate_seeded,
};
use proptest::prelude::*;

fn perfect_params() -> impl Strategy<Value = PerfectMazeParams> {
    (0..8_usize, 0..8_usize, any::<bool>(), 0.0..=1.0_f64)
        .prop_filter("two cells at least", |(w, h, _, _)| w + h > 0)
        .prop_flat_map(|(half_w, half_h, wilson, fraction)| {
            let (width, height) = (2 * half_w + 1, 2 * half_h + 1);
            (
                Just((width, height, wilson, fraction)),
                0..=half_w,
                0..=half_h,
                0..=half_w,
                0..=half_h,
            )
        })
        .prop_filter("start and target differ", |(_, sx, sy, tx, ty)| {
            (sx, sy) != (tx, ty)
        })
        .prop_map(|((width, height, wilson, fraction), sx, sy, tx, ty)| {
            let algorithm = if wilson {
                MazeAlgorithm::Wilson
            } else {
                MazeAlgorithm::Backtracker
            };
            let mut params = PerfectMazeParams {
                width,
                height,
                algorithm,
                openings: 0,
                start: Pos::new(2 * sx, 2 * sy),
                target: Pos::new(2 * tx, 2 * ty),
            };
            params.openings = (fraction * params.max_openings() as f64) as usize;
            params
        })
}

fn rooms_params() -> impl Strategy<Value = RoomsParams> {
    (1..=4_usize, 1..=4_usize)
        .prop_filter("two rooms at least", |(x, y)| x * y >= 2)
        .prop_flat_map(|(rooms_x, rooms_y)| {
            (
                Just((rooms_x, rooms_y)),
                (3 * rooms_x - 1)..=(3 * rooms_x + 6),
                (3 * rooms_y - 1)..=(3 * rooms_y + 6),
                0.0..=1.0_f64,
                0..=12_usize,
            )
        })
        .prop_map(|((rooms_x, rooms_y), width, height, fraction, obstacles)| {
            let mut params = RoomsParams::new(width, height, rooms_x, rooms_y, 0, obstacles);
            params.extra_doors = (fraction * params.max_extra_doors() as f64) as usize;
            params.max_attempts = 200;
            params
        })
}

fn trap_params() -> impl Strategy<Value = TrapParams> {
    (3..=16_usize, 2..=12_usize)
        .prop_flat_map(|(width, height)| {
            (
                Just((width, height)),
                1..=(width - 1) / 2,
                1..height,
                0..=10_usize,
            )
        })
        .prop_map(|((width, height), walls, gap, obstacles)| {
            let mut params = TrapParams::new(width, height, walls, gap, obstacles);
            params.max_attempts = 200;
            params
        })
}

fn any_spec() -> impl Strategy<Value = LayoutSpec> {
    prop_oneof![
        crate::common::small_params(10, 0.5).prop_map(LayoutSpec::Uniform),
        perfect_params().prop_map(LayoutSpec::PerfectMaze),
        rooms_params().prop_map(LayoutSpec::Rooms),
        trap_params().prop_map(LayoutSpec::Trap),
    ]
}

/// The BFS optimum computed apart from `Maze::shortest_path_len`, over `distances_from`.
fn optimum(maze: &Maze) -> usize {
    let target = maze.state_of(maze.target()).expect("the target is inside");
    maze.distances_from(maze.start())[target].expect("the target is reachable")
}

/// Pairs of neighbouring free tiles.
fn free_pairs(maze: &Maze) -> usize {
    let mut pairs = 0;
    for y in 0..maze.height() {
        for x in 0..maze.width() {
            let here = Pos::new(x, y);
            if maze.is_free(here) {
                pairs += usize::from(maze.is_free(Pos::new(x + 1, y)));
                pairs += usize::from(maze.is_free(Pos::new(x, y + 1)));
            }
        }
    }
    pairs
}

fn free_tiles(maze: &Maze) -> usize {
    maze.n_tiles() - maze.obstacle_count()
}

proptest! {
    /// Every layout has the spec's size, start and target, exactly the promised obstacle
    /// count, a reachable target and the detour ratio of its BFS optimum; the same seed gives
    /// the same layout. A scatter may give up, with a typed error only.
    #[test]
    fn every_layout_keeps_its_promises(spec in any_spec(), seed: u64) {
        match spec.generate(seed) {
            Ok(maze) => {
                prop_assert_eq!((maze.width(), maze.height()), spec.size());
                prop_assert_eq!((maze.start(), maze.target()), (spec.start(), spec.target()));
                prop_assert_eq!(Some(maze.obstacle_count()), spec.obstacle_count());
                prop_assert!(maze.is_free(maze.start()) && maze.is_free(maze.target()));
                let optimum = optimum(&maze);
                prop_assert_eq!(optimum, maze.shortest_path_len());
                let manhattan = maze.start().manhattan(maze.target());
                prop_assert_eq!(maze.manhattan_distance(), manhattan);
                prop_assert_eq!(maze.detour_ratio(), optimum as f64 / manhattan as f64);
                prop_assert!(maze.detour_ratio() >= 1.0);
                prop_assert_eq!(spec.generate(seed), Ok(maze));
            }
            Err(error) => {
                let gave_up = matches!(
                    error,
                    LayoutError::Maze(
                        MazeError::NoReachableLayout { .. } | MazeError::TooManyObstacles { .. }
                    )
                );
                prop_assert!(gave_up, "{error}");
                prop_assert!(spec.kind() != LayoutKind::PerfectMaze);
            }
        }
    }

    /// A perfect maze is a spanning tree of its cells carved into rock: `2 · cells − 1` free
    /// tiles, neighbouring free pairs one fewer (no loop), and each opening adds one free tile
    /// and one loop.
    #[test]
    fn a_perfect_maze_is_a_tree_plus_its_openings(params in perfect_params(), seed: u64) {
        let maze = LayoutSpec::PerfectMaze(params).generate(seed).unwrap();
        let cells = params.width.div_ceil(2) * params.height.div_ceil(2);
        prop_assert_eq!(free_tiles(&maze), 2 * cells - 1 + params.openings);
        prop_assert_eq!(free_pairs(&maze), free_tiles(&maze) - 1 + params.openings);
        // Every cell is reachable from the start.
        let distance = maze.distances_from(maze.start());
        for y in (0..params.height).step_by(2) {
            for x in (0..params.width).step_by(2) {
                prop_assert!(distance[y * params.width + x].is_some());
            }
        }
    }

    /// Without a scatter every room is reachable, and the walls have exactly
    /// `rooms − 1 + extra_doors` doors.
    #[test]
    fn rooms_are_joined_by_their_doors(params in rooms_params(), seed: u64) {
        let params = RoomsParams { obstacles: 0, ..params };
        let maze = LayoutSpec::Rooms(params).generate(seed).unwrap();
        let distance = maze.distances_from(maze.start());
        let free = (0..maze.n_tiles()).filter(|&s| maze.is_free(maze.pos_of(s).unwrap())).count();
        prop_assert_eq!(distance.iter().flatten().count(), free);
        let walls = (params.rooms_x - 1) * params.height + (params.rooms_y - 1) * params.width
            - (params.rooms_x - 1) * (params.rooms_y - 1);
        let doors = params.rooms_x * params.rooms_y - 1 + params.extra_doors;
        prop_assert_eq!(maze.obstacle_count(), walls - doors);
    }

    /// A trap with one-tile gaps and no scatter has the optimum its docs state:
    /// `(width − 1) + 2⌈walls/2⌉(height − 1)`, whatever columns the walls stand in.
    #[test]
    fn a_trap_costs_what_its_docs_say(params in trap_params(), seed: u64) {
        let params = TrapParams { gap: 1, obstacles: 0, ..params };
        let maze = LayoutSpec::Trap(params).generate(seed).unwrap();
        let expected = (params.width - 1) + 2 * params.walls.div_ceil(2) * (params.height - 1);
        prop_assert_eq!(maze.shortest_path_len(), expected);
    }
}

/// Value stability: these small layouts are the bits every platform must make from these
/// seeds (a change of draw order, of the draw itself or of a generator shows here).
#[test]
fn small_layouts_are_the_same_on_every_platform() {
    let cases: [(LayoutSpec, u64, &str); 4] = [
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams::corner_to_corner(
                11,
                7,
                MazeAlgorithm::Backtracker,
                0,
            )),
            1,
            BACKTRACKER_11X7_SEED1,
        ),
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams::corner_to_corner(
                11,
                7,
                MazeAlgorithm::Wilson,
                2,
            )),
            1,
            WILSON_11X7_OPENINGS2_SEED1,
        ),
        (
            LayoutSpec::Rooms(RoomsParams::new(14, 8, 3, 2, 1, 6)),
            2,
            ROOMS_14X8_SEED2,
        ),
        (
            LayoutSpec::Trap(TrapParams::new(13, 6, 3, 2, 4)),
            3,
            TRAP_13X6_SEED3,
        ),
    ];
    for (spec, seed, expected) in cases {
        let maze = spec.generate(seed).unwrap();
        assert_eq!(maze.to_text(), expected, "{spec:?} seed {seed}");
    }
}

const BACKTRACKER_11X7_SEED1: &str = "\
S..#.....#.
##.#.###.#.
.#...#.#.#.
.#####.#.#.
.......#...
.###.#####.
...#......T
";

const WILSON_11X7_OPENINGS2_SEED1: &str = "\
S..........
######.#.#.
.......#.#.
.###.#.#.#.
.....#.#.#.
##.###.#.#.
...#...#..T
";

const ROOMS_14X8_SEED2: &str = "\
S..##......#..
....#.#..#....
#...##...##...
....#....#....
##.##.#######.
.........#....
....#....#....
....#........T
";

const TRAP_13X6_SEED3: &str = "\
S#.....#.#..T
.#.......#...
.#.#...#.#...
.#.....#.#...
.......#....#
......##.....
";

/// The paper's layouts are uniform layouts of the family: the same generator, the same bits,
/// and both at the Manhattan bound (detour ratio 1).
#[test]
fn the_papers_layouts_are_uniform_layouts_at_the_manhattan_bound() {
    for preset in Preset::ALL {
        let spec = LayoutSpec::Uniform(preset.generator_params());
        let maze = spec.generate(preset.seed()).unwrap();
        assert_eq!(maze, preset.maze());
        assert_eq!(spec.obstacle_count(), Some(maze.obstacle_count()));
        assert_eq!(maze.detour_ratio(), 1.0);
    }
    let params = GeneratorParams::corner_to_corner(12, 9, 30);
    for seed in 0..5 {
        assert_eq!(
            LayoutSpec::Uniform(params).generate(seed),
            generate_seeded(&params, seed).map_err(LayoutError::from)
        );
    }
}

#[test]
fn impossible_layouts_are_typed_errors_naming_the_field() {
    let perfect = PerfectMazeParams::corner_to_corner(9, 7, MazeAlgorithm::Backtracker, 0);
    let cases: Vec<(LayoutSpec, LayoutError, &str)> = vec![
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams {
                width: 8,
                ..perfect
            }),
            LayoutError::EvenSize {
                field: "width",
                value: 8,
            },
            "`width` = 8 is even: a perfect maze needs an odd width (cells sit on even coordinates)",
        ),
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams {
                height: 4,
                ..perfect
            }),
            LayoutError::EvenSize {
                field: "height",
                value: 4,
            },
            "`height` = 4 is even: a perfect maze needs an odd height (cells sit on even coordinates)",
        ),
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams {
                target: Pos::new(7, 5),
                ..perfect
            }),
            LayoutError::NotOnCell {
                what: "target",
                pos: Pos::new(7, 5),
            },
            "the target (7, 5) is not a cell of the perfect maze: both coordinates must be even",
        ),
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams {
                openings: 13,
                ..perfect
            }),
            LayoutError::TooManyOpenings {
                requested: 13,
                max: 12,
            },
            "`openings` = 13 is more than the 12 walls between cells that a spanning tree leaves closed",
        ),
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams {
                start: Pos::new(8, 8),
                ..perfect
            }),
            LayoutError::Maze(MazeError::OutOfBounds {
                what: "start",
                pos: Pos::new(8, 8),
                width: 9,
                height: 7,
            }),
            "the start (8, 8) lies outside the 9×7 grid",
        ),
        (
            LayoutSpec::PerfectMaze(PerfectMazeParams::corner_to_corner(
                2049,
                1025,
                MazeAlgorithm::Wilson,
                0,
            )),
            LayoutError::TooLarge {
                kind: "perfect_maze",
                width: 2049,
                height: 1025,
                max: 1 << 20,
            },
            "a 2049×1025 perfect_maze layout has more than the 1048576 tiles a structured layout \
             may have; lower `width` or `height`",
        ),
        (
            LayoutSpec::Rooms(RoomsParams::new(10, 10, 4, 2, 0, 0)),
            LayoutError::RoomsDoNotFit {
                field: "rooms_x",
                rooms: 4,
                size: 10,
                max: 3,
            },
            "`rooms_x` = 4 rooms do not fit in 10 tiles: each room needs at least 2 tiles inside \
             and one wall tile between rooms (rooms_x at most 3)",
        ),
        (
            LayoutSpec::Rooms(RoomsParams::new(10, 10, 2, 0, 0, 0)),
            LayoutError::RoomsDoNotFit {
                field: "rooms_y",
                rooms: 0,
                size: 10,
                max: 3,
            },
            "`rooms_y` = 0 rooms do not fit in 10 tiles: each room needs at least 2 tiles inside \
             and one wall tile between rooms (rooms_y at most 3)",
        ),
        (
            LayoutSpec::Rooms(RoomsParams::new(10, 10, 1, 1, 0, 0)),
            LayoutError::TooFewRooms { rooms: 1 },
            "`rooms_x` × `rooms_y` = 1: a rooms layout needs at least 2 rooms",
        ),
        (
            LayoutSpec::Rooms(RoomsParams::new(10, 10, 3, 3, 5, 0)),
            LayoutError::TooManyDoors {
                requested: 5,
                max: 4,
            },
            "`extra_doors` = 5 is more than the 4 pairs of neighbouring rooms a spanning tree \
             leaves without a door",
        ),
        (
            LayoutSpec::Trap(TrapParams::new(8, 5, 4, 1, 0)),
            LayoutError::WallsDoNotFit {
                walls: 4,
                width: 8,
                max: 3,
            },
            "`walls` = 4 does not fit a width of 8: walls stand in columns 1..width−1 with a free \
             column between two (walls in 1..=3)",
        ),
        (
            LayoutSpec::Trap(TrapParams::new(8, 5, 0, 1, 0)),
            LayoutError::WallsDoNotFit {
                walls: 0,
                width: 8,
                max: 3,
            },
            "`walls` = 0 does not fit a width of 8: walls stand in columns 1..width−1 with a free \
             column between two (walls in 1..=3)",
        ),
        (
            LayoutSpec::Trap(TrapParams::new(8, 5, 2, 5, 0)),
            LayoutError::GapOutOfRange {
                gap: 5,
                height: 5,
                max: 4,
            },
            "`gap` = 5 must be in 1..=4 (height 5): a wall needs a gap and a tile",
        ),
        (
            LayoutSpec::Trap(TrapParams {
                max_attempts: 0,
                ..TrapParams::new(8, 5, 2, 1, 3)
            }),
            LayoutError::Maze(MazeError::ZeroAttempts),
            "`max_attempts` must be at least 1, got 0",
        ),
        (
            LayoutSpec::Uniform(GeneratorParams::corner_to_corner(4, 3, 7)),
            LayoutError::Maze(MazeError::TooManyObstacles {
                requested: 7,
                max: 6,
            }),
            "`obstacles` = 7 is more than the 6 that fit while keeping a path from start to \
             target open",
        ),
    ];
    for (spec, error, message) in cases {
        assert_eq!(spec.validate(), Err(error.clone()), "{spec:?}");
        assert_eq!(spec.generate(0), Err(error.clone()), "{spec:?}");
        assert_eq!(spec.obstacle_count(), None, "{spec:?}");
        assert_eq!(error.to_string(), message);
    }
}

#[test]
fn a_scatter_beyond_the_route_is_refused_and_the_bound_itself_works() {
    // One wall, gap 1, on 5 × 3: 15 tiles, 2 wall tiles, start and target; the route has
    // 4 + 2·2 = 8 moves, so 13 − 2 − 7 = 4 tiles lie off it.
    let exact = LayoutSpec::Trap(TrapParams::new(5, 3, 1, 1, 4));
    let maze = exact.generate(0).unwrap();
    assert_eq!(maze.obstacle_count(), 6);
    assert_eq!(maze.shortest_path_len(), 8);
    let over = LayoutSpec::Trap(TrapParams::new(5, 3, 1, 1, 5));
    assert_eq!(
        over.generate(0),
        Err(LayoutError::Maze(MazeError::TooManyObstacles {
            requested: 5,
            max: 4
        }))
    );
}

#[test]
fn specs_round_trip_through_serde_and_refuse_unknown_keys() {
    let specs = [
        LayoutSpec::Uniform(GeneratorParams::corner_to_corner(30, 30, 100)),
        LayoutSpec::PerfectMaze(PerfectMazeParams::corner_to_corner(
            31,
            31,
            MazeAlgorithm::Wilson,
            16,
        )),
        LayoutSpec::Rooms(RoomsParams::new(30, 30, 3, 3, 2, 40)),
        LayoutSpec::Trap(TrapParams::new(30, 30, 3, 1, 0)),
    ];
    for spec in specs {
        let json = serde_json::to_string(&spec).unwrap();
        assert_eq!(
            serde_json::from_str::<LayoutSpec>(&json).unwrap(),
            spec,
            "{json}"
        );
    }
    let trap: LayoutSpec = serde_json::from_str(
        r#"{"kind": "trap", "width": 30, "height": 30, "walls": 3, "gap": 1}"#,
    )
    .unwrap();
    assert_eq!(trap, LayoutSpec::Trap(TrapParams::new(30, 30, 3, 1, 0)));
    let unknown = serde_json::from_str::<LayoutSpec>(
        r#"{"kind": "trap", "width": 30, "height": 30, "walls": 3, "gap": 1, "wall": 2}"#,
    )
    .unwrap_err();
    assert!(
        unknown.to_string().contains("unknown field `wall`"),
        "{unknown}"
    );
    assert_eq!(
        serde_json::to_string(&LayoutKind::ALL).unwrap(),
        r#"["uniform","perfect_maze","rooms","trap"]"#
    );
}

/// Each kind's data name reads back as the kind; its name for people differs only where the
/// data name is not a word ("perfect maze").
#[test]
fn a_kind_reads_back_from_its_name_and_has_a_title_for_people() {
    for kind in LayoutKind::ALL {
        assert_eq!(LayoutKind::from_name(kind.name()), Some(kind));
        assert!(!kind.title().contains('_'), "{kind:?}");
    }
    assert_eq!(LayoutKind::PerfectMaze.title(), "perfect maze");
    assert_eq!(LayoutKind::Trap.title(), "trap");
    assert_eq!(LayoutKind::from_name("perfect maze"), None);
}
