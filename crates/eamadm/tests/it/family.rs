//! The maze family (issue 33): the default family pinned layout by layout, its laws (prefixes,
//! sizes, mixing), its experiments, and the layout table.

use eamadm::config::TaskConfig;
use eamadm::family::{
    DEFAULT_FAMILY_SIZE, FAMILY_SEED_BASE, FamilyError, LAYOUT_COLUMNS, MAX_FAMILY_SIZE, RECIPES,
    maze_family, methods, paper_layout_rows, write_layouts_csv,
};
use eamadm::mazes::{LayoutKind, Preset};
use eamadm::{Experiment, Role, scores};

/// The 64-bit FNV-1a hash of a map's text: a short fingerprint of every tile.
fn fingerprint(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Value stability: every layout of the default family, with its kind, seed, size, obstacle
/// count, optimum, Manhattan distance, detour ratio and a fingerprint of its map. A change of
/// a generator, a draw or a recipe shows here.
#[test]
fn the_default_family_is_pinned_layout_by_layout() {
    let family = maze_family(DEFAULT_FAMILY_SIZE).unwrap();
    let lines: Vec<String> = family
        .iter()
        .map(|layout| {
            format!(
                "{} {} seed {} {}x{} obstacles {} optimum {} manhattan {} ratio {:.3} map {:016x}",
                layout.name,
                layout.kind().name(),
                layout.seed,
                layout.maze.width(),
                layout.maze.height(),
                layout.maze.obstacle_count(),
                layout.optimum(),
                layout.maze.manhattan_distance(),
                layout.detour_ratio(),
                fingerprint(&layout.maze.to_text()),
            )
        })
        .collect();
    insta::assert_snapshot!(lines.join("\n"));
}

#[test]
fn the_default_family_mixes_kinds_densities_and_detours() {
    let family = maze_family(DEFAULT_FAMILY_SIZE).unwrap();
    assert_eq!(family.len(), 24);
    for kind in LayoutKind::ALL {
        assert_eq!(
            family.iter().filter(|l| l.kind() == kind).count(),
            6,
            "{kind:?}"
        );
    }
    // Any four consecutive layouts hold one of each kind.
    for window in family.chunks(4) {
        let mut kinds: Vec<_> = window
            .iter()
            .map(eamadm::family::FamilyLayout::kind)
            .collect();
        kinds.sort();
        assert_eq!(kinds, LayoutKind::ALL);
    }
    let ratios: Vec<f64> = family
        .iter()
        .map(eamadm::family::FamilyLayout::detour_ratio)
        .collect();
    let at_bound = ratios.iter().filter(|&&r| r == 1.0).count();
    let far = ratios.iter().filter(|&&r| r >= 2.0).count();
    assert!(at_bound >= 2, "layouts at the Manhattan bound: {ratios:?}");
    assert!(
        far >= 6,
        "layouts at least twice the Manhattan distance: {ratios:?}"
    );
    assert!(
        ratios.iter().copied().fold(0.0, f64::max) >= 5.0,
        "{ratios:?}"
    );
    let densities: Vec<f64> = family
        .iter()
        .map(|l| l.maze.obstacle_count() as f64 / l.maze.n_tiles() as f64)
        .collect();
    assert!(densities.iter().any(|&d| d < 0.12) && densities.iter().any(|&d| d > 0.4));
    // Names are unique, and none of the paper's layouts is in the family.
    let mut names: Vec<&str> = family.iter().map(|l| l.name.as_str()).collect();
    names.dedup();
    assert_eq!(names.len(), 24);
    for preset in Preset::ALL {
        assert!(family.iter().all(|l| l.maze != preset.maze()));
    }
}

/// A larger family starts with the default one and cycles the recipes with new seeds; the
/// first 200 layouts all generate.
#[test]
fn larger_families_extend_the_default_one() {
    let family = maze_family(200).unwrap();
    assert_eq!(family[..24], maze_family(24).unwrap()[..]);
    for layout in &family {
        assert_eq!(layout.spec, RECIPES[layout.index % RECIPES.len()]);
        assert_eq!(layout.seed, FAMILY_SEED_BASE + layout.index as u64);
        assert_eq!(
            Some(layout.maze.obstacle_count()),
            layout.spec.obstacle_count()
        );
    }
    assert_eq!(family[24].name, "f24-uniform");
    assert_ne!(family[24].maze, family[0].maze);
    assert_eq!(maze_family(5).unwrap()[..], family[..5]);
}

#[test]
fn a_family_size_out_of_range_is_refused() {
    for size in [0, MAX_FAMILY_SIZE + 1] {
        let error = maze_family(size).unwrap_err();
        assert!(matches!(error, FamilyError::Size { size: s } if s == size));
        assert_eq!(
            error.to_string(),
            format!("a family of {size} layouts: expected 1 to 10000 layouts")
        );
    }
}

/// Every layout is a maze experiment of Task II's rewards with the family's methods, which
/// loads, and whose optimum is the layout's.
#[test]
fn every_layout_is_a_loadable_experiment() {
    let labels: Vec<String> = methods().into_iter().map(|spec| spec.label).collect();
    assert_eq!(
        labels,
        [
            "ea-madm",
            "epsilon-greedy",
            "epsilon-decreasing",
            "softmax",
            "ea-madm-table",
            "ea-madm-uniform",
            "ea-madm-literal",
            "ea-madm-distance",
            "subtask0-alone",
            "epsilon-greedy-shaped",
            "epsilon-decreasing-shaped",
            "softmax-shaped",
        ]
    );
    for layout in maze_family(DEFAULT_FAMILY_SIZE).unwrap() {
        let config = layout.experiment();
        assert_eq!(config.name, format!("family-{}", layout.name));
        assert!(matches!(
            &config.task,
            TaskConfig::MazeText {
                rewards: Preset::Task2,
                step_cap: None,
                ..
            }
        ));
        assert_eq!(
            (config.episodes, config.seeds, config.base_seed),
            (6400, 10, 0)
        );
        let experiment = Experiment::new(config).unwrap();
        assert_eq!(
            experiment.task().optimum_steps(),
            Some(layout.optimum() as u64)
        );
    }
}

/// A family layout runs end to end: a trap with every method shortened, scored like the
/// paper's mazes (one row per method and seed, the layout's optimum).
#[test]
fn a_family_layout_runs_and_scores() {
    let family = maze_family(4).unwrap();
    let mut config = family[3].experiment();
    config.episodes = 4;
    config.seeds = 1;
    if let TaskConfig::MazeText { step_cap, .. } = &mut config.task {
        *step_cap = Some(200);
    }
    for spec in &mut config.methods {
        if let eamadm::Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = 3;
        }
        if let eamadm::Method::SubtaskGreedy(alone) = &mut spec.method {
            alone.pretrain.episodes = 3;
        }
    }
    let experiment = Experiment::new(config).unwrap();
    let records = experiment.run_all().unwrap();
    let rows = scores::final_scores(&records, &experiment).unwrap();
    assert_eq!(rows.len(), 12);
    assert!(
        rows.iter()
            .all(|row| row.optimum_steps == Some(family[3].optimum() as u64))
    );
    assert_eq!(rows.iter().filter(|row| row.role == Role::Paper).count(), 4);
}

