//! The presentation of EA-MADM runs: the figures (SVG), `REPORT.md` and the README's generated
//! blocks. Pure: data in (run records, per-seed scores, verdicts and findings of
//! `eamadm-eval`, the arena a task is played on), SVG and Markdown text out; no file is opened
//! here, so the main job (`cargo xtask reproduce-paper`) and the Python package draw the same
//! bytes from the same data, and write them where they like.
//!
//! | module | what it holds |
//! |---|---|
//! | [`theme`] | one colour and dash per method (Okabe–Ito; paper solid, ablations dashed, controls dotted) |
//! | [`chart`] | the SVG line chart: IQM over seeds with its bootstrap band, per-seed lines, panels |
//! | [`figures`] | which figures an experiment gets, collected run by run, with their captions |
//! | [`checks`] | what a reader's trust in a figure rests on, checked on its SVG |
//! | [`generated`] | generated text in committed files: a block spliced between its markers, the first line where it differs |
//!
//! The figures draw the paper's Fig. 6–11 (steps, return and greedy paths on the mazes) and
//! Fig. 13–15 (the robot's average reward, reaching time and retention time over reaching
//! episodes) for our runs, with the estimator the report's tables use (the interquartile mean
//! over seeds) and its 95 % percentile-bootstrap band.
//!
//! # Example
//!
//! A chart of two methods' steps per episode over three seeds each:
//!
//! ```
//! use eamadm_eval::Role;
//! use eamadm_present::chart::{LineChart, Series};
//! use eamadm_present::theme::method_style;
//!
//! let mut chart = LineChart::new("steps per episode", "episode", "steps").with_smoothing(1);
//! for (label, start) in [("ea-madm", 90.0), ("softmax", 120.0)] {
//!     let mut series = Series::new(label, label, method_style(label, Role::Paper), 1);
//!     for seed in 0..3 {
//!         let curve: Vec<f64> = (0..10).map(|e| start - 3.0 * f64::from(e) + f64::from(seed)).collect();
//!         series.push(&curve);
//!     }
//!     chart = chart.with_series(series);
//! }
//! let svg = chart.render_svg()?;
//! assert!(eamadm_present::checks::check_figures(&[("steps.svg".to_owned(), svg)]).is_empty());
//! # Ok::<(), eamadm_present::chart::FigureError>(())
//! ```

pub mod chart;
pub mod checks;
pub mod family;
pub mod figures;
pub mod generated;
pub mod report;
pub mod theme;
