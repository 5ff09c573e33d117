//! Lookups in a tree of 3,600 samples (Task I: 30 × 30 cells × 4 actions) against a plain
//! `HashMap<(state, action), (Q1, Q2)>`, with the literal walk of Fig. 4 beside them.
//!
//! Each benchmark iteration answers all 3,600 pairs once, in a shuffled order; divide the
//! time by 3,600 for ns per lookup. The setup prints the tree's bytes per cluster.
#![allow(
    missing_docs,
    clippy::unwrap_used,
    reason = "benchmark set-up may unwrap, and criterion's generated main has no docs"
)]

use eamadm::ea_tree;
use std::collections::HashMap;
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ea_tree::{EaTree, EaTreeConfig, Sample, TableEntry};
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SIDE: u32 = 30;
const ACTIONS: usize = 4;

struct Fixture {
    /// Feature bins `[x, y]` of each state id.
    features: Vec<[u32; 2]>,
    /// `(state id, action, q1, q2)` for every pair.
    table: Vec<(usize, usize, f64, f64)>,
    /// Every `(state id, action)` once, shuffled.
    queries: Vec<(usize, usize)>,
}

fn fixture() -> Fixture {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let features: Vec<[u32; 2]> = (0..SIDE)
        .flat_map(|x| (0..SIDE).map(move |y| [x, y]))
        .collect();
    let mut table = Vec::new();
    for state in 0..features.len() {
        for action in 0..ACTIONS {
            table.push((
                state,
                action,
                rng.random_range(-100.0..100.0),
                rng.random_range(-100.0..100.0),
            ));
        }
    }
    let mut queries: Vec<(usize, usize)> = table.iter().map(|&(s, a, _, _)| (s, a)).collect();
    queries.shuffle(&mut rng);
    Fixture {
        features,
        table,
        queries,
    }
}

fn tree(fixture: &Fixture, config: EaTreeConfig) -> EaTree {
    EaTree::from_table(
        config,
        fixture
            .table
            .iter()
            .map(|&(state_id, action, q1, q2)| TableEntry {
                state_id,
                state: &fixture.features[state_id],
                action,
                q1,
                q2,
            }),
    )
    .unwrap()
}

/// Estimated heap bytes of a `std` `HashMap` (same estimate as the tree's stats).
fn hash_map_bytes<K, V>(capacity: usize) -> usize {
    let buckets = (capacity * 8 / 7).next_power_of_two();
    buckets * (size_of::<(K, V)>() + 1) + 16
}

fn lookups(c: &mut Criterion) {
    let fixture = fixture();
    let map: HashMap<(usize, usize), (f64, f64)> = fixture
        .table
        .iter()
        .map(|&(s, a, q1, q2)| ((s, a), (q1, q2)))
        .collect();
    let exact = tree(&fixture, EaTreeConfig::EXACT);
    let answers = exact.answer_table(fixture.features.iter().map(<[u32; 2]>::as_slice), ACTIONS);

    let stats = exact.stats();
    let map_bytes = hash_map_bytes::<(usize, usize), (f64, f64)>(map.capacity());
    println!(
        "tau=1 tree: {} clusters, depth {}, longest chain {}, {} B ({} clusters + {} index) = {:.1} B/cluster; \
         HashMap: {map_bytes} B = {:.1} B/entry",
        stats.clusters,
        stats.depth,
        stats.longest_chain,
        stats.bytes(),
        stats.cluster_bytes,
        stats.index_bytes,
        stats.bytes_per_cluster(),
        map_bytes as f64 / map.len() as f64,
    );

    let mut group = c.benchmark_group("lookup_3600_tau1");
    group.throughput(Throughput::Elements(fixture.queries.len() as u64));
    group.bench_function("hashmap", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(s, a) in &fixture.queries {
                if let Some(&(q1, q2)) = map.get(black_box(&(s, a))) {
                    sum += 0.5 * q1 + 0.5 * q2;
                }
            }
            sum
        });
    });
    group.bench_function("ea_tree_indexed", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(s, a) in &fixture.queries {
                if let Some(answer) = exact.lookup(black_box(&fixture.features[s]), a) {
                    sum += answer.q_mean();
                }
            }
            sum
        });
    });
    group.bench_function("ea_tree_answer_table", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(s, a) in &fixture.queries {
                if let Some(answer) = answers.get(black_box(s), a) {
                    sum += answer.q_mean();
                }
            }
            sum
        });
    });
    group.bench_function("ea_tree_literal", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(s, a) in &fixture.queries {
                if let Some(answer) = exact.lookup_literal(black_box(&fixture.features[s]), a) {
                    sum += answer.q_mean();
                }
            }
            sum
        });
    });
    group.finish();

    // Below τ = 1: the shared-token index. At τₛ = 0.5 no two cells merge (sharing one
    // coordinate gives 1/3), so the tree has the same degenerate chain as at τ = 1.
    let loose = tree(&fixture, EaTreeConfig::new(0.5, 1.0).unwrap());
    let mut group = c.benchmark_group("lookup_3600_tau_s_0.5");
    group.throughput(Throughput::Elements(fixture.queries.len() as u64));
    group.bench_function("ea_tree_indexed", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(s, a) in &fixture.queries {
                if let Some(answer) = loose.lookup(black_box(&fixture.features[s]), a) {
                    sum += answer.q_mean();
                }
            }
            sum
        });
    });
    group.bench_function("ea_tree_literal", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            for &(s, a) in &fixture.queries {
                if let Some(answer) = loose.lookup_literal(black_box(&fixture.features[s]), a) {
                    sum += answer.q_mean();
                }
            }
            sum
        });
    });
    group.finish();
}

fn build(c: &mut Criterion) {
    let fixture = fixture();
    let mut group = c.benchmark_group("build_3600_tau1");
    group.sample_size(10);
    group.bench_function("insert_indexed", |b| {
        b.iter(|| tree(&fixture, EaTreeConfig::EXACT).len());
    });
    group.bench_function("insert_literal", |b| {
        b.iter(|| {
            let mut tree = EaTree::new(EaTreeConfig::EXACT).unwrap();
            for &(s, a, q1, q2) in &fixture.table {
                tree.insert_literal(Sample {
                    state: &fixture.features[s],
                    action: a,
                    q1,
                    q2,
                })
                .unwrap();
            }
            tree.len()
        });
    });
    group.finish();
}

criterion_group!(benches, lookups, build);
criterion_main!(benches);
