//! The figures of an output folder, written atomically: per experiment the SVG charts and the
//! greedy paths under `<name>/`, collected run by run ([`ExperimentFigures`]) so that no run is
//! held until the figures are drawn. The CSV tables and the run store are streamed by
//! [`crate::finish`].

use std::fmt::Write as _;
use std::path::Path;

use eamadm::mazes::{self, Pos, SvgOptions, SvgTrajectory};
use eamadm::wmr_model::{self, RenderedPath};
use eamadm::{EpisodeRecord, RobotEpisodeMetrics, RunRecord, TrajectoryRecord, results};
use nalgebra::Point2;
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};
use eamadm::paper::method_title;

use crate::experiments::PlannedExperiment;
use crate::figures::{FigureError, LineChart, Series};

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

/// One of the robot's charts over reaching episodes (Fig. 13–15).
struct ReachingChart {
    /// The SVG file.
    file: &'static str,
    /// What is drawn, for the title.
    what: &'static str,
    /// The y axis label.
    y_label: &'static str,
    /// The value of a reaching episode.
    value: fn(&RobotEpisodeMetrics) -> f64,
}

/// The robot's charts over reaching episodes, in the order they are written.
const REACHING_CHARTS: [ReachingChart; 3] = [
    ReachingChart {
        file: "average-reward.svg",
        what: "average reward",
        y_label: "average reward (return per second)",
        value: |m| m.average_reward,
    },
    ReachingChart {
        file: "reaching-time.svg",
        what: "reaching time",
        y_label: "time to reach (s)",
        value: |m| m.time_to_reach.unwrap_or(m.time),
    },
    ReachingChart {
        file: "retention-time.svg",
        what: "retention time",
        y_label: "retention time (s)",
        value: |m| m.retention_time,
    },
];

/// The figures of one experiment, collected run by run in job order and drawn at the end:
/// per method the per-episode mean bands of what the charts draw ([`Series`]), and the greedy
/// evaluation path of its first run. No run is held, so memory does not grow with the seeds.
pub(crate) struct ExperimentFigures<'a> {
    planned: &'a PlannedExperiment,
    is_robot: bool,
    /// The first run's optimum (the charts' reference line); `None` before the first run.
    optimum: Option<Option<u64>>,
    /// One per method, in the order methods first came.
    methods: Vec<MethodCurves>,
}

/// What the figures draw of one method's runs.
struct MethodCurves {
    /// The method's label.
    method: String,
    steps: Series,
    task_return: Series,
    /// Robot only: 1 for an episode that reached the target, else 0.
    success: Option<Series>,
    /// Robot only: one per [`REACHING_CHARTS`] entry, each seed's curve over its reaching
    /// episodes (a seed without one adds no curve).
    reaching: Vec<Series>,
    /// The first run's greedy evaluation, for the trajectory figure.
    first: FirstRun,
}

/// The greedy evaluation of a method's first run.
struct FirstRun {
    seed: u64,
    reached: bool,
    steps: u64,
    trajectory: TrajectoryRecord,
}

impl MethodCurves {
    fn new(record: &RunRecord, is_robot: bool) -> Self {
        let title = method_title(&record.method);
        let series = || Series::new(title.clone(), FIGURE_SMOOTHING);
        Self {
            method: record.method.clone(),
            steps: series(),
            task_return: series(),
            success: is_robot.then(series),
            reaching: if is_robot {
                REACHING_CHARTS.iter().map(|_| series()).collect()
            } else {
                Vec::new()
            },
            first: FirstRun {
                seed: record.seed,
                reached: record.evaluation.reached,
                steps: record.evaluation.steps,
                trajectory: record.evaluation_trajectory.clone(),
            },
        }
    }

