//! Which figures an experiment gets, and their captions: per experiment the SVG charts and
//! the greedy paths, collected run by run ([`ExperimentFigures`]: each seed's smoothed curves,
//! no run record) and drawn at the end. Every method keeps its look ([`crate::theme`]) in every
//! figure; no figure has more than [`MAX_SERIES`] series (the ablations and the controls get
//! figures of their own, with EA-MADM in each). Writing the files is the caller's: `xtask`
//! writes them into the output folder, the Python package where it is asked to.

use std::fmt::Write as _;

use eamadm_eval::facts::{ExperimentFacts, Figures, NotDrawn, PaperFigures};
use eamadm_eval::paper_claims::method_title;
use eamadm_eval::reaching::{ReachingMetric, reaching_curve};
use eamadm_eval::scores::{FINAL_WINDOW, REACHING_EPISODES, RunOutcome};
use eamadm_eval::{EpisodeRecord, Role, RunRecord, TrajectoryRecord};
use mazes::{Pos, SvgOptions, SvgTrajectory};

use crate::chart::{
    FigureError, LineChart, Series, escape, px, stroke_attributes, wrap, wrapped_text,
};
use crate::theme::{Dash, MethodStyle, assign, method_style};
use std::collections::BTreeMap;

/// Episodes of the trailing moving average drawn in the per-episode figures.
pub const FIGURE_SMOOTHING: usize = 5;

/// Where the greedy paths of an experiment are drawn.
#[derive(Debug, Clone, PartialEq)]
pub enum Arena {
    /// A grid maze: each path is a panel of the maze with its tiles shaded by visits.
    Maze(mazes::Maze),
    /// The robot's scenario: every path on one drawing of the arena.
    Robot(Box<wmr_model::Scenario>),
}

impl Arena {
    /// The arena of a task: its maze, or its robot scenario (`None` for neither).
    #[must_use]
    pub fn from_parts(
        maze: Option<&mazes::Maze>,
        scenario: Option<&wmr_model::Scenario>,
    ) -> Option<Self> {
        maze.map(|maze| Self::Maze(maze.clone()))
            .or_else(|| scenario.map(|scenario| Self::Robot(Box::new(scenario.clone()))))
    }
}

/// What the figures of one experiment need beside its runs: its folder name and title, the
/// paper's figures it is the analogue of, its methods with their roles (config order), and the
/// arena its paths are drawn on.
#[derive(Debug, Clone, PartialEq)]
pub struct FigurePlan {
    /// The folder the figures go under (the experiment's name).
    pub name: String,
    /// The title the figures' titles start with.
    pub title: String,
    /// The paper's figures these are the analogues of.
    pub analogues: PaperFigures,
    /// Each method's label and role, in the config's order.
    pub methods: Vec<(String, Role)>,
    /// Where the greedy paths are drawn (no path figure without).
    pub arena: Option<Arena>,
    /// The method drawn on top of every figure and in each ablations' and controls' figure:
    /// the paper's EA-MADM (role `paper`, kind `ea_madm`), if the experiment has it.
    pub on_top: Option<String>,
}

impl FigurePlan {
    /// The plan of the experiment `facts` states (its name, title, methods with their roles
    /// and the paper's figures), drawing its paths on `arena`.
    #[must_use]
    pub fn new(facts: &ExperimentFacts, arena: Option<Arena>) -> Self {
        Self {
            name: facts.name.clone(),
            title: facts.title.clone(),
            analogues: facts.paper_figures.clone(),
            methods: facts
                .methods
                .iter()
                .map(|m| (m.label.clone(), m.role))
                .collect(),
            arena,
            on_top: facts
                .methods
                .iter()
                .find(|m| m.role == Role::Paper && m.kind == "ea_madm")
                .map(|m| m.label.clone()),
        }
    }

    /// The role of the method labelled `label` (a method the plan does not name is taken as
    /// one of the paper's).
    fn role(&self, label: &str) -> Role {
        self.methods
            .iter()
            .find(|(l, _)| l == label)
            .map_or(Role::Paper, |(_, role)| *role)
    }

    /// Whether `label` is one of the paper's methods in this experiment (`role = paper`), as
    /// opposed to an ablation or a control.
    fn is_paper_method(&self, label: &str) -> bool {
        self.methods
            .iter()
            .any(|(l, role)| l == label && *role == Role::Paper)
    }

    fn is_robot(&self) -> bool {
        matches!(self.arena, Some(Arena::Robot(_)))
    }
}

/// The figures of an experiment as drawn: each file's name and SVG text (in the order written)
/// and what the report says of them ([`Figures`]: file names, captions, those not drawn).
#[derive(Debug, Clone, PartialEq)]
pub struct Drawing {
    /// `(file name, SVG text)` under the experiment's folder.
    pub files: Vec<(String, String)>,
    /// The file names, the key figures' captions and the figures left out.
    pub figures: Figures,
}

/// One of the robot's charts over reaching episodes (Fig. 13–15).
struct ReachingChart {
    /// The SVG file.
    file: &'static str,
    /// What is drawn, for the title.
    what: &'static str,
    /// The y axis label, with its unit.
    y_label: &'static str,
    /// The paper's figure.
    figure: &'static str,
    /// The metric's lowest value, if bounded.
    lowest: Option<f64>,
    /// The metric of a reaching episode.
    metric: ReachingMetric,
}

/// The robot's charts over reaching episodes, in the order they are written.
const REACHING_CHARTS: [ReachingChart; 3] = [
    ReachingChart {
        file: "average-reward.svg",
        what: "average reward",
        y_label: "average reward (return per second)",
        figure: "Fig. 13",
        lowest: None,
        metric: ReachingMetric::AverageReward,
    },
    ReachingChart {
        file: "reaching-time.svg",
        what: "reaching time",
        y_label: "time to reach the target (s)",
        figure: "Fig. 14",
        lowest: Some(0.0),
        metric: ReachingMetric::ReachingTime,
    },
    ReachingChart {
        file: "retention-time.svg",
        what: "retention time",
        y_label: "retention time in front of obstacles (s)",
        figure: "Fig. 15",
        lowest: Some(0.0),
        metric: ReachingMetric::RetentionTime,
    },
];

/// The figures drawn (file name and SVG text) and those left out.
type Rendered = (Vec<(String, String)>, Vec<NotDrawn>);

/// The most series in one figure: more cannot be told apart.
pub const MAX_SERIES: usize = 8;

