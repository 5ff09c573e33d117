//! The findings (`findings.json`): what the report states follows the numbers and the
//! methods' configs, never their labels, and reads back from JSON unchanged.

use eamadm_eval::Role;
use eamadm_eval::claims::{ClaimOptions, Margin, Margins, Verdict, claim_columns};
use eamadm_eval::facts::{
    ControlFamily, ExperimentFacts, Figures, MethodFacts, PaperFigures, PredictionFacts,
    ReportContext, RewardReference, SubtaskReference,
};
use eamadm_eval::findings::{
    AggregatorFinding, Cause, Deciding, Estimand, FINDINGS_FORMAT, Findings, Rejudgement,
    SeedCount, Test,
};
use eamadm_eval::oracle::{FailingPart, OracleFinding, OracleValues, PretrainingSummary};
use eamadm_eval::scores::{FinalScore, RunOutcome};
use eamadm_eval::sensitivity::{Change, SensitivityRow};
use eamadm_eval::stats::{Bootstrap, SignFlipTest};
use eamadm_eval::verdicts::Verdicts;

fn row(method: &str, role: Role, kind: &str, seed: u64, steps: f64) -> FinalScore {
    FinalScore {
        task: "task1".to_owned(),
        layout: String::new(),
        method: method.to_owned(),
        role,
        kind: kind.to_owned(),
        seed,
        episodes: 200,
        final_window: 20,
        final_steps: steps,
        final_return: -steps,
        success_rate: 1.0,
        greedy_reached: true,
        greedy_steps: 80,
        outcome: RunOutcome::Converged,
        collapse_episode: None,
        fluctuation_steps: steps / 10.0,
        fluctuation_return: steps / 10.0,
        greedy_evaluations: 10,
        stable_reaching: Some(true),
        fluctuation_greedy_steps: Some(steps / 10.0),
        fluctuation_greedy_return: Some(steps / 10.0),
        env_steps_total: 10_000,
        pretrain_env_steps: 0,
        step_cap: 2000,
        optimum_steps: Some(58),
        reaching_episodes: 100,
        reach_average_reward: None,
        reach_time: None,
        reach_retention_time: None,
        retention_decay: None,
    }
}

fn facts(label: &str, role: Role, kind: &str, control: Option<ControlFamily>) -> MethodFacts {
    MethodFacts {
        label: label.to_owned(),
        role,
        kind: kind.to_owned(),
        control,
        tree_threshold: None,
    }
}

/// The methods of [`scores`] by their configs; the controls' labels say nothing of what they
/// are (`shaped-by-label` is no reward-matched control: its config says so).
fn methods() -> Vec<MethodFacts> {
    let alone = ControlFamily::SubtaskAlone {
        subtask: 0,
        learns: false,
    };
    vec![
        facts("ea-madm", Role::Paper, "ea_madm", None),
        facts("epsilon-greedy", Role::Paper, "epsilon_greedy", None),
        facts("softmax", Role::Paper, "softmax", None),
        facts("lonely", Role::Control, "subtask_greedy", Some(alone)),
        facts(
            "matched",
            Role::Control,
            "softmax",
            Some(ControlFamily::RewardMatched),
        ),
        facts("softmax-shaped", Role::Control, "softmax", None),
        facts("ea-madm-table", Role::Ablation, "ea_madm", None),
    ]
}

fn context(reward_references: Vec<RewardReference>) -> ReportContext {
    ReportContext {
        quick: false,
        paper_tasks: Vec::new(),
        preset_seeds: 8,
        action_names: Vec::new(),
        curves_file: String::new(),
        trajectories_file: String::new(),
        experiments: vec![ExperimentFacts {
            name: "task1".to_owned(),
            title: "Task I".to_owned(),
            episodes: 200,
            seeds: 8,
            gamma: 0.95,
            figures: Figures::default(),
            behaviour: Vec::new(),
            reward_references,
            final_epsilon: Vec::new(),
            margins: Vec::new(),
            methods: methods(),
            paper_figures: PaperFigures::default(),
            base_seed: 0,
            tables_written: false,
        }],
        readings: Vec::new(),
        oracle: Vec::new(),
        pretraining: Vec::new(),
        predictions: Vec::new(),
        deviations: Vec::new(),
    }
}