    fn push(&mut self, record: &RunRecord) {
        let curve = |value: &dyn Fn(&EpisodeRecord) -> f64| -> Vec<f64> {
            record.episodes.iter().map(value).collect()
        };
        // step counts far below 2^52
        self.steps.push(&curve(&|e| e.steps as f64));
        self.task_return.push(&curve(&|e| e.task_return));
        if let Some(success) = &mut self.success {
            success.push(&curve(&|e| f64::from(u8::from(e.reached))));
        }
        for (series, chart) in self.reaching.iter_mut().zip(&REACHING_CHARTS) {
            // The reaching episodes in order; a NaN value is left out like the episodes that
            // did not reach (the figures have always drawn the non-NaN reaching values).
            let reaching: Vec<f64> = record
                .episodes
                .iter()
                .filter(|e| e.reached)
                .map(|e| e.robot.as_ref().map_or(0.0, chart.value))
                .filter(|v| !v.is_nan())
                .collect();
            if !reaching.is_empty() {
                series.push(&reaching);
            }
        }
    }
}

impl<'a> ExperimentFigures<'a> {
    /// A collector for the figures of `planned`, without runs.
    pub(crate) fn new(planned: &'a PlannedExperiment) -> Self {
        Self {
            planned,
            is_robot: planned.experiment.task().scenario().is_some(),
            optimum: None,
            methods: Vec::new(),
        }
    }

    /// Adds one run (runs come in job order: method by method, seed by seed).
    pub(crate) fn push(&mut self, record: &RunRecord) {
        self.optimum.get_or_insert(record.optimum_steps);
        let index = match self.methods.iter().position(|m| m.method == record.method) {
            Some(index) => index,
            None => {
                self.methods.push(MethodCurves::new(record, self.is_robot));
                self.methods.len() - 1
            }
        };
        self.methods[index].push(record);
    }

    /// Numbers held per episode and per path point over every series and first run: what the
    /// collector keeps, which depends on methods and episodes, not on seeds.
    #[cfg(test)]
    pub(crate) fn held_size(&self) -> usize {
        self.methods
            .iter()
            .map(|m| {
                let series = [&m.steps, &m.task_return]
                    .into_iter()
                    .chain(&m.success)
                    .chain(&m.reaching);
                series.map(Series::held_episodes).sum::<usize>()
                    + m.first.trajectory.states.len()
                    + m.first.trajectory.positions.len()
            })
            .sum()
    }

    /// Writes the SVG figures under `<out>/<name>/` (the experiment's CSV tables are streamed by
    /// [`crate::finish`]) and returns their file names.
    pub(crate) fn write(self, out: &Path) -> Result<Vec<String>, OutputError> {
        let folder = out.join(&self.planned.name);
        let mut written = Vec::new();
        for (file, svg) in self.render()? {
            write_atomic(&folder.join(&file), svg.as_bytes())?;
            written.push(file);
        }
        Ok(written)
    }

