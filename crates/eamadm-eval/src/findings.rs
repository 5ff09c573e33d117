//! What a run's report states, as data: per task the paper's EA-MADM's verdicts with the
//! comparison that decides each, the strongest control of each claim and the verdict against
//! it, whether the verdicts survive the readings of the paper, the seeds EA-MADM collapsed on
//! and the verdicts judged again without them, which methods end exactly as another, why a
//! method that never reaches does not (the robot's reward diagnosis), and the one cause the
//! report's first screen names. `findings.json` beside `REPORT.md` holds it
//! ([`FINDINGS_FORMAT`]); the report's sentences and the README's generated blocks are
//! rendered from it (`eamadm_present`), never re-derived and never scraped from text.
//!
//! Everything here is computed from [`Verdicts`] (the judged scores) and the run's
//! [`ReportContext`] (methods' roles and control families from their configs, the robot's
//! reward references): a pure function, so the same run gives the same findings bit for bit.
//!
//! A verdict's deciding comparison is a small self-describing [`Deciding`]: which estimand it
//! estimates (`paired_mean_difference`, the one every metric comparison decides on, or
//! `seeds_reaching` / `seeds_stable_reaching` for a per-seed test), the estimate with its
//! interval, the margin, the test and its Holm-adjusted p, the seeds paired, and for a per-seed
//! test the seeds each side reaches on, so that a new estimand is one new [`Estimand`] and one
//! way to say it.
//!
//! ```
//! use eamadm_eval::findings::{Findings, FINDINGS_FORMAT};
//!
//! let findings = Findings::default();
//! assert_eq!(findings.format, FINDINGS_FORMAT);
//! let json = findings.to_json()?;
//! assert_eq!(Findings::from_json(&json)?, findings);
//! # Ok::<(), serde_json::Error>(())
//! ```

use serde::{Deserialize, Serialize};

use crate::Role;
use crate::claims::{self, Judgement, ReachingComparison, Verdict};
use crate::facts::{ControlFamily, PredictionFacts, ReportContext, RewardReference};
use crate::family::FamilyFindings;
use crate::oracle::{FailingPart, OracleFinding, OracleValues, PretrainingSummary};
use crate::scores::{FinalScore, RunOutcome};
use crate::sensitivity::Change;
use crate::verdicts::{ControlVerdict, Verdicts, collapsed_seeds};

/// The version of `findings.json`'s layout; a reader refuses another.
pub const FINDINGS_FORMAT: u32 = 3;

/// What the report states, per task of the run on which the paper's EA-MADM has verdicts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Findings {
    /// [`FINDINGS_FORMAT`].
    pub format: u32,
    /// Per task, in run order.
    pub tasks: Vec<TaskFindings>,
    /// "Each method at its best": per tuned task, the paper's EA-MADM judged again when every
    /// method runs the trial its tuning chose (`--suite tuning`, docs/paper-notes.md §23), a
    /// verdict set beside the paper-setting verdicts of `tasks`, which it never changes. Empty
    /// (and left out of `findings.json`) when no tuning ran.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub at_best: Vec<AtBestFindings>,
    /// The maze family (`--suite family`, docs/paper-notes.md §22): its layouts, EA-MADM's
    /// pooled verdicts on C1 and C2 and the spread of the per-layout effects. Absent (and left
    /// out of `findings.json`) when no family ran.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub family: Option<FamilyFindings>,
}

impl Default for Findings {
    fn default() -> Self {
        Self {
            format: FINDINGS_FORMAT,
            tasks: Vec::new(),
            at_best: Vec::new(),
            family: None,
        }
    }
}

/// A method's chosen trial of a tuning (a row of `tuning.csv` with `chosen` true).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChosenTrial {
    /// The task tuned.
    pub task: String,
    /// The method's label.
    pub method: String,
    /// The trial's index (0: the preset's setting).
    pub trial: u32,
    /// Whether it is the preset's (the paper's) setting.
    pub paper_setting: bool,
    /// The objective's name (`final_steps_iqm`, `success_rate_mean`).
    pub objective: String,
    /// Its value over the tuning seeds.
    pub score: f64,
    /// Trials the method had (the same for every method of a tuning).
    pub trials: u32,
    /// Tuning seeds each trial ran on.
    pub tuning_seeds: u32,
}

/// The "each at its best" verdicts of one task: every method at its chosen trial, run on the
/// held-out seeds, and the paper's EA-MADM judged against the paper's competitors by the
/// normal claims (paired by seed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AtBestFindings {
    /// The task (experiment name).
    pub task: String,
    /// Its title for people.
    pub title: String,
    /// The paper's EA-MADM's label.
    pub method: String,
    /// Each method's chosen trial, in the tuning's method order.
    pub chosen: Vec<ChosenTrial>,
    /// EA-MADM's seeds at its best, and those it converges on.
    pub converged: SeedCount,
    /// Each competitor at its best with the seeds it converges on.
    pub competitors: Vec<MethodCount>,
    /// EA-MADM's verdict on each claim made on the task, claim order.
    pub verdicts: Vec<VerdictFinding>,
    /// The claims whose verdict differs from the paper-setting verdict on the task (none
    /// when the paper setting has no verdict there).
    pub changed: Vec<String>,
}

