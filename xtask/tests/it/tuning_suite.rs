//! `--suite tuning` (black box: the built binary; moved from xtask's `tuning_suite` unit
//! tests): every method gets the same number of trials, stage 2 is planned only once stage 1
//! is stored, and the "each at its best" verdicts are the claims judged on the chosen trials
//! rerun on the held-out seeds.

use crate::succeeds;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use eamadm::findings::Findings;
use eamadm::tuning::{self, TRIALS_PER_METHOD, TUNING_COLUMNS, TaskTuning};
use eamadm::{Experiment, Shortening};

/// `xtask <command> <args>` with the artefact cache of `dir`, its output kept.
fn xtask(dir: &Path, command: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .arg(command)
        .args(args)
        .arg("--pretrained-cache")
        .arg(dir.join("cache"))
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("xtask starts")
}

/// A tiny tuning plan into `out`: Task I shortened by --quick, EA-MADM against softmax, two
/// held-out seeds (three tuning seeds), no readings.
fn tiny(out: &str, tuned: bool) -> Vec<String> {
    let mut args: Vec<String> = [
        "--quick",
        "--seeds",
        "2",
        "--task",
        "task1",
        "--method",
        "ea-madm",
        "--method",
        "softmax",
        "--readings",
        "none",
        "--out",
        out,
    ]
    .map(str::to_owned)
    .to_vec();
    if tuned {
        args.extend(["--suite".to_owned(), "tuning".to_owned()]);
    }
    args
}

fn refs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

/// The experiment of every job `--list-jobs` lists for `args`.
fn listed(dir: &Path, args: &[&str]) -> Vec<(String, String)> {
    let mut with = vec!["--list-jobs"];
    with.extend(args);
    succeeds(&xtask(dir, "reproduce-paper", &with))
        .lines()
        .map(|line| {
            let job: serde_json::Value = serde_json::from_str(line).expect("a JSON line");
            let field = |name: &str| job[name].as_str().expect("a string").to_owned();
            (field("experiment"), field("method"))
        })
        .collect()
}

fn read(folder: &Path, file: &str) -> String {
    std::fs::read_to_string(folder.join(file)).expect("written")
}

/// The law at the plan: on every tuned task each method the claims compare has the
/// same number of stage-1 experiments, one per trial, each of the one method.
#[test]
fn the_plan_gives_every_method_the_same_number_of_trials() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let plan = [
        "--quick",
        "--seeds",
        "2",
        "--readings",
        "none",
        "--out",
        "out",
        "--task",
        "task1",
        "--task",
        "task2",
        "--task",
        "robot",
        "--task",
        "robot-paper-state",
    ];
    let mut tuned = plan.to_vec();
    tuned.extend(["--suite", "tuning"]);
    let jobs = listed(dir.path(), &tuned);
    for task in tuning::SUITE_TASKS {
        let prefix = format!("{task}-tune-");
        let mut methods_of: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
        for (experiment, method) in jobs.iter().filter(|(e, _)| e.starts_with(&prefix)) {
            methods_of.entry(experiment).or_default().push(method);
        }
        let mut per_method: BTreeMap<&str, usize> = BTreeMap::new();
        for (experiment, methods) in &methods_of {
            assert!(methods.windows(2).all(|m| m[0] == m[1]), "{experiment}");
            *per_method.entry(methods[0]).or_default() += 1;
        }
        let expected: BTreeMap<&str, usize> =
            ["ea-madm", "epsilon-greedy", "epsilon-decreasing", "softmax"]
                .map(|m| (m, TRIALS_PER_METHOD as usize))
                .into();
        assert_eq!(per_method, expected, "{task}");
    }
    // The robot over the paper's state is not a claim's task: not tuned.
    assert!(
        !jobs
            .iter()
            .any(|(e, _)| e.starts_with("robot-paper-state-tune-"))
    );
    // Without the suite, nothing of it is planned.
    let plain = listed(dir.path(), &plan);
    assert!(plain.iter().all(|(e, _)| !e.contains("-tune-")));
}

