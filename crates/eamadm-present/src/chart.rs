//! SVG line charts of per-episode curves over seeds, drawn with the estimator the tables use:
//! for each method the **interquartile mean** (IQM) over seeds as a line and the 95 %
//! percentile-bootstrap interval of that IQM as a translucent band ([`eamadm_eval::stats`], the
//! functions behind `REPORT.md`'s numbers). A bootstrap interval of a statistic of the seeds'
//! values lies between the smallest and largest value, so a band can never leave its metric's
//! range (no negative steps, no success share above 1).
//!
//! What a chart can add: thin per-seed lines (so a collapse or a seed stuck at the step cap is
//! seen, not averaged away), a panel of the number of seeds at the step cap per episode, a
//! zoomed panel of the final episodes (so the end of training is readable when the first
//! episodes span orders of magnitude more), dashed reference lines (the optimum).
//!
//! Every method has one look ([`crate::theme`]): its colour and dash are the same in every
//! figure. EA-MADM is drawn last, on top. Titles, legends and captions are wrapped to the
//! canvas with a conservative estimate of the text's width ([`text_width`]), and the figure
//! checks ([`crate::checks`]) verify it on every figure of a run.
//!
//! The SVG is written directly (no plotting library): it needs `stroke-dasharray` for the
//! methods' dashes and carries, for the checks, the data coordinates of each plot
//! (`data-x0`…) and the method of each line (`data-method`). Coordinates are rounded to a
//! tenth of a pixel and nothing depends on time or the machine, so equal input gives equal
//! bytes.
//!
//! ```
//! use eamadm_eval::Role;
//! use eamadm_present::chart::{LineChart, Series};
//! use eamadm_present::theme::method_style;
//!
//! let style = method_style("ea-madm", Role::Paper);
//! let mut ea_madm = Series::new("ea-madm", "EA-MADM", style, 5);
//! for seed in 0..4 {
//!     let steps: Vec<f64> = (0..30).map(|e| 200.0 / f64::from(e + 1) + f64::from(seed)).collect();
//!     ea_madm.push(&steps);
//! }
//! let svg = LineChart::new("Task I: steps per episode", "episode", "steps per episode")
//!     .with_smoothing(5)
//!     .with_series(ea_madm)
//!     .with_reference_line("BFS optimum = 58", 58.0)
//!     .render_svg()?;
//! assert!(svg.starts_with("<svg") && svg.contains("data-method=\"ea-madm\""));
//! # Ok::<(), eamadm_present::chart::FigureError>(())
//! ```

use std::fmt::Write as _;

use crate::theme::MethodStyle;
use eamadm_eval::stats::{self, Bootstrap, Statistic};
use eamadm_eval::summary::{self, StatsError};
use thiserror::Error;

/// Bad chart input, or a failure to write it.
#[derive(Debug, Error)]
pub enum FigureError {
    /// A chart with no series.
    #[error("chart {title:?} has no series")]
    NoSeries {
        /// The chart's title.
        title: String,
    },
    /// A series whose curves cannot be summarised.
    #[error("series {series:?}: {source}")]
    Series {
        /// The series' name.
        series: String,
        /// What is wrong with its curves.
        #[source]
        source: StatsError,
    },
    /// The bootstrap band of a series failed (values near `f64::MAX`).
    #[error("series {series:?}, episode {episode}: {source}")]
    Band {
        /// The series' name.
        series: String,
        /// The episode (from 1).
        episode: usize,
        /// Why.
        #[source]
        source: stats::StatsError,
    },
    /// A reference line at a NaN or infinite height.
    #[error("reference line {label:?}: value {value} is not finite")]
    NonFiniteReference {
        /// The line's label.
        label: String,
        /// Its value.
        value: f64,
    },
    /// A smoothing window of zero episodes.
    #[error("smoothing window must be at least 1 episode, got 0")]
    ZeroSmoothingWindow,
    /// A series smoothed over another window than its chart's.
    #[error(
        "series {series:?} is smoothed over {series_window} episodes but its chart over \
         {chart_window}; make the series with the chart's window"
    )]
    SmoothingMismatch {
        /// The series' name.
        series: String,
        /// The window the series' curves were smoothed with.
        series_window: usize,
        /// The chart's window.
        chart_window: usize,
    },
    /// A share series ([`Series::share`]) with a value that no share of 0/1 outcomes takes.
    #[error(
        "series {series:?} is a share of 0/1 outcomes but has {value} at episode {episode}; push \
         0/1 curves (1 for a reached episode) or leave `share` unset"
    )]
    ShareOutOfRange {
        /// The series' name.
        series: String,
        /// The episode (from 1).
        episode: usize,
        /// The value, smoothed over the window, outside [0, 1].
        value: f64,
    },
    /// A canvas too narrow for the plot and the legend.
    #[error("chart width {width} px is below the minimum {MIN_WIDTH} px")]
    TooSmall {
        /// Requested width in pixels.
        width: u32,
    },
}

/// Narrowest accepted canvas.
const MIN_WIDTH: u32 = 600;
/// Bootstrap resamples of each band point: enough for a figure's 95 % band (its ends move by
/// well under a line's width between seeds of the bootstrap).
pub const FIGURE_RESAMPLES: u32 = 1_000;
/// The most episodes per series at which the band is bootstrapped; on longer curves it is
/// computed every `⌈episodes / MAX_BAND_POINTS⌉` episodes (and at the last) and the caption
/// says so. The curves are moving averages, so the band changes slowly between those points.
pub const MAX_BAND_POINTS: usize = 100;
/// The seeds up to which a series gets all [`MAX_BAND_POINTS`] band points. Each point costs
/// [`FIGURE_RESAMPLES`] resamples of every seed, so with more seeds the band is computed at
/// proportionally fewer points (at least [`MIN_BAND_POINTS`]): the band's cost stays that of
/// `MAX_BAND_POINTS × BAND_FULL_SEEDS` seeds' values instead of growing with thousands of
/// seeds (docs/paper-notes.md §24), and the caption says every how many episodes it was
/// computed. With more seeds the band is narrower and smoother (its width falls as
/// 1/√seeds), so fewer points lose little.
pub const BAND_FULL_SEEDS: usize = 50;
/// The fewest band points a bootstrapped series gets, however many seeds it has (besides the
/// last episode's).
pub const MIN_BAND_POINTS: usize = 5;
/// Seed of the bootstrap of every band point (the episode index is added).
const BAND_SEED: u64 = 0x0F16_0BAD;

/// One method's curves over seeds, taken one seed at a time and kept smoothed (one number per
/// seed and episode): the IQM and its bootstrap band need every seed's value at each episode.
///
/// The first bad curve (empty, or with a NaN or infinite value) is kept as the series' failure
/// and the curves after it are ignored; drawing the series then fails naming it, the seed (its
/// position among the curves pushed) and the episode. A series that is never drawn never fails.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The method's label (`data-method` in the SVG, for the checks).
    pub method: String,
    /// Legend label, e.g. `"EA-MADM"`.
    pub name: String,
    /// The method's colour and dash.
    pub style: MethodStyle,
    /// Trailing moving-average window each curve is smoothed with (1: none).
    smoothing_window: usize,
    /// Curves pushed, failed ones included.
    pushed: usize,
    /// The smoothed curves, in the order pushed.
    curves: Vec<Vec<f64>>,
    /// Per episode, the number of seeds whose episode hit the step cap.
    at_cap: Vec<u32>,
    /// The first bad curve's error.
    failure: Option<StatsError>,
    /// Whether the chart draws a thin line per seed.
    pub per_seed: bool,
    /// Whether the curves are 0/1 outcomes (reached the target or not): the line is then the
    /// share pooled over seeds and the smoothing window, with its Wilson 95 % interval as the
    /// band, never an IQM of 0s and 1s (which reads 0 while a quarter of the seeds succeed).
    pub share: bool,
    /// Whether it is drawn last, on top of the others (the paper's EA-MADM).
    pub on_top: bool,
    /// Per seed noted, the episode from which its run never reached the target again, if it
    /// collapsed ([`Series::note_collapse`]); the collapse strip draws them.
    collapses: Vec<Option<u64>>,
    /// The methods of the series that draw exactly as this one and are drawn as it
    /// (`data-also` in the SVG).
    also: Vec<String>,
}

/// What a plot draws of the series: each one's line and band, the draw order, and each one's
/// stroke width in that plot.
#[derive(Clone, Copy)]
struct Lines<'a> {
    drawn: &'a [Drawn],
    order: &'a [usize],
    widths: &'a [f64],
}

/// What is drawn of a series: the IQM per episode and band points (episode index, low, high).
#[derive(Debug, Clone, PartialEq)]
struct Drawn {
    line: Vec<f64>,
    band: Vec<(usize, f64, f64)>,
}

impl Series {
    /// A series without curves of the method labelled `method`, shown as `name`, whose curves
    /// are smoothed over `smoothing_window` episodes (1 = none; it must be its chart's window).
    pub fn new(
        method: impl Into<String>,
        name: impl Into<String>,
        style: MethodStyle,
        smoothing_window: usize,
    ) -> Self {
        Self {
            method: method.into(),
            name: name.into(),
            style,
            smoothing_window,
            pushed: 0,
            curves: Vec::new(),
            at_cap: Vec::new(),
            failure: None,
            per_seed: false,
            share: false,
            on_top: false,
            collapses: Vec::new(),
            also: Vec::new(),
        }
    }

    /// Notes the next seed's run outcome for the collapse strip: the episode from which it
    /// never reached the target again when it collapsed, else `None`.
    pub fn note_collapse(&mut self, episode: Option<u64>) {
        self.collapses.push(episode);
    }

    /// The episodes the noted seeds collapsed from, in seed order, and the seeds noted.
    #[must_use]
    pub fn collapses(&self) -> (Vec<u64>, usize) {
        (
            self.collapses.iter().flatten().copied().collect(),
            self.collapses.len(),
        )
    }

    /// Whether every value of every curve is 0 (a chart of such series shows nothing).
    #[must_use]
    pub fn all_zero(&self) -> bool {
        self.failure.is_none() && self.curves.iter().flatten().all(|v| *v == 0.0)
    }

    /// Whether `other` draws exactly what this series draws: the same curves, seeds at the
    /// cap, collapses and estimator (then one line stands for both).
    #[must_use]
    pub fn draws_as(&self, other: &Self) -> bool {
        self.failure.is_none()
            && other.failure.is_none()
            && self.curves == other.curves
            && self.at_cap == other.at_cap
            && self.collapses == other.collapses
            && self.share == other.share
            && self.smoothing_window == other.smoothing_window
    }

    /// The pooled share at episode index `episode` of 0/1 curves smoothed over the window:
    /// (successes, trials) over the seeds with a value there.
    fn pooled(&self, episode: usize) -> (u64, u64) {
        let count = (episode + 1).min(self.smoothing_window.max(1)) as f64;
        self.curves.iter().filter_map(|c| c.get(episode)).fold(
            (0, 0),
            |(successes, trials), value| {
                // Clamped so that a value outside [0, 1] (refused by the chart,
                // `outside_zero_to_one`) can neither wrap the counts nor exceed the trials.
                (
                    successes + (value.clamp(0.0, 1.0) * count).round() as u64,
                    trials + count as u64,
                )
            },
        )
    }

    /// The first (episode index, smoothed value) outside [0, 1], which no share of 0/1
    /// outcomes takes; `None` when every value lies inside.
    fn outside_zero_to_one(&self) -> Option<(usize, f64)> {
        self.curves.iter().find_map(|curve| {
            curve
                .iter()
                .enumerate()
                .find(|(_, v)| !(0.0..=1.0).contains(*v))
                .map(|(episode, &value)| (episode, value))
        })
    }

