//! The paper's claims ([`paper::CLAIMS`]) tested on per-seed final scores
//! ([`scores`](crate::scores)), with a verdict per claim × task × method under test, and
//! `claims.csv`.
//!
//! # Who is compared with whom
//!
//! - **Methods under test**: every EA-MADM method of the task (`kind = ea_madm`): the paper's
//!   `ea-madm`, each ablation, and each EA-MADM control (e.g. tree thresholds below 1).
//! - **Competitors**: the paper's own competitors, the methods with `role = paper` that are not
//!   EA-MADM (ε-greedy, ε-decreasing, softmax). Controls that change a competitor (budget- or
//!   reward-matched) are reported beside them, never used to judge the paper's claim.
//! - **Fairness both ways** ([`VersusSet`]): a repaired reading of EA-MADM on the robot
//!   ([`SAME_REWARDS`]: its sub-task rewards or its decision differ from the paper's) is judged
//!   twice, against the paper's competitors on the task reward and against the competitors
//!   trained on its own sub-task rewards (`COMPETITOR-shaped-repaired`, …). Each judgement
//!   names its set, and so does each row of `claims.csv` (`versus_set`). The paper's EA-MADM is
//!   judged against the paper's competitors only: that is the headline.
//!
//! # The statistics (all from [`stats`], seeded, so reports are reproducible)
//!
//! For a metric (a column of `final-scores.csv`) the sample of a method is its per-seed values
//! (seeds with an empty cell, e.g. no reaching episode, are left out and counted). Per method:
//! the interquartile mean (IQM) with a percentile-bootstrap 95 % interval. Per comparison of a
//! method under test `X` with a competitor `Y`: the bootstrap 95 % interval of
//! `IQM(X) − IQM(Y)` (X and Y resampled independently), the two-sided permutation p-value of
//! that difference, and the probability of improvement (`P(X better than Y)`, ties ½, oriented
//! by the metric's direction). Holm–Bonferroni adjusts the p-values across every comparison of
//! one claim × task × method under test (all its metrics × all competitors).
//!
//! # The verdict rule (stated in the report too)
//!
//! A comparison **favours** X when the difference's estimate goes the claim's way, its 95 %
//! interval excludes 0 and its Holm-adjusted p is below 0.05; it **favours** Y under the same
//! conditions the other way; otherwise it settles nothing. Per claim × task × method:
//!
//! - when X has fewer than two seeds with a value on one of the claim's metrics (it seldom or
//!   never reaches the target, so C4 has nothing to average), the claim is judged on per-seed
//!   reaching instead ([`judge_by_reaching`]: the exact paired sign test against each
//!   competitor, Holm over them): `contradicted` when a competitor reaches on significantly
//!   more seeds, `inconclusive` when one reaches on 2 or more seeds but not significantly
//!   more, `untestable` when none reaches on 2 or more seeds either (the reason gives the
//!   counts);
//! - `untestable` when no competitor has two seeds with a value (the reason is given);
//! - `contradicted` when any comparison favours a competitor;
//! - `supported` when every testable comparison favours X;
//! - `equivalent` when every comparison is equivalent (Holm-adjusted TOST p below α that the
//!   mean paired difference lies within the metric's margin on the task, [`Margins`]: the
//!   task supplies them, `eamadm::Task::equivalence_margins`; a metric without one is never
//!   equivalent, and "favours" on a metric with one needs an IQM difference beyond it);
//! - `inconclusive` otherwise.
//!
//! # C3: fluctuation that cannot be won by being stuck
//!
//! C3 is judged on the greedy policy evaluated during training (`fluctuation_greedy_steps`,
//! `fluctuation_greedy_return`: the SDs over the second half's periodic greedy evaluations,
//! which only a **stable-reaching** seed has, one whose every such evaluation reached; see
//! [`scores`](crate::scores)). Against each competitor Y two things are compared:
//!
//! - **(a)** the stable-reaching seeds, paired by seed: the exact sign test on the seeds only
//!   one side is stable-reaching on (McNemar), Holm over the competitors ([`per_seed_tests`],
//!   claims.csv metric [`STABLE_REACHING`]);
//! - **(b)** the greedy fluctuation over the seeds where each side has a value, by the same
//!   statistics, margins ([`Margins`]) and Holm as C1/C2.
//!
//! A comparison of a metric with Y favours a side when (a) or (b) does and the other does not
//! favour the other side ([`combine`]); a competitor with no (b) comparison (fewer than two
//! stable-reaching seeds) enters by (a) alone. The verdict rule above then applies to these
//! combined outcomes; `equivalent` also needs every (a) without a discordant seed (a
//! per-seed test has no margin, so equivalence there is the same seeds stable-reaching). When X itself has fewer than
//! two stable-reaching seeds, (a) alone decides as [`judge_by_reaching`] does. A seed stuck at
//! the step cap is thus a failure, never the most stable seed. The training curves' SDs
//! (`fluctuation_steps`, `fluctuation_return`) are C3's **secondary** metrics: estimated and
//! compared (their own Holm) in claims.csv with an empty `verdict`, never deciding it.
//!
//! Comparisons with a competitor that has fewer than two values are listed as untestable and
//! left out of the rule (that competitor reaches the target in fewer than two seeds).

use std::io::Write;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::Role;
use crate::columns::{Column, FieldType};
use crate::paper_claims::{self as paper, Claim, ClaimMetric, Direction};
use crate::scores::{FinalScore, RunOutcome};
use crate::stats::paired::differences;
use crate::stats::{self, Bootstrap, Interval, SignFlipTest, Statistic, StatsError};

/// The significance level of the verdict rule.
pub const ALPHA: f64 = 0.05;

/// The kind of the EA-MADM methods (`eamadm::Method::kind_name`).
const EA_MADM_KIND: &str = "ea_madm";

/// Claims that cannot be evaluated.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ClaimsError {
    /// A statistic failed.
    #[error("claim {claim}, task {task}, method {method}, metric {metric}: {source}")]
    Stats {
        /// The claim (empty for a single-method estimate).
        claim: String,
        /// The task.
        task: String,
        /// The method.
        method: String,
        /// The metric.
        metric: String,
        /// Why.
        #[source]
        source: Box<StatsError>,
    },
    /// A task's equivalence margin is not a finite positive number.
    #[error(
        "task {task}, metric {column}: equivalence margin {value} is not a finite positive number"
    )]
    BadMargin {
        /// The task.
        task: String,
        /// The metric's column.
        column: String,
        /// The margin given.
        value: f64,
    },
    /// Writing `claims.csv` failed.
    #[error("claims CSV: {0}")]
    Csv(#[from] csv::Error),
    /// A cell of a table read back (`sensitivity.csv`) holds a value no writer writes.
    #[error("{file}, row {row}, column {column}: unknown value {value:?}")]
    BadCell {
        /// The table's file name.
        file: &'static str,
        /// The data row (1 = first row after the header).
        row: usize,
        /// The column.
        column: &'static str,
        /// What it holds.
        value: String,
    },
}

/// A metric's region of practical equivalence on one task: a difference within `±value` (in
/// the metric's unit) is no difference in practice. The task's definition supplies it
/// (`eamadm::Task::equivalence_margins` derives each from the task's rewards and control
/// period), so this crate holds no reward scheme.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Margin {
    /// The column of `final-scores.csv` it applies to.
    pub column: String,
    /// The margin, positive and finite, in the column's unit.
    pub value: f64,
    /// Why this value, in one line (the report's rule paragraph and docs/paper-notes.md
    /// state it).
    pub reason: String,
}

/// The equivalence margins of every task × metric that has one ([`Margin`]). A metric
/// without a margin on a task is never judged equivalent there, and "favours" on it needs no
/// effect size.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Margins {
    /// (task, margin), in insertion order.
    entries: Vec<(String, Margin)>,
}

impl Margins {
    /// No margin at all.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the margins of `task` (a later margin of the same task and column replaces the
    /// earlier one).
    ///
    /// # Errors
    /// [`ClaimsError::BadMargin`] naming the task and column when a value is not positive and
    /// finite.
    pub fn insert(&mut self, task: &str, margins: &[Margin]) -> Result<(), ClaimsError> {
        for margin in margins {
            if !(margin.value.is_finite() && margin.value > 0.0) {
                return Err(ClaimsError::BadMargin {
                    task: task.to_owned(),
                    column: margin.column.clone(),
                    value: margin.value,
                });
            }
            self.entries
                .retain(|(t, m)| !(t == task && m.column == margin.column));
            self.entries.push((task.to_owned(), margin.clone()));
        }
        Ok(())
    }

    /// The margin of `column` on `task`, if it has one.
    #[must_use]
    pub fn get(&self, task: &str, column: &str) -> Option<&Margin> {
        self.entries
            .iter()
            .find(|(t, m)| t == task && m.column == column)
            .map(|(_, m)| m)
    }

    /// The margin's value of `column` on `task`, if it has one.
    #[must_use]
    pub fn value(&self, task: &str, column: &str) -> Option<f64> {
        self.get(task, column).map(|m| m.value)
    }

    /// Every (task, margin), in insertion order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &Margin)> {
        self.entries.iter().map(|(t, m)| (t.as_str(), m))
    }

    /// Whether there is no margin.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// The settings of the statistics behind the verdicts.
#[derive(Debug, Clone, PartialEq)]
pub struct ClaimOptions {
    /// Bootstrap of IQM intervals and of differences (the same seed for every call, so each
    /// number is a function of its two samples only).
    pub bootstrap: Bootstrap,
    /// The sign-flip distribution of the mean paired difference, which decides every
    /// comparison: enumerated up to [`EXACT_MAX_PAIRS`](stats::EXACT_MAX_PAIRS) pairs (then
    /// `sign_flip` is not used), else `sign_flip.resamples` random sign vectors drawn from a
    /// stream of their own per comparison: `sign_flip.seed` mixed with the bits of the
    /// differences ([`stream_seed`]).
    pub sign_flip: SignFlipTest,
    /// Significance level of the verdict rule.
    pub alpha: f64,
    /// The equivalence margin of each task × metric (none: nothing is judged equivalent).
    pub margins: Margins,
}

impl Default for ClaimOptions {
    /// 10 000 bootstrap resamples at 95 % (the descriptive IQM intervals), 100 000 sign vectors beyond
    /// the exact enumeration, seed 0, α = [`ALPHA`], no margins (the run's come with its
    /// tasks: `ReportContext::margins`).
    fn default() -> Self {
        Self {
            bootstrap: Bootstrap::default(),
            sign_flip: SignFlipTest {
                resamples: 100_000,
                seed: 0,
            },
            alpha: ALPHA,
            margins: Margins::new(),
        }
    }
}

/// The verdict on one claim × task × method under test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every testable comparison favours the method under test.
    Supported,
    /// A competitor is significantly better on one of the claim's metrics.
    Contradicted,
    /// Every comparison shows equivalence: the mean paired difference lies within the metric's
    /// margin on the task ([`Margins`]) by a Holm-adjusted TOST p below α.
    Equivalent,
    /// Neither.
    Inconclusive,
    /// The data cannot test the claim (see the reason).
    Untestable,
}

impl Verdict {
    /// `supported`, `contradicted`, `inconclusive` or `untestable`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Supported => "supported",
            Self::Contradicted => "contradicted",
            Self::Equivalent => "equivalent",
            Self::Inconclusive => "inconclusive",
            Self::Untestable => "untestable",
        }
    }
}

