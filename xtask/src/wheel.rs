//! `cargo xtask wheel`: the Python package as users install it, without a Rust toolchain.
//!
//! 1. `maturin build --release --locked` (from the test virtualenv `target/py-venv`) builds an
//!    abi3 wheel (`cp39-abi3`, pyo3's `abi3-py39`) into `target/wheels/`, tagged manylinux by
//!    maturin's auditwheel check of the libraries it links;
//! 2. a fresh virtualenv `target/wheel-venv` (removed first) gets the wheel with its `[pandas]`
//!    extra from pip, with a `PATH` that holds no `cargo` or `rustc`, so that pip could not
//!    build the package from source even if it tried;
//! 3. every ```` ```python ```` block of `README.md` runs in that virtualenv, each in a fresh
//!    interpreter in a scratch folder (so `import eamadm` finds the installed wheel, not the
//!    sources) that holds only a `--quick` output of the main job at `target/reproduce-paper`
//!    (made by this binary, for the examples that read one), and must print something;
//! 4. the `--quick` plan is run twice: by this binary (`reproduce-paper --quick`, into a scratch
//!    folder) and from the installed wheel (`eamadm.run` on each of the plan's configs, which
//!    this binary writes out, then `eamadm.report`). The wheel's `final-scores.csv` and
//!    `claims.csv` must equal the main job's byte for byte, and `eamadm.report` of the main
//!    job's folder must equal its `REPORT.md` byte for byte (the figures, and so their captions,
//!    are drawn only by xtask).
//!
//! `cargo xtask test` runs it after the pytest suite.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::Failure;
use crate::plan::Workspace;
use crate::test_all::{announce, run};

/// The Python package's folder, relative to the workspace root.
const PY_CRATE: &str = "crates/eamadm-py";
/// The virtualenv with maturin (made by `cargo xtask test`).
const BUILD_VENV: &str = "target/py-venv";
/// Where the wheel is written.
const WHEELS: &str = "target/wheels";
/// The clean virtualenv the wheel is installed into.
const CLEAN_VENV: &str = "target/wheel-venv";
/// The tag every wheel we ship carries: one wheel for every Python from 3.9 on.
const ABI3_TAG: &str = "-cp39-abi3-";

