//! The presets and their frozen layouts under `fixtures/mazes/`.

use mazes::{FIXTURE_DIR, Maze, Pos, Preset};

fn committed(preset: Preset) -> String {
    let path = format!(
        "{}/../../{}",
        env!("CARGO_MANIFEST_DIR"),
        preset.fixture_path()
    );
    std::fs::read_to_string(&path).unwrap_or_else(|error| panic!("reading {path}: {error}"))
}

/// The seed still makes the committed map, byte for byte.
#[test]
fn the_seeds_still_make_the_committed_maps() {
    for preset in Preset::ALL {
        assert!(
            committed(preset) == preset.fixture_text(),
            "{} no longer matches what {:?} (seed {}) generates; if the change is intended, \
             run `cargo xtask regen-fixtures` and review the diff",
            preset.fixture_path(),
            preset,
            preset.seed()
        );
    }
}

#[test]
fn the_committed_maps_parse_to_the_presets() {
    for preset in Preset::ALL {
        assert_eq!(Maze::parse(&committed(preset)).unwrap(), preset.maze());
    }
}

#[test]
fn the_presets_are_the_papers_tasks() {
    let task1 = Preset::Task1.maze();
    assert_eq!((task1.width(), task1.height()), (30, 30));
    assert_eq!(task1.obstacle_count(), 100);
    assert_eq!(
        (task1.start(), task1.target()),
        (Pos::new(0, 0), Pos::new(29, 29))
    );

    let task2 = Preset::Task2.maze();
    assert_eq!((task2.width(), task2.height()), (39, 36));
    assert_eq!(task2.obstacle_count(), 156);
    assert_eq!(
        (task2.start(), task2.target()),
        (Pos::new(0, 0), Pos::new(38, 35))
    );
    // Same density as Task I: one obstacle in nine tiles.
    assert_eq!(task2.obstacle_count() * 9, task2.n_tiles());

    assert_eq!(Preset::Task1.task_spec(), mazes::TaskSpec::task1());
    assert_eq!(Preset::Task2.task_spec(), mazes::TaskSpec::task2());
    assert_eq!(
        Preset::Task1.fixture_path(),
        format!("{FIXTURE_DIR}/task1.map")
    );
    assert_eq!(
        Preset::Task2.fixture_path(),
        format!("{FIXTURE_DIR}/task2.map")
    );
    assert_eq!(
        serde_json::to_string(&Preset::ALL).unwrap(),
        r#"["task1","task2"]"#
    );
}

/// The optimum every learning curve is compared with.
#[test]
fn preset_shortest_paths() {
    insta::assert_snapshot!(
        Preset::ALL
            .map(|p| format!("{}: {} moves", p.title(), p.maze().shortest_path_len()))
            .join("\n"),
        @r"
    Task I: 58 moves
    Task II: 73 moves
    "
    );
}

/// The positive control's frozen map is the code's, byte for byte, and parses to it.
#[test]
fn the_control_map_is_frozen() {
    let path = format!(
        "{}/../../{FIXTURE_DIR}/{}",
        env!("CARGO_MANIFEST_DIR"),
        mazes::AGGREGATION_CONTROL_FIXTURE
    );
    let text =
        std::fs::read_to_string(&path).unwrap_or_else(|error| panic!("reading {path}: {error}"));
    assert!(
        text == mazes::aggregation_control_fixture_text(),
        "{path} differs from mazes::AGGREGATION_CONTROL_MAP; run `cargo xtask regen-fixtures`"
    );
    assert_eq!(
        Maze::parse(&text).unwrap(),
        mazes::aggregation_control_maze()
    );
}