/// What one comparison settles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ComparisonOutcome {
    /// Significantly better for the method under test (the claim's way).
    FavoursMethod,
    /// Significantly better for the competitor.
    FavoursCompetitor,
    /// Not significant, the interval includes 0, or the effect lies within the metric's
    /// equivalence margin.
    Unsettled,
}

/// One method under test against one competitor on one metric of a claim, paired by seed: the
/// mean paired difference with its exact interval and tests decides ([`PairedComparison`]);
/// the IQM difference and the probability of improvement describe.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// The metric.
    pub metric: ClaimMetric,
    /// The competitor's label.
    pub versus: String,
    /// Seeds with a value: the method's and the competitor's.
    pub n: (usize, usize),
    /// The deciding comparison, paired by seed (runs of one seed share their random streams).
    pub paired: PairedComparison,
    /// The deciding p-value: that the mean paired difference lies beyond the metric's margin on
    /// one side ([`PairedComparison::p_beyond`]; with no margin, that it is not 0).
    pub p_value: f64,
    /// `p_value` Holm-adjusted across the claim × task × method's informative comparisons (and,
    /// for C3, its per-seed tests: one family); `p_value` itself for an uninformative one.
    pub p_holm: f64,
    /// The metric's equivalence margin on the task ([`Margins`]); `None` when it has none.
    pub margin: Option<f64>,
    /// False when every paired value of both methods is one and the same number (the metric
    /// sits at a bound for both, e.g. a greedy SD of 0 on every stable-reaching seed): such a
    /// comparison shows neither a difference nor an equivalence: it takes no part in Holm, and
    /// in the verdict it settles nothing and is not equivalent.
    pub informative: bool,
    /// What it settles.
    pub outcome: ComparisonOutcome,
    /// IQM(method) − IQM(competitor) over all seeds with a value, with its bootstrap interval:
    /// descriptive (the IQM trims the seeds at the step cap that the mean counts).
    pub iqm_difference: Interval,
    /// Probability that a random seed of the method beats one of the competitor (the metric's
    /// direction; ties count ½): descriptive.
    pub p_improvement: f64,
}

/// The estimand of every verdict: the mean of the paired differences method − competitor.
/// Every seed counts — a seed that collapsed to the step cap is a failure of its method, and
/// robust locations hide it (the IQM trims 25 % of seeds at each end, the Hodges–Lehmann
/// estimator breaks down at 29 %, and Task II's EA-MADM collapses on 30 %); the mean of
/// differences is the difference of means, the paper's average curves' estimand; and its
/// sign-flip distribution is exact and cheap to enumerate ([`stats::SignFlipMeans`]).
pub const PAIRED_STATISTIC: Statistic = Statistic::Mean;

/// A comparison paired by seed: the seeds where both methods have a value, the mean of their
/// differences (method − competitor) with the interval and tests of its sign-flip
/// distribution ([`stats::SignFlipMeans`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairedComparison {
    /// Seeds paired.
    pub n: usize,
    /// Mean of the paired differences.
    pub estimate: f64,
    /// Lower end of its 95 % (1 − α) sign-flip interval; `None` when unbounded (fewer than 6
    /// pairs: no location can be rejected).
    pub low: Option<f64>,
    /// Upper end; `None` when unbounded.
    pub high: Option<f64>,
    /// Two-sided sign-flip p-value of a mean paired difference of 0.
    pub p_value: f64,
    /// p-value that the mean lies beyond `±margin` on one side (at most α exactly when the
    /// interval lies beyond the margin); without a margin, `p_value`.
    pub p_beyond: f64,
    /// p-value that the mean lies within `±margin` (at most α exactly when the interval lies
    /// inside it: two one-sided tests at α/2 each); `None` when there is no margin.
    pub p_equivalence: Option<f64>,
    /// `p_equivalence` Holm-adjusted across the claim × task × method's informative
    /// comparisons.
    pub p_equivalence_holm: Option<f64>,
    /// Whether every sign vector was counted (at most
    /// [`EXACT_MAX_PAIRS`](stats::EXACT_MAX_PAIRS) pairs); else they were drawn.
    pub exact: bool,
    /// The Monte-Carlo standard error of `p_beyond` when the sign vectors were drawn.
    pub p_monte_carlo_se: Option<f64>,
}

impl PairedComparison {
    /// Whether the interval lies wholly beyond `±margin` (0 without one) on one side.
    #[must_use]
    pub fn lies_beyond(&self, margin: Option<f64>) -> bool {
        let m = margin.unwrap_or(0.0);
        self.high.is_some_and(|h| h < -m) || self.low.is_some_and(|l| l > m)
    }

    /// Whether the interval lies inside `(−margin, margin)`; false without a margin.
    #[must_use]
    pub fn lies_within(&self, margin: Option<f64>) -> bool {
        match (margin, self.low, self.high) {
            (Some(m), Some(l), Some(h)) => -m < l && h < m,
            _ => false,
        }
    }
}

/// The values of `column` of `method` and `versus` on `task` on the seeds where both have
/// one, in seed order.
#[must_use]
pub fn paired_values(
    scores: &[FinalScore],
    task: &str,
    method: &str,
    versus: &str,
    column: &str,
) -> (Vec<f64>, Vec<f64>) {
    let mut pairs: Vec<(u64, f64, f64)> = scores
        .iter()
        .filter(|row| row.task == task && row.method == method)
        .filter_map(|row| {
            let x = row.value(column)?;
            let y = scores
                .iter()
                .find(|other| {
                    other.task == task && other.method == versus && other.seed == row.seed
                })?
                .value(column)?;
            Some((row.seed, x, y))
        })
        .collect();
    pairs.sort_by_key(|&(seed, _, _)| seed);
    pairs.into_iter().map(|(_, x, y)| (x, y)).unzip()
}

/// The seed of the random sign vectors of one comparison's differences `d` (drawn only beyond
/// [`EXACT_MAX_PAIRS`](stats::EXACT_MAX_PAIRS) pairs): `base` mixed with the bits of `d`
/// (FNV-1a, then `SplitMix64`'s finaliser), so that each comparison has a stream of its own and
/// the same comparison gets the same stream whichever judgement makes it.
#[must_use]
pub fn stream_seed(base: u64, d: &[f64]) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for value in d {
        for byte in value.to_bits().to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    }
    let mut z = base ^ hash;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The paired comparison of `x` and `y` (seed-aligned) with the metric's equivalence
/// `margin`, or `None` with fewer than 2 pairs.
///
/// # Errors
/// A [`StatsError`] for non-finite values.
pub fn compare_paired(
    x: &[f64],
    y: &[f64],
    margin: Option<f64>,
    options: &ClaimOptions,
) -> Result<Option<PairedComparison>, StatsError> {
    if x.len() < 2 {
        return Ok(None);
    }
    let d = differences(x, y)?;
    let means = stats::SignFlipMeans::new(
        &d,
        options.sign_flip.resamples,
        stream_seed(options.sign_flip.seed, &d),
    )?;
    let (low, high) = means.interval(1.0 - options.alpha)?;
    let p_value = means.p_two_sided(0.0);
    let p_beyond = means.beyond_margin(margin.unwrap_or(0.0))?;
    let p_equivalence = margin.map(|m| means.within_margin(m)).transpose()?;
    Ok(Some(PairedComparison {
        n: d.len(),
        estimate: means.mean(),
        low,
        high,
        p_value,
        p_beyond,
        p_equivalence,
        p_equivalence_holm: p_equivalence,
        exact: means.is_exact(),
        p_monte_carlo_se: means.monte_carlo_se(p_beyond),
    }))
}

/// A comparison that could not be made, and why.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Untested {
    /// The metric's column.
    pub metric: &'static str,
    /// The competitor's label.
    pub versus: String,
    /// Why.
    pub reason: String,
}

/// The verdict on one claim × task × method under test, with every comparison behind it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Judgement {
    /// The claim.
    pub claim: &'static Claim,
    /// The task (experiment name).
    pub task: String,
    /// The method under test.
    pub method: String,
    /// Its role (`paper` for the paper's own EA-MADM).
    pub role: Role,
    /// Whom it is judged against ([`versus_sets`]).
    pub versus_set: VersusSet,
    /// The verdict.
    pub verdict: Verdict,
    /// Why, in words computed from the numbers (e.g. the untestable reason).
    pub reason: String,
    /// The comparisons, metric-major, competitor order as in the scores.
    pub comparisons: Vec<Comparison>,
    /// The comparisons that could not be made.
    pub untested: Vec<Untested>,
    /// The comparison that decides the verdict: for `supported` the weakest (largest Holm p),
    /// for `contradicted` the strongest against (smallest Holm p), for `inconclusive` the
    /// weakest of those that do not favour the method.
    pub deciding: Option<usize>,
    /// The per-seed tests against each competitor (paired exact sign test): when the method
    /// has too few seeds with a value to compare the claim's metrics, the reaching test that
    /// decides the verdict instead ([`judge_by_reaching`]); for a claim with a
    /// [`per_seed`](Claim::per_seed) column (C3: `stable_reaching`), that column's test,
    /// which takes part in the verdict ([`combine`]); empty otherwise.
    pub reaching: Vec<ReachingComparison>,
    /// The comparisons on the claim's [`secondary`](Claim::secondary) metrics (C3: the
    /// training curves' SDs), Holm-adjusted among themselves; they do not decide the verdict.
    pub secondary: Vec<Comparison>,
}

impl Judgement {
    /// The deciding comparison, if any.
    #[must_use]
    pub fn deciding_comparison(&self) -> Option<&Comparison> {
        self.deciding.and_then(|i| self.comparisons.get(i))
    }
}

/// The method under test against one competitor on per-seed reaching ([`reached`]), paired
/// by seed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReachingComparison {
    /// The per-seed column tested: [`REACHED`] ([`reached`]) or `stable_reaching`
    /// ([`stable_reaching`]).
    pub metric: &'static str,
    /// The competitor's label.
    pub versus: String,
    /// Seeds paired (both methods ran them).
    pub n: usize,
    /// Paired seeds the method reaches on, and the competitor.
    pub reached: (usize, usize),
    /// Discordant seeds: only the method reaches, only the competitor reaches.
    pub discordant: (u64, u64),
    /// Exact two-sided sign test on the discordant seeds (McNemar's exact test).
    pub p_value: f64,
    /// `p_value` Holm-adjusted across the competitors.
    pub p_holm: f64,
    /// What it settles: the side that reaches on more seeds is favoured when `p_holm` is
    /// below α.
    pub outcome: ComparisonOutcome,
}

/// The `metric` of the `claims.csv` rows of a [`ReachingComparison`].
pub const REACHED: &str = "reached";

/// The `estimate` of a [`ReachingComparison`]'s row: the share of paired seeds the method
/// reaches on minus the competitor's.
#[must_use]
#[expect(clippy::cast_precision_loss, reason = "seed counts are far below 2^52")]
pub fn reaching_difference(test: &ReachingComparison) -> f64 {
    (test.reached.0 as f64 - test.reached.1 as f64) / test.n as f64
}

/// Whether a run reached the target at all: its greedy evaluation episode or any training
/// episode did.
#[must_use]
pub fn reached(row: &FinalScore) -> bool {
    row.greedy_reached || row.reaching_episodes > 0
}

/// The `metric` of the `claims.csv` rows of C3's per-seed test: the `stable_reaching` column.
pub const STABLE_REACHING: &str = "stable_reaching";

