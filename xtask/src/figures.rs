//! SVG line charts of per-episode curves over seeds: for each named series, the mean over seeds
//! as a line and its 95% confidence band (see [`eamadm::summary`]) as a translucent area; optional
//! dashed horizontal reference lines (e.g. the BFS optimum); a title, axis labels and a legend in
//! its own panel to the right of the plot, so it never covers data.
//!
//! Plotters' SVG backend writes text as `<text>` elements in the generic `sans-serif` family and
//! only *estimates* text extents for layout, so rendering needs no font file and no font
//! features (`ttf`/`ab_glyph` stay off): it works on a headless machine. The output bytes are a
//! pure function of the chart (integer pixel coordinates, no timestamps), so equal input gives
//! equal files.
//!
//! A [`Series`] takes one seed's curve at a time ([`Series::push`]) and keeps only per-episode
//! running sums ([`eamadm::summary::BandAccumulator`]), so a chart over many seeds holds no
//! curve: its memory grows with the episodes, not with the seeds.
//!
//! ```ignore
//! let mut ea_madm = Series::new("EA-MADM", 5);
//! for run in ea_madm_runs {
//!     ea_madm.push(&steps_of(run));                  // one seed's curve, then dropped
//! }
//! LineChart::new("Task I: steps per episode", "episode", "steps")
//!     .with_smoothing(5)
//!     .with_series(ea_madm)
//!     .with_series(epsilon_greedy)
//!     .with_reference_line("BFS optimum = 58", 58.0)
//!     .write_svg(&out.join("task1/steps.svg"))?;
//! ```

use std::path::Path;

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};
use eamadm::summary::{self as stats, BandAccumulator, BandPoint, StatsError};

/// Bad chart input, or a failure to draw or write it.
#[derive(Debug, Error)]
pub(crate) enum FigureError {
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
    /// A reference line at a NaN or infinite height.
    #[error("reference line {label:?}: value {value} is not finite")]
    NonFiniteReference {
        /// The line's label.
        label: String,
        /// Its value.
        value: f64,
    },
    /// Values so large that the band's arithmetic overflows (beyond about 1e150).
    #[error("series {series:?}: values too large to plot (the confidence band overflows)")]
    TooLarge {
        /// The series' name.
        series: String,
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
    /// A canvas too small to hold the axes and the legend.
    #[error("chart size {width}×{height} px is below the minimum {MIN_WIDTH}×{MIN_HEIGHT} px")]
    TooSmall {
        /// Requested width in pixels.
        width: u32,
        /// Requested height in pixels.
        height: u32,
    },
    /// Plotters failed while drawing.
    #[error("drawing chart {title:?}: {message}")]
    Draw {
        /// The chart's title.
        title: String,
        /// Plotters' error message.
        message: String,
    },
    /// Writing the SVG file failed.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
}

/// Smallest accepted canvas.
const MIN_WIDTH: u32 = 400;
/// Smallest accepted canvas.
const MIN_HEIGHT: u32 = 250;

/// One method's curves over seeds, taken one seed at a time: the mean band of the raw curves
/// and of their trailing moving averages, accumulated per episode. Curves may differ in length
/// (episode `i` is then summarised over the seeds that reach it).
///
/// The first bad curve (empty, or with a NaN or infinite value) is kept as the series' failure
/// and the curves after it are ignored; drawing the series then fails naming it, the seed (its
/// position among the curves pushed) and the episode, as [`stats::mean_band`] would on all the
/// curves at once. A series that is never drawn never fails.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Series {
    /// Legend label, e.g. `"EA-MADM"`.
    pub(crate) name: String,
    /// Trailing moving-average window each curve is smoothed with (1: none).
    smoothing_window: usize,
    /// Curves pushed, failed ones included.
    curves: usize,
    /// Band of the raw curves: what is drawn without smoothing, and what checks every curve as
    /// given (so errors name the episode as given).
    raw: BandAccumulator,
    /// Band of the smoothed curves (unused without smoothing).
    smoothed: BandAccumulator,
    /// The first bad curve's error.
    failure: Option<StatsError>,
}