/// What the report states about one task.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TaskFindings {
    /// The task (experiment name).
    pub task: String,
    /// Its title for people.
    pub title: String,
    /// The label of the paper's EA-MADM on it (role `paper`, kind `ea_madm`).
    pub method: String,
    /// EA-MADM's seeds, and those its greedy policy after training reaches the target on.
    pub converged: SeedCount,
    /// Each of the paper's competitors with the seeds it converges on, in run order.
    pub competitors: Vec<MethodCount>,
    /// EA-MADM's verdict on each claim made on the task, claim order.
    pub verdicts: Vec<VerdictFinding>,
    /// The verdicts of EA-MADM's ablations and variants (every other method judged), in
    /// judgement order.
    pub variants: Vec<VariantVerdict>,
    /// The strongest control of each claim and EA-MADM's verdict against it.
    pub strongest: Vec<StrongestControl>,
    /// Whether the verdicts survive the readings of the paper; `None` when none was run.
    pub readings: Option<ReadingsFinding>,
    /// The seeds EA-MADM collapsed on and the verdicts judged again without them; `None`
    /// when it collapsed on none.
    pub collapses: Option<Collapses>,
    /// Why EA-MADM never reaches the target, from the sub-task rewards it learns from; `None`
    /// when it reaches on some seed or learns from no sub-task rewards the run diagnoses.
    pub never_reaches: Option<Diagnosis>,
    /// EA-MADM paired by seed on converging with its strongest frozen sub-task acting alone.
    pub subtask_pairing: Option<Pairing>,
    /// EA-MADM variants that end exactly as a sub-task alone on at least half the seeds.
    pub equalities: Vec<Equality>,
    /// Methods whose per-seed scores equal an earlier method's on every seed.
    pub identical: Vec<Identical>,
    /// The oracle (issue 32): per decision rule (the paper's EA-MADM first, then the plain
    /// aggregators) what it does with the best sub-task values available; empty when the run
    /// has no oracle analysis.
    #[serde(default)]
    pub oracle: Vec<OracleFinding>,
    /// The reach sub-task's pre-training (sub-task 0) in the runs of EA-MADM, its variants and
    /// the plain aggregators.
    #[serde(default)]
    pub reach_pretraining: Vec<PretrainingSummary>,
    /// The plain aggregators' runs against the paper's EA-MADM (OWA with visibility weights).
    #[serde(default)]
    pub aggregators: Vec<AggregatorFinding>,
    /// What was predicted for the task before any run, and whether it held.
    #[serde(default)]
    pub prediction: Option<PredictionOutcome>,
    /// The one cause the first screen names, chosen by the numbers; `None` when none stands
    /// out.
    pub cause: Option<Cause>,
}

/// A plain aggregator's runs beside the paper's EA-MADM's, on the same sub-tasks.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AggregatorFinding {
    /// Its label (`subtasks-mean`, `subtasks-max`).
    pub method: String,
    /// The seeds its greedy policy after training reaches the target on.
    pub converged: SeedCount,
    /// The seeds on which EA-MADM ends exactly as it (final-window steps and return, the
    /// greedy episode and the outcome), of the seeds both ran.
    pub ends_as_ea_madm: SeedCount,
}

/// A prediction written before any run ([`PredictionFacts`]) against the run's outcome.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PredictionOutcome {
    /// What was predicted.
    pub predicted: PredictionFacts,
    /// EA-MADM's best verdict on the task.
    pub best_verdict: Option<Verdict>,
    /// The seeds on which EA-MADM ends exactly as the predicted sub-task alone.
    pub ends_as_followed: SeedCount,
    /// The seeds on which EA-MADM's decision with exact sub-task values and its initial own
    /// values reaches, of the seeds of the oracle; `None` without an oracle.
    pub oracle_reaches: Option<SeedCount>,
    /// Whether each part of the prediction held.
    pub held: bool,
}

/// Seeds with an outcome, of seeds run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct SeedCount {
    /// Seeds with the outcome.
    pub hits: usize,
    /// Seeds run.
    pub seeds: usize,
}

/// A method with the seeds it converges on.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct MethodCount {
    /// Its label.
    pub method: String,
    /// Its converged seeds.
    pub converged: SeedCount,
}

/// One claim's verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VerdictFinding {
    /// `C1` … `C4`.
    pub claim: String,
    /// The verdict.
    pub verdict: Verdict,
    /// The comparison that decides it; `None` when none does (untestable).
    pub deciding: Option<Deciding>,
    /// The judgement's reason in words (what the report says when nothing decides).
    pub reason: String,
}

/// The verdict of an EA-MADM variant (an ablation or a control that is EA-MADM).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VariantVerdict {
    /// Its label.
    pub method: String,
    /// Its role.
    pub role: Role,
    /// Whom it is judged against: `paper` (the paper's competitors) or `same_rewards` (the
    /// competitors on its own repaired sub-task rewards).
    pub versus_set: String,
    /// The verdict and what decides it.
    #[serde(flatten)]
    pub verdict: VerdictFinding,
}

/// What a deciding comparison estimates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimand {
    /// The mean of the per-seed differences (method − versus), paired by seed: the estimand
    /// every metric comparison of a verdict decides on, with its exact sign-flip interval
    /// (docs/paper-notes.md §10.5).
    PairedMeanDifference,
    /// The share of seeds the method reaches the target on minus the other's (per-seed
    /// reaching: a greedy episode or any training episode reaches).
    SeedsReaching,
    /// The share of seeds every greedy evaluation of the second half reaches on, minus the
    /// other's (C3's stable reaching).
    SeedsStableReaching,
}

/// The test behind a deciding comparison's p.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Test {
    /// The sign-flip test that the mean paired difference lies beyond the margin on one side
    /// (not 0, without a margin): exact up to 24 pairs, drawn sign vectors beyond. At most α
    /// exactly when the interval lies beyond the margin.
    SignFlipBeyondMargin,
    /// The sign-flip test that the mean paired difference lies within the margin (two
    /// one-sided tests at α/2 each): at most α exactly when the interval lies inside it.
    SignFlipWithinMargin,
    /// The exact paired sign test on the seeds only one side reaches on (McNemar).
    ExactSignTest,
}

/// The comparison that decides a verdict, self-describing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Deciding {
    /// The other side (a competitor or a control).
    pub versus: String,
    /// The column of `final-scores.csv` compared, or `reached` / `stable_reaching` for a
    /// per-seed test.
    pub metric: String,
    /// What is estimated.
    pub estimand: Estimand,
    /// The estimate.
    pub estimate: f64,
    /// Its 95 % interval; `None` for a per-seed test, and for a paired comparison of fewer
    /// than 6 seeds, whose interval is unbounded.
    pub interval: Option<[f64; 2]>,
    /// The equivalence margin of the metric on the task, if it has one.
    pub margin: Option<f64>,
    /// The test of the p-value.
    pub test: Test,
    /// The p-value, Holm-adjusted as the rule adjusts it (an uninformative comparison's raw
    /// p: it takes no part in Holm).
    pub p_holm: f64,
    /// For a paired comparison: the seeds paired (both sides have a value).
    pub pairs: Option<usize>,
    /// For a per-seed test: the seeds each side reaches on, of those paired.
    pub seeds: Option<SeedPair>,
}

