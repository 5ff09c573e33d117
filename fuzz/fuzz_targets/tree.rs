//! Fuzz target: saved experience-aggregation trees through `EaTree::from_json`, then a lookup
//! and a save. Any panic is a bug.
#![no_main]

use eamadm::ea_tree::{EaTree, WeightedJaccard};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(tree) = EaTree::<WeightedJaccard>::from_json(text) {
        let _ = tree.lookup(&[0, 0], 0);
        let _ = tree.to_json();
    }
});
