//! Fuzzing the tree-file loader (issue 14, item 12): random bytes and byte-mutated valid tree
//! files go through `EaTree::from_json` and `EaTree::load`; every input must give a tree or a
//! typed `LoadError`, never a panic (proptest turns a panic into a failed test).
//!
//! The case count is bounded for `cargo test` (a few seconds); set `EAMADM_FUZZ_CASES` to run
//! longer, e.g. `EAMADM_FUZZ_CASES=100000 cargo test -p ea-tree --test it fuzz`.

use ea_tree::{EaTree, EaTreeConfig, Sample};
use proptest::prelude::*;

/// Cases per fuzz property: `EAMADM_FUZZ_CASES`, or 256.
fn fuzz_config() -> ProptestConfig {
    let cases = std::env::var("EAMADM_FUZZ_CASES")
        .ok()
        .and_then(|text| text.parse().ok())
        .unwrap_or(256);
    ProptestConfig {
        cases,
        max_shrink_iters: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Valid tree files to mutate: an empty tree, and trees with a few clusters.
fn corpus() -> Vec<Vec<u8>> {
    let mut files = Vec::new();
    for (state_threshold, action_threshold, n) in [(1.0, 1.0, 0), (0.3, 0.5, 4), (0.0, 1.0, 9)] {
        let mut tree: EaTree =
            EaTree::new(EaTreeConfig::new(state_threshold, action_threshold).unwrap()).unwrap();
        for i in 0..n {
            let state = [i % 3, i / 3, 7];
            tree.insert(Sample {
                state: &state,
                action: (i % 2) as usize,
                q1: f64::from(i) * 0.5 - 1.0,
                q2: -f64::from(i),
            })
            .unwrap();
        }
        files.push(tree.to_json().into_bytes());
    }
    files
}

/// One edit of a byte string.
#[derive(Debug, Clone)]
enum Edit {
    /// Replace the byte at (position mod length).
    Set(usize, u8),
    /// Insert a byte.
    Insert(usize, u8),
    /// Remove up to `len` bytes.
    Remove(usize, usize),
    /// Copy a run of bytes to another place.
    Duplicate(usize, usize, usize),
    /// Insert a token that parsers treat specially.
    Token(usize, usize),
    /// Cut the input short.
    Truncate(usize),
}

const TOKENS: &[&str] = &[
    "-1",
    "0",
    "1e308",
    "-1e308",
    "NaN",
    "inf",
    "null",
    "18446744073709551616",
    "4294967296",
    "\"\"",
    "[]",
    "{}",
    "true",
    "\"\\u0000\"",
    ",",
    ":",
    "\n",
    "9007199254740993",
    "-0",
];

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, byte)| Edit::Set(at, byte)),
        (any::<usize>(), any::<u8>()).prop_map(|(at, byte)| Edit::Insert(at, byte)),
        (any::<usize>(), 0..16_usize).prop_map(|(at, len)| Edit::Remove(at, len)),
        (any::<usize>(), 0..32_usize, any::<usize>())
            .prop_map(|(from, len, to)| Edit::Duplicate(from, len, to)),
        (any::<usize>(), 0..TOKENS.len()).prop_map(|(at, token)| Edit::Token(at, token)),
        any::<usize>().prop_map(Edit::Truncate),
    ]
}

fn apply(mut bytes: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
    for edit in edits {
        let len = bytes.len();
        let at = |i: usize| if len == 0 { 0 } else { i % (len + 1) };
        match *edit {
            Edit::Set(i, byte) if len > 0 => bytes[i % len] = byte,
            Edit::Set(..) => {}
            Edit::Insert(i, byte) => bytes.insert(at(i), byte),
            Edit::Remove(i, n) => {
                let start = at(i).min(len);
                let end = (start + n).min(len);
                bytes.drain(start..end);
            }
            Edit::Duplicate(from, n, to) => {
                let start = at(from).min(len);
                let end = (start + n).min(len);
                let run: Vec<u8> = bytes[start..end].to_vec();
                let to = at(to);
                bytes.splice(to..to, run);
            }
            Edit::Token(i, token) => {
                let to = at(i);
                bytes.splice(to..to, TOKENS[token].bytes());
            }
            Edit::Truncate(i) => bytes.truncate(at(i)),
        }
    }
    bytes
}

/// A mutated corpus file: a seed from the corpus and 1 to 8 edits.
fn mutated() -> impl Strategy<Value = Vec<u8>> {
    let corpus = corpus();
    (0..corpus.len(), prop::collection::vec(edit(), 1..8))
        .prop_map(move |(seed, edits)| apply(corpus[seed].clone(), &edits))
}

/// Loading must end in `Ok` or `Err`; a loaded tree must answer lookups and save again.
fn load_text(text: &str) {
    if let Ok(tree) = EaTree::<ea_tree::WeightedJaccard>::from_json(text) {
        let _ = tree.to_json();
        let _ = tree.lookup(&[0, 0, 7], 0);
        let _ = tree.stats();
    }
}

proptest! {
    #![proptest_config(fuzz_config())]

    #[test]
    fn fuzz_mutated_tree_files_never_panic(bytes in mutated()) {
        load_text(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn fuzz_random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        load_text(&String::from_utf8_lossy(&bytes));
    }
}

/// The file loader too: invalid UTF-8 and mutated files on disk are typed errors.
#[test]
fn fuzz_mutated_tree_files_load_from_disk_without_panic() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tree.json");
    let mut runner = proptest::test_runner::TestRunner::new_with_rng(
        ProptestConfig {
            cases: 32,
            ..fuzz_config()
        },
        proptest::test_runner::TestRng::deterministic_rng(
            proptest::test_runner::RngAlgorithm::ChaCha,
        ),
    );
    runner
        .run(&mutated(), |bytes| {
            std::fs::write(&path, &bytes).unwrap();
            if let Ok(tree) = EaTree::<ea_tree::WeightedJaccard>::load(&path) {
                let _ = tree.to_json();
            }
            Ok(())
        })
        .unwrap();
}