    /// The figures: file name and SVG text (none without runs).
    pub(crate) fn render(self) -> Result<Vec<(String, String)>, OutputError> {
        let planned = self.planned;
        if self.methods.is_empty() {
            return Ok(Vec::new());
        }
        let is_paper = |m: &&MethodCurves| planned.is_paper_method(&m.method);
        let main: Vec<&MethodCurves> = self.methods.iter().filter(is_paper).collect();
        let shown = if main.is_empty() {
            self.methods.iter().collect()
        } else {
            main
        };
        let ablations: Vec<&MethodCurves> = self
            .methods
            .iter()
            .filter(|m| m.method == "ea-madm" || !planned.is_paper_method(&m.method))
            .collect();
        let is_robot = self.is_robot;
        // optimum far below 2^52
        let reference = self.optimum.flatten().map(|optimum| {
            let source = if is_robot { "planner" } else { "BFS" };
            (format!("{source} optimum = {optimum}"), optimum as f64)
        });
        let title = &planned.title;
        let smoothing =
            format!("(mean over seeds, 95% CI; {FIGURE_SMOOTHING}-episode moving average)");
        let of = |methods: &[&MethodCurves], series: fn(&MethodCurves) -> &Series| {
            methods.iter().map(|&m| series(m).clone()).collect()
        };
        let mut figures = vec![
            (
                "steps.svg".to_owned(),
                chart(
                    format!("{title}: steps per episode {smoothing}"),
                    "steps",
                    of(&shown, |m| &m.steps),
                    reference.clone(),
                )?,
            ),
            (
                "return.svg".to_owned(),
                chart(
                    format!("{title}: return per episode {smoothing}"),
                    "return",
                    of(&shown, |m| &m.task_return),
                    None,
                )?,
            ),
        ];
        let has_ea_madm = ablations.iter().any(|m| m.method == "ea-madm");
        if ablations.len() > 1 || (ablations.len() == 1 && !has_ea_madm) {
            figures.push((
                "ablations-steps.svg".to_owned(),
                chart(
                    format!("{title}: EA-MADM and its ablations, steps per episode {smoothing}"),
                    "steps",
                    of(&ablations, |m| &m.steps),
                    reference,
                )?,
            ));
        }
        if is_robot {
            // The robot's first figure is success per episode: with no success, more steps
            // only means surviving longer.
            let success = shown.iter().filter_map(|m| m.success.clone()).collect();
            figures.insert(
                0,
                (
                    "success.svg".to_owned(),
                    chart(
                        format!("{title}: success per episode"),
                        "share of seeds that reached the target",
                        success,
                        None,
                    )?,
                ),
            );
            // Fig. 13–15 plot "episodes that are to reach the target": x is the
            // reaching-episode index, each seed contributing its own reaching episodes in
            // order.
            for (index, reaching) in REACHING_CHARTS.iter().enumerate() {
                let series = shown
                    .iter()
                    .filter_map(|m| Some((m.method.as_str(), m.reaching.get(index)?.clone())))
                    .collect();
                figures.push((
                    reaching.file.to_owned(),
                    reaching_chart(
                        &format!("{title}: {} over reaching episodes", reaching.what),
                        reaching.y_label,
                        series,
                    )?,
                ));
            }
        }
        if let Some(svg) = trajectory_figure(planned, &shown) {
            figures.push(("trajectories.svg".to_owned(), svg));
        }
        Ok(figures)
    }
}

/// A chart of one per-episode quantity, one series per method.
fn chart(
    title: String,
    y_label: &str,
    series: Vec<Series>,
    reference: Option<(String, f64)>,
) -> Result<String, FigureError> {
    let mut chart = LineChart::new(title, "episode", y_label).with_smoothing(FIGURE_SMOOTHING);
    for series in series {
        chart = chart.with_series(series);
    }
    if let Some((label, y)) = reference {
        chart = chart.with_reference_line(label, y);
    }
    chart.render_svg()
}