/// Seeds each side of a per-seed test reaches on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct SeedPair {
    /// The method's.
    pub method: usize,
    /// The other side's.
    pub versus: usize,
    /// Seeds paired.
    pub of: usize,
}

/// The strongest control of a claim on a task, and EA-MADM judged against it alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StrongestControl {
    /// The claim.
    pub claim: String,
    /// The control's label.
    pub control: String,
    /// What it is, from its config.
    pub family: ControlFamily,
    /// The metric it is the strongest on.
    pub metric: String,
    /// Its IQM of that metric.
    pub control_iqm: f64,
    /// EA-MADM's IQM of it; `None` when no seed has a value.
    pub method_iqm: Option<f64>,
    /// The seeds the control converges on.
    pub converged: SeedCount,
    /// Mean environment steps per run: the control's and EA-MADM's.
    pub env_steps: [f64; 2],
    /// EA-MADM's verdict against it.
    pub verdict: Verdict,
    /// The comparison that decides it.
    pub deciding: Option<Deciding>,
    /// The judgement's reason.
    pub reason: String,
    /// Whether this verdict is worse for EA-MADM than its verdict against the paper's
    /// competitors: the control overturns that verdict.
    pub overturns: bool,
}

/// Whether the verdicts of a task survive the readings of the paper.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ReadingsFinding {
    /// The claims whose verdict no reading flips, and how many readings each survived.
    pub holds: Vec<(String, usize)>,
    /// The claims some reading flips, with those readings.
    pub flips: Vec<(String, Vec<String>)>,
}

/// The seeds EA-MADM collapsed on (its greedy policy and final window stopped reaching after
/// an earlier training episode did), and its verdicts judged again without them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Collapses {
    /// Each collapsed seed with the episode from which it never reached again.
    pub seeds: Vec<(u64, Option<u64>)>,
    /// Seeds run.
    pub of: usize,
    /// Each inconclusive or contradicted verdict judged again without those seeds (left out
    /// of every method, so still paired): a diagnosis, never a verdict.
    pub rejudged: Vec<Rejudgement>,
}

/// One verdict judged again without the collapsed seeds.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rejudgement {
    /// The claim.
    pub claim: String,
    /// The verdict with every seed.
    pub was: Verdict,
    /// Without the collapsed seeds.
    pub now: Verdict,
}

/// Why a method never reaches the target: what each sub-task's reward definition under the
/// repairs it learns from values most, and what its learners learned.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// The repairs of the sub-task rewards it learns from; empty for the paper's (Eq. 6–8).
    pub repairs: Vec<String>,
    /// Per sub-task: its name and whether its reward values reaching above both ending the
    /// episode at once and idling.
    pub subtasks: Vec<(String, bool)>,
}

impl Diagnosis {
    /// The sub-tasks whose reward values reaching most.
    #[must_use]
    pub fn valuing_reaching(&self) -> usize {
        self.subtasks.iter().filter(|(_, pays)| *pays).count()
    }
}

/// EA-MADM against a frozen sub-task alone on converging, paired by seed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Pairing {
    /// The sub-task-alone control.
    pub control: String,
    /// Seeds both ran.
    pub paired: usize,
    /// Seeds both converge on.
    pub both: usize,
    /// Seeds only EA-MADM converges on.
    pub only_method: usize,
    /// Seeds only the sub-task alone converges on.
    pub only_control: usize,
    /// Of those, seeds EA-MADM collapsed on.
    pub method_collapsed: usize,
}

/// How far an EA-MADM variant ends as a sub-task alone, seed for seed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Equality {
    /// The EA-MADM variant.
    pub method: String,
    /// The sub-task-alone control.
    pub other: String,
    /// Seeds both ran.
    pub both: usize,
    /// Seeds on which the two end the same: final-window steps and return, the greedy episode
    /// and the outcome.
    pub end_same: usize,
    /// Of those, seeds on which every score but the environment steps is the same.
    pub all_through: usize,
    /// Of those that end the same, on how many seeds each part still differs.
    pub differing: Vec<(String, usize)>,
}

/// A method whose per-seed scores equal an earlier method's on every seed (every score but
/// the environment steps).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Identical {
    /// The method.
    pub method: String,
    /// The earlier method it equals.
    pub same_as: String,
    /// The seeds (all of them).
    pub seeds: usize,
}

/// The one cause of a task's result the report's first screen names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Cause {
    /// With exact sub-task values neither EA-MADM's decision nor any sub-task alone reaches
    /// the target (the oracle): the sub-tasks carry no route to it, so the decision step has
    /// nothing to combine.
    SubtaskValues {
        /// The decision's seeds reaching with exact values (none), of the oracle's seeds.
        reaches: SeedCount,
        /// The sub-task alone the decision follows (the reach sub-task).
        follows: String,
        /// The seeds on which the decision's greedy episode equals that sub-task's alone.
        follows_on: SeedCount,
        /// The task's optimum (BFS) in steps.
        optimum_steps: Option<u64>,
        /// The Manhattan distance from start to target.
        manhattan_steps: Option<u64>,
    },
    /// EA-MADM never reaches the target, and its reach sub-task never reached it in
    /// pre-training on any seed: a reward for reaching (the goal bonus of a repaired reading)
    /// is never paid, so nothing the aggregation or the tree does can use it.
    Pretraining {
        /// The reach sub-task's pre-training over EA-MADM's seeds.
        reach: PretrainingSummary,
        /// Why its rewards do not lead to the target either, when the run diagnoses them.
        diagnosis: Option<Diagnosis>,
    },
    /// The task sits at the Manhattan bound (its shortest path equals the Manhattan distance:
    /// no obstacle forces a detour), and with exact sub-task values EA-MADM's decision equals
    /// the distance-shaped reach sub-task alone: there is nothing for a second attribute to add.
    Ceiling {
        /// The optimum, equal to the Manhattan distance.
        optimum_steps: u64,
        /// The sub-task alone the decision equals.
        follows: String,
        /// The seeds on which it does, of the oracle's seeds.
        follows_on: SeedCount,
        /// The seeds on which the decision with exact values reaches.
        reaches: SeedCount,
    },
    /// EA-MADM never reaches the target, and the reward reference it learns from values
    /// reaching in no (or too few) sub-tasks.
    Rewards {
        /// The diagnosis.
        diagnosis: Diagnosis,
    },
    /// A control given EA-MADM's reward information or step budget overturns a verdict:
    /// that is where EA-MADM's advantage comes from.
    MatchedControl {
        /// The control.
        control: String,
        /// Reward-matched or budget-matched.
        family: ControlFamily,
        /// The claims it overturns.
        claims: Vec<String>,
        /// EA-MADM's verdict against it.
        verdict: Verdict,
    },
    /// A pre-trained sub-task acting alone, without the MADM step, is not shown worse than
    /// EA-MADM where EA-MADM has no better verdict than against the competitors.
    SubtaskAlone {
        /// The control.
        control: String,
        /// The claims.
        claims: Vec<String>,
        /// Whether it is better (contradicted) rather than only not worse.
        better: bool,
        /// The seeds EA-MADM ends exactly as it (and of how many).
        end_same: Option<SeedCount>,
    },
}

