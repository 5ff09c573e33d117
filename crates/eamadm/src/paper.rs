//! The paper in one place: its three experiments as presets (Table 1 and 2), the methods it
//! compares (with our ablations), their display titles, the numbers it reports, and its claims
//! as data that [`claims`](crate::claims) tests.
//!
//! Everything here is read off the paper (Sec. VI, Fig. 6–15, Tables 1–2); nothing is computed.
//! The presets are the embedded TOML files [`PAPER_TASK1_TOML`], [`PAPER_TASK2_TOML`],
//! [`PAPER_ROBOT_TOML`], … parsed: their values are written once, there.
//!
//! ```
//! use eamadm::paper::{self, Direction, PaperTask};
//!
//! let task1 = paper::task1();
//! assert_eq!(task1.episodes, 200);
//! assert_eq!(task1.seeds, paper::seeds());
//! assert_eq!(PaperTask::Task2.reported().map(|r| r.steps), Some(86.0));
//! let c1 = paper::claim("C1").unwrap();
//! assert_eq!(c1.metrics[0].column, "final_steps");
//! assert_eq!(c1.metrics[0].direction, Direction::LowerIsBetter);
//! assert_eq!(paper::method_title("epsilon-decreasing"), "ε-decreasing");
//! ```

use dql::Schedule;
use madm_owa::{Normalisation, Support, Weighting};
use mazes::Preset;
use reward_std::Standardisation;
use serde::Serialize;
use wmr_model::{Action, SubtaskRepairs};

use crate::facts::{
    ControlFamily, DeviationFacts, ExperimentFacts, Figures, FinalEpsilon, MethodFacts,
    PaperFigures, PaperTaskFacts, PredictionFacts, ReadingFacts, ReportContext,
};
use crate::output_names;

use ea_tree::EaTreeConfig;

use std::sync::OnceLock;

use crate::config::{
    AGGREGATION_CONTROL_TOML, PAPER_ROBOT_PAPER_STATE_TOML, PAPER_ROBOT_TOML, PAPER_TASK1_TOML,
    PAPER_TASK2_TOML,
};
use crate::config::{
    CompetitorSignal, CompetitorTraining, Convergence, EaMadmConfig, ExperimentConfig, Method,
    MethodSpec, PretrainConfig, Role, Storage, SubtaskGreedyConfig, TaskConfig,
    table1_epsilon_decreasing, table1_temperature,
};

/// Seeds per method of every preset, as the embedded configs write it (`seeds = 20` in each;
/// the test `every_preset_runs_the_same_seeds` checks they agree). The paper shows single runs;
/// 20 seeds give the bootstrap and permutation statistics of [`claims`](crate::claims) enough
/// resolution (a two-sided exact permutation test of 20 against 20 can reach p ≈ 1e-11) while
/// the whole default run stays well under half a minute on two cores.
#[must_use]
pub fn seeds() -> u32 {
    task1().seeds
}

/// The paper's three experiments, in the order they are run and reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub enum PaperTask {
    /// Task I: the 30 × 30 maze with 100 obstacles (Sec. VI.A, Fig. 6–8).
    Task1,
    /// Task II: the 39 × 36 maze with the +10 / −1 reward (Sec. VI.A, Fig. 9–11).
    Task2,
    /// The wheeled robot among obstacles (Sec. VI.B, Fig. 12–15), its state with the target's
    /// image position.
    Robot,
    /// The same robot task over the paper's literal state (no target feature).
    RobotPaperState,
    /// Not the paper's: the positive control of issue 32, a hand-designed maze on which
    /// distance shaping alone walks into a wall ([`aggregation_control`]).
    AggregationControl,
}

impl PaperTask {
    /// Every experiment, in run order.
    pub const ALL: [Self; 5] = [
        Self::Task1,
        Self::Task2,
        Self::Robot,
        Self::RobotPaperState,
        Self::AggregationControl,
    ];

    /// The experiment's name: its config's `name`, output folder and `task` column
    /// (`task1`, `task2`, `robot`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Task1 => "task1",
            Self::Task2 => "task2",
            Self::Robot => "robot",
            Self::RobotPaperState => "robot-paper-state",
            Self::AggregationControl => "aggregation-control",
        }
    }

    /// The title for people: `Task I`, `Task II`, `Robot`.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            Self::Task1 => "Task I",
            Self::Task2 => "Task II",
            Self::Robot => "Robot",
            Self::RobotPaperState => "Robot (paper's state)",
            Self::AggregationControl => "Aggregation control",
        }
    }

    /// What the task is, for people: `Task I, 30×30 maze`, `wheeled robot`.
    #[must_use]
    pub fn description(self) -> &'static str {
        match self {
            Self::Task1 => "Task I, 30×30 maze",
            Self::Task2 => "Task II, 39×36 maze",
            Self::Robot => "wheeled robot",
            Self::RobotPaperState => "wheeled robot, the paper's state",
            Self::AggregationControl => "positive control, 30×30 maze with a walled box",
        }
    }

    /// The task whose config `name` this is, if it is one of the paper's.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|task| task.name() == name)
    }

    /// The preset: [`task1`], [`task2`] or [`robot`].
    #[must_use]
    pub fn config(self) -> ExperimentConfig {
        match self {
            Self::Task1 => task1(),
            Self::Task2 => task2(),
            Self::Robot => robot(),
            Self::RobotPaperState => robot_paper_state(),
            Self::AggregationControl => aggregation_control(),
        }
    }

    /// The paper's figures this task's figures are the analogues of (Fig. 6–8 for Task I,
    /// 9–11 for Task II; the robot's Fig. 13–15 are named by their own figures).
    #[must_use]
    pub fn figures(self) -> PaperFigures {
        let figure = |number: u8| Some(format!("Fig. {number}"));
        match self {
            Self::Task1 => PaperFigures {
                trajectories: figure(6),
                steps: figure(7),
                task_return: figure(8),
            },
            Self::Task2 => PaperFigures {
                trajectories: figure(9),
                steps: figure(10),
                task_return: figure(11),
            },
            Self::Robot | Self::RobotPaperState | Self::AggregationControl => {
                PaperFigures::default()
            }
        }
    }

    /// What the paper reports for EA-MADM on this task; `None` for the robot (no numbers).
    #[must_use]
    pub fn reported(self) -> Option<ReportedNumbers> {
        match self {
            Self::Task1 => Some(ReportedNumbers {
                steps: 80.0,
                task_return: 155.0,
            }),
            Self::Task2 => Some(ReportedNumbers {
                steps: 86.0,
                task_return: -71.0,
            }),
            Self::Robot | Self::RobotPaperState | Self::AggregationControl => None,
        }
    }
}

