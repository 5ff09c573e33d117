//! The figures of an output folder, written atomically: per experiment the SVG charts and the
//! greedy paths under `<name>/`. The CSV tables and the run store are streamed by
//! [`crate::finish`].

use std::fmt::Write as _;
use std::path::Path;

use eamadm::mazes::{self, Pos, SvgOptions, SvgTrajectory};
use eamadm::wmr_model::{self, RenderedPath};
use eamadm::{EpisodeRecord, RunRecord, results};
use nalgebra::Point2;
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};
use eamadm::paper::method_title;

use crate::experiments::PlannedExperiment;
use crate::figures::{FigureError, LineChart};

/// Episodes of the trailing moving average drawn in the per-episode figures.
pub(crate) const FIGURE_SMOOTHING: usize = 5;

/// Writing an output failed.
#[derive(Debug, Error)]
pub(crate) enum OutputError {
    /// Serialising results failed.
    #[error("{file}: {source}")]
    Results {
        /// The file being made.
        file: String,
        /// Why.
        #[source]
        source: results::ResultsError,
    },
    /// A figure failed.
    #[error(transparent)]
    Figure(#[from] FigureError),
    /// Writing failed.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
}

/// Writes the SVG figures of one experiment under `<out>/<name>/` (its CSV tables are streamed
/// by [`crate::finish`]).
pub(crate) fn write_figures(
    out: &Path,
    planned: &PlannedExperiment,
    records: &[RunRecord],
) -> Result<Vec<String>, OutputError> {
    let folder = out.join(&planned.name);
    let mut written = Vec::new();
    for (file, svg) in experiment_figures(planned, records)? {
        write_atomic(&folder.join(&file), svg.as_bytes())?;
        written.push(file);
    }
    Ok(written)
}

/// The methods of `records`, in record order, without repeats.
pub(crate) fn methods_of(records: &[RunRecord]) -> Vec<&str> {
    let mut methods: Vec<&str> = Vec::new();
    for record in records {
        if !methods.contains(&record.method.as_str()) {
            methods.push(&record.method);
        }
    }
    methods
}

/// Per method (of `methods`), the per-seed curves of `value`.
fn curves<'a>(
    records: &[RunRecord],
    methods: &[&'a str],
    value: impl Fn(&EpisodeRecord) -> f64,
) -> Vec<(&'a str, Vec<Vec<f64>>)> {
    methods
        .iter()
        .map(|&method| {
            let runs = records
                .iter()
                .filter(|r| r.method == method)
                .map(|r| r.episodes.iter().map(&value).collect())
                .collect();
            (method, runs)
        })
        .collect()
}

// step counts far below 2^52
fn steps(episode: &EpisodeRecord) -> f64 {
    episode.steps as f64
}

/// A chart of one per-episode quantity for `methods`.
fn chart(
    title: String,
    y_label: &str,
    series: Vec<(&str, Vec<Vec<f64>>)>,
    reference: Option<(String, f64)>,
) -> Result<String, FigureError> {
    let mut chart = LineChart::new(title, "episode", y_label).with_smoothing(FIGURE_SMOOTHING);
    for (method, runs) in series {
        chart = chart.with_series(method_title(method), runs);
    }
    if let Some((label, y)) = reference {
        chart = chart.with_reference_line(label, y);
    }
    chart.render_svg()
}

/// A chart of one robot metric over *reaching* episodes (x = the n-th episode of a seed that
/// reached the target; seeds with fewer reaching episodes drop out to the right). Methods that
/// never reach are not drawn; the title names them.
fn reaching_chart(
    title: &str,
    y_label: &str,
    records: &[RunRecord],
    methods: &[&str],
    value: impl Fn(&EpisodeRecord) -> f64,
) -> Result<String, FigureError> {
    let series = curves(records, methods, |e| {
        if e.reached { value(e) } else { f64::NAN }
    });
    let mut never = Vec::new();
    let mut chart =
        LineChart::new(String::new(), "reaching episode", y_label).with_smoothing(FIGURE_SMOOTHING);
    let mut drawn = 0;
    for (method, runs) in series {
        let reaching: Vec<Vec<f64>> = runs
            .into_iter()
            .map(|run| {
                run.into_iter()
                    .filter(|v| !v.is_nan())
                    .collect::<Vec<f64>>()
            })
            .filter(|run| !run.is_empty())
            .collect();
        if reaching.is_empty() {
            never.push(method_title(method));
        } else {
            let seeds = reaching.len();
            chart = chart.with_series(
                format!(
                    "{} ({seeds} seed{})",
                    method_title(method),
                    if seeds == 1 { "" } else { "s" }
                ),
                reaching,
            );
            drawn += 1;
        }
    }
    chart.title = if never.is_empty() {
        format!("{title} (mean over reaching seeds, 95% CI)")
    } else {
        format!("{title}; never reached: {}", never.join(", "))
    };
    if drawn == 0 {
        // Nothing reached: the chart says so and draws no data (a single point draws no line;
        // a chart without any series would be an error).
        chart.title = format!(
            "{}: no method reached the target",
            title.split(':').next().unwrap_or(title)
        );
        chart = chart.with_series("no method reached the target", vec![vec![0.0]]);
    }
    chart.render_svg()
}

/// The figures of one experiment: file name and SVG text.
pub(crate) fn experiment_figures(
    planned: &PlannedExperiment,
    records: &[RunRecord],
) -> Result<Vec<(String, String)>, OutputError> {
    let all = methods_of(records);
    if all.is_empty() {
        return Ok(Vec::new());
    }
    let main: Vec<&str> = all
        .iter()
        .copied()
        .filter(|m| planned.is_paper_method(m))
        .collect();
    let shown = if main.is_empty() { all.clone() } else { main };
    let ablations: Vec<&str> = all
        .iter()
        .copied()
        .filter(|m| *m == "ea-madm" || !planned.is_paper_method(m))
        .collect();
    let is_robot = planned.experiment.task().scenario().is_some();
    // optimum far below 2^52
    let reference = records
        .first()
        .and_then(|r| r.optimum_steps)
        .map(|optimum| {
            let source = if is_robot { "planner" } else { "BFS" };
            (format!("{source} optimum = {optimum}"), optimum as f64)
        });
    let title = &planned.title;
    let smoothing = format!("(mean over seeds, 95% CI; {FIGURE_SMOOTHING}-episode moving average)");
    let mut figures = vec![
        (
            "steps.svg".to_owned(),
            chart(
                format!("{title}: steps per episode {smoothing}"),
                "steps",
                curves(records, &shown, steps),
                reference.clone(),
            )?,
        ),
        (
            "return.svg".to_owned(),
            chart(
                format!("{title}: return per episode {smoothing}"),
                "return",
                curves(records, &shown, |e| e.task_return),
                None,
            )?,
        ),
    ];
    if ablations.len() > 1 || (ablations.len() == 1 && !ablations.contains(&"ea-madm")) {
        figures.push((
            "ablations-steps.svg".to_owned(),
            chart(
                format!("{title}: EA-MADM and its ablations, steps per episode {smoothing}"),
                "steps",
                curves(records, &ablations, steps),
                reference,
            )?,
        ));
    }
    if is_robot {
        // The robot's first figure is success per episode: with no success, more steps only
        // means surviving longer.
        figures.insert(
            0,
            (
                "success.svg".to_owned(),
                chart(
                    format!("{title}: success per episode"),
                    "share of seeds that reached the target",
                    curves(records, &shown, |e| f64::from(u8::from(e.reached))),
                    None,
                )?,
            ),
        );
        let robot = |value: fn(&eamadm::RobotEpisodeMetrics) -> f64| {
            move |e: &EpisodeRecord| e.robot.as_ref().map_or(0.0, value)
        };
        // Fig. 13–15 plot "episodes that are to reach the target": x is the reaching-episode
        // index, each seed contributing its own reaching episodes in order.
        for (file, what, y_label, value) in [
            (
                "average-reward.svg",
                "average reward",
                "average reward (return per second)",
                robot(|m| m.average_reward),
            ),
            (
                "reaching-time.svg",
                "reaching time",
                "time to reach (s)",
                robot(|m| m.time_to_reach.unwrap_or(m.time)),
            ),
            (
                "retention-time.svg",
                "retention time",
                "retention time (s)",
                robot(|m| m.retention_time),
            ),
        ] {
            figures.push((
                file.to_owned(),
                reaching_chart(
                    &format!("{title}: {what} over reaching episodes"),
                    y_label,
                    records,
                    &shown,
                    value,
                )?,
            ));
        }
    }
    if let Some(svg) = trajectory_figure(planned, records, &shown) {
        figures.push(("trajectories.svg".to_owned(), svg));
    }
    Ok(figures)
}

/// The greedy evaluation path of each method's first seed, drawn on the maze or the robot's
/// arena (the analogue of Fig. 6 and 9).
fn trajectory_figure(
    planned: &PlannedExperiment,
    records: &[RunRecord],
    methods: &[&str],
) -> Option<String> {
    let firsts: Vec<&RunRecord> = methods
        .iter()
        .filter_map(|&m| records.iter().find(|r| r.method == m))
        .collect();
    let task = planned.experiment.task();
    if let Some(maze) = task.maze() {
        let paths: Vec<(String, Vec<Pos>)> = firsts
            .iter()
            .map(|r| {
                let path = r
                    .evaluation_trajectory
                    .states
                    .iter()
                    .filter_map(|&s| maze.pos_of(s))
                    .collect();
                (
                    format!(
                        "{} (seed {}, greedy{})",
                        method_title(&r.method),
                        r.seed,
                        if r.evaluation.reached {
                            ""
                        } else {
                            ", target not reached"
                        }
                    ),
                    path,
                )
            })
            .collect();
        let trajectories: Vec<SvgTrajectory<'_>> = paths
            .iter()
            .map(|(label, path)| SvgTrajectory {
                label,
                path,
                color: None,
            })
            .collect();
        let options = SvgOptions {
            title: Some(format!("{}: greedy paths after training", planned.title)),
            ..SvgOptions::default()
        };
        return Some(mazes::render_svg(maze, &trajectories, &options));
    }
    let scenario = task.scenario()?;
    let paths: Vec<(String, Vec<Point2<f64>>)> = firsts
        .iter()
        .map(|r| {
            let points = r
                .evaluation_trajectory
                .positions
                .iter()
                .map(|&[x, y]| Point2::new(x, y))
                .collect();
            let outcome = if r.evaluation.reached {
                "reached the target"
            } else {
                "target not reached"
            };
            (
                format!(
                    "{} (seed {}, greedy, {} steps, {outcome})",
                    method_title(&r.method),
                    r.seed,
                    r.evaluation.steps
                ),
                points,
            )
        })
        .collect();
    let rendered: Vec<RenderedPath<'_>> = paths
        .iter()
        .map(|(label, points)| RenderedPath { points, label })
        .collect();
    let arena = wmr_model::render_svg(scenario, &rendered);
    let legend: Vec<(&str, &str)> = paths
        .iter()
        .enumerate()
        .map(|(index, (label, _))| {
            (
                label.as_str(),
                wmr_model::render::PATH_COLOURS[index % wmr_model::render::PATH_COLOURS.len()],
            )
        })
        .collect();
    Some(titled_with_legend(
        &arena,
        &format!("{}: greedy paths after training", planned.title),
        &legend,
    ))
}

/// Height of the title band and of one legend line, in pixels.
const BAND_PX: u32 = 24;

/// `inner` (an SVG document without a title or legend, such as `wmr_model::render_svg`'s)
/// nested in a document with `title` above it and a legend of (label, colour) below.
fn titled_with_legend(inner: &str, title: &str, legend: &[(&str, &str)]) -> String {
    let attribute = |name: &str| -> u32 {
        let pattern = format!("{name}=\"");
        inner
            .find(&pattern)
            .and_then(|start| {
                let rest = &inner[start + pattern.len()..];
                rest[..rest.find('"')?].parse().ok()
            })
            .unwrap_or(520)
    };
    let (width, height) = (attribute("width"), attribute("height"));
    let legend_top = BAND_PX + height + BAND_PX / 2;
    let total = legend_top + BAND_PX * u32::try_from(legend.len()).unwrap_or(0) + BAND_PX / 2;
    let escape = |text: &str| {
        text.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{total}\" \
         viewBox=\"0 0 {width} {total}\" font-family=\"sans-serif\">\n\
         <rect width=\"{width}\" height=\"{total}\" fill=\"white\"/>\n\
         <text x=\"{}\" y=\"17\" font-size=\"15\" text-anchor=\"middle\">{}</text>\n\
         <svg x=\"0\" y=\"{BAND_PX}\"{}\n",
        width / 2,
        escape(title),
        inner.strip_prefix("<svg").unwrap_or(inner),
    );
    for (index, (label, colour)) in legend.iter().enumerate() {
        let y = legend_top + BAND_PX * u32::try_from(index).unwrap_or(0) + BAND_PX / 2;
        let _ = writeln!(
            svg,
            "<line x1=\"12\" y1=\"{y}\" x2=\"40\" y2=\"{y}\" stroke=\"{colour}\" \
             stroke-width=\"3\"/><text x=\"48\" y=\"{}\" font-size=\"13\">{}</text>",
            y + 4,
            escape(label)
        );
    }
    svg.push_str("</svg>\n");
    svg
}