    /// Adds the next seed's curve (`curve[episode]`).
    pub fn push(&mut self, curve: &[f64]) {
        let seed = self.pushed;
        self.pushed += 1;
        if self.failure.is_some() {
            return;
        }
        if curve.is_empty() {
            self.failure = Some(StatsError::EmptyCurve { seed });
            return;
        }
        if let Some((episode, &value)) = curve.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            self.failure = Some(StatsError::NonFiniteInCurve {
                seed,
                episode,
                value,
            });
            return;
        }
        match summary::moving_average(curve, self.smoothing_window.max(1)) {
            Ok(smoothed) => self.curves.push(smoothed),
            Err(error) => self.failure = Some(error),
        }
    }

    /// Counts, per episode, the seed's episodes that hit the step cap (`at_cap[episode]`).
    pub fn count_at_cap(&mut self, at_cap: &[bool]) {
        if self.at_cap.len() < at_cap.len() {
            self.at_cap.resize(at_cap.len(), 0);
        }
        for (count, &capped) in self.at_cap.iter_mut().zip(at_cap) {
            *count += u32::from(capped);
        }
    }

    /// Curves pushed so far (seeds), failed ones included.
    pub fn seeds(&self) -> usize {
        self.pushed
    }

    /// The pooled share at the last episode of the longest curves, with its successes and
    /// trials (a [`share`](Self::share) series); `None` without curves, or when a value lies
    /// outside [0, 1] (no share of 0/1 outcomes).
    #[must_use]
    pub fn final_share(&self) -> Option<(f64, u64, u64)> {
        if self.outside_zero_to_one().is_some() {
            return None;
        }
        let last = self.curves_len().checked_sub(1)?;
        let (successes, trials) = self.pooled(last);
        (trials > 0).then(|| (successes as f64 / trials as f64, successes, trials))
    }

    /// The IQM over seeds of the last episode of the longest curves (their smoothed value
    /// there), and how many seeds hit the step cap in that episode; `None` without curves.
    pub fn final_iqm(&self) -> Option<(f64, u32)> {
        let longest = self.curves_len();
        let values: Vec<f64> = self
            .curves
            .iter()
            .filter_map(|c| c.get(longest.checked_sub(1)?).copied())
            .collect();
        let at_cap = self
            .at_cap
            .get(longest.wrapping_sub(1))
            .copied()
            .unwrap_or(0);
        Some((stats::iqm(&values).ok()?, at_cap))
    }

    /// Per episode (x index from 0), the seeds whose curve has a value there
    /// ([`eamadm_eval::reaching::seeds_contributing`]); up to the longest curve.
    pub fn seeds_per_x(&self) -> Vec<usize> {
        let lengths: Vec<usize> = self.curves.iter().map(Vec::len).collect();
        eamadm_eval::reaching::seeds_contributing(&lengths)
    }

    /// Episodes of the longest curve.
    pub fn curves_len(&self) -> usize {
        self.curves.iter().map(Vec::len).max().unwrap_or(0)
    }

    /// Seeds behind the series' last point: the curves as long as the longest. Fewer than
    /// [`Self::seeds`] where curves end early (over reaching episodes, a seed that reached
    /// fewer times drops out), so with it a caption can state the range along x.
    pub fn seeds_at_end(&self) -> usize {
        let longest = self.curves_len();
        self.curves.iter().filter(|c| c.len() == longest).count()
    }

    /// Numbers held (for the memory law: one per seed and episode).
    #[cfg(test)]
    pub fn held_numbers(&self) -> usize {
        self.curves.iter().map(Vec::len).sum::<usize>() + self.at_cap.len()
    }

    /// The IQM per episode over the seeds that reach it, and its bootstrap band every `stride`
    /// episodes (and at the last), each band (low, high) asked of `band_of`, given the episode
    /// and the values there, in episode order.
    fn drawn_by(&self, stride: usize, band_of: &mut BandOf<'_>) -> Result<Drawn, FigureError> {
        if let Some(failure) = &self.failure {
            return Err(self.error(failure.clone()));
        }
        if self.curves.is_empty() {
            return Err(self.error(StatsError::NoSeeds));
        }
        let longest = self.curves.iter().map(Vec::len).max().unwrap_or(0);
        let mut line = Vec::with_capacity(longest);
        let mut band = Vec::new();
        let mut values = Vec::with_capacity(self.curves.len());
        for episode in 0..longest {
            values.clear();
            values.extend(self.curves.iter().filter_map(|c| c.get(episode).copied()));
            let band_error = |source| FigureError::Band {
                series: self.name.clone(),
                episode: episode + 1,
                source,
            };
            if self.share {
                let (successes, trials) = self.pooled(episode);
                let interval = stats::wilson(successes, trials, 0.95).map_err(band_error)?;
                line.push(interval.estimate);
                band.push((episode, interval.low, interval.high));
                continue;
            }
            line.push(stats::iqm(&values).map_err(band_error)?);
            if episode % stride == 0 || episode + 1 == longest {
                let (low, high) = band_of(episode, &values).map_err(band_error)?;
                band.push((episode, low, high));
            }
        }
        Ok(Drawn { line, band })
    }

    fn error(&self, source: StatsError) -> FigureError {
        FigureError::Series {
            series: self.name.clone(),
            source,
        }
    }
}

/// Answers a series' band (low, high) at an episode from the values there
/// ([`Series::drawn_by`]).
type BandOf<'a> = dyn FnMut(usize, &[f64]) -> Result<(f64, f64), StatsError> + 'a;

/// The bootstrap of the band at `episode` (0-based): every series' band there draws the same
/// resamples, whichever chart it is in.
fn band_bootstrap(episode: usize) -> Result<Bootstrap, StatsError> {
    Bootstrap::new(FIGURE_RESAMPLES, 0.95, BAND_SEED + episode as u64)
}

/// Every how many episodes the band of a chart whose longest curve has `longest` episodes and
/// whose largest series has `seeds` seeds is bootstrapped: at most [`MAX_BAND_POINTS`] points,
/// and beyond [`BAND_FULL_SEEDS`] seeds proportionally fewer, down to [`MIN_BAND_POINTS`].
fn band_stride(longest: usize, seeds: Option<usize>) -> usize {
    let seeds = seeds.unwrap_or(1).max(1);
    let points = if seeds <= BAND_FULL_SEEDS {
        MAX_BAND_POINTS
    } else {
        (MAX_BAND_POINTS * BAND_FULL_SEEDS / seeds).max(MIN_BAND_POINTS)
    };
    longest.div_ceil(points).max(1)
}

/// A dashed horizontal line with a legend label, e.g. `"BFS optimum = 58"` at 58.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceLine {
    /// Legend label.
    pub label: String,
    /// Height in data units.
    pub y: f64,
}

/// A line chart of per-episode curves over seeds; build it with [`LineChart::new`] and the
/// `with_*` methods, then call [`LineChart::render_svg`].
#[derive(Debug, Clone, PartialEq)]
pub struct LineChart {
    /// Title above the chart (wrapped to the canvas).
    pub title: String,
    /// Smaller text under the title (wrapped), e.g. what the figure is the analogue of.
    pub subtitle: String,
    /// Label of the x axis (episodes, numbered from 1), with its unit.
    pub x_label: String,
    /// Label of the y axis, with its unit.
    pub y_label: String,
    /// The metric's range, `(lowest, highest)` where bounded: the y axis never leaves it and
    /// the checks hold every band inside it.
    pub metric_range: (Option<f64>, Option<f64>),
    /// The series, in legend order (EA-MADM is drawn last whatever its place).
    pub series: Vec<Series>,
    /// Dashed horizontal reference lines.
    pub reference_lines: Vec<ReferenceLine>,
    /// Trailing moving-average window applied to every seed's curve before the IQM over seeds
    /// ([`summary::moving_average`]); 1 means no smoothing.
    pub smoothing_window: usize,
    /// A panel of the seeds at the step cap per episode, titled with this text.
    pub cap_panel: Option<String>,
    /// A panel zoomed on the final this-many episodes, beside the whole run.
    pub final_zoom: Option<usize>,
    /// A panel of the seeds each series' line is the IQM of, per episode, titled with this
    /// text (seeds whose curves are shorter drop out to the right).
    pub seed_panel: Option<String>,
    /// The x axis's last episode, when fixed (otherwise the longest curve's).
    pub x_end: Option<usize>,
    /// A strip under the plot marking, per series, the episode each collapsed seed never
    /// reached the target again from ([`Series::note_collapse`]), so that collapses are seen
    /// in every figure, not averaged away.
    pub collapse_strip: bool,
    /// Canvas width in pixels (the height follows from the content).
    pub width: u32,
}

/// Colour of reference lines (dark grey, dashed) and of secondary text.
const REFERENCE_COLOUR: &str = "#444444";
const NOTE_COLOUR: &str = "#444444";
/// Opacity of the bands and of the per-seed lines.
const BAND_OPACITY: f64 = 0.16;
/// The opacity and width (px) of a band drawn as bars ([`band_as_bars`]): a bar is thin, so it
/// is drawn denser than an area.
const BAND_BAR_OPACITY: f64 = 0.4;
const BAND_BAR_WIDTH: f64 = 5.0;

/// Whether a panel holding `points` of a band computed every `stride` episodes draws them as
/// bars, one per computed episode, instead of an area through them. With the band at every
/// episode the area is exact; with a stride, an area through fewer than [`MIN_BAND_POINTS`]
/// points (the zoomed panel of a chart of 1000 seeds holds two) is a straight wedge from one to
/// the next that no computed interval supports.
fn band_as_bars(stride: usize, points: usize) -> bool {
    stride > 1 && points > 0 && points < MIN_BAND_POINTS
}
const SEED_OPACITY: f64 = 0.35;
/// Width (px) of the per-seed lines.
const SEED_WIDTH: f64 = 0.8;

/// A `class` polyline of `series`' colour through `points` at `(width, opacity)`: the thin
/// lines per seed and the bars of a band ([`band_as_bars`]).
fn translucent_stroke(
    svg: &mut String,
    class: &str,
    series: &Series,
    (width, opacity): (f64, f64),
    points: &str,
) {
    let _ = writeln!(
        svg,
        "<polyline class=\"{class}\" data-method=\"{}\" fill=\"none\" stroke=\"{}\" \
         stroke-width=\"{width}\" stroke-opacity=\"{opacity}\" points=\"{points}\"/>",
        escape(&series.method),
        series.style.colour,
    );
}
/// Font sizes in pixels.
const TITLE_FONT: f64 = 18.0;
const SUBTITLE_FONT: f64 = 13.0;
const AXIS_FONT: f64 = 14.0;
const TICK_FONT: f64 = 12.0;
const LEGEND_FONT: f64 = 13.0;
const CAPTION_FONT: f64 = 12.0;
/// Layout in pixels.
const PAD: f64 = 12.0;
const LEGEND_WIDTH: f64 = 250.0;
const LEGEND_SAMPLE: f64 = 30.0;
const Y_AXIS_ROOM: f64 = 66.0;
const X_AXIS_ROOM: f64 = 46.0;
const PLOT_HEIGHT: f64 = 330.0;
const CAP_PANEL_HEIGHT: f64 = 80.0;
/// Share of the plot's width the zoomed panel takes.
const ZOOM_SHARE: f64 = 0.3;

/// Conservative estimate of the width in pixels of `text` at `font` px in a sans-serif face:
/// 0.85 em for capitals and `m`/`w`, 0.65 em for every other character (the `DejaVu Sans` face, the
/// widest common default, averages about 0.6 em for lower case and digits).
pub fn text_width(text: &str, font: f64) -> f64 {
    text.chars()
        .map(|c| {
            if c.is_uppercase() || c == 'm' || c == 'w' {
                0.85
            } else {
                0.65
            }
        })
        .sum::<f64>()
        * font
}

/// Greedy word wrap to lines at most `width` px wide at `font` px (a longer word keeps its
/// own line).
pub fn wrap(text: &str, width: f64, font: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line} {word}"), font) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ if text_width(word, font) > width => lines.extend(break_word(word, width, font)),
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