/// What `REPORT.md` needs to know about the paper's tasks and the robot (titles, the numbers
/// the paper reports, the robot's action names, the output tables' file names) for
/// `eamadm_present::report::render`, with no experiment yet: the caller adds one
/// [`experiment_facts`] per experiment run, with its figures and behaviour.
#[must_use]
pub fn report_context(quick: bool) -> ReportContext {
    ReportContext {
        quick,
        paper_tasks: PaperTask::ALL
            .into_iter()
            .map(|task| PaperTaskFacts {
                name: task.name().to_owned(),
                title: task.title().to_owned(),
                title_in_sentence: match task {
                    PaperTask::Robot => "the robot".to_owned(),
                    other => other.title().to_owned(),
                },
                robot: matches!(task, PaperTask::Robot | PaperTask::RobotPaperState),
                reported: task.reported(),
            })
            .collect(),
        preset_seeds: seeds(),
        action_names: Action::ALL.map(|a| a.name().to_owned()).to_vec(),
        curves_file: output_names::CURVES.to_owned(),
        trajectories_file: output_names::TRAJECTORIES.to_owned(),
        experiments: Vec::new(),
        readings: readings()
            .iter()
            .map(|reading| ReadingFacts {
                name: reading.name().to_owned(),
                change: reading.change().to_owned(),
                source: reading.source().to_owned(),
                methods: reading.methods().iter().map(|m| (*m).to_owned()).collect(),
            })
            .collect(),
        deviations: deviations(),
        oracle: Vec::new(),
        pretraining: Vec::new(),
        predictions: predictions(),
    }
}

/// What was predicted before any run (docs/paper-notes.md §21.2, committed in 0b067f4 before
/// the positive control was first run): on `aggregation-control` no verdict of EA-MADM better
/// than inconclusive, EA-MADM ending as its reach sub-task alone (`subtask0-alone`) on most
/// seeds, and its decision with exact sub-task values never reaching (it follows the reach
/// sub-task into the walled box). The report judges it against the run
/// (`eamadm_eval::findings::PredictionOutcome`).
#[must_use]
pub fn predictions() -> Vec<PredictionFacts> {
    vec![PredictionFacts {
        task: PaperTask::AggregationControl.name().to_owned(),
        notes: "§21.2".to_owned(),
        best_verdict: crate::claims::Verdict::Inconclusive,
        follows: "subtask0-alone".to_owned(),
        oracle_reaches: false,
    }]
}

/// How this reproduction differs from the paper wherever the difference could change a
/// verdict, each with where `docs/paper-notes.md` records it and the readings, ablations or
/// controls that run the other choice: what the report's first screen lists.
#[must_use]
pub fn deviations() -> Vec<DeviationFacts> {
    let strings = |items: &[&str]| items.iter().map(|s| (*s).to_owned()).collect::<Vec<_>>();
    let deviation = |what: &str,
                     ours: &str,
                     notes: &str,
                     tasks: &[&str],
                     readings: &[&str],
                     methods: &[&str]| DeviationFacts {
        what: what.to_owned(),
        ours: ours.to_owned(),
        notes: notes.to_owned(),
        tasks: strings(tasks),
        readings: strings(readings),
        methods: strings(methods),
    };
    let robots = ["robot", "robot-paper-state"];
    vec![
        deviation(
            "Generated mazes",
            "the paper does not publish its maze layouts; ours are generated with its sizes and \
             obstacle counts, so our steps and returns are not its numbers",
            "§7",
            &["task1", "task2"],
            &[],
            &[],
        ),
        deviation(
            "Task II's reward",
            "we pay +10 at the target and −1 otherwise, as Sec. VI.A states, though it also \
             calls Task II similar to Task I",
            "§7, §10.3",
            &["task2"],
            &[Reading::Task2RewardAsTask1.name()],
            &[],
        ),
        deviation(
            "A 2D robot, not Webots",
            "our own model of an e-puck-class robot with a range camera stands in for the \
             paper's Webots simulation",
            "§8",
            &robots,
            &[],
            &[],
        ),
        deviation(
            "The robot's task reward",
            "the paper never defines it (the competitors learn from it); ours is Task I's: +1 \
             closer, −1 otherwise, −100 for a hit, +100 for reaching, −10 for losing the target",
            "§8",
            &robots,
            &[],
            &[],
        ),
        deviation(
            "The target's bearing in the robot's state",
            "`robot` adds the target's position in the camera image (7 bins), without which no \
             competitor learns; `robot-paper-state` keeps the paper's state",
            "§8.1",
            &robots,
            &[],
            &[],
        ),
        deviation(
            "Robot settings chosen on the competitors",
            "control period, step cap, reach radius, distance bins and 500 episodes were picked \
             by a sweep of the three competitors alone, before any EA-MADM run was looked at",
            "§8.5",
            &robots,
            &[],
            &[],
        ),
        deviation(
            "ε of ε-greedy",
            "Table 1's ε = 0.95 is read as the start of the annealed schedules; fixed ε-greedy \
             gets 0.1",
            "§2",
            &[],
            &[Reading::EpsilonGreedy095.name()],
            &[],
        ),
        deviation(
            "Softmax's temperature",
            "Table 1's temperatures 0.1 and 0.01 are read as the start and the floor of one \
             schedule annealed by 0.95",
            "§2, §10.3",
            &[],
            &[Reading::TemperatureFloor01.name()],
            &[],
        ),
        deviation(
            "Sub-task pre-training",
            "the paper trains the sub-tasks \"to convergence\" without a rule; ours stop when \
             3 greedy checks 10 episodes apart agree (reaching, for a sub-task paid for the \
             target), after at least 200 and at most 1000 episodes, and every step of it \
             counts in EA-MADM's budget",
            "§6, §21.4",
            &[],
            &[
                Reading::PretrainHalf.name(),
                Reading::PretrainDouble.name(),
                Reading::PretrainFixed.name(),
            ],
            &[],
        ),
        deviation(
            "Reward standardisation",
            "Eq. 10–12 as printed give the source task 0 on every step; EA-MADM standardises \
             each sub-task's reward against its own running statistics instead",
            "§3",
            &[],
            &[],
            &["ea-madm-literal"],
        ),
        deviation(
            "The OWA support",
            "Eq. 15 is undefined for equal values and negative for opposite signs; ours is \
             max(0, xy) / (|x − y|² + 10⁻⁹)",
            "§5",
            &[],
            &[],
            &["ea-madm-distance", "ea-madm-uniform"],
        ),
        deviation(
            "Tree thresholds and missing experience",
            "the paper gives no thresholds; ours are τ = 1, where a tree answers as a table, and \
             a sub-task without experience of an action abstains from its row",
            "§4, §6",
            &[],
            &[],
            &["ea-madm-table", "ea-madm-tau0.5", "ea-madm-tau0.33"],
        ),
        deviation(
            "Many seeds and C3 on greedy evaluations",
            "the paper shows single runs; we judge 20 seeds by interval estimates and tests, and \
             C3's fluctuation on greedy evaluations, so that a seed stuck at the step cap cannot \
             count as stable",
            "§10.2, §10.2d",
            &[],
            &[],
            &[],
        ),
    ]
}

