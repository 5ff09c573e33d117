//! The command line: `cargo xtask reproduce-paper [OPTIONS]` and
//! `cargo xtask regen-fixtures [--check]`. Parsing only; [`crate::plan`] checks the values
//! against each other and the file system.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

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
    ReproducePaper(ReproduceArgs),
    /// Regenerate fixtures/: maze layouts, robot scenario, reference trajectories and curves.
    RegenFixtures(RegenFixturesArgs),
    /// Run every test: `cargo test --workspace`, then the Python package's pytest suite in
    /// target/py-venv (made and filled from the package registry when missing).
    Test,
}

/// Options of `reproduce-paper`.
#[derive(Debug, Clone, PartialEq, Eq, Args)]
pub(crate) struct ReproduceArgs {
    /// Seeds per task and method [default: 10, or 3 with --quick].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub(crate) seeds: Option<u32>,
    /// Run only this task; repeat for several [default: all three].
    #[arg(long = "task", value_name = "TASK", value_enum)]
    pub(crate) tasks: Vec<Task>,
    /// Run only this method (by label); repeat for several [default: all]. Labels: ea-madm,
    /// epsilon-greedy, epsilon-decreasing, softmax, and the ablations ea-madm-table,
    /// ea-madm-uniform, ea-madm-literal, ea-madm-distance.
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
}

/// Options of `regen-fixtures`.
#[derive(Debug, Clone, PartialEq, Eq, Args)]
pub(crate) struct RegenFixturesArgs {
    /// Write nothing; fail, naming the file, if a committed fixture differs from what the code
    /// produces now.
    #[arg(long)]
    pub(crate) check: bool,
}

/// The paper's three experiments, in the order they are run and reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, ValueEnum)]
pub(crate) enum Task {
    /// Task I: the 30×30 maze (Sec. VI.A).
    #[value(name = "task1", alias = "task-i")]
    Task1,
    /// Task II: the 39×36 maze (Sec. VI.A).
    #[value(name = "task2", alias = "task-ii")]
    Task2,
    /// The wheeled robot among obstacles (Sec. VI.B).
    #[value(name = "robot")]
    Robot,
}

impl Task {
    /// All tasks, in run order.
    pub(crate) const ALL: [Task; 3] = [Task::Task1, Task::Task2, Task::Robot];

    /// The command-line name, also used for output folders (`task1`, `task2`, `robot`).
    pub(crate) fn name(self) -> &'static str {
        match self {
            Task::Task1 => "task1",
            Task::Task2 => "task2",
            Task::Robot => "robot",
        }
    }

    /// What the task is, for people.
    pub(crate) fn description(self) -> &'static str {
        match self {
            Task::Task1 => "Task I, 30×30 maze",
            Task::Task2 => "Task II, 39×36 maze",
            Task::Robot => "wheeled robot",
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory as _;

    use super::*;

    fn parse(args: &[&str]) -> Result<Cli, clap::Error> {
        Cli::try_parse_from(std::iter::once("xtask").chain(args.iter().copied()))
    }

    fn reproduce(args: &[&str]) -> ReproduceArgs {
        match parse(args).unwrap().command {
            Command::ReproducePaper(args) => args,
            Command::RegenFixtures(_) => panic!("parsed as regen-fixtures"),
            Command::Test => panic!("parsed as test"),
        }
    }

    #[test]
    fn cli_is_well_formed() {
        Cli::command().debug_assert();
    }

    #[test]
    fn no_options_means_defaults() {
        assert_eq!(
            reproduce(&["reproduce-paper"]),
            ReproduceArgs {
                seeds: None,
                tasks: vec![],
                methods: vec![],
                config: None,
                out: None,
                quick: false,
            }
        );
    }

    #[test]
    fn every_option_parses() {
        assert_eq!(
            reproduce(&[
                "reproduce-paper",
                "--seeds",
                "4",
                "--task",
                "robot",
                "--task",
                "task-i",
                "--method",
                "softmax",
                "--method",
                "ea-madm",
                "--config",
                "my.toml",
                "--out",
                "/tmp/out",
                "--quick",
            ]),
            ReproduceArgs {
                seeds: Some(4),
                tasks: vec![Task::Robot, Task::Task1],
                methods: vec!["softmax".to_owned(), "ea-madm".to_owned()],
                config: Some(PathBuf::from("my.toml")),
                out: Some(PathBuf::from("/tmp/out")),
                quick: true,
            }
        );
        let Command::RegenFixtures(args) = parse(&["regen-fixtures", "--check"]).unwrap().command
        else {
            panic!("parsed as reproduce-paper");
        };
        assert!(args.check);
    }

    #[test]
    fn bad_values_are_refused_by_the_parser() {
        for args in [
            &["reproduce-paper", "--seeds", "0"][..],
            &["reproduce-paper", "--seeds", "ten"],
            &["reproduce-paper", "--task", "task3"],
            &["reproduce-paper", "--frobnicate"],
            &["regen-fixtures", "--quick"],
        ] {
            let error = parse(args).unwrap_err();
            assert_eq!(error.exit_code(), 2, "{args:?}");
        }
    }

    #[test]
    fn task_names_match_the_command_line() {
        for task in Task::ALL {
            let value = task.to_possible_value().unwrap();
            assert_eq!(value.get_name(), task.name());
        }
    }
}
