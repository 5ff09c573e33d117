//! The maze family's pooled verdicts (issue 33, docs/paper-notes.md §22): EA-MADM against each
//! of the paper's competitors over many layouts at once.
//!
//! Runs of one layout and one seed share their random streams across methods, so each
//! (layout, seed) gives one paired difference `EA-MADM − competitor` on a claim's metric. The
//! **effect** is the mean over layouts of each layout's mean paired difference (every layout
//! weighs the same). Its interval is the two-level bootstrap
//! ([`HierarchicalBootstrap::paired_difference`]: layouts, then seeds within each drawn
//! layout; conservative), with the layouts-only (cluster) interval beside it.
//!
//! **The verdict** uses the rule of the main claims on the two-level interval, with the
//! metric's equivalence margin of the family's rewards (Task II's): it **favours EA-MADM**
//! (or the competitor) when the interval lies wholly beyond the margin on that side (beyond 0
//! when there is no margin), **equivalent** when it lies inside `(−margin, margin)`,
//! **inconclusive** otherwise. No p-value enters: the interval already counts the layouts'
//! spread, and with 95 % intervals per competitor the three competitors of a claim are not
//! Holm-adjusted (stated in the report beside the table).
//!
//! Only C1 (`final_steps`) and C2 (`final_return`) are pooled: every run has both. C3's
//! deciding metrics exist only on stable-reaching seeds, so its pairs would be a selected
//! subset that differs by method; C4 is the robot's.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::Role;
use crate::claims::Margin;
use crate::paper_claims::{self, Direction};
use crate::scores::FinalScore;
use crate::stats::hierarchical::{HierarchicalBootstrap, Stages};
use crate::stats::{Statistic, StatsError};

/// The prefix of a family layout's experiment name (`family-f07-trap`), as
/// `eamadm::family::EXPERIMENT_PREFIX` names it.
pub const EXPERIMENT_PREFIX: &str = "family-";

/// The method whose claims the family tests: the paper's EA-MADM.
pub const METHOD: &str = "ea-madm";

/// The claims pooled over the family, with their deciding metric.
pub const POOLED_CLAIMS: [(&str, &str); 2] = [("C1", "final_steps"), ("C2", "final_return")];

/// The family layout of an experiment (`family-f07-trap` → `f07-trap`); `None` otherwise.
#[must_use]
pub fn layout_of(task: &str) -> Option<&str> {
    task.strip_prefix(EXPERIMENT_PREFIX)
}

/// What a pooled comparison settles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PooledVerdict {
    /// The interval lies wholly beyond the margin on EA-MADM's side.
    FavoursEaMadm,
    /// The interval lies wholly beyond the margin on the competitor's side.
    FavoursCompetitor,
    /// The interval lies inside `(−margin, margin)`.
    Equivalent,
    /// Neither.
    Inconclusive,
}

impl PooledVerdict {
    /// `favours_ea_madm`, `favours_competitor`, `equivalent`, `inconclusive`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::FavoursEaMadm => "favours_ea_madm",
            Self::FavoursCompetitor => "favours_competitor",
            Self::Equivalent => "equivalent",
            Self::Inconclusive => "inconclusive",
        }
    }
}

/// One claim × competitor, pooled over the family's layouts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PooledComparison {
    /// `C1` or `C2`.
    pub claim: String,
    /// The deciding column of `final-scores.csv`.
    pub metric: String,
    /// The competitor's label.
    pub competitor: String,
    /// Layouts with at least one pair.
    pub layouts: usize,
    /// (layout, seed) pairs.
    pub pairs: usize,
    /// Mean over layouts of the mean paired difference `EA-MADM − competitor`, in the
    /// metric's unit (negative is better for EA-MADM on steps, positive on return).
    pub effect: f64,
    /// The two-level (layouts, then seeds) 95 % interval's ends.
    pub low: f64,
    /// Upper end.
    pub high: f64,
    /// The layouts-only (cluster bootstrap) 95 % interval's ends.
    pub layouts_only_low: f64,
    /// Upper end.
    pub layouts_only_high: f64,
    /// The metric's equivalence margin, if it has one.
    pub margin: Option<f64>,
    /// Layouts whose mean paired difference goes EA-MADM's way (strictly).
    pub layouts_favouring_ea_madm: usize,
    /// The verdict (see the module docs).
    pub verdict: PooledVerdict,
}

