//! The command line: `cargo xtask reproduce-paper [OPTIONS]`, `run-job --key KEY [OPTIONS]`,
//! `merge [OPTIONS] STORE...` and `cargo xtask regen-fixtures [--check]`. Parsing only; [`crate::plan`] checks the values
//! against each other and the file system.

use std::path::PathBuf;

use clap::builder::PossibleValue;
use clap::builder::TypedValueParser as _;
use clap::{Args, Parser, Subcommand, ValueEnum};
use eamadm::paper::PaperTask;

/// eamadm project tooling.
#[derive(Debug, Parser)]
#[command(name = "xtask", about = "eamadm project tooling")]
pub(crate) struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub(crate) command: Command,
}

/// The tooling commands.
#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Rerun the paper's experiments (Task I, Task II, the robot) for EA-MADM, its competitors
    /// and the ablations over many seeds; write curves, the full record, figures and REPORT.md.
    ReproducePaper(ReproduceCommand),
    /// Regenerate fixtures/: maze layouts, robot scenario, reference trajectories and curves.
    RegenFixtures(RegenFixturesArgs),
    /// Run exactly one run of a plan (a key from `reproduce-paper --list-jobs`, with the same
    /// plan options) into the run store of --out, for GNU parallel, SLURM or any job engine.
    RunJob(RunJobArgs),
    /// Check the run stores of finished shards (or run-job folders) and write the outputs of
    /// the plan (the same options as the sharded runs) as one unsharded run would.
    Merge(MergeArgs),
    /// Recompute a seeded sample of the plan's stored runs and pre-trained artefacts and
    /// compare them byte for byte with what is stored (checksums catch faults, not forgery);
    /// exit 1 on any difference.
    Verify(VerifyArgs),
    /// Remove what no plan needs: runs of another results format or version, entries set
    /// aside long ago, artefacts the plan does not pre-train; print each removal.
    Gc(GcArgs),
    /// Run every test: `cargo test --workspace`, `regen-fixtures --check`, the Python
    /// package's pytest suite in target/py-venv (made and filled from the package registry when
    /// missing), then `wheel`.
    Test,
    /// Build the abi3 manylinux wheel with maturin, install it into a clean virtualenv without
    /// Rust on PATH (target/wheel-venv), and run the README's Python examples from it.
    Wheel,
}

/// What `reproduce-paper` does with its plan besides running it all and reporting.
#[derive(Debug, Clone, Default, PartialEq, Eq, Args)]
pub(crate) struct RunModeArgs {
    /// Run only the runs whose key falls in shard K of N (1 ≤ K ≤ N), store them under --out and
    /// exit without the report; `cargo xtask merge` makes the outputs from all shards.
    #[arg(long, value_name = "K/N", conflicts_with_all = ["runs_only", "list_jobs"])]
    pub(crate) shard: Option<String>,
    /// Run (or resume) every run into the run store under --out and exit without the report.
    #[arg(long, conflicts_with = "list_jobs")]
    pub(crate) runs_only: bool,
    /// Print one JSON line per run of the plan (key, experiment, task, method, seed and the
    /// `run-job` arguments that run it) and exit; runs nothing, writes nothing.
    #[arg(long)]
    pub(crate) list_jobs: bool,
}

/// Options of `reproduce-paper`.
#[derive(Debug, Clone, PartialEq, Eq, Args)]
pub(crate) struct ReproduceCommand {
    /// The plan.
    #[command(flatten)]
    pub(crate) plan: ReproduceArgs,
    /// Sharding and job listing.
    #[command(flatten)]
    pub(crate) mode: RunModeArgs,
}

/// Options of `run-job`.
#[derive(Debug, Clone, PartialEq, Eq, Args)]
pub(crate) struct RunJobArgs {
    /// The run's key, as `reproduce-paper --list-jobs` prints it.
    #[arg(long, value_name = "KEY")]
    pub(crate) key: String,
    /// The plan the key belongs to (the options given to --list-jobs).
    #[command(flatten)]
    pub(crate) plan: ReproduceArgs,
}