impl Series {
    /// A series without curves, whose curves are smoothed over `smoothing_window` episodes
    /// (1 = no smoothing; it must be its chart's window).
    pub(crate) fn new(name: impl Into<String>, smoothing_window: usize) -> Self {
        Self {
            name: name.into(),
            smoothing_window,
            curves: 0,
            raw: BandAccumulator::new(),
            smoothed: BandAccumulator::new(),
            failure: None,
        }
    }

    /// Adds the next seed's curve (`curve[episode]`).
    pub(crate) fn push(&mut self, curve: &[f64]) {
        self.curves += 1;
        if self.failure.is_some() {
            return;
        }
        let pushed = self.raw.push(curve).and_then(|()| {
            if self.smoothing_window > 1 {
                self.smoothed
                    .push(&stats::moving_average(curve, self.smoothing_window)?)
            } else {
                Ok(())
            }
        });
        self.failure = pushed.err();
    }

    /// Curves pushed so far (seeds), failed ones included.
    pub(crate) fn seeds(&self) -> usize {
        self.curves
    }

    /// Numbers held per episode, over both bands (for the memory law: they do not grow with
    /// the seeds).
    #[cfg(test)]
    pub(crate) fn held_episodes(&self) -> usize {
        self.raw.episodes() + self.smoothed.episodes()
    }

    /// The band drawn: the smoothed curves' (the raw ones' without smoothing).
    fn band(&self) -> Result<Vec<BandPoint>, StatsError> {
        if let Some(failure) = &self.failure {
            return Err(failure.clone());
        }
        if self.curves == 0 {
            return Err(StatsError::NoSeeds);
        }
        Ok(if self.smoothing_window > 1 {
            self.smoothed.band()
        } else {
            self.raw.band()
        })
    }
}

/// A dashed horizontal line with a legend label, e.g. `"BFS optimum = 58"` at 58.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ReferenceLine {
    /// Legend label.
    pub(crate) label: String,
    /// Height in data units.
    pub(crate) y: f64,
}

/// A line chart of per-episode curves over seeds; build it with [`LineChart::new`] and the
/// `with_*` methods, then call [`LineChart::render_svg`] or [`LineChart::write_svg`].
///
/// Colours follow the order of the series (Okabe–Ito palette, readable by colour-blind
/// readers): give the methods in the same order in every figure and each keeps its colour.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LineChart {
    /// Title above the chart.
    pub(crate) title: String,
    /// Label of the x axis (episodes, numbered from 1).
    pub(crate) x_label: String,
    /// Label of the y axis.
    pub(crate) y_label: String,
    /// The series, drawn in this order (later ones on top).
    pub(crate) series: Vec<Series>,
    /// Dashed horizontal reference lines.
    pub(crate) reference_lines: Vec<ReferenceLine>,
    /// Trailing moving-average window applied to every seed's curve before averaging over seeds
    /// ([`stats::moving_average`]); 1 means no smoothing. The legend states the window; every
    /// series is smoothed with it.
    pub(crate) smoothing_window: usize,
    /// Canvas size in pixels, (width, height).
    pub(crate) size: (u32, u32),
}

/// Okabe–Ito colours (black last, kept for an eighth series).
const PALETTE: [RGBColor; 8] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0xF0, 0xE4, 0x42), // yellow
    RGBColor(0x00, 0x00, 0x00), // black
];
/// Reference lines are dark grey and dashed, unlike any series.
const REFERENCE_COLOR: RGBColor = RGBColor(0x44, 0x44, 0x44);
/// Opacity of the confidence bands.
const BAND_OPACITY: f64 = 0.18;
/// Font sizes as plotters counts them (the SVG backend writes `size / 1.24` px).
const TITLE_FONT: f64 = 26.0;
const AXIS_FONT: f64 = 18.0;
const TICK_FONT: f64 = 15.0;
const LEGEND_FONT: f64 = 16.0;
const NOTE_FONT: f64 = 14.0;

