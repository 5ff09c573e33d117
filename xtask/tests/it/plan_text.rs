//! The plan `reproduce-paper` prints before it runs, for people (black box; moved from xtask's
//! `plan` unit tests). Each plan is run as a shard of a billion, which holds none of its runs:
//! the plan is checked, loaded and printed, and nothing runs.

use crate::Folder;

/// The plan text `reproduce-paper args` prints, its folder written `[folder]`.
fn plan_text(args: &[&str]) -> String {
    let folder = Folder::new();
    let mut all = vec![
        "reproduce-paper",
        "--out",
        "results",
        "--shard",
        "1/1000000000",
    ];
    all.extend(args);
    let stdout = folder.succeeds(&all);
    let end = stdout.find("  output:").expect("the plan names its output");
    let end = end + stdout[end..].find('\n').expect("a whole line") + 1;
    let root = folder.path("").display().to_string();
    stdout[..end].replace(root.trim_end_matches('/'), "[folder]")
}

#[test]
fn plans_read_well() {
    insta::assert_snapshot!("reproduce_default", plan_text(&[]));
    let quick = [
        "--quick", "--task", "task2", "--method", "ea-madm", "--method", "softmax",
    ];
    insta::assert_snapshot!("reproduce_quick", plan_text(&quick));
    let no_readings = [
        "--readings",
        "none",
        "--task",
        "task1",
        "--method",
        "epsilon-greedy",
    ];
    insta::assert_snapshot!("reproduce_no_readings", plan_text(&no_readings));
}
