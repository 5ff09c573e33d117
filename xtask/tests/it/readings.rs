//! The readings of the paper in a plan (black box: the built binary): each reading's
//! experiment runs only the methods it changes, `--method` narrows them as it narrows the
//! base's, and `sensitivity.csv` and the report's section on the readings are the same bytes
//! at one and two threads (moved from xtask's `sensitivity_report` unit tests).

use crate::succeeds;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};

/// `(experiment, method)` of every job of `reproduce-paper --list-jobs` with `args`.
fn jobs(args: &[&str], out: &Path) -> Vec<(String, String)> {
    let output = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["reproduce-paper", "--list-jobs", "--quick", "--seeds", "2"])
        .args(args)
        .arg("--out")
        .arg(out)
        .stdin(Stdio::null())
        .output()
        .expect("xtask starts");
    succeeds(&output)
        .lines()
        .map(|line| {
            let job: serde_json::Value = serde_json::from_str(line).expect("a JSON line");
            let field = |name: &str| job[name].as_str().expect("a string field").to_owned();
            (field("experiment"), field("method"))
        })
        .collect()
}

#[test]
fn each_reading_plans_only_the_runs_of_the_methods_it_changes() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("out");
    let listed = jobs(&["--task", "task1", "--task", "task2"], &out);
    let mut per_experiment: BTreeMap<&str, usize> = BTreeMap::new();
    for (experiment, method) in &listed {
        *per_experiment.entry(experiment.as_str()).or_default() += 1;
        let Some((_, reading)) = experiment.split_once("-reading-") else {
            assert!(
                experiment == "task1" || experiment == "task2",
                "{experiment}"
            );
            continue;
        };
        let reading = eamadm::paper::readings()
            .iter()
            .find(|r| r.name() == reading)
            .unwrap_or_else(|| panic!("{reading} is a reading"));
        assert!(
            reading.methods().contains(&method.as_str()),
            "{experiment} reruns {method}"
        );
    }
    let runs = |name: &str| per_experiment.get(name).copied().unwrap_or(0);
    assert_eq!(runs("task1-reading-gamma-0.99"), 4 * 2);
    assert_eq!(runs("task2-reading-task2-reward-as-task1"), 4 * 2);
    assert_eq!(runs("task1-reading-epsilon-greedy-0.95"), 2);
    assert_eq!(runs("task1-reading-task2-reward-as-task1"), 0);
    // --method narrows the readings' runs as it narrows the base's.
    let narrow = jobs(
        &["--task", "task1", "--task", "task2", "--method", "softmax"],
        &out,
    );
    assert!(!narrow.is_empty());
    assert!(narrow.iter().all(|(_, method)| method == "softmax"));
    assert!(narrow.iter().any(|(e, _)| e.contains("-reading-")));
}

#[test]
fn the_quick_plan_writes_the_same_sensitivity_at_one_and_two_threads() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let run = |threads: &str| {
        let folder = dir.path().join(format!("threads-{threads}"));
        let output = Command::new(env!("CARGO_BIN_EXE_xtask"))
            .args([
                "reproduce-paper",
                "--quick",
                "--seeds",
                "2",
                "--task",
                "task1",
            ])
            .args(["--method", "ea-madm", "--method", "epsilon-greedy"])
            .args(["--method", "softmax"])
            .arg("--out")
            .arg(folder.join("out"))
            .arg("--pretrained-cache")
            .arg(folder.join("cache"))
            .env("RAYON_NUM_THREADS", threads)
            .stdin(Stdio::null())
            .output()
            .expect("xtask starts");
        let plan = succeeds(&output);
        assert!(plan.contains("readings: "), "{plan}");
        assert!(plan.contains("gamma-0.99"), "{plan}");
        let read =
            |file: &str| std::fs::read_to_string(folder.join("out").join(file)).expect("written");
        (read(eamadm::output_names::SENSITIVITY), read("REPORT.md"))
    };
    let (csv, report) = run("1");
    // Task I: C1–C3 under each of the six readings that change Task I.
    assert_eq!(csv.lines().count(), 1 + 3 * 6, "{csv}");
    assert!(csv.starts_with("claim,task,reading,method,base_verdict,verdict,change"));
    assert!(report.contains("### Sensitivity to the readings of the paper"));
    assert!(report.contains("`pretrain-double`"));
    assert_eq!((csv, report), run("2"));
}