fn options() -> ClaimOptions {
    let mut margins = Margins::new();
    let table: Vec<Margin> = claim_columns()
        .into_iter()
        .filter(|c| c.contains("steps") || c.contains("return"))
        .map(|column| Margin {
            column: column.to_owned(),
            value: 2.0,
            reason: "the shortest detour".to_owned(),
        })
        .collect();
    margins.insert("task1", &table).unwrap();
    ClaimOptions {
        bootstrap: Bootstrap::new(2000, 0.95, 0).unwrap(),
        sign_flip: SignFlipTest::new(2000, 0).unwrap(),
        alpha: 0.05,
        margins,
    }
}

/// EA-MADM at `ea` steps (collapsing on `collapses`), two competitors at 100, the sub-task
/// alone as EA-MADM, the reward-matched control at `matched`, a control labelled like one at
/// 1 step, and the table ablation as EA-MADM; each plus the seed.
fn scores(ea: f64, collapses: &[u64], matched: f64) -> Vec<FinalScore> {
    let mut rows = Vec::new();
    for (method, kind, role, base) in [
        ("ea-madm", "ea_madm", Role::Paper, ea),
        ("epsilon-greedy", "epsilon_greedy", Role::Paper, 100.0),
        ("softmax", "softmax", Role::Paper, 100.0),
        ("lonely", "subtask_greedy", Role::Control, ea),
        ("matched", "softmax", Role::Control, matched),
        ("softmax-shaped", "softmax", Role::Control, 1.0),
        ("ea-madm-table", "ea_madm", Role::Ablation, ea),
    ] {
        for seed in 0..8 {
            let mut r = row(method, role, kind, seed, base + seed as f64);
            if kind == "ea_madm" && collapses.contains(&seed) {
                r.outcome = RunOutcome::Collapsed;
                r.collapse_episode = Some(60 + seed);
                r.greedy_reached = false;
                r.final_steps = 2000.0;
                r.final_return = -2000.0;
            }
            rows.push(r);
        }
    }
    rows
}

fn findings_of(scores: Vec<FinalScore>, context: &ReportContext) -> Findings {
    let verdicts = Verdicts::compute(scores, &options(), context).unwrap();
    Findings::of(context, &verdicts)
}

fn verdicts(findings: &Findings) -> Vec<(String, Verdict)> {
    findings.tasks[0]
        .verdicts
        .iter()
        .map(|v| (v.claim.clone(), v.verdict))
        .collect()
}

#[test]
fn the_verdicts_follow_the_numbers_with_their_deciding_comparison() {
    let claims = |v: Verdict| ["C1", "C2", "C3"].map(|c| (c.to_owned(), v)).to_vec();
    let better = findings_of(scores(60.0, &[], 150.0), &context(Vec::new()));
    assert_eq!(verdicts(&better), claims(Verdict::Supported));
    let task = &better.tasks[0];
    assert_eq!(
        (task.task.as_str(), task.method.as_str()),
        ("task1", "ea-madm")
    );
    assert_eq!(task.converged, SeedCount { hits: 8, seeds: 8 });
    // The deciding comparison describes itself: the mean paired difference with its exact
    // sign-flip interval and the Holm p that it lies beyond the margin, against a competitor
    // (issue 34: one estimand decides every comparison).
    let deciding = task.verdicts[0].deciding.as_ref().unwrap();
    assert_eq!(deciding.estimand, Estimand::PairedMeanDifference);
    assert_eq!(deciding.test, Test::SignFlipBeyondMargin);
    assert_eq!(deciding.metric, "final_steps");
    assert_eq!(deciding.estimate, -40.0);
    assert_eq!(deciding.interval, Some([-40.0, -40.0]));
    assert_eq!((deciding.margin, deciding.pairs), (Some(2.0), Some(8)));
    // Every difference is −40: of the 2⁸ sign vectors, one lies beyond −2 and one beyond +2,
    // so p = 2/256, Holm over the two competitors 4/256.
    assert_eq!(deciding.p_holm, 4.0 / 256.0);
    let worse = findings_of(scores(140.0, &[], 150.0), &context(Vec::new()));
    assert_eq!(verdicts(&worse)[0].1, Verdict::Contradicted);
    // Equal seed for seed: equivalent within the margins, decided by the same paired
    // difference and the p that it lies within the margin.
    let same = findings_of(scores(100.0, &[], 150.0), &context(Vec::new()));
    assert_eq!(verdicts(&same)[0].1, Verdict::Equivalent);
    let deciding: &Deciding = same.tasks[0].verdicts[0].deciding.as_ref().unwrap();
    assert_eq!(
        (deciding.estimand, deciding.test, deciding.margin),
        (
            Estimand::PairedMeanDifference,
            Test::SignFlipWithinMargin,
            Some(2.0)
        )
    );
    assert_eq!(deciding.interval, Some([0.0, 0.0]));
}

