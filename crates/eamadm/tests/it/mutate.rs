//! Byte-level mutation of seed inputs for the fuzz tests: set, insert, remove, duplicate, insert
//! a token parsers treat specially, truncate. Proptest draws the edits, so every case is
//! reproducible and shrinks to a small edit list.

use proptest::prelude::*;

/// Cases per fuzz property: `EAMADM_FUZZ_CASES`, or 256.
pub(crate) fn fuzz_config() -> ProptestConfig {
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

/// One edit of a byte string.
#[derive(Debug, Clone)]
pub(crate) enum Edit {
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

pub(crate) const TOKENS: &[&str] = &[
    "-1",
    "..",
    "/",
    "\"\"\"",
    "[[methods]]",
    "kind = \"robot\"",
    "1e9",
    "1.0e10",
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

pub(crate) fn edit() -> impl Strategy<Value = Edit> {
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

pub(crate) fn apply(mut bytes: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
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

/// A mutated seed: one of `corpus` with 1 to 8 edits.
pub(crate) fn mutated(corpus: Vec<Vec<u8>>) -> impl Strategy<Value = Vec<u8>> {
    (0..corpus.len(), prop::collection::vec(edit(), 1..8))
        .prop_map(move |(seed, edits)| apply(corpus[seed].clone(), &edits))
}

/// A mutated seed as text (invalid UTF-8 replaced), for parsers of `&str`.
pub(crate) fn mutated_text(corpus: Vec<String>) -> impl Strategy<Value = String> {
    mutated(corpus.into_iter().map(String::into_bytes).collect())
        .prop_map(|bytes| String::from_utf8_lossy(&bytes).into_owned())
}