/// `context` as the text of an output folder's [`output_names::REPORT_CONTEXT`]: TOML, whose
/// floats (the robot's behaviour shares) read back bit for bit, so that
/// [`report_context_from_toml`] and the folder's `final-scores.csv` render its `REPORT.md`
/// again byte for byte.
///
/// # Errors
/// A value TOML cannot hold (an integer past `i64::MAX`).
pub fn report_context_toml(context: &ReportContext) -> Result<String, toml::ser::Error> {
    toml::to_string(context)
}

/// The [`ReportContext`] of an output folder's [`output_names::REPORT_CONTEXT`] text.
///
/// # Errors
/// The text is not what [`report_context_toml`] writes; the message names the field.
pub fn report_context_from_toml(text: &str) -> Result<ReportContext, toml::de::Error> {
    toml::from_str(text)
}

/// The title of the experiment named `name`: the paper task's (`Task I`, …) when it is one,
/// else the name itself.
#[must_use]
pub fn experiment_title(name: &str) -> String {
    PaperTask::from_name(name).map_or_else(|| name.to_owned(), |task| task.title().to_owned())
}

/// The report's facts of one experiment (folder `name`, `title`, and from `config` its
/// episodes, seeds and γ), with no figures, no behaviour and no reward readings yet (see
/// [`diagnosis::reward_references`](crate::diagnosis::reward_references)).
#[must_use]
pub fn experiment_facts(name: &str, title: &str, config: &ExperimentConfig) -> ExperimentFacts {
    ExperimentFacts {
        name: name.to_owned(),
        title: title.to_owned(),
        episodes: config.episodes,
        seeds: config.seeds,
        gamma: config.learner.gamma,
        figures: Figures::default(),
        behaviour: Vec::new(),
        reward_references: Vec::new(),
        final_epsilon: final_epsilon(config),
        margins: Vec::new(),
        methods: config.methods.iter().map(method_facts).collect(),
        paper_figures: PaperTask::from_name(name)
            .map_or_else(PaperFigures::default, PaperTask::figures),
        base_seed: config.base_seed,
        tables_written: false,
    }
}

/// What the report and the verdicts know of `spec` beyond its scores: its role, its kind and,
/// for a control, what it matches or isolates (read off its config, never its label).
#[must_use]
pub fn method_facts(spec: &MethodSpec) -> MethodFacts {
    let control = match &spec.method {
        Method::SubtaskGreedy(alone) => Some(ControlFamily::SubtaskAlone {
            subtask: alone.subtask,
            learns: alone.learn,
        }),
        Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } => {
            if training.signal.needs_subtasks() {
                Some(ControlFamily::RewardMatched)
            } else if training.warmup_env_steps > 0 {
                Some(ControlFamily::BudgetMatched)
            } else {
                None
            }
        }
        _ => None,
    };
    let tree_threshold = match &spec.method {
        Method::EaMadm(ea) => match ea.storage {
            Storage::Tree(tree) => Some(tree.state_threshold),
            Storage::Table => None,
        },
        _ => None,
    };
    MethodFacts {
        label: spec.label.clone(),
        role: spec.role,
        kind: spec.method.kind_name().to_owned(),
        control: control.filter(|_| spec.role == Role::Control),
        tree_threshold,
    }
}

/// ε over the final window of every method of `config` that explores ε-greedily (EA-MADM, its
/// ε-greedy competitors and the sub-task-alone controls), from its schedule.
fn final_epsilon(config: &ExperimentConfig) -> Vec<FinalEpsilon> {
    let window = config.episodes.min(crate::DEFAULT_FINAL_WINDOW as u64);
    let first = config.episodes.saturating_sub(window);
    let last = config.episodes.saturating_sub(1);
    config
        .methods
        .iter()
        .filter_map(|spec| {
            let schedule = match &spec.method {
                Method::EaMadm(ea) => &ea.epsilon,
                Method::EpsilonGreedy { epsilon, .. } => epsilon,
                Method::SubtaskGreedy(alone) => &alone.epsilon,
                _ => return None,
            };
            Some(FinalEpsilon {
                method: spec.label.clone(),
                first: schedule.value(first),
                last: schedule.value(last),
            })
        })
        .collect()
}

/// A preset: its embedded TOML parsed (once per process). The TOML files are the one source
/// of the presets' values (the robot's open settings, episodes, seeds, budgets): nothing in the
/// code repeats them; the test `presets_are_built_from_the_method_builders` checks that the
/// presets' methods are those of [`methods`], [`controls`], [`robot_repairs`],
/// [`robot_controls`] and [`aggregators`].
fn embedded(text: &'static str, parsed: &'static OnceLock<ExperimentConfig>) -> ExperimentConfig {
    parsed
        .get_or_init(|| {
            ExperimentConfig::from_toml_str(text)
                .expect("the embedded presets are valid (test tasks_round_trip_by_name_and_match_their_presets)")
        })
        .clone()
}

/// The paper's Task I (Sec. VI.A, Table 1): the 30 × 30 maze, 200 episodes, [`seeds()`] seeds,
/// α = 0.1, γ = 0.95, [`methods`] and the [`controls`]: [`PAPER_TASK1_TOML`] parsed.
#[must_use]
pub fn task1() -> ExperimentConfig {
    static PARSED: OnceLock<ExperimentConfig> = OnceLock::new();
    embedded(PAPER_TASK1_TOML, &PARSED)
}

