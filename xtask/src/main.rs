//! Project tooling. Run `cargo xtask --help` for the list of commands.
//!
//! - `cargo xtask reproduce-paper [--seeds N] [--task T]... [--method M]... [--config FILE]
//!   [--out DIR] [--quick]` reruns the paper's experiments and writes curves, figures and a report.
//! - `cargo xtask regen-fixtures [--check]` regenerates (or checks) `fixtures/`.
//!
//! Exit codes: 0 success, 1 the command failed (today: the experiment runner has not landed),
//! 2 invalid arguments.
//!
//! Modules: [`cli`] parses, [`plan`] checks the arguments; [`figures`], [`report`],
//! [`resume`], [`progress`] and [`atomic`] are the building blocks of the outputs.

use std::process::ExitCode;

use clap::Parser as _;

mod atomic;
mod cli;
// The experiment runner (crate `eamadm`) has not landed yet, so outside the tests nothing calls
// these modules. `expect` (not `allow`) makes the compiler say when the wiring is done and the
// attribute must go.
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod figures;
mod plan;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod progress;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod report;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod resume;

use cli::{Cli, Command};
use plan::{DEFAULT_METHODS, ReproducePlan, Workspace};

/// Exit code for arguments that cannot work (as clap uses for parse errors).
const EXIT_INVALID_ARGUMENTS: u8 = 2;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let workspace = match Workspace::from_env() {
        Ok(workspace) => workspace,
        Err(error) => {
            print_error(&format!("cannot read the current folder: {error}"));
            return ExitCode::FAILURE;
        }
    };
    match cli.command {
        Command::ReproducePaper(args) => {
            match ReproducePlan::from_args(&args, &DEFAULT_METHODS, &workspace) {
                Ok(plan) => {
                    print!("{}", plan.describe());
                    runner_not_landed()
                }
                Err(error) => {
                    print_error(&error.to_string());
                    ExitCode::from(EXIT_INVALID_ARGUMENTS)
                }
            }
        }
        Command::RegenFixtures(args) => {
            print!("{}", plan::describe_regen_fixtures(args.check, &workspace));
            runner_not_landed()
        }
    }
}

/// Says, honestly, that nothing ran, and fails.
fn runner_not_landed() -> ExitCode {
    print_error(
        "not run: the experiment runner (crate `eamadm`) has not landed yet; \
         nothing was trained and nothing was written",
    );
    ExitCode::FAILURE
}

#[expect(
    clippy::print_stderr,
    reason = "a command-line tool reports its errors on stderr"
)]
fn print_error(message: &str) {
    eprintln!("error: {message}");
}
