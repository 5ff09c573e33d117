//! The maze family's pooled verdicts on hand-made scores: the verdict follows the numbers and
//! flips with them, a layout-only spread is what the layouts-only interval sees, rows of other
//! experiments are ignored, and a small snapshot pins the numbers; the family's findings (the
//! layouts run, the spread of the per-layout effects) and `findings.json` with and without
//! them.

use eamadm_eval::Role;
use eamadm_eval::claims::Margin;
use eamadm_eval::family::{self, PooledVerdict, family_verdicts, verdict};
use eamadm_eval::scores::FinalScore;
use eamadm_eval::stats::hierarchical::HierarchicalBootstrap;
use proptest::prelude::*;

fn row(task: &str, method: &str, kind: &str, seed: u64, steps: f64) -> FinalScore {
    FinalScore {
        task: task.to_owned(),
        layout: String::new(),
        method: method.to_owned(),
        role: Role::Paper,
        kind: kind.to_owned(),
        seed,
        episodes: 6400,
        final_window: 20,
        final_steps: steps,
        final_return: 11.0 - steps,
        success_rate: 1.0,
        greedy_reached: true,
        greedy_steps: 60,
        outcome: eamadm_eval::scores::RunOutcome::Collapsed,
        collapse_episode: None,
        fluctuation_steps: 0.0,
        fluctuation_return: 0.0,
        greedy_evaluations: 10,
        stable_reaching: Some(true),
        fluctuation_greedy_steps: Some(0.0),
        fluctuation_greedy_return: Some(0.0),
        env_steps_total: 1000,
        pretrain_env_steps: 0,
        step_cap: 2000,
        optimum_steps: Some(58),
        reaching_episodes: 10,
        reach_average_reward: None,
        reach_time: None,
        reach_retention_time: None,
        retention_decay: None,
    }
}

/// `layouts` layouts, 5 seeds each: EA-MADM at `100 + ea + layout + seed/10`, softmax at
/// `100 + layout + seed/10`, plus a paper-task row that must be ignored.
fn scores(layouts: usize, ea: f64) -> Vec<FinalScore> {
    let mut rows = vec![row("task2", "ea-madm", "ea_madm", 0, 1.0e6)];
    for layout in 0..layouts {
        let task = format!("family-f{layout:02}-trap");
        for seed in 0..5 {
            let base = 100.0 + layout as f64 + seed as f64 / 10.0;
            rows.push(row(&task, "ea-madm", "ea_madm", seed, base + ea));
            rows.push(row(&task, "softmax", "softmax", seed, base));
        }
    }
    rows
}

fn margins() -> Vec<Margin> {
    vec![Margin {
        column: "final_steps".to_owned(),
        value: 2.0,
        reason: "test".to_owned(),
    }]
}

fn quick() -> HierarchicalBootstrap {
    HierarchicalBootstrap {
        resamples: 500,
        ..HierarchicalBootstrap::default()
    }
}

#[test]
fn the_verdict_follows_the_numbers() {
    let steps = |ea: f64| {
        family_verdicts(&scores(6, ea), &margins(), &quick())
            .unwrap()
            .pooled[0]
            .verdict
    };
    // Fewer steps is better: EA-MADM 5 steps fewer on every layout and seed.
    assert_eq!(steps(-5.0), PooledVerdict::FavoursEaMadm);
    assert_eq!(steps(5.0), PooledVerdict::FavoursCompetitor);
    assert_eq!(steps(0.5), PooledVerdict::Equivalent);
    let all = family_verdicts(&scores(6, -5.0), &margins(), &quick()).unwrap();
    // C1 and C2 against the one competitor; C2 (return) has no margin here and goes the same way.
    assert_eq!(all.pooled.len(), 2);
    assert_eq!(all.pooled[1].claim, "C2");
    assert_eq!(all.pooled[1].verdict, PooledVerdict::FavoursEaMadm);
    assert_eq!(all.pooled[0].layouts, 6);
    assert_eq!(all.pooled[0].pairs, 30);
    assert_eq!(all.pooled[0].layouts_favouring_ea_madm, 6);
    assert!((all.pooled[0].effect + 5.0).abs() < 1e-9);
    // The paper task's row is not a family layout's.
    assert_eq!(all.layouts.len(), 12);
    assert!(all.layouts.iter().all(|e| e.layout.starts_with('f')));
}

fn points(layouts: usize) -> Vec<family::LayoutPoint> {
    (0..layouts)
        .map(|layout| family::LayoutPoint {
            layout: format!("f{layout:02}-trap"),
            kind: if layout % 2 == 0 { "trap" } else { "rooms" }.to_owned(),
            detour_ratio: 1.0 + layout as f64,
        })
        .collect()
}