impl Findings {
    /// The findings of `verdicts` in `context`: one [`TaskFindings`] per task (run order)
    /// on which the paper's EA-MADM was judged.
    #[must_use]
    pub fn of(context: &ReportContext, verdicts: &Verdicts) -> Self {
        let tasks = claims::tasks(&verdicts.scores)
            .into_iter()
            .filter_map(|task| task_findings(context, verdicts, task))
            .collect();
        Self {
            format: FINDINGS_FORMAT,
            tasks,
            at_best: Vec::new(),
            family: None,
        }
    }

    /// These findings with the "each at its best" verdicts: `scores` are the held-out runs of
    /// every method's chosen trial, under the tuned tasks' own names (so they pair by seed and
    /// are judged by the claims of those tasks), `chosen` the trials they ran. They are judged
    /// with `options` (the run's) apart from the paper-setting verdicts, which do not change.
    ///
    /// # Errors
    /// [`claims::ClaimsError`] when a statistic fails.
    pub fn with_at_best(
        mut self,
        context: &ReportContext,
        scores: &[FinalScore],
        chosen: &[ChosenTrial],
        options: &claims::ClaimOptions,
    ) -> Result<Self, claims::ClaimsError> {
        let judgements = claims::judge(scores, options)?;
        let mut at_best = Vec::new();
        for task in claims::tasks(scores) {
            let Some(ea) = claims::methods(scores, task)
                .into_iter()
                .find(|&(_, role, kind)| role == Role::Paper && claims::is_under_test(kind))
                .map(|(method, _, _)| method)
            else {
                continue;
            };
            let verdicts: Vec<VerdictFinding> = judgements
                .iter()
                .filter(|j| j.task == task && j.method == ea)
                .map(verdict_finding)
                .collect();
            if verdicts.is_empty() {
                continue;
            }
            let paper = self.task(task);
            let changed = verdicts
                .iter()
                .filter(|v| {
                    paper
                        .and_then(|p| p.verdicts.iter().find(|pv| pv.claim == v.claim))
                        .is_some_and(|pv| pv.verdict != v.verdict)
                })
                .map(|v| v.claim.clone())
                .collect();
            at_best.push(AtBestFindings {
                task: task.to_owned(),
                title: context.task_title(task),
                method: ea.to_owned(),
                chosen: chosen.iter().filter(|c| c.task == task).cloned().collect(),
                converged: converged(scores, task, ea),
                competitors: claims::methods(scores, task)
                    .into_iter()
                    .filter(|&(_, role, kind)| claims::is_competitor(role, kind))
                    .map(|(m, _, _)| MethodCount {
                        method: m.to_owned(),
                        converged: converged(scores, task, m),
                    })
                    .collect(),
                verdicts,
                changed,
            });
        }
        self.at_best = at_best;
        Ok(self)
    }

    /// These findings with the maze family's (`None`: no family ran).
    #[must_use]
    pub fn with_family(mut self, family: Option<FamilyFindings>) -> Self {
        self.family = family;
        self
    }

    /// The findings of `task`, if it has any.
    #[must_use]
    pub fn task(&self, task: &str) -> Option<&TaskFindings> {
        self.tasks.iter().find(|t| t.task == task)
    }

    /// `findings.json`: pretty-printed JSON ending in a newline.
    ///
    /// # Errors
    /// A value JSON cannot hold (a non-finite number).
    pub fn to_json(&self) -> Result<String, serde_json::Error> {
        let mut text = serde_json::to_string_pretty(self)?;
        text.push('\n');
        Ok(text)
    }

    /// The findings of `findings.json`'s text.
    ///
    /// # Errors
    /// Text that is not this layout, or another [`FINDINGS_FORMAT`].
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        let findings: Self = serde_json::from_str(text)?;
        if findings.format != FINDINGS_FORMAT {
            return Err(serde::de::Error::custom(format!(
                "findings format {} is not {FINDINGS_FORMAT}: rerun `cargo xtask \
                 reproduce-paper` with this version",
                findings.format
            )));
        }
        Ok(findings)
    }
}

/// How good a verdict is for the method under test, to tell whether another comparison
/// overturns it.
#[must_use]
pub fn rank(verdict: Verdict) -> u8 {
    match verdict {
        Verdict::Contradicted => 0,
        Verdict::Inconclusive | Verdict::Untestable => 1,
        Verdict::Equivalent => 2,
        Verdict::Supported => 3,
    }
}

/// The outcomes of `method`'s seeds on `task`, by seed.
#[must_use]
pub fn outcomes(scores: &[FinalScore], task: &str, method: &str) -> Vec<(u64, RunOutcome)> {
    let mut seeds: Vec<(u64, RunOutcome)> = scores
        .iter()
        .filter(|s| s.task == task && s.method == method)
        .map(|s| (s.seed, s.outcome))
        .collect();
    seeds.sort_unstable();
    seeds
}