/// The figures of one experiment, collected run by run in job order and drawn at the end:
/// per method each seed's smoothed curve of what the charts draw ([`Series`]: one number per
/// seed and episode, what the IQM and its bootstrap band need), and the greedy evaluation
/// path of its first run. No run record is held.
pub struct ExperimentFigures {
    plan: FigurePlan,
    /// The first run's optimum (the charts' reference line); `None` before the first run.
    optimum: Option<Option<u64>>,
    /// The step cap: the most steps of any truncated episode seen.
    step_cap: Option<u64>,
    /// One per method, in the order methods first came.
    methods: Vec<MethodCurves>,
}

/// What the figures draw of one method's runs.
struct MethodCurves {
    /// The method's label.
    method: String,
    /// Its role in the experiment.
    role: Role,
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
    fn new(record: &RunRecord, role: Role, is_robot: bool, on_top: bool) -> Self {
        let title = method_title(&record.method);
        let style = method_style(&record.method, role);
        let series = || {
            let mut series = Series::new(
                record.method.clone(),
                title.clone(),
                style,
                FIGURE_SMOOTHING,
            );
            series.on_top = on_top;
            series
        };
        // The per-seed story is the story for the paper's methods: collapses and seeds stuck
        // at the step cap, in steps and in return; every figure over episodes has the strip of
        // collapsed seeds besides.
        let mut steps = series();
        steps.per_seed = role == Role::Paper;
        let mut task_return = series();
        task_return.per_seed = role == Role::Paper;
        let success = is_robot.then(|| {
            let mut success = series();
            success.share = true;
            success
        });
        Self {
            method: record.method.clone(),
            role,
            steps,
            task_return,
            success,
            reaching: if is_robot {
                // Few seeds reach: each one's curve is drawn.
                REACHING_CHARTS
                    .iter()
                    .map(|_| {
                        let mut reaching = series();
                        reaching.per_seed = true;
                        reaching
                    })
                    .collect()
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
        let at_cap: Vec<bool> = record.episodes.iter().map(|e| e.truncated).collect();
        self.steps.count_at_cap(&at_cap);
        self.task_return.push(&curve(&|e| e.task_return));
        let (outcome, episode) =
            RunOutcome::of(record.evaluation.reached, &record.episodes, FINAL_WINDOW);
        let collapse = (outcome == RunOutcome::Collapsed)
            .then_some(episode)
            .flatten();
        self.steps.note_collapse(collapse);
        self.task_return.note_collapse(collapse);
        if let Some(success) = &mut self.success {
            success.push(&curve(&|e| f64::from(u8::from(e.reached))));
            success.note_collapse(collapse);
        }
        for (series, chart) in self.reaching.iter_mut().zip(&REACHING_CHARTS) {
            // The first reaching episodes in order, as C4's scores take them.
            let reaching = reaching_curve(record, chart.metric);
            if !reaching.is_empty() {
                series.push(&reaching);
            }
        }
    }
}

/// The paper's figure a figure of `kind` (`steps`, `return` or `trajectories`) is the
/// analogue of, from `analogues`.
fn paper_figure<'a>(analogues: &'a PaperFigures, kind: &str) -> Option<&'a str> {
    match kind {
        "steps" => analogues.steps.as_deref(),
        "return" => analogues.task_return.as_deref(),
        "trajectories" => analogues.trajectories.as_deref(),
        _ => None,
    }
}

/// `methods` split into figures of at most [`MAX_SERIES`] with EA-MADM (when there is one)
/// in each, as evenly as possible.
fn chunks<'m>(
    ea_madm: Option<&'m MethodCurves>,
    methods: &[&'m MethodCurves],
) -> Vec<Vec<&'m MethodCurves>> {
    if methods.is_empty() {
        return Vec::new();
    }
    let room = MAX_SERIES - usize::from(ea_madm.is_some());
    let figures = methods.len().div_ceil(room);
    let size = methods.len().div_ceil(figures);
    methods
        .chunks(size)
        .map(|chunk| ea_madm.into_iter().chain(chunk.iter().copied()).collect())
        .collect()
}

/// `name.svg`, or `name-k.svg` when there are several.
fn numbered(name: &str, index: usize, count: usize) -> String {
    if count == 1 {
        format!("{name}.svg")
    } else {
        format!("{name}-{}.svg", index + 1)
    }
}

impl ExperimentFigures {
    /// A collector for the figures of `plan`, without runs.
    #[must_use]
    pub fn new(plan: FigurePlan) -> Self {
        Self {
            plan,
            optimum: None,
            step_cap: None,
            methods: Vec::new(),
        }
    }

    /// Adds one run (runs come in job order: method by method, seed by seed).
    pub fn push(&mut self, record: &RunRecord) {
        self.optimum.get_or_insert(record.optimum_steps);
        let truncated = record
            .episodes
            .iter()
            .filter(|e| e.truncated)
            .map(|e| e.steps);
        self.step_cap = self.step_cap.into_iter().chain(truncated).max();
        let index = match self.methods.iter().position(|m| m.method == record.method) {
            Some(index) => index,
            None => {
                let role = self.plan.role(&record.method);
                let on_top = self.plan.on_top.as_deref() == Some(record.method.as_str());
                self.methods.push(MethodCurves::new(
                    record,
                    role,
                    self.plan.is_robot(),
                    on_top,
                ));
                self.methods.len() - 1
            }
        };
        self.methods[index].push(record);
    }

    /// Numbers held over every series and first run: one per seed and episode of each curve
    /// drawn, and the first run's path per method; no run record.
    #[cfg(test)]
    pub fn held_size(&self) -> usize {
        self.methods
            .iter()
            .map(|m| {
                let series = [&m.steps, &m.task_return]
                    .into_iter()
                    .chain(&m.success)
                    .chain(&m.reaching);
                series.map(Series::held_numbers).sum::<usize>()
                    + m.first.trajectory.states.len()
                    + m.first.trajectory.positions.len()
            })
            .sum()
    }

    /// The experiment's figures ([`Drawing`]): each file's SVG text, and the file names, the
    /// key figures' captions and the figures not drawn, which the report shows.
    ///
    /// # Errors
    /// [`FigureError`] naming the series, seed and episode of a value a figure cannot draw.
    pub fn draw(self) -> Result<Drawing, FigureError> {
        let captions = self
            .captions()
            .into_iter()
            .map(|(file, caption)| (file.to_owned(), caption))
            .collect();
        let mut not_drawn = self.not_drawn();
        let (files, nothing) = self.render()?;
        not_drawn.extend(nothing);
        Ok(Drawing {
            figures: Figures {
                files: files.iter().map(|(file, _)| file.clone()).collect(),
                captions,
                not_drawn,
            },
            files,
        })
    }