impl LineChart {
    /// An empty 900×500 px chart with no smoothing.
    pub(crate) fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            reference_lines: Vec::new(),
            smoothing_window: 1,
            size: (900, 500),
        }
    }

    /// Adds a series (made with this chart's smoothing window).
    pub(crate) fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Adds a dashed horizontal reference line at height `y`.
    pub(crate) fn with_reference_line(mut self, label: impl Into<String>, y: f64) -> Self {
        self.reference_lines.push(ReferenceLine {
            label: label.into(),
            y,
        });
        self
    }

    /// States that every seed's curve is smoothed with a trailing moving average over `window`
    /// episodes before averaging over seeds (1 = no smoothing); the series must be made with the
    /// same window ([`Series::new`]).
    pub(crate) fn with_smoothing(mut self, window: usize) -> Self {
        self.smoothing_window = window;
        self
    }

    #[cfg_attr(
        not(test),
        expect(
            dead_code,
            reason = "the figures of reproduce-paper use the default size and are written via outputs"
        )
    )]
    /// Sets the canvas size in pixels.
    pub(crate) fn with_size(mut self, width: u32, height: u32) -> Self {
        self.size = (width, height);
        self
    }

    /// Renders the chart as an SVG document.
    pub(crate) fn render_svg(&self) -> Result<String, FigureError> {
        let bands = self.bands()?;
        let (width, height) = self.size;
        if width < MIN_WIDTH || height < MIN_HEIGHT {
            return Err(FigureError::TooSmall { width, height });
        }
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, self.size).into_drawing_area();
            self.draw(&root, &bands)
                .map_err(|message| FigureError::Draw {
                    title: self.title.clone(),
                    message,
                })?;
        }
        Ok(svg)
    }

    #[cfg_attr(
        not(test),
        expect(
            dead_code,
            reason = "the figures of reproduce-paper use the default size and are written via outputs"
        )
    )]
    /// Renders the chart and writes it to `path` atomically (creating parent folders).
    pub(crate) fn write_svg(&self, path: &Path) -> Result<(), FigureError> {
        let svg = self.render_svg()?;
        write_atomic(path, svg.as_bytes())?;
        Ok(())
    }

    /// Validates the input and computes each series' smoothed mean band.
    fn bands(&self) -> Result<Vec<Vec<BandPoint>>, FigureError> {
        if self.series.is_empty() {
            return Err(FigureError::NoSeries {
                title: self.title.clone(),
            });
        }
        if self.smoothing_window == 0 {
            return Err(FigureError::ZeroSmoothingWindow);
        }
        if let Some(line) = self.reference_lines.iter().find(|l| !l.y.is_finite()) {
            return Err(FigureError::NonFiniteReference {
                label: line.label.clone(),
                value: line.y,
            });
        }
        self.series
            .iter()
            .map(|series| {
                if series.smoothing_window != self.smoothing_window {
                    return Err(FigureError::SmoothingMismatch {
                        series: series.name.clone(),
                        series_window: series.smoothing_window,
                        chart_window: self.smoothing_window,
                    });
                }
                let band = series.band().map_err(|source| FigureError::Series {
                    series: series.name.clone(),
                    source,
                })?;
                let finite = |p: &BandPoint| p.lower.is_finite() && p.upper.is_finite();
                if band.iter().all(finite) {
                    Ok(band)
                } else {
                    Err(FigureError::TooLarge {
                        series: series.name.clone(),
                    })
                }
            })
            .collect()
    }

    /// The data ranges: x over episodes 1..=longest, y over every band and reference line,
    /// padded by 5% so nothing touches the frame.
    fn ranges(&self, bands: &[Vec<BandPoint>]) -> ((f64, f64), (f64, f64)) {
        let longest = bands.iter().map(Vec::len).max().unwrap_or(1);
        let x_max = (longest as f64).max(2.0);
        let ys = bands
            .iter()
            .flatten()
            .flat_map(|p| [p.lower, p.upper])
            .chain(self.reference_lines.iter().map(|l| l.y));
        let (low, high) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
            (lo.min(y), hi.max(y))
        });
        // 5% of each end separately: `high - low` itself could overflow.
        let pad = if high > low {
            0.05 * high - 0.05 * low
        } else {
            (0.1 * low.abs()).max(1.0)
        };
        ((1.0, x_max), (low - pad, high + pad))
    }

    /// Width of the legend panel: enough for the longest label (estimated, the SVG viewer picks
    /// the real font), at most 40% of the canvas; longer labels are wrapped at spaces.
    fn legend_width(&self) -> u32 {
        let labels = self
            .series
            .iter()
            .map(|s| s.name.as_str())
            .chain(self.reference_lines.iter().map(|l| l.label.as_str()))
            .map(|label| f64::from(LEGEND_SAMPLE + LEGEND_GAP) + text_width(label, LEGEND_FONT));
        let notes = self.notes();
        let widest = labels
            .chain(notes.iter().map(|note| text_width(note, NOTE_FONT)))
            .fold(0.0, f64::max);
        (widest.ceil() as u32 + 2 * LEGEND_PAD).clamp(140, self.size.0 * 2 / 5)
    }

    /// Small print under the legend: what the lines and bands are.
    fn notes(&self) -> Vec<String> {
        let mut notes = vec![
            "line: mean over seeds".to_owned(),
            "band: 95% CI of the mean".to_owned(),
        ];
        if self.smoothing_window > 1 {
            notes.push(format!("{}-episode moving average", self.smoothing_window));
        }
        notes
    }

    fn draw(
        &self,
        root: &DrawingArea<SVGBackend<'_>, Shift>,
        bands: &[Vec<BandPoint>],
    ) -> Result<(), String> {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let body = if self.title.is_empty() {
            root.clone()
        } else {
            root.titled(&self.title, ("sans-serif", TITLE_FONT))
                .map_err(|e| e.to_string())?
        };
        let body_width = body.dim_in_pixel().0;
        let (plot_area, legend_area) =
            body.split_horizontally(body_width.saturating_sub(self.legend_width()));
        self.draw_plot(&plot_area, bands)
            .map_err(|e| e.to_string())?;
        self.draw_legend(&legend_area).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())
    }

    fn draw_plot(
        &self,
        area: &DrawingArea<SVGBackend<'_>, Shift>,
        bands: &[Vec<BandPoint>],
    ) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
        let ((x_min, x_max), (y_min, y_max)) = self.ranges(bands);
        let y_decimals = tick_decimals(y_max - y_min);
        let mut chart = ChartBuilder::on(area)
            .margin(PLOT_MARGIN)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(x_min..x_max, y_min..y_max)?;
        chart
            .configure_mesh()
            .x_desc(self.x_label.as_str())
            .y_desc(self.y_label.as_str())
            .axis_desc_style(("sans-serif", AXIS_FONT))
            .label_style(("sans-serif", TICK_FONT))
            // Episodes are whole numbers: at most one tick per episode, so no label repeats.
            .x_labels(((x_max - x_min) as usize + 1).clamp(2, 10))
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_label_formatter(&|y| format!("{y:.y_decimals$}"))
            .bold_line_style(RGBColor(0xDD, 0xDD, 0xDD))
            .light_line_style(RGBColor(0xF2, 0xF2, 0xF2))
            .draw()?;

        // Bands first, so every mean line is drawn on top of every band.
        for (index, band) in bands.iter().enumerate() {
            let color = PALETTE[index % PALETTE.len()];
            let outline: Vec<(f64, f64)> = band
                .iter()
                .enumerate()
                .map(|(i, p)| (episode(i), p.upper))
                .chain(
                    band.iter()
                        .enumerate()
                        .rev()
                        .map(|(i, p)| (episode(i), p.lower)),
                )
                .collect();
            chart.draw_series(std::iter::once(Polygon::new(
                outline,
                color.mix(BAND_OPACITY).filled(),
            )))?;
        }
        for line in &self.reference_lines {
            chart.draw_series(std::iter::once(DashedPathElement::new(
                [(x_min, line.y), (x_max, line.y)],
                8,
                5,
                REFERENCE_COLOR.stroke_width(2),
            )))?;
        }
        for (index, band) in bands.iter().enumerate() {
            let color = PALETTE[index % PALETTE.len()];
            chart.draw_series(LineSeries::new(
                band.iter().enumerate().map(|(i, p)| (episode(i), p.mean)),
                color.stroke_width(2),
            ))?;
        }
        Ok(())
    }

    fn draw_legend(
        &self,
        area: &DrawingArea<SVGBackend<'_>, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
        let label_style =
            TextStyle::from(("sans-serif", LEGEND_FONT)).pos(Pos::new(HPos::Left, VPos::Center));
        let note_style = TextStyle::from(("sans-serif", NOTE_FONT).into_font())
            .color(&RGBColor(0x55, 0x55, 0x55))
            .pos(Pos::new(HPos::Left, VPos::Center));
        let x0 = LEGEND_PAD as i32;
        let x1 = x0 + LEGEND_SAMPLE as i32;
        let text_x = x1 + LEGEND_GAP as i32;
        let width = f64::from(area.dim_in_pixel().0) - f64::from(LEGEND_PAD);
        let chars_that_fit = |from: i32, font: f64| {
            ((width - f64::from(from)) / text_width("m", font))
                .floor()
                .max(1.0) as usize
        };
        let label_chars = chars_that_fit(text_x, LEGEND_FONT);
        let note_chars = chars_that_fit(x0, NOTE_FONT);
        // Start level with the top of the plot.
        let mut y = PLOT_MARGIN as i32 + LEGEND_ROW / 2;
        for (index, series) in self.series.iter().enumerate() {
            let color = PALETTE[index % PALETTE.len()];
            area.draw(&Rectangle::new(
                [(x0, y - 7), (x1, y + 7)],
                color.mix(BAND_OPACITY).filled(),
            ))?;
            area.draw(&PathElement::new(
                vec![(x0, y), (x1, y)],
                color.stroke_width(2),
            ))?;
            y = draw_wrapped(area, &series.name, label_chars, (text_x, y), &label_style)?;
        }
        for line in &self.reference_lines {
            area.draw(&DashedPathElement::new(
                [(x0, y), (x1, y)],
                8,
                5,
                REFERENCE_COLOR.stroke_width(2),
            ))?;
            y = draw_wrapped(area, &line.label, label_chars, (text_x, y), &label_style)?;
        }
        y += LEGEND_ROW / 2;
        for note in self.notes() {
            for line in wrap(&note, note_chars) {
                area.draw(&Text::new(line, (x0, y), &note_style))?;
                y += LEGEND_LINE;
            }
        }
        Ok(())
    }
}