/// A control is the strongest by what its config says it is, never by its label: the
/// control labelled `softmax-shaped` (far better, but no family) is never the strongest.
#[test]
fn the_strongest_control_comes_from_the_configs_and_can_overturn_a_verdict() {
    let findings = findings_of(scores(60.0, &[], 10.0), &context(Vec::new()));
    let task = &findings.tasks[0];
    assert!(task.strongest.iter().all(|s| s.control == "matched"));
    let c1 = &task.strongest[0];
    assert_eq!(c1.family, ControlFamily::RewardMatched);
    assert_eq!(c1.verdict, Verdict::Contradicted);
    assert!(c1.overturns);
    assert_eq!(c1.converged, SeedCount { hits: 8, seeds: 8 });
    assert_eq!(
        task.cause,
        Some(Cause::MatchedControl {
            control: "matched".to_owned(),
            family: ControlFamily::RewardMatched,
            claims: vec!["C1".to_owned(), "C2".to_owned(), "C3".to_owned()],
            verdict: Verdict::Contradicted,
        })
    );
    // Without the methods' configs no control is known: no strongest, no cause.
    let mut unknown = context(Vec::new());
    unknown.experiments[0].methods.clear();
    let findings = findings_of(scores(60.0, &[], 10.0), &unknown);
    assert!(findings.tasks[0].strongest.is_empty());
    assert_eq!(findings.tasks[0].cause, None);
}

/// Where the sub-task alone (EA-MADM without the MADM step) is not shown worse, that is the
/// cause; with the seeds it ends exactly as EA-MADM.
#[test]
fn a_sub_task_alone_as_good_as_ea_madm_is_the_cause() {
    let findings = findings_of(scores(60.0, &[], 150.0), &context(Vec::new()));
    let task = &findings.tasks[0];
    assert!(task.strongest.iter().any(|s| s.control == "lonely"));
    let Some(Cause::SubtaskAlone {
        control,
        better,
        end_same,
        ..
    }) = &task.cause
    else {
        panic!("{:?}", task.cause);
    };
    assert_eq!((control.as_str(), *better), ("lonely", false));
    assert_eq!(*end_same, Some(SeedCount { hits: 8, seeds: 8 }));
    // The pairing on converging is with the strongest frozen sub-task alone, by config.
    let pairing = task.subtask_pairing.as_ref().unwrap();
    assert_eq!((pairing.control.as_str(), pairing.both), ("lonely", 8));
    // The table ablation scores as EA-MADM on every seed.
    assert!(
        task.identical
            .iter()
            .any(|i| i.method == "ea-madm-table" && i.same_as == "ea-madm" && i.seeds == 8)
    );
}