/// Stage 2 is planned only once stage 1 is in the store: not from an empty folder nor from a
/// shard's part; a merge of the shards stores stage 1 and says to rerun; the rerun runs stage
/// 2 and writes what one invocation writes, byte for byte.
#[test]
fn stage_two_is_planned_only_after_stage_one() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let dir = dir.path();
    let tuned = |out: &str| tiny(out, true);
    // From an empty folder: the base runs and stage 1 only (2 methods × 16 trials × 3 tuning
    // seeds under --quick), no held-out trial.
    let jobs = listed(dir, &refs(&tuned("empty")));
    let stage1 = jobs.iter().filter(|(e, _)| e.contains("-tune-")).count();
    assert_eq!(stage1, 2 * TRIALS_PER_METHOD as usize * 3);
    assert!(jobs.iter().all(|(e, _)| !e.contains("-best-")));

    // Two shards: each holds part of stage 1, so neither plans stage 2.
    for k in 1..=2 {
        let mut args = tuned(&format!("shard{k}"));
        args.extend(["--shard".to_owned(), format!("{k}/2")]);
        succeeds(&xtask(dir, "reproduce-paper", &refs(&args)));
    }
    let mut merge = tuned("merged");
    merge.extend(["shard1".to_owned(), "shard2".to_owned()]);
    let output = xtask(dir, "merge", &refs(&merge));
    assert_eq!(output.status.code(), Some(1));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(
        message.contains("stage 1 is complete") && message.contains("stage 2 (4 runs"),
        "{message}"
    );
    assert!(!dir.join("merged/REPORT.md").exists());
    // Now stage 1 is in the merged folder's store, and stage 2 is planned from it.
    let mut held_out: Vec<String> = listed(dir, &refs(&tuned("merged")))
        .into_iter()
        .map(|(e, _)| e)
        .filter(|e| e.contains("-best-"))
        .collect();
    held_out.dedup();
    assert_eq!(held_out, ["task1-best-ea-madm", "task1-best-softmax"]);
    // The rerun of the same command runs stage 2 and reports.
    succeeds(&xtask(dir, "reproduce-paper", &refs(&tuned("merged"))));
    // One invocation does both stages in sequence, and writes the same outputs.
    succeeds(&xtask(dir, "reproduce-paper", &refs(&tuned("whole"))));
    for file in [
        "REPORT.md",
        "tuning.csv",
        "findings.json",
        "final-scores.csv",
    ] {
        assert_eq!(
            read(&dir.join("merged"), file),
            read(&dir.join("whole"), file),
            "{file}"
        );
    }
}

