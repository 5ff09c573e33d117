//! The job list of the default plan (black box: `reproduce-paper --list-jobs`): every method
//! each preset defines, for every seed, once (moved from xtask's `jobs` unit test; the shard
//! rule is `eamadm_runs::shard`'s, tested there).

use crate::succeeds;
use std::collections::HashSet;
use std::process::{Command, Stdio};

#[test]
fn the_default_plan_lists_each_preset_method_and_seed_once() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let output = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["reproduce-paper", "--list-jobs", "--seeds", "3"])
        .args(["--readings", "none"])
        .arg("--out")
        .arg(dir.path().join("out"))
        .stdin(Stdio::null())
        .output()
        .expect("xtask starts");
    let lines: Vec<serde_json::Value> = succeeds(&output)
        .lines()
        .map(|line| serde_json::from_str(line).expect("a JSON line"))
        .collect();
    // Each task runs the methods its preset defines (the robots have no maze controls).
    let expected: usize = eamadm::paper::PaperTask::ALL
        .iter()
        .map(|task| task.config().methods.len() * 3)
        .sum();
    assert_eq!(lines.len(), expected);
    let keys: HashSet<&str> = lines
        .iter()
        .map(|line| line["key"].as_str().expect("a key"))
        .collect();
    assert_eq!(keys.len(), lines.len(), "every run once");
}