/// One layout × claim × competitor: the mean paired difference over its seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LayoutEffect {
    /// The layout's name (`f07-trap`).
    pub layout: String,
    /// `C1` or `C2`.
    pub claim: String,
    /// The deciding column.
    pub metric: String,
    /// The competitor's label.
    pub competitor: String,
    /// Paired seeds.
    pub seeds: usize,
    /// Mean paired difference `EA-MADM − competitor`.
    pub effect: f64,
}

/// The pooled verdicts and the per-layout effects of a family.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FamilyVerdicts {
    /// Per claim × competitor, claims in [`POOLED_CLAIMS`] order, competitors by label.
    pub pooled: Vec<PooledComparison>,
    /// Per layout × claim × competitor, in the same order, layouts by name.
    pub layouts: Vec<LayoutEffect>,
}

/// A family layout as the findings, the figure and the report need it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LayoutPoint {
    /// The layout's name (`f07-trap`).
    pub layout: String,
    /// Its kind's data name (`uniform`, `perfect_maze`, `rooms`, `trap`).
    pub kind: String,
    /// BFS optimum ÷ Manhattan distance.
    pub detour_ratio: f64,
}

/// The mean per-layout effect over the layouts of one kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct KindMean {
    /// The kind's data name.
    pub kind: String,
    /// Layouts of that kind with an effect.
    pub layouts: usize,
    /// Their mean effect.
    pub mean: f64,
}

/// How one claim × competitor's per-layout effects spread over the family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EffectSpread {
    /// `C1` or `C2`.
    pub claim: String,
    /// The competitor's label.
    pub competitor: String,
    /// Layouts with an effect.
    pub layouts: usize,
    /// The smallest per-layout effect.
    pub min: f64,
    /// The median per-layout effect.
    pub median: f64,
    /// The largest.
    pub max: f64,
    /// Per kind present (in the order of the layouts' first appearance), the mean effect.
    pub by_kind: Vec<KindMean>,
}

/// What the reports state of the family, as data (`findings.json`'s `family`): the layouts
/// run, the pooled verdicts and how each comparison's per-layout effects spread.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FamilyFindings {
    /// Training episodes of every family run.
    pub episodes: u64,
    /// Held-out seeds per layout and method (the most any layout has).
    pub seeds: usize,
    /// The family's layouts that have runs, in the given order.
    pub layouts: Vec<LayoutPoint>,
    /// The pooled comparisons ([`FamilyVerdicts::pooled`]).
    pub pooled: Vec<PooledComparison>,
    /// Per pooled comparison, the spread of its per-layout effects (same order).
    pub spread: Vec<EffectSpread>,
}

/// The findings of a family judged as `verdicts` from `scores` (rows of other experiments
/// ignored), `layouts` naming each layout's kind and detour ratio (layouts without runs are
/// left out). `None` when `scores` holds no family run.
#[must_use]
#[expect(
    clippy::cast_precision_loss,
    reason = "layout counts are far below 2^52"
)]
pub fn family_findings(
    verdicts: &FamilyVerdicts,
    layouts: &[LayoutPoint],
    scores: &[FinalScore],
) -> Option<FamilyFindings> {
    let family: Vec<&FinalScore> = scores
        .iter()
        .filter(|row| layout_of(&row.task).is_some())
        .collect();
    let episodes = family.iter().map(|row| row.episodes).max()?;
    let mut seeds_of: BTreeMap<&str, Vec<u64>> = BTreeMap::new();
    for row in &family {
        let seeds = seeds_of.entry(row.task.as_str()).or_default();
        if !seeds.contains(&row.seed) {
            seeds.push(row.seed);
        }
    }
    let seeds = seeds_of.values().map(Vec::len).max().unwrap_or(0);
    let run: Vec<LayoutPoint> = layouts
        .iter()
        .filter(|point| {
            family
                .iter()
                .any(|row| layout_of(&row.task) == Some(point.layout.as_str()))
        })
        .cloned()
        .collect();
    let kind_of: BTreeMap<&str, &str> = run
        .iter()
        .map(|point| (point.layout.as_str(), point.kind.as_str()))
        .collect();
    let mut kinds: Vec<&str> = Vec::new();
    for point in &run {
        if !kinds.contains(&point.kind.as_str()) {
            kinds.push(point.kind.as_str());
        }
    }
    let spread = verdicts
        .pooled
        .iter()
        .filter_map(|p| {
            let effects: Vec<(f64, &str)> = verdicts
                .layouts
                .iter()
                .filter(|e| e.claim == p.claim && e.competitor == p.competitor)
                .map(|e| {
                    (
                        e.effect,
                        kind_of.get(e.layout.as_str()).copied().unwrap_or(""),
                    )
                })
                .collect();
            let mut sorted: Vec<f64> = effects.iter().map(|(v, _)| *v).collect();
            sorted.sort_by(f64::total_cmp);
            let (&min, &max) = (sorted.first()?, sorted.last()?);
            let half = sorted.len() / 2;
            let median = if sorted.len() % 2 == 1 {
                sorted[half]
            } else {
                f64::midpoint(sorted[half - 1], sorted[half])
            };
            let by_kind = kinds
                .iter()
                .filter_map(|&kind| {
                    let of: Vec<f64> = effects
                        .iter()
                        .filter(|(_, k)| *k == kind)
                        .map(|(v, _)| *v)
                        .collect();
                    (!of.is_empty()).then(|| KindMean {
                        kind: kind.to_owned(),
                        layouts: of.len(),
                        mean: of.iter().sum::<f64>() / of.len() as f64,
                    })
                })
                .collect();
            Some(EffectSpread {
                claim: p.claim.clone(),
                competitor: p.competitor.clone(),
                layouts: sorted.len(),
                min,
                median,
                max,
                by_kind,
            })
        })
        .collect();
    Some(FamilyFindings {
        episodes,
        seeds,
        layouts: run,
        pooled: verdicts.pooled.clone(),
        spread,
    })
}

