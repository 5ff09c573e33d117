//! `reproduce-paper --suite family --family-size 2 --quick` end to end: the run's
//! `layouts.csv` (the paper's two and the family's), the `layout` column of every
//! `final-scores.csv`, the family in `findings.json` and in the main report, the family's
//! outputs (its final scores, the pooled verdicts, the figures, which pass
//! `eamadm_present::checks`), two shards merged into the same bytes, and `--family-size`
//! refused without `--suite family`.

use crate::tree;
use std::path::Path;
use std::process::{Command, Output};

const PLAN: [&str; 9] = [
    "--quick",
    "--task",
    "task2",
    "--readings",
    "none",
    "--suite",
    "family",
    "--family-size",
    "2",
];

fn xtask(args: &[&str], out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .expect("xtask starts")
}

fn ok(output: &Output) {
    assert!(
        output.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn a_small_family_writes_its_outputs_and_merges_from_shards_to_the_same_bytes() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let whole = dir.path().join("whole");
    let mut args = vec!["reproduce-paper"];
    args.extend(PLAN);
    ok(&xtask(&args, &whole));
    let family = whole.join("family");
    // One layout table, at the top: the paper's two mazes, then the family's two layouts.
    assert!(!family.join("layouts.csv").exists());
    let layouts = std::fs::read_to_string(whole.join("layouts.csv")).unwrap();
    let names: Vec<&str> = layouts
        .lines()
        .skip(1)
        .filter_map(|line| line.split(',').next())
        .filter(|name| name.starts_with('f') || name.starts_with("task"))
        .collect();
    assert_eq!(names, ["task1", "task2", "f00-uniform", "f01-perfect"]);
    let package = std::fs::read_to_string(whole.join("datapackage.json")).unwrap();
    assert!(package.contains("\"path\": \"layouts.csv\""), "{package}");
    let scores = std::fs::read_to_string(family.join("final-scores.csv")).unwrap();
    // 2 layouts × 12 methods × 3 quick seeds, each row naming its layout.
    assert_eq!(scores.lines().count(), 1 + 72);
    assert!(scores.starts_with("task,layout,method,"), "{scores}");
    assert!(
        scores
            .lines()
            .skip(1)
            .all(|l| l.starts_with("family-f00-uniform,f00-uniform,")
                || l.starts_with("family-f01-perfect,f01-perfect,"))
    );
    // The findings carry the family; the main report has its section, linking family/REPORT.md.
    let findings = std::fs::read_to_string(whole.join("findings.json")).unwrap();
    let findings = eamadm::findings::Findings::from_json(&findings).unwrap();
    let found = findings.family.as_ref().expect("the family's findings");
    assert_eq!(found.layouts.len(), 2);
    assert_eq!(found.pooled.len(), 6);
    let main_report = std::fs::read_to_string(whole.join("REPORT.md")).unwrap();
    assert!(main_report.contains("## The maze family"), "{main_report}");
    assert!(main_report.contains("[family/REPORT.md](family/REPORT.md)"));
    let verdicts = std::fs::read_to_string(family.join("verdicts.csv")).unwrap();
    // C1 and C2 against the three paper competitors.
    assert_eq!(verdicts.lines().count(), 1 + 6, "{verdicts}");
    let report = std::fs::read_to_string(family.join("REPORT.md")).unwrap();
    assert!(report.starts_with("# The maze family"));
    assert!(report.contains("| task2 | C1 |"), "{report}");
    let figures: Vec<(String, String)> = ["effect-C1.svg", "effect-C2.svg"]
        .iter()
        .map(|name| {
            (
                format!("family/{name}"),
                std::fs::read_to_string(family.join(name)).unwrap(),
            )
        })
        .collect();
    let problems = eamadm_present::checks::check_figures(&figures);
    assert!(problems.is_empty(), "{problems:?}");
    // The family writes no per-layout folder; the paper's final-scores.csv has no family row.
    assert!(!whole.join("family-f00-uniform").exists());
    let paper_scores = std::fs::read_to_string(whole.join("final-scores.csv")).unwrap();
    assert!(!paper_scores.contains("family-"));
    assert!(paper_scores.starts_with("task,layout,method,"));
    assert!(
        paper_scores
            .lines()
            .skip(1)
            .all(|l| l.starts_with("task2,task2,"))
    );

    // Two shards and a merge: the same bytes.
    let mut stores = Vec::new();
    for k in 1..=2 {
        let shard = dir.path().join(format!("shard-{k}"));
        let spec = format!("{k}/2");
        let mut args = vec!["reproduce-paper", "--shard", spec.as_str()];
        args.extend(PLAN);
        ok(&xtask(&args, &shard));
        stores.push(shard);
    }
    let merged = dir.path().join("merged");
    let mut command = Command::new(env!("CARGO_BIN_EXE_xtask"));
    command.arg("merge").args(PLAN).arg("--out").arg(&merged);
    command.args(&stores);
    ok(&command.output().expect("xtask starts"));
    let (expected, actual) = (tree(&whole), tree(&merged));
    for (name, bytes) in &expected {
        if name.starts_with("runs/") || name.starts_with('.') {
            continue;
        }
        assert!(actual.get(name) == Some(bytes), "{name} differs");
    }
}

#[test]
fn family_size_without_the_family_suite_is_refused() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("out");
    let output = xtask(&["reproduce-paper", "--quick", "--family-size", "3"], &out);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("--family-size") && stderr.contains("--suite family"),
        "{stderr}"
    );
    let output = xtask(
        &[
            "reproduce-paper",
            "--quick",
            "--suite",
            "family",
            "--family-size",
            "0",
        ],
        &out,
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("1 to 10000"));
    assert!(!out.exists());
}