/// Whether a run is a stable-reaching seed (C3): every periodic greedy evaluation of the
/// second half of training reached the target. A run without such evaluations (an empty
/// cell) is not.
#[must_use]
pub fn stable_reaching(row: &FinalScore) -> bool {
    row.stable_reaching == Some(true)
}

/// The per-seed yes/no of a per-seed column ([`STABLE_REACHING`], else [`reached`]).
fn per_seed_flag(column: &str) -> fn(&FinalScore) -> bool {
    if column == STABLE_REACHING {
        stable_reaching
    } else {
        reached
    }
}

/// How the reasons say that a seed has the per-seed property of `column`.
pub fn per_seed_words(column: &str) -> &'static str {
    if column == STABLE_REACHING {
        "reaches in every greedy evaluation of the second half"
    } else {
        "reaches"
    }
}

/// What a metric comparison and the per-seed test with the same competitor settle together
/// (C3): a side is favoured when either favours it and the other does not favour the other
/// side; when they favour opposite sides, nothing is settled.
#[must_use]
pub fn combine(metric: ComparisonOutcome, per_seed: ComparisonOutcome) -> ComparisonOutcome {
    match (metric, per_seed) {
        (x, ComparisonOutcome::Unsettled) | (ComparisonOutcome::Unsettled, x) => x,
        (x, y) if x == y => x,
        _ => ComparisonOutcome::Unsettled,
    }
}

/// The per-seed tests of `method` against each of `competitors` on `task` on the per-seed
/// column `column` ([`REACHED`] or [`STABLE_REACHING`]), paired by seed: the exact two-sided
/// sign test on the discordant seeds (McNemar's exact test), Holm-adjusted across the
/// competitors; a side is favoured when it has the property on more discordant seeds and the
/// Holm p is below `alpha`.
///
/// # Errors
/// A [`StatsError`] from Holm (it cannot fail on sign-test p-values).
pub fn per_seed_tests(
    scores: &[FinalScore],
    task: &str,
    method: &str,
    competitors: &[&str],
    column: &'static str,
    alpha: f64,
) -> Result<Vec<ReachingComparison>, StatsError> {
    let flag = per_seed_flag(column);
    let per_seed = |method: &str| -> Vec<(u64, bool)> {
        let mut seeds: Vec<(u64, bool)> = scores
            .iter()
            .filter(|row| row.task == task && row.method == method)
            .map(|row| (row.seed, flag(row)))
            .collect();
        seeds.sort_unstable();
        seeds
    };
    let mine = per_seed(method);
    let mut tests = Vec::new();
    for &versus in competitors {
        let theirs = per_seed(versus);
        let (mut n, mut reached_mine, mut reached_theirs) = (0, 0, 0);
        let (mut wins, mut losses) = (0_u64, 0_u64);
        for &(seed, a) in &mine {
            if let Some(&(_, b)) = theirs.iter().find(|(s, _)| *s == seed) {
                n += 1;
                reached_mine += usize::from(a);
                reached_theirs += usize::from(b);
                wins += u64::from(a && !b);
                losses += u64::from(b && !a);
            }
        }
        if n > 0 {
            tests.push(ReachingComparison {
                metric: column,
                versus: versus.to_owned(),
                n,
                reached: (reached_mine, reached_theirs),
                discordant: (wins, losses),
                p_value: stats::sign_test(wins, losses),
                p_holm: 1.0,
                outcome: ComparisonOutcome::Unsettled,
            });
        }
    }
    if !tests.is_empty() {
        let raw: Vec<f64> = tests.iter().map(|t| t.p_value).collect();
        for (test, p) in tests.iter_mut().zip(stats::holm(&raw)?) {
            test.p_holm = p;
            test.outcome = per_seed_outcome(test, alpha);
        }
    }
    Ok(tests)
}

/// A per-seed test in words, e.g. "EA-MADM reaches on 3/20 seeds, softmax on 11/20; exact
/// paired sign test, Holm p < 0.001".
pub fn per_seed_reason(method: &str, test: &ReachingComparison) -> String {
    format!(
        "{} {} on {}/{n} seeds, {} on {}/{n}; exact paired sign test, Holm p {}",
        paper::method_title(method),
        per_seed_words(test.metric),
        test.reached.0,
        paper::method_title(&test.versus),
        test.reached.1,
        p_text(test.p_holm),
        n = test.n
    )
}

/// A p-value as the report prints it: `< 0.001` or three decimals.
fn p_text(p: f64) -> String {
    if p < 0.001 {
        "< 0.001".to_owned()
    } else {
        format!("{p:.3}")
    }
}

/// The verdict of a claim whose metrics the method under test cannot be compared on (fewer
/// than 2 seeds with a value, because it seldom or never reaches the target; `lacking` says
/// so), decided by per-seed reaching ([`reached`]) against each competitor, paired by seed
/// (runs of one seed share their random streams): the exact sign test on the discordant seeds
/// (McNemar's exact test), Holm-adjusted across the competitors.
///
/// - `untestable` when no competitor reaches on 2 or more seeds either (neither reaches);
/// - `contradicted` when a competitor reaches on more seeds with a Holm p below `alpha` (the
///   strongest such comparison decides);
/// - `inconclusive` otherwise (the competitor reaching on most seeds decides).
///
/// The reason states the counts and the p-value, e.g. "EA-MADM reaches on 0/20 seeds, softmax
/// on 11/20; exact paired sign test, Holm p < 0.001".
///
/// # Errors
/// A [`StatsError`] from Holm (it cannot fail on sign-test p-values).
pub fn judge_by_reaching(
    scores: &[FinalScore],
    judgement: &mut Judgement,
    competitors: &[&str],
    column: &'static str,
    lacking: &str,
    alpha: f64,
) -> Result<(), StatsError> {
    let tests = per_seed_tests(
        scores,
        &judgement.task,
        &judgement.method,
        competitors,
        column,
        alpha,
    )?;
    let flag = per_seed_flag(column);
    let mine: Vec<bool> = scores
        .iter()
        .filter(|row| row.task == judgement.task && row.method == judgement.method)
        .map(flag)
        .collect();
    let title = paper::method_title(&judgement.method);
    let mine_reached = mine.iter().filter(|r| **r).count();
    let best = tests
        .iter()
        .enumerate()
        .max_by(|(i, a), (j, b)| a.reached.1.cmp(&b.reached.1).then(j.cmp(i)))
        .map(|(i, _)| i);
    let Some(best) = best.filter(|&i| tests[i].reached.1 >= 2) else {
        let counts: Vec<String> = tests
            .iter()
            .map(|t| format!("{} {}/{}", paper::method_title(&t.versus), t.reached.1, t.n))
            .collect();
        judgement.verdict = Verdict::Untestable;
        let words = per_seed_words(column);
        judgement.reason = format!(
            "{lacking}, and no competitor {words} on 2 or more seeds: {title} {words} on \
             {mine_reached}/{}, {}",
            mine.len(),
            if counts.is_empty() {
                "no competitor shares its seeds".to_owned()
            } else {
                counts.join(", ")
            }
        );
        judgement.reaching = tests;
        return Ok(());
    };
    let against = tests
        .iter()
        .enumerate()
        .filter(|(_, t)| t.outcome == ComparisonOutcome::FavoursCompetitor)
        .min_by(|(i, a), (j, b)| a.p_holm.total_cmp(&b.p_holm).then(i.cmp(j)))
        .map(|(i, _)| i);
    judgement.verdict = if against.is_some() {
        Verdict::Contradicted
    } else {
        Verdict::Inconclusive
    };
    let deciding = &tests[against.unwrap_or(best)];
    judgement.reason = format!(
        "{}; {lacking}",
        per_seed_reason(&judgement.method, deciding)
    );
    judgement.reaching = tests;
    Ok(())
}

/// One method's IQM of one metric over seeds, with its bootstrap interval.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// The task.
    pub task: String,
    /// The method.
    pub method: String,
    /// Its role.
    pub role: Role,
    /// The metric's column.
    pub metric: &'static str,
    /// Seeds with a value.
    pub n: usize,
    /// Seeds in all.
    pub seeds: usize,
    /// The IQM and its 95 % interval; `None` when no seed has a value.
    pub iqm: Option<Interval>,
}

/// Whom a method under test is judged against (issue 21 item 4, fairness both ways): every
/// method under test against the paper's competitors on the task reward, and a repaired
/// reading of EA-MADM ([`SAME_REWARDS`]) also against the competitors trained on its own
/// sub-task rewards.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VersusSet {
    /// The paper's competitors (role `paper`, not EA-MADM), which learn from the task reward
    /// with its goal bonus. The headline verdicts are these.
    Paper,
    /// The controls `COMPETITOR-SUFFIX` of the method's [`SameRewards`] entry: each paper
    /// competitor learning from the standardised signal of the method's own sub-task rewards.
    SameRewards,
}

impl VersusSet {
    /// `paper` or `same_rewards` (the `versus_set` column of `claims.csv`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Paper => "paper",
            Self::SameRewards => "same_rewards",
        }
    }
}

/// A repaired reading of EA-MADM and the competitors trained on the same rewards.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SameRewards {
    /// The reading's label.
    pub method: &'static str,
    /// The suffix of its competitors' labels: `COMPETITOR-SUFFIX` for each paper competitor.
    pub suffix: &'static str,
    /// The rewards both learn from, in words.
    pub rewards: &'static str,
}

/// The robot's repaired readings (`eamadm::paper::robot_repairs`) and their reward-matched
/// competitors. The literal `ea-madm` is not listed: the paper judges it against its
/// competitors on the task reward, and so does the headline. `eamadm` checks that the preset's
/// controls of each entry learn from exactly the reading's sub-task rewards.
pub const SAME_REWARDS: [SameRewards; 4] = [
    SameRewards {
        method: "ea-madm-goal-bonus",
        suffix: "shaped-goal-bonus",
        rewards: "the sub-task rewards with the reach sub-task's goal bonus",
    },
    SameRewards {
        method: "ea-madm-end-penalties",
        suffix: "shaped-end-penalties",
        rewards: "the sub-task rewards with the end penalties in every sub-task",
    },
    SameRewards {
        method: "ea-madm-normalised",
        suffix: "shaped",
        rewards: "the paper's sub-task rewards (normalising changes the decision, not the rewards)",
    },
    SameRewards {
        method: "ea-madm-repaired",
        suffix: "shaped-repaired",
        rewards: "the sub-task rewards with both repairs",
    },
];

/// The [`SAME_REWARDS`] entry of `method`, if it is a repaired reading.
#[must_use]
pub fn same_rewards(method: &str) -> Option<&'static SameRewards> {
    SAME_REWARDS.iter().find(|entry| entry.method == method)
}

/// The sets a method under test is judged against, the headline's ([`VersusSet::Paper`])
/// first.
#[must_use]
pub fn versus_sets(method: &str) -> Vec<VersusSet> {
    let mut sets = vec![VersusSet::Paper];
    if same_rewards(method).is_some() {
        sets.push(VersusSet::SameRewards);
    }
    sets
}

