//! Seeded generation: the laws every generated maze obeys, and impossible requests.

use crate::common;

use mazes::{GeneratorParams, MazeError, Pos, generate, generate_seeded};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

proptest! {
    /// Exactly the requested obstacle count, free start and target at the requested
    /// tiles, reachable target; or, only for dense requests, a typed give-up.
    #[test]
    fn generated_mazes_obey_the_request(params in common::small_params(10, 1.0), seed: u64) {
        match generate_seeded(&params, seed) {
            Ok(maze) => {
                prop_assert_eq!((maze.width(), maze.height()), (params.width, params.height));
                prop_assert_eq!(maze.obstacle_count(), params.obstacles);
                prop_assert_eq!(maze.start(), params.start);
                prop_assert_eq!(maze.target(), params.target);
                prop_assert!(maze.is_free(maze.start()) && maze.is_free(maze.target()));
                let path = maze.shortest_path();
                prop_assert_eq!(path.first(), Some(&params.start));
                prop_assert_eq!(path.last(), Some(&params.target));
            }
            Err(error) => prop_assert_eq!(
                error,
                MazeError::NoReachableLayout { attempts: params.max_attempts }
            ),
        }
    }

    /// The same seed gives the same maze; `generate_seeded` is `generate` with ChaCha8.
    #[test]
    fn generation_is_deterministic(params in common::small_params(10, 0.5), seed: u64) {
        let first = generate_seeded(&params, seed);
        prop_assert_eq!(&first, &generate_seeded(&params, seed));
        prop_assert_eq!(&first, &generate(&params, &mut ChaCha8Rng::seed_from_u64(seed)));
    }

    /// The feasibility bound is exact: asking for one obstacle more is refused.
    #[test]
    fn one_obstacle_past_the_bound_is_refused(params in common::small_params(10, 0.0)) {
        let max = params.max_obstacles();
        let request = GeneratorParams { obstacles: max + 1, ..params };
        prop_assert_eq!(
            generate_seeded(&request, 0),
            Err(MazeError::TooManyObstacles { requested: max + 1, max })
        );
    }
}

#[test]
fn the_bound_itself_is_reachable_when_the_path_is_forced() {
    // A 1 × 5 corridor with the target at the far end: no obstacle fits.
    let corridor = GeneratorParams::corner_to_corner(5, 1, 0);
    assert_eq!(corridor.max_obstacles(), 0);
    assert_eq!(generate_seeded(&corridor, 3).unwrap().to_text(), "S...T\n");
    // Start and target adjacent on 3 × 3: all 7 other tiles can be obstacles.
    let full = GeneratorParams {
        start: Pos::new(1, 1),
        target: Pos::new(2, 1),
        ..GeneratorParams::corner_to_corner(3, 3, 7)
    };
    assert_eq!(full.max_obstacles(), 7);
    assert_eq!(
        generate_seeded(&full, 3).unwrap().to_text(),
        "###\n#ST\n###\n"
    );
}

#[test]
fn impossible_requests_are_typed_errors() {
    let base = GeneratorParams::corner_to_corner(4, 3, 2);
    let cases = [
        (
            GeneratorParams { width: 0, ..base },
            MazeError::EmptyGrid {
                width: 0,
                height: 3,
            },
        ),
        (
            GeneratorParams {
                width: 1 << 20,
                height: 1 << 20,
                ..base
            },
            MazeError::TooLarge {
                width: 1 << 20,
                height: 1 << 20,
            },
        ),
        (
            GeneratorParams {
                start: Pos::new(4, 0),
                ..base
            },
            MazeError::OutOfBounds {
                what: "start",
                pos: Pos::new(4, 0),
                width: 4,
                height: 3,
            },
        ),
        (
            GeneratorParams {
                target: Pos::new(0, 3),
                ..base
            },
            MazeError::OutOfBounds {
                what: "target",
                pos: Pos::new(0, 3),
                width: 4,
                height: 3,
            },
        ),
        (
            GeneratorParams {
                target: Pos::new(0, 0),
                ..base
            },
            MazeError::StartIsTarget {
                pos: Pos::new(0, 0),
            },
        ),
        (
            GeneratorParams {
                obstacles: 7,
                ..base
            },
            MazeError::TooManyObstacles {
                requested: 7,
                max: 6,
            },
        ),
        (
            GeneratorParams {
                max_attempts: 0,
                ..base
            },
            MazeError::ZeroAttempts,
        ),
    ];
    for (params, expected) in cases {
        assert_eq!(generate_seeded(&params, 0), Err(expected), "{params:?}");
    }
}

#[test]
fn bounded_attempts_give_up_with_a_typed_error() {
    // 6 obstacles among the 10 tiles left of an open 4 × 3 grid, one attempt: some seed
    // must block the target (the max is 6, and most layouts at the max are blocked).
    let params = GeneratorParams {
        max_attempts: 1,
        ..GeneratorParams::corner_to_corner(4, 3, 6)
    };
    let failure = (0..100)
        .map(|seed| generate_seeded(&params, seed))
        .find(Result::is_err)
        .expect("some seed fails in one attempt");
    assert_eq!(failure, Err(MazeError::NoReachableLayout { attempts: 1 }));
    let message = failure.unwrap_err().to_string();
    assert!(message.contains("after 1 attempts"), "{message}");
}

#[test]
fn error_messages_name_the_parameter() {
    let too_many = generate_seeded(&GeneratorParams::corner_to_corner(4, 3, 9), 0).unwrap_err();
    assert_eq!(
        too_many.to_string(),
        "`obstacles` = 9 is more than the 6 that fit while keeping a path from start to target open"
    );
    let zero = generate_seeded(
        &GeneratorParams {
            max_attempts: 0,
            ..GeneratorParams::corner_to_corner(4, 3, 1)
        },
        0,
    )
    .unwrap_err();
    assert_eq!(zero.to_string(), "`max_attempts` must be at least 1, got 0");
}

#[test]
fn params_deserialise_with_a_default_attempt_bound() {
    let params: GeneratorParams = serde_json::from_str(
        r#"{"width": 30, "height": 30, "obstacles": 100,
            "start": {"x": 0, "y": 0}, "target": {"x": 29, "y": 29}}"#,
    )
    .unwrap();
    assert_eq!(params, GeneratorParams::corner_to_corner(30, 30, 100));
}