#[test]
fn collapses_are_named_and_judged_again_without_them() {
    // EA-MADM equals the competitors but for the collapsed seed: without it C1 and C2 are
    // equivalent (within the 2-step and 2-reward margins), so the collapse decides them.
    // (7 paired seeds are the fewest that can show equivalence against two competitors: the
    // sign-flip interval's ends are subset means, and Holm's 2 × 2/2ⁿ must fall below 0.05.)
    let findings = findings_of(scores(100.0, &[3], 200.0), &context(Vec::new()));
    let collapses = findings.tasks[0].collapses.as_ref().unwrap();
    assert_eq!(collapses.seeds, [(3, Some(63))]);
    assert_eq!(collapses.of, 8);
    assert_eq!(
        collapses.rejudged[0],
        Rejudgement {
            claim: "C1".to_owned(),
            was: Verdict::Inconclusive,
            now: Verdict::Equivalent,
        }
    );
    assert_eq!(findings.tasks[0].converged, SeedCount { hits: 7, seeds: 8 });
    // Two collapses leave 6 paired seeds: too few to show equivalence, so judged again
    // without them C1 stays inconclusive.
    let findings = findings_of(scores(100.0, &[3, 5], 200.0), &context(Vec::new()));
    let collapses = findings.tasks[0].collapses.as_ref().unwrap();
    assert_eq!(collapses.seeds, [(3, Some(63)), (5, Some(65))]);
    assert!(
        collapses
            .rejudged
            .iter()
            .all(|r| r.claim != "C1" || r.now == Verdict::Inconclusive),
        "{:?}",
        collapses.rejudged
    );
    assert_eq!(findings.tasks[0].converged, SeedCount { hits: 6, seeds: 8 });
    // None collapsed: nothing to say.
    let none = findings_of(scores(60.0, &[], 150.0), &context(Vec::new()));
    assert_eq!(none.tasks[0].collapses, None);
}

#[test]
fn the_readings_say_which_verdicts_flip_under_which_reading() {
    let verdicts =
        Verdicts::compute(scores(60.0, &[], 150.0), &options(), &context(Vec::new())).unwrap();
    let sensitivity_row = |claim: &'static str, reading: &str, change: Change| SensitivityRow {
        claim,
        task: "task1".to_owned(),
        reading: reading.to_owned(),
        method: "ea-madm".to_owned(),
        base_verdict: Verdict::Supported,
        verdict: if change == Change::Holds {
            Verdict::Supported
        } else {
            Verdict::Inconclusive
        },
        change,
        versus: String::new(),
        metric: String::new(),
        statistic: "iqm_difference",
        estimate: None,
        ci_low: None,
        ci_high: None,
        p_holm: None,
    };
    let rows = vec![
        sensitivity_row("C1", "gamma-0.99", Change::Holds),
        sensitivity_row("C1", "pretrain-half", Change::Holds),
        sensitivity_row("C2", "gamma-0.99", Change::Flips),
        sensitivity_row("C2", "pretrain-half", Change::Holds),
    ];
    let verdicts = verdicts.with_sensitivity(rows);
    let findings = Findings::of(&context(Vec::new()), &verdicts);
    let readings = findings.tasks[0].readings.as_ref().unwrap();
    assert_eq!(readings.holds, [("C1".to_owned(), 2)]);
    assert_eq!(
        readings.flips,
        [("C2".to_owned(), vec!["gamma-0.99".to_owned()])]
    );
}

/// A method that never reaches gets the diagnosis of the sub-task rewards it learns from,
/// and that is the cause.
#[test]
fn a_method_that_never_reaches_is_explained_by_its_rewards() {
    let reading = RewardReference {
        repairs: Vec::new(),
        methods: vec!["ea-madm".to_owned()],
        reach_steps: 14,
        step_cap: 250,
        subtasks: [("reach", -4.6), ("view", 20.5)]
            .into_iter()
            .map(|(name, reach)| SubtaskReference {
                name: name.to_owned(),
                reach,
                lose_at_once: -0.8,
                idle: 40.0,
                alone: Vec::new(),
            })
            .collect(),
    };
    let mut rows = scores(250.0, &[], 150.0);
    for r in rows.iter_mut().filter(|r| r.kind == "ea_madm") {
        r.outcome = RunOutcome::NeverReached;
        r.greedy_reached = false;
    }
    let findings = findings_of(rows, &context(vec![reading]));
    let task = &findings.tasks[0];
    let diagnosis = task.never_reaches.as_ref().unwrap();
    assert_eq!(diagnosis.valuing_reaching(), 0);
    assert_eq!(
        task.cause,
        Some(Cause::Rewards {
            diagnosis: diagnosis.clone()
        })
    );
}

