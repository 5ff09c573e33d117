//! `reproduce-paper` with a config file, refusals before writing, and what a run leaves in its
//! output folder (black box; moved from xtask's `reproduce` unit tests).

use crate::{Folder, fails};

/// `--seeds 1 --method epsilon-greedy --quick --config FILE --out OUT`.
fn with_config<'a>(config: &'a str, out: &'a str) -> Vec<&'a str> {
    vec![
        "reproduce-paper",
        "--seeds",
        "1",
        "--method",
        "epsilon-greedy",
        "--quick",
        "--config",
        config,
        "--out",
        out,
    ]
}

/// Task I's preset named `name`, 3 episodes, written to `file`.
fn write_config(folder: &Folder, file: &str, name: &str) {
    let mut config = eamadm::paper::task1();
    config.name = name.to_owned();
    config.episodes = 3;
    let text = config.to_toml_string().expect("a preset writes as TOML");
    std::fs::write(folder.path(file), text).expect("a writable folder");
}

#[test]
fn an_invalid_config_names_the_field_and_writes_nothing() {
    let folder = Folder::new();
    let text = eamadm::PAPER_TASK2_TOML.replace("gamma = 0.95", "gamma = 1.5");
    std::fs::write(folder.path("bad.toml"), text).unwrap();
    let message = fails(&folder.xtask(&with_config("bad.toml", "out")), 2);
    assert!(message.contains("`learner.gamma` = 1.5"), "{message}");
    assert!(!folder.path("out").exists());
}

#[test]
fn a_valid_config_runs_and_writes_every_output() {
    let folder = Folder::new();
    write_config(&folder, "mine.toml", "mine");
    folder.succeeds(&with_config("mine.toml", "out"));
    for file in [
        "REPORT.md",
        "runs/mine.jsonl.zst",
        "mine/curves.csv.gz",
        "mine/trajectories.csv.gz",
        "mine/steps.svg",
        "mine/return.svg",
        "mine/trajectories.svg",
    ] {
        assert!(folder.path("out").join(file).is_file(), "{file}");
    }
    let report = std::fs::read_to_string(folder.path("out/REPORT.md")).unwrap();
    assert!(report.contains("## mine (`mine`)"), "{report}");
    // Every visible top-level entry but the experiment's folder is a name configs may not
    // take, so no experiment can overwrite it.
    for entry in std::fs::read_dir(folder.path("out")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || name == "mine" {
            continue;
        }
        assert!(
            eamadm::RESERVED_NAMES
                .iter()
                .any(|reserved| reserved.eq_ignore_ascii_case(&name)),
            "{name} is not reserved"
        );
    }
}

#[test]
fn a_run_of_other_arguments_leaves_no_stale_outputs() {
    let folder = Folder::new();
    write_config(&folder, "first.toml", "first");
    write_config(&folder, "second.toml", "second");
    folder.succeeds(&with_config("first.toml", "out"));
    assert!(folder.path("out/first/curves.csv.gz").is_file());
    folder.succeeds(&with_config("second.toml", "out"));
    let out = folder.path("out");
    assert!(
        !out.join("first").exists(),
        "the first run's outputs are gone"
    );
    assert!(out.join("second/curves.csv.gz").is_file());
    let manifest = std::fs::read_to_string(out.join(".outputs")).unwrap();
    assert!(
        manifest.lines().all(|line| !line.starts_with("first/")),
        "{manifest}"
    );
    assert!(manifest.contains("REPORT.md\n"), "{manifest}");
    assert!(!out.join(".staging").exists() && !out.join(".committed").exists());
    // The run store is not part of the set: both runs' records stay for resuming.
    let bundles = std::fs::read_dir(out.join("runs"))
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            name.to_string_lossy().ends_with(".jsonl.zst")
        })
        .count();
    assert_eq!(bundles, 2);
}

