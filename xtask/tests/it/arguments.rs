//! The command line and the plan's checks, black box: what parses, what is refused with exit
//! code 2 before anything is written, and the plan `--list-jobs` shows (moved from xtask's
//! `cli`, `plan` and `experiments` unit tests).

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use crate::{Folder, fails, succeeds};

/// The workspace root (the binary's `fixtures/` is under it).
fn workspace_root() -> PathBuf {
    let xtask = Path::new(env!("CARGO_MANIFEST_DIR"));
    xtask
        .parent()
        .expect("xtask/ is under the root")
        .to_path_buf()
}

/// `xtask args` started in `dir`.
fn xtask_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("xtask starts")
}

/// The `--list-jobs` lines of `reproduce-paper args`, started in `dir`, as JSON.
fn jobs_in(dir: &Path, args: &[&str]) -> Vec<serde_json::Value> {
    let mut all = vec!["reproduce-paper", "--list-jobs"];
    all.extend(args);
    succeeds(&xtask_in(dir, &all))
        .lines()
        .map(|line| serde_json::from_str(line).expect("a JSON line"))
        .collect()
}

/// The plan options a listed job carries (its `run` without `run-job --key KEY`).
fn plan_of(job: &serde_json::Value) -> Vec<String> {
    let run: Vec<String> = serde_json::from_value(job["run"].clone()).expect("a run");
    run[3..].to_vec()
}

/// A cheap plan: Task I's ε-greedy on one seed, no readings.
const CHEAP: [&str; 10] = [
    "--quick",
    "--seeds",
    "1",
    "--task",
    "task1",
    "--method",
    "epsilon-greedy",
    "--readings",
    "none",
    "--list-jobs",
];

#[test]
fn every_command_and_the_cli_are_well_formed() {
    // clap checks the whole command tree (debug assertions) when it builds the help.
    let folder = Folder::new();
    folder.succeeds(&["--help"]);
    for command in [
        "reproduce-paper",
        "run-job",
        "merge",
        "verify",
        "gc",
        "regen-fixtures",
        "test",
        "wheel",
    ] {
        folder.succeeds(&[command, "--help"]);
    }
    // The task values are the paper's task names.
    let help = folder.succeeds(&["reproduce-paper", "--help"]);
    for task in eamadm::paper::PaperTask::ALL {
        assert!(help.contains(task.name()), "{}: {help}", task.name());
    }
}

#[test]
fn every_plan_option_parses_and_is_listed_with_each_job() {
    let folder = Folder::new();
    let (out, cache) = (folder.path("o"), folder.path("c"));
    let jobs = jobs_in(
        &folder.path(""),
        &[
            "--seeds",
            "4",
            "--task",
            "robot",
            "--task",
            "task-i",
            "--method",
            "softmax",
            "--method",
            "ea-madm",
            "--out",
            "o",
            "--quick",
            "--wait",
            "--keep-trajectories",
            "all",
            "--readings",
            "none",
            "--pretrained-cache",
            "c",
        ],
    );
    assert_eq!(jobs.len(), 2 * 2 * 4);
    let expected = [
        "--seeds",
        "4",
        "--task",
        "robot",
        "--task",
        "task1",
        "--method",
        "softmax",
        "--method",
        "ea-madm",
        "--out",
        &out.display().to_string(),
        "--quick",
        "--keep-trajectories",
        "all",
        "--readings",
        "none",
        "--pretrained-cache",
        &cache.display().to_string(),
    ]
    .map(str::to_owned);
    for job in &jobs {
        assert_eq!(plan_of(job), expected);
    }
    // No option but --out: the defaults (20 seeds, or 3 with --quick; every task) add none.
    let defaults = jobs_in(&folder.path(""), &["--out", "o"]);
    for job in &defaults {
        assert_eq!(
            plan_of(job)[..],
            ["--out".to_owned(), out.display().to_string()]
        );
    }
    let seeds = |jobs: &[serde_json::Value]| {
        let mut seeds: Vec<u64> = jobs.iter().filter_map(|j| j["seed"].as_u64()).collect();
        seeds.sort_unstable();
        seeds.dedup();
        seeds.len()
    };
    assert_eq!(seeds(&defaults), 20);
    for task in eamadm::paper::PaperTask::ALL {
        assert!(
            defaults.iter().any(|job| job["task"] == task.name()),
            "{}",
            task.name()
        );
    }
    let quick = jobs_in(
        &folder.path(""),
        &["--out", "o", "--quick", "--task", "task1"],
    );
    assert_eq!(seeds(&quick), 3);
}

