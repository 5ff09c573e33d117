//! Many `run-job` processes (what a SLURM array does), some killed at random moments, and a
//! `reproduce-paper` of a narrower plan, all on one output folder at once: afterwards the store
//! holds every run whose process exited 0, and `merge` accepts them. (On 4dc0c45 the store held
//! 29 of 54 runs after such a storm: readers cut other writers' entries as torn tails.)

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// A tiny plan: 2 methods × 5 seeds of Task I (and its readings' runs), shortened by --quick.
const PLAN: [&str; 9] = [
    "--quick",
    "--task",
    "task1",
    "--method",
    "epsilon-greedy",
    "--method",
    "softmax",
    "--seeds",
    "5",
];

fn xtask() -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_xtask"));
    command.stdout(Stdio::piped()).stderr(Stdio::piped());
    command
}

/// The keys of the plan's jobs in `out`.
fn keys(out: &Path) -> Vec<String> {
    let listed = xtask()
        .arg("reproduce-paper")
        .args(PLAN)
        .arg("--out")
        .arg(out)
        .arg("--list-jobs")
        .output()
        .expect("xtask starts");
    assert!(listed.status.success());
    String::from_utf8(listed.stdout)
        .expect("UTF-8")
        .lines()
        .map(|line| {
            let value: serde_json::Value = serde_json::from_str(line).expect("a JSON line");
            value["key"].as_str().expect("a key").to_owned()
        })
        .collect()
}

fn run_job(out: &Path, key: &str) -> Child {
    xtask()
        .arg("run-job")
        .arg("--key")
        .arg(key)
        .args(PLAN)
        .arg("--out")
        .arg(out)
        .spawn()
        .expect("xtask starts")
}

/// Keys `merge` reports missing (none when it succeeds).
fn missing_in_merge(out: &Path, merged: &Path) -> Vec<String> {
    let merge = xtask()
        .arg("merge")
        .args(PLAN)
        .arg("--out")
        .arg(merged)
        .arg(out)
        .output()
        .expect("xtask starts");
    if merge.status.success() {
        return Vec::new();
    }
    let message = String::from_utf8_lossy(&merge.stderr).into_owned();
    let missing: Vec<String> = message
        .lines()
        .filter_map(|line| line.split("(key ").nth(1))
        .map(|rest| rest.trim_end_matches(')').to_owned())
        .collect();
    assert!(!missing.is_empty(), "merge failed otherwise: {message}");
    missing
}

#[test]
fn fifty_run_jobs_with_random_kills_and_a_reproduce_paper_lose_no_finished_run() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("out");
    let keys = keys(&out);
    // 2 methods × 5 seeds, and the runs of the readings that change them on Task I (ε-greedy
    // 0.95: ε-greedy; γ 0.99: both; the temperature floor: softmax), 4 per seed.
    assert_eq!(keys.len(), 10 + 4 * 5);
    // A fixed pseudo-random sequence (xorshift): which processes are killed, and when.
    let mut state = 0x2545_F491_4F6C_DD1D_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let narrower = xtask()
        .arg("reproduce-paper")
        .args([
            "--quick", "--task", "task1", "--method", "softmax", "--seeds", "3",
        ])
        .arg("--out")
        .arg(&out)
        .arg("--wait")
        .spawn()
        .expect("xtask starts");
    let mut children: Vec<(String, Child)> = Vec::new();
    let mut killed = 0;
    for i in 0..50 {
        let key = keys[i % keys.len()].clone();
        let mut child = run_job(&out, &key);
        // Two in five are killed a few milliseconds in: while starting, running or storing.
        if next() % 5 < 2 {
            std::thread::sleep(Duration::from_millis(next() % 25));
            if child.try_wait().expect("pollable").is_none() {
                child.kill().expect("killable");
                killed += 1;
            }
        }
        children.push((key, child));
    }
    let mut succeeded = BTreeSet::new();
    for (key, child) in children {
        let output = child.wait_with_output().expect("the child ends");
        if output.status.success() {
            succeeded.insert(key);
        }
    }
    let narrower = narrower.wait_with_output().expect("the child ends");
    assert!(
        narrower.status.success(),
        "{}",
        String::from_utf8_lossy(&narrower.stderr)
    );
    println!(
        "{killed} killed, {} keys of exited-0 processes",
        succeeded.len()
    );
    assert!(!succeeded.is_empty());
    let missing = missing_in_merge(&out, &dir.path().join("merged"));
    for key in &missing {
        assert!(
            !succeeded.contains(key),
            "run {key} of a process that exited 0 is missing"
        );
    }
    // The rest, one job each, then the merge accepts the whole plan.
    for key in &missing {
        let status = run_job(&out, key).wait().expect("the child ends");
        assert!(status.success());
    }
    assert!(missing_in_merge(&out, &dir.path().join("merged")).is_empty());
    assert!(dir.path().join("merged/REPORT.md").is_file());
}