/// A word wider than `width` (a long method label such as
/// `epsilon-decreasing-shaped-repaired`) as lines broken after its hyphens, each hyphen kept at
/// the end of its line; a part that is still too wide is broken between characters.
fn break_word(word: &str, width: f64, font: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for part in word.split_inclusive('-') {
        if !line.is_empty() && text_width(&format!("{line}{part}"), font) > width {
            lines.push(std::mem::take(&mut line));
        }
        for character in part.chars() {
            if !line.is_empty() && text_width(&format!("{line}{character}"), font) > width {
                lines.push(std::mem::take(&mut line));
            }
            line.push(character);
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// A legend entry's label, `lines` beside its sample centred at `middle`; returns the height
/// the entry takes (one line at least, and the gap to the next entry).
fn legend_label(svg: &mut String, text_x: f64, middle: f64, lines: &[String]) -> f64 {
    for (index, line) in lines.iter().enumerate() {
        text_element(
            svg,
            (
                text_x,
                middle + LEGEND_FONT * 0.35 + index as f64 * LEGEND_FONT * 1.2,
            ),
            LEGEND_FONT,
            "start",
            "#111111",
            line,
        );
    }
    LEGEND_FONT * 1.2 * lines.len().max(1) as f64 + 8.0
}

/// Escapes text for SVG.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A number rounded to a tenth, as SVG coordinates are written.
pub fn px(value: f64) -> String {
    let mut text = String::new();
    Px::of(value).write(&mut text);
    text
}

/// A number rounded to a tenth, held as its count of tenths where that prints exactly, so a
/// chart's thousands of coordinates are compared and written without formatting a float each
/// (a figure of 1000 seeds draws about a million points; docs/paper-notes.md §24.3).
#[derive(Debug, Clone, PartialEq)]
enum Px {
    /// `value × 10` rounded, below [`Px::EXACT_TENTHS`] in size and not −0.
    Tenths(i64),
    /// Any other value's text: `{:.0}` of the rounded value when it is whole, else `{:.1}`.
    Text(String),
}

impl Px {
    /// Tenths below this in size print exactly from the integer: a tenth of them is a float
    /// within far less than 0.05 of the decimal, which `{:.1}` therefore prints, and it is
    /// whole exactly when the tenths are a multiple of ten.
    const EXACT_TENTHS: f64 = 1e12;

    fn of(value: f64) -> Self {
        let tenths = (value * 10.0).round();
        if tenths.abs() < Self::EXACT_TENTHS && !(tenths == 0.0 && tenths.is_sign_negative()) {
            #[expect(
                clippy::cast_possible_truncation,
                reason = "a whole number below 10¹² in size converts exactly"
            )]
            return Self::Tenths(tenths as i64);
        }
        let rounded = tenths / 10.0;
        Self::Text(if rounded == rounded.trunc() {
            format!("{rounded:.0}")
        } else {
            format!("{rounded:.1}")
        })
    }

    fn write(&self, text: &mut String) {
        match self {
            Self::Tenths(tenths) => {
                let (whole, tenth) = (tenths / 10, (tenths % 10).unsigned_abs());
                if *tenths < 0 && whole == 0 {
                    text.push('-');
                }
                text.push_str(itoa::Buffer::new().format(whole));
                if tenth != 0 {
                    text.push('.');
                    text.push_str(itoa::Buffer::new().format(tenth));
                }
            }
            Self::Text(rounded) => text.push_str(rounded),
        }
    }
}

/// A `<text>` element (`anchor`: `start`, `middle` or `end`).
pub fn text_element(
    svg: &mut String,
    (x, y): (f64, f64),
    font: f64,
    anchor: &str,
    colour: &str,
    text: &str,
) {
    let _ = writeln!(
        svg,
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\" fill=\"{colour}\">{}</text>",
        px(x),
        px(y),
        px(font),
        escape(text)
    );
}

/// Wrapped lines of `text` starting at baseline `y`; returns the `y` below the last line.
pub fn wrapped_text(
    svg: &mut String,
    (x, y): (f64, f64),
    width: f64,
    font: f64,
    anchor: &str,
    colour: &str,
    text: &str,
) -> f64 {
    let mut y = y;
    for line in wrap(text, width, font) {
        y += font * 1.25;
        text_element(svg, (x, y), font, anchor, colour, &line);
    }
    y
}

/// ` data-also="m2 m3"`: the methods a merged series also draws (empty when none).
fn also_attribute(series: &Series) -> String {
    if series.also.is_empty() {
        String::new()
    } else {
        format!(" data-also=\"{}\"", escape(&series.also.join(" ")))
    }
}

/// The SVG attributes of a method's stroke: colour and dash.
pub fn stroke_attributes(style: &MethodStyle) -> String {
    let mut attributes = format!("stroke=\"{}\"", style.colour);
    if let Some(dash) = style.dash.dasharray() {
        let _ = write!(attributes, " stroke-dasharray=\"{dash}\"");
    }
    attributes
}

/// A round tick step (1, 2 or 5 × 10ⁿ) giving about `target` intervals over `span`.
fn tick_step(span: f64, target: f64) -> f64 {
    if !(span.is_finite() && span > 0.0) {
        return 1.0;
    }
    let raw = span / target;
    let decade = 10_f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&step| step >= raw)
        .unwrap_or(10.0 * decade)
}

/// Decimals to print ticks `step` apart.
fn tick_decimals(step: f64) -> usize {
    if step >= 1.0 || !(step.is_finite() && step > 0.0) {
        0
    } else {
        (-step.log10().floor()).min(6.0) as usize
    }
}

/// A rectangle of the canvas holding a plot, and the data range it shows.
#[derive(Debug, Clone, Copy)]
struct Frame {
    left: f64,
    right: f64,
    top: f64,
    bottom: f64,
    x: (f64, f64),
    y: (f64, f64),
}

impl Frame {
    fn at(&self, x: f64, y: f64) -> (f64, f64) {
        let fx = (x - self.x.0) / (self.x.1 - self.x.0);
        let fy = (y - self.y.0) / (self.y.1 - self.y.0);
        (
            self.left + fx * (self.right - self.left),
            self.bottom - fy * (self.bottom - self.top),
        )
    }

    /// The SVG `points` of `points` in this frame, rounded to a tenth of a pixel, leaving out
    /// every point that lies strictly between its two neighbours on one horizontal line: the
    /// drawn line is the same, and long runs at one value (a seed at the step cap, a converged
    /// seed) take two points instead of hundreds.
    fn points(&self, points: impl Iterator<Item = (f64, f64)>) -> String {
        let rounded: Vec<(f64, Px, Px)> = points
            .map(|(x, y)| {
                let (a, b) = self.at(x, y);
                (a, Px::of(a), Px::of(b))
            })
            .collect();
        let mut text = String::with_capacity(12 * rounded.len());
        for (index, (a, x, y)) in rounded.iter().enumerate() {
            let between = index > 0
                && rounded.get(index + 1).is_some_and(|(next_a, _, next_y)| {
                    let (previous_a, _, previous_y) = &rounded[index - 1];
                    previous_y == y
                        && next_y == y
                        && ((previous_a < a && a < next_a) || (next_a < a && a < previous_a))
                });
            if !between {
                if !text.is_empty() {
                    text.push(' ');
                }
                x.write(&mut text);
                text.push(',');
                y.write(&mut text);
            }
        }
        text
    }

    /// Opens the plot's group, with the data attributes the checks read, and draws its frame,
    /// grid and ticks.
    fn open(&self, svg: &mut String, class: &str, metric: (Option<f64>, Option<f64>)) {
        let _ = write!(
            svg,
            "<g class=\"{class}\" data-left=\"{}\" data-right=\"{}\" data-top=\"{}\" \
             data-bottom=\"{}\" data-x0=\"{}\" data-x1=\"{}\" data-y0=\"{}\" data-y1=\"{}\"",
            self.left, self.right, self.top, self.bottom, self.x.0, self.x.1, self.y.0, self.y.1
        );
        if let Some(low) = metric.0 {
            let _ = write!(svg, " data-metric-min=\"{low}\"");
        }
        if let Some(high) = metric.1 {
            let _ = write!(svg, " data-metric-max=\"{high}\"");
        }
        svg.push_str(">\n");
        let _ = writeln!(
            svg,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"white\" stroke=\"#888888\"/>",
            px(self.left),
            px(self.top),
            px(self.right - self.left),
            px(self.bottom - self.top)
        );
        for (tick, label) in y_ticks(self.y) {
            let (_, y) = self.at(self.x.0, tick);
            let _ = writeln!(
                svg,
                "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#e4e4e4\"/>",
                px(self.left),
                px(y),
                px(self.right),
                px(y)
            );
            text_element(
                svg,
                (self.left - 5.0, y + TICK_FONT * 0.35),
                TICK_FONT,
                "end",
                "#333333",
                &label,
            );
        }
        let width = self.right - self.left;
        let x_step = tick_step(self.x.1 - self.x.0, (width / 90.0).clamp(2.0, 10.0)).max(1.0);
        let mut tick = (self.x.0 / x_step).ceil() * x_step;
        while tick <= self.x.1 + 1e-9 {
            let (x, _) = self.at(tick, self.y.0);
            text_element(
                svg,
                (x, self.bottom + TICK_FONT + 4.0),
                TICK_FONT,
                "middle",
                "#333333",
                &format!("{tick:.0}"),
            );
            tick += x_step;
        }
    }
}

/// The y tick labels of a range, with their values (as [`Frame::open`] draws them).
fn y_ticks(y: (f64, f64)) -> Vec<(f64, String)> {
    let span = y.1 - y.0;
    // A range wider than the largest float (values near ±f64::MAX) is stepped by halves;
    // without that the step fell back to 1 and the loop ran over 10^308 ticks.
    let step = if span.is_finite() {
        tick_step(span, 5.0)
    } else {
        2.0 * tick_step(y.1 / 2.0 - y.0 / 2.0, 5.0)
    };
    let decimals = tick_decimals(step);
    let mut ticks = Vec::new();
    let mut tick = (y.0 / step).ceil() * step;
    // A step too small to move the tick at this magnitude ends the axis too.
    while tick <= y.1 + step * 1e-9 && ticks.len() < MAX_Y_TICKS {
        let label = format!("{:.*}", decimals, if tick == 0.0 { 0.0 } else { tick });
        ticks.push((tick, label));
        let next = tick + step;
        if next == tick {
            break;
        }
        tick = next;
    }
    ticks
}

/// More y ticks than a plot has room for: [`y_ticks`] aims at five.
const MAX_Y_TICKS: usize = 32;

/// The width of the widest y tick label of a range.
fn widest_tick(y: (f64, f64)) -> f64 {
    y_ticks(y)
        .iter()
        .map(|(_, label)| text_width(label, TICK_FONT))
        .fold(0.0, f64::max)
}

/// Each series' stroke width, so that a line lying under a later one stays visible around
/// it: 2 px, and 2 px wider than the widest later line it runs along (within 1.5 px of it, in
/// a plot of height [`PLOT_HEIGHT`] over `y`) on at least a tenth of its episodes from `from`
/// on. Each panel has its own: lines apart in the zoomed panel are drawn thin there.
fn line_widths(drawn: &[Drawn], order: &[usize], y: (f64, f64), from: usize) -> Vec<f64> {
    let close = 1.5 / PLOT_HEIGHT * (y.1 - y.0);
    let mut widths = vec![2.0; drawn.len()];
    for (position, &i) in order.iter().enumerate().rev() {
        let line = drawn[i].line.get(from..).unwrap_or(&[]);
        let under = order[position + 1..]
            .iter()
            .filter(|&&j| {
                let other = drawn[j].line.get(from..).unwrap_or(&[]);
                let common = line.len().min(other.len());
                let near = line
                    .iter()
                    .zip(other)
                    .filter(|(a, b)| (*a - *b).abs() <= close)
                    .count();
                common > 0 && near * 10 >= common
            })
            .map(|&j| widths[j])
            .fold(0.0, f64::max);
        if under > 0.0 {
            widths[i] = (under + 2.0).min(8.0);
        }
    }
    widths
}

