//! Fuzz target: arbitrary bytes as a run store bundle or loose run file through
//! `eamadm_runs::store::check_bytes` (decompression with its per-entry cap, header, checksum,
//! key, record and agreement checks). Any panic is a bug.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let (verified, problems) = eamadm_runs::store::check_bytes(data);
    // Every entry is either verified or named as a problem; never more than the bytes allow.
    assert!(verified + problems.len() <= data.len());
});