/// The paper's Task II (Sec. VI.A): the 39 × 36 maze with the +10 / −1 reward, otherwise as
/// [`task1`]: [`PAPER_TASK2_TOML`] parsed.
#[must_use]
pub fn task2() -> ExperimentConfig {
    static PARSED: OnceLock<ExperimentConfig> = OnceLock::new();
    embedded(PAPER_TASK2_TOML, &PARSED)
}

/// The paper's robot experiment (Sec. VI.B, Table 2): the embedded default scenario (8
/// distance sensors, the analogue of Fig. 12, whose state includes the target's image
/// position in [`wmr_model::DEFAULT_TARGET_BINS`] bins) with the settings the paper leaves
/// open as the competitors-only sweep of docs/paper-notes.md §8.5 chose them (`task.
/// control_period`, `step_cap`, `reach_radius`, `distance_bins` and `episodes` of the TOML),
/// [`seeds()`] seeds, α = 0.1, γ = 0.95, ε 0.95 annealed by 0.95, T 0.1 → 0.01, [`methods`],
/// [`robot_repairs`] and [`robot_controls`]: [`PAPER_ROBOT_TOML`] parsed.
#[must_use]
pub fn robot() -> ExperimentConfig {
    static PARSED: OnceLock<ExperimentConfig> = OnceLock::new();
    embedded(PAPER_ROBOT_TOML, &PARSED)
}

/// [`robot`] over the paper's literal state (Sec. III.B: distance × obstacle image bin × angle
/// bin, `target_bins = 0`), named `robot-paper-state`, with [`methods`] and [`aggregators`]:
/// [`PAPER_ROBOT_PAPER_STATE_TOML`] parsed.
#[must_use]
pub fn robot_paper_state() -> ExperimentConfig {
    static PARSED: OnceLock<ExperimentConfig> = OnceLock::new();
    embedded(PAPER_ROBOT_PAPER_STATE_TOML, &PARSED)
}

/// The positive control of issue 32 (not the paper's; docs/paper-notes.md §21.2): the
/// hand-designed maze [`mazes::AGGREGATION_CONTROL_MAP`] (the target in a walled box whose door
/// faces away from the start) with Task II's rewards and sub-tasks, 200 episodes, [`seeds()`]
/// seeds, Table 1's learner, [`methods`] and the maze [`controls`]:
/// [`AGGREGATION_CONTROL_TOML`] parsed.
#[must_use]
pub fn aggregation_control() -> ExperimentConfig {
    static PARSED: OnceLock<ExperimentConfig> = OnceLock::new();
    embedded(AGGREGATION_CONTROL_TOML, &PARSED)
}

impl PaperTask {
    /// EA-MADM's mean sub-task pre-training on the task, in environment steps, rounded: the
    /// budget its budget-matched controls (`COMPETITOR-budget`) warm up for, read off the
    /// preset (`warmup_env_steps`); `None` for a preset without them (`robot-paper-state`).
    /// Measured over seeds 0–19 with [`pretrain_to_convergence`] (the stopping rule's check
    /// episodes included): Task I 464 000 (mean 463 868, range 454 487–495 889); Task II 896 000
    /// (mean 895 620, median 472 025, range 464 275–2 593 707: on four seeds the reach sub-task
    /// trains to the cap of 1000 episodes); the robot 53 000 (three sub-tasks; mean 52 611,
    /// range 20 938–59 545: the reach sub-task trains to the cap of 1000 episodes, most of them
    /// ending within ten steps by losing the target); `aggregation-control` 2 640 000 (mean
    /// 2 639 499, range 2 637 634–2 640 000; the reach sub-task runs to the cap of 1000 episodes
    /// of 2000 steps on every seed).
    #[must_use]
    pub fn pretrain_budget(self) -> Option<u64> {
        self.config()
            .methods
            .iter()
            .find_map(|spec| match &spec.method {
                Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. }
                    if training.warmup_env_steps > 0 =>
                {
                    Some(training.warmup_env_steps)
                }
                _ => None,
            })
    }
}

/// The methods of every preset, in report order: `ea-madm`, `epsilon-greedy` (constant
/// ε = 0.1), `epsilon-decreasing` and `softmax` (Table 1's schedules), then the ablations, each
/// EA-MADM with one switch flipped: `ea-madm-table` (sub-task tables instead of trees),
/// `ea-madm-uniform` (uniform instead of visibility weights), `ea-madm-literal` (the literal,
/// identically zero, standardisation) and `ea-madm-distance` (the distance support instead of
/// the paper's).
#[must_use]
pub fn methods() -> Vec<MethodSpec> {
    let ea_madm = paper_ea_madm();
    let variant = |label: &str, role: Role, change: &dyn Fn(&mut EaMadmConfig)| {
        let mut config = ea_madm.clone();
        change(&mut config);
        MethodSpec {
            label: label.to_owned(),
            role,
            method: Method::EaMadm(config),
        }
    };
    vec![
        variant("ea-madm", Role::Paper, &|_| {}),
        MethodSpec {
            label: "epsilon-greedy".to_owned(),
            role: Role::Paper,
            method: Method::EpsilonGreedy {
                epsilon: Schedule::Constant(0.1),
                training: CompetitorTraining::default(),
            },
        },
        MethodSpec {
            label: "epsilon-decreasing".to_owned(),
            role: Role::Paper,
            method: Method::EpsilonGreedy {
                epsilon: table1_epsilon_decreasing(),
                training: CompetitorTraining::default(),
            },
        },
        MethodSpec {
            label: "softmax".to_owned(),
            role: Role::Paper,
            method: Method::Softmax {
                temperature: table1_temperature(),
                training: CompetitorTraining::default(),
            },
        },
        variant("ea-madm-table", Role::Ablation, &|c| {
            c.storage = Storage::Table;
        }),
        variant("ea-madm-uniform", Role::Ablation, &|c| {
            c.weighting = Weighting::Uniform;
        }),
        variant("ea-madm-literal", Role::Ablation, &|c| {
            c.standardisation = Standardisation::CrossSectional;
        }),
        variant("ea-madm-distance", Role::Ablation, &|c| {
            c.weighting = Weighting::Visibility {
                support: Support::Distance,
            };
        }),
    ]
}

/// The presets' sub-task pre-training: Table 1's ε schedule, at least 200 episodes, then on
/// until the stopping rule [`Convergence::PRESETS`] finds the sub-task converged, at most 1000
/// (Sec. V's "trained to convergence"; docs/paper-notes.md §21.4).
#[must_use]
pub fn pretrain_to_convergence() -> PretrainConfig {
    PretrainConfig {
        until: Some(Convergence::PRESETS),
        ..PretrainConfig::default()
    }
}