/// Values of one method on each layout, by seed.
type BySeed = BTreeMap<u64, f64>;

/// The family's verdicts from `scores` (rows of other experiments are ignored): EA-MADM
/// ([`METHOD`]) against every paper competitor (role `paper`, not EA-MADM) present,
/// `margins` giving each metric's equivalence margin (the family's rewards'). An empty
/// result when there is no family row or no competitor.
///
/// # Errors
/// What the bootstrap returns (e.g. a non-finite value).
pub fn family_verdicts(
    scores: &[FinalScore],
    margins: &[Margin],
    bootstrap: &HierarchicalBootstrap,
) -> Result<FamilyVerdicts, StatsError> {
    // (metric) → method → layout → seed → value.
    let mut competitors: Vec<&str> = scores
        .iter()
        .filter(|row| layout_of(&row.task).is_some())
        .filter(|row| row.role == Role::Paper && row.kind != "ea_madm")
        .map(|row| row.method.as_str())
        .collect();
    competitors.sort_unstable();
    competitors.dedup();
    let values = |method: &str, metric: &str| -> BTreeMap<&str, BySeed> {
        let mut by_layout: BTreeMap<&str, BySeed> = BTreeMap::new();
        for row in scores.iter().filter(|row| row.method == method) {
            if let (Some(layout), Some(value)) = (layout_of(&row.task), row.value(metric)) {
                by_layout.entry(layout).or_default().insert(row.seed, value);
            }
        }
        by_layout
    };
    let mut verdicts = FamilyVerdicts::default();
    for (claim, metric) in POOLED_CLAIMS {
        let direction = paper_claims::claim(claim)
            .and_then(|c| c.metrics.iter().find(|m| m.column == metric))
            .map_or(Direction::LowerIsBetter, |m| m.direction);
        let sign = match direction {
            Direction::LowerIsBetter => -1.0,
            Direction::HigherIsBetter => 1.0,
        };
        let margin = margins.iter().find(|m| m.column == metric).map(|m| m.value);
        let ours = values(METHOD, metric);
        for &competitor in &competitors {
            let theirs = values(competitor, metric);
            let mut x: Vec<Vec<f64>> = Vec::new();
            let mut y: Vec<Vec<f64>> = Vec::new();
            for (layout, mine) in &ours {
                let Some(other) = theirs.get(layout) else {
                    continue;
                };
                let (a, b): (Vec<f64>, Vec<f64>) = mine
                    .iter()
                    .filter_map(|(seed, v)| other.get(seed).map(|w| (*v, *w)))
                    .unzip();
                if a.is_empty() {
                    continue;
                }
                let effect = a.iter().zip(&b).map(|(v, w)| v - w).sum::<f64>() / a.len() as f64;
                verdicts.layouts.push(LayoutEffect {
                    layout: (*layout).to_owned(),
                    claim: claim.to_owned(),
                    metric: metric.to_owned(),
                    competitor: competitor.to_owned(),
                    seeds: a.len(),
                    effect,
                });
                x.push(a);
                y.push(b);
            }
            if x.is_empty() {
                continue;
            }
            let xs: Vec<&[f64]> = x.iter().map(Vec::as_slice).collect();
            let ys: Vec<&[f64]> = y.iter().map(Vec::as_slice).collect();
            let two = HierarchicalBootstrap {
                stages: Stages::LayoutsThenSeeds,
                ..*bootstrap
            }
            .paired_difference(&xs, &ys, Statistic::Mean, Statistic::Mean)?;
            let one = HierarchicalBootstrap {
                stages: Stages::LayoutsOnly,
                ..*bootstrap
            }
            .paired_difference(&xs, &ys, Statistic::Mean, Statistic::Mean)?;
            let start = verdicts.layouts.len() - x.len();
            let favouring = verdicts.layouts[start..]
                .iter()
                .filter(|effect| sign * effect.effect > 0.0)
                .count();
            verdicts.pooled.push(PooledComparison {
                claim: claim.to_owned(),
                metric: metric.to_owned(),
                competitor: competitor.to_owned(),
                layouts: x.len(),
                pairs: x.iter().map(Vec::len).sum(),
                effect: two.estimate,
                low: two.low,
                high: two.high,
                layouts_only_low: one.low,
                layouts_only_high: one.high,
                margin,
                layouts_favouring_ea_madm: favouring,
                verdict: verdict(two.low, two.high, margin, sign),
            });
        }
    }
    Ok(verdicts)
}