/// A chart of one robot metric over *reaching* episodes (x = the n-th episode of a seed that
/// reached the target; seeds with fewer reaching episodes drop out to the right), from each
/// method's label and series. Methods that never reach are not drawn; the title names them.
fn reaching_chart(
    title: &str,
    y_label: &str,
    series: Vec<(&str, Series)>,
) -> Result<String, FigureError> {
    let mut never = Vec::new();
    let mut chart =
        LineChart::new(String::new(), "reaching episode", y_label).with_smoothing(FIGURE_SMOOTHING);
    let mut drawn = 0;
    for (method, mut reaching) in series {
        let seeds = reaching.seeds();
        if seeds == 0 {
            never.push(method_title(method));
        } else {
            reaching.name = format!(
                "{} ({seeds} seed{})",
                method_title(method),
                if seeds == 1 { "" } else { "s" }
            );
            chart = chart.with_series(reaching);
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
        let mut nothing = Series::new("no method reached the target", FIGURE_SMOOTHING);
        nothing.push(&[0.0]);
        chart = chart.with_series(nothing);
    }
    chart.render_svg()
}

/// The greedy evaluation path of each method's first seed, drawn on the maze or the robot's
/// arena (the analogue of Fig. 6 and 9).
fn trajectory_figure(planned: &PlannedExperiment, methods: &[&MethodCurves]) -> Option<String> {
    let task = planned.experiment.task();
    if let Some(maze) = task.maze() {
        let paths: Vec<(String, Vec<Pos>)> = methods
            .iter()
            .map(|m| {
                let path = m
                    .first
                    .trajectory
                    .states
                    .iter()
                    .filter_map(|&s| maze.pos_of(s))
                    .collect();
                (
                    format!(
                        "{} (seed {}, greedy{})",
                        method_title(&m.method),
                        m.first.seed,
                        if m.first.reached {
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
    let paths: Vec<(String, Vec<Point2<f64>>)> = methods
        .iter()
        .map(|m| {
            let points = m
                .first
                .trajectory
                .positions
                .iter()
                .map(|&[x, y]| Point2::new(x, y))
                .collect();
            let outcome = if m.first.reached {
                "reached the target"
            } else {
                "target not reached"
            };
            (
                format!(
                    "{} (seed {}, greedy, {} steps, {outcome})",
                    method_title(&m.method),
                    m.first.seed,
                    m.first.steps
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

#[cfg(test)]
mod tests {
    use eamadm::{Experiment, ExperimentConfig};

    use super::*;

    /// A tiny maze experiment with a paper method (softmax) and a control (ε-greedy), `seeds`
    /// seeds of 12 episodes each.
    fn planned(seeds: u64) -> PlannedExperiment {
        let config = ExperimentConfig::from_toml_str(&format!(
            r#"
name = "tiny"
episodes = 12
seeds = {seeds}
[task]
kind = "maze_text"
rewards = "task1"
map = "S...\n.#..\n...T\n"
[learner]
alpha = 0.1
gamma = 0.95
[[methods]]
label = "softmax"
kind = "softmax"
temperature = {{ constant = 0.1 }}
[[methods]]
label = "epsilon-greedy"
kind = "epsilon_greedy"
role = "control"
epsilon = {{ constant = 0.1 }}
"#
        ))
        .unwrap();
        PlannedExperiment {
            name: "tiny".to_owned(),
            title: "Tiny".to_owned(),
            experiment: Experiment::new(config).unwrap(),
        }
    }

    fn collect<'a>(planned: &'a PlannedExperiment, records: &[RunRecord]) -> ExperimentFigures<'a> {
        let mut figures = ExperimentFigures::new(planned);
        for record in records {
            figures.push(record);
        }
        figures
    }

    /// The memory law of the figures: what the collector holds is a function of the methods and
    /// the episodes (and each method's first path), not of the number of seeds.
    #[test]
    fn the_collector_holds_the_same_for_two_seeds_and_for_twelve() {
        let few = planned(2);
        let many = planned(12);
        let few_runs = few.experiment.run_all().unwrap();
        let many_runs = many.experiment.run_all().unwrap();
        let few_figures = collect(&few, &few_runs);
        let many_figures = collect(&many, &many_runs);
        assert!(few_figures.held_size() > 0);
        assert_eq!(few_figures.held_size(), many_figures.held_size());
        let files: Vec<String> = many_figures
            .render()
            .unwrap()
            .into_iter()
            .map(|(file, _)| file)
            .collect();
        assert_eq!(
            files,
            [
                "steps.svg",
                "return.svg",
                "ablations-steps.svg",
                "trajectories.svg"
            ]
        );
    }

    /// A non-finite value fails the figure that draws it, naming the series, the seed among
    /// the method's runs and the episode; a method a figure does not draw cannot fail it.
    #[test]
    fn a_non_finite_value_fails_only_the_figures_that_draw_it() {
        let planned = planned(3);
        let mut runs = planned.experiment.run_all().unwrap();
        // Runs come method by method: softmax seeds 0..3, then ε-greedy seeds 0..3.
        assert_eq!(runs[4].method, "epsilon-greedy");
        runs[4].episodes[5].task_return = f64::NAN;
        // ε-greedy is a control: the return figure draws the paper's softmax only.
        assert!(collect(&planned, &runs).render().is_ok());

        runs[1].episodes[7].task_return = f64::INFINITY;
        let error = collect(&planned, &runs).render().unwrap_err();
        assert_eq!(
            error.to_string(),
            "series \"softmax\": seed 1, episode 7: value inf is not finite"
        );
    }
}