#[test]
fn findings_read_back_from_json_and_refuse_another_format() {
    let findings = findings_of(scores(100.0, &[3, 5], 10.0), &context(Vec::new()));
    assert_eq!(findings.format, FINDINGS_FORMAT);
    let json = findings.to_json().unwrap();
    assert!(json.ends_with("}\n"));
    assert_eq!(Findings::from_json(&json).unwrap(), findings);
    let other = json.replacen(
        &format!("\"format\": {FINDINGS_FORMAT}"),
        "\"format\": 999",
        1,
    );
    let error = Findings::from_json(&other).unwrap_err();
    assert!(error.to_string().contains("findings format 999"), "{error}");
}

/// An oracle finding of `decision` on Task I (8 seeds): reaching with exact values on
/// `reaches` seeds, the same episode as the reach sub-task alone on `follows` seeds, at the
/// Manhattan bound when `bound`.
fn oracle(
    decision: &str,
    reaches: u64,
    follows: u64,
    bound: bool,
    part: FailingPart,
) -> OracleFinding {
    OracleFinding {
        task: "task1".to_owned(),
        decision: decision.to_owned(),
        values: OracleValues::Exact,
        seeds: 8,
        optimum_steps: Some(58),
        manhattan_steps: Some(if bound { 58 } else { 24 }),
        at_manhattan_bound: Some(bound),
        reaches_initial: reaches,
        reaches_learned: reaches,
        median_steps_initial: Some(if reaches > 4 { 58.0 } else { 2000.0 }),
        median_steps_learned: Some(58.0),
        optimal_share_initial: Some(0.9),
        optimal_share_learned: Some(0.9),
        best_subtask_alone: Some(("lonely".to_owned(), reaches)),
        equals_subtask_alone: follows,
        runs_converged: Some(8),
        failing_part: part,
    }
}

fn reach_pretraining(method: &str, seeds_reaching: u64) -> PretrainingSummary {
    PretrainingSummary {
        task: "task1".to_owned(),
        method: method.to_owned(),
        subtask: 0,
        name: "reach".to_owned(),
        seeds: 8,
        converged_seeds: Some(0),
        seeds_reaching,
        reaching_episodes: seeds_reaching * 3,
        greedy_alone_reaching: 0,
        mean_episodes: 1000.0,
        mean_env_steps: 8600.0,
    }
}

#[test]
fn the_oracle_names_the_ceiling_at_the_manhattan_bound_and_the_aggregators_are_compared() {
    let mut context = context(Vec::new());
    context.oracle = vec![
        oracle("ea-madm", 8, 8, true, FailingPart::Neither),
        oracle("ea-madm-table", 8, 8, true, FailingPart::Neither),
    ];
    let findings = findings_of(scores(60.0, &[], 150.0), &context);
    let task = &findings.tasks[0];
    // At the bound, with the decision the reach sub-task's episode on every seed, the cause is
    // the ceiling, not the sub-task alone (which the same numbers named before the oracle).
    assert_eq!(
        task.cause,
        Some(Cause::Ceiling {
            optimum_steps: 58,
            follows: "lonely".to_owned(),
            follows_on: SeedCount { hits: 8, seeds: 8 },
            reaches: SeedCount { hits: 8, seeds: 8 },
        })
    );
    assert_eq!(task.oracle.len(), 2);
    // Every decision of the oracle but EA-MADM's is compared with it as a plain aggregator.
    assert_eq!(
        task.aggregators,
        vec![AggregatorFinding {
            method: "ea-madm-table".to_owned(),
            converged: SeedCount { hits: 8, seeds: 8 },
            ends_as_ea_madm: SeedCount { hits: 8, seeds: 8 },
        }]
    );
    // Off the bound, or following the sub-task on fewer than half the seeds: no ceiling.
    for other in [
        oracle("ea-madm", 8, 8, false, FailingPart::Neither),
        oracle("ea-madm", 8, 4, true, FailingPart::Neither),
    ] {
        context.oracle = vec![other];
        let findings = findings_of(scores(60.0, &[], 150.0), &context);
        assert!(
            matches!(findings.tasks[0].cause, Some(Cause::SubtaskAlone { .. })),
            "{:?}",
            findings.tasks[0].cause
        );
    }
    // A reward-matched control that overturns a verdict still comes first (shaping).
    context.oracle = vec![oracle("ea-madm", 8, 8, true, FailingPart::Neither)];
    let shaped = findings_of(scores(60.0, &[], 10.0), &context);
    assert!(matches!(
        shaped.tasks[0].cause,
        Some(Cause::MatchedControl { .. })
    ));
}

