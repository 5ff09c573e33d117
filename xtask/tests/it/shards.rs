//! Shards, `run-job`, `merge` and resuming give the bytes of one unsharded run; the run store
//! keeps every run a narrower or different plan does not need (black box; moved from xtask's
//! `reproduce` unit tests).

use std::collections::BTreeMap;
use std::path::Path;

use crate::{Folder, assert_same_tree, fails};
use eamadm_runs::{KeepTrajectories, RunKey, RunStore};

/// Runs per seed of the readings [`small`] plans on Task I (the readings change no robot
/// task): γ (EA-MADM and softmax), pre-training half, double and fixed (EA-MADM) and the
/// temperature floor (softmax).
const SMALL_READING_RUNS_PER_SEED: usize = 6;

/// The options of a small plan into `out`: two methods, two seeds, Task I and the robot,
/// shortened by a config-free --quick, in the order `--list-jobs` writes them.
fn small_plan(out: &str) -> Vec<String> {
    let plan = [
        "--seeds", "2", "--task", "task1", "--task", "robot", "--method", "ea-madm", "--method",
        "softmax", "--out", out, "--quick",
    ];
    let mut plan: Vec<String> = plan.map(str::to_owned).to_vec();
    plan.extend(["--pretrained-cache".to_owned(), "cache".to_owned()]);
    plan
}

/// `reproduce-paper` with [`small_plan`].
pub(crate) fn small(out: &str) -> Vec<String> {
    let mut args = vec!["reproduce-paper".to_owned()];
    args.extend(small_plan(out));
    args
}

/// `args` with `extra` appended.
fn with(mut args: Vec<String>, extra: &[&str]) -> Vec<String> {
    args.extend(extra.iter().map(|s| (*s).to_owned()));
    args
}

/// `merge` of `stores` under [`small_plan`] into `out`, then `extra` options.
fn merge(out: &str, stores: &[&str], extra: &[&str]) -> Vec<String> {
    let mut args = vec!["merge".to_owned()];
    args.extend(small_plan(out));
    args.extend(stores.iter().map(|s| (*s).to_owned()));
    with(args, extra)
}

/// The lines of a bundle (any framing), without their newlines.
fn bundle_lines(bytes: &[u8]) -> Vec<String> {
    let text = eamadm_runs::frames::decompress(bytes).expect("a readable bundle");
    String::from_utf8(text)
        .expect("UTF-8 lines")
        .lines()
        .map(str::to_owned)
        .collect()
}

/// The keys of the verified runs stored in `out`, and with which trajectories.
fn stored_runs(out: &Path) -> BTreeMap<String, bool> {
    let store = RunStore::open(out, &mut |w| panic!("{w}")).expect("a readable store");
    let mut runs = BTreeMap::new();
    for bundle in std::fs::read_dir(out.join("runs")).expect("a store folder") {
        let bundle = bundle.expect("a folder entry").path();
        if !bundle.to_string_lossy().ends_with(".jsonl.zst") {
            continue;
        }
        let bytes = std::fs::read(&bundle).expect("a readable bundle");
        for line in bundle_lines(&bytes) {
            let header = line.split('\t').next().unwrap_or_default();
            let header: serde_json::Value = serde_json::from_str(header).expect("a JSON header");
            let key = header["key"].as_str().expect("a key").to_owned();
            let all = header["trajectories"] == "all";
            assert!(
                store.has(
                    &RunKey::from_verified_hex(key.clone()),
                    KeepTrajectories::Figures
                ),
                "{key}"
            );
            assert!(runs.insert(key, all).is_none(), "each run once");
        }
    }
    runs
}

/// The `--list-jobs` lines of `args` (a `reproduce-paper` command) as JSON.
fn listed_jobs(folder: &Folder, args: Vec<String>) -> Vec<serde_json::Value> {
    folder
        .succeeds(&with(args, &["--list-jobs"]))
        .lines()
        .map(|line| serde_json::from_str(line).expect("a JSON line"))
        .collect()
}

#[test]
fn three_shards_merged_equal_the_unsharded_run_byte_for_byte() {
    let folder = Folder::new();
    folder.succeeds(&small("whole"));
    // Every run, the readings' reruns too, ran its experiment shortened by --quick (the
    // facade's shortening: 30 episodes); the runs per seed are counted by the tests below.
    let mut readings = 0;
    for bundle in std::fs::read_dir(folder.path("whole/runs")).unwrap() {
        let bundle = bundle.unwrap().path();
        if !bundle.to_string_lossy().ends_with(".jsonl.zst") {
            continue;
        }
        readings += usize::from(bundle.to_string_lossy().contains("-reading-"));
        for line in bundle_lines(&std::fs::read(&bundle).unwrap()) {
            let description: serde_json::Value =
                serde_json::from_str(line.split('\t').nth(1).unwrap()).unwrap();
            let config = &description["config"];
            assert_eq!(config["episodes"], 30, "{}", bundle.display());
        }
    }
    // Task I's readings of ea-madm and softmax: γ, pre-training half, double and fixed, and
    // the temperature floor.
    assert_eq!(readings, 5);
    for k in 1..=3 {
        let out = format!("shard{k}");
        folder.succeeds(&with(small(&out), &["--shard", &format!("{k}/3")]));
        assert!(!folder.path(&out).join("REPORT.md").exists(), "no report");
    }
    // Merging two of three shards names what is missing and writes nothing.
    let message = fails(
        &folder.xtask(&merge("merged", &["shard1", "shard2"], &[])),
        1,
    );
    assert!(message.contains("are in none of the stores"), "{message}");
    assert!(message.contains("seed"), "{message}");
    assert!(!folder.path("merged").exists());
    // The merge recomputes a third of the shards' runs and artefacts first.
    let stores = ["shard1", "shard2", "shard3"];
    folder.succeeds(&merge("merged", &stores, &["--verify", "0.3"]));
    assert_same_tree(&folder.path("whole"), &folder.path("merged"));
}