/// The plain aggregators (issue 32 item 3; docs/paper-notes.md §21.3), `role = "control"`:
/// EA-MADM in every respect but the aggregation of a decision-matrix row, which is the mean
/// (`subtasks-mean`) or the largest (`subtasks-max`) of its standardised attributes (each
/// column's z-score over the state's actions, [`Normalisation::ZScore`]) instead of OWA with
/// visibility weights.
#[must_use]
pub fn aggregators() -> Vec<MethodSpec> {
    [
        ("subtasks-mean", Weighting::Uniform),
        ("subtasks-max", Weighting::MaximumEntropy { orness: 1.0 }),
    ]
    .into_iter()
    .map(|(label, weighting)| MethodSpec {
        label: label.to_owned(),
        role: Role::Control,
        method: Method::EaMadm(EaMadmConfig {
            weighting,
            normalisation: Normalisation::ZScore,
            ..paper_ea_madm()
        }),
    })
    .collect()
}

/// EA-MADM as the paper presets run it.
fn paper_ea_madm() -> EaMadmConfig {
    EaMadmConfig {
        epsilon: table1_epsilon_decreasing(),
        weighting: Weighting::default(),
        standardisation: Standardisation::Running,
        storage: Storage::default(),
        pretrain: pretrain_to_convergence(),
        normalisation: Normalisation::None,
        subtask_rewards: SubtaskRepairs::PAPER,
    }
}

/// The controls of the maze presets (`role = "control"`; comparisons the paper does not run),
/// after [`methods`] in report order:
///
/// - `subtask0-alone`, `subtask1-alone`: each pre-trained sub-task acting by itself
///   ([`Method::SubtaskGreedy`], frozen, with EA-MADM's ε schedule);
/// - `epsilon-greedy-budget`, `epsilon-decreasing-budget`, `softmax-budget`: each competitor
///   warmed up on the task for `pretrain_budget` environment steps first (EA-MADM's sub-task
///   pre-training budget on the task);
/// - `epsilon-greedy-shaped`, `epsilon-decreasing-shaped`, `softmax-shaped`: each competitor
///   learning from EA-MADM's own standardised sub-task signal
///   ([`CompetitorSignal::Standardised`]);
/// - `ea-madm-tau0.5`, `ea-madm-tau0.33`: EA-MADM with both tree thresholds at τ < 1 (on a
///   maze, whose state similarities are 0, 1/3 or 1, τ = 0.5 is still exact and τ = 0.33
///   aggregates the states of a row or a column);
/// - `subtasks-mean`, `subtasks-max`: the plain [`aggregators`].
#[must_use]
pub fn controls(pretrain_budget: u64) -> Vec<MethodSpec> {
    let competitors: Vec<(String, Method)> = methods()
        .into_iter()
        .filter(|spec| spec.role == Role::Paper)
        .filter_map(|spec| match spec.method {
            Method::EpsilonGreedy { .. } | Method::Softmax { .. } => {
                Some((spec.label, spec.method))
            }
            _ => None,
        })
        .collect();
    let with_training = |method: &Method, change: &dyn Fn(&mut CompetitorTraining)| {
        let mut method = method.clone();
        if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
            &mut method
        {
            change(training);
        }
        method
    };
    let control = |label: String, method: Method| MethodSpec {
        label,
        role: Role::Control,
        method,
    };
    let mut methods = Vec::new();
    for subtask in 0..2 {
        methods.push(control(
            format!("subtask{subtask}-alone"),
            Method::SubtaskGreedy(SubtaskGreedyConfig {
                subtask,
                epsilon: table1_epsilon_decreasing(),
                learn: false,
                pretrain: pretrain_to_convergence(),
            }),
        ));
    }
    for (label, method) in &competitors {
        methods.push(control(
            format!("{label}-budget"),
            with_training(method, &|t| t.warmup_env_steps = pretrain_budget),
        ));
    }
    for (label, method) in &competitors {
        methods.push(control(
            format!("{label}-shaped"),
            with_training(method, &|t| t.signal = CompetitorSignal::Standardised),
        ));
    }
    // A maze state's features are its column and row, so state similarities are 0, 1/3 or 1:
    // 0.5 stands for every exact threshold in (1/3, 1], 0.33 merges rows and columns.
    for (tau, name) in [(0.5, "0.5"), (0.33, "0.33")] {
        let mut config = paper_ea_madm();
        config.storage = Storage::Tree(EaTreeConfig {
            state_threshold: tau,
            action_threshold: tau,
        });
        methods.push(control(
            format!("ea-madm-tau{name}"),
            Method::EaMadm(config),
        ));
    }
    methods.extend(aggregators());
    methods
}

pub use eamadm_eval::paper_claims::{
    CLAIMS, Claim, ClaimMetric, Direction, ReportedNumbers, claim, method_title,
};

