//! The text of `REPORT.md` and of the README's generated blocks. Pure: it returns text and
//! never touches a file; `xtask` (and the Python package) gather the inputs
//! ([`ReportContext`], [`Verdicts`], [`Findings`]) and write.
//!
//! Every statement comes from the [`Findings`] (what the report states, as data, also
//! written as `findings.json`) and every number of a table from [`Verdicts`]; this module only
//! lays them out. The text is a pure function of the scores and the context (no paths, dates
//! or timings), so an interrupted and resumed run writes the same bytes as an uninterrupted
//! one.
//!
//! The report's first screen (its first 50 lines) holds per task the answer, with the one
//! cause the findings name, and every way this reproduction differs from the paper that could
//! change a verdict; then the verdicts, a section per task, the paper's numbers, and an
//! appendix (the rule, the margins, the readings, how the scores are made, the glossary).
//! Tables show a method that scores as an earlier one on every seed once, and the readings'
//! verdicts that hold in one line.
//!
//! | file | what it writes |
//! |---|---|
//! | [`format`](mod@format) | Markdown tables and numbers, intervals, p-values, shares |
//! | `words` | a method's name, a control's family, a deciding comparison in words |
//! | `answer` | the first screen: the answer per task and the deviations from the paper |
//! | `verdicts` | the verdict table, the claims, the ablations' verdicts, the rule |
//! | `at_best` | "each method at its best": the verdicts after the same tuning budget per method |
//! | `strongest` | the strongest control's sentences of a task section |
//! | `outcomes` | how each run ended, the paired tests on converging, the controls' facts |
//! | `task` | per task: scores, controls, comparisons, distributions, explanations, figures |
//! | `robot` | the robot's C4 metrics and its methods' behaviour |
//! | `sensitivity`, `margins`, `glossary` | the appendix's readings, margins and terms |
//! | `paper_numbers` | the paper's numbers beside ours |
//!
//! # Example
//!
//! ```
//! use eamadm_present::report::format::{Align, MarkdownTable};
//!
//! let mut table = MarkdownTable::new([("method", Align::Left), ("final steps", Align::Right)]);
//! table.push_row(["EA-MADM", "80.1 ± 3.5"])?;
//! assert_eq!(
//!     table.render(),
//!     "| method  | final steps |\n| :------ | ----------: |\n| EA-MADM |  80.1 ± 3.5 |\n"
//! );
//! # Ok::<(), eamadm_present::report::format::RowLengthError>(())
//! ```

use std::fmt::Write as _;

use thiserror::Error;

use eamadm_eval::claims::{ClaimOptions, ClaimsError};
pub use eamadm_eval::findings::Findings;
use eamadm_eval::scores::{self, ScoresError};
use eamadm_eval::sensitivity::SensitivityRow;
pub use eamadm_eval::verdicts::{ControlVerdict, SurvivesReadings, Verdicts};

mod answer;
mod at_best;
pub mod format;
mod glossary;
mod margins;
mod oracle;
mod outcomes;
mod paper_numbers;
mod robot;
mod sensitivity;
mod strongest;
mod task;
mod verdicts;
mod words;

pub use answer::readme_answer;
pub use eamadm_eval::facts::{
    ExperimentFacts, Figures, FinalEpsilon, NotDrawn, PaperTaskFacts, Play, ReadingFacts,
    ReportContext, RewardReference, SubtaskReference,
};
pub use verdicts::readme_verdicts;