/// The verdict of an interval `[low, high]` of `EA-MADM − competitor` with `margin`, `sign`
/// +1 when higher is better for EA-MADM, −1 when lower is.
#[must_use]
pub fn verdict(low: f64, high: f64, margin: Option<f64>, sign: f64) -> PooledVerdict {
    let m = margin.unwrap_or(0.0);
    // In EA-MADM's orientation: positive is better for it.
    let (low, high) = if sign > 0.0 {
        (low, high)
    } else {
        (-high, -low)
    };
    if low > m {
        PooledVerdict::FavoursEaMadm
    } else if high < -m {
        PooledVerdict::FavoursCompetitor
    } else if margin.is_some() && low > -m && high < m {
        PooledVerdict::Equivalent
    } else {
        PooledVerdict::Inconclusive
    }
}

/// Writes the pooled comparisons as CSV (`family.csv`), one row each, numbers as computed.
///
/// # Errors
/// What the writer returns.
pub fn write_pooled_csv<W: std::io::Write>(
    rows: &[PooledComparison],
    writer: W,
) -> Result<(), csv::Error> {
    let mut csv = csv::Writer::from_writer(writer);
    csv.write_record([
        "claim",
        "metric",
        "competitor",
        "layouts",
        "pairs",
        "effect",
        "low",
        "high",
        "layouts_only_low",
        "layouts_only_high",
        "margin",
        "layouts_favouring_ea_madm",
        "verdict",
    ])?;
    for row in rows {
        csv.write_record([
            row.claim.clone(),
            row.metric.clone(),
            row.competitor.clone(),
            row.layouts.to_string(),
            row.pairs.to_string(),
            row.effect.to_string(),
            row.low.to_string(),
            row.high.to_string(),
            row.layouts_only_low.to_string(),
            row.layouts_only_high.to_string(),
            row.margin.map_or_else(String::new, |m| m.to_string()),
            row.layouts_favouring_ea_madm.to_string(),
            row.verdict.name().to_owned(),
        ])?;
    }
    csv.flush()?;
    Ok(())
}

/// Writes the per-layout effects as CSV (`family-effects.csv`).
///
/// # Errors
/// What the writer returns.
pub fn write_effects_csv<W: std::io::Write>(
    rows: &[LayoutEffect],
    writer: W,
) -> Result<(), csv::Error> {
    let mut csv = csv::Writer::from_writer(writer);
    csv.write_record(["layout", "claim", "metric", "competitor", "seeds", "effect"])?;
    for row in rows {
        csv.write_record([
            row.layout.clone(),
            row.claim.clone(),
            row.metric.clone(),
            row.competitor.clone(),
            row.seeds.to_string(),
            row.effect.to_string(),
        ])?;
    }
    csv.flush()?;
    Ok(())
}