#[test]
fn the_layout_table_has_its_documented_columns() {
    let mut rows: Vec<_> = maze_family(4)
        .unwrap()
        .iter()
        .map(eamadm::family::FamilyLayout::row)
        .collect();
    rows.extend(paper_layout_rows());
    let mut bytes = Vec::new();
    write_layouts_csv(&rows, &mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .unwrap()
        .iter()
        .map(str::to_owned)
        .collect();
    let names: Vec<&str> = LAYOUT_COLUMNS.iter().map(|c| c.name).collect();
    assert_eq!(header, names);
    let records: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(records.len(), 6);
    // The paper's layouts close the table, at the Manhattan bound.
    assert_eq!(&records[4][0], "task1");
    assert_eq!(&records[5][0], "task2");
    assert_eq!(&records[4][14], "1.0");
    assert_eq!(&records[5][13], "73");
    // The map column reads back as the layout.
    let first = &maze_family(1).unwrap()[0];
    assert_eq!(&records[0][15], first.maze.to_text());
    assert_eq!(
        eamadm::mazes::Maze::parse(&records[0][15]).unwrap(),
        first.maze
    );
    let parameters: eamadm::mazes::LayoutSpec = serde_json::from_str(&records[0][2]).unwrap();
    assert_eq!(parameters.generate(first.seed).unwrap(), first.maze);
    let mut empty = Vec::new();
    write_layouts_csv(&[], &mut empty).unwrap();
    assert_eq!(
        String::from_utf8(empty).unwrap().trim_end(),
        names.join(",")
    );
}

/// The `layout` of each experiment's rows: a preset's id (its readings' too), a family
/// layout's name, the robot's scenario, another map's experiment name; and the run's layout
/// table: the paper's two, then each other maze layout once (the positive control's map as
/// hand-designed, a family layout with its generator), the robot none; it reads back.
#[test]
fn every_experiment_names_its_layout_and_the_table_lists_each_maze_once() {
    use eamadm::scores::MethodRoles;
    let family = maze_family(2).unwrap();
    let experiment = |config| Experiment::new(config).unwrap();
    let task2 = experiment(eamadm::paper::task2());
    let reading = experiment(
        eamadm::paper::readings()
            .iter()
            .find_map(|r| r.apply(&eamadm::paper::task2()))
            .unwrap(),
    );
    let robot = experiment(eamadm::paper::robot());
    let control = experiment(eamadm::paper::aggregation_control());
    let layout = experiment(family[1].experiment());
    let names: Vec<String> = [&task2, &reading, &robot, &control, &layout]
        .iter()
        .map(|e| e.layout())
        .collect();
    assert_eq!(
        names,
        [
            "task2",
            "task2",
            "fig12",
            "aggregation-control",
            "f01-perfect"
        ]
    );
    let row = family[1].row();
    let rows = eamadm::family::layouts_table([
        (&task2, None),
        (&reading, None),
        (&robot, None),
        (&control, None),
        (&layout, Some(&row)),
        (&control, None),
    ]);
    let names: Vec<&str> = rows.iter().map(|r| r.layout.as_str()).collect();
    assert_eq!(
        names,
        ["task1", "task2", "aggregation-control", "f01-perfect"]
    );
    assert_eq!(rows[2].kind, None);
    assert_eq!((rows[2].optimum_steps, rows[2].manhattan_steps), (64, 24));
    assert_eq!(rows[3], row);
    let mut bytes = Vec::new();
    write_layouts_csv(&rows, &mut bytes).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    // A hand-designed map has no kind, parameters or generator seed: blank cells.
    assert!(text.contains("\naggregation-control,,,,30,30,"), "{text}");
    assert_eq!(
        eamadm::family::read_layouts_csv(bytes.as_slice()).unwrap(),
        rows
    );
}