/// Options of `merge`.
#[derive(Debug, Clone, PartialEq, Args)]
pub(crate) struct MergeArgs {
    /// The plan the stores belong to (the options the shards were run with, without --shard).
    #[command(flatten)]
    pub(crate) plan: ReproduceArgs,
    /// Output folders of the shards (each holding runs/), or runs/ folders themselves.
    #[arg(value_name = "STORE", required = true)]
    pub(crate) stores: Vec<PathBuf>,
    /// Before merging, recompute this fraction (0 < F ≤ 1, seeded) of the runs and artefacts
    /// the shards hold, as `verify` does, and merge nothing on any difference.
    #[arg(long, value_name = "F", value_parser = fraction)]
    pub(crate) verify: Option<f64>,
}

/// Options of `verify`.
#[derive(Debug, Clone, PartialEq, Args)]
pub(crate) struct VerifyArgs {
    /// The plan whose runs and artefacts are checked (the options it was run with).
    #[command(flatten)]
    pub(crate) plan: ReproduceArgs,
    /// Check this fraction (0 < F ≤ 1) of the stored runs and of the artefacts [default: 0.05].
    #[arg(long, value_name = "F", value_parser = fraction, conflicts_with = "all")]
    pub(crate) sample: Option<f64>,
    /// Check every stored run and artefact.
    #[arg(long)]
    pub(crate) all: bool,
    /// The seed of the sample (each seed picks another sample).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub(crate) sample_seed: u64,
}

/// Options of `gc`.
#[derive(Debug, Clone, PartialEq, Eq, Args)]
pub(crate) struct GcArgs {
    /// The plan to keep (the options it was run with): artefacts it does not pre-train go.
    #[command(flatten)]
    pub(crate) plan: ReproduceArgs,
    /// Remove entries set aside (runs/.set-aside/) more than this many days ago.
    #[arg(long, value_name = "DAYS", default_value_t = 30)]
    pub(crate) older_than: u64,
}

/// A fraction in (0, 1].
fn fraction(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(value) if value > 0.0 && value <= 1.0 => Ok(value),
        _ => Err(format!("{text:?} is not a fraction in (0, 1], e.g. 0.05")),
    }
}

pub(crate) use eamadm_runs::KeepTrajectories;

/// The most seeds per task and method a plan may have, from `--seeds` or a config's `seeds`
/// (more would list millions of jobs before running one).
pub(crate) const MAX_SEEDS: u32 = 1000;

/// `--keep-trajectories`: `figures` (only what the figures draw: the evaluation episodes, in
/// trajectories.csv.gz the first seed's) or `all` (also every seed's evaluation path and every
/// training trajectory the config records).
fn keep_trajectories_values() -> impl clap::builder::TypedValueParser<Value = KeepTrajectories> {
    clap::builder::PossibleValuesParser::new(KeepTrajectories::ALL.map(KeepTrajectories::name))
        .map(|name| name.parse().unwrap_or_default())
}

/// `--task`: the paper's experiments by [`PaperTask::name`] (`task-i` and `task-ii` also name
/// Task I and II), each shown with its [`PaperTask::description`].
fn task_values() -> impl clap::builder::TypedValueParser<Value = PaperTask> {
    let values = PaperTask::ALL.map(|task| {
        let value = PossibleValue::new(task.name()).help(task.description());
        match task {
            PaperTask::Task1 => value.alias("task-i"),
            PaperTask::Task2 => value.alias("task-ii"),
            _ => value,
        }
    });
    // The parser admits only these names, so the fallback is never taken.
    clap::builder::PossibleValuesParser::new(values).map(|name| match name.as_str() {
        "task-ii" => PaperTask::Task2,
        other => PaperTask::from_name(other).unwrap_or(PaperTask::Task1),
    })
}

