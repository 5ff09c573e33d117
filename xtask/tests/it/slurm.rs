//! The SLURM recipe for real: `scripts/slurm/submit` sends three shards and a dependent merge
//! (which first recomputes a fifth of the shards' runs, `merge --verify`) to
//! a running SLURM cluster (CI starts a single-node one with `.ci/slurm-cluster`), and the merged
//! output must equal an unsharded run's byte for byte. Without SLURM the test skips, except
//! under `CI=true`, where SLURM must be there. A skip leaves a note (the test's name and why) in
//! `target/tmp/skipped-tests/`, which `cargo xtask test` lists in its summary: libtest itself
//! can only print "ok" for a test that returned early.

use crate::tree;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// A small plan (`--quick`, two seeds) so the round trip takes seconds, with the smallest maze
/// family (two layouts: 48 more runs, and the family's outputs in `family/`).
const PLAN_ARGS: &str = "--quick --seeds 2 --suite family --family-size 2";

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask sits in the workspace root")
        .to_path_buf()
}

fn run(command: &mut Command) -> Output {
    let output = command.output().expect("the command starts");
    assert!(
        output.status.success(),
        "{command:?} failed: {}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    output
}

/// Why SLURM cannot be used here, if it cannot.
fn slurm_missing() -> Option<String> {
    match Command::new("sbatch").arg("--version").output() {
        Err(error) => return Some(format!("`sbatch` cannot be run ({error})")),
        Ok(output) if !output.status.success() => {
            return Some(
                "`sbatch --version` fails (no SLURM config? start a cluster with \
                 `.ci/slurm-cluster start DIR` and export SLURM_CONF)"
                    .to_owned(),
            );
        }
        Ok(_) => {}
    }
    match Command::new("sinfo")
        .args(["--noheader", "--format=%t"])
        .output()
    {
        Ok(output) if output.status.success() => {
            let states = String::from_utf8_lossy(&output.stdout);
            if states
                .lines()
                .any(|state| state.trim() == "idle" || state.trim() == "mix")
            {
                None
            } else {
                Some(format!(
                    "no idle SLURM node (sinfo says {:?})",
                    states.trim()
                ))
            }
        }
        Ok(output) => Some(format!(
            "no SLURM controller answers (start one with `.ci/slurm-cluster start DIR` and \
             export SLURM_CONF): {}",
            String::from_utf8_lossy(&output.stderr).trim()
        )),
        Err(error) => Some(format!("`sinfo` cannot be run ({error})")),
    }
}

/// Notes that the test `name` skipped and why, for `cargo xtask test`'s summary (see
/// `xtask/src/test_all.rs`, which reads the same folder), and says so on stdout.
fn record_skip(name: &str, reason: &str) {
    println!("skipped: {reason}");
    let folder = Path::new(env!("CARGO_TARGET_TMPDIR")).join("skipped-tests");
    std::fs::create_dir_all(&folder).expect("the skipped-tests folder can be made");
    std::fs::write(
        folder.join(format!("xtask {name}.txt")),
        format!("{reason}\n"),
    )
    .expect("the skip note can be written");
}

fn logs(folder: &Path) -> String {
    let mut text = String::new();
    if let Ok(entries) = std::fs::read_dir(folder) {
        for entry in entries.flatten() {
            let content = std::fs::read_to_string(entry.path()).unwrap_or_default();
            text.push_str(&format!("== {}\n{content}\n", entry.path().display()));
        }
    }
    text
}

#[test]
fn three_shards_and_a_merge_on_slurm_equal_an_unsharded_run() {
    if let Some(reason) = slurm_missing() {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI must run the SLURM test, but {reason}; `.ci/run` installs slurm-wlm and munge and \
             starts a cluster"
        );
        record_skip(
            "it::slurm::three_shards_and_a_merge_on_slurm_equal_an_unsharded_run",
            &reason,
        );
        return;
    }
    let xtask = env!("CARGO_BIN_EXE_xtask");
    let dir = tempfile::tempdir().expect("a temporary folder");
    let whole = dir.path().join("whole");
    run(Command::new(xtask)
        .arg("reproduce-paper")
        .args(PLAN_ARGS.split(' '))
        .arg("--out")
        .arg(&whole));

    let out = dir.path().join("slurm");
    let submitted = run(Command::new(workspace_root().join("scripts/slurm/submit"))
        .env("SHARDS", "3")
        .env("OUT", &out)
        .env("PLAN_ARGS", PLAN_ARGS)
        .env("VERIFY", "0.2")
        .env("XTASK", xtask));
    let stdout = String::from_utf8_lossy(&submitted.stdout);
    let merge_job = stdout
        .lines()
        .last()
        .expect("submit prints the merge job's id")
        .trim()
        .to_owned();
    assert!(
        merge_job.chars().all(|c| c.is_ascii_digit()),
        "not a job id: {stdout}"
    );

    let started = Instant::now();
    loop {
        let queue = run(Command::new("squeue").args(["--noheader", "--jobs", &merge_job]));
        if String::from_utf8_lossy(&queue.stdout).trim().is_empty() {
            break;
        }
        assert!(
            started.elapsed() < Duration::from_secs(180),
            "the merge job {merge_job} did not finish within 180 s; logs:\n{}",
            logs(&out.join("logs"))
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    let merged = out.join("merged");
    assert!(
        merged.join("REPORT.md").is_file(),
        "the merge wrote no report; logs:\n{}",
        logs(&out.join("logs"))
    );
    // The merge recomputed a sample of the shards' runs and artefacts first (`--verify`).
    let merge_log = std::fs::read_to_string(out.join("logs/merge.out")).unwrap_or_default();
    assert!(
        merge_log.contains("verify: recomputed") && merge_log.contains("; 0 differ"),
        "{merge_log}"
    );
    for k in 1..=3 {
        assert!(
            out.join(format!("shard-{k}/runs")).is_dir(),
            "shard {k} ran"
        );
        assert!(!out.join(format!("shard-{k}/REPORT.md")).exists());
    }
    let (expected, actual) = (tree(&whole), tree(&merged));
    assert_eq!(
        expected.keys().collect::<Vec<_>>(),
        actual.keys().collect::<Vec<_>>(),
        "the same files"
    );
    for (name, bytes) in &expected {
        assert!(actual[name] == *bytes, "{name} differs");
    }
}