#[test]
fn exact_values_that_lead_nowhere_and_pre_training_that_never_reaches_are_causes() {
    let mut rows = scores(250.0, &[], 150.0);
    for r in rows.iter_mut().filter(|r| r.kind == "ea_madm") {
        r.outcome = RunOutcome::NeverReached;
        r.greedy_reached = false;
    }
    let mut context = context(Vec::new());
    // The reach sub-task never reached in pre-training on any seed: pre-training is the cause.
    context.pretraining = vec![reach_pretraining("ea-madm", 0)];
    let findings = findings_of(rows.clone(), &context);
    let Some(Cause::Pretraining { reach, diagnosis }) = &findings.tasks[0].cause else {
        panic!("{:?}", findings.tasks[0].cause);
    };
    assert_eq!((reach.seeds_reaching, reach.seeds), (0, 8));
    assert!(diagnosis.is_none());
    // Once it reaches on a seed, it is not.
    context.pretraining = vec![reach_pretraining("ea-madm", 1)];
    let findings = findings_of(rows.clone(), &context);
    assert!(!matches!(
        findings.tasks[0].cause,
        Some(Cause::Pretraining { .. })
    ));
    // Exact sub-task values with which nothing reaches come before pre-training.
    context.pretraining = vec![reach_pretraining("ea-madm", 0)];
    context.oracle = vec![oracle("ea-madm", 0, 8, false, FailingPart::SubtaskValues)];
    let findings = findings_of(rows, &context);
    assert_eq!(
        findings.tasks[0].cause,
        Some(Cause::SubtaskValues {
            reaches: SeedCount { hits: 0, seeds: 8 },
            follows: "lonely".to_owned(),
            follows_on: SeedCount { hits: 8, seeds: 8 },
            optimum_steps: Some(58),
            manhattan_steps: Some(24),
        })
    );
}

#[test]
fn a_prediction_is_judged_against_the_run() {
    let predicted = PredictionFacts {
        task: "task1".to_owned(),
        notes: "§21.2".to_owned(),
        best_verdict: Verdict::Inconclusive,
        follows: "lonely".to_owned(),
        oracle_reaches: false,
    };
    let mut context = context(Vec::new());
    context.predictions = vec![predicted.clone()];
    context.oracle = vec![oracle("ea-madm", 0, 8, false, FailingPart::SubtaskValues)];
    // EA-MADM beats the competitors (supported) while it ends as the sub-task alone: the
    // verdict part of the prediction fails.
    let findings = findings_of(scores(60.0, &[], 150.0), &context);
    let outcome = findings.tasks[0].prediction.as_ref().unwrap();
    assert_eq!(outcome.best_verdict, Some(Verdict::Supported));
    assert_eq!(outcome.ends_as_followed, SeedCount { hits: 8, seeds: 8 });
    assert_eq!(
        outcome.oracle_reaches,
        Some(SeedCount { hits: 0, seeds: 8 })
    );
    assert!(!outcome.held);
    // EA-MADM worse than the competitors: no verdict better than inconclusive, and the rest
    // holds.
    let findings = findings_of(scores(130.0, &[], 150.0), &context);
    let outcome = findings.tasks[0].prediction.as_ref().unwrap();
    assert!(
        outcome
            .best_verdict
            .is_some_and(|v| eamadm_eval::findings::rank(v) <= 1),
        "{outcome:?}"
    );
    assert!(outcome.held, "{outcome:?}");
    // A decision that reaches with exact values contradicts it.
    context.oracle = vec![oracle("ea-madm", 8, 8, false, FailingPart::Neither)];
    let findings = findings_of(scores(130.0, &[], 150.0), &context);
    assert!(!findings.tasks[0].prediction.as_ref().unwrap().held);
    // The findings read back from JSON with all of it.
    let json = findings.to_json().unwrap();
    assert_eq!(Findings::from_json(&json).unwrap(), findings);
}