/// A y-axis label, rotated, centred on the frame's height, `room` pixels left of the frame.
fn y_label(svg: &mut String, frame: &Frame, label: &str, room: f64) {
    let x = frame.left - room + AXIS_FONT;
    let y = (frame.top + frame.bottom) / 2.0;
    let _ = writeln!(
        svg,
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"middle\" fill=\"#222222\" \
         transform=\"rotate(-90 {} {})\">{}</text>",
        px(x),
        px(y),
        px(AXIS_FONT),
        px(x),
        px(y),
        escape(label)
    );
}

/// The y range of `values` padded by 4 %, kept inside the metric's range.
fn padded_range(
    values: impl Iterator<Item = f64>,
    metric: (Option<f64>, Option<f64>),
) -> (f64, f64) {
    let (low, high) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
        (lo.min(y), hi.max(y))
    });
    if !(low.is_finite() && high.is_finite()) {
        return (0.0, 1.0);
    }
    let pad = if high > low {
        0.04 * high - 0.04 * low
    } else {
        (0.1 * low.abs()).max(1.0)
    };
    let mut range = (low - pad, high + pad);
    if let Some(min) = metric.0 {
        range.0 = range.0.max(min.min(low));
    }
    if let Some(max) = metric.1 {
        range.1 = range.1.min(max.max(high));
    }
    if range.1 <= range.0 {
        range.1 = range.0 + 1.0;
    }
    range
}