#[test]
fn names_that_would_escape_the_output_folder_are_refused_before_writing() {
    let folder = Folder::new();
    for name in ["..", "runs", "REPORT.md"] {
        let text =
            eamadm::PAPER_TASK1_TOML.replacen("name = \"task1\"", &format!("name = {name:?}"), 1);
        std::fs::write(folder.path("bad.toml"), text).unwrap();
        let message = fails(&folder.xtask(&with_config("bad.toml", "out/sub")), 2);
        assert!(message.contains("`name`"), "{name}: {message}");
        assert!(!folder.path("out").exists(), "{name}");
    }
}

#[test]
fn a_busy_output_folder_is_refused_with_a_clear_message() {
    let folder = Folder::new();
    write_config(&folder, "mine.toml", "mine");
    let held = eamadm_runs::output_folder::OutputFolder::open(&folder.path("out"), false).unwrap();
    let message = fails(&folder.xtask(&with_config("mine.toml", "out")), 1);
    assert!(
        message.contains("another reproduce-paper is using this output folder"),
        "{message}"
    );
    assert!(!folder.path("out/REPORT.md").exists());
    drop(held);
    folder.succeeds(&with_config("mine.toml", "out"));
}

#[test]
fn a_config_with_more_seeds_than_the_cap_is_refused_before_planning() {
    let folder = Folder::new();
    let mut config = eamadm::paper::task1();
    config.name = "many".to_owned();
    config.seeds = 100_000;
    std::fs::write(folder.path("many.toml"), config.to_toml_string().unwrap()).unwrap();
    let mut args = with_config("many.toml", "out");
    args.drain(1..3); // no --seeds
    let message = fails(&folder.xtask(&args), 2);
    assert!(message.contains("`seeds` = 100000"), "{message}");
    assert!(!folder.path("out").exists());
}

#[cfg(unix)]
#[test]
fn links_and_fifos_at_store_and_output_paths_are_refused_by_name() {
    use std::os::unix::fs::symlink;
    use std::path::Path;
    let folder = Folder::new();
    let elsewhere = folder.path("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    std::fs::write(elsewhere.join("keep.txt"), b"not ours").unwrap();
    let fifo = |path: &Path| {
        assert!(
            std::process::Command::new("mkfifo")
                .arg(path)
                .status()
                .unwrap()
                .success()
        );
    };
    type Plant<'a> = (&'a str, &'a dyn Fn(&Path));
    let plant: [Plant<'_>; 10] = [
        ("runs", &|p| symlink(&elsewhere, p).unwrap()),
        ("runs/task1.jsonl.zst", &|p| {
            symlink(elsewhere.join("keep.txt"), p).unwrap();
        }),
        ("runs/loose", &|p| symlink(&elsewhere, p).unwrap()),
        ("task1", &|p| symlink(&elsewhere, p).unwrap()),
        (".committed", &|p| symlink(&elsewhere, p).unwrap()),
        (".reproduce-paper.lock", &|p| fifo(p)),
        ("runs/task1.jsonl.zst", &|p| fifo(p)),
        // 9dc06af waited for ever on this FIFO, holding the folder's lock.
        (".outputs", &|p| fifo(p)),
        ("runs/.writers.lock", &|p| fifo(p)),
        (".reproduce-paper.lock", &|p| {
            symlink(elsewhere.join("keep.txt"), p).unwrap();
        }),
    ];
    for (n, (path, make)) in plant.iter().enumerate() {
        let out = format!("out{n}");
        let target = folder.path(&out).join(path);
        std::fs::create_dir_all(target.parent().unwrap()).unwrap();
        make(&target);
        let output = folder.xtask(&crate::shards::small(&out));
        if !output.status.success() {
            let message = String::from_utf8_lossy(&output.stderr);
            assert!(
                message.contains(&*target.to_string_lossy()) || message.contains(path),
                "{path}: {message}"
            );
        }
        // Nothing outside the output folder was written, moved or removed.
        let names: Vec<_> = std::fs::read_dir(&elsewhere)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["keep.txt"], "{path}");
        assert_eq!(
            std::fs::read(elsewhere.join("keep.txt")).unwrap(),
            b"not ours",
            "{path}"
        );
        assert!(
            !output.status.success() || path.ends_with(".jsonl.zst"),
            "{path}: accepted"
        );
    }
}
