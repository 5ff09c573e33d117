//! The verdicts judged again under a reading: a reading that changes nothing holds everywhere,
//! one that makes a competitor better flips the verdict, only the named methods' runs on the
//! named task are replaced, survival follows the flips, the rows are bit-identical with one and
//! two threads, and `sensitivity.csv` is pinned in a snapshot.

use eamadm_eval::Role;
use eamadm_eval::claims::{ClaimOptions, Verdict};
use eamadm_eval::scores::{FinalScore, RunOutcome};
use eamadm_eval::sensitivity::{
    Change, ReadingRuns, SENSITIVITY_COLUMNS, read_csv, sensitivity, substitute, survival,
    write_csv,
};
use eamadm_eval::stats::{Bootstrap, SignFlipTest};

fn row(task: &str, method: &str, kind: &str, seed: u64, steps: f64) -> FinalScore {
    FinalScore {
        task: task.to_owned(),
        layout: String::new(),
        method: method.to_owned(),
        role: Role::Paper,
        kind: kind.to_owned(),
        seed,
        episodes: 200,
        final_window: 20,
        final_steps: steps,
        final_return: -steps,
        success_rate: 1.0,
        greedy_reached: true,
        greedy_steps: 73,
        outcome: RunOutcome::Converged,
        collapse_episode: None,
        fluctuation_steps: steps / 4.0,
        fluctuation_return: steps / 4.0,
        greedy_evaluations: 10,
        stable_reaching: Some(true),
        fluctuation_greedy_steps: Some(steps / 4.0),
        fluctuation_greedy_return: Some(steps / 4.0),
        env_steps_total: 1000,
        pretrain_env_steps: 0,
        step_cap: 2000,
        optimum_steps: Some(73),
        reaching_episodes: 10,
        reach_average_reward: None,
        reach_time: None,
        reach_retention_time: None,
        retention_decay: None,
    }
}

/// A method's 12 seeds on `task` at `level + 3·seed`.
fn method(task: &str, label: &str, kind: &str, level: f64) -> Vec<FinalScore> {
    (0..12)
        .map(|seed| row(task, label, kind, seed, level + 3.0 * seed as f64))
        .collect()
}

/// Task II: EA-MADM far better than ε-greedy and softmax; Task I likewise.
fn base() -> Vec<FinalScore> {
    let mut rows = Vec::new();
    for task in ["task1", "task2"] {
        rows.extend(method(task, "ea-madm", "ea_madm", 100.0));
        rows.extend(method(task, "epsilon-greedy", "epsilon_greedy", 400.0));
        rows.extend(method(task, "softmax", "softmax", 500.0));
    }
    rows
}

fn options() -> ClaimOptions {
    ClaimOptions {
        bootstrap: Bootstrap::new(2000, 0.95, 7).unwrap(),
        sign_flip: SignFlipTest::new(2000, 7).unwrap(),
        alpha: 0.05,
        margins: crate::margins::maze_margins(&["task1", "task2"]),
    }
}

/// The reading's reruns: `methods` on `task` at `level` (named by the reading's experiment).
fn reruns(name: &str, task: &str, methods: &[(&str, &str, f64)]) -> ReadingRuns {
    ReadingRuns {
        reading: name.to_owned(),
        task: task.to_owned(),
        methods: methods
            .iter()
            .map(|(label, _, _)| (*label).to_owned())
            .collect(),
        scores: methods
            .iter()
            .flat_map(|&(label, kind, level)| {
                method(&format!("{task}-reading-{name}"), label, kind, level)
            })
            .collect(),
    }
}

#[test]
fn a_reading_that_changes_nothing_holds_everywhere() {
    let base = base();
    // The same runs again, as a rerun that changes nothing would give.
    let no_op = ReadingRuns {
        reading: "no-op".to_owned(),
        task: "task2".to_owned(),
        methods: vec!["ea-madm".to_owned(), "softmax".to_owned()],
        scores: base
            .iter()
            .filter(|r| r.task == "task2" && r.method != "epsilon-greedy")
            .map(|r| FinalScore {
                task: "task2-reading-no-op".to_owned(),
                ..r.clone()
            })
            .collect(),
    };
    assert_eq!(substitute(&base, &no_op), base);
    let rows = sensitivity(&base, &[no_op], &options()).unwrap();
    // C1–C3 are made on Task II; C4 (the robot) is not.
    let claims: Vec<&str> = rows.iter().map(|r| r.claim).collect();
    assert_eq!(claims, ["C1", "C2", "C3"]);
    for row in &rows {
        assert_eq!(row.change, Change::Holds, "{row:?}");
        assert_eq!(row.verdict, row.base_verdict);
        assert_eq!(row.verdict, Verdict::Supported);
        assert_eq!(row.statistic, "paired_mean_difference");
        assert!(row.estimate.is_some() && row.p_holm.is_some());
    }
    assert!(
        survival(&rows)
            .iter()
            .all(|s| s.survives && s.readings == 1)
    );
}