impl LineChart {
    /// An empty 960 px wide chart with no smoothing.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            subtitle: String::new(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            metric_range: (None, None),
            series: Vec::new(),
            reference_lines: Vec::new(),
            smoothing_window: 1,
            cap_panel: None,
            final_zoom: None,
            seed_panel: None,
            x_end: None,
            collapse_strip: false,
            width: 960,
        }
    }

    /// Adds a series (made with this chart's smoothing window).
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Adds a dashed horizontal reference line at height `y`.
    pub fn with_reference_line(mut self, label: impl Into<String>, y: f64) -> Self {
        self.reference_lines.push(ReferenceLine {
            label: label.into(),
            y,
        });
        self
    }

    /// States that every seed's curve is smoothed over `window` episodes.
    pub fn with_smoothing(mut self, window: usize) -> Self {
        self.smoothing_window = window;
        self
    }

    /// Sets the subtitle.
    pub fn with_subtitle(mut self, subtitle: impl Into<String>) -> Self {
        self.subtitle = subtitle.into();
        self
    }

    /// Sets the metric's range.
    pub fn with_metric_range(mut self, low: Option<f64>, high: Option<f64>) -> Self {
        self.metric_range = (low, high);
        self
    }

    /// Adds the panel of seeds at the step cap.
    pub fn with_cap_panel(mut self, title: impl Into<String>) -> Self {
        self.cap_panel = Some(title.into());
        self
    }

    /// Adds the panel of the seeds behind each line per episode.
    pub fn with_seed_panel(mut self, title: impl Into<String>) -> Self {
        self.seed_panel = Some(title.into());
        self
    }

    /// Fixes the x axis to episodes 1 ..= `episodes` (curves are never longer: the caller
    /// cuts them).
    pub fn with_x_end(mut self, episodes: usize) -> Self {
        self.x_end = Some(episodes);
        self
    }

    /// Adds a panel zoomed on the final `episodes` episodes.
    pub fn with_final_zoom(mut self, episodes: usize) -> Self {
        self.final_zoom = Some(episodes);
        self
    }

    /// Adds the strip of collapsed seeds under the plot.
    #[must_use]
    pub fn with_collapse_strip(mut self) -> Self {
        self.collapse_strip = true;
        self
    }

    /// Sets the canvas width in pixels.
    pub fn with_width(mut self, width: u32) -> Self {
        self.width = width;
        self
    }

    /// Validates the input and computes each series' IQM line and band.
    fn drawn(&self) -> Result<(Vec<Drawn>, usize), FigureError> {
        self.drawn_by(&mut |episode, values| {
            let interval = band_bootstrap(episode)?.interval(values, Statistic::Iqm)?;
            Ok((interval.low, interval.high))
        })
    }

    /// [`Self::drawn`], each bootstrap band asked of `band_of` ([`Series::drawn_by`]), series
    /// by series.
    fn drawn_by(&self, band_of: &mut BandOf<'_>) -> Result<(Vec<Drawn>, usize), FigureError> {
        let stride = self.validated_stride()?;
        let drawn = self
            .series
            .iter()
            .map(|series| {
                self.check_smoothing(series)?;
                if let Some((episode, value)) =
                    series.share.then(|| series.outside_zero_to_one()).flatten()
                {
                    return Err(FigureError::ShareOutOfRange {
                        series: series.name.clone(),
                        episode: episode + 1,
                        value,
                    });
                }
                series.drawn_by(stride, band_of)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok((drawn, stride))
    }

    /// Checks the chart and its series' smoothing, and returns every how many episodes the
    /// bands are bootstrapped ([`band_stride`]).
    fn validated_stride(&self) -> Result<usize, FigureError> {
        if self.series.is_empty() {
            return Err(FigureError::NoSeries {
                title: self.title.clone(),
            });
        }
        if self.smoothing_window == 0 {
            return Err(FigureError::ZeroSmoothingWindow);
        }
        if self.width < MIN_WIDTH {
            return Err(FigureError::TooSmall { width: self.width });
        }
        if let Some(line) = self.reference_lines.iter().find(|l| !l.y.is_finite()) {
            return Err(FigureError::NonFiniteReference {
                label: line.label.clone(),
                value: line.y,
            });
        }
        let longest = self
            .series
            .iter()
            .flat_map(|s| s.curves.iter().map(Vec::len))
            .max()
            .unwrap_or(1);
        Ok(band_stride(
            longest,
            self.series.iter().map(Series::seeds).max(),
        ))
    }

    /// Checks that `series` is smoothed as the chart is (before it is drawn, so that errors
    /// come series by series).
    fn check_smoothing(&self, series: &Series) -> Result<(), FigureError> {
        if series.smoothing_window == self.smoothing_window {
            return Ok(());
        }
        Err(FigureError::SmoothingMismatch {
            series: series.name.clone(),
            series_window: series.smoothing_window,
            chart_window: self.smoothing_window,
        })
    }

    /// The caption's sentences: estimator, band, smoothing, what the thin lines are.
    fn notes(&self, stride: usize, bars: bool) -> Vec<String> {
        let (fewest, most) = (
            self.series
                .iter()
                .map(Series::seeds_at_end)
                .min()
                .unwrap_or(0),
            self.series.iter().map(Series::seeds).max().unwrap_or(0),
        );
        let over = if fewest == most {
            format!("{most} seeds")
        } else {
            format!("{fewest}–{most} seeds")
        };
        let smoothing = if self.smoothing_window > 1 {
            format!(
                "each seed's {}-episode trailing moving average",
                self.smoothing_window
            )
        } else {
            "each seed's value".to_owned()
        };
        let band_points = match (stride > 1, bars) {
            (true, false) => format!(", computed every {stride} episodes)"),
            (true, true) => format!(
                ", computed every {stride} episodes; where a panel holds fewer than \
                 {MIN_BAND_POINTS} of them, each is a bar at its episode)"
            ),
            (false, _) => ")".to_owned(),
        };
        let mut notes = vec![if self.series.iter().all(|s| s.share) {
            format!(
                "Line: the share of episodes that reached the target, pooled over {over} and \
                 each seed's last {} episodes. Band: its Wilson 95% interval (the episodes of \
                 one seed are not independent, so it is too narrow).",
                self.smoothing_window
            )
        } else {
            format!(
                "Line: interquartile mean (IQM) over {over} of {smoothing}, as in the tables. \
                 Band: 95% percentile bootstrap interval of the IQM ({FIGURE_RESAMPLES} \
                 resamples{band_points}."
            )
        }];
        if self.series.iter().any(|s| s.per_seed) {
            notes.push("Thin lines: one per seed.".to_owned());
        }
        notes
    }

    /// Renders the chart as an SVG document.
    pub fn render_svg(&self) -> Result<String, FigureError> {
        self.merged_or_self().render_merged()
    }

    /// [`Self::merged`] where it merges series, else this chart as it is.
    fn merged_or_self(&self) -> std::borrow::Cow<'_, Self> {
        let merged = self.merged();
        if merged.series.len() < self.series.len() {
            std::borrow::Cow::Owned(merged)
        } else {
            std::borrow::Cow::Borrowed(self)
        }
    }

    /// Renders each of `charts` as [`Self::render_svg`] does, bit for bit, errors included,
    /// drawing each episode's band resamples once for all their series: every band at an
    /// episode has the same bootstrap, so series of as many seeds (one experiment's methods,
    /// its steps and its return) share the resamples ([`Bootstrap::intervals`]).
    ///
    /// # Errors
    /// The first error of the first chart that [`Self::render_svg`] fails on.
    pub fn render_svgs(charts: &[&Self]) -> Result<Vec<String>, FigureError> {
        match Self::render_sharing_bands(charts) {
            Some(svgs) => Ok(svgs),
            // Some chart fails: rendered one by one, for the error `render_svg` gives.
            None => charts.iter().map(|chart| chart.render_svg()).collect(),
        }
    }

    /// [`Self::render_svgs`] when no chart fails; `None` when one does.
    fn render_sharing_bands(charts: &[&Self]) -> Option<Vec<String>> {
        let merged: Vec<_> = charts.iter().map(|chart| chart.merged_or_self()).collect();
        // First every line, with the values of each band asked for (in order, per series).
        let mut asked: Vec<(usize, Vec<f64>)> = Vec::new();
        let mut drawn_charts = Vec::with_capacity(merged.len());
        for chart in &merged {
            let mut ask = |episode, values: &[f64]| {
                asked.push((episode, values.to_vec()));
                Ok((f64::NAN, f64::NAN))
            };
            drawn_charts.push(chart.drawn_by(&mut ask).ok()?);
        }
        // Then the bands, episode by episode, each episode's resamples drawn once.
        let mut by_episode: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for (index, (episode, _)) in asked.iter().enumerate() {
            by_episode.entry(*episode).or_default().push(index);
        }
        let mut bands = vec![(f64::NAN, f64::NAN); asked.len()];
        for (episode, indices) in by_episode {
            let samples: Vec<&[f64]> = indices.iter().map(|&i| asked[i].1.as_slice()).collect();
            let intervals = band_bootstrap(episode)
                .ok()?
                .intervals(&samples, Statistic::Iqm)
                .ok()?;
            for (&i, interval) in indices.iter().zip(intervals) {
                bands[i] = (interval.low, interval.high);
            }
        }
        // The bands asked for, in the order asked: a series' bootstrap bands are in order.
        let mut answers = bands.into_iter();
        for (chart, (drawn, _)) in merged.iter().zip(&mut drawn_charts) {
            for (series, drawn) in chart.series.iter().zip(drawn) {
                if series.share {
                    continue;
                }
                for point in &mut drawn.band {
                    let (low, high) = answers.next()?;
                    (point.1, point.2) = (low, high);
                }
            }
        }
        merged
            .iter()
            .zip(drawn_charts)
            .map(|(chart, (drawn, stride))| chart.render_drawn(&drawn, stride).ok())
            .collect()
    }

    /// This chart with series that draw exactly the same thing ([`Series::draws_as`]) as
    /// one: the first, named with all of their names (`EA-MADM = ea-madm-table`) and listing
    /// the others' methods in `also`.
    fn merged(&self) -> Self {
        let mut merged = Self {
            series: Vec::new(),
            ..self.clone()
        };
        for series in &self.series {
            match merged.series.iter_mut().find(|m| m.draws_as(series)) {
                Some(first) => {
                    first.name = format!("{} = {}", first.name, series.name);
                    first.also.push(series.method.clone());
                    first.on_top |= series.on_top;
                }
                None => merged.series.push(series.clone()),
            }
        }
        merged
    }

    /// Whether every series is 0 everywhere: the chart would show nothing but flat lines.
    #[must_use]
    pub fn shows_nothing(&self) -> bool {
        !self.series.is_empty() && self.series.iter().all(Series::all_zero)
    }

    /// Renders the chart (its series merged already).
    fn render_merged(&self) -> Result<String, FigureError> {
        let (drawn, stride) = self.drawn()?;
        self.render_drawn(&drawn, stride)
    }

    /// The SVG of this chart with its series' lines and bands `drawn` (bands every `stride`
    /// episodes).
    fn render_drawn(&self, drawn: &[Drawn], stride: usize) -> Result<String, FigureError> {
        let width = f64::from(self.width);
        let mut body = String::new();

        // Title and subtitle, wrapped to the canvas.
        let mut y = PAD - TITLE_FONT * 0.25;
        y = wrapped_text(
            &mut body,
            (width / 2.0, y),
            width - 2.0 * PAD,
            TITLE_FONT,
            "middle",
            "#111111",
            &self.title,
        );
        if !self.subtitle.is_empty() {
            y = wrapped_text(
                &mut body,
                (width / 2.0, y),
                width - 2.0 * PAD,
                SUBTITLE_FONT,
                "middle",
                NOTE_COLOUR,
                &self.subtitle,
            );
        }
        let longest = drawn.iter().map(|d| d.line.len()).max().unwrap_or(1);
        let x_range = (1.0, (self.x_end.unwrap_or(longest) as f64).max(2.0));

        // The draw order: the series on top (EA-MADM) last.
        let mut order: Vec<usize> = (0..self.series.len()).collect();
        order.sort_by_key(|&i| self.series[i].on_top);

        let zoom = self
            .final_zoom
            .filter(|&episodes| episodes >= 2 && longest > 2 * episodes);
        let values_in = |from: usize| {
            let lines = drawn
                .iter()
                .flat_map(move |d| d.line.iter().skip(from).copied());
            let bands = drawn.iter().flat_map(move |d| {
                d.band
                    .iter()
                    .filter(move |(e, ..)| *e >= from)
                    .flat_map(|&(_, low, high)| [low, high])
            });
            lines.chain(bands)
        };
        let seed_values = self
            .series
            .iter()
            .filter(|s| s.per_seed)
            .flat_map(|s| s.curves.iter().flatten().copied());
        let references = self.reference_lines.iter().map(|l| l.y);
        let main_y = padded_range(
            values_in(0).chain(seed_values).chain(references),
            self.metric_range,
        );
        // Room left of the plot for the widest tick label and the rotated axis label.
        let axis_room = Y_AXIS_ROOM.max(widest_tick(main_y) + 5.0 + 1.3 * AXIS_FONT + 8.0);
        let plot_left = PAD + axis_room;
        let plot_right = width - LEGEND_WIDTH - PAD;
        let main_right = if zoom.is_some() {
            plot_right - (plot_right - plot_left) * ZOOM_SHARE
        } else {
            plot_right
        };
        // The zoomed panel: its range, the room for its ticks, its title wrapped to its width.
        let zoomed_panel = zoom.map(|episodes| {
            let from = longest - episodes;
            let references = self.reference_lines.iter().map(|l| l.y);
            let y = padded_range(values_in(from).chain(references), self.metric_range);
            let left = main_right + (Y_AXIS_ROOM - 6.0).max(widest_tick(y) + 14.0);
            let title = wrap(
                &format!("last {episodes} episodes"),
                plot_right - left,
                SUBTITLE_FONT,
            );
            (from, y, left, title)
        });
        let title_lines = zoomed_panel
            .as_ref()
            .map_or(1, |(.., title)| title.len().max(1));
        let plot_top = y + 26.0 + (title_lines - 1) as f64 * SUBTITLE_FONT * 1.25;
        let main = Frame {
            left: plot_left,
            right: main_right,
            top: plot_top,
            bottom: plot_top + PLOT_HEIGHT,
            x: x_range,
            y: main_y,
        };
        let widths = line_widths(drawn, &order, main.y, 0);
        let lines = Lines {
            drawn,
            order: &order,
            widths: &widths,
        };
        let mut bars = self.draw_plot(&mut body, &main, &lines, (0, stride), true);
        y_label(&mut body, &main, &self.y_label, axis_room);
        let mut bottom = main.bottom + X_AXIS_ROOM;
        text_element(
            &mut body,
            (
                (main.left + main.right) / 2.0,
                main.bottom + TICK_FONT + 4.0 + AXIS_FONT + 8.0,
            ),
            AXIS_FONT,
            "middle",
            "#222222",
            &self.x_label,
        );
        if let Some((from, y, left, title)) = zoomed_panel {
            let zoomed = Frame {
                left,
                right: plot_right,
                x: ((from + 1) as f64, longest as f64),
                y,
                ..main
            };
            let widths = line_widths(drawn, &order, zoomed.y, from);
            let lines = Lines {
                drawn,
                order: &order,
                widths: &widths,
            };
            bars |= self.draw_plot(&mut body, &zoomed, &lines, (from, stride), false);
            let lines = title.len();
            for (index, line) in title.iter().enumerate() {
                text_element(
                    &mut body,
                    (
                        (zoomed.left + zoomed.right) / 2.0,
                        zoomed.top - 5.0 - (lines - 1 - index) as f64 * SUBTITLE_FONT * 1.25,
                    ),
                    SUBTITLE_FONT,
                    "middle",
                    NOTE_COLOUR,
                    line,
                );
            }
            text_element(
                &mut body,
                (
                    (zoomed.left + zoomed.right) / 2.0,
                    zoomed.bottom + TICK_FONT + 4.0 + AXIS_FONT + 8.0,
                ),
                AXIS_FONT,
                "middle",
                "#222222",
                &self.x_label,
            );
        }
        if let Some(title) = &self.cap_panel {
            bottom = self.draw_cap_panel(&mut body, title, &main, bottom, axis_room);
        }
        if let Some(title) = &self.seed_panel {
            bottom = self.draw_seed_panel(&mut body, title, &main, bottom, axis_room);
        }
        if self.collapse_strip {
            bottom = self.draw_collapse_strip(&mut body, &main, bottom);
        }
        let legend_bottom = self.draw_legend(&mut body, plot_right + PAD, plot_top);
        let mut caption_y = bottom.max(legend_bottom) + 4.0;
        for note in self.notes(stride, bars) {
            caption_y = wrapped_text(
                &mut body,
                (PAD, caption_y),
                width - 2.0 * PAD,
                CAPTION_FONT,
                "start",
                NOTE_COLOUR,
                &note,
            );
        }
        let height = (caption_y + PAD).ceil();
        let mut svg = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{height}\" \
             viewBox=\"0 0 {} {height}\" font-family=\"sans-serif\">\n\
             <title>{}</title>\n<rect width=\"{}\" height=\"{height}\" fill=\"white\"/>\n",
            self.width,
            self.width,
            escape(&self.title),
            self.width
        );
        svg.push_str(&body);
        svg.push_str("</svg>\n");
        Ok(svg)
    }

    /// One plot: bands, per-seed lines, reference lines, IQM lines, from episode index `from`;
    /// returns whether it drew a band as bars ([`band_as_bars`]).
    fn draw_plot(
        &self,
        svg: &mut String,
        frame: &Frame,
        lines: &Lines<'_>,
        (from, stride): (usize, usize),
        per_seed: bool,
    ) -> bool {
        let Lines {
            drawn,
            order,
            widths,
        } = *lines;
        frame.open(svg, "plot", self.metric_range);
        let mut bars = false;
        for &i in order {
            let (series, d) = (&self.series[i], &drawn[i]);
            let band: Vec<&(usize, f64, f64)> =
                d.band.iter().filter(|(e, ..)| *e >= from).collect();
            if band_as_bars(stride, band.len()) {
                bars = true;
                for &&(e, low, high) in &band {
                    let bar = frame.points([(episode(e), low), (episode(e), high)].into_iter());
                    translucent_stroke(
                        svg,
                        "band",
                        series,
                        (BAND_BAR_WIDTH, BAND_BAR_OPACITY),
                        &bar,
                    );
                }
                continue;
            }
            if band.len() < 2 {
                continue;
            }
            let outline = band
                .iter()
                .map(|&&(e, _, high)| (episode(e), high))
                .chain(band.iter().rev().map(|&&(e, low, _)| (episode(e), low)));
            let _ = writeln!(
                svg,
                "<polygon class=\"band\" data-method=\"{}\" fill=\"{}\" fill-opacity=\"{BAND_OPACITY}\" points=\"{}\"/>",
                escape(&series.method),
                series.style.colour,
                frame.points(outline)
            );
        }
        if per_seed {
            for &i in order {
                let series = &self.series[i];
                if !series.per_seed {
                    continue;
                }
                for curve in &series.curves {
                    let line = frame.points(
                        curve
                            .iter()
                            .enumerate()
                            .skip(from)
                            .map(|(e, &v)| (episode(e), v)),
                    );
                    translucent_stroke(svg, "seed", series, (SEED_WIDTH, SEED_OPACITY), &line);
                }
            }
        }
        for line in &self.reference_lines {
            let _ = writeln!(
                svg,
                "<polyline class=\"reference\" fill=\"none\" stroke=\"{REFERENCE_COLOUR}\" \
                 stroke-width=\"1.5\" stroke-dasharray=\"6 4\" points=\"{}\"/>",
                frame.points([(frame.x.0, line.y), (frame.x.1, line.y)].into_iter())
            );
        }
        for &i in order {
            let (series, d) = (&self.series[i], &drawn[i]);
            let _ = writeln!(
                svg,
                "<polyline class=\"line\" data-method=\"{}\"{} fill=\"none\" {} stroke-width=\"{}\" \
                 points=\"{}\"/>",
                escape(&series.method),
                also_attribute(series),
                stroke_attributes(&series.style),
                px(widths[i]),
                frame.points(
                    d.line
                        .iter()
                        .enumerate()
                        .skip(from)
                        .map(|(e, &v)| (episode(e), v))
                )
            );
        }
        svg.push_str("</g>\n");
        bars
    }

    /// The panel of seeds at the step cap per episode under `main`; returns its bottom.
    fn draw_cap_panel(
        &self,
        svg: &mut String,
        title: &str,
        main: &Frame,
        top: f64,
        room: f64,
    ) -> f64 {
        let capped: Vec<&Series> = self
            .series
            .iter()
            .filter(|s| s.at_cap.iter().any(|&n| n > 0))
            .collect();
        let label_y = top + SUBTITLE_FONT + 2.0;
        if capped.is_empty() {
            text_element(
                svg,
                (main.left, label_y),
                SUBTITLE_FONT,
                "start",
                NOTE_COLOUR,
                &format!("{title}: none in any episode"),
            );
            return label_y + 8.0;
        }
        let most = self.series.iter().map(Series::seeds).max().unwrap_or(1);
        text_element(
            svg,
            (main.left, label_y),
            SUBTITLE_FONT,
            "start",
            NOTE_COLOUR,
            &format!("{title} (methods with any; of {most} seeds)"),
        );
        let frame = Frame {
            top: label_y + 8.0,
            bottom: label_y + 8.0 + CAP_PANEL_HEIGHT,
            y: (0.0, most as f64),
            ..*main
        };
        frame.open(svg, "plot cap", (Some(0.0), Some(most as f64)));
        let mut order: Vec<&&Series> = capped.iter().collect();
        order.sort_by_key(|s| s.on_top);
        for series in order {
            let points = series
                .at_cap
                .iter()
                .enumerate()
                .map(|(e, &n)| (episode(e), f64::from(n)));
            let _ = writeln!(
                svg,
                "<polyline class=\"line\" data-method=\"{}\" fill=\"none\" {} stroke-width=\"1.5\" \
                 points=\"{}\"/>",
                escape(&series.method),
                stroke_attributes(&series.style),
                frame.points(points)
            );
        }
        svg.push_str("</g>\n");
        seeds_axis_label(svg, &frame, room)
    }

    /// The panel under `main` of the seeds each line is the IQM of, per episode: a step line
    /// per series ([`Series::seeds_per_x`]), so a jump of a line where seeds drop out is seen
    /// with its cause; returns its bottom.
    fn draw_seed_panel(
        &self,
        svg: &mut String,
        title: &str,
        main: &Frame,
        top: f64,
        room: f64,
    ) -> f64 {
        let most = self
            .series
            .iter()
            .map(Series::seeds)
            .max()
            .unwrap_or(1)
            .max(1);
        let label_y = top + SUBTITLE_FONT + 2.0;
        text_element(
            svg,
            (main.left, label_y),
            SUBTITLE_FONT,
            "start",
            NOTE_COLOUR,
            title,
        );
        let frame = Frame {
            top: label_y + 8.0,
            bottom: label_y + 8.0 + CAP_PANEL_HEIGHT,
            y: (0.0, most as f64),
            ..*main
        };
        frame.open(svg, "plot seeds", (Some(0.0), Some(most as f64)));
        let mut order: Vec<&Series> = self.series.iter().collect();
        order.sort_by_key(|s| s.on_top);
        for series in order {
            let counts = series.seeds_per_x();
            // A step line: the count holds until the episode where it falls.
            let mut points = Vec::with_capacity(2 * counts.len());
            for (x, &n) in counts.iter().enumerate() {
                if let Some(&before) = x.checked_sub(1).and_then(|p| counts.get(p))
                    && before != n
                {
                    points.push((episode(x), before as f64));
                }
                points.push((episode(x), n as f64));
            }
            let _ = writeln!(
                svg,
                "<polyline class=\"line\" data-method=\"{}\" data-seeds=\"{}\" fill=\"none\" {} \
                 stroke-width=\"1.5\" points=\"{}\"/>",
                escape(&series.method),
                counts
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(" "),
                stroke_attributes(&series.style),
                frame.points(points.into_iter())
            );
        }
        svg.push_str("</g>\n");
        seeds_axis_label(svg, &frame, room)
    }

    /// The strip under `main` of the seeds that collapsed: a row per series with a seed's
    /// mark at the episode it never reached the target again from, and the count; one line
    /// when no seed of any series collapsed. Returns its bottom.
    fn draw_collapse_strip(&self, svg: &mut String, main: &Frame, top: f64) -> f64 {
        let label_y = top + SUBTITLE_FONT + 2.0;
        let rows: Vec<(&Series, Vec<u64>, usize)> = self
            .series
            .iter()
            .map(|s| {
                let (episodes, seeds) = s.collapses();
                (s, episodes, seeds)
            })
            .collect();
        if rows.iter().all(|(_, episodes, _)| episodes.is_empty()) {
            text_element(
                svg,
                (main.left, label_y),
                SUBTITLE_FONT,
                "start",
                NOTE_COLOUR,
                "collapsed seeds (reached the target, then never again): none",
            );
            return label_y + 8.0;
        }
        text_element(
            svg,
            (main.left, label_y),
            SUBTITLE_FONT,
            "start",
            NOTE_COLOUR,
            "collapsed seeds: a mark at the episode each never reached the target again from",
        );
        let row_height = 14.0;
        let frame = Frame {
            top: label_y + 8.0,
            bottom: label_y + 8.0 + row_height * rows.len() as f64,
            y: (0.0, rows.len() as f64),
            ..*main
        };
        let _ = writeln!(
            svg,
            "<g class=\"collapses\" data-left=\"{}\" data-right=\"{}\" data-x0=\"{}\" \
             data-x1=\"{}\">",
            frame.left, frame.right, frame.x.0, frame.x.1
        );
        for (row, (series, episodes, seeds)) in rows.iter().enumerate() {
            let middle = frame.top + row_height * (row as f64 + 0.5);
            // The row in the series' colour and dash, so the legend names it.
            let _ = writeln!(
                svg,
                "<line class=\"strip\" data-method=\"{}\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" \
                 {} stroke-width=\"1\" stroke-opacity=\"0.6\"/>",
                escape(&series.method),
                px(frame.left),
                px(middle),
                px(frame.right),
                px(middle),
                stroke_attributes(&series.style)
            );
            for &episode in episodes {
                let (x, _) = frame.at(episode as f64 + 1.0, 0.0);
                let _ = writeln!(
                    svg,
                    "<circle class=\"collapse\" data-method=\"{}\" data-episode=\"{episode}\" \
                     cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"{}\"/>",
                    escape(&series.method),
                    px(x.clamp(frame.left, frame.right)),
                    px(middle),
                    series.style.colour
                );
            }
            text_element(
                svg,
                (frame.left - 5.0, middle + TICK_FONT * 0.35),
                TICK_FONT,
                "end",
                "#333333",
                &format!("{}/{seeds}", episodes.len()),
            );
        }
        svg.push_str("</g>\n");
        frame.bottom + 8.0
    }

    /// The legend in its own column at `x`, from `top`; returns its bottom.
    fn draw_legend(&self, svg: &mut String, x: f64, top: f64) -> f64 {
        let text_x = x + LEGEND_SAMPLE + 8.0;
        let text_width = f64::from(self.width) - PAD - text_x;
        let mut y = top;
        svg.push_str("<g class=\"legend\">\n");
        for series in &self.series {
            let lines = wrap(&series.name, text_width, LEGEND_FONT);
            let middle = y + LEGEND_FONT * 0.8;
            let _ = writeln!(
                svg,
                "<rect x=\"{}\" y=\"{}\" width=\"{LEGEND_SAMPLE}\" height=\"12\" fill=\"{}\" fill-opacity=\"{BAND_OPACITY}\"/>",
                px(x),
                px(middle - 6.0),
                series.style.colour
            );
            let _ = writeln!(
                svg,
                "<line class=\"sample\" data-method=\"{}\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {} stroke-width=\"2.4\"/>",
                escape(&series.method),
                px(x),
                px(middle),
                px(x + LEGEND_SAMPLE),
                px(middle),
                stroke_attributes(&series.style)
            );
            y += legend_label(svg, text_x, middle, &lines);
        }
        for line in &self.reference_lines {
            let middle = y + LEGEND_FONT * 0.8;
            let _ = writeln!(
                svg,
                "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{REFERENCE_COLOUR}\" stroke-width=\"1.5\" stroke-dasharray=\"6 4\"/>",
                px(x),
                px(middle),
                px(x + LEGEND_SAMPLE),
                px(middle)
            );
            let lines = wrap(&line.label, text_width, LEGEND_FONT);
            y += legend_label(svg, text_x, middle, &lines);
        }
        svg.push_str("</g>\n");
        y
    }
}

