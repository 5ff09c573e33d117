//! `cargo xtask gc` (black box: the built binary) removes runs of another results format,
//! entries set aside long ago and artefacts of other plans, and keeps everything the plan it
//! is given needs (moved from xtask's `gc` unit test).

use std::path::Path;
use std::process::{Command, Stdio};

use eamadm::{Experiment, Shortening};
use eamadm_runs::{KeepTrajectories, PretrainedStore, RunKey, RunStore};

/// Runs `xtask <command>` on the Task I plan of `methods` (two seeds, `--quick`, no readings)
/// into `out`, with the artefact cache of `dir`.
fn xtask(command: &str, dir: &Path, task: &str, out: &str, methods: &[&str], extra: &[&str]) {
    let mut call = Command::new(env!("CARGO_BIN_EXE_xtask"));
    call.arg(command)
        .args([
            "--quick",
            "--seeds",
            "2",
            "--readings",
            "none",
            "--task",
            task,
        ])
        .arg("--out")
        .arg(dir.join(out))
        .arg("--pretrained-cache")
        .arg(dir.join("cache"))
        .args(extra)
        .stdin(Stdio::null())
        .stdout(Stdio::null());
    for method in methods {
        call.args(["--method", method]);
    }
    let output = call.output().expect("xtask starts");
    assert!(
        output.status.success(),
        "{command}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn gc_removes_stale_runs_old_set_aside_entries_and_other_plans_artefacts() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let dir = dir.path();
    // Two plans pre-train in the cache (the second on Task II, into another folder); the
    // folder keeps both of its plans' runs.
    xtask("reproduce-paper", dir, "task1", "out", &["ea-madm"], &[]);
    xtask("reproduce-paper", dir, "task1", "out", &["softmax"], &[]);
    xtask("reproduce-paper", dir, "task2", "other", &["ea-madm"], &[]);
    let cache = PretrainedStore::new(&dir.join("cache"));
    let before = cache.keys().expect("the cache lists its keys");
    let out = dir.join("out");
    // A run of an earlier results format, an entry set aside long ago and one just now, and
    // artefacts an earlier version kept in the folder.
    let mut config = eamadm::paper::task1().shortened(&Shortening::QUICK);
    config.seeds = 2;
    let experiment = Experiment::new(config).expect("the quick preset checks");
    let method = experiment.config().method("ea-madm").expect("ea-madm");
    let mut old = eamadm_runs::RunDescription::new(&experiment, method, 0);
    old.results_format -= 1;
    let old_key = RunKey::of(&old).expect("hashes");
    let record = experiment.run(method, 0).expect("runs");
    let store = RunStore::open(&out, &mut |w| panic!("{w}")).expect("opens");
    store
        .append(&old_key, &old, &record, KeepTrajectories::Figures)
        .expect("appends");
    let aside = out.join("runs/.set-aside");
    std::fs::create_dir_all(&aside).expect("creatable");
    std::fs::write(aside.join("old.at-0"), b"x").expect("writable");
    let file = std::fs::File::options()
        .write(true)
        .open(aside.join("old.at-0"))
        .expect("opens");
    let long_ago = std::time::SystemTime::now() - std::time::Duration::from_secs(40 * 86_400);
    file.set_modified(long_ago).expect("dated");
    std::fs::write(aside.join("new.at-0"), b"y").expect("writable");
    let legacy = PretrainedStore::legacy(&out);
    legacy
        .adopt(&cache, &mut |w| panic!("{w}"))
        .expect("adopts");
    xtask(
        "gc",
        dir,
        "task1",
        "out",
        &["ea-madm"],
        &["--older-than", "30"],
    );
    let store = RunStore::open(&out, &mut |w| panic!("{w}")).expect("opens");
    assert!(!store.line_exists(&old_key));
    assert_eq!(store.len(), 4, "both plans' runs stay");
    assert!(!aside.join("old.at-0").exists());
    assert!(aside.join("new.at-0").exists());
    assert!(!legacy.folder().exists());
    // Only the artefacts of the plan given stay (Task II's go).
    let after = cache.keys().expect("the cache lists its keys");
    assert!(
        after.len() < before.len(),
        "{} of {}",
        after.len(),
        before.len()
    );
    assert!(after.iter().all(|key| before.contains(key)));
    // The plan still resumes whole: nothing it needs was removed.
    xtask("reproduce-paper", dir, "task1", "out", &["ea-madm"], &[]);
}