/// The seeds of `method` on `task` that converged, of its seeds.
#[must_use]
pub fn converged(scores: &[FinalScore], task: &str, method: &str) -> SeedCount {
    let seeds = outcomes(scores, task, method);
    SeedCount {
        hits: seeds
            .iter()
            .filter(|(_, o)| *o == RunOutcome::Converged)
            .count(),
        seeds: seeds.len(),
    }
}

fn task_findings(context: &ReportContext, verdicts: &Verdicts, task: &str) -> Option<TaskFindings> {
    let ea = verdicts.paper_ea_madm(task)?;
    let judgements: Vec<&Judgement> = verdicts
        .judgements
        .iter()
        .filter(|j| j.task == task && j.method == ea)
        .collect();
    if judgements.is_empty() {
        return None;
    }
    let scores = &verdicts.scores;
    let verdict_findings: Vec<VerdictFinding> =
        judgements.iter().map(|j| verdict_finding(j)).collect();
    let competitors = claims::methods(scores, task)
        .into_iter()
        .filter(|&(_, role, kind)| claims::is_competitor(role, kind))
        .map(|(m, _, _)| MethodCount {
            method: m.to_owned(),
            converged: converged(scores, task, m),
        })
        .collect();
    let variants = verdicts
        .judgements
        .iter()
        .filter(|j| j.task == task && j.method != ea)
        .map(|j| VariantVerdict {
            method: j.method.clone(),
            role: j.role,
            versus_set: j.versus_set.name().to_owned(),
            verdict: verdict_finding(j),
        })
        .collect();
    let strongest: Vec<StrongestControl> = verdicts
        .against_strongest
        .iter()
        .filter(|c| c.judgement.task == task && c.judgement.method == ea)
        .filter_map(|c| strongest_control(context, verdicts, task, ea, &judgements, c))
        .collect();
    let collapses = collapses(verdicts, task, ea, &judgements);
    let never_reaches = never_reaches(context, scores, task, ea);
    let subtask_pairing = subtask_pairing(context, scores, task, ea);
    let equalities = equalities(context, scores, task);
    let oracle: Vec<OracleFinding> = context
        .oracle
        .iter()
        .filter(|o| o.task == task)
        .cloned()
        .collect();
    let reach_pretraining: Vec<PretrainingSummary> = context
        .pretraining
        .iter()
        .filter(|p| p.task == task)
        .cloned()
        .collect();
    let aggregators = oracle
        .iter()
        .filter(|o| o.decision != ea)
        .map(|o| {
            let same = equality(scores, task, ea, &o.decision);
            AggregatorFinding {
                method: o.decision.clone(),
                converged: converged(scores, task, &o.decision),
                ends_as_ea_madm: SeedCount {
                    hits: same.end_same,
                    seeds: same.both,
                },
            }
        })
        .filter(|a| a.converged.seeds > 0)
        .collect();
    let mut findings = TaskFindings {
        task: task.to_owned(),
        title: context.task_title(task),
        method: ea.to_owned(),
        converged: converged(scores, task, ea),
        competitors,
        verdicts: verdict_findings,
        variants,
        strongest,
        readings: readings(verdicts, task),
        collapses,
        never_reaches,
        subtask_pairing,
        equalities,
        identical: identical(scores, task),
        oracle,
        reach_pretraining,
        aggregators,
        prediction: None,
        cause: None,
    };
    findings.prediction = context
        .predictions
        .iter()
        .find(|p| p.task == task)
        .map(|p| prediction_outcome(scores, &findings, p));
    findings.cause = cause(&findings);
    Some(findings)
}

/// One judgement as a finding: its claim, verdict, deciding comparison and reason.
#[must_use]
pub fn verdict_finding(judgement: &Judgement) -> VerdictFinding {
    VerdictFinding {
        claim: judgement.claim.id.to_owned(),
        verdict: judgement.verdict,
        deciding: deciding(judgement),
        reason: judgement.reason.clone(),
    }
}

/// A per-seed test as a [`Deciding`].
fn per_seed(test: &ReachingComparison) -> Deciding {
    Deciding {
        versus: test.versus.clone(),
        metric: test.metric.to_owned(),
        estimand: if test.metric == claims::REACHED {
            Estimand::SeedsReaching
        } else {
            Estimand::SeedsStableReaching
        },
        estimate: share_difference(test),
        interval: None,
        margin: None,
        test: Test::ExactSignTest,
        p_holm: test.p_holm,
        pairs: None,
        seeds: Some(SeedPair {
            method: test.reached.0,
            versus: test.reached.1,
            of: test.n,
        }),
    }
}

#[expect(clippy::cast_precision_loss, reason = "seed counts are far below 2^52")]
fn share_difference(test: &ReachingComparison) -> f64 {
    if test.n == 0 {
        0.0
    } else {
        (test.reached.0 as f64 - test.reached.1 as f64) / test.n as f64
    }
}

/// The comparison that decides `judgement`'s verdict: the per-seed test when it came nearer
/// to settling an inconclusive verdict than the deciding comparison (an inconclusive C3 whose
/// greedy SDs are all 0 is decided by who reaches stably), or the per-seed test the verdict
/// was judged on when the metrics could not be compared; otherwise the deciding comparison's
/// mean paired difference with its exact interval, and the p that it lies within the margin
/// for an equivalent verdict, beyond it for any other.
fn deciding(judgement: &Judgement) -> Option<Deciding> {
    let comparison = judgement.deciding_comparison();
    if let Some(c) = comparison
        && judgement.verdict == Verdict::Inconclusive
        && let Some(test) = judgement
            .reaching
            .iter()
            .find(|t| t.versus == c.versus && t.p_holm < c.p_holm)
    {
        return Some(per_seed(test));
    }
    let Some(c) = comparison else {
        // Judged on per-seed reaching: the test the reason states.
        return judgement
            .reaching
            .iter()
            .find(|t| {
                judgement
                    .reason
                    .starts_with(&claims::per_seed_reason(&judgement.method, t))
            })
            .map(per_seed);
    };
    let paired = &c.paired;
    Some(Deciding {
        versus: c.versus.clone(),
        metric: c.metric.column.to_owned(),
        estimand: Estimand::PairedMeanDifference,
        estimate: paired.estimate,
        interval: paired.low.zip(paired.high).map(|(low, high)| [low, high]),
        margin: c.margin,
        test: if judgement.verdict == Verdict::Equivalent {
            Test::SignFlipWithinMargin
        } else {
            Test::SignFlipBeyondMargin
        },
        p_holm: if judgement.verdict == Verdict::Equivalent {
            paired.p_equivalence_holm.unwrap_or(1.0)
        } else {
            c.p_holm
        },
        pairs: Some(paired.n),
        seeds: None,
    })
}