/// Margin around the plot, in pixels.
const PLOT_MARGIN: u32 = 12;
/// Legend layout, in pixels: padding, line-sample length, gap before the text, row height.
const LEGEND_PAD: u32 = 10;
const LEGEND_SAMPLE: u32 = 28;
const LEGEND_GAP: u32 = 8;
const LEGEND_ROW: i32 = 24;
const LEGEND_LINE: i32 = 18;

/// Estimated width in pixels of `text` at plotters font size `font` (0.6 em per character).
fn text_width(text: &str, font: f64) -> f64 {
    text.chars().count() as f64 * 0.6 * font / 1.24
}

/// Greedy word wrap to lines of at most `max_chars` characters (a longer word keeps its line).
fn wrap(text: &str, max_chars: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= max_chars => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_owned()),
        }
    }
    lines
}

/// Draws a legend label wrapped to `max_chars` per line, the first line centred on `at`;
/// returns the `y` of the next legend row.
fn draw_wrapped(
    area: &DrawingArea<SVGBackend<'_>, Shift>,
    label: &str,
    max_chars: usize,
    at: (i32, i32),
    style: &TextStyle<'_>,
) -> Result<i32, DrawingAreaErrorKind<std::io::Error>> {
    let (x, mut y) = at;
    let lines = wrap(label, max_chars);
    for (index, line) in lines.iter().enumerate() {
        if index > 0 {
            y += LEGEND_LINE;
        }
        area.draw(&Text::new(line.as_str(), (x, y), style))?;
    }
    Ok(y + LEGEND_ROW)
}

