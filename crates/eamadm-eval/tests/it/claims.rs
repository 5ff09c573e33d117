//! The claims and their verdicts on hand-made per-seed scores: the claims name real columns,
//! the verdict follows the numbers (it flips when they flip), untestable claims say why, and the
//! judgements are bit-identical with one and two threads.

use eamadm_eval::Role;
use eamadm_eval::claims::{self, ClaimOptions, ComparisonOutcome, Verdict, VersusSet};
use eamadm_eval::paper_claims::{self as paper, CLAIMS};
use eamadm_eval::scores::{COLUMNS, FinalScore};
use eamadm_eval::stats::Bootstrap;

fn row(method: &str, role: Role, kind: &str, seed: u64, steps: f64) -> FinalScore {
    FinalScore {
        task: "task2".to_owned(),
        layout: String::new(),
        method: method.to_owned(),
        role,
        kind: kind.to_owned(),
        seed,
        episodes: 200,
        final_window: 20,
        final_steps: steps,
        final_return: -steps,
        success_rate: 0.5,
        greedy_reached: false,
        greedy_steps: 2000,
        outcome: eamadm_eval::scores::RunOutcome::Collapsed,
        collapse_episode: Some(150),
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

/// EA-MADM at `ea + seed`, softmax at `other + seed`, 10 seeds each.
fn scores(ea: f64, other: f64) -> Vec<FinalScore> {
    (0..10)
        .map(|seed| row("ea-madm", Role::Paper, "ea_madm", seed, ea + seed as f64))
        .chain(
            (0..10).map(|seed| row("softmax", Role::Paper, "softmax", seed, other + seed as f64)),
        )
        .collect()
}

fn options() -> ClaimOptions {
    ClaimOptions {
        bootstrap: Bootstrap::new(2000, 0.95, 7).unwrap(),
        sign_flip: eamadm_eval::stats::SignFlipTest::new(2000, 7).unwrap(),
        alpha: 0.05,
        margins: crate::margins::maze_margins(&["task1", "task2"]),
    }
}

fn verdict(scores: &[FinalScore], claim: &str) -> Verdict {
    claims::judge(scores, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == claim && j.method == "ea-madm")
        .unwrap()
        .verdict
}

#[test]
fn every_claim_metric_is_a_column_of_final_scores() {
    for claim in CLAIMS {
        for metric in claim.metrics {
            assert!(
                COLUMNS.iter().any(|c| c.name == metric.column),
                "{}: {}",
                claim.id,
                metric.column
            );
        }
    }
    assert_eq!(paper::claim("C3").unwrap().metrics.len(), 2);
}

#[test]
fn the_verdict_flips_when_the_numbers_flip() {
    let fewer = scores(100.0, 1500.0);
    assert_eq!(verdict(&fewer, "C1"), Verdict::Supported);
    assert_eq!(verdict(&fewer, "C2"), Verdict::Supported);
    assert_eq!(verdict(&fewer, "C3"), Verdict::Supported);
    let more = scores(1500.0, 100.0);
    assert_eq!(verdict(&more, "C1"), Verdict::Contradicted);
    assert_eq!(verdict(&more, "C2"), Verdict::Contradicted);
    // Identical per seed: the paired difference is 0, inside the 2-step margin, and the
    // return's inside the 2-reward margin.
    let same = scores(100.0, 100.0);
    assert_eq!(verdict(&same, "C1"), Verdict::Equivalent);
    assert_eq!(verdict(&same, "C2"), Verdict::Equivalent);
    // The deciding comparison of a contradicted claim favours the competitor.
    let judgement = claims::judge(&more, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C1")
        .unwrap();
    let deciding = judgement.deciding_comparison().unwrap();
    assert_eq!(deciding.outcome, ComparisonOutcome::FavoursCompetitor);
    assert!(deciding.paired.low.unwrap() > 2.0, "{deciding:?}");
    assert!(deciding.p_holm < 0.05);
}

/// Ten seeds of EA-MADM that reach in every greedy evaluation (greedy SD 3 + seed/10, a
/// training-curve SD of 30) against a softmax stuck at the step cap on `stuck` of its seeds
/// (no greedy SD there, a flat training curve: SD 0) and stable-reaching on the others.
fn stuck_competitor(stuck: u64) -> Vec<FinalScore> {
    let mut rows = scores(100.0, 100.0);
    for row in &mut rows {
        let sd = 3.0 + row.seed as f64 / 10.0;
        if row.method == "softmax" && row.seed < stuck {
            row.stable_reaching = Some(false);
            row.fluctuation_greedy_steps = None;
            row.fluctuation_greedy_return = None;
            row.fluctuation_steps = 0.0;
            row.fluctuation_return = 0.0;
        } else {
            row.fluctuation_greedy_steps = Some(sd);
            row.fluctuation_greedy_return = Some(sd);
            row.fluctuation_steps = 30.0;
            row.fluctuation_return = 30.0;
        }
    }
    rows
}

fn c3(scores: &[FinalScore]) -> claims::Judgement {
    claims::judge(scores, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C3" && j.method == "ea-madm")
        .unwrap()
}

#[test]
fn c3_counts_a_seed_stuck_at_the_cap_as_a_failure_not_as_stability() {
    // Stuck on every seed: the training-curve SD (secondary) favours softmax, but it has no
    // stable-reaching seed, so the paired sign test on stable-reaching decides for EA-MADM.
    let judgement = c3(&stuck_competitor(10));
    assert_eq!(judgement.verdict, Verdict::Supported, "{judgement:?}");
    assert!(judgement.comparisons.is_empty());
    let test = &judgement.reaching[0];
    assert_eq!(test.metric, claims::STABLE_REACHING);
    assert_eq!((test.reached, test.discordant), ((10, 0), (10, 0)));
    assert_eq!(test.outcome, ComparisonOutcome::FavoursMethod);
    assert!(
        judgement
            .reason
            .contains("reaches in every greedy evaluation of the second half on 10/10 seeds"),
        "{}",
        judgement.reason
    );
    let secondary = &judgement.secondary;
    assert_eq!(secondary.len(), 2);
    // The training curves say the opposite (softmax's SD is 0 on every seed), and do not
    // decide.
    assert!(
        secondary
            .iter()
            .all(|c| c.paired.estimate == 30.0 && c.outcome != ComparisonOutcome::FavoursMethod),
        "{secondary:?}"
    );
    // claims.csv: the stable-reaching row carries the verdict, the secondary rows do not.
    let rows = claims::rows(
        std::slice::from_ref(&judgement),
        &claims::estimates(&stuck_competitor(10), &options()).unwrap(),
    );
    let stable: Vec<_> = rows
        .iter()
        .filter(|r| r.metric == claims::STABLE_REACHING)
        .collect();
    assert_eq!(stable.len(), 1);
    assert_eq!(stable[0].estimate, Some(1.0));
    assert_eq!(stable[0].verdict, Some(Verdict::Supported));
    for row in rows.iter().filter(|r| r.metric == "fluctuation_steps") {
        assert_eq!(row.verdict, None, "{row:?}");
    }
    // Stuck on 3 seeds only: 3 discordant seeds cannot reach p < 0.05, and on the 7 paired
    // stable seeds the greedy SDs are equal (equivalent within their margins): nothing
    // favours either side, but 3 seeds stable-reach on one side only, so it is not
    // equivalent either (the per-seed test has no margin).
    let judgement = c3(&stuck_competitor(3));
    assert_eq!(judgement.verdict, Verdict::Inconclusive, "{judgement:?}");
    assert!(
        judgement
            .comparisons
            .iter()
            .all(|c| c.paired.p_equivalence_holm.unwrap() < 0.05),
        "{judgement:?}"
    );
    // Stuck nowhere: the same seeds stable-reach and the greedy SDs are equal: equivalent.
    assert_eq!(c3(&stuck_competitor(0)).verdict, Verdict::Equivalent);
    assert_eq!(judgement.reaching[0].discordant, (3, 0));
    assert!(judgement.comparisons.iter().all(|c| c.n == (10, 7)));
    // The other way round: EA-MADM stuck on every seed is contradicted, not "most stable".
    let flipped: Vec<FinalScore> = stuck_competitor(10)
        .into_iter()
        .map(|mut row| {
            row.method = if row.method == "softmax" {
                "ea-madm"
            } else {
                "softmax"
            }
            .to_owned();
            (row.role, row.kind) = if row.method == "softmax" {
                (Role::Paper, "softmax".to_owned())
            } else {
                (Role::Paper, "ea_madm".to_owned())
            };
            row
        })
        .collect();
    let judgement = c3(&flipped);
    assert_eq!(judgement.verdict, Verdict::Contradicted, "{judgement:?}");
    assert_eq!(judgement.reaching[0].discordant, (0, 10));
}

#[test]
fn c3_combines_the_two_tests_and_conflicts_settle_nothing() {
    use ComparisonOutcome::{FavoursCompetitor as Y, FavoursMethod as X, Unsettled as U};
    assert_eq!(claims::combine(X, U), X);
    assert_eq!(claims::combine(U, Y), Y);
    assert_eq!(claims::combine(X, X), X);
    assert_eq!(claims::combine(U, U), U);
    assert_eq!(claims::combine(X, Y), U);
    assert_eq!(claims::combine(Y, X), U);
}

#[test]
fn equivalence_needs_the_paired_difference_inside_the_margin() {
    // 1.5 steps fewer on every seed: within the 2-step margin, so equivalent, never "favours".
    let within = scores(100.0, 101.5);
    assert_eq!(verdict(&within, "C1"), Verdict::Equivalent);
    let judgement = claims::judge(&within, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C1")
        .unwrap();
    assert_eq!(judgement.comparisons[0].margin, Some(2.0));
    let paired = &judgement.comparisons[0].paired;
    assert_eq!(paired.n, 10);
    assert_eq!(paired.estimate, -1.5);
    assert_eq!((paired.low, paired.high), (Some(-1.5), Some(-1.5)));
    // All ten shifted differences share one sign: 1 of the 2^10 sign vectors is as extreme on
    // each side, and the within-margin p doubles the larger one-sided p (the 95 % interval
    // inside the margin).
    assert_eq!(paired.p_equivalence, Some(2.0 / 1024.0));
    // 3 steps fewer on every seed: beyond the margin, so not equivalent; paired by seed the
    // spread of the seeds cancels, and every difference is −3: supported (issue 34: the
    // unpaired IQM difference, not significant with these spread-out seeds, decided before).
    let beyond = scores(100.0, 103.0);
    assert_eq!(verdict(&beyond, "C1"), Verdict::Supported);
}

#[test]
fn a_return_metric_is_judged_equivalent_within_its_margin_on_its_task() {
    // 1.5 reward more on every seed (the rows' return is −steps): within Task II's 2-reward
    // return margin, so C2 is equivalent, as C1 is on the steps.
    let within = scores(100.0, 101.5);
    assert_eq!(verdict(&within, "C2"), Verdict::Equivalent);
    let c2 = claims::judge(&within, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C2")
        .unwrap();
    let comparison = &c2.comparisons[0];
    assert_eq!(comparison.metric.column, "final_return");
    assert_eq!(comparison.margin, Some(2.0));
    assert_eq!(comparison.outcome, ComparisonOutcome::Unsettled);
    let paired = &comparison.paired;
    assert_eq!(paired.estimate, 1.5);
    assert_eq!(paired.p_equivalence, Some(2.0 / 1024.0));
    // The same scores with margins for Task I only: Task II's return has none, so C2 cannot
    // be equivalent, and the row says so with a blank margin; without a margin any difference
    // beyond 0 counts, and 1.5 reward more on every seed is.
    let elsewhere = ClaimOptions {
        margins: crate::margins::maze_margins(&["task1"]),
        ..options()
    };
    let c2 = claims::judge(&within, &elsewhere)
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C2")
        .unwrap();
    assert_eq!(c2.verdict, Verdict::Supported);
    assert_eq!(c2.comparisons[0].margin, None);
    assert_eq!(c2.comparisons[0].paired.p_equivalence, None);
    // 3 reward more on every seed: beyond the margin, never equivalent.
    assert_ne!(verdict(&scores(100.0, 103.0), "C2"), Verdict::Equivalent);
}

#[test]
fn an_effect_within_the_margin_never_favours_a_side() {
    // Every seed 1.5 steps fewer: the paired difference is significantly not 0 and its
    // interval excludes 0, but it lies within the 2-step margin, so it settles nothing.
    let tight: Vec<FinalScore> = scores(100.0, 101.5)
        .into_iter()
        .map(|mut r| {
            let level = if r.method == "ea-madm" { 100.0 } else { 101.5 };
            r.final_steps = level + (r.seed % 2) as f64 * 0.01;
            r
        })
        .collect();
    let c1 = claims::judge(&tight, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C1")
        .unwrap();
    let comparison = &c1.comparisons[0];
    assert!(comparison.paired.p_value < 0.05 && comparison.paired.high.unwrap() < 0.0);
    assert!(comparison.p_holm >= 0.05 && !comparison.paired.lies_beyond(Some(2.0)));
    assert_eq!(comparison.outcome, ComparisonOutcome::Unsettled);
    assert_eq!(c1.verdict, Verdict::Equivalent);
    // Without a margin the same comparison favours EA-MADM.
    let none = ClaimOptions {
        margins: claims::Margins::new(),
        ..options()
    };
    let c1 = claims::judge(&tight, &none)
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C1")
        .unwrap();
    assert_eq!(c1.comparisons[0].outcome, ComparisonOutcome::FavoursMethod);
    assert_eq!(c1.verdict, Verdict::Supported);
}

#[test]
fn margins_are_per_task_and_column_and_refuse_bad_values() {
    let margins = crate::margins::maze_margins(&["task1"]);
    assert_eq!(margins.value("task1", "final_return"), Some(2.0));
    assert_eq!(margins.value("task2", "final_return"), None);
    assert_eq!(margins.value("task1", "reach_time"), None);
    // A later margin of the same task and column replaces the earlier one.
    let mut replaced = margins.clone();
    let wider = claims::Margin {
        column: "final_return".to_owned(),
        value: 5.0,
        reason: "wider".to_owned(),
    };
    replaced
        .insert("task1", std::slice::from_ref(&wider))
        .unwrap();
    assert_eq!(replaced.value("task1", "final_return"), Some(5.0));
    assert_eq!(replaced.iter().count(), margins.iter().count());
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let error = replaced
            .insert(
                "task1",
                &[claims::Margin {
                    value: bad,
                    ..wider.clone()
                }],
            )
            .unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains("task1") && text.contains("final_return"),
            "{text}"
        );
    }
}

#[test]
fn claims_on_other_tasks_and_without_competitors_are_not_judged_or_untestable() {
    let judgements = claims::judge(&scores(100.0, 1500.0), &options()).unwrap();
    // Task II carries C1–C3; C4 is the robot's.
    let ids: Vec<&str> = judgements.iter().map(|j| j.claim.id).collect();
    assert_eq!(ids, ["C1", "C2", "C3"]);
    let alone: Vec<FinalScore> = scores(100.0, 1500.0)
        .into_iter()
        .filter(|s| s.method == "ea-madm")
        .collect();
    let judgement = &claims::judge(&alone, &options()).unwrap()[0];
    assert_eq!(judgement.verdict, Verdict::Untestable);
    assert_eq!(judgement.reason, "none of the paper's competitors was run");
}

#[test]
fn judgements_are_bit_identical_with_one_and_two_threads() {
    let rows = scores(300.0, 320.0);
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                (
                    claims::judge(&rows, &options()).unwrap(),
                    claims::estimates(&rows, &options()).unwrap(),
                )
            })
    };
    assert_eq!(on(1), on(2));
}

#[test]
fn outcome_rows_count_seeds_and_pair_them() {
    use eamadm_eval::scores::RunOutcome;
    let mut rows = scores(100.0, 100.0);
    for row in &mut rows {
        let collapsed = row.method == "ea-madm" && row.seed >= 7;
        row.outcome = if collapsed {
            RunOutcome::Collapsed
        } else {
            RunOutcome::Converged
        };
    }
    let out = claims::outcome_rows(&rows).unwrap();
    let share = out
        .iter()
        .find(|r| r.method == "ea-madm" && r.versus.is_empty())
        .unwrap();
    assert_eq!(share.estimate, Some(0.7));
    assert!(share.ci_low.unwrap() < 0.7 && 0.7 < share.ci_high.unwrap());
    let paired = out
        .iter()
        .find(|r| r.method == "ea-madm" && r.versus == "softmax")
        .unwrap();
    // Three seeds only softmax converged on, none the other way: (0 − 3) / 10, p = 2 / 2³.
    assert_eq!(paired.estimate, Some(-0.3));
    assert!((paired.p_value.unwrap() - 0.25).abs() < 1e-12);
    assert_eq!(paired.n, 10);
}

/// A robot run: it reaches the target when `reaches` (then with C4 values that grow with the
/// seed), and never otherwise (no reaching episode, greedy episode fails, empty C4 cells).
fn robot_row(method: &str, kind: &str, seed: u64, reaches: bool) -> FinalScore {
    let value = reaches.then_some(1.0 + seed as f64);
    FinalScore {
        task: "robot".to_owned(),
        greedy_reached: reaches,
        reaching_episodes: if reaches { 10 } else { 0 },
        reach_average_reward: value,
        reach_time: value,
        reach_retention_time: value,
        retention_decay: value.map(|v| -v),
        ..row(method, Role::Paper, kind, seed, 500.0)
    }
}

/// 20 seeds each: EA-MADM reaches on the seeds below `ea`, softmax below `softmax`,
/// ε-greedy below `greedy`.
fn robot(ea: u64, softmax: u64, greedy: u64) -> Vec<FinalScore> {
    let mut rows = Vec::new();
    for (method, kind, reaching) in [
        ("ea-madm", "ea_madm", ea),
        ("softmax", "softmax", softmax),
        ("epsilon-greedy", "epsilon_greedy", greedy),
    ] {
        rows.extend((0..20).map(|seed| robot_row(method, kind, seed, seed < reaching)));
    }
    rows
}

fn c4(scores: &[FinalScore]) -> claims::Judgement {
    claims::judge(scores, &options())
        .unwrap()
        .into_iter()
        .find(|j| j.claim.id == "C4" && j.method == "ea-madm")
        .unwrap()
}

#[test]
fn a_method_that_never_reaches_while_a_competitor_does_is_contradicted_by_a_sign_test() {
    let judgement = c4(&robot(0, 11, 3));
    assert_eq!(judgement.verdict, Verdict::Contradicted);
    assert!(judgement.comparisons.is_empty());
    // scipy.stats.binomtest(0, 11, 0.5).pvalue = 0.0009765625 (= 2 / 2¹¹) and
    // binomtest(0, 3, 0.5).pvalue = 0.25; Holm over the two competitors doubles the smaller.
    let softmax = &judgement.reaching[0];
    assert_eq!(softmax.versus, "softmax");
    assert_eq!(
        (softmax.n, softmax.reached, softmax.discordant),
        (20, (0, 11), (0, 11))
    );
    assert!((softmax.p_value - 0.000_976_562_5).abs() < 1e-15);
    assert!((softmax.p_holm - 0.001_953_125).abs() < 1e-15);
    let greedy = &judgement.reaching[1];
    assert_eq!((greedy.reached, greedy.discordant), ((0, 3), (0, 3)));
    assert!((greedy.p_value - 0.25).abs() < 1e-15);
    assert!((greedy.p_holm - 0.25).abs() < 1e-15);
    assert_eq!(softmax.outcome, ComparisonOutcome::FavoursCompetitor);
    assert_eq!(greedy.outcome, ComparisonOutcome::Unsettled);
    // claims.csv carries each reaching test as a `reached` row with the verdict.
    let rows = claims::rows(std::slice::from_ref(&judgement), &[]);
    let reached: Vec<_> = rows
        .iter()
        .filter(|r| r.metric == claims::REACHED)
        .collect();
    assert_eq!(reached.len(), 2);
    assert_eq!(reached[0].versus, "softmax");
    assert_eq!(reached[0].estimate, Some(-0.55));
    assert_eq!(reached[0].p_holm, Some(softmax.p_holm));
    assert_eq!(reached[0].verdict, Some(Verdict::Contradicted));
    assert!(
        judgement
            .reason
            .starts_with("EA-MADM reaches on 0/20 seeds, softmax on 11/20; exact paired sign test, Holm p 0.002; EA-MADM has a `reach_average_reward` value in 0 of 20 seeds"),
        "{}",
        judgement.reason
    );
}

#[test]
fn a_competitor_reaching_on_a_few_seeds_more_is_inconclusive() {
    // binomtest(0, 3, 0.5).pvalue = 0.25 for softmax; ε-greedy reaches on 1 seed.
    let judgement = c4(&robot(0, 3, 1));
    assert_eq!(judgement.verdict, Verdict::Inconclusive);
    assert!(
        judgement.reason.starts_with(
            "EA-MADM reaches on 0/20 seeds, softmax on 3/20; exact paired sign test, Holm p 0.500"
        ),
        "{}",
        judgement.reason
    );
}

#[test]
fn when_neither_reaches_c4_stays_untestable_with_the_counts() {
    let judgement = c4(&robot(0, 1, 0));
    assert_eq!(judgement.verdict, Verdict::Untestable);
    assert_eq!(
        judgement.reason,
        "EA-MADM has a `reach_average_reward` value in 0 of 20 seeds (it needs a reaching \
         episode), and no competitor reaches on 2 or more seeds: EA-MADM reaches on 0/20, \
         softmax 1/20, ε-greedy 0/20"
    );
    // The counts are in claims.csv too, Holm-adjusted: binomtest(0, 1, 0.5).pvalue = 1.
    assert_eq!(judgement.reaching.len(), 2);
    assert!(judgement.reaching.iter().all(|t| t.p_holm == 1.0));
    assert_eq!(judgement.reaching[0].discordant, (0, 1));
}

#[test]
fn when_both_reach_c4_compares_the_metrics_as_before() {
    let judgement = c4(&robot(20, 20, 20));
    assert!(judgement.reaching.is_empty());
    // 3 metrics × 2 competitors, identical values: nothing favours anyone.
    assert_eq!(judgement.comparisons.len(), 6);
    assert_eq!(judgement.verdict, Verdict::Inconclusive);
    assert!(judgement.deciding_comparison().is_some());
}

/// The robot with the repaired reading `ea-madm-repaired` (role ablation) and its reward-matched
/// competitors `softmax-shaped-repaired` and `epsilon-greedy-shaped-repaired` (role control),
/// 20 seeds each: the reading reaches below `repaired`, the matched competitors below
/// `matched`; EA-MADM never, softmax below 11, ε-greedy below 3.
fn robot_with_repaired(repaired: u64, matched: u64) -> Vec<FinalScore> {
    let mut rows = robot(0, 11, 3);
    for (method, role, kind, reaching) in [
        ("ea-madm-repaired", Role::Ablation, "ea_madm", repaired),
        ("softmax-shaped-repaired", Role::Control, "softmax", matched),
        (
            "epsilon-greedy-shaped-repaired",
            Role::Control,
            "epsilon_greedy",
            matched,
        ),
        // A budget control of softmax: never in a set of a reading.
        ("softmax-budget", Role::Control, "softmax", 20),
    ] {
        rows.extend((0..20).map(|seed| FinalScore {
            role,
            ..robot_row(method, kind, seed, seed < reaching)
        }));
    }
    rows
}

fn c4_of(judgements: &[claims::Judgement], method: &str, set: VersusSet) -> claims::Judgement {
    judgements
        .iter()
        .find(|j| j.claim.id == "C4" && j.method == method && j.versus_set == set)
        .unwrap()
        .clone()
}

#[test]
fn a_repaired_reading_is_judged_against_the_paper_competitors_and_those_on_its_rewards() {
    let scores = robot_with_repaired(0, 0);
    let judgements = claims::judge(&scores, &options()).unwrap();
    // The paper's EA-MADM has one judgement (the headline), the reading two, paper set first.
    let sets = |method: &str| -> Vec<VersusSet> {
        judgements
            .iter()
            .filter(|j| j.method == method)
            .map(|j| j.versus_set)
            .collect()
    };
    assert_eq!(sets("ea-madm"), [VersusSet::Paper]);
    assert_eq!(
        sets("ea-madm-repaired"),
        [VersusSet::Paper, VersusSet::SameRewards]
    );
    assert_eq!(
        claims::competitors_in(&scores, "robot", "ea-madm-repaired", VersusSet::Paper),
        ["softmax", "epsilon-greedy"]
    );
    assert_eq!(
        claims::competitors_in(&scores, "robot", "ea-madm-repaired", VersusSet::SameRewards),
        ["softmax-shaped-repaired", "epsilon-greedy-shaped-repaired"]
    );
    // Against the paper's competitors the reading is contradicted (softmax 11/20), against
    // those on its own rewards untestable: neither side reaches, and the reason says which
    // competitors and why.
    let paper = c4_of(&judgements, "ea-madm-repaired", VersusSet::Paper);
    assert_eq!(paper.verdict, Verdict::Contradicted);
    let same = c4_of(&judgements, "ea-madm-repaired", VersusSet::SameRewards);
    assert_eq!(same.verdict, Verdict::Untestable);
    assert_eq!(
        same.reaching
            .iter()
            .map(|t| t.versus.as_str())
            .collect::<Vec<_>>(),
        ["softmax-shaped-repaired", "epsilon-greedy-shaped-repaired"]
    );
    assert!(
        same.reason.starts_with(
            "against the competitors trained on the sub-task rewards with both repairs: "
        ) && same.reason.ends_with(
            "ea-madm-repaired reaches on 0/20, softmax-shaped-repaired 0/20, \
             epsilon-greedy-shaped-repaired 0/20"
        ),
        "{}",
        same.reason
    );
    // claims.csv says which set each row judges against; the single-method rows carry the
    // headline (paper) verdict.
    let rows = claims::rows(
        &judgements,
        &claims::estimates(&scores, &options()).unwrap(),
    );
    let of = |versus: &str| {
        rows.iter()
            .find(|r| r.method == "ea-madm-repaired" && r.versus == versus)
            .unwrap()
    };
    assert_eq!(of("softmax").versus_set, "paper");
    assert_eq!(of("softmax").verdict, Some(Verdict::Contradicted));
    assert_eq!(of("softmax-shaped-repaired").versus_set, "same_rewards");
    assert_eq!(
        of("softmax-shaped-repaired").verdict,
        Some(Verdict::Untestable)
    );
    assert_eq!(of("").versus_set, "paper");
    assert_eq!(of("").verdict, Some(Verdict::Contradicted));
    let competitor_row = rows.iter().find(|r| r.method == "softmax").unwrap();
    assert_eq!(competitor_row.versus_set, "");
}

#[test]
fn a_reading_that_never_reaches_while_its_matched_competitors_do_is_contradicted() {
    let judgements = claims::judge(&robot_with_repaired(0, 12), &options()).unwrap();
    let same = c4_of(&judgements, "ea-madm-repaired", VersusSet::SameRewards);
    assert_eq!(same.verdict, Verdict::Contradicted);
    // binomtest(0, 12, 0.5).pvalue = 2 / 2¹², Holm over the two matched competitors.
    assert!((same.reaching[0].p_holm - 2.0 * 2.0 / 4096.0).abs() < 1e-15);
    // The reading reaching as often as its matched competitors compares the metrics.
    let judgements = claims::judge(&robot_with_repaired(20, 20), &options()).unwrap();
    let same = c4_of(&judgements, "ea-madm-repaired", VersusSet::SameRewards);
    assert!(same.reaching.is_empty());
    assert_eq!(same.comparisons.len(), 6);
    assert!(
        same.comparisons
            .iter()
            .all(|c| c.versus.ends_with("-shaped-repaired"))
    );
}

#[test]
fn a_reading_whose_matched_competitors_were_not_run_is_untestable_with_the_reason() {
    let mut scores = robot_with_repaired(0, 0);
    scores.retain(|row| !row.method.ends_with("-shaped-repaired"));
    let judgements = claims::judge(&scores, &options()).unwrap();
    let same = c4_of(&judgements, "ea-madm-repaired", VersusSet::SameRewards);
    assert_eq!(same.verdict, Verdict::Untestable);
    assert_eq!(
        same.reason,
        "against the competitors trained on the sub-task rewards with both repairs: none of \
         them (`COMPETITOR-shaped-repaired`) was run"
    );
    // Every reading of SAME_REWARDS has two sets; any other EA-MADM method only the paper's.
    for entry in &claims::SAME_REWARDS {
        assert_eq!(
            claims::versus_sets(entry.method),
            [VersusSet::Paper, VersusSet::SameRewards]
        );
    }
    assert_eq!(claims::versus_sets("ea-madm-table"), [VersusSet::Paper]);
}
