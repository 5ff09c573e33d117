//! Text and SVG rendering.

use mazes::{Maze, Pos, SvgOptions, SvgTrajectory, render_svg, render_text};

fn small_maze() -> Maze {
    Maze::parse(
        "S...#.\n\
         .##.#.\n\
         ...#..\n\
         .#...T\n",
    )
    .expect("a valid map")
}

fn walk(moves: &[(usize, usize)]) -> Vec<Pos> {
    moves.iter().map(|&(x, y)| Pos::new(x, y)).collect()
}

#[test]
fn text_rendering_of_a_trajectory() {
    let maze = small_maze();
    // A detour with a bump against the obstacle at (1, 1): the repeated tile.
    let trajectory = walk(&[
        (0, 0),
        (1, 0),
        (1, 0),
        (2, 0),
        (3, 0),
        (3, 1),
        (3, 2),
        (4, 2),
        (4, 3),
        (5, 3),
    ]);
    insta::assert_snapshot!(render_text(&maze, &trajectory), @r"
    S***#.
    .##*#.
    ...**.
    .#..*T
    ");
    insta::assert_snapshot!(render_text(&maze, &maze.shortest_path()), @r"
    S...#.
    *##.#.
    ***#..
    .#***T
    ");
}

#[test]
fn text_rendering_without_a_trajectory_is_the_map() {
    let maze = small_maze();
    assert_eq!(render_text(&maze, &[]), maze.to_text());
    // Tiles outside the grid are ignored.
    assert_eq!(render_text(&maze, &[Pos::new(9, 9)]), maze.to_text());
}

#[test]
fn svg_rendering_of_two_trajectories() {
    let maze = Maze::parse("S.#\n..T\n").unwrap();
    let bfs = maze.shortest_path();
    let detour = walk(&[(0, 0), (0, 1), (0, 0), (1, 0), (1, 1), (2, 1)]);
    let svg = render_svg(
        &maze,
        &[
            SvgTrajectory {
                label: "BFS",
                path: &bfs,
                color: None,
            },
            SvgTrajectory {
                label: "ε-greedy <1>",
                path: &detour,
                color: Some("crimson"),
            },
        ],
        &SvgOptions {
            tile_px: 20,
            title: Some("Task & demo".to_owned()),
            grid_lines: true,
        },
    );
    assert_eq!(svg.matches("<polyline").count(), 2);
    assert_eq!(svg.matches("fill=\"#808080\"").count(), 1, "one obstacle");
    assert!(
        svg.contains("ε-greedy &lt;1&gt; (5 steps)"),
        "labels are escaped"
    );
    assert!(svg.contains("Task &amp; demo"));
    insta::assert_snapshot!(svg);
}

#[test]
fn svg_handles_degenerate_input() {
    let maze = small_maze();
    let svg = render_svg(
        &maze,
        &[
            SvgTrajectory {
                label: "empty",
                path: &[],
                color: None,
            },
            SvgTrajectory {
                label: "one tile",
                path: &[Pos::new(0, 0)],
                color: None,
            },
        ],
        &SvgOptions {
            tile_px: 0,
            title: None,
            grid_lines: false,
        },
    );
    assert_eq!(svg.matches("<polyline").count(), 0);
    assert_eq!(svg.matches("<circle").count(), 1);
    assert!(!svg.contains("NaN"));
}
