//! The text of `REPORT.md` and of the README's generated blocks: the verdicts on the paper's
//! claims first, then per task the numbers behind them. Pure: it returns text and never
//! touches a file; `xtask` gathers the inputs ([`ReportContext`], [`Verdicts`]) and writes.
//!
//! Every number comes from [`scores`] and [`claims`]; this
//! module only lays them out, and every sentence that states a result is chosen by the numbers
//! (tests flip the numbers and watch the sentence flip). The text is a pure function of the
//! scores and the context (no paths, dates or timings), so an interrupted and resumed run
//! writes the same bytes as an uninterrupted one.
//!
//! What the text needs to know about the workspace's tasks and methods (task titles, the
//! paper's reported numbers, the robot's action names, the figures written) comes in as plain
//! data in [`ReportContext`]; `eamadm::paper::report_context` fills it from the presets.
//!
//! | file | what it writes |
//! |---|---|
//! | [`format`](mod@format) | Markdown tables and numbers, intervals, p-values, shares |
//! | `answer` | the answer paragraph `REPORT.md` opens with and the README states |
//! | `verdicts` | the verdict table, the claims, the rule, the ablations' verdicts |
//! | `task` | per task: scores, controls, comparisons, distributions, explanations, figures |
//! | `robot` | the robot's C4 metrics and its methods' behaviour |
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
use eamadm_eval::scores::{self, ScoresError};
pub use eamadm_eval::verdicts::{ControlVerdict, SurvivesReadings, Verdicts};

mod answer;
pub mod format;
mod glossary;
mod margins;
mod outcomes;
mod paper_numbers;
mod robot;
mod sensitivity;
pub mod strongest;
mod task;
mod verdicts;

pub use answer::readme_answer;
pub use eamadm_eval::facts::{
    ExperimentFacts, Figures, FinalEpsilon, NotDrawn, PaperTaskFacts, Play, ReadingFacts,
    ReportContext, RewardReading, SubtaskReference,
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
    format!(
        "Not drawn, since none of {} reached the target in any training episode of any seed: \
         {}.",
        first.methods.join(", "),
        whats.join("; ")
    )
}

/// `REPORT.md`: the answer (a paragraph per task, when EA-MADM has verdicts), the verdicts,
/// how the scores are made, the glossary, a section per experiment of `context` and the
/// paper's numbers.
pub fn render(context: &ReportContext, verdicts: &Verdicts) -> Result<String, ReportError> {
    Ok(render_body(context, verdicts))
}

/// `REPORT.md` from the text of a run's `final-scores.csv`: the verdicts are judged again
/// with `options` (the run's are [`ReportContext::claim_options`]), so with the run's context this is
/// the run's `REPORT.md` byte for byte. What the Python package's `eamadm.report(dir)` calls.
pub fn render_from_csv(
    context: &ReportContext,
    scores_csv: &str,
    options: &ClaimOptions,
) -> Result<String, ReportError> {
    let scores = scores::read_csv(scores_csv.as_bytes())?;
    render(context, &Verdicts::compute(scores, options)?)
}

/// `REPORT.md`.
fn render_body(context: &ReportContext, verdicts: &Verdicts) -> String {
    let mut text = String::from("# EA-MADM reproduction report\n\n");
    let _ = writeln!(
        text,
        "Made by `cargo xtask reproduce-paper`{}. Do not edit: rerun the command. The per-seed \
         scores are in [final-scores.csv](final-scores.csv), every estimate and comparison in \
         [claims.csv](claims.csv).\n",
        if context.quick {
            " --quick (a smoke run: few seeds and episodes; these numbers mean little)"
        } else {
            ""
        }
    );
    if let Some(answer) = answer::answer(context, verdicts) {
        let _ = writeln!(text, "{}\n\n{answer}\n", answer::ANSWER_HEADING);
    }
    verdicts::write_verdicts(&mut text, context, verdicts);
    sensitivity::write_sensitivity(&mut text, context, &verdicts.sensitivity);
    write_method(&mut text, verdicts);
    glossary::write_glossary(&mut text, verdicts);
    for experiment in &context.experiments {
        task::write_task(&mut text, context, experiment, verdicts);
    }
    paper_numbers::write_paper_numbers(&mut text, context, verdicts);
    text
}