/// The competitors of `method` on `task` in `set`, in score order: the paper's competitors, or
/// for [`VersusSet::SameRewards`] the methods labelled `COMPETITOR-SUFFIX` of its
/// [`SameRewards`] entry that are not EA-MADM (empty when none was run).
#[must_use]
pub fn competitors_in<'a>(
    scores: &'a [FinalScore],
    task: &str,
    method: &str,
    set: VersusSet,
) -> Vec<&'a str> {
    let methods = methods(scores, task);
    let paper: Vec<&str> = methods
        .iter()
        .filter(|&&(_, role, kind)| is_competitor(role, kind))
        .map(|&(label, _, _)| label)
        .collect();
    match (set, same_rewards(method)) {
        (VersusSet::Paper, _) => paper,
        (VersusSet::SameRewards, None) => Vec::new(),
        (VersusSet::SameRewards, Some(entry)) => paper
            .iter()
            .filter_map(|competitor| {
                let label = format!("{competitor}-{}", entry.suffix);
                methods
                    .iter()
                    .find(|&&(m, _, kind)| m == label && !is_under_test(kind))
                    .map(|&(m, _, _)| m)
            })
            .collect(),
    }
}

/// The reason of a judgement whose set of competitors was not run.
fn none_run(method: &str, set: VersusSet) -> String {
    match (set, same_rewards(method)) {
        (VersusSet::SameRewards, Some(entry)) => {
            format!("none of them (`COMPETITOR-{}`) was run", entry.suffix)
        }
        (VersusSet::SameRewards, None) => {
            format!("{method} has no competitors on the same rewards")
        }
        (VersusSet::Paper, _) => "none of the paper's competitors was run".to_owned(),
    }
}

/// The tasks of `scores`, in first-appearance order.
#[must_use]
pub fn tasks(scores: &[FinalScore]) -> Vec<&str> {
    let mut tasks: Vec<&str> = Vec::new();
    for row in scores {
        if !tasks.contains(&row.task.as_str()) {
            tasks.push(&row.task);
        }
    }
    tasks
}

/// The methods of `task` in `scores` with their role and kind, in first-appearance order.
#[must_use]
pub fn methods<'a>(scores: &'a [FinalScore], task: &str) -> Vec<(&'a str, Role, &'a str)> {
    let mut methods: Vec<(&str, Role, &str)> = Vec::new();
    for row in scores.iter().filter(|row| row.task == task) {
        if !methods.iter().any(|(m, _, _)| *m == row.method) {
            methods.push((&row.method, row.role, &row.kind));
        }
    }
    methods
}

/// The per-seed values of `column` for `method` on `task` (empty cells left out), in score
/// order, and the number of seeds in all.
#[must_use]
pub fn values(scores: &[FinalScore], task: &str, method: &str, column: &str) -> (Vec<f64>, usize) {
    let rows: Vec<&FinalScore> = scores
        .iter()
        .filter(|row| row.task == task && row.method == method)
        .collect();
    let values = rows.iter().filter_map(|row| row.value(column)).collect();
    (values, rows.len())
}

/// Whether `kind` is EA-MADM's: such methods are the ones under test.
#[must_use]
pub fn is_under_test(kind: &str) -> bool {
    kind == EA_MADM_KIND
}

/// Whether a method is one of the paper's competitors.
#[must_use]
pub fn is_competitor(role: Role, kind: &str) -> bool {
    role == Role::Paper && !is_under_test(kind)
}

/// The IQM with its bootstrap interval of every metric of every claim, for every method of
/// every task in `scores` (task, method, then the claims' metrics in order, each once).
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn estimates(
    scores: &[FinalScore],
    options: &ClaimOptions,
) -> Result<Vec<Estimate>, ClaimsError> {
    estimates_where(scores, options, |_, _| true)
}

/// The metrics whose estimate every method's overview states on every task, judged or not:
/// the final steps and return with their fluctuations (each task's scores table) and the
/// robot's average reward over reaching episodes (its ranking sentence).
pub const OVERVIEW_COLUMNS: [&str; 5] = [
    "final_steps",
    "final_return",
    "fluctuation_steps",
    "fluctuation_return",
    "reach_average_reward",
];

/// The estimates [`estimates`] computes that a verdict or the report states: for every method
/// of every task, the [`OVERVIEW_COLUMNS`] and the metrics of every claim judged on the task
/// (`judgements`: [`judge`]'s), in [`estimates`]' order. The others (the metrics of a claim
/// no method is judged on there) are nowhere shown, though each is 10,000 resamples of
/// every seed (docs/paper-notes.md §24.3).
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn stated_estimates(
    scores: &[FinalScore],
    judgements: &[Judgement],
    options: &ClaimOptions,
) -> Result<Vec<Estimate>, ClaimsError> {
    estimates_where(scores, options, |task, column| {
        OVERVIEW_COLUMNS.contains(&column)
            || judgements.iter().any(|j| {
                j.task == task
                    && j.claim
                        .metrics
                        .iter()
                        .chain(j.claim.secondary)
                        .any(|m| m.column == column)
            })
    })
}

/// The estimates of every method of every task in `scores`, of the claim columns `wanted`
/// keeps (given the task and the column).
fn estimates_where(
    scores: &[FinalScore],
    options: &ClaimOptions,
    wanted: impl Fn(&str, &str) -> bool,
) -> Result<Vec<Estimate>, ClaimsError> {
    let mut jobs = Vec::new();
    for task in tasks(scores) {
        let columns: Vec<&'static str> = claim_columns()
            .into_iter()
            .filter(|column| wanted(task, column))
            .collect();
        for (method, role, _) in methods(scores, task) {
            jobs.push((task, method, role, columns.clone()));
        }
    }
    let per_method: Vec<Vec<Estimate>> = jobs
        .par_iter()
        .map(|(task, method, role, columns)| {
            method_estimates(scores, task, method, *role, columns, &options.bootstrap)
        })
        .collect::<Result<_, _>>()?;
    Ok(per_method.into_iter().flatten().collect())
}

/// [`estimate`] of each of `columns` for one method, the bootstrap's draws shared among its
/// metrics with a value on equally many seeds ([`Bootstrap::intervals`]: the same bits).
fn method_estimates(
    scores: &[FinalScore],
    task: &str,
    method: &str,
    role: Role,
    columns: &[&'static str],
    bootstrap: &Bootstrap,
) -> Result<Vec<Estimate>, ClaimsError> {
    let values: Vec<(Vec<f64>, usize)> = columns
        .iter()
        .map(|column| self::values(scores, task, method, column))
        .collect();
    let samples: Vec<&[f64]> = values
        .iter()
        .map(|(x, _)| x.as_slice())
        .filter(|x| !x.is_empty())
        .collect();
    let Ok(intervals) = bootstrap.intervals(&samples, Statistic::Iqm) else {
        // Name the metric that fails, as one estimate at a time does.
        return columns
            .iter()
            .map(|&metric| estimate(scores, task, method, role, metric, bootstrap))
            .collect();
    };
    let mut intervals = intervals.into_iter();
    Ok(columns
        .iter()
        .zip(values)
        .map(|(&metric, (x, seeds))| {
            let iqm = if x.is_empty() { None } else { intervals.next() };
            Estimate::of(task, method, role, metric, (x.len(), seeds), iqm)
        })
        .collect())
}

impl Estimate {
    /// The estimate of `metric` for `method` on `task`, with a value on `n` of `seeds` seeds.
    fn of(
        task: &str,
        method: &str,
        role: Role,
        metric: &'static str,
        (n, seeds): (usize, usize),
        iqm: Option<Interval>,
    ) -> Self {
        Self {
            task: task.to_owned(),
            method: method.to_owned(),
            role,
            metric,
            n,
            seeds,
            iqm,
        }
    }
}

/// The IQM and interval of one method's metric.
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn estimate(
    scores: &[FinalScore],
    task: &str,
    method: &str,
    role: Role,
    metric: &'static str,
    bootstrap: &Bootstrap,
) -> Result<Estimate, ClaimsError> {
    let (x, seeds) = values(scores, task, method, metric);
    let iqm = if x.is_empty() {
        None
    } else {
        Some(
            bootstrap
                .interval(&x, Statistic::Iqm)
                .map_err(|source| ClaimsError::Stats {
                    claim: String::new(),
                    task: task.to_owned(),
                    method: method.to_owned(),
                    metric: metric.to_owned(),
                    source: Box::new(source),
                })?,
        )
    };
    Ok(Estimate::of(
        task,
        method,
        role,
        metric,
        (x.len(), seeds),
        iqm,
    ))
}

/// Every claim metric's column (the deciding ones, then the secondary ones, of each claim),
/// each once, in claim order.
#[must_use]
pub fn claim_columns() -> Vec<&'static str> {
    let mut columns: Vec<&'static str> = Vec::new();
    for claim in &paper::CLAIMS {
        for metric in claim.metrics.iter().chain(claim.secondary) {
            if !columns.contains(&metric.column) {
                columns.push(metric.column);
            }
        }
    }
    columns
}

/// Judges every claim on every task of `scores` it is made on, for every method under test
/// (claim order, then task order, then method order).
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn judge(scores: &[FinalScore], options: &ClaimOptions) -> Result<Vec<Judgement>, ClaimsError> {
    let present = tasks(scores);
    let mut jobs = Vec::new();
    for claim in &paper::CLAIMS {
        for task in claim.tasks.iter().filter(|t| present.contains(t)) {
            for (method, role, kind) in methods(scores, task) {
                if is_under_test(kind) {
                    for set in versus_sets(method) {
                        jobs.push((claim, *task, method, role, set));
                    }
                }
            }
        }
    }
    jobs.par_iter()
        .map(|&(claim, task, method, role, set)| {
            judge_against(scores, claim, task, method, role, set, options)
        })
        .collect()
}

/// Judges one claim on one task for one method under test against the paper's competitors
/// ([`VersusSet::Paper`]).
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn judge_one(
    scores: &[FinalScore],
    claim: &'static Claim,
    task: &str,
    method: &str,
    role: Role,
    options: &ClaimOptions,
) -> Result<Judgement, ClaimsError> {
    judge_against(scores, claim, task, method, role, VersusSet::Paper, options)
}

/// Judges one claim on one task for one method under test against the competitors of `set`
/// ([`competitors_in`]). The reason of a [`VersusSet::SameRewards`] judgement opens with the
/// rewards its competitors learn from.
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn judge_against(
    scores: &[FinalScore],
    claim: &'static Claim,
    task: &str,
    method: &str,
    role: Role,
    set: VersusSet,
    options: &ClaimOptions,
) -> Result<Judgement, ClaimsError> {
    let competitors = competitors_in(scores, task, method, set);
    judge_labels(
        scores,
        claim,
        task,
        method,
        role,
        set,
        &competitors,
        options,
    )
}

/// Judges one claim on one task for one method under test against `competitors` (labels of
/// methods of `task`) by the rule of [`judge_one`]: what the report uses to judge EA-MADM
/// against a control (the strongest one) exactly as against the paper's competitors. The
/// judgement's set is [`VersusSet::Paper`] (the rule is the paper's; only the competitors
/// differ).
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn judge_against_competitors(
    scores: &[FinalScore],
    claim: &'static Claim,
    task: &str,
    method: &str,
    role: Role,
    competitors: &[&str],
    options: &ClaimOptions,
) -> Result<Judgement, ClaimsError> {
    judge_labels(
        scores,
        claim,
        task,
        method,
        role,
        VersusSet::Paper,
        competitors,
        options,
    )
}

/// [`judge_versus`] against the given competitors.
#[expect(
    clippy::too_many_arguments,
    reason = "the claim × task × method × set being judged, the competitors and the options: a struct would only rename them"
)]
fn judge_labels(
    scores: &[FinalScore],
    claim: &'static Claim,
    task: &str,
    method: &str,
    role: Role,
    set: VersusSet,
    competitors: &[&str],
    options: &ClaimOptions,
) -> Result<Judgement, ClaimsError> {
    let mut judgement = judge_versus(scores, claim, task, method, role, set, competitors, options)?;
    if let (VersusSet::SameRewards, Some(entry)) = (set, same_rewards(method))
        && !judgement.reason.is_empty()
    {
        judgement.reason = format!(
            "against the competitors trained on {}: {}",
            entry.rewards, judgement.reason
        );
    }
    Ok(judgement)
}

