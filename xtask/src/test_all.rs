//! `cargo xtask test`: the one test command. Runs the Rust tests, then the Python package's
//! pytest suite in a virtualenv (`target/py-venv`, made from the package registry with the
//! pinned `crates/eamadm-py/requirements-test.txt` when missing or when those pins change),
//! into which it builds and installs the package with `maturin develop` (the dev profile, so
//! the workspace crates `cargo test` just built are reused). Fails if either suite fails, and
//! when pytest collects no test.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::Failure;
use crate::plan::Workspace;

/// The Python package's folder, relative to the workspace root.
const PY_CRATE: &str = "crates/eamadm-py";
/// The virtualenv, relative to the workspace root.
const VENV: &str = "target/py-venv";
/// Copy of the requirements last installed into the virtualenv.
const INSTALLED_STAMP: &str = "installed-requirements-test.txt";
/// pytest's exit code when it collected no test.
const PYTEST_NO_TESTS: i32 = 5;

/// Runs both suites; the first failure ends the command.
pub(crate) fn test_all(workspace: &Workspace) -> Result<(), Failure> {
    let root = &workspace.root;
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| OsString::from("cargo"));
    announce("cargo test --workspace --locked");
    run(
        Command::new(&cargo)
            .args(["test", "--workspace", "--locked"])
            .current_dir(root),
        "cargo test --workspace --locked",
    )?;

    let venv = root.join(VENV);
    let python = venv.join("bin").join("python");
    if !python.exists() {
        announce(&format!("python3 -m venv {VENV}"));
        run(
            Command::new("python3").args(["-m", "venv"]).arg(&venv),
            "python3 -m venv",
        )?;
    }
    install_requirements(root, &venv, &python)?;

    announce("maturin develop --locked (dev profile)");
    let bin = venv.join("bin");
    let path = prepend_path(&bin)?;
    run(
        Command::new(bin.join("maturin"))
            .args(["develop", "--locked", "--quiet"])
            .current_dir(root.join(PY_CRATE))
            .env("VIRTUAL_ENV", &venv)
            .env("PATH", &path)
            .env("CARGO", &cargo),
        "maturin develop",
    )?;

    announce("pytest crates/eamadm-py/tests");
    let xtask = std::env::current_exe().map_err(Failure::failed)?;
    let status = Command::new(&python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(root.join(PY_CRATE).join("tests"))
        .current_dir(root)
        .env("PATH", &path)
        .env("EAMADM_XTASK", xtask)
        .status()
        .map_err(|error| Failure::failed(format!("cannot start pytest: {error}")))?;
    match status.code() {
        Some(0) => Ok(()),
        Some(PYTEST_NO_TESTS) => Err(Failure::failed(
            "pytest collected no test in crates/eamadm-py/tests",
        )),
        _ => Err(Failure::failed(format!("pytest failed ({status})"))),
    }
}

/// Installs the pinned test requirements unless exactly these are installed already.
fn install_requirements(root: &Path, venv: &Path, python: &Path) -> Result<(), Failure> {
    let requirements = root.join(PY_CRATE).join("requirements-test.txt");
    let wanted = std::fs::read_to_string(&requirements).map_err(|error| {
        Failure::failed(format!("cannot read {}: {error}", requirements.display()))
    })?;
    let stamp = venv.join(INSTALLED_STAMP);
    if std::fs::read_to_string(&stamp).is_ok_and(|installed| installed == wanted) {
        return Ok(());
    }
    announce("pip install -r crates/eamadm-py/requirements-test.txt");
    run(
        Command::new(python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
                "-r",
            ])
            .arg(&requirements),
        "pip install",
    )?;
    crate::atomic::write_atomic(&stamp, wanted.as_bytes()).map_err(Failure::failed)
}

/// `PATH` with `dir` first (maturin and the build find the virtualenv's Python).
fn prepend_path(dir: &Path) -> Result<OsString, Failure> {
    let mut paths: Vec<PathBuf> = vec![dir.to_path_buf()];
    if let Some(path) = std::env::var_os("PATH") {
        paths.extend(std::env::split_paths(&path));
    }
    std::env::join_paths(paths).map_err(Failure::failed)
}

fn announce(what: &str) {
    println!("== {what}");
}

/// Runs `command`; a non-zero exit (or none) is a failure naming `what`.
fn run(command: &mut Command, what: &str) -> Result<(), Failure> {
    let status = command
        .status()
        .map_err(|error| Failure::failed(format!("cannot start {what}: {error}")))?;
    if status.success() {
        Ok(())
    } else {
        Err(Failure::failed(format!("{what} failed ({status})")))
    }
}