#[test]
fn the_findings_hold_the_layouts_run_and_the_spread_of_their_effects() {
    // EA-MADM 3 steps worse on every layout of four; a fifth layout has no runs.
    let rows = scores(4, 3.0);
    let verdicts = family_verdicts(&rows, &margins(), &quick()).unwrap();
    let found = family::family_findings(&verdicts, &points(5), &rows).unwrap();
    assert_eq!(found.episodes, 6400);
    assert_eq!(found.seeds, 5);
    let names: Vec<&str> = found.layouts.iter().map(|l| l.layout.as_str()).collect();
    assert_eq!(names, ["f00-trap", "f01-trap", "f02-trap", "f03-trap"]);
    assert_eq!(found.pooled, verdicts.pooled);
    // C1 and C2 against softmax, each layout's effect 3 steps (and −3 in return).
    assert_eq!(found.spread.len(), 2);
    let steps = &found.spread[0];
    assert_eq!(
        (steps.claim.as_str(), steps.competitor.as_str()),
        ("C1", "softmax")
    );
    assert_eq!(steps.layouts, 4);
    for value in [steps.min, steps.median, steps.max] {
        assert!((value - 3.0).abs() < 1e-9, "{steps:?}");
    }
    let kinds: Vec<(&str, usize)> = steps
        .by_kind
        .iter()
        .map(|k| (k.kind.as_str(), k.layouts))
        .collect();
    assert_eq!(kinds, [("trap", 2), ("rooms", 2)]);
    assert!((found.spread[1].median + 3.0).abs() < 1e-9);
    // No family run, no findings.
    assert!(family::family_findings(&verdicts, &points(5), &rows[..1]).is_none());
}

#[test]
fn findings_json_carries_the_family_only_when_it_ran() {
    use eamadm_eval::findings::{FINDINGS_FORMAT, Findings};
    let without = Findings::default();
    let text = without.to_json().unwrap();
    assert!(!text.contains("\"family\""), "{text}");
    assert_eq!(Findings::from_json(&text).unwrap(), without);
    let rows = scores(3, -4.0);
    let verdicts = family_verdicts(&rows, &margins(), &quick()).unwrap();
    let with =
        Findings::default().with_family(family::family_findings(&verdicts, &points(3), &rows));
    assert_eq!(with.format, FINDINGS_FORMAT);
    let text = with.to_json().unwrap();
    assert!(text.contains("\"family\""));
    let back = Findings::from_json(&text).unwrap();
    assert_eq!(back, with);
    assert_eq!(back.family.unwrap().layouts.len(), 3);
    // An older format is refused, naming what to do.
    let old = text.replacen(
        &format!("\"format\": {FINDINGS_FORMAT}"),
        "\"format\": 2",
        1,
    );
    let error = Findings::from_json(&old).unwrap_err().to_string();
    assert!(
        error.contains("rerun `cargo xtask reproduce-paper`"),
        "{error}"
    );
}

#[test]
fn no_family_rows_no_verdicts() {
    let rows = vec![row("task2", "ea-madm", "ea_madm", 0, 1.0)];
    let verdicts = family_verdicts(&rows, &margins(), &quick()).unwrap();
    assert!(verdicts.pooled.is_empty() && verdicts.layouts.is_empty());
    assert_eq!(family::layout_of("family-f03-trap"), Some("f03-trap"));
    assert_eq!(family::layout_of("task2"), None);
}

#[test]
fn snapshot_of_a_small_family() {
    let mut rows = scores(4, -3.0);
    // One layout where EA-MADM loses, so the effects differ.
    for row in rows
        .iter_mut()
        .filter(|r| r.task == "family-f01-trap" && r.method == "ea-madm")
    {
        row.final_steps += 8.0;
        row.final_return -= 8.0;
    }
    let verdicts = family_verdicts(&rows, &margins(), &quick()).unwrap();
    let text: Vec<String> = verdicts
        .pooled
        .iter()
        .map(|p| {
            format!(
                "{} {} {} effect {:.2} [{:.2}, {:.2}] layouts-only [{:.2}, {:.2}] {}/{} {}",
                p.claim,
                p.metric,
                p.competitor,
                p.effect,
                p.low,
                p.high,
                p.layouts_only_low,
                p.layouts_only_high,
                p.layouts_favouring_ea_madm,
                p.layouts,
                p.verdict.name()
            )
        })
        .collect();
    insta::assert_snapshot!(text.join("\n"));
}

proptest! {
    /// Laws of the interval rule: mirroring the interval and the direction gives the same
    /// verdict; a wider margin never turns an equivalence into anything else, and an interval
    /// beyond 0 with no margin favours the side it lies on.
    #[test]
    fn the_interval_rule(a in -50.0f64..50.0, width in 0.0f64..20.0, margin in 0.1f64..10.0) {
        let (low, high) = (a, a + width);
        for m in [None, Some(margin)] {
            prop_assert_eq!(verdict(low, high, m, 1.0), verdict(-high, -low, m, -1.0));
        }
        if verdict(low, high, Some(margin), 1.0) == PooledVerdict::Equivalent {
            prop_assert_eq!(verdict(low, high, Some(margin * 2.0), 1.0), PooledVerdict::Equivalent);
        }
        if low > 0.0 {
            prop_assert_eq!(verdict(low, high, None, 1.0), PooledVerdict::FavoursEaMadm);
            prop_assert_eq!(verdict(low, high, None, -1.0), PooledVerdict::FavoursCompetitor);
        }
    }
}