/// [`judge_labels`] without the words on the set.
#[expect(
    clippy::too_many_arguments,
    reason = "the claim × task × method × set being judged, the competitors and the options: a struct would only rename them"
)]
fn judge_versus(
    scores: &[FinalScore],
    claim: &'static Claim,
    task: &str,
    method: &str,
    role: Role,
    set: VersusSet,
    competitors: &[&str],
    options: &ClaimOptions,
) -> Result<Judgement, ClaimsError> {
    let competitors = competitors.to_vec();
    let error = |metric: &str, source| ClaimsError::Stats {
        claim: claim.id.to_owned(),
        task: task.to_owned(),
        method: method.to_owned(),
        metric: metric.to_owned(),
        source: Box::new(source),
    };
    let mut judgement = Judgement {
        claim,
        task: task.to_owned(),
        method: method.to_owned(),
        role,
        versus_set: set,
        verdict: Verdict::Untestable,
        reason: String::new(),
        comparisons: Vec::new(),
        untested: Vec::new(),
        deciding: None,
        reaching: Vec::new(),
        secondary: Vec::new(),
    };
    if competitors.is_empty() {
        judgement.reason = none_run(method, set);
        return Ok(judgement);
    }
    // The secondary metrics' comparisons (their own Holm family); those that cannot be made
    // are left out.
    (judgement.secondary, _) =
        metric_comparisons(scores, claim.secondary, task, method, &competitors, options)
            .map_err(|(metric, e)| error(metric, e))?;
    adjust(&mut judgement.secondary, &mut [], options.alpha).map_err(|e| error("(holm)", e))?;
    let per_seed_column = claim.per_seed.unwrap_or(REACHED);
    for metric in claim.metrics {
        let (x, seeds) = values(scores, task, method, metric.column);
        if x.len() < 2 {
            let lacking = format!(
                "{} has a `{}` value in {} of {seeds} seeds (it needs {})",
                paper::method_title(method),
                metric.column,
                x.len(),
                if per_seed_column == STABLE_REACHING {
                    "a seed whose every greedy evaluation of the second half reaches, 2 or \
                     more of them"
                } else {
                    "a reaching episode"
                }
            );
            judge_by_reaching(
                scores,
                &mut judgement,
                &competitors,
                per_seed_column,
                &lacking,
                options.alpha,
            )
            .map_err(|e| error(per_seed_column, e))?;
            return Ok(judgement);
        }
    }
    let (comparisons, untested) =
        metric_comparisons(scores, claim.metrics, task, method, &competitors, options)
            .map_err(|(metric, e)| error(metric, e))?;
    judgement.comparisons = comparisons;
    judgement.untested = untested;
    if let Some(column) = claim.per_seed {
        judgement.reaching =
            per_seed_tests(scores, task, method, &competitors, column, options.alpha)
                .map_err(|e| error(column, e))?;
    }
    if judgement.comparisons.is_empty() && judgement.reaching.is_empty() {
        judgement.reason =
            "no competitor has a value in 2 or more seeds (none reaches the target)".to_owned();
        return Ok(judgement);
    }
    // One Holm family: the informative comparisons of every metric and competitor, and the
    // per-seed tests (C3).
    adjust(
        &mut judgement.comparisons,
        &mut judgement.reaching,
        options.alpha,
    )
    .map_err(|e| error("(holm)", e))?;
    decide(&mut judgement, options.alpha);
    Ok(judgement)
}

/// The comparisons made and those that could not be.
type MetricComparisons = (Vec<Comparison>, Vec<Untested>);

/// The comparisons of `method` with each competitor on `metrics` (both sides need 2 or more
/// seeds with a value, and 2 or more seeds where both have one; the others are listed as
/// untested), not yet Holm-adjusted ([`adjust`]).
///
/// # Errors
/// The metric and the [`StatsError`] when a statistic fails.
fn metric_comparisons(
    scores: &[FinalScore],
    metrics: &[ClaimMetric],
    task: &str,
    method: &str,
    competitors: &[&str],
    options: &ClaimOptions,
) -> Result<MetricComparisons, (&'static str, StatsError)> {
    let mut comparisons = Vec::new();
    let mut untested = Vec::new();
    for metric in metrics {
        let (x, _) = values(scores, task, method, metric.column);
        for &versus in competitors {
            let (y, versus_seeds) = values(scores, task, versus, metric.column);
            if x.len() < 2 {
                continue;
            }
            if y.len() < 2 {
                untested.push(Untested {
                    metric: metric.column,
                    versus: versus.to_owned(),
                    reason: format!(
                        "{} has a value in {} of {versus_seeds} seeds",
                        paper::method_title(versus),
                        y.len()
                    ),
                });
                continue;
            }
            let margin = options.margins.value(task, metric.column);
            let (px, py) = paired_values(scores, task, method, versus, metric.column);
            match compare(&x, &y, (&px, &py), *metric, versus, margin, options)
                .map_err(|e| (metric.column, e))?
            {
                Some(comparison) => comparisons.push(comparison),
                None => untested.push(Untested {
                    metric: metric.column,
                    versus: versus.to_owned(),
                    reason: format!(
                        "{} and {} both have a value on {} seed(s) only",
                        paper::method_title(method),
                        paper::method_title(versus),
                        px.len()
                    ),
                }),
            }
        }
    }
    Ok((comparisons, untested))
}

/// Holm-adjusts one family — the informative `comparisons` and the per-seed `tests` together
/// — and sets their outcomes at level `alpha`; the equivalence p-values of the informative
/// comparisons form a family of their own (a comparison without a margin enters it with 1).
/// An uninformative comparison keeps its raw p-values and settles nothing.
///
/// # Errors
/// A [`StatsError`] from Holm (it cannot fail on p-values).
fn adjust(
    comparisons: &mut [Comparison],
    tests: &mut [ReachingComparison],
    alpha: f64,
) -> Result<(), StatsError> {
    let raw: Vec<f64> = comparisons
        .iter()
        .filter(|c| c.informative)
        .map(|c| c.p_value)
        .chain(tests.iter().map(|t| t.p_value))
        .collect();
    if !raw.is_empty() {
        let mut adjusted = stats::holm(&raw)?.into_iter();
        for c in comparisons.iter_mut().filter(|c| c.informative) {
            c.p_holm = adjusted.next().unwrap_or(1.0);
        }
        for t in tests.iter_mut() {
            t.p_holm = adjusted.next().unwrap_or(1.0);
            t.outcome = per_seed_outcome(t, alpha);
        }
    }
    let equivalence: Vec<f64> = comparisons
        .iter()
        .filter(|c| c.informative)
        .map(|c| c.paired.p_equivalence.unwrap_or(1.0))
        .collect();
    if !equivalence.is_empty() {
        let mut adjusted = stats::holm(&equivalence)?.into_iter();
        for c in comparisons.iter_mut().filter(|c| c.informative) {
            let p = adjusted.next().unwrap_or(1.0);
            c.paired.p_equivalence_holm = c.paired.p_equivalence.map(|_| p);
        }
    }
    for c in comparisons.iter_mut() {
        if !c.informative {
            c.p_holm = c.p_value;
            c.paired.p_equivalence_holm = None;
        }
        c.outcome = outcome(c, alpha);
    }
    Ok(())
}

/// Whether a comparison is equivalent at level `alpha`: informative, and its Holm-adjusted
/// equivalence p below `alpha` (its interval lies inside the margin).
#[must_use]
pub fn is_equivalent(comparison: &Comparison, alpha: f64) -> bool {
    comparison.informative
        && comparison
            .paired
            .p_equivalence_holm
            .is_some_and(|p| p < alpha)
}

/// The verdict of a judgement whose comparisons and per-seed tests are made (see the module
/// docs): each metric comparison counts with the outcome [`combine`]d with the per-seed test
/// against the same competitor (C3), and a per-seed test against a competitor with no metric
/// comparison counts by itself. An uninformative comparison counts as settling nothing (so a
/// claim cannot be supported past a tie at a bound) and as not equivalent.
fn decide(judgement: &mut Judgement, alpha: f64) {
    let comparisons = &judgement.comparisons;
    let tests = &judgement.reaching;
    let test_of = |versus: &str| tests.iter().find(|t| t.versus == versus);
    let effective: Vec<ComparisonOutcome> = comparisons
        .iter()
        .map(|c| test_of(&c.versus).map_or(c.outcome, |t| combine(c.outcome, t.outcome)))
        .collect();
    let alone: Vec<&ReachingComparison> = tests
        .iter()
        .filter(|t| !comparisons.iter().any(|c| c.versus == t.versus))
        .collect();
    let all = || {
        effective
            .iter()
            .copied()
            .chain(alone.iter().map(|t| t.outcome))
    };
    // The deciding comparison among those `keep` keeps, the informative ones first.
    let by_p = |pick_max: bool, keep: &dyn Fn(usize, &Comparison) -> bool| {
        let best = |informative: bool| {
            comparisons
                .iter()
                .enumerate()
                .filter(|&(i, c)| c.informative == informative && keep(i, c))
                .max_by(|(i, a), (j, b)| {
                    let order = a.p_holm.total_cmp(&b.p_holm);
                    // Ties go to the earlier comparison either way.
                    (if pick_max { order } else { order.reverse() }).then(j.cmp(i))
                })
                .map(|(i, _)| i)
        };
        best(true).or_else(|| best(false))
    };
    // The per-seed test that decides when no metric comparison can (ties: the earlier one).
    let test_by_p = |pick_max: bool, outcome: Option<ComparisonOutcome>| {
        tests
            .iter()
            .enumerate()
            .filter(|(_, t)| outcome.is_none_or(|o| t.outcome == o))
            .max_by(|(i, a), (j, b)| {
                let order = a.p_holm.total_cmp(&b.p_holm);
                (if pick_max { order } else { order.reverse() }).then(j.cmp(i))
            })
            .map(|(_, t)| t)
    };
    let (verdict, deciding, test) = if all().any(|o| o == ComparisonOutcome::FavoursCompetitor) {
        // A metric comparison that favours the competitor by itself shows the numbers;
        // otherwise the per-seed test that does.
        match by_p(false, &|i, c| {
            effective[i] == ComparisonOutcome::FavoursCompetitor
                && c.outcome == ComparisonOutcome::FavoursCompetitor
        }) {
            Some(i) => (Verdict::Contradicted, Some(i), None),
            None => (
                Verdict::Contradicted,
                None,
                test_by_p(false, Some(ComparisonOutcome::FavoursCompetitor)),
            ),
        }
    } else if all().all(|o| o == ComparisonOutcome::FavoursMethod) {
        match by_p(true, &|_, c| c.outcome == ComparisonOutcome::FavoursMethod) {
            Some(i) => (Verdict::Supported, Some(i), None),
            None => (
                Verdict::Supported,
                None,
                test_by_p(true, Some(ComparisonOutcome::FavoursMethod)),
            ),
        }
    } else if alone.is_empty()
        // A per-seed test has no margin: only the same seeds on both sides is equivalence
        // there ("unsettled" with discordant seeds is absence of evidence, not equivalence);
        // an uninformative comparison shows no equivalence either.
        && tests.iter().all(|t| t.discordant == (0, 0))
        && !comparisons.is_empty()
        && comparisons.iter().all(|c| is_equivalent(c, alpha))
    {
        // The weakest equivalence decides.
        let weakest = comparisons
            .iter()
            .enumerate()
            .max_by(|(i, a), (j, b)| {
                let p = |c: &Comparison| c.paired.p_equivalence_holm.unwrap_or(1.0);
                p(a).total_cmp(&p(b)).then(j.cmp(i))
            })
            .map(|(i, _)| i);
        (Verdict::Equivalent, weakest, None)
    } else {
        // The weakest informative comparison that does not favour the method; else the
        // per-seed test (C3 with uninformative greedy SDs is decided by who reaches stably);
        // else an uninformative comparison.
        let pick = by_p(true, &|i, _| {
            effective[i] != ComparisonOutcome::FavoursMethod
        });
        match pick {
            Some(i) if comparisons[i].informative => (Verdict::Inconclusive, Some(i), None),
            _ => {
                match test_by_p(true, Some(ComparisonOutcome::Unsettled))
                    .or_else(|| test_by_p(true, None))
                {
                    Some(test) => (Verdict::Inconclusive, None, Some(test)),
                    None => (Verdict::Inconclusive, pick, None),
                }
            }
        }
    };
    judgement.verdict = verdict;
    judgement.deciding = deciding;
    if let Some(test) = test {
        judgement.reason = per_seed_reason(&judgement.method, test);
    }
}