#[test]
fn selections_are_deduplicated_and_tasks_ordered() {
    let folder = Folder::new();
    let jobs = jobs_in(
        &folder.path(""),
        &[
            "--seeds",
            "2",
            "--quick",
            "--task",
            "robot",
            "--task",
            "task1",
            "--task",
            "robot",
            "--method",
            "softmax",
            "--method",
            "ea-madm",
            "--method",
            "softmax",
            "--readings",
            "none",
            "--out",
            "o",
        ],
    );
    let order: Vec<(&str, &str)> = jobs
        .iter()
        .map(|job| {
            (
                job["task"].as_str().unwrap(),
                job["method"].as_str().unwrap(),
            )
        })
        .collect();
    let mut expected = Vec::new();
    for task in ["task1", "robot"] {
        for method in ["softmax", "ea-madm"] {
            expected.extend([(task, method); 2]);
        }
    }
    assert_eq!(order, expected);
}

#[test]
fn bad_values_are_refused_by_the_parser() {
    let folder = Folder::new();
    for args in [
        &["reproduce-paper", "--seeds", "0"][..],
        &["reproduce-paper", "--seeds", "ten"],
        &["reproduce-paper", "--task", "task3"],
        &["reproduce-paper", "--frobnicate"],
        &["regen-fixtures", "--quick"],
        &["reproduce-paper", "--shard", "1/3", "--runs-only"],
        &["reproduce-paper", "--list-jobs", "--runs-only"],
        &["reproduce-paper", "--keep-trajectories", "some"],
        &["reproduce-paper", "--readings", "some"],
        &["merge", "--out", "x"],
        &["run-job", "--quick"],
    ] {
        let output = folder.xtask(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
    }
    assert!(!folder.path("x").exists());
}

#[test]
fn an_unknown_method_lists_the_known_ones() {
    let folder = Folder::new();
    let message = fails(
        &folder.xtask(&[
            "reproduce-paper",
            "--method",
            "ea-madm",
            "--method",
            "sarsa",
        ]),
        2,
    );
    assert!(
        message.contains("--method \"sarsa\": unknown method; the methods are: ea-madm, "),
        "{message}"
    );
}

#[test]
fn an_output_folder_inside_fixtures_is_refused_before_writing() {
    let root = workspace_root();
    for out in [
        "fixtures",
        "fixtures/results",
        "./target/../fixtures/new/deeper",
    ] {
        let mut args = vec!["reproduce-paper", "--out", out];
        args.extend(CHEAP);
        let message = fails(&xtask_in(&root, &args), 2);
        assert!(message.contains("must not be inside"), "{out}: {message}");
    }
    assert!(!root.join("fixtures/results").exists());
    assert!(!root.join("fixtures/new").exists());
    // A sibling whose name merely starts with "fixtures" is fine (listing writes nothing).
    let jobs = jobs_in(
        &root,
        &["--out", "fixtures-results", "--quick", "--seeds", "1"],
    );
    let fine = root.join("fixtures-results").display().to_string();
    assert!(plan_of(&jobs[0]).contains(&fine));
    // From a sub-folder, a relative --out is taken from there, and `../fixtures` is still
    // the fixtures.
    let crates = root.join("crates");
    let jobs = jobs_in(&crates, &["--out", "../results", "--quick", "--seeds", "1"]);
    assert!(plan_of(&jobs[0]).contains(&root.join("results").display().to_string()));
    let mut args = vec!["reproduce-paper", "--out", "../fixtures"];
    args.extend(CHEAP);
    fails(&xtask_in(&crates, &args), 2);
}

#[cfg(unix)]
#[test]
fn an_output_folder_through_a_link_into_fixtures_or_at_a_file_is_refused() {
    let folder = Folder::new();
    std::os::unix::fs::symlink(workspace_root().join("fixtures"), folder.path("sneaky"))
        .expect("a link");
    let mut args = vec!["reproduce-paper", "--out", "sneaky/out"];
    args.extend(CHEAP);
    let message = fails(&folder.xtask(&args), 2);
    assert!(message.contains("must not be inside"), "{message}");
    std::fs::write(folder.path("REPORT.md"), "x").expect("a writable folder");
    let mut args = vec!["reproduce-paper", "--out", "REPORT.md"];
    args.extend(CHEAP);
    let message = fails(&folder.xtask(&args), 2);
    assert!(message.contains("exists and is not a folder"), "{message}");
}

#[test]
fn presets_are_planned_with_the_given_seeds_then_each_reading_reading_major() {
    let folder = Folder::new();
    let jobs = jobs_in(&folder.path(""), &["--seeds", "2", "--quick", "--out", "o"]);
    let mut names: Vec<&str> = Vec::new();
    for job in &jobs {
        let name = job["experiment"].as_str().unwrap();
        if names.last() != Some(&name) {
            names.push(name);
        }
    }
    assert_eq!(
        names,
        [
            "task1",
            "task2",
            "robot",
            "robot-paper-state",
            "aggregation-control",
            "task2-reading-task2-reward-as-task1",
            "task1-reading-epsilon-greedy-0.95",
            "task2-reading-epsilon-greedy-0.95",
            "task1-reading-gamma-0.99",
            "task2-reading-gamma-0.99",
            "task1-reading-pretrain-half",
            "task2-reading-pretrain-half",
            "task1-reading-pretrain-double",
            "task2-reading-pretrain-double",
            "task1-reading-pretrain-fixed",
            "task2-reading-pretrain-fixed",
            "task1-reading-temperature-floor-0.1",
            "task2-reading-temperature-floor-0.1",
        ]
    );
    assert!(
        jobs.iter()
            .all(|job| job["seed"].as_u64().unwrap() < 2 + 1_000_000),
        "seeds"
    );
    let mut per_run: std::collections::BTreeMap<(String, String), usize> = Default::default();
    for job in &jobs {
        let run = (job["experiment"].to_string(), job["method"].to_string());
        *per_run.entry(run).or_default() += 1;
    }
    assert!(per_run.values().all(|&seeds| seeds == 2), "{per_run:?}");
}

#[test]
fn a_bad_config_file_names_the_field_and_cannot_take_a_task() {
    let folder = Folder::new();
    let text = eamadm::PAPER_TASK1_TOML.replace("episodes = 200", "episodes = 0");
    std::fs::write(folder.path("bad.toml"), text).expect("a writable folder");
    let args = [
        "reproduce-paper",
        "--config",
        "bad.toml",
        "--out",
        "o",
        "--list-jobs",
    ];
    let message = fails(&folder.xtask(&args), 2);
    assert!(message.contains("`episodes` = 0"), "{message}");
    std::fs::write(folder.path("good.toml"), eamadm::PAPER_TASK1_TOML).expect("writable");
    let args = [
        "reproduce-paper",
        "--config",
        "good.toml",
        "--task",
        "task1",
        "--list-jobs",
    ];
    let message = fails(&folder.xtask(&args), 2);
    assert!(
        message.contains("--task cannot be combined with --config"),
        "{message}"
    );
}
