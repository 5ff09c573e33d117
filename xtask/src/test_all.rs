//! `cargo xtask test`: the one test command. Runs the Rust tests, `regen-fixtures --check`
//! (the README's generated parts and `fixtures/` against the code), then the Python package's
//! pytest suite in a virtualenv (`<target>/py-venv`, `<target>` being `CARGO_TARGET_DIR` or
//! `target/`, made from the package registry with the pinned
//! `crates/eamadm-py/requirements-test.txt` when missing or when those pins change), into which
//! it builds and installs the package with `maturin develop` (the dev profile, so the workspace
//! crates `cargo test` just built are reused). The suite includes `mypy --strict` and
//! `stubtest` of the package (`tests/test_typing.py`). Then `cargo xtask wheel` (the release
//! wheel, installed without Rust, running the README's Python examples). Fails if any step
//! fails, and when pytest collects no test.
//!
//! A Rust test that cannot run here (the SLURM test without a cluster) returns early, which
//! libtest prints as "ok"; such a test leaves a note in `target/tmp/skipped-tests/` (named
//! after the test, holding the reason), and this command prints every note by name after the
//! Rust tests, so a skip is never mistaken for a pass. Under `CI=true` those tests fail instead.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::Failure;
use crate::plan::Workspace;

/// The Python package's folder, relative to the workspace root.
const PY_CRATE: &str = "crates/eamadm-py";
/// The virtualenv, in the target folder ([`Workspace::target_dir`]).
pub(crate) const VENV: &str = "py-venv";
/// Copy of the requirements last installed into the virtualenv.
const INSTALLED_STAMP: &str = "installed-requirements-test.txt";
/// pytest's exit code when it collected no test.
const PYTEST_NO_TESTS: i32 = 5;

/// Runs both suites; the first failure ends the command.
pub(crate) fn test_all(workspace: &Workspace) -> Result<(), Failure> {
    let root = &workspace.root;
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| OsString::from("cargo"));
    let skipped = workspace.target_dir().join("tmp").join("skipped-tests");
    // Notes of an earlier run would list tests that ran this time.
    match std::fs::remove_dir_all(&skipped) {
        Ok(()) => {}
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => {}
        Err(error) => {
            return Err(Failure::failed(format!(
                "cannot clear {}: {error}",
                skipped.display()
            )));
        }
    }
    announce("cargo test --workspace --locked");
    run(
        Command::new(&cargo)
            .args(["test", "--workspace", "--locked"])
            .current_dir(root),
        "cargo test --workspace --locked",
    )?;
    print!("{}", skipped_summary(&skipped));

    // The README's verdicts, answer and figure, and fixtures/, against the code's output now: a
    // default run in release (about 25 s of CPU) plus the reference runs.
    announce("cargo xtask regen-fixtures --check");
    crate::fixtures::regen_fixtures(true, workspace)?;

    let venv = workspace.target_dir().join(VENV);
    let python = make_venv(&venv)?;
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
        Some(0) => crate::wheel::wheel(workspace),
        Some(PYTEST_NO_TESTS) => Err(Failure::failed(
            "pytest collected no test in crates/eamadm-py/tests",
        )),
        _ => Err(Failure::failed(format!("pytest failed ({status})"))),
    }
}

/// The virtualenv `venv` (made with `python3 -m venv` when missing); returns its Python.
pub(crate) fn make_venv(venv: &Path) -> Result<PathBuf, Failure> {
    let python = venv.join("bin").join("python");
    if !python.exists() {
        announce(&format!("python3 -m venv {}", venv.display()));
        run(
            Command::new("python3").args(["-m", "venv"]).arg(venv),
            "python3 -m venv",
        )?;
    }
    Ok(python)
}

/// The pinned requirement of `package` in the test requirements (`maturin==1.16.0`).
pub(crate) fn pinned(root: &Path, package: &str) -> Result<String, Failure> {
    let requirements = root.join(PY_CRATE).join("requirements-test.txt");
    let text = std::fs::read_to_string(&requirements).map_err(|error| {
        Failure::failed(format!("cannot read {}: {error}", requirements.display()))
    })?;
    pin_in(&text, package).ok_or_else(|| {
        Failure::failed(format!(
            "{} pins no {package} (a line `{package}==<version>`)",
            requirements.display()
        ))
    })
}

/// The line `package==version` of a requirements text.
fn pin_in(text: &str, package: &str) -> Option<String> {
    text.lines()
        .map(str::trim)
        .find(|line| {
            line.strip_prefix(package)
                .is_some_and(|rest| rest.starts_with("=="))
        })
        .map(str::to_owned)
}

/// The summary of the skip notes in `folder`: one line per skipped test, by name, with its
/// reason, sorted; empty when no test skipped.
fn skipped_summary(folder: &Path) -> String {
    let mut notes: Vec<(String, String)> = std::fs::read_dir(folder)
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|entry| {
            let name = entry.file_name().to_string_lossy().into_owned();
            let name = name.strip_suffix(".txt")?.to_owned();
            let reason = std::fs::read_to_string(entry.path()).unwrap_or_default();
            Some((name, reason.trim().to_owned()))
        })
        .collect();
    notes.sort();
    if notes.is_empty() {
        return String::new();
    }
    let mut text = format!(
        "== SKIPPED: {} test(s) printed \"ok\" above but did not run:\n",
        notes.len()
    );
    for (name, reason) in notes {
        text.push_str(&format!("   skipped {name}: {reason}\n"));
    }
    text
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
    announce(&format!(
        "pip install -r crates/eamadm-py/requirements-test.txt (into {})",
        venv.display()
    ));
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

pub(crate) fn announce(what: &str) {
    println!("== {what}");
}

/// Runs `command`; a non-zero exit (or none) is a failure naming `what`.
pub(crate) fn run(command: &mut Command, what: &str) -> Result<(), Failure> {
    let status = command
        .status()
        .map_err(|error| Failure::failed(format!("cannot start {what}: {error}")))?;
    if status.success() {
        Ok(())
    } else {
        Err(Failure::failed(format!("{what} failed ({status})")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pin_is_found_by_its_package_name() {
        let text = "# comment\nmaturin==1.16.0\nmaturin-extra==2\n  numpy==2.4.6\n";
        assert_eq!(pin_in(text, "maturin").as_deref(), Some("maturin==1.16.0"));
        assert_eq!(pin_in(text, "numpy").as_deref(), Some("numpy==2.4.6"));
        assert_eq!(pin_in(text, "pandas"), None);
        let root = Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .expect("the workspace");
        assert!(
            pinned(root, "maturin")
                .expect("the file pins maturin")
                .starts_with("maturin==")
        );
    }

    #[test]
    fn the_summary_names_each_skipped_test_with_its_reason() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        assert_eq!(skipped_summary(&dir.path().join("absent")), "");
        assert_eq!(skipped_summary(dir.path()), "");
        std::fs::write(dir.path().join("xtask it::b.txt"), "no cluster\n").expect("write");
        std::fs::write(dir.path().join("xtask it::a.txt"), "no sbatch\n").expect("write");
        assert_eq!(
            skipped_summary(dir.path()),
            "== SKIPPED: 2 test(s) printed \"ok\" above but did not run:\n   \
             skipped xtask it::a: no sbatch\n   skipped xtask it::b: no cluster\n"
        );
    }
}