/// Making the report's text failed.
#[derive(Debug, Error)]
pub enum ReportError {
    /// Writing or reading `final-scores.csv` text.
    #[error("final-scores.csv: {0}")]
    Scores(#[from] ScoresError),
    /// Writing `claims.csv` text or computing a statistic.
    #[error(transparent)]
    Claims(#[from] ClaimsError),
}

/// The one sentence that replaces the figures of `not_drawn` in the report (empty when every
/// figure was drawn), e.g. "Not drawn, since none of EA-MADM, softmax reached the target in
/// any training episode of any seed: average reward over reaching episodes (Fig. 13)."
#[must_use]
pub fn not_drawn_sentence(not_drawn: &[NotDrawn]) -> String {
    let Some(first) = not_drawn.first() else {
        return String::new();
    };
    let whats: Vec<&str> = not_drawn.iter().map(|n| n.what.as_str()).collect();
    format!("Not drawn, since {}: {}.", first.why, whats.join("; "))
}

/// `REPORT.md` of `verdicts` in `context`, stating `findings` (which
/// [`Findings::of`]`(context, verdicts)` computes): the first screen (the answer per task and
/// the deviations from the paper), the verdicts, a section per experiment of `context`, the
/// paper's numbers and the appendix.
#[must_use]
pub fn render(context: &ReportContext, verdicts: &Verdicts, findings: &Findings) -> String {
    let mut text = String::from("# EA-MADM reproduction report\n\n");
    let _ = writeln!(
        text,
        "Made by `cargo xtask reproduce-paper`{}. Do not edit: rerun the command. Per-seed \
         scores: [final-scores.csv](final-scores.csv); every estimate and comparison: \
         [claims.csv](claims.csv); what this report states, as data: \
         [findings.json](findings.json).\n",
        if context.quick {
            " --quick (a smoke run: few seeds and episodes; these numbers mean little)"
        } else {
            ""
        }
    );
    if let Some(answer) = answer::answer(findings) {
        let _ = writeln!(text, "{}\n\n{answer}\n", answer::ANSWER_HEADING);
    }
    if let Some(deviations) = answer::deviations(context, findings) {
        let _ = writeln!(text, "{}\n\n{deviations}", answer::DEVIATIONS_HEADING);
    }
    let titles: Vec<String> = context
        .paper_tasks
        .iter()
        .map(|t| t.title.clone())
        .collect();
    verdicts::write_verdicts(&mut text, &titles, findings);
    at_best::write_at_best(&mut text, findings);
    crate::family::write_family_section(&mut text, findings);
    for experiment in &context.experiments {
        task::write_task(
            &mut text,
            context,
            experiment,
            verdicts,
            findings.task(&experiment.name),
        );
    }
    oracle::write_oracle(&mut text, findings);
    paper_numbers::write_paper_numbers(&mut text, context, verdicts);
    let _ = writeln!(
        text,
        "## Appendix\n\nHow the verdicts are judged, the readings of the paper tried, how \
         the scores are made, and the words this report uses.\n"
    );
    verdicts::write_rule(&mut text, verdicts);
    margins::write_margins(&mut text, context, verdicts);
    sensitivity::write_sensitivity(&mut text, context, &verdicts.sensitivity);
    write_method(&mut text, verdicts);
    glossary::write_glossary(&mut text, verdicts);
    text
}

/// `REPORT.md` and its findings from the text of a run's `final-scores.csv` (and the rows of
/// its `sensitivity.csv`): the verdicts are judged again with `options` (the run's are
/// [`ReportContext::claim_options`]), so with the run's context this is the run's
/// `REPORT.md` byte for byte. What the Python package's `eamadm.report(dir)` calls.
///
/// # Errors
/// [`ReportError`] when the scores cannot be read or a statistic fails.
pub fn render_from_csv(
    context: &ReportContext,
    scores_csv: &str,
    sensitivity: Vec<SensitivityRow>,
    options: &ClaimOptions,
) -> Result<(String, Findings), ReportError> {
    let scores = scores::read_csv(scores_csv.as_bytes())?;
    let verdicts = Verdicts::compute(scores, options, context)?.with_sensitivity(sensitivity);
    let findings = Findings::of(context, &verdicts);
    Ok((render(context, &verdicts, &findings), findings))
}

fn write_method(text: &mut String, verdicts: &Verdicts) {
    let _ = writeln!(
        text,
        "### How the scores are made\n\n\
         - **Final** steps and return: per seed the mean over the last {} training episodes; \
         tables show the IQM over seeds with its bootstrap 95% interval.\n\
         - **Fluctuation** (C3, secondary; C3 is judged on the greedy evaluations, see the \
         rule): per seed the sample standard deviation of steps and of return over the second \
         half of training. These are training curves, so exploration is in \
         them: a fixed-ε method (ε-greedy, ε = 0.1) keeps exploring to the end, while the \
         decreasing schedules of ε-decreasing and EA-MADM hardly explore in the second half.\n\
         - **Robot** (C4): over a run's first {} training episodes that reach the target (the \
         paper's \"100 episodes that are to reach the target\"): mean average reward (return \
         per second), mean time to reach, and the least-squares slope of retention time over \
         the reaching-episode index (`retention_decay`, seconds per reaching episode; more \
         negative falls faster). A seed with no reaching episode has no C4 value; a method \
         whose seeds never reach is named as such and is never ranked.\n\
         - **Success**: final-window training episodes that reached the target, pooled over \
         seeds, with a Wilson 95% interval (episodes of one seed are not independent, so it is \
         too narrow); **greedy reached**: seeds whose greedy episode after training reached \
         it, with a Wilson interval over seeds.\n\
         - **Environment steps** count every step of a run, sub-task pre-training included.\n\
         - The verdicts' numbers (mean paired differences, their intervals and p-values) are \
         exact sign-flip enumerations for up to 24 paired seeds; the descriptive IQM intervals \
         are a bootstrap seeded with seed {}: rerunning gives the same report bit for bit, \
         while another bootstrap seed moves those intervals' endpoints within the Monte-Carlo \
         tolerance of the glossary.\n",
        scores::FINAL_WINDOW,
        scores::REACHING_EPISODES,
        verdicts.options.bootstrap.seed
    );
}

#[cfg(test)]
pub(crate) mod tests {
    use super::robot::robot_ranking;
    use super::task::training_versus_greedy;
    use super::*;
    use eamadm_eval::Role;
    use eamadm_eval::claims::{self, MethodOverview, Share, Verdict};
    use eamadm_eval::facts::{ControlFamily, DeviationFacts, MethodFacts, PaperFigures};
    use eamadm_eval::paper_claims::ReportedNumbers;
    use eamadm_eval::scores::{FinalScore, RunOutcome};

    /// The facts of a method of these tests: label, role, kind and control family.
    pub(crate) fn method(
        label: &str,
        role: Role,
        kind: &str,
        control: Option<ControlFamily>,
    ) -> MethodFacts {
        MethodFacts {
            label: label.to_owned(),
            role,
            kind: kind.to_owned(),
            control,
            tree_threshold: None,
        }
    }

    /// An experiment of these tests with the methods of [`scores`], by their configs.
    pub(crate) fn experiment(name: &str, title: &str) -> ExperimentFacts {
        ExperimentFacts {
            name: name.to_owned(),
            title: title.to_owned(),
            episodes: 200,
            seeds: 8,
            gamma: 0.95,
            figures: Figures::default(),
            behaviour: Vec::new(),
            reward_references: Vec::new(),
            final_epsilon: Vec::new(),
            margins: Vec::new(),
            methods: vec![
                method("ea-madm", Role::Paper, "ea_madm", None),
                method("epsilon-greedy", Role::Paper, "epsilon_greedy", None),
                method("softmax", Role::Paper, "softmax", None),
                method(
                    "subtask0-alone",
                    Role::Control,
                    "subtask_greedy",
                    Some(ControlFamily::SubtaskAlone {
                        subtask: 0,
                        learns: false,
                    }),
                ),
                method(
                    "softmax-shaped",
                    Role::Control,
                    "softmax",
                    Some(ControlFamily::RewardMatched),
                ),
                method("ea-madm-table", Role::Ablation, "ea_madm", None),
            ],
            paper_figures: PaperFigures::default(),
            base_seed: 0,
            tables_written: false,
        }
    }

    /// The paper's tasks as `eamadm::paper::report_context` states them, one deviation, and
    /// Task I's experiment.
    pub(crate) fn context() -> ReportContext {
        let task =
            |name: &str, title: &str, in_sentence: &str, robot: bool, reported| PaperTaskFacts {
                name: name.to_owned(),
                title: title.to_owned(),
                title_in_sentence: in_sentence.to_owned(),
                robot,
                reported,
            };
        ReportContext {
            quick: false,
            paper_tasks: vec![
                task(
                    "task1",
                    "Task I",
                    "Task I",
                    false,
                    Some(ReportedNumbers {
                        steps: 80.0,
                        task_return: 155.0,
                    }),
                ),
                task(
                    "task2",
                    "Task II",
                    "Task II",
                    false,
                    Some(ReportedNumbers {
                        steps: 86.0,
                        task_return: -71.0,
                    }),
                ),
                task("robot", "Robot", "the robot", true, None),
            ],
            preset_seeds: 20,
            action_names: ["forward", "left", "right", "back", "stop"]
                .map(str::to_owned)
                .to_vec(),
            curves_file: "curves.csv.gz".to_owned(),
            trajectories_file: "trajectories.csv.gz".to_owned(),
            experiments: vec![experiment("task1", "Task I")],
            readings: Vec::new(),
            oracle: Vec::new(),
            pretraining: Vec::new(),
            predictions: Vec::new(),
            deviations: vec![
                DeviationFacts {
                    what: "Generated mazes".to_owned(),
                    ours: "ours are generated".to_owned(),
                    notes: "§7".to_owned(),
                    tasks: vec!["task1".to_owned()],
                    readings: Vec::new(),
                    methods: Vec::new(),
                },
                DeviationFacts {
                    what: "Reward standardisation".to_owned(),
                    ours: "a running one".to_owned(),
                    notes: "§3".to_owned(),
                    tasks: Vec::new(),
                    readings: vec!["gamma-0.99".to_owned()],
                    methods: vec!["ea-madm-literal".to_owned()],
                },
            ],
        }
    }

    pub(crate) fn row(
        task: &str,
        method: &str,
        role: Role,
        kind: &str,
        seed: u64,
        steps: f64,
    ) -> FinalScore {
        FinalScore {
            task: task.to_owned(),
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

    /// Task I with EA-MADM at `ea` steps (collapsing on `collapses`), two competitors at 100
    /// and 101 plus seed noise, the sub-task alone as EA-MADM, the reward-matched control at
    /// `shaped` and the table ablation as EA-MADM.
    pub(crate) fn scores(ea: f64, collapses: &[u64], shaped: f64) -> Vec<FinalScore> {
        let mut rows = Vec::new();
        for (method, kind, role, base) in [
            ("ea-madm", "ea_madm", Role::Paper, ea),
            ("epsilon-greedy", "epsilon_greedy", Role::Paper, 100.0),
            ("softmax", "softmax", Role::Paper, 101.0),
            ("subtask0-alone", "subtask_greedy", Role::Control, ea),
            ("softmax-shaped", "softmax", Role::Control, shaped),
            ("ea-madm-table", "ea_madm", Role::Ablation, ea),
        ] {
            for seed in 0..8 {
                let mut r = row("task1", method, role, kind, seed, base + seed as f64);
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

    pub(crate) fn options() -> ClaimOptions {
        ClaimOptions {
            bootstrap: eamadm_eval::stats::Bootstrap::new(2000, 0.95, 0).unwrap(),
            sign_flip: eamadm_eval::stats::SignFlipTest::new(2000, 0).unwrap(),
            alpha: 0.05,
            margins: test_margins(),
        }
    }

    /// The paper's maze margins on Task I (2 steps, 2 reward), as `eamadm::Task` derives them.
    pub(crate) fn test_margins() -> claims::Margins {
        let mut margins = claims::Margins::new();
        let table: Vec<claims::Margin> = claims::claim_columns()
            .into_iter()
            .filter(|c| c.contains("steps") || c.contains("return"))
            .map(|column| claims::Margin {
                column: column.to_owned(),
                value: 2.0,
                reason: format!("the shortest detour, for `{column}`"),
            })
            .collect();
        margins.insert("task1", &table).unwrap();
        margins
    }

    /// The verdicts and findings of `scores` in [`context`].
    pub(crate) fn judged(scores: Vec<FinalScore>) -> (Verdicts, Findings) {
        let verdicts = Verdicts::compute(scores, &options(), &context()).unwrap();
        let findings = Findings::of(&context(), &verdicts);
        (verdicts, findings)
    }

    fn report_of(scores: Vec<FinalScore>) -> String {
        let (verdicts, findings) = judged(scores);
        render(&context(), &verdicts, &findings)
    }

    /// The report's first screen: its lines before the verdicts.
    fn first_screen(report: &str) -> String {
        report[..report.find(verdicts::VERDICTS_HEADING).unwrap()].to_owned()
    }

    #[test]
    fn the_first_screen_holds_each_answer_and_every_deviation_in_50_lines() {
        let report = report_of(scores(60.0, &[3], 10.0));
        let screen: Vec<&str> = report.lines().take(50).collect();
        let screen = screen.join("\n");
        assert!(screen.contains("## The answer\n\n**Task I.** "), "{screen}");
        assert!(screen.contains(answer::DEVIATIONS_HEADING), "{screen}");
        for what in ["Generated mazes", "Reward standardisation"] {
            assert!(screen.contains(&format!("- **{what}**")), "{screen}");
        }
        assert!(first_screen(&report).lines().count() <= 50, "{report}");
        // The README states the answer of the first screen.
        let (_, findings) = judged(scores(60.0, &[3], 10.0));
        assert!(report.contains(&readme_answer(&findings).unwrap()));
        // Without EA-MADM's verdicts (a config of one's own) there is no answer.
        let other: Vec<FinalScore> = scores(60.0, &[], 150.0)
            .into_iter()
            .filter(|r| r.kind != "ea_madm")
            .collect();
        let report = report_of(other);
        assert!(!report.contains("## The answer"), "{report}");
        assert!(readme_answer(&Findings::default()).is_err());
    }

    /// The first screen as a reader sees it: a reward-matched control that overturns the
    /// verdicts, a collapse that decides nothing, the readings not run.
    /// [`context`] with what the oracle of issue 32 adds: EA-MADM's decision on exact
    /// sub-task values (Task I, at the Manhattan bound, the reach sub-task's episode on every
    /// seed), its reach sub-task's pre-training, and a prediction.
    pub(crate) fn context_with_oracle() -> ReportContext {
        use eamadm_eval::facts::PredictionFacts;
        use eamadm_eval::oracle::{FailingPart, OracleFinding, OracleValues, PretrainingSummary};
        let mut context = context();
        context.oracle = vec![OracleFinding {
            task: "task1".to_owned(),
            decision: "ea-madm".to_owned(),
            values: OracleValues::Exact,
            seeds: 8,
            optimum_steps: Some(58),
            manhattan_steps: Some(58),
            at_manhattan_bound: Some(true),
            reaches_initial: 8,
            reaches_learned: 7,
            median_steps_initial: Some(58.0),
            median_steps_learned: Some(58.0),
            optimal_share_initial: Some(0.998),
            optimal_share_learned: Some(0.9904),
            best_subtask_alone: Some(("subtask0-alone".to_owned(), 8)),
            equals_subtask_alone: 8,
            runs_converged: Some(6),
            failing_part: FailingPart::Learning,
        }];
        context.pretraining = vec![PretrainingSummary {
            task: "task1".to_owned(),
            method: "ea-madm".to_owned(),
            subtask: 0,
            name: "reach".to_owned(),
            seeds: 8,
            converged_seeds: Some(8),
            seeds_reaching: 8,
            reaching_episodes: 1571,
            greedy_alone_reaching: 8,
            mean_episodes: 200.0,
            mean_env_steps: 23_190.5,
        }];
        context.predictions = vec![PredictionFacts {
            task: "task1".to_owned(),
            notes: "§21.2".to_owned(),
            best_verdict: Verdict::Inconclusive,
            follows: "subtask0-alone".to_owned(),
            oracle_reaches: false,
        }];
        context
    }

    #[test]
    fn the_oracle_section_and_its_first_screen_sentences_read_as_pinned() {
        let with_oracle = context_with_oracle();
        let verdicts =
            Verdicts::compute(scores(60.0, &[], 150.0), &options(), &with_oracle).unwrap();
        let findings = Findings::of(&with_oracle, &verdicts);
        let report = render(&with_oracle, &verdicts, &findings);
        let start = report.find(oracle::ORACLE_HEADING).unwrap();
        let end = start + 1 + report[start + 1..].find("\n## ").unwrap();
        insta::assert_snapshot!(&report[start..end]);
        // The first screen names the oracle, the cause through the slot (the ceiling), and the
        // prediction against the outcome, within 50 lines.
        let screen = first_screen(&report);
        assert!(screen.lines().count() <= 50, "{screen}");
        let answer = &findings.tasks[0];
        assert!(matches!(
            answer.cause,
            Some(eamadm_eval::findings::Cause::Ceiling { .. })
        ));
        for said in [
            "**Why:** A ceiling: the layout is at the Manhattan bound (shortest path 58",
            "**Oracle:** with exact sub-task values",
            "reaches on 8 of 8 seeds in a median of 58 steps",
            "the prediction failed",
        ] {
            assert!(screen.contains(said), "{said}\n{screen}");
        }
        // Without an oracle the section is absent.
        let (verdicts, findings) = judged(scores(60.0, &[], 150.0));
        let plain = render(&context(), &verdicts, &findings);
        assert!(!plain.contains(oracle::ORACLE_HEADING));
    }

    #[test]
    fn the_first_screen_reads_as_pinned() {
        insta::assert_snapshot!(first_screen(&report_of(scores(60.0, &[3], 10.0))));
    }

    /// The README's verdict block, and the variants' table with the identical ablation left
    /// out by name.
    #[test]
    fn the_verdict_tables_read_as_pinned() {
        let (_, findings) = judged(scores(60.0, &[3], 10.0));
        insta::assert_snapshot!(readme_verdicts(&findings).unwrap());
        let report = report_of(scores(60.0, &[3], 10.0));
        assert!(
            report.contains(
                "Not listed, since they score exactly as another method on every seed and so \
                 get its verdicts: on Task I: `ea-madm-table` (as EA-MADM, 8 of 8 seeds)."
            ),
            "{report}"
        );
        assert!(!report.contains("| ea-madm-table "), "{report}");
    }

    /// Issue 34: every stable-reaching seed has greedy SD 0, so C3's SD comparisons are
    /// uninformative (one value on both sides) and the stable-reaching test decides the
    /// inconclusive verdict; the report states that test, not a 0 [0, 0].
    #[test]
    fn an_inconclusive_c3_shows_the_stable_reaching_test_that_decides_it() {
        // EA-MADM is stable on 4 of 8 seeds, every other method on all 8.
        let mut rows = scores(60.0, &[], 50.0);
        for r in &mut rows {
            r.fluctuation_greedy_steps = Some(0.0);
            r.fluctuation_greedy_return = Some(0.0);
            if r.method == "ea-madm" && r.seed < 4 {
                r.stable_reaching = Some(false);
                r.fluctuation_greedy_steps = None;
                r.fluctuation_greedy_return = None;
            }
        }
        let (verdicts, findings) = judged(rows);
        let c3 = verdicts
            .judgements
            .iter()
            .find(|j| j.claim.id == "C3" && j.method == "ea-madm")
            .unwrap();
        assert_eq!(c3.verdict, Verdict::Inconclusive);
        assert!(c3.comparisons.iter().all(|c| !c.informative));
        assert_eq!(c3.deciding, None);
        let deciding = findings.tasks[0]
            .verdicts
            .iter()
            .find(|v| v.claim == "C3")
            .and_then(|v| v.deciding.as_ref())
            .unwrap();
        assert_eq!(
            deciding.estimand,
            eamadm_eval::findings::Estimand::SeedsStableReaching
        );
        // 4 discordant seeds: p = 2/2⁴, Holm over the two competitors 0.25.
        assert_eq!(
            words::deciding(deciding, "ea-madm", true),
            "EA-MADM reaches in every greedy evaluation of the second half on 4/8 seeds, \
             ε-greedy on 8/8; exact paired sign test, Holm p 0.250"
        );
        // Where the column names the competitor, the test goes without the names.
        assert_eq!(
            words::deciding(deciding, "ea-madm", false),
            "reaches in every greedy evaluation of the second half on 4/8 seeds against 8/8; \
             exact paired sign test, Holm p 0.250"
        );
    }

    /// The verdict cells follow the numbers, and the margins decide equivalence.
    #[test]
    fn the_verdict_cell_follows_the_numbers() {
        let verdict_of = |report: &str, claim: &str| -> String {
            let row = report
                .lines()
                .find(|l| l.starts_with(&format!("| {claim} ")))
                .unwrap();
            row.split('|').nth(3).unwrap().trim().to_owned()
        };
        let report = report_of(scores(60.0, &[], 150.0));
        assert_eq!(verdict_of(&report, "C1"), "**supported**");
        assert_eq!(verdict_of(&report, "C2"), "**supported**");
        let report = report_of(scores(140.0, &[], 150.0));
        assert_eq!(verdict_of(&report, "C1"), "**contradicted**");
        let report = report_of(scores(100.0, &[], 150.0));
        assert_eq!(verdict_of(&report, "C1"), "**equivalent**");
        assert!(
            report.contains(
                "- Task I, `final_return`: ±2 reward, the shortest detour, for `final_return`."
            ),
            "{report}"
        );
        let no_margins = ClaimOptions {
            margins: claims::Margins::new(),
            ..options()
        };
        let verdicts =
            Verdicts::compute(scores(100.0, &[], 150.0), &no_margins, &context()).unwrap();
        let report = render(&context(), &verdicts, &Findings::of(&context(), &verdicts));
        assert_eq!(verdict_of(&report, "C1"), "**inconclusive**");
        assert!(
            report.contains("No task of this run defines an equivalence margin"),
            "{report}"
        );
        // The appendix comes after the task sections.
        assert!(report.find("## Task I").unwrap() < report.find("## Appendix").unwrap());
        assert!(report.find("## Appendix").unwrap() < report.find("### The rule").unwrap());
    }

    /// A method that scores as an earlier one on every seed is one row of the tables.
    #[test]
    fn identical_methods_are_one_row() {
        let report = report_of(scores(60.0, &[], 150.0));
        let section = &report[report.find("## Task I (`task1`)").unwrap()..];
        assert!(!section.contains("| ea-madm-table "), "{section}");
        assert!(
            section.contains(
                "`subtask0-alone` and `ea-madm-table` score exactly as EA-MADM on all 8 seeds"
            ),
            "{section}"
        );
    }

    pub(crate) fn overview(
        training: (u64, u64),
        greedy: (u64, u64),
        at_cap: usize,
    ) -> MethodOverview {
        let share = |(s, t): (u64, u64)| Share {
            successes: s,
            trials: t,
            wilson: eamadm_eval::stats::wilson(s, t, 0.95).unwrap(),
        };
        MethodOverview {
            task: "task2".into(),
            method: "ea-madm".into(),
            role: Role::Paper,
            kind: "ea_madm".into(),
            seeds: greedy.1 as usize,
            training_success: share(training),
            greedy_success: share(greedy),
            greedy_at_cap: at_cap,
            step_cap: Some(2000),
            final_steps: eamadm_eval::stats::distribution(&[1.0, 2.0], None).unwrap(),
            reaching_seeds: 0,
            env_steps_total: 1.0,
            pretrain_env_steps: 0.0,
        }
    }

    #[test]
    fn training_and_greedy_success_are_explained_only_when_they_differ() {
        let loops = training_versus_greedy(&overview((250, 400), (0, 20), 20), None).unwrap();
        assert!(loops.contains("only in 0/20"), "{loops}");
        assert!(loops.contains("in 20 of the 20 failing seeds"), "{loops}");
        assert!(!loops.contains("exploration"), "{loops}");
        // ε so small that a final-window episode takes under one random action: online
        // learning, not exploration, breaks the loops.
        let tiny = FinalEpsilon {
            method: "ea-madm".to_owned(),
            first: 9.0e-5,
            last: 3.5e-5,
        };
        let learning =
            training_versus_greedy(&overview((250, 400), (0, 20), 20), Some(&tiny)).unwrap();
        assert!(
            learning.contains(
                "ε over the final window is 9.0e-5 to 3.5e-5, under 0.00 random actions per \
                 episode of 2 steps (median), so online learning, not exploration, breaks"
            ),
            "{learning}"
        );
        let large = FinalEpsilon {
            method: "ea-madm".to_owned(),
            first: 0.9,
            last: 0.9,
        };
        let exploring =
            training_versus_greedy(&overview((250, 400), (0, 20), 20), Some(&large)).unwrap();
        assert!(
            exploring.contains("so exploration and online learning both break"),
            "{exploring}"
        );
        let flipped = training_versus_greedy(&overview((0, 400), (20, 20), 0), None).unwrap();
        assert!(flipped.contains("more often"), "{flipped}");
        assert_eq!(
            training_versus_greedy(&overview((200, 400), (10, 20), 0), None),
            None
        );
    }

    #[test]
    fn the_robot_ranks_only_methods_that_reach() {
        let mut rows = Vec::new();
        for (method, kind, reward) in [("ea-madm", "ea_madm", None), ("softmax", "softmax", None)] {
            for seed in 0..4 {
                let mut r = row("robot", method, Role::Paper, kind, seed, 500.0);
                r.reaching_episodes = 0;
                r.greedy_reached = false;
                r.reach_average_reward = reward;
                rows.push(r);
            }
        }
        let none = Verdicts::compute(rows.clone(), &options(), &context()).unwrap();
        let overviews: Vec<&MethodOverview> = none.overviews.iter().collect();
        let sentence = robot_ranking("robot", &overviews, &none);
        assert!(sentence.starts_with("No method reaches"), "{sentence}");
        assert!(
            sentence.contains("Never reaches the target: EA-MADM, softmax"),
            "{sentence}"
        );
        // Neither reaches: C4 stays untestable, with the counts.
        let c4 = none
            .judgements
            .iter()
            .find(|j| j.claim.id == "C4" && j.method == "ea-madm")
            .unwrap();
        assert_eq!(c4.verdict, Verdict::Untestable);
        assert!(
            c4.reason.ends_with(
                "no competitor reaches on 2 or more seeds: EA-MADM reaches on 0/4, softmax 0/4"
            ),
            "{}",
            c4.reason
        );
        for r in rows.iter_mut().filter(|r| r.method == "softmax") {
            r.reaching_episodes = 3;
            r.reach_average_reward = Some(1.0 + r.seed as f64);
        }
        let some = Verdicts::compute(rows, &options(), &context()).unwrap();
        let overviews: Vec<&MethodOverview> = some.overviews.iter().collect();
        let sentence = robot_ranking("robot", &overviews, &some);
        assert!(sentence.starts_with("Only softmax reaches"), "{sentence}");
        assert!(
            sentence.contains("Never reaches the target: EA-MADM."),
            "{sentence}"
        );
        // C4 for EA-MADM is judged on per-seed reaching: 0/4 against 4/4 is exact sign test
        // p = 2 / 2⁴ = 0.125 (scipy.stats.binomtest(0, 4, 0.5)), so inconclusive, with the
        // counts and the reason.
        let c4 = some
            .judgements
            .iter()
            .find(|j| j.claim.id == "C4" && j.method == "ea-madm")
            .unwrap();
        assert_eq!(c4.verdict, Verdict::Inconclusive);
        let finding = eamadm_eval::findings::verdict_finding(c4);
        assert_eq!(
            words::deciding_or_reason(finding.deciding.as_ref(), &finding.reason, "ea-madm", true),
            "EA-MADM reaches on 0/4 seeds, softmax on 4/4; exact paired sign test, Holm p 0.125"
        );
    }

    #[test]
    fn the_report_from_final_scores_csv_is_the_reports_bytes() {
        let (verdicts, findings) = judged(scores(60.0, &[3], 10.0));
        let report = render(&context(), &verdicts, &findings);
        let scores_csv = verdicts.scores_csv().unwrap();
        assert_eq!(
            render_from_csv(&context(), &scores_csv, Vec::new(), &options()).unwrap(),
            (report, findings)
        );
        let error = render_from_csv(&context(), "task,method\ntask1\n", Vec::new(), &options())
            .unwrap_err();
        assert!(
            error.to_string().starts_with("final-scores.csv: "),
            "{error}"
        );
    }
}