#[test]
fn each_listed_job_parses_back_to_the_plan_and_its_key_and_rebuilds_the_same_store() {
    let folder = Folder::new();
    folder.succeeds(&small("whole"));
    let jobs = listed_jobs(&folder, small("jobs"));
    assert_eq!(jobs.len(), 2 * 2 * 2 + 2 * SMALL_READING_RUNS_PER_SEED);
    // The plan again, its paths absolute, so a job runs from any folder.
    let mut plan = small_plan(&folder.path("jobs").display().to_string());
    *plan.last_mut().unwrap() = folder.path("cache").display().to_string();
    let mut keys = std::collections::BTreeSet::new();
    for job in &jobs {
        let key = job["key"].as_str().unwrap();
        assert!(["ea-madm", "softmax"].contains(&job["method"].as_str().unwrap()));
        assert!(job["seed"].is_u64(), "{job}");
        assert!(["task1", "robot"].contains(&job["task"].as_str().unwrap()));
        keys.insert(key.to_owned());
        let run: Vec<String> = serde_json::from_value(job["run"].clone()).unwrap();
        assert_eq!(run[..3], ["run-job", "--key", key]);
        assert_eq!(run[3..], plan[..]);
    }
    assert_eq!(keys.len(), jobs.len(), "keys are unique");
    // In reverse, from another folder, so the appended order differs from job order.
    let elsewhere = Folder::new();
    for job in jobs.iter().rev() {
        let run: Vec<String> = serde_json::from_value(job["run"].clone()).unwrap();
        elsewhere.succeeds(&run);
    }
    let mut unknown = vec!["run-job".to_owned(), "--key".to_owned(), "0".repeat(64)];
    unknown.extend(small_plan("jobs"));
    let message = fails(&folder.xtask(&unknown), 2);
    assert!(message.contains("--list-jobs"), "{message}");
    // Resuming everything (nothing left to run) compacts the store into job order.
    folder.succeeds(&with(small("jobs"), &["--runs-only"]));
    assert_same_tree(&folder.path("whole/runs"), &folder.path("jobs/runs"));
    folder.succeeds(&merge("merged", &["jobs"], &[]));
    assert_same_tree(&folder.path("whole"), &folder.path("merged"));
}

#[test]
fn an_interrupted_or_damaged_store_resumes_to_the_same_bytes() {
    let folder = Folder::new();
    folder.succeeds(&small("whole"));
    let copy = folder.path("resumed");
    std::fs::create_dir_all(copy.join("runs")).unwrap();
    let bundle = std::fs::read(folder.path("whole/runs/task1.jsonl.zst")).unwrap();
    let lines = bundle_lines(&bundle);
    assert_eq!(lines.len(), 4);
    // As an earlier version (one gzip member a run) killed mid-append left it: one run
    // whole, one edited, one torn, one never written.
    let line = |i: usize| lines[i].clone();
    let member = |text: &str| eamadm_runs::gzip::compress(format!("{text}\n").as_bytes()).unwrap();
    let edited = line(1).replacen("\"steps\":", "\"steps\":1", 1);
    let torn = member(&line(2));
    std::fs::write(
        copy.join("runs/task1.jsonl.gz"),
        [
            member(&line(0)).as_slice(),
            &member(&edited),
            &torn[..torn.len() / 2],
        ]
        .concat(),
    )
    .unwrap();
    // What an earlier version left: results.json and a one-file-per-run store.
    std::fs::write(copy.join("results.json"), "[]").unwrap();
    let legacy = copy.join("runs").join(format!("{}.json", "ab".repeat(32)));
    std::fs::write(&legacy, "{}").unwrap();
    // And an uncompressed bundle (format 2 before the store was compressed).
    let uncompressed = copy.join("runs/task1.jsonl");
    std::fs::write(&uncompressed, line(0)).unwrap();
    std::fs::write(copy.join("runs/notes.json"), "mine").unwrap();
    folder.succeeds(&small("resumed"));
    assert!(!legacy.exists());
    assert!(!uncompressed.exists());
    // Only files of ours are removed.
    assert_eq!(
        std::fs::read(copy.join("runs/notes.json")).unwrap(),
        b"mine"
    );
    std::fs::remove_file(copy.join("runs/notes.json")).unwrap();
    // The edited and the torn entry are set aside, not deleted.
    let aside = copy.join("runs/.set-aside");
    assert_eq!(std::fs::read_dir(&aside).unwrap().count(), 2);
    std::fs::remove_dir_all(&aside).unwrap();
    // The earlier version's bundle was read, its good run kept, and replaced.
    assert!(!copy.join("runs/task1.jsonl.gz").exists());
    assert_same_tree(&folder.path("whole"), &copy);
}

