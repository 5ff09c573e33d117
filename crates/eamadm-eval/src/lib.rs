//! The evaluation of EA-MADM runs: statistics over seeds, per-seed final scores, the paper's
//! claims tested with a verdict each, the methods' behaviour, and the tidy tables that hold
//! them. Pure: run records in ([`RunRecord`], the output of `eamadm`'s runner), numbers,
//! verdicts and findings out; no file is opened here (writers take any [`std::io::Write`]).
//!
//! It depends on no crate of the workspace: the run record types ([`record`]), a method's
//! [`Role`] and the paper's claims as data ([`paper_claims`]) live here, and `eamadm`
//! re-exports every module, so `eamadm::stats::…`, `eamadm::scores::FinalScore`,
//! `eamadm::RunRecord` and `eamadm::summarise` name the items of this crate.
//!
//! | module | what it holds |
//! |---|---|
//! | [`record`] | what one run produces (curves, trajectories, evaluation, pre-training) |
//! | [`stats`] | IQM, bootstrap and stratified bootstrap intervals, permutation tests, Holm, P(X > Y), Wilson |
//! | [`summary`] | mean curves and bands over seeds, the final-window summary per method |
//! | [`scores`] | per-seed final scores (one row per task, method, seed): `final-scores.csv` |
//! | [`paper_claims`] | the paper's claims C1–C4 as data, metric directions, method titles |
//! | [`claims`] | each claim × task × method tested against the competitors, with a verdict |
//! | [`reaching`] | the robot's curves over its first 100 reaching episodes (C4, Fig. 13–15) and the seeds behind each point |
//! | [`facts`] | what the report and figures know beyond the scores: the paper's tasks, the run's experiments, the readings |
//! | [`columns`] | every column of `final-scores.csv` and `claims.csv` documented: the data package and its Markdown |
//! | [`sensitivity`] | each verdict judged again under other readings of the paper: holds or flips |
//! | [`oracle`] | the decision step on exact (or converged) sub-task values, and each sub-task's pre-training: `oracle.csv`, `pretraining.csv` |
//! | [`behaviour`](mod@behaviour) | action shares, success and sub-task agreement per method |
//! | [`results`] | the full records as JSON, curves and trajectories as CSV |
//! | [`findings`] | what the report states, as data (`findings.json`): verdicts, deciding comparisons, strongest controls, collapses, equalities, the diagnosis |
//! | [`verdicts`] | every verdict of a run: against the competitors, the strongest control, without collapses, under the readings |
//! | [`rounding`] | numbers as text, rounded to the digits they support |
//!
//! The paper's equations this crate evaluates against: the claims of Sec. VI.A (Fig. 7, 8,
//! 10, 11: steps and cumulative reward per episode, their fluctuation) and Sec. VI.B (Fig.
//! 13–15: average reward, reaching time, retention time); the method itself (Eq. 3–16) is in
//! the crates `eamadm` composes.
//!
//! # Example
//!
//! The interquartile mean of per-seed final steps, a bootstrap interval of a difference
//! between two methods, and a Wilson interval for a success count:
//!
//! ```
//! use eamadm_eval::stats::{Bootstrap, Statistic, iqm, wilson};
//!
//! let method = [73.0, 73.0, 75.0, 73.0, 2000.0, 73.0, 77.0, 73.0];
//! let other = [812.0, 2000.0, 1377.0, 954.0, 2000.0, 1640.0, 1105.0, 2000.0];
//! let centre = iqm(&method)?; // drops the 2 smallest and 2 largest
//! assert!((centre - 73.5).abs() < 1e-12);
//! let difference = Bootstrap::default().difference(&method, &other, Statistic::Iqm)?;
//! assert!(difference.high < 0.0); // fewer steps, and the interval says so
//! let reached = wilson(7, 8, 0.95)?;
//! assert!(reached.low < 0.875 && 0.875 < reached.high);
//! # Ok::<(), eamadm_eval::stats::StatsError>(())
//! ```

pub mod behaviour;
pub mod claims;
pub mod columns;
pub mod facts;
pub mod family;
pub mod findings;
pub mod oracle;
pub mod paper_claims;
pub mod reaching;
pub mod record;
pub mod results;
mod role;
pub mod rounding;
pub mod scores;
pub mod sensitivity;
pub mod stats;
pub mod summary;
pub mod verdicts;

pub use behaviour::{BehaviourAccumulator, Endings, MethodBehaviour, SubtaskBehaviour, behaviour};
pub use record::{
    AgreementCounts, AgreementRecord, EpisodeRecord, RobotEpisodeMetrics, RunRecord, SubtaskRecord,
    TrajectoryRecord,
};
pub use role::Role;
pub use summary::{DEFAULT_FINAL_WINDOW, MethodSummary, RobotSummary, SeedSummary, summarise};