/// Options of `reproduce-paper`.
#[derive(Debug, Clone, PartialEq, Eq, Args)]
pub(crate) struct ReproduceArgs {
    /// Seeds per task and method [default: 20, or 3 with --quick].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SEEDS)))]
    pub(crate) seeds: Option<u32>,
    /// Run only this task; repeat for several [default: all five].
    #[arg(long = "task", value_name = "TASK", value_parser = task_values())]
    pub(crate) tasks: Vec<PaperTask>,
    /// Run only this method (by label); repeat for several [default: all]. Labels: ea-madm,
    /// epsilon-greedy, epsilon-decreasing, softmax, the ablations ea-madm-table,
    /// ea-madm-uniform, ea-madm-literal, ea-madm-distance, the plain aggregators subtasks-mean
    /// and subtasks-max (every task), and the maze tasks' controls
    /// subtask0-alone, subtask1-alone, COMPETITOR-budget, COMPETITOR-shaped,
    /// ea-madm-tau0.5, ea-madm-tau0.33; the robot's repaired readings ea-madm-goal-bonus,
    /// ea-madm-end-penalties, ea-madm-normalised, ea-madm-repaired, COMPETITOR-shaped-repaired,
    /// COMPETITOR-shaped-goal-bonus, COMPETITOR-shaped-end-penalties, and its controls subtaskK-alone, subtaskK-alone-learning (K = 0, 1, 2),
    /// COMPETITOR-budget, COMPETITOR-shaped, COMPETITOR-shaped-sum.
    #[arg(long = "method", value_name = "METHOD")]
    pub(crate) methods: Vec<String>,
    /// Experiment config (TOML) to use instead of the embedded defaults.
    #[arg(long, value_name = "FILE")]
    pub(crate) config: Option<PathBuf>,
    /// Output folder [default: target/reproduce-paper in the workspace]; never inside fixtures/.
    #[arg(long, value_name = "DIR")]
    pub(crate) out: Option<PathBuf>,
    /// Smoke run: few seeds and episodes, done in seconds.
    #[arg(long)]
    pub(crate) quick: bool,
    /// If another reproduce-paper is using the output folder, wait for it to finish instead
    /// of exiting with an error.
    #[arg(long)]
    pub(crate) wait: bool,
    /// Which training trajectories to keep in the run store and trajectories.csv.gz.
    #[arg(long, value_name = "WHICH", value_parser = keep_trajectories_values(), default_value_t)]
    pub(crate) keep_trajectories: KeepTrajectories,
    /// Whether to rerun the selected methods under the other readings of the paper (ε-greedy
    /// 0.95, γ 0.99, …) for sensitivity.csv and the report's sensitivity section: `all`, or
    /// `none` to run only the presets' experiments (what one method's run usually wants; the
    /// report then has no sensitivity section and its verdict table says "not run" there).
    #[arg(long, value_name = "WHICH", value_enum, default_value_t)]
    pub(crate) readings: Readings,
    /// Folder of the pre-trained sub-task learners, a cache shared by every output folder and
    /// process that names it (content-addressed: safe to share) [default:
    /// target/pretrained-cache in the workspace]; not inside --out.
    #[arg(long, value_name = "DIR")]
    pub(crate) pretrained_cache: Option<PathBuf>,
    /// Heavier work beside the paper's experiments; repeat for several. `tuning`: the same
    /// hyperparameter budget for every method the claims compare on task1, task2 and the robot
    /// (16 trials each on tuning seeds, then each method's best on the held-out seeds), written
    /// to tuning.csv and the report's "each method at its best" verdicts.
    #[arg(long = "suite", value_name = "SUITE", value_enum)]
    pub(crate) suites: Vec<Suite>,
    /// Layouts of `--suite family` (1 to 10000) [default: 24]; only with `--suite family`.
    #[arg(long, value_name = "N")]
    pub(crate) family_size: Option<usize>,
}

/// `--suite`: heavier work a plan adds beside the paper's experiments (the README gives each
/// one's cost).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, ValueEnum)]
pub(crate) enum Suite {
    /// The maze family of issue 33: every maze method on each of `--family-size` generated
    /// layouts (Task II's rewards, 6400 episodes, 10 seeds), judged pooled over layouts.
    Family,
    /// The same tuning budget for every method (issue 33 item 3): two stages, trials on the
    /// tuning seeds, then each method's chosen trial on the held-out seeds.
    Tuning,
}

/// `--readings`: which readings of the paper a plan reruns besides the presets.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, ValueEnum)]
pub(crate) enum Readings {
    /// Every reading of [`eamadm::paper::readings`] on each task it changes.
    #[default]
    All,
    /// None: the presets' experiments only.
    None,
}

/// Options of `regen-fixtures`.
#[derive(Debug, Clone, PartialEq, Eq, Args)]
pub(crate) struct RegenFixturesArgs {
    /// Write nothing; fail, naming the file, if a committed fixture differs from what the code
    /// produces now.
    #[arg(long)]
    pub(crate) check: bool,
}
