//! The cost of one call of each resampling statistic at the size the verdicts report uses:
//! 20 seeds per method, 10 000 resamples (the defaults), IQM and mean.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use eamadm::stats::{Bootstrap, PermutationTest, Statistic, probability_of_improvement};

/// Twenty seeds of final steps: most near the optimum, a few stuck at the 2000-step cap.
fn seeds(offset: f64) -> Vec<f64> {
    (0..20)
        .map(|i| {
            if i % 5 == 0 {
                2000.0
            } else {
                73.0 + offset + f64::from(i % 7) * 3.5
            }
        })
        .collect()
}

fn bench_stats(c: &mut Criterion) {
    let x = seeds(0.0);
    let y = seeds(40.0);
    let bootstrap = Bootstrap::default();
    let permutation = PermutationTest::default();
    for statistic in [Statistic::Iqm, Statistic::Mean] {
        let name = statistic.name();
        c.bench_function(&format!("bootstrap interval, {name}, n = 20"), |b| {
            b.iter(|| bootstrap.interval(black_box(&x), statistic));
        });
        c.bench_function(&format!("bootstrap difference, {name}, 20 vs 20"), |b| {
            b.iter(|| bootstrap.difference(black_box(&x), black_box(&y), statistic));
        });
        c.bench_function(
            &format!("stratified interval, {name}, 3 groups of 20"),
            |b| b.iter(|| bootstrap.stratified_interval(&[&x, &y, &x], statistic)),
        );
        c.bench_function(&format!("permutation p, {name}, 20 vs 20"), |b| {
            b.iter(|| permutation.p_value(black_box(&x), black_box(&y), statistic));
        });
    }
    c.bench_function("probability of improvement, 20 vs 20", |b| {
        b.iter(|| probability_of_improvement(black_box(&x), black_box(&y)));
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench_stats
}
criterion_main!(benches);