/// Builds the wheel, installs it into a clean virtualenv without Rust, and runs the README's
/// Python examples there.
pub(crate) fn wheel(workspace: &Workspace) -> Result<(), Failure> {
    let root = &workspace.root;
    let maturin = root.join(BUILD_VENV).join("bin").join("maturin");
    if !maturin.exists() {
        return Err(Failure::failed(format!(
            "{} is missing: run `cargo xtask test` once (it makes {BUILD_VENV} with maturin)",
            maturin.display()
        )));
    }
    let wheels = root.join(WHEELS);
    remove_dir(&wheels)?;
    announce("maturin build --release --locked");
    run(
        Command::new(&maturin)
            .args(["build", "--release", "--locked", "--quiet", "--out"])
            .arg(&wheels)
            .current_dir(root.join(PY_CRATE))
            .env("VIRTUAL_ENV", root.join(BUILD_VENV))
            .env("PATH", path_with(&root.join(BUILD_VENV).join("bin"), true)?),
        "maturin build",
    )?;
    let wheel = the_wheel(&wheels)?;
    let name = wheel
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if !(name.contains(ABI3_TAG) && name.contains("manylinux")) {
        return Err(Failure::failed(format!(
            "the wheel {name} is not an abi3 manylinux wheel (want `{ABI3_TAG}` and a manylinux tag)"
        )));
    }
    println!("built {name}");

    let venv = root.join(CLEAN_VENV);
    remove_dir(&venv)?;
    let no_rust = path_with(&venv.join("bin"), false)?;
    announce(&format!(
        "python3 -m venv {CLEAN_VENV} (PATH without cargo or rustc)"
    ));
    run(
        Command::new("python3")
            .args(["-m", "venv"])
            .arg(&venv)
            .env("PATH", &no_rust),
        "python3 -m venv",
    )?;
    let python = venv.join("bin").join("python");
    announce(&format!("pip install {name}[pandas]"));
    let mut requirement = OsString::from(wheel.as_os_str());
    requirement.push("[pandas]");
    run(
        Command::new(&python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
                "--only-binary=:all:",
            ])
            .arg(&requirement)
            .env("PATH", &no_rust)
            .env_remove("CARGO")
            .env_remove("RUSTC"),
        "pip install of the wheel",
    )?;

    let readme = std::fs::read_to_string(root.join("README.md"))
        .map_err(|error| Failure::failed(format!("cannot read README.md: {error}")))?;
    let snippets = python_blocks(&readme);
    if snippets.is_empty() {
        return Err(Failure::failed("README.md has no ```python block to run"));
    }
    let scratch = tempfile::tempdir().map_err(Failure::failed)?;
    // The examples that read the main job's output find a `--quick` one where the README
    // says it is, `target/reproduce-paper`, made by this very binary.
    announce("reproduce-paper --quick --out target/reproduce-paper (for the README's examples)");
    let xtask = std::env::current_exe().map_err(Failure::failed)?;
    run(
        Command::new(&xtask)
            .args(["reproduce-paper", "--quick", "--out"])
            .arg(scratch.path().join("target").join("reproduce-paper"))
            .stdout(std::process::Stdio::null()),
        "reproduce-paper --quick",
    )?;
    for (index, snippet) in snippets.iter().enumerate() {
        announce(&format!(
            "README python block {} of {} (installed wheel)",
            index + 1,
            snippets.len()
        ));
        let output = Command::new(&python)
            .args(["-c", snippet])
            .current_dir(scratch.path())
            .env("PATH", &no_rust)
            .env_remove("PYTHONPATH")
            .output()
            .map_err(|error| Failure::failed(format!("cannot start python: {error}")))?;
        let stdout = String::from_utf8_lossy(&output.stdout);
        if !output.status.success() || stdout.trim().is_empty() {
            return Err(Failure::failed(format!(
                "README python block {} failed from the installed wheel ({}):\n{snippet}\n{stdout}{}",
                index + 1,
                output.status,
                String::from_utf8_lossy(&output.stderr)
            )));
        }
    }
    println!(
        "the wheel installs without Rust and runs the README's {} Python examples",
        snippets.len()
    );
    quick_plan_from_the_wheel(&python, &no_rust, scratch.path())
}

/// The Python run of step 4: `argv[1]` holds the main job's folder, `argv[2:]` the plan's
/// configs in run order, each as `path=label,label,…` with its methods in job order.
const QUICK_FROM_PYTHON: &str = r#"
import pathlib, sys
import eamadm

folder = pathlib.Path(sys.argv[1])
def run(argument):
    path, labels = argument.rsplit("=", 1)
    return eamadm.run(pathlib.Path(path), methods=labels.split(","))
results = [run(argument) for argument in sys.argv[2:]]
ours = eamadm.report(results, quick=True)
from_folder = eamadm.report(folder)
def same(name, text):
    if text != (folder / name).read_text(encoding="utf-8"):
        sys.exit(f"{name}: the wheel's text differs from the main job's")
same("final-scores.csv", ours.scores_csv)
same("claims.csv", ours.claims_csv)
same("REPORT.md", from_folder.markdown)
same("claims.csv", from_folder.claims_csv)
print(f"the wheel reproduces the --quick plan: {len(results)} experiments, "
      f"{len(ours.verdicts)} rows of claims.csv")
"#;