fn strongest_control(
    context: &ReportContext,
    verdicts: &Verdicts,
    task: &str,
    ea: &str,
    judgements: &[&Judgement],
    c: &ControlVerdict,
) -> Option<StrongestControl> {
    let family = context.method(task, &c.control)?.control?;
    let env_steps = |method: &str| {
        verdicts
            .overviews
            .iter()
            .find(|o| o.task == task && o.method == method)
            .map_or(0.0, |o| o.env_steps_total)
    };
    let overturns = judgements
        .iter()
        .any(|b| b.claim.id == c.judgement.claim.id && rank(c.judgement.verdict) < rank(b.verdict));
    Some(StrongestControl {
        claim: c.judgement.claim.id.to_owned(),
        control: c.control.clone(),
        family,
        metric: c.metric.to_owned(),
        control_iqm: c.control_iqm,
        method_iqm: verdicts
            .estimate(task, ea, c.metric)
            .and_then(|e| e.iqm.as_ref())
            .map(|i| i.estimate),
        converged: converged(&verdicts.scores, task, &c.control),
        env_steps: [env_steps(&c.control), env_steps(ea)],
        verdict: c.judgement.verdict,
        deciding: deciding(&c.judgement),
        reason: c.judgement.reason.clone(),
        overturns,
    })
}

fn readings(verdicts: &Verdicts, task: &str) -> Option<ReadingsFinding> {
    let survival: Vec<_> = crate::sensitivity::survival(&verdicts.sensitivity)
        .into_iter()
        .filter(|s| s.task == task)
        .collect();
    if survival.is_empty() {
        // Readings that were not run in this process, but whose survival is known.
        let known: Vec<_> = verdicts
            .survives_readings
            .iter()
            .filter(|s| s.task == task)
            .collect();
        if known.is_empty() {
            return None;
        }
        return Some(ReadingsFinding {
            holds: known
                .iter()
                .filter(|s| s.holds)
                .map(|s| (s.claim.clone(), 0))
                .collect(),
            flips: known
                .iter()
                .filter(|s| !s.holds)
                .map(|s| (s.claim.clone(), Vec::new()))
                .collect(),
        });
    }
    let flipping = |claim: &str| -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for row in verdicts
            .sensitivity
            .iter()
            .filter(|r| r.task == task && r.claim == claim && r.change == Change::Flips)
        {
            if !names.contains(&row.reading) {
                names.push(row.reading.clone());
            }
        }
        names
    };
    Some(ReadingsFinding {
        holds: survival
            .iter()
            .filter(|s| s.survives)
            .map(|s| (s.claim.to_owned(), s.readings))
            .collect(),
        flips: survival
            .iter()
            .filter(|s| !s.survives)
            .map(|s| (s.claim.to_owned(), flipping(s.claim)))
            .collect(),
    })
}

fn collapses(
    verdicts: &Verdicts,
    task: &str,
    ea: &str,
    judgements: &[&Judgement],
) -> Option<Collapses> {
    let seeds = collapsed_seeds(&verdicts.scores, task, ea);
    if seeds.is_empty() {
        return None;
    }
    let rejudged = verdicts
        .without_collapses
        .iter()
        .filter(|j| j.task == task && j.method == ea)
        .filter_map(|j| {
            let before = judgements.iter().find(|b| b.claim.id == j.claim.id)?;
            Some(Rejudgement {
                claim: j.claim.id.to_owned(),
                was: before.verdict,
                now: j.verdict,
            })
        })
        .collect();
    Some(Collapses {
        seeds,
        of: outcomes(&verdicts.scores, task, ea).len(),
        rejudged,
    })
}

/// The reward reference `method` learns from, when it never reached the target on any seed.
fn never_reaches(
    context: &ReportContext,
    scores: &[FinalScore],
    task: &str,
    method: &str,
) -> Option<Diagnosis> {
    let seeds = outcomes(scores, task, method);
    if seeds.is_empty() || seeds.iter().any(|(_, o)| *o != RunOutcome::NeverReached) {
        return None;
    }
    let reference: &RewardReference = context
        .experiment(task)?
        .reward_references
        .iter()
        .find(|r| r.methods.iter().any(|m| m == method))?;
    Some(Diagnosis {
        repairs: reference.repairs.clone(),
        subtasks: reference
            .subtasks
            .iter()
            .map(|s| (s.name.clone(), s.reaching_pays()))
            .collect(),
    })
}

/// The frozen sub-task-alone controls of `task` (config order), from their configs.
fn frozen_subtasks_alone<'a>(context: &'a ReportContext, task: &str) -> Vec<&'a str> {
    context.experiment(task).map_or_else(Vec::new, |e| {
        e.methods
            .iter()
            .filter(|m| {
                matches!(
                    m.control,
                    Some(ControlFamily::SubtaskAlone { learns: false, .. })
                )
            })
            .map(|m| m.label.as_str())
            .collect()
    })
}