fn write_method(text: &mut String, verdicts: &Verdicts) {
    let _ = writeln!(
        text,
        "## How the scores are made\n\n\
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
         whose seeds never reach is shown as \"never reaches\" and is never ranked.\n\
         - **Success**: final-window training episodes that reached the target, pooled over \
         seeds, with a Wilson 95% interval (episodes of one seed are not independent, so it is \
         too narrow); **greedy reached**: seeds whose greedy episode after training reached \
         it, with a Wilson interval over seeds.\n\
         - **Environment steps** count every step of a run, sub-task pre-training included.\n\
         - Bootstrap and permutations are seeded (seed {}): rerunning gives the same report \
         bit for bit, while another bootstrap seed moves interval endpoints within the \
         Monte-Carlo tolerance of the glossary.\n",
        scores::FINAL_WINDOW,
        scores::REACHING_EPISODES,
        verdicts.options.bootstrap.seed
    );
}

#[cfg(test)]
pub(crate) mod tests {
    use super::robot::robot_ranking;
    use super::task::training_versus_greedy;
    use super::verdicts::deciding_number;
    use super::*;
    use eamadm_eval::Role;
    use eamadm_eval::claims::{self, MethodOverview, Share, Verdict};
    use eamadm_eval::paper_claims::ReportedNumbers;
    use eamadm_eval::scores::FinalScore;

