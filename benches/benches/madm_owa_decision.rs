//! Speed of one full MADM decision on the robot task's shape: 5 actions x 4 attributes
//! (3 sub-task values and the source task's own). Target: at most 200 ns per decision.

use eamadm::madm_owa;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use madm_owa::{MadmDecider, Support, Weighting};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A realistic 5x4 decision matrix: Q-values of mixed sign and scale, one exact tie.
const MATRIX: [f64; 20] = [
    12.5, -3.0, 0.8, 4.1, //
    10.2, 1.5, 0.8, 3.9, //
    -95.0, 2.0, 1.1, -7.5, //
    11.0, 0.3, 0.8, 4.4, //
    9.7, 2.2, 2.2, 5.0, //
];

fn bench_decision(c: &mut Criterion) {
    let weightings = [
        ("visibility_paper", Weighting::default()),
        (
            "visibility_distance",
            Weighting::Visibility {
                support: Support::Distance,
            },
        ),
        ("uniform", Weighting::Uniform),
    ];
    let mut group = c.benchmark_group("madm_5x4");
    for (name, weighting) in weightings {
        let mut decider = MadmDecider::new(weighting).expect("valid weighting");
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        group.bench_function(format!("best_row/{name}"), |b| {
            b.iter(|| {
                decider
                    .best_row(black_box(&MATRIX), 5, 4, &mut rng)
                    .expect("valid matrix")
            });
        });
        let mut out = [0.0; 5];
        group.bench_function(format!("evaluate/{name}"), |b| {
            b.iter(|| {
                decider
                    .evaluate(black_box(&MATRIX), 5, 4, &mut out)
                    .expect("valid matrix");
                black_box(out[0])
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench_decision);
criterion_main!(benches);