/// Paired by seed: (seeds both ran, both converged, only `method`, only `versus`, of those
/// only `versus` converged on, the seeds `method` collapsed on).
fn discordant(scores: &[FinalScore], task: &str, method: &str, versus: &str) -> Pairing {
    let theirs = outcomes(scores, task, versus);
    let mut pairing = Pairing {
        control: versus.to_owned(),
        paired: 0,
        both: 0,
        only_method: 0,
        only_control: 0,
        method_collapsed: 0,
    };
    for (seed, a) in outcomes(scores, task, method) {
        if let Some(&(_, b)) = theirs.iter().find(|(s, _)| *s == seed) {
            pairing.paired += 1;
            let (ca, cb) = (a == RunOutcome::Converged, b == RunOutcome::Converged);
            pairing.both += usize::from(ca && cb);
            pairing.only_method += usize::from(ca && !cb);
            pairing.only_control += usize::from(cb && !ca);
            pairing.method_collapsed += usize::from(cb && a == RunOutcome::Collapsed);
        }
    }
    pairing
}

/// The frozen sub-task alone that converges on the most seeds (the first on a tie): the
/// sub-task that carries the task.
#[must_use]
pub fn strongest_subtask_alone<'a>(
    context: &'a ReportContext,
    scores: &[FinalScore],
    task: &str,
) -> Option<&'a str> {
    frozen_subtasks_alone(context, task)
        .into_iter()
        .filter(|m| !outcomes(scores, task, m).is_empty())
        .fold(None, |best: Option<(&str, usize)>, m| {
            let hits = converged(scores, task, m).hits;
            match best {
                Some((_, b)) if b >= hits => best,
                _ => Some((m, hits)),
            }
        })
        .map(|(m, _)| m)
}

fn subtask_pairing(
    context: &ReportContext,
    scores: &[FinalScore],
    task: &str,
    ea: &str,
) -> Option<Pairing> {
    let control = strongest_subtask_alone(context, scores, task)?;
    let pairing = discordant(scores, task, ea, control);
    (pairing.paired > 0).then_some(pairing)
}

/// Whether two runs of one seed end the same: final-window steps and return, the greedy
/// episode and the outcome (the training curves before may differ, e.g. a collapse episode).
fn same_ending(a: &FinalScore, b: &FinalScore) -> bool {
    a.seed == b.seed
        && a.final_steps == b.final_steps
        && a.final_return == b.final_return
        && a.greedy_steps == b.greedy_steps
        && a.outcome == b.outcome
}

/// The parts of two runs of one seed that end the same which still differ; empty when the
/// runs are the same all through (every score but the environment steps, which count each
/// method's own pre-training).
fn differing_parts(a: &FinalScore, b: &FinalScore) -> Vec<&'static str> {
    let mut parts = Vec::new();
    if a.fluctuation_steps != b.fluctuation_steps || a.fluctuation_return != b.fluctuation_return {
        parts.push("the training curve's SD");
    }
    if a.collapse_episode != b.collapse_episode || a.reaching_episodes != b.reaching_episodes {
        parts.push("the collapse episode or the count of reaching episodes");
    }
    if a.greedy_evaluations != b.greedy_evaluations
        || a.stable_reaching != b.stable_reaching
        || a.fluctuation_greedy_steps != b.fluctuation_greedy_steps
        || a.fluctuation_greedy_return != b.fluctuation_greedy_return
    {
        parts.push("the greedy evaluations");
    }
    if a.success_rate != b.success_rate {
        parts.push("the final-window success");
    }
    if a.reach_average_reward != b.reach_average_reward
        || a.reach_time != b.reach_time
        || a.reach_retention_time != b.reach_retention_time
        || a.retention_decay != b.retention_decay
    {
        parts.push("the robot's reaching scores");
    }
    parts
}

/// How far `method` and `other` agree seed for seed on `task`.
#[must_use]
pub fn equality(scores: &[FinalScore], task: &str, method: &str, other: &str) -> Equality {
    let rows = |m: &str| -> Vec<&FinalScore> {
        scores
            .iter()
            .filter(|s| s.task == task && s.method == m)
            .collect()
    };
    let theirs = rows(other);
    let mut eq = Equality {
        method: method.to_owned(),
        other: other.to_owned(),
        both: 0,
        end_same: 0,
        all_through: 0,
        differing: Vec::new(),
    };
    for a in rows(method) {
        let Some(b) = theirs.iter().find(|b| b.seed == a.seed) else {
            continue;
        };
        eq.both += 1;
        if !same_ending(a, b) {
            continue;
        }
        eq.end_same += 1;
        let parts = differing_parts(a, b);
        eq.all_through += usize::from(parts.is_empty());
        for part in parts {
            match eq.differing.iter_mut().find(|(p, _)| p == part) {
                Some((_, n)) => *n += 1,
                None => eq.differing.push((part.to_owned(), 1)),
            }
        }
    }
    eq
}

/// Each EA-MADM variant against each frozen sub-task alone: the pairs that end the same on at
/// least half the seeds.
fn equalities(context: &ReportContext, scores: &[FinalScore], task: &str) -> Vec<Equality> {
    let alone = frozen_subtasks_alone(context, task);
    let mut found = Vec::new();
    for (method, _, kind) in claims::methods(scores, task) {
        if !claims::is_under_test(kind) {
            continue;
        }
        for other in &alone {
            let eq = equality(scores, task, method, other);
            if eq.both > 0 && 2 * eq.end_same >= eq.both {
                found.push(eq);
            }
        }
    }
    found
}

/// Whether two runs of one seed have the same scores (every score but the environment
/// steps, which count each method's own pre-training or warm-up).
fn same_scores(a: &FinalScore, b: &FinalScore) -> bool {
    same_ending(a, b) && differing_parts(a, b).is_empty()
}