/// The repaired readings of EA-MADM on the robot (issue 21 item 4), each one switch
/// (docs/paper-notes.md §8.6), `role = "ablation"`; the literal method stays `ea-madm`:
///
/// - `ea-madm-goal-bonus`: sub-task 1 (Eq. 6) gets the +100 goal bonus the competitors' task
///   reward pays on reaching ([`SubtaskRepairs::reach_goal_bonus`]);
/// - `ea-madm-end-penalties`: a hit or a lost target ends the episode with its penalty in every
///   sub-task ([`SubtaskRepairs::end_penalties`]);
/// - `ea-madm-normalised`: each attribute of the decision matrix scaled onto `[0, 1]` over the
///   state's actions before OWA ([`Normalisation::MinMax`]);
/// - `ea-madm-repaired`: all three.
///
/// And, as controls on the same rewards (fairness both ways: each reading is also judged
/// against them, [`claims::SAME_REWARDS`](crate::claims::SAME_REWARDS)), each competitor
/// learning from the standardised signal of the repaired sub-task rewards: with both repairs
/// (`COMPETITOR-shaped-repaired`), with the goal bonus only (`COMPETITOR-shaped-goal-bonus`),
/// with the end penalties only (`COMPETITOR-shaped-end-penalties`). `ea-madm-normalised`
/// learns from the paper's sub-task rewards, so its matched competitors are the robot's
/// `COMPETITOR-shaped` ([`robot_controls`]).
#[must_use]
pub fn robot_repairs() -> Vec<MethodSpec> {
    let both = SubtaskRepairs {
        reach_goal_bonus: true,
        end_penalties: true,
    };
    let goal_bonus = SubtaskRepairs {
        reach_goal_bonus: true,
        ..SubtaskRepairs::PAPER
    };
    let end_penalties = SubtaskRepairs {
        end_penalties: true,
        ..SubtaskRepairs::PAPER
    };
    let variants = [
        ("goal-bonus", Normalisation::None, goal_bonus),
        ("end-penalties", Normalisation::None, end_penalties),
        ("normalised", Normalisation::MinMax, SubtaskRepairs::PAPER),
        ("repaired", Normalisation::MinMax, both),
    ];
    let mut specs: Vec<MethodSpec> = variants
        .into_iter()
        .map(|(name, normalisation, subtask_rewards)| MethodSpec {
            label: format!("ea-madm-{name}"),
            role: Role::Ablation,
            method: Method::EaMadm(EaMadmConfig {
                normalisation,
                subtask_rewards,
                ..paper_ea_madm()
            }),
        })
        .collect();
    for (name, subtask_rewards) in [
        ("repaired", both),
        ("goal-bonus", goal_bonus),
        ("end-penalties", end_penalties),
    ] {
        for spec in methods() {
            if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
                &spec.method
            {
                if spec.role != Role::Paper || *training != CompetitorTraining::default() {
                    continue;
                }
                let mut control = MethodSpec {
                    label: format!("{}-shaped-{name}", spec.label),
                    role: Role::Control,
                    method: spec.method.clone(),
                };
                if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
                    &mut control.method
                {
                    training.signal = CompetitorSignal::Standardised;
                    training.subtask_rewards = subtask_rewards;
                }
                specs.push(control);
            }
        }
    }
    specs
}

/// The robot's controls (issue 21 item 2), as on the mazes, all `role = "control"`:
///
/// - `subtask{0,1,2}-alone`: each pre-trained sub-task acting by itself, frozen, with EA-MADM's
///   ε schedule; `subtask{0,1,2}-alone-learning`: the same, still learning from its own reward;
/// - `COMPETITOR-budget`: each competitor warmed up on the task for `pretrain_budget` steps;
/// - `COMPETITOR-shaped`: each competitor learning from EA-MADM's standardised sub-task signal,
///   and `COMPETITOR-shaped-sum` from the plain sum of the sub-task rewards: the reward
///   information EA-MADM's sub-tasks get, instead of the task reward with its goal bonus;
/// - `subtasks-mean`, `subtasks-max`: the plain [`aggregators`].
///
/// The τ < 1 controls of the mazes are left out: they exercise aggregation, not the robot.
#[must_use]
pub fn robot_controls(pretrain_budget: u64) -> Vec<MethodSpec> {
    let maze_controls = controls(pretrain_budget);
    let mut methods = Vec::new();
    for subtask in 0..wmr_model::SUBTASK_COUNT {
        for learn in [false, true] {
            let suffix = if learn { "-learning" } else { "" };
            methods.push(MethodSpec {
                label: format!("subtask{subtask}-alone{suffix}"),
                role: Role::Control,
                method: Method::SubtaskGreedy(SubtaskGreedyConfig {
                    subtask,
                    epsilon: table1_epsilon_decreasing(),
                    learn,
                    pretrain: pretrain_to_convergence(),
                }),
            });
        }
    }
    for spec in maze_controls {
        let keep = spec.label.ends_with("-budget") || spec.label.ends_with("-shaped");
        if !keep {
            continue;
        }
        if spec.label.ends_with("-shaped") {
            let mut sum = spec.clone();
            sum.label = format!("{}-sum", spec.label);
            if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
                &mut sum.method
            {
                training.signal = CompetitorSignal::SubtaskSum;
            }
            methods.push(spec);
            methods.push(sum);
        } else {
            methods.push(spec);
        }
    }
    methods.extend(aggregators());
    methods
}

/// A reading of the paper that can flip a verdict (issue 20 item 4; docs/paper-notes.md §10.3):
/// the paper's words read another way, as one change to a preset. The default run reruns only
/// the methods a reading changes, on the tasks it changes, with the same seeds (so the same
/// random streams), and judges the maze claims again with those runs in place of the base
/// experiment's (`eamadm::sensitivity`). [`readings`] lists them.
///
/// ```
/// use eamadm::paper::{self, Reading};
///
/// let reading = Reading::EpsilonGreedy095;
/// let rerun = reading.apply(&paper::task1()).unwrap();
/// assert_eq!(rerun.name, "task1-reading-epsilon-greedy-0.95");
/// assert_eq!(rerun.methods.len(), 1); // only ε-greedy runs again
/// assert!(Reading::Task2RewardAsTask1.apply(&paper::task1()).is_none()); // Task II only
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Reading {
    /// Task II's rewards "similar to the scenario of task 1": Task I's reward rules (task
    /// reward and sub-task rewards, [`mazes::RewardScheme::TASK_I`]) on Task II's map, instead
    /// of the literal +10 / −1.
    Task2RewardAsTask1,
    /// ε-greedy with Table 1's "exploring rate 0.95" as its constant ε, instead of 0.1.
    EpsilonGreedy095,
    /// γ = 0.99 instead of Table 1's 0.95, for every learner.
    Gamma099,
    /// EA-MADM's sub-tasks pre-trained for at least half as many episodes (100 instead of 200),
    /// then on until converged as ours.
    PretrainHalf,
    /// EA-MADM's sub-tasks pre-trained for at least twice as many episodes (400 instead of
    /// 200), then on until converged as ours.
    PretrainDouble,
    /// EA-MADM's sub-tasks pre-trained for exactly 200 episodes, without the stopping rule
    /// "to convergence" (our earlier reading, docs/paper-notes.md §21.4).
    PretrainFixed,
    /// softmax's temperature floor at Table 1's maximum, 0.1, instead of its minimum 0.01: a
    /// constant T = 0.1.
    TemperatureFloor01,
}

/// The paper's methods (`role = "paper"`) a reading of the task's reward or learner reruns.
const PAPER_METHODS: [&str; 4] = ["ea-madm", "epsilon-greedy", "epsilon-decreasing", "softmax"];

impl Reading {
    /// Every reading, in report order.
    pub const ALL: [Self; 7] = [
        Self::Task2RewardAsTask1,
        Self::EpsilonGreedy095,
        Self::Gamma099,
        Self::PretrainHalf,
        Self::PretrainDouble,
        Self::PretrainFixed,
        Self::TemperatureFloor01,
    ];