fn episode(i: usize) -> f64 {
    (i + 1) as f64
}

/// Closes a strip panel: its rotated "seeds" label left of `frame`, `room` from the axis; returns
/// where the next panel starts (the one place both strips draw it, so they stay alike).
fn seeds_axis_label(svg: &mut String, frame: &Frame, room: f64) -> f64 {
    let y = (frame.top + frame.bottom) / 2.0;
    let x = frame.left - room + AXIS_FONT;
    let _ = writeln!(
        svg,
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"middle\" fill=\"#222222\" \
         transform=\"rotate(-90 {} {})\">seeds</text>",
        px(x),
        px(y),
        px(AXIS_FONT),
        px(x),
        px(y)
    );
    frame.bottom + TICK_FONT + 10.0
}

#[cfg(test)]
mod tests {
    use crate::theme::method_style;
    use eamadm_eval::Role;

    use super::*;

    /// A series of `runs[seed][episode]`, pushed seed by seed.
    fn series(method: &str, window: usize, runs: &[Vec<f64>]) -> Series {
        let mut series = Series::new(
            method,
            eamadm_eval::paper_claims::method_title(method),
            method_style(method, Role::Paper),
            window,
        );
        for curve in runs {
            series.push(curve);
        }
        // EA-MADM is the series on top, as the figures draw it.
        series.on_top = method == "ea-madm";
        series
    }

    /// A chart of two methods of four episodes, smoothed over `window` episodes.
    fn tiny_chart(window: usize) -> LineChart {
        LineChart::new("Task I: steps per episode", "episode", "steps per episode")
            .with_smoothing(window)
            .with_metric_range(Some(0.0), Some(2000.0))
            .with_series(series(
                "ea-madm",
                window,
                &[
                    vec![300.0, 120.0, 70.0, 61.0],
                    vec![280.0, 140.0, 66.0, 60.0],
                    vec![2000.0, 2000.0, 2000.0, 2000.0],
                ],
            ))
            .with_series(series(
                "epsilon-greedy",
                window,
                &[vec![400.0, 260.0, 150.0], vec![380.0, 300.0, 170.0, 120.0]],
            ))
            .with_reference_line("BFS optimum = 58", 58.0)
    }

    #[test]
    fn svg_names_every_series_and_draws_bands_lines_and_reference() {
        let svg = tiny_chart(1).render_svg().unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        for text in [
            "Task I: steps per episode",
            "EA-MADM",
            "ε-greedy",
            "BFS optimum = 58",
            "episode",
            "steps per episode",
            "interquartile mean (IQM)",
        ] {
            assert!(svg.contains(text), "missing {text:?}");
        }
        assert_eq!(svg.matches("class=\"band\"").count(), 2, "{svg}");
        assert!(svg.contains(
            "class=\"line\" data-method=\"ea-madm\" fill=\"none\" stroke=\"#0072B2\" stroke-width=\"2\""
        ));
        // EA-MADM is drawn last although it is listed first.
        let ea = svg.find("class=\"line\" data-method=\"ea-madm\"").unwrap();
        let eg = svg
            .find("class=\"line\" data-method=\"epsilon-greedy\"")
            .unwrap();
        assert!(eg < ea);
        assert!(!svg.contains("moving average"));
    }

    #[test]
    fn the_line_is_the_iqm_and_the_band_stays_within_the_seeds() {
        let chart = tiny_chart(1);
        let (drawn, stride) = chart.drawn().unwrap();
        assert_eq!(stride, 1);
        // Episode 1 of EA-MADM: seeds 300, 280, 2000; IQM of 3 values is their mean.
        assert!((drawn[0].line[0] - 860.0).abs() < 1e-9);
        for (d, s) in drawn.iter().zip(&chart.series) {
            for &(e, low, high) in &d.band {
                let values: Vec<f64> = s.curves.iter().filter_map(|c| c.get(e).copied()).collect();
                let min = values.iter().copied().fold(f64::INFINITY, f64::min);
                let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                assert!(min <= low && low <= d.line[e] && d.line[e] <= high && high <= max);
            }
        }
    }

    #[test]
    fn the_band_costs_a_bounded_number_of_draws_beyond_fifty_seeds() {
        // Up to BAND_FULL_SEEDS seeds (the default run's 20 among them) nothing changes.
        for seeds in [1, 20, BAND_FULL_SEEDS] {
            assert_eq!(band_stride(100, Some(seeds)), 1);
            assert_eq!(band_stride(500, Some(seeds)), 5);
        }
        // Beyond, the points times the seeds stay within MAX_BAND_POINTS × BAND_FULL_SEEDS
        // until the floor of MIN_BAND_POINTS is reached.
        for seeds in [51, 100, 200, 333, 500, 1000, 5000] {
            for longest in [100, 500, 1000] {
                let stride = band_stride(longest, Some(seeds));
                let points = longest.div_ceil(stride);
                assert!(
                    points * seeds <= MAX_BAND_POINTS * BAND_FULL_SEEDS
                        || points <= MIN_BAND_POINTS,
                    "{seeds} seeds, {longest} episodes: {points} points"
                );
                assert!(points >= MIN_BAND_POINTS.min(longest));
            }
        }
        assert_eq!(band_stride(100, Some(1000)), 20);
        let curve: Vec<f64> = (0..100).map(|i| f64::from(i % 7)).collect();
        let chart = LineChart::new("many", "episode", "steps").with_series(series(
            "softmax",
            1,
            &vec![curve; 1000],
        ));
        let (drawn, stride) = chart.drawn().unwrap();
        assert_eq!(stride, 20);
        // Episodes 1, 21, 41, 61, 81 and the last.
        assert_eq!(drawn[0].band.len(), 6);
        assert!(
            chart
                .render_svg()
                .unwrap()
                .contains("computed every 20 episodes")
        );
    }