    /// The paper's methods the figures draw (at most [`MAX_SERIES`]; the first methods when
    /// the plan has none of the paper's).
    fn shown(&self) -> Vec<&MethodCurves> {
        let paper: Vec<&MethodCurves> = self
            .methods
            .iter()
            .filter(|m| self.plan.is_paper_method(&m.method))
            .collect();
        if paper.is_empty() {
            self.methods.iter().take(MAX_SERIES).collect()
        } else {
            paper.into_iter().take(MAX_SERIES).collect()
        }
    }

    /// The robot's C4 figures (average reward, reaching time, retention time) that would be
    /// empty axes, because none of the methods they draw has a reaching episode in any seed:
    /// [`Self::draw`] draws no SVG for them and the report says why
    /// ([`crate::report::not_drawn_sentence`]).
    pub fn not_drawn(&self) -> Vec<NotDrawn> {
        if !self.plan.is_robot() || self.methods.is_empty() {
            return Vec::new();
        }
        let shown = self.shown();
        REACHING_CHARTS
            .iter()
            .enumerate()
            .filter(|(index, _)| {
                shown
                    .iter()
                    .all(|m| m.reaching.get(*index).is_none_or(|s| s.seeds() == 0))
            })
            .map(|(_, chart)| NotDrawn {
                file: chart.file.to_owned(),
                what: format!("{} over reaching episodes ({})", chart.what, chart.figure),
                why: format!(
                    "none of {} reached the target in any training episode of any seed",
                    shown
                        .iter()
                        .map(|m| method_title(&m.method))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            })
            .collect()
    }

    /// One-line captions of the key figures, computed from what they draw: each paper
    /// method's value at the last episode and the seeds at the step cap there.
    fn captions(&self) -> Vec<(&'static str, String)> {
        let plan = &self.plan;
        let paper: Vec<&MethodCurves> = self
            .methods
            .iter()
            .filter(|m| plan.is_paper_method(&m.method))
            .take(MAX_SERIES)
            .collect();
        let ending = |series: fn(&MethodCurves) -> Option<&Series>, decimals: usize| {
            paper
                .iter()
                .filter_map(|m| {
                    let (value, at_cap) = series(m)?.final_iqm()?;
                    let cap = if at_cap > 0 {
                        format!(
                            " ({at_cap} of {} seeds at the step cap)",
                            series(m)?.seeds()
                        )
                    } else {
                        String::new()
                    };
                    Some(format!(
                        "{} {value:.decimals$}{cap}",
                        method_title(&m.method)
                    ))
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        let figure = |kind: &str| {
            paper_figure(&plan.analogues, kind)
                .map_or_else(String::new, |f| format!(" (analogue of {f})"))
        };
        let optimum = self
            .optimum
            .flatten()
            .map_or_else(String::new, |o| format!("; optimum {o}"));
        let mut captions = vec![
            (
                "steps.svg",
                format!(
                    "Steps per episode{}, IQM over seeds of the {FIGURE_SMOOTHING}-episode moving average at the last episode: {}{optimum}.",
                    figure("steps"),
                    ending(|m| Some(&m.steps), 0)
                ),
            ),
            (
                "return.svg",
                format!(
                    "Return per episode{}, IQM over seeds of the {FIGURE_SMOOTHING}-episode moving average at the last episode: {}.",
                    figure("return"),
                    ending(|m| Some(&m.task_return), 0)
                ),
            ),
        ];
        if plan.is_robot() {
            captions.insert(
                0,
                (
                    "success.svg",
                    format!(
                        "Share of episodes that reached the target, pooled over the seeds and \
                         their last {FIGURE_SMOOTHING} episodes, at the last episode: {}.",
                        paper
                            .iter()
                            .filter_map(|m| {
                                let (share, successes, trials) =
                                    m.success.as_ref()?.final_share()?;
                                Some(format!(
                                    "{} {share:.2} ({successes} of {trials})",
                                    method_title(&m.method)
                                ))
                            })
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ),
            );
        }
        let unreached = paper.iter().filter(|m| !m.first.reached).count();
        captions.push((
            "trajectories.svg",
            format!(
                "Greedy paths of each method's first seed{}: {} of {} reach the target.",
                figure("trajectories"),
                paper.len() - unreached,
                paper.len()
            ),
        ));
        captions
    }

    /// The figures: file name and SVG text (none without runs), and the charts left out
    /// because every line of them would be 0.
    fn render(self) -> Result<Rendered, FigureError> {
        let plan = &self.plan;
        if self.methods.is_empty() {
            return Ok((Vec::new(), Vec::new()));
        }
        let of_role = |role: Role| -> Vec<&MethodCurves> {
            self.methods.iter().filter(|m| m.role == role).collect()
        };
        let shown = self.shown();
        let ea_madm = self
            .methods
            .iter()
            .find(|m| plan.on_top.as_deref() == Some(m.method.as_str()));
        let ablations = chunks(ea_madm, &of_role(Role::Ablation));
        let controls = chunks(ea_madm, &of_role(Role::Control));
        // One colour per method in each figure, a method's colour the same in all of them.
        let groups: Vec<Vec<(&str, Role)>> = std::iter::once(&shown)
            .chain(&ablations)
            .chain(&controls)
            .map(|group| group.iter().map(|m| (m.method.as_str(), m.role)).collect())
            .collect();
        let looks = assign(&groups);
        let styled = |series: &Series| {
            let mut series = series.clone();
            if let Some(look) = looks.get(&series.method) {
                series.style = *look;
            }
            series
        };
        let is_robot = plan.is_robot();
        // optimum far below 2^52
        let reference = self.optimum.flatten().map(|optimum| {
            let source = if is_robot { "planner" } else { "BFS" };
            (
                format!("{source} optimum = {optimum} steps"),
                optimum as f64,
            )
        });
        let title = &plan.title;
        let cap_text = self.step_cap.map_or_else(
            || "seeds whose episode hit the step cap".to_owned(),
            |cap| format!("seeds whose episode hit the step cap ({cap} steps)"),
        );
        let steps_range = (Some(0.0), self.step_cap.map(|cap| cap as f64));
        let analogue = |kind: &str| {
            paper_figure(&plan.analogues, kind)
                .map_or_else(String::new, |f| format!("Analogue of the paper's {f}. "))
        };
        let longest = self
            .methods
            .iter()
            .map(|m| m.task_return.curves_len())
            .max()
            .unwrap_or(0);
        // The end of training, zoomed: the final fifth of the episodes, at least 10.
        let zoom = (longest / 5).max(10);
        let steps_chart = |methods: &[&MethodCurves], subtitle: String| {
            let mut chart = LineChart::new(
                format!("{title}: steps per episode"),
                "episode",
                "steps per episode",
            )
            .with_subtitle(subtitle)
            .with_smoothing(FIGURE_SMOOTHING)
            .with_metric_range(steps_range.0, steps_range.1)
            .with_cap_panel(cap_text.clone())
            .with_collapse_strip()
            .with_final_zoom(zoom);
            for m in methods {
                chart = chart.with_series(styled(&m.steps));
            }
            if let Some((label, y)) = &reference {
                chart = chart.with_reference_line(label.clone(), *y);
            }
            chart
        };
        let mut figures: Vec<(String, LineChart)> = vec![(
            "steps.svg".to_owned(),
            steps_chart(
                &shown,
                format!(
                    "{}EA-MADM and the paper's competitors; thin lines show every seed and the \
                     strip under the plot the seeds that collapsed, so collapses and seeds at \
                     the step cap stay visible; the right panel zooms on the end of training.",
                    analogue("steps")
                ),
            ),
        )];
        let mut return_chart = LineChart::new(
            format!("{title}: return per episode"),
            "episode",
            "return per episode (task reward)",
        )
        .with_subtitle(format!(
            "{}EA-MADM and the paper's competitors; thin lines show every seed and the strip \
             under the plot the seeds that collapsed; the right panel zooms on the end of \
             training.",
            analogue("return")
        ))
        .with_smoothing(FIGURE_SMOOTHING)
        .with_collapse_strip()
        .with_final_zoom(zoom);
        for m in &shown {
            return_chart = return_chart.with_series(styled(&m.task_return));
        }
        figures.push(("return.svg".to_owned(), return_chart));

        for (groups, name, what) in [
            (&ablations, "ablations-steps", "EA-MADM and its ablations"),
            (
                &controls,
                "controls-steps",
                "EA-MADM and controls the paper does not run",
            ),
        ] {
            let count = groups.len();
            for (index, group) in groups.iter().enumerate() {
                let part = if count > 1 {
                    format!(", part {} of {count}", index + 1)
                } else {
                    String::new()
                };
                let dashes = dash_words(
                    group
                        .iter()
                        .filter(|m| m.role != Role::Paper)
                        .map(|m| looks.get(&m.method).map_or(Dash::Solid, |look| look.dash)),
                );
                figures.push((
                    numbered(name, index, count),
                    steps_chart(group, format!("{what} ({dashes}){part}.")),
                ));
            }
        }
        let mut not_drawn = Vec::new();
        if is_robot {
            // The robot's first figure is success per episode: with no success, more steps
            // only means surviving longer.
            let mut chart = LineChart::new(
                format!("{title}: success per episode"),
                "episode",
                "share of episodes that reached the target",
            )
            .with_subtitle(
                "The share of episodes that reached the target, pooled over the seeds; the strip \
                 under the plot marks the seeds that collapsed.",
            )
            .with_smoothing(FIGURE_SMOOTHING)
            .with_metric_range(Some(0.0), Some(1.0))
            .with_collapse_strip();
            for m in &shown {
                if let Some(success) = &m.success {
                    chart = chart.with_series(styled(success));
                }
            }
            figures.insert(0, ("success.svg".to_owned(), chart));
        }
        // A chart whose every line is 0 shows nothing: a sentence says so instead.
        let mut files = Vec::new();
        let mut drawn = Vec::new();
        for (file, chart) in &figures {
            if chart.shows_nothing() {
                not_drawn.push(NotDrawn {
                    file: file.clone(),
                    what: format!("{} ({})", chart.title, chart.y_label),
                    why: format!(
                        "it is 0 in every episode of every seed of {}",
                        chart
                            .series
                            .iter()
                            .map(|s| s.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                });
            } else {
                drawn.push((file.clone(), chart));
            }
        }
        // Rendered together: the charts' series at an episode share its band resamples.
        let charts: Vec<&LineChart> = drawn.iter().map(|(_, chart)| *chart).collect();
        let svgs = LineChart::render_svgs(&charts)?;
        files.extend(drawn.into_iter().map(|(file, _)| file).zip(svgs));
        if is_robot {
            // Fig. 13–15 plot "episodes that are to reach the target": x is the
            // reaching-episode index, each seed contributing its own first reaching episodes
            // in order. A chart none of whose methods reaches is not drawn (`not_drawn`).
            for (index, reaching) in REACHING_CHARTS.iter().enumerate() {
                let series = shown
                    .iter()
                    .filter_map(|m| Some((m.method.as_str(), styled(m.reaching.get(index)?))))
                    .collect();
                if let Some(svg) = reaching_chart(title, reaching, series)? {
                    files.push((reaching.file.to_owned(), svg));
                }
            }
        }
        if let Some(svg) = trajectory_figure(plan, &shown, &looks, &analogue("trajectories")) {
            files.push(("trajectories.svg".to_owned(), svg));
        }
        Ok((files, not_drawn))
    }
}

/// The dashes of a group's methods in words, in first-appearance order: `dashed`, `dotted,
/// dash-dotted`.
fn dash_words(dashes: impl Iterator<Item = Dash>) -> String {
    let mut words: Vec<&str> = Vec::new();
    for dash in dashes {
        let word = match dash {
            Dash::Solid => "solid",
            Dash::Dashed => "dashed",
            Dash::Dotted => "dotted",
            Dash::DashDot => "dash-dotted",
            Dash::DashDotDot => "dash-dot-dotted",
            Dash::LongDash => "long-dashed",
            Dash::LongDashDot => "long-dash-dotted",
            Dash::LongDashDotDot => "long-dash-dot-dotted",
        };
        if !words.contains(&word) {
            words.push(word);
        }
    }
    words.join(", ")
}

/// A chart of one robot metric over the first [`REACHING_EPISODES`] *reaching* episodes
/// (x = the n-th episode of a seed that reached the target, the axis ends at
/// [`REACHING_EPISODES`] as C4's scores do; seeds with fewer reaching episodes drop out to the
/// right, and the panel under the plot counts the seeds behind each point), from each
/// method's label and series. Methods that never reach are not drawn; the subtitle names them.
/// `None` when no method reaches: no empty axes are drawn.
fn reaching_chart(
    title: &str,
    reaching: &ReachingChart,
    series: Vec<(&str, Series)>,
) -> Result<Option<String>, FigureError> {
    let mut never = Vec::new();
    let mut chart = LineChart::new(
        format!("{title}: {} over reaching episodes", reaching.what),
        "reaching episode (the n-th episode of a seed that reached the target)",
        reaching.y_label,
    )
    .with_smoothing(FIGURE_SMOOTHING)
    .with_metric_range(reaching.lowest, None)
    .with_x_end(REACHING_EPISODES)
    .with_seed_panel("seeds behind each point: those with at least n reaching episodes");
    for (method, mut series) in series {
        let seeds = series.seeds();
        if seeds == 0 {
            never.push(method_title(method));
        } else {
            series.name = format!(
                "{} ({seeds} seed{} reached)",
                method_title(method),
                if seeds == 1 { "" } else { "s" }
            );
            chart = chart.with_series(series);
        }
    }
    let never_text = if never.is_empty() {
        String::new()
    } else {
        format!(" Never reached the target: {}.", never.join(", "))
    };
    chart.subtitle = format!(
        "Analogue of the paper's {}: each seed's first {REACHING_EPISODES} reaching episodes, \
         over the seeds that reached the target at least n times.{never_text}",
        reaching.figure
    );
    if chart.series.is_empty() {
        return Ok(None);
    }
    chart.render_svg().map(Some)
}

/// The greedy evaluation path of each method's first seed (the analogue of Fig. 6 and 9, and
/// of the robot's paths): on a maze one panel per method with the tiles it visits more than
/// once shaded by their number of visits, so a looping policy shows as a dark patch with its
/// count; on the robot's arena every path in its method's colour.
fn trajectory_figure(
    plan: &FigurePlan,
    methods: &[&MethodCurves],
    looks: &BTreeMap<String, MethodStyle>,
    analogue: &str,
) -> Option<String> {
    let title = format!("{}: greedy paths after training", plan.title);
    let look = |m: &MethodCurves| {
        looks
            .get(&m.method)
            .copied()
            .unwrap_or_else(|| method_style(&m.method, m.role))
    };
    Some(match plan.arena.as_ref()? {
        Arena::Maze(maze) => maze_trajectories(maze, methods, &look, &title, analogue),
        Arena::Robot(scenario) => {
            robot_trajectories(scenario, methods, &look, plan, &title, analogue)
        }
    })
}

/// Side of a maze tile in the trajectory panels, in pixels.
const TILE_PX: u32 = 12;
/// Margin `mazes::render_svg` leaves around the grid without a title: `max(tile, 12)`.
const MAZE_MARGIN: f64 = 12.0;

/// One method's maze panel: its caption, its path and its visits per tile.
type PathPanel = (String, Vec<Pos>, Vec<(Pos, u64)>);

/// How a path visits tiles: per tile its visits, in first-visit order.
fn visits(path: &[Pos]) -> Vec<(Pos, u64)> {
    let mut counts: Vec<(Pos, u64)> = Vec::new();
    for &pos in path {
        match counts.iter_mut().find(|(p, _)| *p == pos) {
            Some((_, n)) => *n += 1,
            None => counts.push((pos, 1)),
        }
    }
    counts
}

/// One line about a greedy path: steps, distinct tiles, the most-visited tile.
fn path_summary(first: &FirstRun, visits: &[(Pos, u64)]) -> String {
    let most = visits.iter().map(|(_, n)| *n).max().unwrap_or(0);
    let outcome = if first.reached {
        "reached the target"
    } else {
        "target not reached"
    };
    if most > 2 {
        format!(
            "seed {}: {} steps over {} tile{}, loops (a tile visited {most}×); {outcome}",
            first.seed,
            first.steps,
            visits.len(),
            if visits.len() == 1 { "" } else { "s" }
        )
    } else {
        format!("seed {}: {} steps; {outcome}", first.seed, first.steps)
    }
}

fn maze_trajectories(
    maze: &mazes::Maze,
    methods: &[&MethodCurves],
    look: &dyn Fn(&MethodCurves) -> MethodStyle,
    title: &str,
    analogue: &str,
) -> String {
    let panel_w = f64::from(TILE_PX) * maze.width() as f64 + 2.0 * MAZE_MARGIN;
    let panel_h = f64::from(TILE_PX) * maze.height() as f64 + 2.0 * MAZE_MARGIN + 18.0;
    let columns = methods.len().clamp(1, 2);
    let rows = methods.len().div_ceil(columns).max(1);
    let gap = 16.0;
    let width = (PAD + columns as f64 * (panel_w + gap)).max(600.0).ceil();
    let mut body = String::new();
    let y = heading(
        &mut body,
        width,
        title,
        &format!(
            "{analogue}Greedy evaluation of each method's first seed after training; a tile \
             visited more than once is shaded by its visits (darker: more), so a loop shows."
        ),
    );
    let top = y + 10.0;
    let summaries: Vec<PathPanel> = methods
        .iter()
        .map(|m| {
            let path: Vec<Pos> = m
                .first
                .trajectory
                .states
                .iter()
                .filter_map(|&s| maze.pos_of(s))
                .collect();
            let counts = visits(&path);
            let caption = format!(
                "{}, {}",
                method_title(&m.method),
                path_summary(&m.first, &counts)
            );
            (caption, path, counts)
        })
        .collect();
    // Room for the longest caption above every panel, each as wide as its column.
    let caption_w = panel_w.max((width - PAD) / columns as f64 - gap);
    let lines = summaries
        .iter()
        .map(|(caption, ..)| wrap(caption, caption_w, 13.0).len())
        .max()
        .unwrap_or(1);
    let caption_lines = lines as f64 * 13.0 * 1.25 + 8.0;
    for (index, (m, (caption, path, counts))) in methods.iter().zip(&summaries).enumerate() {
        let style = look(m);
        let x0 = PAD + (index % columns) as f64 * (panel_w + gap);
        let y0 = top + (index / columns) as f64 * (panel_h + caption_lines + gap);
        wrapped_text(
            &mut body,
            (x0, y0 - 4.0),
            caption_w,
            13.0,
            "start",
            "#111111",
            caption,
        );
        let label = method_title(&m.method);
        let inner = mazes::render_svg(
            maze,
            &[SvgTrajectory {
                label: &label,
                path,
                color: Some(style.colour),
            }],
            &SvgOptions {
                tile_px: TILE_PX,
                title: None,
                ..SvgOptions::default()
            },
        );
        let panel_top = y0 + caption_lines - 8.0;
        let _ = writeln!(
            body,
            "<svg x=\"{}\" y=\"{}\"{}",
            px(x0),
            px(panel_top),
            inner.trim_end().strip_prefix("<svg").unwrap_or(&inner)
        );
        let most = counts.iter().map(|(_, n)| *n).max().unwrap_or(1).max(2);
        let _ = writeln!(
            body,
            "<g class=\"path\" data-method=\"{}\" stroke=\"{}\">",
            escape(&m.method),
            style.colour
        );
        for (pos, n) in counts.iter().filter(|(_, n)| *n > 1) {
            // Opacity grows with the logarithm of the visits: 2 visits are faint, the most
            // visited tile is nearly solid.
            let opacity = 0.2 + 0.6 * (*n as f64).ln() / (most as f64).ln();
            let _ = writeln!(
                body,
                "<rect class=\"visits\" x=\"{}\" y=\"{}\" width=\"{TILE_PX}\" height=\"{TILE_PX}\" \
                 fill=\"{}\" fill-opacity=\"{opacity:.2}\" stroke=\"none\"><title>{n} visits</title></rect>",
                px(x0 + MAZE_MARGIN + f64::from(TILE_PX) * pos.x as f64),
                px(panel_top + MAZE_MARGIN + f64::from(TILE_PX) * pos.y as f64),
                style.colour
            );
        }
        body.push_str("</g>\n");
        // The loop's count beside its most visited tile, inside the panel.
        if let Some((pos, n)) = counts
            .iter()
            .max_by_key(|(_, n)| *n)
            .filter(|(_, n)| *n > 2)
        {
            let tile = f64::from(TILE_PX);
            let x = x0 + MAZE_MARGIN + tile * pos.x as f64;
            let y = panel_top + MAZE_MARGIN + tile * pos.y as f64 + tile * 0.8;
            let (x, anchor) = if pos.x * 2 < maze.width() {
                (x + tile + 3.0, "start")
            } else {
                (x - 3.0, "end")
            };
            let _ = writeln!(
                body,
                "<text x=\"{}\" y=\"{}\" font-size=\"12\" font-weight=\"bold\" text-anchor=\"{anchor}\" \
                 fill=\"{}\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\">{n}×</text>",
                px(x),
                px(y),
                style.colour
            );
        }
    }
    let bottom = top + rows as f64 * (panel_h + caption_lines + gap);
    let height = (bottom + PAD).ceil();
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\">\n<title>{}</title>\n\
         <rect width=\"{width}\" height=\"{height}\" fill=\"white\"/>\n{body}</svg>\n",
        escape(title)
    )
}

/// An attribute's value in the first tag of `svg`.
fn attribute<'s>(svg: &'s str, name: &str) -> Option<&'s str> {
    let pattern = format!(" {name}=\"");
    let start = svg.find(&pattern)? + pattern.len();
    let rest = &svg[start..];
    Some(&rest[..rest.find('"')?])
}

fn robot_trajectories(
    scenario: &wmr_model::Scenario,
    methods: &[&MethodCurves],
    look: &dyn Fn(&MethodCurves) -> MethodStyle,
    plan: &FigurePlan,
    title: &str,
    analogue: &str,
) -> String {
    let arena = wmr_model::render_svg(scenario, &[]);
    let arena_w: f64 = attribute(&arena, "width")
        .and_then(|w| w.parse().ok())
        .unwrap_or(520.0);
    let arena_h: f64 = attribute(&arena, "height")
        .and_then(|h| h.parse().ok())
        .unwrap_or(520.0);
    let view_box = attribute(&arena, "viewBox")
        .unwrap_or("0 0 520 520")
        .to_owned();
    let width = (arena_w + 2.0 * PAD).max(700.0).ceil();
    let mut body = String::new();
    let y = heading(
        &mut body,
        width,
        title,
        &format!(
            "{analogue}Greedy evaluation of each method's first seed after training; a dot marks \
             where each path ends; a path under another is drawn wider, so both show, and \
             methods with the same path share one line."
        ),
    );
    let top = y + 8.0;
    let left = ((width - arena_w) / 2.0).floor();
    let _ = writeln!(
        body,
        "<svg x=\"{left}\" y=\"{}\"{}",
        px(top),
        arena.trim_end().strip_prefix("<svg").unwrap_or(&arena)
    );
    let _ = writeln!(
        body,
        "<svg x=\"{left}\" y=\"{}\" width=\"{arena_w}\" height=\"{arena_h}\" viewBox=\"{view_box}\">",
        px(top)
    );
    let metres = |v: f64| (v * wmr_model::render::PIXELS_PER_METRE * 10.0).round() / 10.0;
    // Methods with the same path are one line; the paper's EA-MADM is drawn last, and each
    // path 1.5 px wider than the next one drawn over it, so a path under another shows.
    let mut paths: Vec<(&MethodCurves, Vec<&str>)> = Vec::new();
    for m in methods {
        match paths
            .iter_mut()
            .find(|(first, _)| first.first.trajectory.positions == m.first.trajectory.positions)
        {
            Some((_, also)) => also.push(&m.method),
            None => paths.push((m, Vec::new())),
        }
    }
    paths.sort_by_key(|(m, _)| plan.on_top.as_deref() == Some(m.method.as_str()));
    let count = paths.len();
    for (index, (m, also)) in paths.iter().enumerate() {
        let style = look(m);
        let points: Vec<String> = m
            .first
            .trajectory
            .positions
            .iter()
            .map(|&[x, y]| format!("{},{}", metres(x), metres(-y)))
            .collect();
        let width = 2.5 + 1.5 * (count - 1 - index).min(4) as f64;
        let _ = writeln!(
            body,
            "<polyline class=\"path\" data-method=\"{}\"{} fill=\"none\" {} stroke-width=\"{}\" points=\"{}\"/>",
            escape(&m.method),
            if also.is_empty() {
                String::new()
            } else {
                format!(" data-also=\"{}\"", escape(&also.join(" ")))
            },
            stroke_attributes(&style),
            px(width),
            points.join(" ")
        );
        if let Some(&[x, y]) = m.first.trajectory.positions.last() {
            let _ = writeln!(
                body,
                "<circle cx=\"{}\" cy=\"{}\" r=\"6\" fill=\"{}\"/>",
                metres(x),
                metres(-y),
                style.colour
            );
        }
    }
    body.push_str("</svg>\n");
    let mut y = top + arena_h + 10.0;
    for m in methods {
        let style = look(m);
        let same: Vec<String> = paths
            .iter()
            .find(|(_, also)| also.contains(&m.method.as_str()))
            .map(|(first, _)| format!(" (the same path as {})", method_title(&first.method)))
            .into_iter()
            .collect();
        let outcome = if m.first.reached {
            "reached the target"
        } else {
            "target not reached"
        };
        let label = format!(
            "{}: seed {}, {} steps, {outcome}{}",
            method_title(&m.method),
            m.first.seed,
            m.first.steps,
            same.join("")
        );
        let _ = writeln!(
            body,
            "<line class=\"sample\" data-method=\"{}\" x1=\"{PAD}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {} stroke-width=\"3\"/>",
            escape(&m.method),
            px(y + 8.0),
            px(PAD + 30.0),
            px(y + 8.0),
            stroke_attributes(&style)
        );
        y = wrapped_text(
            &mut body,
            (PAD + 38.0, y - 4.0),
            width - 2.0 * PAD - 38.0,
            13.0,
            "start",
            "#111111",
            &label,
        ) + 6.0;
    }
    let height = (y + PAD).ceil();
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" \
         viewBox=\"0 0 {width} {height}\" font-family=\"sans-serif\">\n<title>{}</title>\n\
         <rect width=\"{width}\" height=\"{height}\" fill=\"white\"/>\n{body}</svg>\n",
        escape(title)
    )
}

/// Padding of the trajectory figures, in pixels.
const PAD: f64 = 12.0;

/// A path figure's title and, under it, its subtitle, centred on a canvas `width` wide;
/// returns the bottom of the subtitle.
fn heading(body: &mut String, width: f64, title: &str, subtitle: &str) -> f64 {
    let y = wrapped_text(
        body,
        (width / 2.0, PAD - 4.0),
        width - 2.0 * PAD,
        18.0,
        "middle",
        "#111111",
        title,
    );
    wrapped_text(
        body,
        (width / 2.0, y),
        width - 2.0 * PAD,
        13.0,
        "middle",
        "#444444",
        subtitle,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::not_drawn_sentence;
    use eamadm_eval::{RobotEpisodeMetrics, TrajectoryRecord};

    /// The tiny maze of these tests: 4 × 3 tiles, one obstacle.
    fn tiny_maze() -> mazes::Maze {
        mazes::Maze::parse("S...\n.#..\n...T\n").unwrap()
    }

    /// An episode of `steps` steps (a robot one with its metrics when `robot`).
    fn episode(index: u64, steps: u64, reached: bool, robot: bool) -> EpisodeRecord {
        EpisodeRecord {
            episode: index,
            steps,
            task_return: 100.0 - steps as f64,
            learning_return: 0.0,
            terminated: reached,
            truncated: !reached && steps >= 12,
            reached,
            collisions: 0,
            env_steps: steps,
            robot: robot.then(|| RobotEpisodeMetrics {
                time: steps as f64 * 0.4,
                average_reward: 10.0 - steps as f64 * 0.1,
                time_to_reach: reached.then_some(steps as f64 * 0.4),
                retention_time: 0.4,
            }),
        }
    }

    /// A run of `method` with one episode per entry of `steps` (an episode of fewer than 12
    /// steps reaches), its greedy episode walking the maze's top row.
    fn record(method: &str, seed: u64, steps: &[u64], robot: bool) -> RunRecord {
        let episodes: Vec<EpisodeRecord> = steps
            .iter()
            .enumerate()
            .map(|(i, &n)| episode(i as u64, n, n < 12, robot))
            .collect();
        let evaluation = episode(steps.len() as u64, 5, true, robot);
        RunRecord {
            experiment: "tiny".to_owned(),
            method: method.to_owned(),
            seed,
            optimum_steps: Some(5),
            subtasks: Vec::new(),
            pretrain_env_steps: 0,
            total_env_steps: steps.iter().sum(),
            episodes,
            trajectories: Vec::new(),
            greedy_evaluations: Vec::new(),
            evaluation,
            evaluation_trajectory: TrajectoryRecord {
                episode: steps.len() as u64,
                greedy: true,
                states: vec![0, 1, 2, 3, 7, 11],
                actions: vec![3, 3, 3, 1, 1],
                positions: (0..6).map(|i| [0.1 * f64::from(i), 0.0]).collect(),
            },
            final_window_episodes: 0,
            final_window_actions: Vec::new(),
            agreement: None,
        }
    }

    /// The tiny maze experiment with a paper method (softmax) and a control (ε-greedy).
    fn plan() -> FigurePlan {
        FigurePlan {
            name: "tiny".to_owned(),
            title: "Tiny".to_owned(),
            analogues: PaperFigures::default(),
            methods: vec![
                ("softmax".to_owned(), Role::Paper),
                ("epsilon-greedy".to_owned(), Role::Control),
            ],
            arena: Some(Arena::Maze(tiny_maze())),
            on_top: None,
        }
    }

    /// The runs of [`plan`]: `seeds` seeds of 12 episodes each, method by method.
    fn runs(seeds: u64) -> Vec<RunRecord> {
        let mut runs = Vec::new();
        for method in ["softmax", "epsilon-greedy"] {
            for seed in 0..seeds {
                let steps: Vec<u64> = (0..12).map(|e| 5 + (e * 7 + seed * 3) % 9).collect();
                runs.push(record(method, seed, &steps, false));
            }
        }
        runs
    }

    /// The robot with two of the paper's competitors, one seed of 3 episodes each, none
    /// reaching.
    fn robot_never_reaching() -> (FigurePlan, Vec<RunRecord>) {
        let plan = FigurePlan {
            name: "robot".to_owned(),
            title: "Robot".to_owned(),
            analogues: PaperFigures::default(),
            methods: vec![
                ("epsilon-greedy".to_owned(), Role::Paper),
                ("softmax".to_owned(), Role::Paper),
            ],
            arena: Some(Arena::Robot(Box::new(
                wmr_model::Scenario::default_scenario(),
            ))),
            on_top: None,
        };
        let runs = ["epsilon-greedy", "softmax"]
            .into_iter()
            .map(|method| record(method, 0, &[250, 250, 250], true))
            .collect();
        (plan, runs)
    }

    /// No empty figure: when no method of the C4 figures has a reaching episode, their SVGs
    /// are not written and one sentence, in the gallery, says which and why; once one seed of
    /// one method reaches, all three are drawn again.
    #[test]
    fn c4_figures_nobody_reaches_in_are_not_drawn_and_a_sentence_says_why() {
        let (plan, mut runs) = robot_never_reaching();
        let figures = collect(&plan, &runs);
        let not_drawn = figures.not_drawn();
        assert_eq!(
            not_drawn
                .iter()
                .map(|n| n.file.as_str())
                .collect::<Vec<_>>(),
            [
                "average-reward.svg",
                "reaching-time.svg",
                "retention-time.svg"
            ]
        );
        assert_eq!(
            not_drawn_sentence(&not_drawn),
            "Not drawn, since none of ε-greedy, softmax reached the target in any training \
             episode of any seed: average reward over reaching episodes (Fig. 13); reaching \
             time over reaching episodes (Fig. 14); retention time over reaching episodes \
             (Fig. 15)."
        );
        let drawing = figures.draw().unwrap();
        let files = &drawing.figures.files;
        assert!(
            not_drawn.iter().all(|n| !files.contains(&n.file)),
            "{files:?}"
        );
        // Success is 0 everywhere: no figure of flat zeros, a sentence instead.
        assert!(!files.contains(&"success.svg".to_owned()), "{files:?}");
        let success = drawing.figures.not_drawn.last().unwrap();
        assert_eq!(success.file, "success.svg");
        assert_eq!(
            success.why,
            "it is 0 in every episode of every seed of ε-greedy, softmax"
        );
        assert_eq!(drawing.figures.not_drawn[..3], not_drawn[..]);
        assert_eq!(
            drawing.files.iter().map(|(f, _)| f).collect::<Vec<_>>(),
            files.iter().collect::<Vec<_>>()
        );

        runs[1].episodes[2] = episode(2, 9, true, true);
        let figures = collect(&plan, &runs);
        assert!(figures.not_drawn().is_empty());
        assert_eq!(not_drawn_sentence(&[]), "");
        let files = figures.draw().unwrap().figures.files;
        for file in [
            "success.svg",
            "average-reward.svg",
            "reaching-time.svg",
            "retention-time.svg",
        ] {
            assert!(files.iter().any(|f| f == file), "{file}: {files:?}");
        }
    }

    fn collect(plan: &FigurePlan, records: &[RunRecord]) -> ExperimentFigures {
        let mut figures = ExperimentFigures::new(plan.clone());
        for record in records {
            figures.push(record);
        }
        figures
    }

    /// The memory law of the figures: the collector holds one number per seed and episode of
    /// each curve it draws (and each method's first path), so it grows linearly with the seeds
    /// and holds no run record.
    #[test]
    fn the_collector_grows_linearly_with_the_seeds() {
        let held = |seeds: u64| collect(&plan(), &runs(seeds)).held_size();
        let (two, three, twelve) = (held(2), held(3), held(12));
        assert!(two > 0);
        assert_eq!(twelve - two, 10 * (three - two));
        let files = collect(&plan(), &runs(12)).draw().unwrap().figures.files;
        assert_eq!(
            files,
            [
                "steps.svg",
                "return.svg",
                "controls-steps.svg",
                "trajectories.svg"
            ]
        );
    }

    /// A greedy path that stays on the start tile shades exactly the start tile of the maze
    /// drawn beneath, and its count is written beside it.
    #[test]
    fn a_loop_is_shaded_on_its_tile_and_counted() {
        let mut runs = runs(1);
        let start = runs[0].evaluation_trajectory.states[0];
        runs[0].evaluation_trajectory.states = vec![start; 6];
        runs[0].evaluation.steps = 5;
        let figures = collect(&plan(), &runs);
        let maze = tiny_maze();
        let first: Vec<&MethodCurves> = figures.methods.iter().take(1).collect();
        let look = |m: &MethodCurves| method_style(&m.method, m.role);
        let svg = maze_trajectories(&maze, &first, &look, "t", "");
        assert!(svg.contains(">6×</text>"), "{svg}");
        assert!(svg.contains("over 1 tile, loops (a tile visited"), "{svg}");
        let number = |text: &str, key: &str| -> f64 {
            let start = text.find(key).unwrap() + key.len();
            text[start..].split('"').next().unwrap().parse().unwrap()
        };
        // The nested maze's offset plus its start tile's position…
        let nested = &svg[svg.find("<svg x=").unwrap()..];
        let (dx, dy) = (number(nested, "<svg x=\""), number(nested, "\" y=\""));
        let fill = nested.find("fill=\"#7fc97f\"").unwrap();
        let tile = &nested[nested[..fill].rfind("<rect").unwrap()..];
        let tile = &tile[..tile.find("/>").unwrap()];
        let (tx, ty) = (number(tile, " x=\""), number(tile, " y=\""));
        // …is where the visits are shaded.
        let shade = &svg[svg.find("class=\"visits\"").unwrap()..];
        assert_eq!(
            (number(shade, " x=\""), number(shade, " y=\"")),
            (dx + tx, dy + ty)
        );
    }

    #[test]
    fn methods_are_split_into_figures_of_at_most_eight() {
        let figures = collect(&plan(), &runs(1));
        let one = &figures.methods[0];
        let many: Vec<&MethodCurves> = std::iter::repeat_n(one, 10).collect();
        let sizes: Vec<usize> = chunks(Some(one), &many).iter().map(Vec::len).collect();
        assert_eq!(sizes, [6, 6]);
        let sizes: Vec<usize> = chunks(None, &many[..8]).iter().map(Vec::len).collect();
        assert_eq!(sizes, [8]);
        assert!(chunks(Some(one), &[]).is_empty());
        assert_eq!(numbered("controls-steps", 1, 2), "controls-steps-2.svg");
    }

    /// A non-finite value fails the figure that draws it, naming the series, the seed among
    /// the method's runs and the episode; a method a figure does not draw cannot fail it.
    #[test]
    fn a_non_finite_value_fails_only_the_figures_that_draw_it() {
        let mut runs = runs(3);
        // Runs come method by method: softmax seeds 0..3, then ε-greedy seeds 0..3.
        assert_eq!(runs[4].method, "epsilon-greedy");
        runs[4].episodes[5].task_return = f64::NAN;
        // ε-greedy is a control: the return figure draws the paper's softmax only.
        assert!(collect(&plan(), &runs).draw().is_ok());

        runs[1].episodes[7].task_return = f64::INFINITY;
        let error = collect(&plan(), &runs).draw().unwrap_err();
        assert_eq!(
            error.to_string(),
            "series \"softmax\": seed 1, episode 7: value inf is not finite"
        );
    }
}