/// Each method whose per-seed scores equal an earlier method's on every seed, with the
/// first such method.
fn identical(scores: &[FinalScore], task: &str) -> Vec<Identical> {
    let methods = claims::methods(scores, task);
    let rows = |m: &str| -> Vec<&FinalScore> {
        let mut rows: Vec<&FinalScore> = scores
            .iter()
            .filter(|s| s.task == task && s.method == m)
            .collect();
        rows.sort_by_key(|s| s.seed);
        rows
    };
    let mut found: Vec<Identical> = Vec::new();
    for (i, &(method, _, _)) in methods.iter().enumerate() {
        let mine = rows(method);
        let same_as = methods[..i].iter().find(|&&(earlier, _, _)| {
            // Compare with the representative of a group, not with its copies.
            !found.iter().any(|f| f.method == earlier) && {
                let theirs = rows(earlier);
                theirs.len() == mine.len()
                    && !mine.is_empty()
                    && mine.iter().zip(&theirs).all(|(a, b)| same_scores(a, b))
            }
        });
        if let Some(&(earlier, _, _)) = same_as {
            found.push(Identical {
                method: method.to_owned(),
                same_as: earlier.to_owned(),
                seeds: mine.len(),
            });
        }
    }
    found
}

/// `predicted` against the run: EA-MADM's best verdict, how often it ends as the sub-task
/// alone it was predicted to follow, and whether its decision reaches with exact values.
fn prediction_outcome(
    scores: &[FinalScore],
    findings: &TaskFindings,
    predicted: &PredictionFacts,
) -> PredictionOutcome {
    let best_verdict = findings
        .verdicts
        .iter()
        .map(|v| v.verdict)
        .max_by_key(|v| rank(*v));
    let same = equality(scores, &findings.task, &findings.method, &predicted.follows);
    let ends_as_followed = SeedCount {
        hits: same.end_same,
        seeds: same.both,
    };
    let oracle_reaches = findings
        .oracle
        .iter()
        .find(|o| o.decision == findings.method && o.values == OracleValues::Exact)
        .map(|o| SeedCount {
            hits: o.reaches_initial as usize,
            seeds: o.seeds as usize,
        });
    let held = best_verdict.is_none_or(|v| rank(v) <= rank(predicted.best_verdict))
        && ends_as_followed.seeds > 0
        && 2 * ends_as_followed.hits > ends_as_followed.seeds
        && oracle_reaches.is_none_or(|o| (o.hits > 0) == predicted.oracle_reaches);
    PredictionOutcome {
        predicted: predicted.clone(),
        best_verdict,
        ends_as_followed,
        oracle_reaches,
        held,
    }
}

/// The oracle finding of EA-MADM's own decision on the task, if the run has one.
fn ea_madm_oracle(findings: &TaskFindings) -> Option<&OracleFinding> {
    findings
        .oracle
        .iter()
        .find(|o| o.decision == findings.method)
}

/// The one cause the first screen names: the sub-task values when even exact ones lead
/// nowhere (the oracle); pre-training when EA-MADM never reaches and its reach sub-task never
/// reached in pre-training; the rewards when EA-MADM never reaches; a reward- or
/// budget-matched control that overturns a verdict; the Manhattan-bound ceiling when exact
/// values make the decision the reach sub-task alone; a sub-task alone no worse than EA-MADM;
/// else none.
fn cause(findings: &TaskFindings) -> Option<Cause> {
    let oracle = ea_madm_oracle(findings);
    if let Some(o) = oracle
        .filter(|o| o.values == OracleValues::Exact && o.failing_part == FailingPart::SubtaskValues)
        && let Some((follows, _)) = &o.best_subtask_alone
    {
        return Some(Cause::SubtaskValues {
            reaches: SeedCount {
                hits: o.reaches_initial as usize,
                seeds: o.seeds as usize,
            },
            follows: follows.clone(),
            follows_on: SeedCount {
                hits: o.equals_subtask_alone as usize,
                seeds: o.seeds as usize,
            },
            optimum_steps: o.optimum_steps,
            manhattan_steps: o.manhattan_steps,
        });
    }
    if findings.converged.hits == 0
        && let Some(reach) = findings
            .reach_pretraining
            .iter()
            .find(|p| p.method == findings.method)
        && reach.seeds > 0
        && reach.seeds_reaching == 0
    {
        return Some(Cause::Pretraining {
            reach: reach.clone(),
            diagnosis: findings.never_reaches.clone(),
        });
    }
    if let Some(diagnosis) = &findings.never_reaches {
        return Some(Cause::Rewards {
            diagnosis: diagnosis.clone(),
        });
    }
    let overturning: Vec<&StrongestControl> = findings
        .strongest
        .iter()
        .filter(|s| {
            s.overturns
                && matches!(
                    s.family,
                    ControlFamily::RewardMatched | ControlFamily::BudgetMatched
                )
        })
        .collect();
    if let Some(first) = overturning.first() {
        return Some(Cause::MatchedControl {
            control: first.control.clone(),
            family: first.family,
            claims: overturning
                .iter()
                .filter(|s| s.control == first.control)
                .map(|s| s.claim.clone())
                .collect(),
            verdict: first.verdict,
        });
    }
    if let Some(o) = oracle.filter(|o| {
        o.at_manhattan_bound == Some(true)
            && o.values == OracleValues::Exact
            && o.seeds > 0
            && 2 * o.equals_subtask_alone > o.seeds
    }) && let (Some(optimum_steps), Some((follows, _))) =
        (o.optimum_steps, &o.best_subtask_alone)
    {
        return Some(Cause::Ceiling {
            optimum_steps,
            follows: follows.clone(),
            follows_on: SeedCount {
                hits: o.equals_subtask_alone as usize,
                seeds: o.seeds as usize,
            },
            reaches: SeedCount {
                hits: o.reaches_initial as usize,
                seeds: o.seeds as usize,
            },
        });
    }
    let alone: Vec<&StrongestControl> = findings
        .strongest
        .iter()
        .filter(|s| {
            matches!(s.family, ControlFamily::SubtaskAlone { .. })
                && s.verdict != Verdict::Supported
        })
        .collect();
    let first = alone.first()?;
    let better = alone.iter().any(|s| s.verdict == Verdict::Contradicted);
    let end_same = findings
        .equalities
        .iter()
        .find(|e| e.method == findings.method && e.other == first.control)
        .map(|e| SeedCount {
            hits: e.end_same,
            seeds: e.both,
        });
    Some(Cause::SubtaskAlone {
        control: first.control.clone(),
        claims: alone
            .iter()
            .filter(|s| s.control == first.control)
            .map(|s| s.claim.clone())
            .collect(),
        better,
        end_same,
    })
}