/// Step 4: the `--quick` plan from this binary and from the installed wheel, compared.
fn quick_plan_from_the_wheel(
    python: &Path,
    path: &OsString,
    scratch: &Path,
) -> Result<(), Failure> {
    let out = scratch.join("quick");
    announce("xtask reproduce-paper --quick (the main job)");
    let xtask = std::env::current_exe().map_err(Failure::failed)?;
    run(
        Command::new(&xtask)
            .args(["reproduce-paper", "--quick", "--out"])
            .arg(&out),
        "reproduce-paper --quick",
    )?;
    let planned = crate::experiments::plan_experiments(
        &crate::cli::Task::ALL,
        false,
        None,
        crate::plan::QUICK_SEEDS,
        true,
        crate::cli::Readings::All,
    )
    .map_err(Failure::failed)?;
    // The main job runs (and lists) each experiment's methods in the order of
    // `default_methods`, which need not be the config's.
    let order = crate::plan::default_methods();
    let mut configs = Vec::with_capacity(planned.len());
    // The readings' reruns feed only `sensitivity.csv`, which `eamadm.report(folder)` reads
    // back; the runs compared here are the presets'.
    for experiment in planned.iter().filter(|e| e.reading.is_none()) {
        let file = scratch.join(format!("{}.toml", experiment.name));
        let text = experiment
            .config()
            .to_toml_string()
            .map_err(Failure::failed)?;
        std::fs::write(&file, text).map_err(|error| {
            Failure::failed(format!("cannot write {}: {error}", file.display()))
        })?;
        let labels: Vec<&str> = order
            .iter()
            .filter(|label| experiment.config().method(label).is_some())
            .map(String::as_str)
            .collect();
        let mut argument = file.into_os_string();
        argument.push(format!("={}", labels.join(",")));
        configs.push(argument);
    }
    announce("the --quick plan from the installed wheel (eamadm.run, eamadm.report)");
    run(
        Command::new(python)
            .args(["-c", QUICK_FROM_PYTHON])
            .arg(&out)
            .args(&configs)
            .current_dir(scratch)
            .env("PATH", path)
            .env_remove("PYTHONPATH"),
        "the --quick plan from the wheel",
    )
}

/// The code of every ```` ```python ```` block of `markdown`, in order.
fn python_blocks(markdown: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in markdown.lines() {
        match &mut current {
            None if line.trim_end() == "```python" => current = Some(String::new()),
            None => {}
            Some(_) if line.trim_end() == "```" => blocks.extend(current.take()),
            Some(block) => {
                block.push_str(line);
                block.push('\n');
            }
        }
    }
    blocks
}

/// The one `.whl` in `folder`.
fn the_wheel(folder: &Path) -> Result<PathBuf, Failure> {
    let wheels: Vec<PathBuf> = std::fs::read_dir(folder)
        .map_err(|error| Failure::failed(format!("cannot read {}: {error}", folder.display())))?
        .flatten()
        .map(|entry| entry.path())
        .filter(|path| path.extension().is_some_and(|e| e == "whl"))
        .collect();
    match wheels.as_slice() {
        [one] => Ok(one.clone()),
        other => Err(Failure::failed(format!(
            "expected one wheel in {}, found {}",
            folder.display(),
            other.len()
        ))),
    }
}

/// `PATH` with `first` in front; without `keep_rust`, every folder holding `cargo` or `rustc`
/// is left out.
fn path_with(first: &Path, keep_rust: bool) -> Result<OsString, Failure> {
    let mut paths = vec![first.to_path_buf()];
    if let Some(path) = std::env::var_os("PATH") {
        let dirs = std::env::split_paths(&path).collect();
        paths.extend(if keep_rust { dirs } else { without_rust(dirs) });
    }
    std::env::join_paths(paths).map_err(Failure::failed)
}

/// `dirs` less every folder that holds a `cargo` or `rustc`.
fn without_rust(dirs: Vec<PathBuf>) -> Vec<PathBuf> {
    dirs.into_iter()
        .filter(|dir| !(dir.join("cargo").exists() || dir.join("rustc").exists()))
        .collect()
}

fn remove_dir(dir: &Path) -> Result<(), Failure> {
    match std::fs::remove_dir_all(dir) {
        Ok(()) => Ok(()),
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(error) => Err(Failure::failed(format!(
            "cannot remove {}: {error}",
            dir.display()
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn python_blocks_are_found_in_order_and_other_blocks_skipped() {
        let text = "a\n```python\nprint(1)\n```\n```sh\nls\n```\n```python\nx = 2\nprint(x)\n```\n";
        assert_eq!(python_blocks(text), ["print(1)\n", "x = 2\nprint(x)\n"]);
        assert!(python_blocks("```python\nopen\n").is_empty());
    }

    #[test]
    fn the_path_without_rust_drops_folders_with_cargo_or_rustc() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let rust = dir.path().join("rust");
        let plain = dir.path().join("plain");
        let toolchain = dir.path().join("toolchain");
        for folder in [&rust, &plain, &toolchain] {
            std::fs::create_dir_all(folder).expect("mkdir");
        }
        std::fs::write(rust.join("cargo"), "").expect("write");
        std::fs::write(toolchain.join("rustc"), "").expect("write");
        let kept = without_rust(vec![rust, plain.clone(), toolchain]);
        assert_eq!(kept, [plain]);
    }
}