/// `tuning.csv` has its documented columns and one chosen trial per method, the best by the
/// objective (the lowest index among equals); the "each at its best" verdicts are the claims
/// judged on the chosen trials run again here on the held-out seeds, apart from the
/// paper-setting verdicts, which are those of the plan without the suite.
#[test]
fn the_at_its_best_verdicts_of_a_tiny_plan() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let dir = dir.path();
    succeeds(&xtask(dir, "reproduce-paper", &refs(&tiny("tuned", true))));
    succeeds(&xtask(dir, "reproduce-paper", &refs(&tiny("plain", false))));
    let (tuned, plain) = (dir.join("tuned"), dir.join("plain"));
    assert!(!plain.join("tuning.csv").exists());

    // tuning.csv: its columns, every trial, one chosen per method, the best.
    let text = read(&tuned, "tuning.csv");
    let mut csv = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> = csv
        .headers()
        .expect("a header")
        .iter()
        .map(str::to_owned)
        .collect();
    let names: Vec<&str> = TUNING_COLUMNS.iter().map(|c| c.name).collect();
    assert_eq!(header, names);
    let rows: Vec<csv::StringRecord> = csv.records().map(|r| r.expect("a row")).collect();
    assert_eq!(rows.len(), 2 * TRIALS_PER_METHOD as usize);
    let column = |name: &str| names.iter().position(|n| *n == name).expect("a column");
    let mut chosen_trials = Vec::new();
    for method in ["ea-madm", "softmax"] {
        let of: Vec<&csv::StringRecord> = rows
            .iter()
            .filter(|r| &r[column("method")] == method)
            .collect();
        assert_eq!(of.len(), TRIALS_PER_METHOD as usize);
        let score = |r: &csv::StringRecord| r[column("score")].parse::<f64>().expect("a score");
        let best = of
            .iter()
            .map(|r| score(r))
            .min_by(f64::total_cmp)
            .expect("trials");
        let expected = of.iter().find(|r| score(r) == best).expect("the best");
        let chosen: Vec<&&csv::StringRecord> = of
            .iter()
            .filter(|r| &r[column("chosen")] == "true")
            .collect();
        assert_eq!(chosen.len(), 1, "{method}");
        assert_eq!(chosen[0][column("trial")], expected[column("trial")]);
        assert!(of.iter().all(|r| &r[column("tuning_seeds")] == "3"));
        chosen_trials.push(expected[column("trial")].parse::<u32>().expect("a trial"));
    }
    let package = read(&tuned, "datapackage.json");
    assert!(package.contains("\"path\": \"tuning.csv\""), "{package}");
    assert!(!read(&plain, "datapackage.json").contains("tuning.csv"));

    // The paper-setting verdicts are those of the plan without the suite.
    let findings = Findings::from_json(&read(&tuned, "findings.json")).expect("findings");
    let without = Findings::from_json(&read(&plain, "findings.json")).expect("findings");
    assert_eq!(findings.tasks, without.tasks);
    assert!(without.at_best.is_empty());
    let report = read(&tuned, "REPORT.md");
    let start = report
        .find("## Each method at its best (same tuning budget)")
        .expect("the report has the section");
    let end = start + report[start..].find("\n## Task I").expect("Task I follows") + 1;
    assert_eq!(
        format!("{}{}", &report[..start], &report[end..]),
        read(&plain, "REPORT.md"),
        "the report gains the section and nothing else changes"
    );

    // The at-its-best verdicts: the chosen trials run here, apart from the store.
    let [at_best] = &findings.at_best[..] else {
        panic!("one tuned task: {:?}", findings.at_best);
    };
    assert_eq!(at_best.task, "task1");
    let chosen: Vec<(&str, u32)> = at_best
        .chosen
        .iter()
        .map(|c| (c.method.as_str(), c.trial))
        .collect();
    assert_eq!(
        chosen,
        [("ea-madm", chosen_trials[0]), ("softmax", chosen_trials[1])]
    );
    let mut base = eamadm::paper::task1().shortened(&Shortening::QUICK);
    base.seeds = 2;
    let tuning =
        TaskTuning::new(&base, &["ea-madm", "softmax"], TRIALS_PER_METHOD, 3).expect("the tuning");
    let mut scores = Vec::new();
    for (method, trial) in chosen {
        let trial = tuning
            .trials
            .iter()
            .find(|t| t.method == method && t.trial == trial)
            .expect("the chosen trial");
        let experiment = Experiment::new(trial.held_out(&base).expect("held out")).expect("checks");
        for record in experiment.run_all().expect("runs") {
            let mut score = eamadm::scores::final_score_of(&record, &experiment).expect("scored");
            score.task = "task1".to_owned();
            scores.push(score);
        }
    }
    let context = eamadm::paper::report_context_from_toml(&read(&tuned, "report-context.toml"))
        .expect("the context");
    let options = context.claim_options().expect("options");
    let judged = eamadm::claims::judge(&scores, &options).expect("judged");
    let expected: Vec<(String, eamadm::claims::Verdict)> = judged
        .iter()
        .filter(|j| j.method == "ea-madm")
        .map(|j| (j.claim.id.to_owned(), j.verdict))
        .collect();
    let got: Vec<(String, eamadm::claims::Verdict)> = at_best
        .verdicts
        .iter()
        .map(|v| (v.claim.clone(), v.verdict))
        .collect();
    assert_eq!(got, expected);
    assert_eq!(got.len(), 3, "C1–C3 are claimed on Task I");
    assert_eq!(
        at_best.converged.seeds, 2,
        "paired over the two held-out seeds"
    );
}
