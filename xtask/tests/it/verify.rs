//! `cargo xtask verify` (black box: the built binary) finds what checksums cannot: a stored
//! record whose numbers were forged and a cached artefact swapped for another, each with its
//! checksum recomputed.

use crate::succeeds;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use eamadm::{Experiment, Shortening};
use eamadm_runs::verify::artefacts_of;
use eamadm_runs::{PretrainedStore, RunStore};

/// The plan: Task I, two of its methods, two seeds, `--quick`, no readings.
const PLAN: [&str; 11] = [
    "--quick",
    "--task",
    "task1",
    "--method",
    "ea-madm",
    "--method",
    "softmax",
    "--seeds",
    "2",
    "--readings",
    "none",
];

fn xtask(command: &str, dir: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .arg(command)
        .args(PLAN)
        .arg("--out")
        .arg(dir.join("out"))
        .arg("--pretrained-cache")
        .arg(dir.join("cache"))
        .args(extra)
        .stdin(Stdio::null())
        .output()
        .expect("xtask starts")
}

/// `verify --all`: `Ok` when every result checks, else the exit code and the output.
fn verify_all(dir: &Path) -> Result<(), (Option<i32>, String)> {
    let output = xtask("verify", dir, &["--all"]);
    let text = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    if output.status.success() {
        Ok(())
    } else {
        Err((output.status.code(), text))
    }
}

fn reproduce(dir: &Path) {
    succeeds(&xtask("reproduce-paper", dir, &[]));
}

/// Rewrites the bundle `path` with `edit` applied to its lines (without newlines).
fn edit_bundle(path: &Path, edit: impl Fn(usize, String) -> String) {
    let bytes = std::fs::read(path).expect("the bundle is readable");
    let text = String::from_utf8(eamadm_runs::frames::decompress(&bytes).expect("zstd frames"))
        .expect("UTF-8 lines");
    let lines: String = text
        .lines()
        .enumerate()
        .map(|(i, line)| edit(i, line.to_owned()) + "\n")
        .collect();
    let compressed = eamadm_runs::frames::compress(lines.as_bytes()).expect("compresses");
    std::fs::write(path, compressed).expect("the bundle is writable");
}

/// Every step count of a stored record's line halved, its checksum recomputed.
fn forged(line: &str) -> String {
    let start = line.find("\"steps\":[").expect("a steps array") + "\"steps\":[".len();
    let end = start + line[start..].find(']').expect("the array ends");
    let halved: Vec<String> = line[start..end]
        .split(',')
        .map(|n| (n.parse::<u64>().expect("a step count") / 2).to_string())
        .collect();
    let forged = format!("{}{}{}", &line[..start], halved.join(","), &line[end..]);
    let line = eamadm_runs::store::with_checksum_recomputed(forged.as_bytes()).expect("a line");
    String::from_utf8(line).expect("UTF-8")
}

/// A record whose numbers were forged and whose checksum was recomputed opens as a valid
/// store; `verify` recomputes it and names it (9dc06af had no way to tell). The same for a
/// pre-trained artefact replaced by the same sub-task's of the other seed.
#[test]
fn verify_finds_a_forged_record_and_a_poisoned_artefact() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let dir = dir.path();
    reproduce(dir);
    verify_all(dir).expect("an honest store verifies");
    edit_bundle(&dir.join("out/runs/task1.jsonl.zst"), |i, line| {
        if i == 0 { forged(&line) } else { line }
    });
    let store = RunStore::open(&dir.join("out"), &mut |w| panic!("{w}")).expect("opens");
    assert_eq!(store.len(), 4, "the forged line checks");
    let (code, text) = verify_all(dir).expect_err("the forged record is found");
    assert_eq!(code, Some(1));
    assert!(text.contains("1 of the results"), "{text}");

    // Put the true line back; poison an artefact: one sub-task's learner swapped for the same
    // sub-task's of the other seed, its checksum recomputed.
    std::fs::remove_dir_all(dir.join("out")).expect("removable");
    reproduce(dir);
    verify_all(dir).expect("an honest store verifies");
    let cache = PretrainedStore::new(&dir.join("cache"));
    let mut by_subtask: std::collections::BTreeMap<String, Vec<_>> = Default::default();
    for key in cache.keys().expect("the cache lists its keys") {
        let (description, subtask) = cache.load_any(&key).expect("loads").expect("present");
        let value: serde_json::Value = serde_json::from_str(&description).expect("JSON");
        by_subtask
            .entry(value["subtask"].to_string())
            .or_default()
            .push((key, subtask));
    }
    let same_subtask = by_subtask
        .values()
        .find(|found| found.len() >= 2)
        .expect("a sub-task pre-trained for both seeds");
    let (victim, _) = &same_subtask[0];
    let (_, other_seed) = &same_subtask[1];
    // The victim's description, rebuilt as the plan builds it (`--quick`, two seeds).
    let mut config = eamadm::paper::task1().shortened(&Shortening::QUICK);
    config.seeds = 2;
    let experiment = Experiment::new(config).expect("the quick preset checks");
    let methods: Vec<_> = experiment.config().methods.iter().collect();
    let description = experiment
        .config()
        .seed_values()
        .flat_map(|seed| artefacts_of(&experiment, &methods, seed).expect("described"))
        .find(|(_, key, _)| key == victim)
        .map(|(description, _, _)| description)
        .expect("the victim is one of the plan's artefacts");
    let poisoned =
        eamadm_runs::pretrained::artefact_file(&description, other_seed).expect("serialises");
    std::fs::write(cache.path(victim), poisoned).expect("writable");
    assert!(
        cache.load(&description).expect("loads").is_some(),
        "the poisoned artefact checks"
    );
    let (code, text) = verify_all(dir).expect_err("the poisoned artefact is found");
    assert_eq!(code, Some(1));
    assert!(text.contains("1 of the results"), "{text}");
}
