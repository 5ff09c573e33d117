//! The paper's claims as data (Sec. VI): what each claim says, where, which columns of
//! `final-scores.csv` test it and which way is better; and the paper's titles of its methods.
//! `eamadm::paper` re-exports all of it.

use serde::{Deserialize, Serialize};

/// A method's title for people: the paper's names for its four methods (`EA-MADM`,
/// `ε-greedy`, `ε-decreasing`, `softmax`), the label itself for every other method.
#[must_use]
pub fn method_title(label: &str) -> String {
    match label {
        "ea-madm" => "EA-MADM".to_owned(),
        "epsilon-greedy" => "ε-greedy".to_owned(),
        "epsilon-decreasing" => "ε-decreasing".to_owned(),
        other => other.to_owned(),
    }
}

/// Whether smaller or larger values of a metric are better.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Direction {
    /// Fewer steps, less fluctuation, shorter reaching time, faster fall of retention time.
    LowerIsBetter,
    /// Higher return, higher average reward.
    HigherIsBetter,
}

impl Direction {
    /// `lower` or `higher` (what is better), for tables and CSV.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::LowerIsBetter => "lower",
            Self::HigherIsBetter => "higher",
        }
    }

    /// Whether `difference` = (method under test − competitor) favours the method under test.
    #[must_use]
    pub fn favours(self, difference: f64) -> bool {
        match self {
            Self::LowerIsBetter => difference < 0.0,
            Self::HigherIsBetter => difference > 0.0,
        }
    }
}

/// One metric of a claim: a column of `final-scores.csv` and which way is better.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct ClaimMetric {
    /// The column of [`FinalScore`](crate::scores::FinalScore) /
    /// `final-scores.csv` (see [`scores::COLUMNS`](crate::scores::COLUMNS)).
    pub column: &'static str,
    /// Which way is better.
    pub direction: Direction,
}

/// One claim of the paper, as data: what it says, where, and how we measure it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Claim {
    /// `C1` … `C4`.
    pub id: &'static str,
    /// The claim in short, close to the paper's own sentence (quoted where it is one).
    pub words: &'static str,
    /// Where the paper makes it: section and figures.
    pub location: &'static str,
    /// The metrics that test it; the claim holds for a method when it holds on every one.
    pub metrics: &'static [ClaimMetric],
    /// A per-seed yes/no column of `final-scores.csv` compared alongside the metrics, paired
    /// by seed (the exact sign test of `claims::judge_by_reaching`); a comparison with a
    /// competitor then favours a side when the metric or this test does (and the other does
    /// not favour the other side). C3: `stable_reaching`, so that a seed stuck at the step
    /// cap counts against its method instead of being left out. `None` for the others.
    pub per_seed: Option<&'static str>,
    /// Metrics reported beside the claim's (estimates and comparisons in `claims.csv`, with
    /// their own Holm adjustment) that do not decide its verdict: C3's training-curve SDs.
    pub secondary: &'static [ClaimMetric],
    /// The experiments (`task1`, `task2`, `robot`: `eamadm::paper::PaperTask::name`) it is judged
    /// on: where the paper makes it, and the positive control `aggregation-control` (issue 32).
    pub tasks: &'static [&'static str],
}

/// The paper's four claims about EA-MADM against its competitors.
///
/// - **C1** fewest steps per episode at the end of training (Fig. 7, 10: "the minimum time step
///   required for each episode, about 80 steps"; "the least time step …, about 86").
/// - **C2** highest return per episode (Fig. 8, 11: "the highest cumulative reward", "about
///   155"; "the highest reward, about −71").
/// - **C3** least fluctuation of the step and return curves (Fig. 7, 8, 10: "the minimum
///   fluctuation", "the smallest fluctuation"), measured on the greedy policy evaluated during
///   training (`fluctuation_greedy_*`, over stable-reaching seeds, with the share of
///   stable-reaching seeds compared too); the training curves' own SDs (`fluctuation_steps`,
///   `fluctuation_return`) are secondary, since exploration and seeds stuck at the step cap
///   drive them (docs/paper-notes.md, "C3 on the greedy policy").
/// - **C4** on the robot, over episodes that reach the target: the largest average reward
///   (Fig. 13), the least reaching time (Fig. 14), and the fastest fall of the retention time
///   (Fig. 15).
pub const CLAIMS: [Claim; 4] = [
    Claim {
        id: "C1",
        words: "EA-MADM needs the fewest steps per episode at the end of training \
                (\"the minimum time step required for each episode\")",
        location: "Sec. VI.A, Fig. 7 and Fig. 10",
        metrics: &[ClaimMetric {
            column: "final_steps",
            direction: Direction::LowerIsBetter,
        }],
        tasks: &["task1", "task2", "aggregation-control"],
        per_seed: None,
        secondary: &[],
    },
    Claim {
        id: "C2",
        words: "EA-MADM obtains the highest return per episode at the end of training \
                (\"the highest cumulative reward\")",
        location: "Sec. VI.A, Fig. 8 and Fig. 11",
        metrics: &[ClaimMetric {
            column: "final_return",
            direction: Direction::HigherIsBetter,
        }],
        tasks: &["task1", "task2", "aggregation-control"],
        per_seed: None,
        secondary: &[],
    },
    Claim {
        id: "C3",
        words: "EA-MADM's step and return curves fluctuate least (\"the minimum fluctuation\")",
        location: "Sec. VI.A, Fig. 7, 8 and 10",
        metrics: &[
            ClaimMetric {
                column: "fluctuation_greedy_steps",
                direction: Direction::LowerIsBetter,
            },
            ClaimMetric {
                column: "fluctuation_greedy_return",
                direction: Direction::LowerIsBetter,
            },
        ],
        per_seed: Some("stable_reaching"),
        secondary: &[
            ClaimMetric {
                column: "fluctuation_steps",
                direction: Direction::LowerIsBetter,
            },
            ClaimMetric {
                column: "fluctuation_return",
                direction: Direction::LowerIsBetter,
            },
        ],
        tasks: &["task1", "task2", "aggregation-control"],
    },
    Claim {
        id: "C4",
        words: "on the robot, over episodes that reach the target, EA-MADM has the largest \
                average reward, the least reaching time, and its retention time \"decreases \
                the fastest\"",
        location: "Sec. VI.B, Fig. 13, 14 and 15",
        metrics: &[
            ClaimMetric {
                column: "reach_average_reward",
                direction: Direction::HigherIsBetter,
            },
            ClaimMetric {
                column: "reach_time",
                direction: Direction::LowerIsBetter,
            },
            ClaimMetric {
                column: "retention_decay",
                direction: Direction::LowerIsBetter,
            },
        ],
        tasks: &["robot"],
        per_seed: None,
        secondary: &[],
    },
];

/// The claim with this id (`C1` … `C4`).
#[must_use]
pub fn claim(id: &str) -> Option<&'static Claim> {
    CLAIMS.iter().find(|claim| claim.id == id)
}

/// What the paper reports for EA-MADM at the end of training on a maze (read off Fig. 7/8 and
/// 10/11 and the text). The paper gives no numbers for the robot.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReportedNumbers {
    /// Steps per episode at the end of training ("about 80", "about 86").
    pub steps: f64,
    /// Return per episode at the end of training ("about 155", "about −71").
    pub task_return: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_judge_the_sign() {
        assert!(Direction::LowerIsBetter.favours(-1.0));
        assert!(!Direction::LowerIsBetter.favours(0.0));
        assert!(Direction::HigherIsBetter.favours(2.0));
        assert!(!Direction::HigherIsBetter.favours(-2.0));
    }
}