    /// The reading's name (a safe slug): the `reading` column of `sensitivity.csv`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Task2RewardAsTask1 => "task2-reward-as-task1",
            Self::EpsilonGreedy095 => "epsilon-greedy-0.95",
            Self::Gamma099 => "gamma-0.99",
            Self::PretrainHalf => "pretrain-half",
            Self::PretrainDouble => "pretrain-double",
            Self::PretrainFixed => "pretrain-fixed",
            Self::TemperatureFloor01 => "temperature-floor-0.1",
        }
    }

    /// What the reading changes, for people: ours, then the alternative.
    #[must_use]
    pub fn change(self) -> &'static str {
        match self {
            Self::Task2RewardAsTask1 => {
                "Task II reward: +10 / −1 (ours) → Task I's rules (+1 closer, −1 otherwise, \
                 −100 bump, +100 target) on the Task II map, sub-tasks included"
            }
            Self::EpsilonGreedy095 => "ε of ε-greedy: 0.1 (ours) → 0.95",
            Self::Gamma099 => "γ of every learner: 0.95 (ours) → 0.99",
            Self::PretrainHalf => {
                "EA-MADM's sub-task pre-training: at least 200 episodes, then until converged \
                 (ours) → at least 100, then until converged"
            }
            Self::PretrainDouble => {
                "EA-MADM's sub-task pre-training: at least 200 episodes, then until converged \
                 (ours) → at least 400, then until converged"
            }
            Self::PretrainFixed => {
                "EA-MADM's sub-task pre-training: at least 200 episodes, then until converged \
                 (ours) → exactly 200 episodes"
            }
            Self::TemperatureFloor01 => "softmax's temperature floor: 0.01 (ours) → 0.1",
        }
    }

    /// Where the reading comes from in the paper, in one sentence.
    #[must_use]
    pub fn source(self) -> &'static str {
        match self {
            Self::Task2RewardAsTask1 => {
                "Sec. VI.A gives Task II \"+10 at the target, −1 otherwise\" but also calls it \
                 \"similar to the scenario of task 1\"."
            }
            Self::EpsilonGreedy095 => {
                "Tables 1 and 2 list one \"exploring rate ε 0.95\" and no other ε, which we read \
                 as the start of the annealed schedules and give fixed ε-greedy 0.1."
            }
            Self::Gamma099 => {
                "Table 1's γ = 0.95 has a horizon 1/(1−γ) of 20 steps, shorter than either \
                 maze's shortest path (58, 73); 0.99 (horizon 100) is the common choice that \
                 lets the target's value reach the start."
            }
            Self::PretrainHalf | Self::PretrainDouble => {
                "The paper never says how long the sub-tasks are pre-trained beyond \"to \
                 convergence\"; we give each at least as many episodes as the source task (200)."
            }
            Self::PretrainFixed => {
                "Sec. V: \"Each sub-task is trained to convergence\"; we read it as a stopping \
                 rule (a greedy check every 10 episodes, 3 agreeing checks, at most 1000 \
                 episodes), where a fixed 200 episodes was our earlier stand-in."
            }
            Self::TemperatureFloor01 => {
                "Table 1 lists a maximum (0.1) and a minimum (0.01) temperature and one \
                 annealing factor without saying what it anneals; at T = 0.01 softmax is greedy \
                 on rewards of ±1 to ±100."
            }
        }
    }

    /// The tasks the reading changes.
    #[must_use]
    pub fn tasks(self) -> &'static [PaperTask] {
        match self {
            Self::Task2RewardAsTask1 => &[PaperTask::Task2],
            _ => &[PaperTask::Task1, PaperTask::Task2],
        }
    }

    /// The labels of the methods the reading changes, and so reruns: a change of the task's
    /// reward or of the learner reruns every paper method; ablations and controls are never
    /// rerun.
    #[must_use]
    pub fn methods(self) -> &'static [&'static str] {
        match self {
            Self::Task2RewardAsTask1 | Self::Gamma099 => &PAPER_METHODS,
            Self::EpsilonGreedy095 => &["epsilon-greedy"],
            Self::PretrainHalf | Self::PretrainDouble | Self::PretrainFixed => &["ea-madm"],
            Self::TemperatureFloor01 => &["softmax"],
        }
    }

    /// The name of the reading's experiment on `task`: `<task>-reading-<reading>`.
    #[must_use]
    pub fn experiment_name(self, task: &str) -> String {
        format!("{task}-reading-{}", self.name())
    }

    /// The reading's experiment on the experiment `base` (a paper maze preset, possibly
    /// shortened or with other seeds): `base` with the reading's change, only the methods it
    /// reruns ([`methods`](Self::methods), those `base` has), named
    /// [`experiment_name`](Self::experiment_name). `None` when `base` is not one of the
    /// reading's [`tasks`](Self::tasks) or has none of its methods.
    #[must_use]
    pub fn apply(self, base: &ExperimentConfig) -> Option<ExperimentConfig> {
        let task = PaperTask::from_name(&base.name)?;
        if !self.tasks().contains(&task) {
            return None;
        }
        let mut config = base.clone();
        config.name = self.experiment_name(&base.name);
        config
            .methods
            .retain(|spec| self.methods().contains(&spec.label.as_str()));
        if config.methods.is_empty() {
            return None;
        }
        match self {
            Self::Task2RewardAsTask1 => {
                if let TaskConfig::Maze { rewards, .. } = &mut config.task {
                    *rewards = Some(Preset::Task1);
                }
            }
            Self::Gamma099 => config.learner.gamma = 0.99,
            Self::EpsilonGreedy095
            | Self::PretrainHalf
            | Self::PretrainDouble
            | Self::PretrainFixed => {
                for spec in &mut config.methods {
                    match (&mut spec.method, self) {
                        (Method::EpsilonGreedy { epsilon, .. }, Self::EpsilonGreedy095) => {
                            *epsilon = Schedule::Constant(0.95);
                        }
                        (Method::EaMadm(ea), Self::PretrainHalf) => {
                            ea.pretrain.episodes = (ea.pretrain.episodes / 2).max(1);
                        }
                        (Method::EaMadm(ea), Self::PretrainDouble) => {
                            ea.pretrain.episodes = ea.pretrain.episodes.saturating_mul(2);
                            // the cap stays at least the fewest episodes
                            if let Some(until) = ea.pretrain.until.as_mut() {
                                until.max_episodes = until.max_episodes.max(ea.pretrain.episodes);
                            }
                        }
                        (Method::EaMadm(ea), Self::PretrainFixed) => ea.pretrain.until = None,
                        _ => {}
                    }
                }
            }
            Self::TemperatureFloor01 => {
                for spec in &mut config.methods {
                    if let Method::Softmax {
                        temperature: Schedule::Exponential { floor, start, .. },
                        ..
                    } = &mut spec.method
                    {
                        // The floor never above the start (a schedule's rule).
                        *floor = start.min(0.1);
                    }
                }
            }
        }
        Some(config)
    }
}