/// One comparison of the per-seed values `x` of a method with the values `y` of `versus` on
/// `metric` with its equivalence `margin` on the task, deciding on the seed-paired values
/// `pairs` ([`compare_paired`]): `None` with fewer than 2 pairs. The IQM difference with its
/// bootstrap interval and the probability of improvement (over all of `x` and `y`) describe.
/// `p_holm` is the raw p and the outcome is judged on it (the caller adjusts).
///
/// # Errors
/// A [`StatsError`] for empty or non-finite samples.
pub fn compare(
    x: &[f64],
    y: &[f64],
    pairs: (&[f64], &[f64]),
    metric: ClaimMetric,
    versus: &str,
    margin: Option<f64>,
    options: &ClaimOptions,
) -> Result<Option<Comparison>, StatsError> {
    let (px, py) = pairs;
    let Some(paired) = compare_paired(px, py, margin, options)? else {
        return Ok(None);
    };
    let iqm_difference = options.bootstrap.difference(x, y, Statistic::Iqm)?;
    let p_improvement = match metric.direction {
        Direction::HigherIsBetter => stats::probability_of_improvement(x, y),
        Direction::LowerIsBetter => stats::probability_of_improvement(y, x),
    }?;
    let informative = px.iter().chain(py).any(|v| *v != px[0]);
    let p_value = paired.p_beyond;
    let mut comparison = Comparison {
        metric,
        versus: versus.to_owned(),
        n: (x.len(), y.len()),
        paired,
        p_value,
        p_holm: p_value,
        margin,
        informative,
        outcome: ComparisonOutcome::Unsettled,
        iqm_difference,
        p_improvement,
    };
    comparison.outcome = outcome(&comparison, options.alpha);
    Ok(Some(comparison))
}

/// What a comparison settles at level `alpha` (see the module docs): a side is favoured when
/// the comparison is informative and its Holm-adjusted p that the mean paired difference lies
/// beyond the margin is below `alpha` — its interval then lies beyond the margin — on that
/// side.
fn outcome(comparison: &Comparison, alpha: f64) -> ComparisonOutcome {
    let estimate = comparison.paired.estimate;
    if !comparison.informative || comparison.p_holm >= alpha {
        ComparisonOutcome::Unsettled
    } else if comparison.metric.direction.favours(estimate) {
        ComparisonOutcome::FavoursMethod
    } else if comparison.metric.direction.favours(-estimate) {
        ComparisonOutcome::FavoursCompetitor
    } else {
        ComparisonOutcome::Unsettled
    }
}

/// What a per-seed test settles at level `alpha`: the side with the property on more
/// discordant seeds, when its Holm p is below `alpha`.
fn per_seed_outcome(test: &ReachingComparison, alpha: f64) -> ComparisonOutcome {
    let (wins, losses) = test.discordant;
    if test.p_holm >= alpha || wins == losses {
        ComparisonOutcome::Unsettled
    } else if wins > losses {
        ComparisonOutcome::FavoursMethod
    } else {
        ComparisonOutcome::FavoursCompetitor
    }
}

/// One row of `claims.csv`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClaimRow {
    /// `C1` … `C4`.
    pub claim: &'static str,
    /// The task.
    pub task: String,
    /// The method (under test, or any method for a single-method row).
    pub method: String,
    /// The method's role.
    pub role: Role,
    /// The column of `final-scores.csv`, or [`REACHED`] for a per-seed reaching test
    /// (`converged` for an outcome row).
    pub metric: &'static str,
    /// `lower` or `higher`: which is better.
    pub better: &'static str,
    /// The competitor; empty for a single-method row.
    pub versus: String,
    /// Whom the verdict of this row judges the method against ([`VersusSet::name`]): `paper`
    /// or `same_rewards` on the rows of a method under test (its single-method rows carry the
    /// `paper` verdict); empty on the rows of other methods and on outcome rows.
    pub versus_set: &'static str,
    /// Seeds with a value (the method's).
    pub n: usize,
    /// Seeds with a value of the competitor (empty for a single-method row).
    pub n_versus: Option<usize>,
    /// IQM over seeds (single-method row), or the mean paired difference method − competitor
    /// (comparison), or a share difference (per-seed test); empty when no seed has a value.
    pub estimate: Option<f64>,
    /// Lower end of its 95 % interval (bootstrap for an IQM, sign-flip for a mean paired
    /// difference; empty when unbounded).
    pub ci_low: Option<f64>,
    /// Upper end.
    pub ci_high: Option<f64>,
    /// The deciding p-value: that the mean paired difference lies beyond the margin
    /// (comparison), the exact sign test (per-seed test).
    pub p_value: Option<f64>,
    /// Holm-adjusted p-value (empty for an uninformative comparison).
    pub p_holm: Option<f64>,
    /// Probability of improvement (comparisons only).
    pub p_improvement: Option<f64>,
    /// What the comparison settles (`favours_method`, `favours_competitor`, `unsettled`).
    pub outcome: Option<ComparisonOutcome>,
    /// The claim × task × method verdict (rows of a method under test only; empty on the rows
    /// of a secondary metric, which does not decide it).
    pub verdict: Option<Verdict>,
    /// Seeds paired (both methods have a value; comparisons and per-seed tests).
    pub paired_n: Option<usize>,
    /// Two-sided sign-flip p-value of a mean paired difference of 0 (comparisons only).
    pub paired_p_value: Option<f64>,
    /// The metric's equivalence margin (empty: the metric has none).
    pub margin: Option<f64>,
    /// p-value that the mean paired difference lies within `±margin`.
    pub p_equivalence: Option<f64>,
    /// `p_equivalence` Holm-adjusted across the claim × task × method's comparisons.
    pub p_equivalence_holm: Option<f64>,
    /// Whether the comparison carries information (comparisons only; see
    /// [`Comparison::informative`]).
    pub informative: Option<bool>,
    /// Whether every sign vector was counted (comparisons only).
    pub exact: Option<bool>,
    /// Monte-Carlo standard error of `p_value` when the sign vectors were drawn.
    pub p_monte_carlo_se: Option<f64>,
    /// IQM(method) − IQM(competitor) over all seeds with a value (comparisons only;
    /// descriptive).
    pub iqm_difference: Option<f64>,
    /// Lower end of its bootstrap 95 % interval.
    pub iqm_ci_low: Option<f64>,
    /// Upper end.
    pub iqm_ci_high: Option<f64>,
}

/// The rows of `claims.csv`: per claim and task, first one single-method row per method and
/// metric (IQM over seeds, `versus` empty; the verdict on rows of a method under test), then
/// every comparison of every method under test: the per-seed tests of a judgement (metric
/// [`REACHED`] when they decide it instead of the metrics, [`STABLE_REACHING`] for C3:
/// `estimate` the difference in the share of paired seeds with the property,
/// [`reaching_difference`]; `p_value` the exact sign test, `p_holm` over the competitors),
/// then the metric comparisons. The claim's secondary metrics (C3's training-curve SDs) have
/// single-method rows and comparison rows too, after the deciding ones, with an empty
/// `verdict`: they do not decide it (their `p_holm` is adjusted among themselves).
#[must_use]
pub fn rows(judgements: &[Judgement], estimates: &[Estimate]) -> Vec<ClaimRow> {
    let mut rows = Vec::new();
    let mut seen: Vec<(&str, &str)> = Vec::new();
    for judgement in judgements {
        let key = (judgement.claim.id, judgement.task.as_str());
        if !seen.contains(&key) {
            seen.push(key);
            let deciding = judgement.claim.metrics.iter().map(|m| (m, true));
            let secondary = judgement.claim.secondary.iter().map(|m| (m, false));
            for (metric, decides) in deciding.chain(secondary) {
                for estimate in estimates
                    .iter()
                    .filter(|e| e.task == judgement.task && e.metric == metric.column)
                {
                    let verdict = judgements
                        .iter()
                        .find(|j| {
                            j.claim.id == judgement.claim.id
                                && j.task == judgement.task
                                && j.method == estimate.method
                                && j.versus_set == VersusSet::Paper
                        })
                        .map(|j| j.verdict)
                        .filter(|_| decides);
                    rows.push(ClaimRow {
                        claim: judgement.claim.id,
                        task: judgement.task.clone(),
                        method: estimate.method.clone(),
                        role: estimate.role,
                        metric: metric.column,
                        better: metric.direction.name(),
                        versus: String::new(),
                        n: estimate.n,
                        n_versus: None,
                        estimate: estimate.iqm.map(|i| i.estimate),
                        ci_low: estimate.iqm.map(|i| i.low),
                        ci_high: estimate.iqm.map(|i| i.high),
                        p_value: None,
                        p_holm: None,
                        p_improvement: None,
                        outcome: None,
                        verdict,
                        versus_set: if verdict.is_some() {
                            VersusSet::Paper.name()
                        } else {
                            ""
                        },
                        ..ClaimRow::paired_none()
                    });
                }
            }
        }
    }
    for judgement in judgements {
        for t in &judgement.reaching {
            rows.push(ClaimRow {
                claim: judgement.claim.id,
                task: judgement.task.clone(),
                method: judgement.method.clone(),
                role: judgement.role,
                metric: t.metric,
                better: Direction::HigherIsBetter.name(),
                versus: t.versus.clone(),
                versus_set: judgement.versus_set.name(),
                n: t.n,
                n_versus: Some(t.n),
                estimate: Some(reaching_difference(t)),
                p_value: Some(t.p_value),
                p_holm: Some(t.p_holm),
                outcome: Some(t.outcome),
                verdict: Some(judgement.verdict),
                paired_n: Some(t.n),
                ..ClaimRow::paired_none()
            });
        }
        let deciding = judgement.comparisons.iter().map(|c| (c, true));
        let secondary = judgement.secondary.iter().map(|c| (c, false));
        for (c, decides) in deciding.chain(secondary) {
            rows.push(ClaimRow {
                claim: judgement.claim.id,
                task: judgement.task.clone(),
                method: judgement.method.clone(),
                role: judgement.role,
                metric: c.metric.column,
                better: c.metric.direction.name(),
                versus: c.versus.clone(),
                versus_set: judgement.versus_set.name(),
                n: c.n.0,
                n_versus: Some(c.n.1),
                estimate: Some(c.paired.estimate),
                ci_low: c.paired.low,
                ci_high: c.paired.high,
                p_value: Some(c.p_value),
                p_holm: c.informative.then_some(c.p_holm),
                p_improvement: Some(c.p_improvement),
                outcome: Some(c.outcome),
                verdict: decides.then_some(judgement.verdict),
                paired_n: Some(c.paired.n),
                paired_p_value: Some(c.paired.p_value),
                margin: c.margin,
                p_equivalence: c.paired.p_equivalence,
                p_equivalence_holm: c.paired.p_equivalence_holm,
                informative: Some(c.informative),
                exact: Some(c.paired.exact),
                p_monte_carlo_se: c.paired.p_monte_carlo_se,
                iqm_difference: Some(c.iqm_difference.estimate),
                iqm_ci_low: Some(c.iqm_difference.low),
                iqm_ci_high: Some(c.iqm_difference.high),
            });
        }
    }
    rows
}