    #[test]
    fn a_zoomed_panel_with_few_band_points_draws_bars_and_says_so() {
        let band_elements = |svg: &str, zoomed: bool| {
            let plots: Vec<&str> = svg.split("class=\"plot").skip(1).collect();
            let plot = if zoomed { plots[1] } else { plots[0] };
            let plot = &plot[..plot.find("</g>").unwrap()];
            (
                plot.matches("<polygon class=\"band\"").count(),
                plot.matches("<polyline class=\"band\"").count(),
            )
        };
        let curve: Vec<f64> = (0..100).map(|i| f64::from(i % 7 + i / 10)).collect();
        // 1000 seeds: the band every 20 episodes, so the last 30 hold episodes 81 and 100 only.
        let many = LineChart::new("many", "episode", "steps")
            .with_series(series("softmax", 1, &vec![curve.clone(); 1000]))
            .with_final_zoom(30);
        let svg = many.render_svg().unwrap();
        assert_eq!(band_elements(&svg, false), (1, 0), "the whole run: an area");
        assert_eq!(
            band_elements(&svg, true),
            (0, 2),
            "the zoom: a bar per point"
        );
        // The caption's words, across the lines it wraps to.
        let words = |svg: &str| {
            let text: Vec<&str> = svg
                .split('>')
                .filter_map(|part| part.split('<').next())
                .collect();
            text.join(" ")
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ")
        };
        assert!(
            words(&svg).contains("each is a bar at its episode"),
            "{svg}"
        );
        assert!(crate::checks::check_figures(&[("many.svg".to_owned(), svg)]).is_empty());
        // Twenty seeds: the band at every episode, an area in both panels, nothing said.
        let few = LineChart::new("few", "episode", "steps")
            .with_series(series("softmax", 1, &vec![curve; 20]))
            .with_final_zoom(30);
        let svg = few.render_svg().unwrap();
        assert_eq!(band_elements(&svg, true), (1, 0));
        assert!(!words(&svg).contains("bar at its episode"));
        assert!(!band_as_bars(1, 2) && !band_as_bars(20, 0) && !band_as_bars(20, MIN_BAND_POINTS));
        assert!(band_as_bars(20, 1) && band_as_bars(20, MIN_BAND_POINTS - 1));
    }

    #[test]
    fn long_curves_get_bands_at_most_every_hundredth_and_say_so() {
        let curve: Vec<f64> = (0..250).map(|i| f64::from(i % 7)).collect();
        let chart = LineChart::new("long", "episode", "steps").with_series(series(
            "softmax",
            1,
            &[curve.clone(), curve],
        ));
        let (drawn, stride) = chart.drawn().unwrap();
        assert_eq!(stride, 3);
        assert_eq!(drawn[0].band.len(), 84);
        assert!(
            chart
                .render_svg()
                .unwrap()
                .contains("computed every 3 episodes")
        );
    }

    #[test]
    fn same_input_gives_the_same_bytes() {
        let a = tiny_chart(2).render_svg().unwrap();
        let b = tiny_chart(2).render_svg().unwrap();
        assert_eq!(a, b);
        assert!(a.contains("2-episode trailing moving average"));
        assert_ne!(a, tiny_chart(1).render_svg().unwrap());
    }

    #[test]
    fn long_titles_wrap_inside_the_canvas() {
        let title = "Task II: EA-MADM and its ablations, steps per episode ".repeat(4);
        let svg = tiny_chart(1)
            .with_subtitle(title.clone())
            .render_svg()
            .unwrap();
        for line in svg.lines().filter(|l| l.starts_with("<text")) {
            let x: f64 = attribute(line, "x");
            let font: f64 = attribute(line, "font-size");
            let content = line.split('>').nth(1).unwrap().split('<').next().unwrap();
            let w = text_width(content, font);
            if line.contains("rotate") {
                continue;
            }
            let (start, end) = if line.contains("\"middle\"") {
                (x - w / 2.0, x + w / 2.0)
            } else if line.contains("\"end\"") {
                (x - w, x)
            } else {
                (x, x + w)
            };
            assert!(start >= 0.0 && end <= 960.0, "{line}");
        }
    }

    fn attribute(line: &str, name: &str) -> f64 {
        let key = format!(" {name}=\"");
        let start = line.find(&key).unwrap() + key.len();
        line[start..].split('"').next().unwrap().parse().unwrap()
    }