/// Decimals for tick labels on an axis spanning `span`: enough to tell apart ticks about a
/// tenth of the span apart, and none for spans of 10 or more.
fn tick_decimals(span: f64) -> usize {
    let step = span / 10.0;
    if step >= 1.0 || step <= 0.0 || !step.is_finite() {
        0
    } else {
        // step in [10^-k, 10^-(k-1)) needs k decimals.
        (-step.log10().floor()).min(6.0) as usize
    }
}

/// Episode number (from 1) of curve index `i`.
fn episode(i: usize) -> f64 {
    (i + 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A series of `runs[seed][episode]`, pushed seed by seed.
    fn series(name: &str, window: usize, runs: &[Vec<f64>]) -> Series {
        let mut series = Series::new(name, window);
        for curve in runs {
            series.push(curve);
        }
        series
    }

    /// A chart of two methods of four episodes, smoothed over `window` episodes.
    fn tiny_chart(window: usize) -> LineChart {
        LineChart::new("Task I: steps per episode", "episode", "steps")
            .with_smoothing(window)
            .with_series(series(
                "EA-MADM",
                window,
                &[
                    vec![300.0, 120.0, 70.0, 61.0],
                    vec![280.0, 140.0, 66.0, 60.0],
                ],
            ))
            .with_series(series(
                "ε-greedy",
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
            "steps",
            "band: 95% CI of the mean",
        ] {
            assert!(svg.contains(text), "missing {text:?}");
        }
        // One translucent band polygon per series, in the series' colour.
        assert_eq!(svg.matches("<polygon").count(), 2, "{svg}");
        assert!(
            svg.contains(r##"<polygon opacity="0.18" fill="#0072B2""##),
            "{svg}"
        );
        assert!(
            svg.contains(r##"<polygon opacity="0.18" fill="#D55E00""##),
            "{svg}"
        );
        // Mean lines are polylines in the series' colours.
        assert!(svg.contains(r##"<polyline fill="none" opacity="1" stroke="#0072B2""##));
        assert!(svg.contains(r##"<polyline fill="none" opacity="1" stroke="#D55E00""##));
        // No smoothing note unless smoothing is on.
        assert!(!svg.contains("moving average"));
    }

    #[test]
    fn same_input_gives_the_same_bytes() {
        let a = tiny_chart(2).render_svg().unwrap();
        let b = tiny_chart(2).render_svg().unwrap();
        assert_eq!(a, b);
        assert!(a.contains("2-episode moving average"));
        assert_ne!(a, tiny_chart(1).render_svg().unwrap());
    }

    /// The texts of an SVG's `<text>` elements (plotters writes each on its own line).
    fn texts(svg: &str) -> Vec<&str> {
        let lines: Vec<&str> = svg.lines().collect();
        lines
            .windows(2)
            .filter(|pair| pair[0].starts_with("<text"))
            .map(|pair| pair[1])
            .collect()
    }

    #[test]
    fn short_runs_get_one_tick_per_episode() {
        let svg = LineChart::new("quick", "episode", "steps")
            .with_series(series("a", 1, &[vec![150.0, 130.0, 120.0, 110.0, 105.0]]))
            .render_svg()
            .unwrap();
        let texts = texts(&svg);
        for tick in ["1", "2", "3", "4", "5"] {
            let count = texts.iter().filter(|text| **text == tick).count();
            assert_eq!(count, 1, "tick {tick} in {texts:?}");
        }
    }

    #[test]
    fn single_seed_and_flat_curves_render() {
        let svg = LineChart::new("flat", "episode", "return")
            .with_series(series("only", 1, &[vec![5.0]]))
            .render_svg()
            .unwrap();
        assert!(svg.contains("only"));
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

        let error = LineChart::new("t", "x", "y")
            .with_series(series("huge", 1, &[vec![1e300], vec![-1e300]]))
            .render_svg()
            .unwrap_err();
        assert!(matches!(error, FigureError::TooLarge { .. }), "{error}");

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

        // The first bad curve is the one named, whatever comes after it; its seed is its
        // position among the curves pushed.
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

        let error = tiny_chart(1).with_size(100, 100).render_svg().unwrap_err();
        assert!(matches!(
            error,
            FigureError::TooSmall {
                width: 100,
                height: 100
            }
        ));
    }

    #[test]
    fn wrap_breaks_at_spaces() {
        assert_eq!(
            wrap("EA-MADM without trees (table)", 14),
            vec!["EA-MADM", "without trees", "(table)"]
        );
        assert_eq!(wrap("softmax", 3), vec!["softmax"]);
        assert_eq!(wrap("a  b", 10), vec!["a b"]);
        assert!(wrap("", 10).is_empty());
    }

    #[test]
    fn tick_decimals_follow_the_span() {
        assert_eq!(tick_decimals(1300.0), 0);
        assert_eq!(tick_decimals(10.0), 0);
        assert_eq!(tick_decimals(2.0), 1);
        assert_eq!(tick_decimals(0.05), 3);
        assert_eq!(tick_decimals(0.0), 0);
        assert_eq!(tick_decimals(1e-300), 6);
    }

    #[test]
    fn write_svg_writes_the_rendered_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("task1/steps.svg");
        let chart = tiny_chart(1);
        chart.write_svg(&path).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            chart.render_svg().unwrap()
        );
    }
}