#[test]
fn a_reading_that_makes_a_competitor_better_flips_and_replaces_only_its_runs() {
    let base = base();
    let better = reruns("softmax-better", "task2", &[("softmax", "softmax", 20.0)]);
    let same = reruns(
        "epsilon-same",
        "task1",
        &[("epsilon-greedy", "epsilon_greedy", 400.0)],
    );
    let substituted = substitute(&base, &better);
    // Only softmax on Task II changed, in place, relabelled to the base task.
    assert_eq!(substituted.len(), base.len());
    for (new, old) in substituted.iter().zip(&base) {
        assert_eq!(new.task, old.task);
        assert_eq!(new.method, old.method);
        let replaced = old.task == "task2" && old.method == "softmax";
        assert_eq!(new == old, !replaced, "{} {}", old.task, old.method);
    }
    let rows = sensitivity(&base, &[better, same], &options()).unwrap();
    assert_eq!(rows.len(), 6);
    let c1 = &rows[0];
    assert_eq!((c1.claim, c1.task.as_str()), ("C1", "task2"));
    assert_eq!(c1.base_verdict, Verdict::Supported);
    assert_eq!(c1.verdict, Verdict::Contradicted);
    assert_eq!(c1.change, Change::Flips);
    assert_eq!(c1.versus, "softmax");
    assert_eq!(c1.metric, "final_steps");
    assert!(c1.estimate.unwrap() > 0.0 && c1.ci_low.unwrap() > 0.0);
    assert!(rows[3..].iter().all(|r| r.change == Change::Holds));
    let survival = survival(&rows);
    assert_eq!(survival.len(), 6);
    assert!(!survival[0].survives);
    assert_eq!(survival[0].flipped_by, ["softmax-better"]);
    assert!(survival[3..].iter().all(|s| s.survives));
}

#[test]
fn a_task_without_the_papers_ea_madm_gives_no_rows() {
    let base: Vec<FinalScore> = base()
        .into_iter()
        .filter(|r| r.method != "ea-madm")
        .collect();
    let runs = reruns("x", "task2", &[("softmax", "softmax", 20.0)]);
    assert!(sensitivity(&base, &[runs], &options()).unwrap().is_empty());
}

#[test]
fn rows_are_bit_identical_with_one_and_two_threads() {
    let base = base();
    let readings = [
        reruns("a", "task2", &[("softmax", "softmax", 20.0)]),
        reruns("b", "task1", &[("ea-madm", "ea_madm", 450.0)]),
    ];
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| sensitivity(&base, &readings, &options()).unwrap())
    };
    assert_eq!(on(1), on(2));
}

#[test]
fn sensitivity_csv_has_its_columns_and_rounded_rows() {
    let base = base();
    let rows = sensitivity(
        &base,
        &[reruns(
            "softmax-better",
            "task2",
            &[("softmax", "softmax", 20.0)],
        )],
        &options(),
    )
    .unwrap();
    let mut empty = Vec::new();
    write_csv(&[], &mut empty).unwrap();
    assert_eq!(
        String::from_utf8(empty).unwrap().trim_end(),
        SENSITIVITY_COLUMNS.join(",")
    );
    let mut csv = Vec::new();
    write_csv(&rows, &mut csv).unwrap();
    let text = String::from_utf8(csv).unwrap();
    assert!(text.starts_with(&SENSITIVITY_COLUMNS.join(",")));
    // The table reads back to the same rows (what re-renders a folder's report), and a cell
    // no writer writes is refused by name.
    assert_eq!(read_csv(text.as_bytes()).unwrap(), rows);
    assert!(read_csv(&[][..]).unwrap().is_empty());
    let bad = text
        .replacen("flips", "flipped", 1)
        .replacen("holds", "held", 1);
    let error = read_csv(bad.as_bytes()).unwrap_err().to_string();
    assert!(error.contains("column change"), "{error}");
    // Rounded for the snapshot (the CSV keeps full precision).
    let rounded: Vec<String> = rows
        .iter()
        .map(|r| {
            let f = |x: Option<f64>| x.map_or_else(String::new, |x| format!("{x:.2}"));
            format!(
                "{} {} {} {} -> {} {} vs {} {} {} {} [{}, {}] p {}",
                r.claim,
                r.task,
                r.reading,
                r.base_verdict.name(),
                r.verdict.name(),
                r.change.name(),
                r.versus,
                r.metric,
                r.statistic,
                f(r.estimate),
                f(r.ci_low),
                f(r.ci_high),
                f(r.p_holm)
            )
        })
        .collect();
    insta::assert_snapshot!(rounded.join("\n"));
}

/// Issue 34 item 6: a C3 verdict decided by the stable-reaching test is labelled by that
/// test's own column (`stable_reaching`, `stable_reaching_share_difference`), not as `reached`
/// (every method may reach in training while only some reach stably).
#[test]
fn a_c3_verdict_decided_by_stable_reaching_is_labelled_so() {
    let mut base = base();
    // The competitors reach in training on every seed but are never stable-reaching: no
    // greedy SD of theirs, so only the stable-reaching test decides C3.
    for r in base.iter_mut().filter(|r| r.method != "ea-madm") {
        r.stable_reaching = Some(false);
        r.fluctuation_greedy_steps = None;
        r.fluctuation_greedy_return = None;
    }
    let no_op = ReadingRuns {
        reading: "no-op".to_owned(),
        task: "task2".to_owned(),
        methods: vec!["softmax".to_owned()],
        scores: base
            .iter()
            .filter(|r| r.task == "task2" && r.method == "softmax")
            .cloned()
            .collect(),
    };
    let rows = sensitivity(&base, &[no_op], &options()).unwrap();
    let c3 = rows.iter().find(|r| r.claim == "C3").unwrap();
    assert_eq!(c3.verdict, Verdict::Supported, "{c3:?}");
    assert_eq!(c3.metric, "stable_reaching");
    assert_eq!(c3.statistic, "stable_reaching_share_difference");
    // 12 of 12 seeds against 0 of 12.
    assert_eq!(c3.estimate, Some(1.0));
    assert_ne!(c3.metric, "reached");
    // The CSV names it so and reads back.
    let mut bytes = Vec::new();
    write_csv(&rows, &mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    assert!(
        text.lines().any(|l| l.starts_with("C3,")
            && l.contains(",stable_reaching,stable_reaching_share_difference,")),
        "{text}"
    );
    assert_eq!(read_csv(text.as_bytes()).unwrap(), rows);
}
