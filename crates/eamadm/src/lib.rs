//! Experience-aggregative reinforcement learning with multi-attribute decision-making
//! (EA-MADM): the method of *An Experience Aggregative Reinforcement Learning With
//! Multi-Attribute Decision-Making for Obstacle Avoidance of Wheeled Mobile Robot* (IEEE
//! Access), its competitors, and the runner every comparison goes through.
//!
//! This is the facade of the workspace. It re-exports every crate as a module and adds only
//! what composes them:
//!
//! | module | what it holds |
//! |---|---|
//! | [`dql`] | double Q-learning (Eq. 9), ε-greedy / softmax with schedules, the episode driver |
//! | [`ea_tree`] | the experience-aggregation tree (Sec. IV.B, Fig. 4) |
//! | [`madm_owa`] | OWA, visibility weights and the multi-attribute decision (Eq. 3, 13–16) |
//! | [`reward_std`] | reward standardisation (Eq. 10–12, literal and running) |
//! | [`mazes`] | Task I and Task II (Sec. VI.A), and layouts with structure |
//! | [`wmr_model`] | the wheeled robot and its scenario (Sec. III, VI.B) |
//! | [`config`] | experiment configs in TOML; `ExperimentConfig::check` makes a checked [`Experiment`] once, errors naming the key the user wrote |
//! | [`paper`] | the paper's presets (Table 1 and 2), methods, titles, reported numbers, claims C1–C4 |
//! | [`pretrain`], [`prior`] | sub-task pre-training and the sub-tasks' stored experience (Fig. 5) |
//! | [`agent`], [`signal`] | the EA-MADM policy and learning signal (Algorithm 2) |
//! | [`runner`], [`record`] | runs as pure functions of (config, method, seed), in parallel |
//! | [`eamadm_eval`] | the evaluation, re-exported module by module: |
//! | [`summary`], [`results`] | statistics over seeds; JSON and CSV output |
//! | [`stats`] | IQM, bootstrap, stratified and two-level (layouts, seeds) bootstrap intervals, permutation tests, Holm, P(X > Y), Wilson |
//! | [`scores`] | per-seed final scores (one row per task, method, seed): `final-scores.csv` |
//! | [`claims`] | each claim × task × method tested against the competitors, with a verdict |
//! | [`reaching`] | the robot's curves over its first 100 reaching episodes (C4) and the seeds behind each point |
//! | [`behaviour`](mod@behaviour) | action shares, success and sub-task agreement per method |
//! | [`fixtures`] | the content of `fixtures/`: frozen layouts, the robot scenario, reference runs as CSV |
//! | [`output_names`] | the name of every file the tooling writes into an output folder |
//! | [`data_package`], [`columns`] | `datapackage.json`: every column of `final-scores.csv` and `claims.csv` with its type, unit and meaning |
//! | [`diagnosis`] | per robot sub-task: its learned start value against the value of reaching (Eq. 6–8 at γ) |
//! | [`margins`] | each task's equivalence margins, derived from its rewards and control period |
//! | [`family`] | the maze family: held-out layouts with structure (perfect mazes, rooms, traps) as experiments, and `layouts.csv` |
//! | [`tuning`] | the same number of hyperparameter trials per method from stated ranges, on tuning seeds apart from the held-out ones, and `tuning.csv` |
//! | [`report_facts`] | what a run's report needs of an experiment (its facts and final scores), gathered run by run |
//! | [`oracle`] | EA-MADM's decision and the plain aggregators on exact (maze) or converged (robot) sub-task values: `oracle.csv`; each sub-task's pre-training: `pretraining.csv` |
//!
//! # A first experiment
//!
//! An experiment is a TOML config: a task, the methods compared on it, episodes and seeds.
//! This one trains EA-MADM and the ε-decreasing competitor on a small maze with Task I's
//! rewards, three seeds each, and prints the summary over seeds.
//!
//! ```
//! use eamadm::{Experiment, summarise};
//!
//! let config = r#"
//! name = "tiny"
//! episodes = 40
//! seeds = 3
//!
//! [task]
//! kind = "maze_text"   # or kind = "maze", preset = "task1" for the paper's 30 x 30 maze
//! rewards = "task1"    # +1 closer, -1 farther, -100 bump, +100 target; two sub-tasks
//! map = """
//! S......#.#
//! ......##..
//! .#.#.#....
//! ......#...
//! ..#..#....
//! .......#..
//! ...#..#.##
//! ....#....T
//! """
//!
//! [learner]            # Table 1
//! alpha = 0.1
//! gamma = 0.95
//!
//! [[methods]]
//! label = "ea-madm"
//! kind = "ea_madm"
//! epsilon = { exponential = { start = 0.95, factor = 0.95, floor = 0.0 } }
//! pretrain = { episodes = 40, epsilon = { exponential = { start = 0.95, factor = 0.95, floor = 0.0 } } }
//!
//! [[methods]]
//! label = "epsilon-decreasing"
//! kind = "epsilon_greedy"
//! epsilon = { exponential = { start = 0.95, factor = 0.95, floor = 0.0 } }
//! "#;
//!
//! let experiment = Experiment::from_toml_str(config)?;
//! let optimum = experiment.task().optimum_steps(); // the BFS shortest path
//! let records = experiment.run_all()?; // 2 methods × 3 seeds, in parallel
//! assert_eq!(records.len(), 6);
//!
//! for summary in summarise(&records, 10)? {
//!     println!(
//!         "{:<20} last 10 episodes: {:.1} ± {:.1} steps (optimum {:?}); {:.0} environment steps in all",
//!         summary.method,
//!         summary.final_steps.mean,
//!         summary.final_steps.ci95_half_width.unwrap_or(0.0),
//!         optimum,
//!         summary.total_env_steps.mean,
//!     );
//! }
//!
//! // EA-MADM's sub-tasks were trained first, and their steps are counted.
//! let ea_madm = &records[0];
//! assert_eq!(ea_madm.subtasks.len(), 2); // "reach the target faster", "do not hit obstacles"
//! assert!(ea_madm.total_env_steps > ea_madm.pretrain_env_steps);
//! // After training, one greedy episode with its trajectory (tile positions).
//! println!("greedy route: {} steps", ea_madm.evaluation.steps);
//!
//! // Per-episode curves as CSV, one row per (method, seed, episode).
//! let mut csv = Vec::new();
//! eamadm::results::write_curves_csv(&records, &mut csv)?;
//! assert_eq!(String::from_utf8(csv)?.lines().count(), 1 + 6 * 40);
//! // Per-seed final scores (one row per run) and `final-scores.csv`, read back unchanged.
//! let rows = eamadm::scores::final_scores(&records, &experiment)?;
//! assert_eq!(rows.len(), 6);
//! assert_eq!(rows[0].final_window, 20);
//! let mut csv = Vec::new();
//! eamadm::scores::write_csv(&rows, &mut csv)?;
//! assert_eq!(eamadm::scores::read_csv(csv.as_slice())?, rows);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The paper's own settings are [`paper::task1`], [`paper::task2`] and [`paper::robot`] (also
//! as TOML: [`PAPER_TASK1_TOML`], …), each with the four methods and four ablations of
//! [`paper::methods`]; [`paper::CLAIMS`] holds the paper's claims, which [`claims`] tests on
//! the per-seed [`scores`] with the resampling statistics of [`stats`]. `cargo run --release -p eamadm
//! --example compare -- task1` runs one and prints the table.
//!
//! # The method (Sec. V, Fig. 5, Algorithm 2)
//!
//! 1. The task is decomposed into m sub-tasks with their own rewards (the environment's
//!    [`subtask_rewards`](dql::Environment::subtask_rewards): "reach the target faster" and
//!    "do not hit obstacles" in the mazes, Eq. 6–8 for the robot).
//! 2. [`pretrain_subtasks`] trains one double-Q learner per sub-task on its own reward, in
//!    parallel.
//! 3. Each sub-task's experience (every visited `(s, a)` with its final `Q1`, `Q2`) goes into
//!    its own EA tree; [`PriorTable`] holds the trees' answers for every `(s, a)`.
//! 4. The source task has its own double-Q tables. [`EaMadmPolicy`] explores with probability ε
//!    and otherwise takes the MADM argmax over the m sub-task values and its own value (Eq.
//!    13–16); [`StandardisedReward`] turns the sub-task rewards into its learning signal
//!    (Eq. 10–12).
//!
//! The competitors ([`Method::EpsilonGreedy`], [`Method::Softmax`]) are plain double-Q learners
//! on the task reward. Each ablation flips one switch of [`EaMadmConfig`]: trees or plain tables
//! ([`Storage`]), visibility or uniform weights and paper or distance support
//! ([`madm_owa::Weighting`]), running or literal standardisation
//! ([`reward_std::Standardisation`]).
//!
//! # Decisions the paper leaves open
//!
//! * **No prior experience.** When a sub-task's tree has no cluster for `(s, a)`, that sub-task
//!   abstains for that action: its row of the decision matrix is aggregated over the
//!   attributes that exist (the source task's own value always does). See [`EaMadmPolicy`].
//! * **Literal standardisation is a zero signal.** Eq. 12 averages z-scores, which is
//!   identically 0; with it the source task's own values never move, and EA-MADM decides on
//!   the sub-tasks' experience alone. The default is the running standardisation.
//! * **Tree thresholds.** The default is `τₛ = τₐ = 1`: on grid features Jaccard similarity
//!   only takes the values 0, 1/3 and 1, so any threshold above 1/3 is exact and any below
//!   merges whole rows or columns. An exact tree answers like the sub-task tables, so the
//!   `ea-madm-table` ablation gives bit-identical runs on the mazes (a test pins this).
//! * **Exploration and pre-training.** EA-MADM's ε follows Table 1's ε-decreasing schedule
//!   (0.95 × 0.95 per episode), so it differs from the ε-decreasing competitor only in its
//!   exploitation step and learning signal. Sub-tasks train on the same schedule "to
//!   convergence" (Sec. V): in the presets at least 200 episodes, then on until a greedy check
//!   every 10 episodes agrees three times (the target reached, for the sub-task whose goal it
//!   is; the same return, for the others), at most 1000 ([`Convergence`],
//!   [`paper::pretrain_to_convergence`]); the check episodes' steps are counted.
//! * **Does the decision step help?** [`oracle`] feeds EA-MADM's decision (and the plain
//!   aggregators, [`paper::aggregators`]) exact sub-task values on the mazes, by value
//!   iteration on their known model, and the positive control [`paper::aggregation_control`]
//!   is a maze designed for it (docs/paper-notes.md §21).
//! * **Counting.** Every cumulative step count includes sub-task pre-training
//!   ([`EpisodeRecord::env_steps`]); the paper leaves it out.
//! * **Evaluation.** After training, one greedy episode (ε = 0, no learning) with its
//!   trajectory; for EA-MADM the greedy policy is the MADM decision itself.
//! * **Randomness.** Every draw comes from a `ChaCha8` stream keyed by the run's seed and the
//!   draw's purpose (source training, evaluation, sub-task `k`, environment resets), so a run
//!   is a pure function of `(config, method, seed)` and [`Experiment::run_all`] gives
//!   bit-identical records with any number of threads.
//!
//! # Speed
//!
//! One training step on Task I costs about 40 ns with ε-greedy and about 100 ns with EA-MADM
//! (`cargo bench -p eamadm`); the decision's rows are cached with the own value they were
//! computed from, since the sub-tasks' experience is frozen. No step allocates.