    /// The paper's tasks as `eamadm::paper::report_context` states them, and no experiment.
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
                task(
                    "robot-paper-state",
                    "Robot (paper's state)",
                    "Robot (paper's state)",
                    true,
                    None,
                ),
            ],
            preset_seeds: 20,
            action_names: ["forward", "left", "right", "back", "stop"]
                .map(str::to_owned)
                .to_vec(),
            curves_file: "curves.csv.gz".to_owned(),
            trajectories_file: "trajectories.csv".to_owned(),
            experiments: Vec::new(),
            readings: Vec::new(),
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
            outcome: eamadm_eval::scores::RunOutcome::Converged,
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

    /// Task I with EA-MADM at `ea` steps and two competitors at 100 + seed noise.
    fn scores(ea: f64) -> Vec<FinalScore> {
        let mut rows = Vec::new();
        for seed in 0..8 {
            let noise = seed as f64;
            rows.push(row(
                "task1",
                "ea-madm",
                Role::Paper,
                "ea_madm",
                seed,
                ea + noise,
            ));
        }
        for method in ["epsilon-greedy", "softmax"] {
            for seed in 0..8 {
                let noise = seed as f64;
                let kind = if method == "softmax" {
                    "softmax"
                } else {
                    "epsilon_greedy"
                };
                rows.push(row("task1", method, Role::Paper, kind, seed, 100.0 + noise));
            }
        }
        rows
    }

    pub(crate) fn options() -> ClaimOptions {
        ClaimOptions {
            bootstrap: eamadm_eval::stats::Bootstrap::new(2000, 0.95, 0).unwrap(),
            permutation: eamadm_eval::stats::PermutationTest::new(2000, 0).unwrap(),
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

    fn verdict_row(report: &str, claim: &str) -> String {
        report
            .lines()
            .find(|l| l.starts_with(&format!("| {claim} ")))
            .unwrap()
            .to_owned()
    }

    #[test]
    fn the_report_opens_with_the_answer_that_the_readme_states() {
        let verdicts = Verdicts::compute(scores(60.0), &options()).unwrap();
        let report = render_body(&context(), &verdicts);
        let answer = readme_answer(&report).unwrap();
        assert!(
            answer.starts_with("**Task I.** EA-MADM beats the paper's competitors"),
            "{answer}"
        );
        // The first screen: the answer to a task is a few lines of a 100-column terminal.
        for paragraph in answer.split("\n\n") {
            assert!(paragraph.len() < 700, "{paragraph}");
        }
        // The first screen: title, intro, the answer, then the verdicts.
        let heading = report.find("## The answer").unwrap();
        assert!(heading < report.find("## Verdicts on the paper's claims").unwrap());
        assert!(report[..heading].lines().count() < 5, "{report}");
        // Without EA-MADM's verdicts (a config of one's own) there is no answer.
        let other: Vec<FinalScore> = scores(60.0)
            .into_iter()
            .map(|mut r| {
                if r.method == "ea-madm" {
                    r.kind = "softmax".to_owned();
                }
                r
            })
            .collect();
        let report = render_body(&context(), &Verdicts::compute(other, &options()).unwrap());
        assert!(!report.contains("## The answer"), "{report}");
        assert!(readme_answer(&report).is_err());
    }

    #[test]
    fn the_verdict_sentence_follows_the_numbers() {
        let better = Verdicts::compute(scores(60.0), &options()).unwrap();
        let report = render_body(&context(), &better);
        assert!(!report.contains("control, not in the paper"), "{report}");
        assert!(
            verdict_row(&report, "C1").contains("**supported**"),
            "{report}"
        );
        // C2 is higher return: EA-MADM's return is −steps, so it is supported too.
        assert!(
            verdict_row(&report, "C2").contains("**supported**"),
            "{report}"
        );
        let worse = Verdicts::compute(scores(140.0), &options()).unwrap();
        let report = render_body(&context(), &worse);
        assert!(
            verdict_row(&report, "C1").contains("**contradicted**"),
            "{report}"
        );
        // Identical per seed: equivalent within the 2-step margin on steps and the 2-reward
        // margin on return; without margins neither can be.
        let same = Verdicts::compute(scores(100.0), &options()).unwrap();
        let report = render_body(&context(), &same);
        assert!(
            verdict_row(&report, "C1").contains("**equivalent**"),
            "{report}"
        );
        assert!(
            verdict_row(&report, "C2").contains("**equivalent**"),
            "{report}"
        );
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
        let report = render_body(
            &context(),
            &Verdicts::compute(scores(100.0), &no_margins).unwrap(),
        );
        for claim in ["C1", "C2"] {
            assert!(
                verdict_row(&report, claim).contains("**inconclusive**"),
                "{report}"
            );
        }
        assert!(
            report.contains("No task of this run defines an equivalence margin"),
            "{report}"
        );
        assert!(report.starts_with("# EA-MADM reproduction report"));
        // A control is judged nowhere but shown as one, with EA-MADM against it.
        let mut with_control = scores(60.0);
        for seed in 0..8 {
            let noise = seed as f64;
            with_control.push(row(
                "task1",
                "softmax-shaped",
                Role::Control,
                "softmax",
                seed,
                50.0 + noise,
            ));
        }
        let verdicts = Verdicts::compute(with_control, &options()).unwrap();
        assert!(verdicts.judgements.iter().all(|j| j.method == "ea-madm"));
        assert!(
            verdicts
                .judgements
                .iter()
                .flat_map(|j| &j.comparisons)
                .all(|c| c.versus != "softmax-shaped")
        );
        let mut planned = context();
        planned.experiments.push(ExperimentFacts {
            name: "task1".to_owned(),
            title: "Task I".to_owned(),
            episodes: 200,
            seeds: 8,
            gamma: 0.95,
            figures: Figures::default(),
            behaviour: Vec::new(),
            reward_readings: Vec::new(),
            final_epsilon: Vec::new(),
            margins: Vec::new(),
        });
        let report = render_body(&planned, &verdicts);
        assert!(
            report.contains("### Controls (control, not in the paper)"),
            "{report}"
        );
        assert!(
            report.contains("| `softmax-shaped` | `final_steps`"),
            "{report}"
        );
        assert!(report.find("## Verdicts").unwrap() < report.find("## How the scores").unwrap());
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
        let none = Verdicts::compute(rows.clone(), &options()).unwrap();
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
        let some = Verdicts::compute(rows, &options()).unwrap();
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
        assert_eq!(
            deciding_number(c4),
            "EA-MADM reaches on 0/4 seeds, softmax on 4/4; exact paired sign test, Holm p \
             0.125; EA-MADM has a `reach_average_reward` value in 0 of 4 seeds (it needs a \
             reaching episode)"
        );
    }

    #[test]
    fn the_report_from_final_scores_csv_is_the_reports_bytes() {
        let verdicts = Verdicts::compute(scores(60.0), &options()).unwrap();
        let report = render(&context(), &verdicts).unwrap();
        assert!(report.contains("## The answer\n\n**Task I.** "), "{report}");
        let scores_csv = verdicts.scores_csv().unwrap();
        assert_eq!(
            render_from_csv(&context(), &scores_csv, &options()).unwrap(),
            report
        );
        let error = render_from_csv(&context(), "task,method\ntask1\n", &options()).unwrap_err();
        assert!(
            error.to_string().starts_with("final-scores.csv: "),
            "{error}"
        );
    }
}