/// The readings of the paper that can flip a verdict, in report order ([`Reading::ALL`]).
#[must_use]
pub fn readings() -> &'static [Reading] {
    &Reading::ALL
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_preset_runs_the_same_seeds() {
        for task in super::PaperTask::ALL {
            assert_eq!(task.config().seeds, super::seeds(), "{}", task.name());
        }
        assert_eq!(super::seeds(), 20);
    }

    use super::*;

    #[test]
    fn final_epsilon_is_the_schedule_over_the_final_window_of_epsilon_greedy_methods() {
        let config = task2();
        let facts = experiment_facts("task2", "Task II", &config);
        let of = |label: &str| facts.final_epsilon.iter().find(|e| e.method == label);
        // ε-greedy's fixed ε; the decreasing schedules far below one random action per episode.
        let fixed = of("epsilon-greedy").unwrap();
        assert_eq!((fixed.first, fixed.last), (0.1, 0.1));
        let decreasing = of("ea-madm").unwrap();
        assert!(decreasing.first < 1e-3 && decreasing.last <= decreasing.first);
        let window = config.episodes - crate::DEFAULT_FINAL_WINDOW as u64;
        let Method::EaMadm(ea) = &config.methods[0].method else {
            panic!("the first method of Task II is EA-MADM");
        };
        assert_eq!(decreasing.first, ea.epsilon.value(window));
        // Softmax explores by temperature: no ε.
        assert!(of("softmax").is_none());
    }

    #[test]
    fn tasks_round_trip_by_name_and_match_their_presets() {
        for task in PaperTask::ALL {
            assert_eq!(PaperTask::from_name(task.name()), Some(task));
            assert_eq!(task.config().name, task.name());
            assert!(task.config().validate().is_ok());
        }
        assert_eq!(PaperTask::from_name("mine"), None);
    }

    /// The label rule of `claims::SAME_REWARDS` agrees with the robot preset: each repaired
    /// reading is there, and each of its matched competitors is the paper's competitor learning
    /// from the standardised signal of exactly the reading's sub-task rewards, nothing else
    /// changed.
    #[test]
    fn the_matched_competitors_of_each_reading_learn_from_its_sub_task_rewards() {
        let robot = robot();
        let spec = |label: &str| robot.methods.iter().find(|spec| spec.label == label);
        let competitors: Vec<&MethodSpec> = robot
            .methods
            .iter()
            .filter(|spec| spec.role == Role::Paper && !matches!(spec.method, Method::EaMadm(_)))
            .collect();
        assert_eq!(competitors.len(), 3);
        for entry in &crate::claims::SAME_REWARDS {
            let Some(Method::EaMadm(reading)) = spec(entry.method).map(|s| &s.method) else {
                panic!(
                    "{} is not an EA-MADM method of the robot preset",
                    entry.method
                );
            };
            for competitor in &competitors {
                let label = format!("{}-{}", competitor.label, entry.suffix);
                let matched = spec(&label).unwrap_or_else(|| panic!("{label} is not run"));
                assert_eq!(matched.role, Role::Control, "{label}");
                let mut expected = competitor.method.clone();
                if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
                    &mut expected
                {
                    training.signal = CompetitorSignal::Standardised;
                    training.subtask_rewards = reading.subtask_rewards;
                }
                assert_eq!(matched.method, expected, "{label}");
            }
        }
    }

    #[test]
    fn each_reading_reruns_only_its_methods_with_one_change() {
        for reading in readings() {
            assert!(crate::config::is_safe_slug(reading.name()), "{reading:?}");
            for task in [PaperTask::Task1, PaperTask::Task2] {
                let base = task.config();
                let Some(rerun) = reading.apply(&base) else {
                    assert!(!reading.tasks().contains(&task), "{reading:?} on {task:?}");
                    continue;
                };
                assert!(rerun.validate().is_ok(), "{reading:?}");
                assert!(crate::config::is_safe_slug(&rerun.name), "{}", rerun.name);
                let labels: Vec<&str> = rerun.methods.iter().map(|m| m.label.as_str()).collect();
                assert_eq!(labels, reading.methods(), "{reading:?}");
                // Something changed in every rerun method or in what they all share.
                let shared_changed = rerun.task != base.task || rerun.learner != base.learner;
                for spec in &rerun.methods {
                    let before = base.method(&spec.label).unwrap();
                    assert_eq!(spec.role, Role::Paper);
                    assert!(
                        shared_changed || before != spec,
                        "{reading:?} {}",
                        spec.label
                    );
                }
                assert_eq!(rerun.episodes, base.episodes);
                assert_eq!(rerun.seeds, base.seeds);
            }
        }
        assert!(Reading::Gamma099.apply(&robot()).is_none());
    }

    #[test]
    fn task2_read_as_task1_loads_task1_rewards_on_the_task2_map() {
        let rerun = Reading::Task2RewardAsTask1.apply(&task2()).unwrap();
        let task = rerun.task.check().unwrap();
        let base = task2().task.check().unwrap();
        assert_eq!(task.optimum_steps(), base.optimum_steps());
        assert_eq!(task.n_states(), base.n_states());
        let crate::task::TaskKind::Maze(env) = task.kind() else {
            panic!("a maze");
        };
        assert_eq!(env.spec(), &mazes::TaskSpec::task1());
        let crate::config::TaskConfig::Maze {
            rewards, preset, ..
        } = rerun.task
        else {
            panic!("a maze");
        };
        assert_eq!((preset, rewards), (Preset::Task2, Some(Preset::Task1)));
        // The base serialises as before the `rewards` field existed (run keys stay).
        assert!(!task2().to_toml_string().unwrap().contains("rewards"));
    }

    #[test]
    fn every_claim_names_paper_tasks() {
        for claim in CLAIMS {
            assert!(!claim.metrics.is_empty(), "{}", claim.id);
            for task in claim.tasks {
                assert!(PaperTask::from_name(task).is_some(), "{}: {task}", claim.id);
            }
        }
    }
}