impl ClaimRow {
    /// A row with every paired column empty, to fill the others into.
    fn paired_none() -> Self {
        Self {
            claim: "",
            task: String::new(),
            method: String::new(),
            role: Role::Paper,
            metric: "",
            better: "",
            versus: String::new(),
            versus_set: "",
            n: 0,
            n_versus: None,
            estimate: None,
            ci_low: None,
            ci_high: None,
            p_value: None,
            p_holm: None,
            p_improvement: None,
            outcome: None,
            verdict: None,
            paired_n: None,
            paired_p_value: None,
            margin: None,
            p_equivalence: None,
            p_equivalence_holm: None,
            informative: None,
            exact: None,
            p_monte_carlo_se: None,
            iqm_difference: None,
            iqm_ci_low: None,
            iqm_ci_high: None,
        }
    }
}

/// The label of the sub-task-alone control every EA-MADM method is paired with on outcomes.
pub const SUBTASK_ALONE: &str = "subtask0-alone";

/// Rows of `claims.csv` on the per-run outcome (claim `outcome`, metric `converged`): per
/// task and method the share of seeds whose final greedy policy reaches the target with its
/// Wilson 95 % interval; and per EA-MADM method against every paper competitor and
/// [`SUBTASK_ALONE`], paired by seed, `estimate` = (seeds only the method converged on −
/// seeds only the other did) / paired seeds, `n` the paired seeds, and `p_value` the exact
/// sign test on those discordant seeds (McNemar's exact test).
///
/// # Errors
/// [`ClaimsError::Stats`] when a Wilson interval fails (it cannot with at least one seed).
pub fn outcome_rows(scores: &[FinalScore]) -> Result<Vec<ClaimRow>, ClaimsError> {
    let converged = |task: &str, method: &str| -> Vec<(u64, bool)> {
        let mut seeds: Vec<(u64, bool)> = scores
            .iter()
            .filter(|r| r.task == task && r.method == method)
            .map(|r| (r.seed, r.outcome == RunOutcome::Converged))
            .collect();
        seeds.sort_unstable();
        seeds
    };
    let mut rows = Vec::new();
    for task in tasks(scores) {
        let methods = methods(scores, task);
        for &(method, role, _) in &methods {
            let seeds = converged(task, method);
            let hits = seeds.iter().filter(|(_, c)| *c).count() as u64;
            let wilson =
                stats::wilson(hits, seeds.len() as u64, 0.95).map_err(|e| ClaimsError::Stats {
                    claim: "outcome".to_owned(),
                    task: task.to_owned(),
                    method: method.to_owned(),
                    metric: "converged".to_owned(),
                    source: Box::new(e),
                })?;
            rows.push(ClaimRow {
                claim: "outcome",
                task: task.to_owned(),
                method: method.to_owned(),
                role,
                metric: "converged",
                better: "higher",
                n: seeds.len(),
                estimate: Some(wilson.estimate),
                ci_low: Some(wilson.low),
                ci_high: Some(wilson.high),
                ..ClaimRow::paired_none()
            });
        }
        for &(method, role, kind) in &methods {
            if !is_under_test(kind) {
                continue;
            }
            let mine = converged(task, method);
            for &(versus, versus_role, versus_kind) in &methods {
                if !(is_competitor(versus_role, versus_kind) || versus == SUBTASK_ALONE) {
                    continue;
                }
                let theirs = converged(task, versus);
                let (mut wins, mut losses, mut paired) = (0_u64, 0_u64, 0_usize);
                for &(seed, c) in &mine {
                    if let Some(&(_, d)) = theirs.iter().find(|(s, _)| *s == seed) {
                        paired += 1;
                        wins += u64::from(c && !d);
                        losses += u64::from(d && !c);
                    }
                }
                if paired == 0 {
                    continue;
                }
                rows.push(ClaimRow {
                    claim: "outcome",
                    task: task.to_owned(),
                    method: method.to_owned(),
                    role,
                    metric: "converged",
                    better: "higher",
                    versus: versus.to_owned(),
                    n: paired,
                    n_versus: Some(theirs.len()),
                    estimate: Some((wins as f64 - losses as f64) / paired as f64),
                    p_value: Some(stats::sign_test(wins, losses)),
                    paired_n: Some(paired),
                    ..ClaimRow::paired_none()
                });
            }
        }
    }
    Ok(rows)
}

/// When the comparison-only columns of `claims.csv` are blank.
const PAIRED_BLANK: &str = "the row is not a comparison";

/// The columns of `claims.csv`, in order (the fields of [`ClaimRow`]), each with its type,
/// unit, meaning and when it is blank: the source of `datapackage.json` and of
/// `docs/outputs.md`. A new field of [`ClaimRow`] needs its entry here (a test compares the
/// CSV header with this table).
///
/// A row is one of four kinds, and which cells are blank follows from the kind: a
/// *single-method* row (`versus` blank: one method's IQM over seeds, or for claim `outcome` its
/// share of converged seeds), a *comparison* (a method under test against the competitor
/// `versus` on a metric), a *reaching test* (metric `reached`: per-seed reaching, paired by
/// seed) and an *outcome comparison* (claim `outcome` with `versus`: converged seeds, paired).
pub const CLAIM_COLUMNS: &[Column] = &[
    Column::new("claim", FieldType::String, "The paper's claim tested (C1 fewer steps, C2 higher cumulative reward, C3 smaller fluctuation, C4 the robot's reward, reaching time and retention decay), or `outcome` for the per-seed run outcome."),
    Column::new("task", FieldType::String, "The experiment (`task` of `final-scores.csv`)."),
    Column::new("method", FieldType::String, "The method: the one under test in a comparison, any method in a single-method row."),
    Column::new("role", FieldType::String, "The method's role (as in `final-scores.csv`).").values(&["paper", "ablation", "control"]),
    Column::new("metric", FieldType::String, "The column of `final-scores.csv` the row is about; `reached` for a per-seed reaching test (C4), `stable_reaching` for C3's paired test of stable-reaching seeds, `converged` for an outcome row. C3's `fluctuation_steps` and `fluctuation_return` (training curves) are secondary rows that carry no verdict."),
    Column::new("better", FieldType::String, "Which way of the metric is better.").values(&["lower", "higher"]),
    Column::new("versus", FieldType::String, "The competitor or control compared against.").blank_when("the row is a single-method row"),
    Column::new("versus_set", FieldType::String, "Which competitors the method is judged against: `paper` (the paper's competitors on the task reward; every method), or `same_rewards` (a repaired robot reading judged a second time against the competitors trained on its own sub-task rewards).").values(&["paper", "same_rewards"]).blank_when("the row carries no verdict: a single-method row of a method not under test on the claim, or an outcome row"),
    Column::new("n", FieldType::Integer, "Seeds with a value of the method (the paired seeds in a reaching test or an outcome comparison).").unit("seeds"),
    Column::new("n_versus", FieldType::Integer, "Seeds with a value of the competitor.").unit("seeds").blank_when("the row is a single-method row"),
    Column::new("estimate", FieldType::Number, "Single-method row: the interquartile mean (IQM) of the metric over seeds (descriptive), or for claim `outcome` the share of seeds that converged. Comparison: the mean over paired seeds of the difference method − versus, the estimand that decides the row. Per-seed test (`reached`, `stable_reaching`): share of paired seeds the method has the property on minus the competitor's. Outcome comparison: (seeds only the method converged on − seeds only `versus` did) / paired seeds. In the metric's unit (a share for `reached`, `stable_reaching` and `converged`).").blank_when("the row is a single-method row and no seed of the method has a value (a C4 metric of a method that never reached the target)"),
    Column::new("ci_low", FieldType::Number, "Lower end of the estimate's 95 % interval: a bootstrap interval for an IQM, a Wilson interval for a share of converged seeds, and for a comparison the exact sign-flip interval of the mean paired difference (the means of all 2ⁿ − 1 non-empty subsets of the paired differences ranked, the one at rank ⌊0.025 · 2ⁿ⌋ from each end: the inversion of the sign-flip test, no resampling; drawn sign vectors beyond 24 pairs, see `exact`).").blank_when("the row is a per-seed test or an outcome comparison (they carry an exact test instead), no seed has a value, or the comparison has fewer than 6 paired seeds (no sign-flip test reaches the 95 % level, so the interval is unbounded)"),
    Column::new("ci_high", FieldType::Number, "Upper end of that interval.").blank_when("as `ci_low`"),
    Column::new("p_value", FieldType::Number, "Comparison: the two-sided sign-flip p-value that the mean paired difference lies beyond ±`margin` on one side, 2 min(p(mean < −margin), p(mean > margin)) — at most α exactly when the 95 % interval lies beyond the margin; without a margin, the two-sided test of 0. Per-seed test or outcome comparison: the exact sign test on discordant seeds (McNemar's exact test).").blank_when("the row is a single-method row"),
    Column::new("p_holm", FieldType::Number, "`p_value` Holm-adjusted across one family: the claim × task × method's informative comparisons (every metric × competitor) together with its per-seed tests (C3's `stable_reaching`; the `reached` tests of a verdict on reaching form a family of their own, across the competitors).").blank_when("the row is a single-method row, an outcome comparison (not adjusted: outcomes explain, they never enter a verdict), or an uninformative comparison (`informative` false: it takes no part)"),
    Column::new("p_improvement", FieldType::Number, "Probability that a random seed of the method beats one of `versus` in the metric's better direction (ties count ½); descriptive.").unit("probability").blank_when("the row is not a comparison"),
    Column::new("outcome", FieldType::String, "What the comparison settles at α = 0.05: `favours_method` or `favours_competitor` when `p_holm` < α (then the 95 % interval lies beyond the margin on that side; per-seed tests: the side with more discordant seeds); otherwise `unsettled` (equivalence is read off `p_equivalence_holm`).").values(&["favours_method", "favours_competitor", "unsettled"]).blank_when("the row is a single-method row or an outcome comparison"),
    Column::new("verdict", FieldType::String, "The verdict on the claim × task × method under test, repeated on each of its rows.").values(&["supported", "contradicted", "equivalent", "inconclusive", "untestable"]).blank_when("the method is not under test on this claim (a competitor's, ablation's or control's single-method row), the row is a secondary metric (C3's training-curve `fluctuation_steps`, `fluctuation_return`), or the row is about outcomes"),
    Column::new("paired_n", FieldType::Integer, "Seeds where both methods have a value (runs of one seed share their random streams across methods).").unit("seeds").blank_when("the row is a single-method row or an outcome comparison"),
    Column::new("paired_p_value", FieldType::Number, "Two-sided sign-flip p-value of a mean paired difference of 0 (descriptive: any difference, margin or not).").blank_when(PAIRED_BLANK),
    Column::new("margin", FieldType::Number, "The metric's equivalence margin on the task (region of practical equivalence), in the metric's unit, derived from the task's rewards and control period (`eamadm::Task::equivalence_margins`; each with its reason in REPORT.md). The paper's mazes: ±2 steps on the step metrics, the shortest detour on a grid; ±2 reward on the return metrics, what that detour costs on Task II (−1 per step) and, where a detour costs nothing (Task I), the smallest difference one step's reward makes (−1 instead of +1). The robot: ±0.8 s on `reach_time` (two 0.4 s control periods); ±1.796 reward/s on `reach_average_reward` (what a 2-step detour takes off the average reward of the planner's 17-step route, 116 over 6.8 s); ±0.008081 s/episode on `retention_decay` (0.8 s over the 99-episode span of 100 reaching episodes).").blank_when("the metric has no margin on the task, or the row is not a comparison"),
    Column::new("p_equivalence", FieldType::Number, "p-value that the mean paired difference lies within ±`margin`: 2 max(p(mean > −margin), p(mean < margin)), two one-sided sign-flip tests each at α/2 — at most α exactly when the 95 % interval lies inside the margin.").blank_when("`margin` is blank, or the row is not a comparison"),
    Column::new("p_equivalence_holm", FieldType::Number, "`p_equivalence` Holm-adjusted across the claim × task × method's informative comparisons; a comparison is equivalent when it is below α.").blank_when("`p_equivalence` is blank, or the comparison is uninformative"),
    Column::new("informative", FieldType::Boolean, "False when every paired value of both methods is one and the same number (the metric sits at a bound for both, e.g. a greedy SD of 0 on every stable-reaching seed): the comparison shows neither a difference nor an equivalence: it takes no part in Holm, and in the verdict it settles nothing and is not equivalent.").blank_when(PAIRED_BLANK),
    Column::new("exact", FieldType::Boolean, "True when the sign-flip distribution counted all 2ⁿ sign vectors (at most 24 paired seeds, by meet in the middle); false when 100 000 were drawn from a stream of the comparison's own.").blank_when(PAIRED_BLANK),
    Column::new("p_monte_carlo_se", FieldType::Number, "Monte-Carlo standard error √(p(1 − p)/B) of `p_value` when the sign vectors were drawn.").blank_when("the row is not a comparison, or `exact` is true"),
    Column::new("iqm_difference", FieldType::Number, "IQM(method) − IQM(versus) over all seeds with a value (descriptive; the IQM trims a quarter of the seeds at each end, so seeds at the step cap may not count).").blank_when(PAIRED_BLANK),
    Column::new("iqm_ci_low", FieldType::Number, "Lower end of the bootstrap 95 % interval of `iqm_difference` (the two methods resampled independently).").blank_when(PAIRED_BLANK),
    Column::new("iqm_ci_high", FieldType::Number, "Upper end of that interval.").blank_when(PAIRED_BLANK),
];