#[test]
fn shards_into_one_folder_in_every_order_merge_to_the_unsharded_run() {
    let folder = Folder::new();
    folder.succeeds(&small("whole"));
    let whole = stored_runs(&folder.path("whole"));
    assert_eq!(whole.len(), 8 + 2 * SMALL_READING_RUNS_PER_SEED);
    for (n, order) in [[3, 1, 2], [2, 3, 1], [1, 2, 3]].iter().enumerate() {
        let out = format!("one{n}");
        for &k in order {
            folder.succeeds(&with(small(&out), &["--shard", &format!("{k}/3")]));
        }
        // Each shard added its runs; none removed another's (4dc0c45: 5 of 8 missing).
        assert_eq!(stored_runs(&folder.path(&out)), whole, "order {order:?}");
        let merged = format!("merged{n}");
        folder.succeeds(&merge(&merged, &[&out], &[]));
        assert_same_tree(&folder.path("whole"), &folder.path(&merged));
    }
}

#[test]
fn readings_none_runs_only_the_presets_and_its_jobs_say_so() {
    let folder = Folder::new();
    let none = with(small("out"), &["--readings", "none"]);
    folder.succeeds(&none);
    // 2 tasks × 2 methods × 2 seeds, and none of the readings' reruns that `small` plans by
    // default (`SMALL_READING_RUNS_PER_SEED` per seed).
    let runs = stored_runs(&folder.path("out"));
    assert_eq!(runs.len(), 8, "{runs:?}");
    let sensitivity =
        std::fs::read_to_string(folder.path("out").join(eamadm::output_names::SENSITIVITY))
            .unwrap();
    assert_eq!(
        sensitivity.lines().count(),
        1,
        "only the header: {sensitivity}"
    );
    // Every listed job carries the option, so `run-job` plans the same runs.
    let jobs = listed_jobs(&folder, none);
    assert_eq!(jobs.len(), 8);
    for job in &jobs {
        let run = job["run"].to_string();
        assert!(run.contains(r#""--readings","none""#), "{run}");
    }
}

#[test]
fn a_narrower_plan_or_a_method_a_task_lacks_keeps_every_stored_run() {
    let folder = Folder::new();
    folder.succeeds(&small("out"));
    let before = stored_runs(&folder.path("out"));
    // What a kill during a bundle rewrite leaves: a hidden temporary file, removed by the
    // next holder of the lock (4dc0c45 kept it for ever).
    let leftover = folder.path("out/runs/.task1.jsonl.zst.Ab12Cd.tmp");
    std::fs::write(&leftover, b"half a bundle").unwrap();
    let mut narrow = small("out");
    let at = narrow.iter().position(|arg| arg == "ea-madm").unwrap();
    narrow.drain(at - 1..=at);
    folder.succeeds(&narrow);
    assert_eq!(stored_runs(&folder.path("out")), before);
    assert!(!leftover.exists());
    // The robot has no tree-threshold control (those are the mazes'): its plan there is
    // empty (4dc0c45 emptied the robot's store).
    let lacking = [
        "reproduce-paper",
        "--seeds",
        "2",
        "--task",
        "robot",
        "--method",
        "ea-madm-tau0.5",
        "--out",
        "out",
        "--quick",
        "--pretrained-cache",
        "cache",
    ];
    let _ = folder.xtask(&lacking);
    assert_eq!(stored_runs(&folder.path("out")), before);
    // A wider plan runs only what is missing.
    let mut wider = small("out");
    wider[2] = "3".to_owned();
    folder.succeeds(&wider);
    let after = stored_runs(&folder.path("out"));
    assert_eq!(after.len(), 12 + 3 * SMALL_READING_RUNS_PER_SEED);
    assert!(before.keys().all(|key| after.contains_key(key)));
}

#[test]
fn keep_trajectories_switched_both_ways_keeps_the_richer_runs_once() {
    let folder = Folder::new();
    let all = with(small("out"), &["--keep-trajectories", "all"]);
    folder.succeeds(&small("out"));
    // Needing more: recomputed once (4dc0c45 failed every time, appending each time).
    for _ in 0..2 {
        folder.succeeds(&all);
        let runs = stored_runs(&folder.path("out"));
        assert_eq!(runs.len(), 8 + 2 * SMALL_READING_RUNS_PER_SEED);
        assert!(runs.values().all(|&all| all), "{runs:?}");
    }
    // Needing less: served by the richer runs, which stay (4dc0c45 stripped them).
    folder.succeeds(&small("out"));
    let runs = stored_runs(&folder.path("out"));
    assert_eq!(runs.len(), 8 + 2 * SMALL_READING_RUNS_PER_SEED);
    assert!(runs.values().all(|&all| all), "{runs:?}");
}