    /// The C4 charts' x axis ends at the given episode whatever the curves' lengths, and the
    /// seed panel's step line is the per-x count of the curves that have a value there: read
    /// back from its pixels, it falls exactly where a seed's curve ends.
    #[test]
    fn the_x_axis_ends_where_asked_and_the_seed_panel_counts_the_curves() {
        let curve = |len: usize| -> Vec<f64> { (0..len).map(|i| i as f64).collect() };
        let series = series("softmax", 1, &[curve(100), curve(60), curve(30)]);
        let counts: Vec<usize> = (0..100)
            .map(|x| [100, 60, 30].iter().filter(|&&l| l > x).count())
            .collect();
        assert_eq!(series.seeds_per_x(), counts);
        let svg = LineChart::new("C4", "reaching episode", "value")
            .with_series(series)
            .with_x_end(100)
            .with_seed_panel("seeds behind each point")
            .render_svg()
            .unwrap();
        let document = roxmltree::Document::parse(&svg).unwrap();
        let plots: Vec<roxmltree::Node<'_, '_>> = document
            .descendants()
            .filter(|n| n.attribute("class").is_some_and(|c| c.starts_with("plot")))
            .collect();
        assert_eq!(plots.len(), 2);
        for plot in &plots {
            assert_eq!(plot.attribute("data-x0"), Some("1"));
            assert_eq!(plot.attribute("data-x1"), Some("100"));
        }
        let panel = plots[1];
        assert_eq!(panel.attribute("class"), Some("plot seeds"));
        let value = |name: &str| -> f64 { panel.attribute(name).unwrap().parse().unwrap() };
        let line = panel
            .descendants()
            .find(|n| n.attribute("class") == Some("line"))
            .unwrap();
        let listed: Vec<usize> = line
            .attribute("data-seeds")
            .unwrap()
            .split(' ')
            .map(|n| n.parse().unwrap())
            .collect();
        assert_eq!(listed, counts);
        // Pixels back to data: (episode, seeds) at each corner of the step line.
        let points: Vec<(i64, i64)> = line
            .attribute("points")
            .unwrap()
            .split(' ')
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
                let fx = (x - value("data-left")) / (value("data-right") - value("data-left"));
                let fy = (value("data-bottom") - y) / (value("data-bottom") - value("data-top"));
                let data_x = value("data-x0") + fx * (value("data-x1") - value("data-x0"));
                let data_y = value("data-y0") + fy * (value("data-y1") - value("data-y0"));
                (data_x.round() as i64, data_y.round() as i64)
            })
            .collect();
        assert_eq!(
            points,
            [(1, 3), (31, 3), (31, 2), (61, 2), (61, 1), (100, 1)]
        );
    }

    #[test]
    fn cap_panel_and_zoom_are_drawn_when_asked() {
        let mut ea = series("ea-madm", 1, &[vec![2000.0; 30], vec![100.0; 30]]);
        ea.count_at_cap(&[true; 30]);
        ea.count_at_cap(&[false; 30]);
        let svg = LineChart::new("t", "episode", "steps")
            .with_series(ea)
            .with_cap_panel("seeds at the step cap")
            .with_final_zoom(10)
            .render_svg()
            .unwrap();
        assert!(svg.contains("class=\"plot cap\""));
        // The zoomed panel's title wraps to its width.
        assert!(
            svg.contains(">last 10</text>") && svg.contains(">episodes</text>"),
            "{svg}"
        );
        assert_eq!(svg.matches("<g class=\"plot").count(), 3);
    }

    #[test]
    fn bad_input_is_named() {
        let error = LineChart::new("t", "x", "y").render_svg().unwrap_err();
        assert!(matches!(error, FigureError::NoSeries { .. }));

        let error = LineChart::new("t", "x", "y")
            .with_series(series("softmax", 1, &[vec![1.0, f64::NAN]]))
            .render_svg()
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            "series \"softmax\": seed 0, episode 1: value NaN is not finite"
        );

        let error = LineChart::new("t", "x", "y")
            .with_series(series("softmax", 1, &[]))
            .render_svg()
            .unwrap_err();
        assert!(error.to_string().contains("no seeds"), "{error}");

        let error = tiny_chart(1)
            .with_reference_line("optimum", f64::INFINITY)
            .render_svg()
            .unwrap_err();
        assert!(matches!(error, FigureError::NonFiniteReference { .. }));

        let error = tiny_chart(0).render_svg().unwrap_err();
        assert!(matches!(error, FigureError::ZeroSmoothingWindow));

        let error = tiny_chart(1)
            .with_series(series("smoothed", 5, &[vec![1.0, 2.0]]))
            .render_svg()
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            "series \"smoothed\" is smoothed over 5 episodes but its chart over 1; make the \
             series with the chart's window"
        );

        // The first bad curve is the one named, whatever comes after it.
        let error = LineChart::new("t", "x", "y")
            .with_smoothing(3)
            .with_series(series(
                "softmax",
                3,
                &[vec![1.0], vec![2.0, f64::INFINITY], vec![], vec![f64::NAN]],
            ))
            .render_svg()
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            "series \"softmax\": seed 1, episode 1: value inf is not finite"
        );

        let error = tiny_chart(1).with_width(100).render_svg().unwrap_err();
        assert!(matches!(error, FigureError::TooSmall { width: 100 }));
    }

    #[test]
    fn wrap_breaks_at_spaces() {
        assert_eq!(
            wrap("EA-MADM without trees (table)", 120.0, 13.0),
            vec!["EA-MADM", "without trees", "(table)"]
        );
        assert_eq!(wrap("a  b", 100.0, 13.0), vec!["a b"]);
        assert!(wrap("", 100.0, 13.0).is_empty());
    }

    #[test]
    fn points_leave_out_only_points_strictly_inside_a_horizontal_run() {
        let frame = Frame {
            left: 0.0,
            right: 100.0,
            top: 0.0,
            bottom: 100.0,
            x: (0.0, 100.0),
            y: (0.0, 100.0),
        };
        let run = [
            (0.0, 50.0),
            (10.0, 50.0),
            (20.0, 50.0),
            (30.0, 60.0),
            (40.0, 60.0),
        ];
        assert_eq!(frame.points(run.into_iter()), "0,50 20,50 30,40 40,40");
        // A turn (a band's outline going back) keeps its end point, as does a lone point.
        let turn = [(0.0, 50.0), (10.0, 50.0), (0.0, 50.0)];
        assert_eq!(frame.points(turn.into_iter()), "0,50 10,50 0,50");
        assert_eq!(frame.points([(5.0, 5.0)].into_iter()), "5,95");
    }

    #[test]
    fn a_word_too_wide_breaks_after_its_hyphens_then_between_characters() {
        let label = "epsilon-decreasing-shaped-repaired";
        let width = text_width("epsilon-decreasing-", 13.0);
        let lines = wrap(label, width, 13.0);
        assert_eq!(lines, vec!["epsilon-decreasing-", "shaped-repaired"]);
        for width in [3.0, 20.0, 60.0, 140.0] {
            let lines = wrap(label, width, 13.0);
            assert_eq!(lines.concat(), label, "nothing is lost or added");
            for line in &lines {
                assert!(
                    line.chars().count() == 1 || text_width(line, 13.0) <= width,
                    "{line:?} wider than {width}"
                );
            }
        }
    }

    #[test]
    fn ticks_are_round() {
        assert_eq!(tick_step(1300.0, 5.0), 500.0);
        assert_eq!(tick_step(10.0, 5.0), 2.0);
        assert_eq!(tick_step(0.05, 5.0), 0.01);
        assert_eq!(tick_decimals(0.01), 2);
        assert_eq!(tick_decimals(500.0), 0);
    }

    /// Series that draw the same are one line named by all of them; a line under another is
    /// drawn wider; a share of 0/1 outcomes is the pooled share with its Wilson band; the
    /// collapse strip marks each collapsed seed.
    #[test]
    fn identical_series_are_one_line_and_hidden_lines_stay_visible() {
        let curves = [vec![10.0; 30], vec![12.0; 30]];
        let mut ea = series("ea-madm", 1, &curves);
        let mut table = series("ea-madm-table", 1, &curves);
        ea.note_collapse(Some(20));
        ea.note_collapse(None);
        table.note_collapse(Some(20));
        table.note_collapse(None);
        let other = series("softmax", 1, &[vec![10.5; 30], vec![11.5; 30]]);
        let svg = LineChart::new("t", "episode", "steps")
            .with_series(ea)
            .with_series(other)
            .with_series(table)
            .with_collapse_strip()
            .render_svg()
            .unwrap();
        // The legend names both (wrapped to its column).
        assert!(
            svg.contains(">EA-MADM =</text>") && svg.contains(">ea-madm-table</text>"),
            "{svg}"
        );
        assert!(svg.contains("data-method=\"ea-madm\" data-also=\"ea-madm-table\""));
        assert!(!svg.contains("class=\"line\" data-method=\"ea-madm-table\""));
        // softmax runs along EA-MADM's line, under it: wider.
        assert!(svg.contains(
            "class=\"line\" data-method=\"softmax\" fill=\"none\" stroke=\"#CC79A7\" stroke-width=\"4\""
        ));
        assert_eq!(svg.matches("class=\"collapse\"").count(), 1, "{svg}");
        assert!(svg.contains(">1/2<"), "{svg}");

        // Success of 4 seeds: 1 reaches in every episode, 3 never: the IQM would be 0.
        let mut success = series(
            "softmax",
            1,
            &[vec![1.0; 5], vec![0.0; 5], vec![0.0; 5], vec![0.0; 5]],
        );
        success.share = true;
        assert_eq!(success.final_share(), Some((0.25, 1, 4)));
        let chart = LineChart::new("s", "episode", "share").with_series(success.clone());
        let (drawn, _) = chart.drawn().unwrap();
        assert_eq!(drawn[0].line, vec![0.25; 5]);
        let wilson = eamadm_eval::stats::wilson(1, 4, 0.95).unwrap();
        assert_eq!(drawn[0].band[0], (0, wilson.low, wilson.high));
        assert!(chart.render_svg().unwrap().contains("pooled over 4 seeds"));
        // All zero: the chart shows nothing.
        let zero = series("softmax", 1, &[vec![0.0; 5]]);
        assert!(
            LineChart::new("z", "episode", "share")
                .with_series(zero)
                .shows_nothing()
        );
        assert!(
            !LineChart::new("s", "episode", "share")
                .with_series(success)
                .shows_nothing()
        );
    }

    #[test]
    fn a_share_series_outside_zero_to_one_is_refused_not_wrapped() {
        for bad in [2.0, -0.5, 1e300] {
            let mut success = series("softmax", 1, &[vec![1.0; 5], vec![0.0, 0.0, bad, 0.0, 0.0]]);
            success.share = true;
            assert_eq!(success.final_share(), None, "{bad}");
            let chart = LineChart::new("s", "episode", "share").with_series(success);
            match chart.render_svg() {
                Err(FigureError::ShareOutOfRange {
                    series, episode, ..
                }) => assert_eq!((series.as_str(), episode), ("softmax", 3)),
                other => panic!("{bad}: {other:?}"),
            }
            let error = chart.drawn().unwrap_err().to_string();
            assert!(
                error.contains("episode 3") && error.contains("0/1"),
                "{error}"
            );
            // Together with a good chart, the error is the one it gives alone.
            let good = LineChart::new("g", "episode", "steps").with_series(series(
                "softmax",
                1,
                &[vec![3.0; 5]],
            ));
            let together = LineChart::render_svgs(&[&good, &chart]).unwrap_err();
            assert_eq!(together.to_string(), error);
        }
    }

    /// The text `px` wrote before coordinates were held as tenths: `{:.0}` of the value
    /// rounded to a tenth when that is whole, else `{:.1}`.
    fn px_by_format(value: f64) -> String {
        let rounded = (value * 10.0).round() / 10.0;
        if rounded == rounded.trunc() {
            format!("{rounded:.0}")
        } else {
            format!("{rounded:.1}")
        }
    }

    #[test]
    fn px_prints_the_edges_as_formatting_does() {
        for value in [
            0.0,
            -0.0,
            -0.04,
            0.05,
            -0.05,
            0.25,
            -0.3,
            -1.0,
            1.05,
            99.95,
            1e11,
            -1e11,
            1e12,
            123_456_789_012.34,
            1e300,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ] {
            assert_eq!(px(value), px_by_format(value), "{value:e}");
        }
    }

    proptest::proptest! {
        /// The law of `Px`: the same text as formatting the float, for every bit pattern and
        /// for the canvas's range.
        #[test]
        fn px_equals_formatting_the_float(bits in proptest::num::u64::ANY, canvas in -2e3..2e3_f64) {
            let value = f64::from_bits(bits);
            proptest::prop_assert_eq!(px(value), px_by_format(value));
            proptest::prop_assert_eq!(px(canvas), px_by_format(canvas));
            // Equal text exactly when equal held values: `points` compares them.
            proptest::prop_assert_eq!(
                Px::of(value) == Px::of(canvas),
                px(value) == px(canvas)
            );
        }
    }

    proptest::proptest! {
        /// A share series draws what the evaluation's `summary::success_band` computes of the
        /// same 0/1 outcomes (seeds of equal length, as a figure's runs are): per episode the
        /// share pooled over the seeds and the smoothing window, and its Wilson band.
        #[test]
        fn a_share_series_draws_the_success_band(
            outcomes in proptest::collection::vec(
                proptest::collection::vec(proptest::bool::ANY, 12), 1..6),
            window in 1_usize..6,
        ) {
            let curves: Vec<Vec<f64>> = outcomes
                .iter()
                .map(|seed| seed.iter().map(|&r| f64::from(u8::from(r))).collect())
                .collect();
            let mut success = series("softmax", window, &curves);
            success.share = true;
            let (drawn, _) = LineChart::new("s", "episode", "share")
                .with_smoothing(window)
                .with_series(success)
                .drawn()
                .unwrap();
            let band = eamadm_eval::summary::success_band(&outcomes, window).unwrap();
            for (episode, point) in band.iter().enumerate() {
                proptest::prop_assert!((drawn[0].line[episode] - point.wilson.estimate).abs() < 1e-12);
                let (at, low, high) = drawn[0].band[episode];
                proptest::prop_assert_eq!(at, episode);
                proptest::prop_assert!((low - point.wilson.low).abs() < 1e-12);
                proptest::prop_assert!((high - point.wilson.high).abs() < 1e-12);
            }
        }
    }

    /// A chart of `runs` per series (seeds × episodes), the series named after methods, one of
    /// them a share series when `share`, smoothed over `window` (`series_window` for the last
    /// series, so that a mismatch can be made).
    fn chart_of(
        runs: &[Vec<Vec<f64>>],
        window: usize,
        series_window: usize,
        share: bool,
    ) -> LineChart {
        let methods = ["ea-madm", "epsilon-greedy", "softmax", "epsilon-decreasing"];
        let mut chart = LineChart::new("c", "episode", "y").with_smoothing(window);
        for (index, (seeds, method)) in runs.iter().zip(methods).enumerate() {
            let last = index + 1 == runs.len();
            let shares = share && index == 1;
            // A share series holds 0/1 outcomes.
            let seeds: Vec<Vec<f64>> = seeds
                .iter()
                .map(|curve| {
                    curve
                        .iter()
                        .map(|&v| {
                            if shares {
                                f64::from(u8::from(v >= 2.0))
                            } else {
                                v
                            }
                        })
                        .collect()
                })
                .collect();
            let mut series = series(method, if last { series_window } else { window }, &seeds);
            series.share = shares;
            chart = chart.with_series(series);
        }
        chart
    }

    proptest::proptest! {
        /// The law of `render_svgs`: each chart's SVG (or the first error) exactly as
        /// `render_svg` gives it, whether the series share sizes (and so resamples), differ in
        /// seeds and lengths, are share series, are equal (merged), or fail.
        #[test]
        fn rendering_charts_together_equals_rendering_each(
            charts in proptest::collection::vec(
                (
                    proptest::collection::vec(
                        proptest::collection::vec(
                            proptest::collection::vec(
                                proptest::prop_oneof![
                                    8 => proptest::strategy::Strategy::prop_map(0_u8..4, f64::from),
                                    2 => -50.0..300.0_f64,
                                    1 => proptest::strategy::Just(f64::MAX),
                                ],
                                1..7,
                            ),
                            1..5,
                        ),
                        0..4,
                    ),
                    1_usize..3,
                    proptest::bool::ANY,
                    proptest::bool::weighted(0.1),
                    proptest::bool::ANY,
                ),
                1..4,
            ),
        ) {
            let charts: Vec<LineChart> = charts
                .iter()
                .map(|(runs, window, share, mismatch, duplicate)| {
                    let mut runs = runs.clone();
                    // Two series of the same curves draw as one (merged).
                    if *duplicate && let Some(first) = runs.first().cloned() {
                        runs.push(first);
                    }
                    chart_of(&runs, *window, window + usize::from(*mismatch), *share)
                })
                .collect();
            let each: Result<Vec<String>, FigureError> =
                charts.iter().map(LineChart::render_svg).collect();
            let references: Vec<&LineChart> = charts.iter().collect();
            let together = LineChart::render_svgs(&references);
            proptest::prop_assert_eq!(
                together.as_ref().map_err(ToString::to_string),
                each.as_ref().map_err(ToString::to_string)
            );
        }
    }

    #[test]
    fn values_near_the_largest_float_get_a_few_ticks() {
        // Once an endless axis: the range overflowed, the step fell back to 1.
        let chart = chart_of(&[vec![vec![f64::MAX, 1.0], vec![2.0, 3.0]]], 1, 1, false);
        let svg = chart.render_svg().unwrap();
        assert!(svg.len() < 200_000, "{} bytes", svg.len());
        let ticks = y_ticks((-f64::MAX, f64::MAX));
        assert!((2..=MAX_Y_TICKS).contains(&ticks.len()), "{}", ticks.len());
        assert!(ticks.windows(2).all(|pair| pair[0].0 < pair[1].0));
    }

    #[test]
    fn charts_rendered_together_share_the_band_of_an_episode() {
        // Steps and return of one method: equal sizes, so one draw per episode serves both;
        // the bands still differ (different values) and each equals its own rendering.
        let steps = tiny_chart(1);
        let mut returns = tiny_chart(1);
        for series in &mut returns.series {
            for curve in &mut series.curves {
                for value in curve.iter_mut() {
                    *value = -*value;
                }
            }
        }
        let svgs = LineChart::render_svgs(&[&steps, &returns]).unwrap();
        assert_eq!(
            svgs,
            [steps.render_svg().unwrap(), returns.render_svg().unwrap()]
        );
        assert_ne!(svgs[0], svgs[1]);
    }
}
