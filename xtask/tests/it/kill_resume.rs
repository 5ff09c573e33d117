//! A `reproduce-paper` killed (SIGKILL) while its runs are being stored, then started again with
//! the same arguments, ends with outputs byte-identical to an uninterrupted run's.

use crate::tree;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const PLAN: [&str; 2] = ["--quick", "--keep-trajectories=all"];

fn reproduce(out: &Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .arg("reproduce-paper")
        .args(PLAN)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .status()
        .expect("xtask starts");
    assert!(status.success(), "{status}");
}

/// Bytes stored so far in the run store of `out`.
fn stored_bytes(out: &Path) -> u64 {
    std::fs::read_dir(out.join("runs")).map_or(0, |entries| {
        entries
            .flatten()
            .filter_map(|entry| entry.metadata().ok())
            .map(|meta| meta.len())
            .sum()
    })
}

#[test]
fn a_run_killed_while_storing_resumes_to_the_same_bytes() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let whole = dir.path().join("whole");
    reproduce(&whole);

    let killed = dir.path().join("killed");
    let mut child = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .arg("reproduce-paper")
        .args(PLAN)
        .arg("--out")
        .arg(&killed)
        .stdout(Stdio::null())
        .spawn()
        .expect("xtask starts");
    // Kill as soon as some runs are stored (or give up waiting after 60 s).
    let started = Instant::now();
    let mut killed_mid_run = false;
    while started.elapsed() < Duration::from_secs(60) {
        if child.try_wait().expect("the child can be polled").is_some() {
            break;
        }
        if stored_bytes(&killed) > 0 {
            child.kill().expect("the child can be killed");
            killed_mid_run = true;
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let _ = child.wait();
    if killed_mid_run {
        assert!(
            !killed.join("REPORT.md").exists(),
            "killed before the report was written"
        );
    } else {
        println!("the run finished before it could be killed; resuming a finished run instead");
    }
    reproduce(&killed);
    let (expected, actual) = (tree(&whole), tree(&killed));
    assert_eq!(
        expected.keys().collect::<Vec<_>>(),
        actual.keys().collect::<Vec<_>>(),
        "the same files"
    );
    for (name, bytes) in &expected {
        assert!(actual[name] == *bytes, "{name} differs");
    }
}