pub use dql;
pub use ea_tree;
pub use madm_owa;
pub use mazes;
pub use reward_std;
pub use wmr_model;

pub use eamadm_eval;
// The evaluation lives in `eamadm-eval`; its modules keep their paths here.
pub use eamadm_eval::{
    behaviour, claims, columns, facts, findings, reaching, record, results, rounding, scores,
    sensitivity, stats, summary, verdicts,
};

pub mod agent;
pub mod config;
pub mod data_package;
pub mod diagnosis;
pub mod error;
pub mod family;
pub mod fixtures;
pub mod margins;
pub mod oracle;
pub mod output_names;
pub mod paper;
pub mod pretrain;
pub mod prior;
pub mod report_facts;
mod rng;
pub mod runner;
pub mod shortening;
pub mod signal;
pub mod task;
pub mod tuning;

pub use agent::{EaMadmPolicy, PolicyError};
// `behaviour` (the function) comes with the module of the same name above.
pub use behaviour::{BehaviourAccumulator, Endings, MethodBehaviour, SubtaskBehaviour};
pub use config::{
    AGGREGATION_CONTROL_TOML, CompetitorSignal, CompetitorTraining, ConfigError, Convergence,
    DEFAULT_EVALUATION_EVERY, EaMadmConfig, EvaluationConfig, ExperimentConfig,
    MAX_INPUT_FILE_BYTES, Method, MethodSpec, PAPER_ROBOT_PAPER_STATE_TOML, PAPER_ROBOT_TOML,
    PAPER_TASK1_TOML, PAPER_TASK2_TOML, PretrainConfig, RESERVED_NAMES, Role, Storage,
    SubtaskGreedyConfig, TaskConfig, TrajectoryConfig, is_safe_slug, read_input_file,
};
pub use diagnosis::{SubtaskDiagnosis, subtask_diagnosis};
pub use error::{RunError, RunFailure};
pub use pretrain::{PretrainedSubtask, SubtaskGoals, pretrain_subtask, pretrain_subtasks};
pub use prior::{PriorTable, build_prior};
pub use record::{
    AgreementCounts, AgreementRecord, EpisodeRecord, RobotEpisodeMetrics, RunRecord, SubtaskRecord,
    TrajectoryRecord,
};
pub use report_facts::ReportFacts;
pub use runner::{
    Experiment, NoPretrainingCache, PretrainingCache, SharedPretraining, run, run_all,
};
pub use shortening::{QUICK_SEEDS, Shortening};
pub use signal::StandardisedReward;
pub use summary::{DEFAULT_FINAL_WINDOW, MethodSummary, RobotSummary, SeedSummary, summarise};
pub use task::Task;

impl scores::MethodRoles for Experiment {
    fn role_and_kind(&self, label: &str) -> Option<(Role, &'static str)> {
        self.config()
            .method(label)
            .map(|spec| (spec.role, spec.method.kind_name()))
    }

    fn step_cap(&self) -> u32 {
        self.task().step_cap()
    }

    fn layout(&self) -> String {
        family::layout_name(self)
    }
}

/// The Rust examples of the workspace's `README.md`, compiled and run as doc tests so that the
/// README cannot show code that no longer builds (only under `cargo test`'s doctest pass).
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