/// Writes `claims.csv` (header: the fields of [`ClaimRow`]; empty cells for absent values).
///
/// # Errors
/// [`ClaimsError::Csv`] when writing fails.
pub fn write_csv<W: Write>(rows: &[ClaimRow], writer: W) -> Result<(), ClaimsError> {
    let mut csv = csv::Writer::from_writer(writer);
    if rows.is_empty() {
        csv.write_record(CLAIM_COLUMNS.iter().map(|c| c.name))?;
    }
    for row in rows {
        csv.serialize(row)?;
    }
    csv.flush().map_err(csv::Error::from)?;
    Ok(())
}

/// The paper's EA-MADM against one control on one metric (not Holm-adjusted: these
/// comparisons explain the verdicts and never enter them).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControlComparison {
    /// The task.
    pub task: String,
    /// The paper's EA-MADM (role `paper`, kind `ea_madm`).
    pub method: String,
    /// The comparison; `versus` is the control.
    pub comparison: Comparison,
}

/// The paper's EA-MADM against every control (role `control`) of every task on `final_steps`
/// and `final_return` (lower and higher is better), where both have at least two values.
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
pub fn control_comparisons(
    scores: &[FinalScore],
    options: &ClaimOptions,
) -> Result<Vec<ControlComparison>, ClaimsError> {
    let metrics = [
        ClaimMetric {
            column: "final_steps",
            direction: Direction::LowerIsBetter,
        },
        ClaimMetric {
            column: "final_return",
            direction: Direction::HigherIsBetter,
        },
    ];
    let mut jobs = Vec::new();
    for task in tasks(scores) {
        let all = methods(scores, task);
        let Some(&(method, _, _)) = all
            .iter()
            .find(|&&(_, role, kind)| role == Role::Paper && is_under_test(kind))
        else {
            continue;
        };
        for &(control, role, _) in &all {
            if role == Role::Control {
                for metric in metrics {
                    jobs.push((task, method, control, metric));
                }
            }
        }
    }
    let results: Vec<Option<ControlComparison>> = jobs
        .par_iter()
        .map(|&(task, method, control, metric)| {
            let (x, _) = values(scores, task, method, metric.column);
            let (y, _) = values(scores, task, control, metric.column);
            if x.len() < 2 || y.len() < 2 {
                return Ok(None);
            }
            let margin = options.margins.value(task, metric.column);
            let (px, py) = paired_values(scores, task, method, control, metric.column);
            let comparison = compare(&x, &y, (&px, &py), metric, control, margin, options)
                .map_err(|source| ClaimsError::Stats {
                    claim: String::new(),
                    task: task.to_owned(),
                    method: method.to_owned(),
                    metric: metric.column.to_owned(),
                    source: Box::new(source),
                })?;
            Ok(comparison.map(|comparison| ControlComparison {
                task: task.to_owned(),
                method: method.to_owned(),
                comparison,
            }))
        })
        .collect::<Result<_, ClaimsError>>()?;
    Ok(results.into_iter().flatten().collect())
}

/// A proportion with its counts and Wilson 95 % interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Share {
    /// Successes.
    pub successes: u64,
    /// Trials.
    pub trials: u64,
    /// `successes / trials` with its Wilson 95 % interval.
    pub wilson: Interval,
}

/// What the report shows of one method beyond the claims: success shares, the per-seed
/// distribution of final steps, the step budget.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MethodOverview {
    /// The task.
    pub task: String,
    /// The method.
    pub method: String,
    /// Its role.
    pub role: Role,
    /// Its kind.
    pub kind: String,
    /// Seeds.
    pub seeds: usize,
    /// Final-window training episodes that reached the target, pooled over seeds (episodes of
    /// one seed are not independent, so this interval is narrower than the truth; the
    /// per-seed `success_rate` is in `final-scores.csv`).
    pub training_success: Share,
    /// Seeds whose greedy evaluation episode reached the target (seeds are independent).
    pub greedy_success: Share,
    /// Seeds whose greedy evaluation episode ran to the step cap.
    pub greedy_at_cap: usize,
    /// The task's step cap as seen in its runs (any truncated episode), if any was hit.
    pub step_cap: Option<u32>,
    /// Per-seed distribution of `final_steps`, with the seeds at the step cap.
    pub final_steps: stats::Distribution,
    /// Seeds with at least one reaching episode.
    pub reaching_seeds: usize,
    /// Mean environment steps per run, pre-training included.
    pub env_steps_total: f64,
    /// Mean environment steps of sub-task pre-training per run.
    pub pretrain_env_steps: f64,
}

/// The overview of every method of every task in `scores`, in score order.
///
/// # Errors
/// [`ClaimsError::Stats`] when a statistic fails.
#[expect(
    clippy::cast_precision_loss,
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "counts are far below 2^52; a success rate times its window is a whole count"
)]
pub fn overview(scores: &[FinalScore]) -> Result<Vec<MethodOverview>, ClaimsError> {
    let mut overviews = Vec::new();
    for task in tasks(scores) {
        let step_cap = scores
            .iter()
            .filter(|row| row.task == task)
            .map(|row| row.step_cap)
            .max();
        for (method, role, kind) in methods(scores, task) {
            let error = |source| ClaimsError::Stats {
                claim: String::new(),
                task: task.to_owned(),
                method: method.to_owned(),
                metric: "overview".to_owned(),
                source: Box::new(source),
            };
            let rows: Vec<&FinalScore> = scores
                .iter()
                .filter(|row| row.task == task && row.method == method)
                .collect();
            let reached: u64 = rows
                .iter()
                .map(|row| (row.success_rate * row.final_window as f64).round() as u64)
                .sum();
            let window: u64 = rows.iter().map(|row| row.final_window as u64).sum();
            let greedy = rows.iter().filter(|row| row.greedy_reached).count() as u64;
            let share = |successes, trials| -> Result<Share, ClaimsError> {
                Ok(Share {
                    successes,
                    trials,
                    wilson: stats::wilson(successes, trials, 0.95).map_err(error)?,
                })
            };
            let steps: Vec<f64> = rows.iter().map(|row| row.final_steps).collect();
            let mean_of = |f: &dyn Fn(&FinalScore) -> u64| -> Result<f64, ClaimsError> {
                let values: Vec<f64> = rows.iter().map(|row| f(row) as f64).collect();
                stats::mean(&values).map_err(error)
            };
            overviews.push(MethodOverview {
                task: task.to_owned(),
                method: method.to_owned(),
                role,
                kind: kind.to_owned(),
                seeds: rows.len(),
                training_success: share(reached, window)?,
                greedy_success: share(greedy, rows.len() as u64)?,
                greedy_at_cap: step_cap.map_or(0, |cap| {
                    rows.iter()
                        .filter(|row| row.greedy_steps >= u64::from(cap))
                        .count()
                }),
                step_cap,
                final_steps: stats::distribution(&steps, step_cap.map(f64::from)).map_err(error)?,
                reaching_seeds: rows.iter().filter(|row| row.reaching_episodes > 0).count(),
                env_steps_total: mean_of(&|row| row.env_steps_total)?,
                pretrain_env_steps: mean_of(&|row| row.pretrain_env_steps)?,
            });
        }
    }
    Ok(overviews)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_is_the_documented_columns_and_blank_cells_are_documented() {
        let single = ClaimRow {
            claim: "C1",
            task: "task1".into(),
            method: "ea-madm".into(),
            metric: "final_steps",
            better: "lower",
            n: 0,
            // No seed has a value (a C4 metric of a method that never reached).
            estimate: None,
            ..ClaimRow::paired_none()
        };
        let mut bytes = Vec::new();
        write_csv(&[single], &mut bytes).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        let mut lines = text.lines();
        let header = lines.next().unwrap();
        assert_eq!(header, crate::columns::names(CLAIM_COLUMNS).join(","));
        // Every cell a single-method row leaves blank is a column that says when it is.
        for (column, cell) in CLAIM_COLUMNS.iter().zip(lines.next().unwrap().split(',')) {
            assert!(
                !cell.is_empty() || column.blank_when.is_some(),
                "{} is blank but documented as always filled",
                column.name
            );
        }
        let mut empty = Vec::new();
        write_csv(&[], &mut empty).unwrap();
        assert_eq!(String::from_utf8(empty).unwrap().trim_end(), header);
    }
}
