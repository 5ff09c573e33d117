//! Shared proptest strategies: small random mazes.

#![allow(
    dead_code,
    unreachable_pub,
    reason = "each test module uses part of these shared helpers"
)]

use mazes::{GeneratorParams, Maze, Pos, generate_seeded};
use proptest::prelude::*;

/// Random generator parameters for grids up to `max_side × max_side` (at least 2 tiles),
/// any distinct start and target, an obstacle count up to `max_fraction` of the feasible most.
pub fn small_params(max_side: usize, max_fraction: f64) -> impl Strategy<Value = GeneratorParams> {
    (1..=max_side, 1..=max_side)
        .prop_filter("need two tiles", |(w, h)| w * h >= 2)
        .prop_flat_map(move |(width, height)| {
            (
                Just((width, height)),
                0..width,
                0..height,
                0..width,
                0..height,
                0.0..=max_fraction,
            )
        })
        .prop_filter("start and target differ", |(_, sx, sy, tx, ty, _)| {
            (sx, sy) != (tx, ty)
        })
        .prop_map(|((width, height), sx, sy, tx, ty, fraction)| {
            let mut params = GeneratorParams {
                width,
                height,
                obstacles: 0,
                start: Pos::new(sx, sy),
                target: Pos::new(tx, ty),
                max_attempts: 200,
            };
            // Truncation keeps the count within the feasible range [0, max_obstacles].
            params.obstacles = (fraction * params.max_obstacles() as f64) as usize;
            params
        })
}

/// Random small mazes (the generator succeeds for most parameters; the rest are skipped).
pub fn small_maze(max_side: usize) -> impl Strategy<Value = Maze> {
    (small_params(max_side, 0.6), any::<u64>())
        .prop_filter_map("generation gave up", |(params, seed)| {
            generate_seeded(&params, seed).ok()
        })
}
