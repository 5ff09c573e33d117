//! Project tooling. Run `cargo xtask --help` for the list of commands.
//!
//! - `cargo xtask reproduce-paper [--seeds N] [--task T]... [--method M]... [--config FILE]
//!   [--out DIR] [--quick]` reruns the paper's experiments and writes curves, figures and a report.
//!   `--shard K/N` or `--runs-only` run into the run store without the report; `--list-jobs`
//!   prints the runs as JSON lines.
//! - `cargo xtask run-job --key KEY [plan options]` runs exactly one run into the store.
//! - `cargo xtask merge --out DIR [plan options] STORE...` checks shards' run stores and writes
//!   the outputs an unsharded run writes.
//! - `cargo xtask verify --out DIR [plan options] [--sample F | --all]` recomputes a seeded
//!   sample of the stored runs and artefacts and compares them byte for byte.
//! - `cargo xtask gc --out DIR [plan options]` removes what no plan needs.
//! - `cargo xtask regen-fixtures [--check]` regenerates (or checks) `fixtures/` and the
//!   README's generated parts (verdicts, answer, figure) from the default run.
//! - `cargo xtask test` runs the Rust tests, `regen-fixtures --check`, the Python package's
//!   pytest suite and `wheel`.
//! - `cargo xtask wheel` builds the Python wheel and runs the README's Python examples from it,
//!   installed into a clean virtualenv without Rust.
//!
//! Exit codes: 0 success, 1 the command failed, 2 invalid arguments or config.
//!
//! Modules: [`cli`] parses, [`plan`] and [`experiments`] check the arguments and load the
//! configs; [`reproduce`] drives a run: [`jobs`] lists, shards and runs
//! them ([`eamadm_runs::jobs`], resuming by [`eamadm_runs::key`]'s keys from the [`eamadm_runs::store`], showing [`progress`]), [`finish`]
//! streams the store into the outputs: CSV, figures ([`outputs`], drawn by
//! [`eamadm_present::figures`]), and
//! [`claims_report`] writes the verdicts, `final-scores.csv`, `claims.csv`, `datapackage.json`
//! and `REPORT.md` (whose text [`eamadm_present::report`] makes), [`sensitivity_report`] the readings'
//! `sensitivity.csv`, `oracle.csv` and `pretraining.csv` ([`oracle_tables`]), all staged and swapped into the
//! locked output folder by [`eamadm_runs::output_folder`]. [`fixtures`] regenerates and checks
//! `fixtures/` and, with [`readme`], the README's generated parts, showing differences with
//! [`eamadm_present::generated`]. [`test_all`] is the one test command; [`wheel`] checks the wheel users install.
//! Every file
//! goes through [`atomic`].

use std::process::ExitCode;

use clap::Parser as _;

mod claims_report;
mod cli;
mod experiments;
mod family_suite;
mod finish;
mod fixtures;
mod gc;
mod jobs;
mod oracle_tables;
mod outputs;
mod plan;
mod progress;
mod readme;
mod reproduce;
mod sensitivity_report;
mod test_all;
mod tuning_suite;
mod verify;
mod wheel;

// Every file goes through the run crate's atomic writes (`crate::atomic` in the modules).
use eamadm_runs::atomic;

use cli::{Cli, Command};
use plan::Workspace;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let workspace = match Workspace::from_env() {
        Ok(workspace) => workspace,
        Err(error) => {
            print_error(&format!("cannot read the current folder: {error}"));
            return ExitCode::FAILURE;
        }
    };
    let outcome = match cli.command {
        Command::ReproducePaper(args) => reproduce::reproduce_paper(&args, &workspace),
        Command::RegenFixtures(args) => fixtures::regen_fixtures(args.check, &workspace),
        Command::RunJob(args) => reproduce::run_job(&args, &workspace),
        Command::Merge(args) => reproduce::merge(&args, &workspace),
        Command::Verify(args) => verify::verify(&args, &workspace),
        Command::Gc(args) => gc::gc(&args, &workspace),
        Command::Test => test_all::test_all(&workspace),
        Command::Wheel => wheel::wheel(&workspace),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            print_error(&failure.message);
            ExitCode::from(failure.exit_code)
        }
    }
}

/// A command that failed: what to tell and the exit code.
#[derive(Debug)]
pub(crate) struct Failure {
    /// The message, naming what went wrong.
    pub(crate) message: String,
    /// 1 for a failed command, 2 for arguments that cannot work.
    pub(crate) exit_code: u8,
}

impl Failure {
    /// Arguments (or a config) that cannot work: exit code 2.
    pub(crate) fn invalid(error: impl std::fmt::Display) -> Self {
        Self {
            message: error.to_string(),
            exit_code: 2,
        }
    }

    /// A command that failed while running: exit code 1.
    pub(crate) fn failed(error: impl std::fmt::Display) -> Self {
        Self {
            message: error.to_string(),
            exit_code: 1,
        }
    }
}

#[expect(
    clippy::print_stderr,
    reason = "a command-line tool reports its errors on stderr"
)]
fn print_error(message: &str) {
    eprintln!("error: {message}");
}
