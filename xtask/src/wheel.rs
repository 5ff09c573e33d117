//! `cargo xtask wheel`: the Python package as users install it, without a Rust toolchain.
//! Every folder it makes is in the target folder, `<target>` (`CARGO_TARGET_DIR` or `target/`).
//!
//! 1. `maturin build --release --locked` (from the virtualenv `<target>/py-venv`, which
//!    `cargo xtask test` fills; on a fresh clone this command makes it and installs the pinned
//!    maturin of `crates/eamadm-py/requirements-test.txt` into it) builds an abi3 wheel
//!    (`cp39-abi3`, pyo3's `abi3-py39`) into `<target>/wheels/`, tagged manylinux by maturin's
//!    auditwheel check of the libraries it links; its metadata must carry the README and the
//!    project URLs;
//! 2. a fresh virtualenv `<target>/wheel-venv` (removed first) gets the wheel with its `[pandas]`
//!    extra from pip, with a `PATH` that holds no `cargo` or `rustc`, so that pip could not
//!    build the package from source even if it tried;
//! 3. every ```` ```python ```` block of `README.md` runs in that virtualenv, each in a fresh
//!    interpreter in a scratch folder (so `import eamadm` finds the installed wheel, not the
//!    sources) that holds only a `--quick` output of the main job at `target/reproduce-paper`
//!    (made by this binary, for the examples that read one), and must print something;
//! 4. the `--quick` plan is run twice: by this binary (`reproduce-paper --quick`, into a scratch
//!    folder) and from the installed wheel (`python -m eamadm reproduce --quick`, the package's
//!    own plan). The wheel's `final-scores.csv`, `claims.csv` and `datapackage.json` must equal
//!    the main job's byte for byte, and `python -m eamadm report` of the main job's folder must
//!    equal its `REPORT.md` byte for byte (the figures, and so their captions, are drawn only by
//!    xtask).
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
/// Where the wheel is written, in the target folder.
const WHEELS: &str = "wheels";
/// The clean virtualenv the wheel is installed into, in the target folder.
const CLEAN_VENV: &str = "wheel-venv";
/// The tag every wheel we ship carries: one wheel for every Python from 3.9 on.
const ABI3_TAG: &str = "-cp39-abi3-";

/// Builds the wheel, installs it into a clean virtualenv without Rust, and runs the README's
/// Python examples there.
pub(crate) fn wheel(workspace: &Workspace) -> Result<(), Failure> {
    let root = &workspace.root;
    let target = workspace.target_dir();
    let build_venv = target.join(crate::test_all::VENV);
    let maturin = build_venv.join("bin").join("maturin");
    if !maturin.exists() {
        // A fresh clone: the build virtualenv with the pinned maturin only (`cargo xtask test`
        // adds the rest of the test requirements later).
        let python = crate::test_all::make_venv(&build_venv)?;
        let pin = crate::test_all::pinned(root, "maturin")?;
        announce(&format!("pip install {pin}"));
        run(
            Command::new(&python).args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--disable-pip-version-check",
                &pin,
            ]),
            "pip install maturin",
        )?;
    }
    let wheels = target.join(WHEELS);
    remove_dir(&wheels)?;
    announce("maturin build --release --locked");
    run(
        Command::new(&maturin)
            .args(["build", "--release", "--locked", "--quiet", "--out"])
            .arg(&wheels)
            .current_dir(root.join(PY_CRATE))
            .env("VIRTUAL_ENV", &build_venv)
            .env("PATH", path_with(&build_venv.join("bin"), true)?),
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
    check_metadata(&wheel)?;

    let venv = target.join(CLEAN_VENV);
    remove_dir(&venv)?;
    let no_rust = path_with(&venv.join("bin"), false)?;
    announce(&format!(
        "python3 -m venv {} (PATH without cargo or rustc)",
        venv.display()
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

/// Step 4: the `--quick` plan from this binary and from the installed wheel's command line,
/// compared.
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
    let python_m = |args: &[&std::ffi::OsStr], what: &str| {
        let output = Command::new(python)
            .args(["-m", "eamadm"])
            .args(args)
            .current_dir(scratch)
            .env("PATH", path)
            .env_remove("PYTHONPATH")
            .output()
            .map_err(|error| Failure::failed(format!("cannot start python: {error}")))?;
        if output.status.success() {
            Ok(output.stdout)
        } else {
            Err(Failure::failed(format!(
                "{what} failed from the installed wheel ({}):\n{}",
                output.status,
                String::from_utf8_lossy(&output.stderr)
            )))
        }
    };
    announce("python -m eamadm --help (installed wheel)");
    python_m(&["--help".as_ref()], "python -m eamadm --help")?;
    announce("python -m eamadm reproduce --quick (installed wheel)");
    let ours = scratch.join("quick-python");
    python_m(
        &[
            "reproduce".as_ref(),
            ours.as_os_str(),
            "--quick".as_ref(),
            "--no-progress".as_ref(),
        ],
        "python -m eamadm reproduce --quick",
    )?;
    let read = |path: &Path| {
        std::fs::read(path)
            .map_err(|error| Failure::failed(format!("cannot read {}: {error}", path.display())))
    };
    for name in [
        eamadm::output_names::FINAL_SCORES,
        eamadm::output_names::CLAIMS,
        eamadm::output_names::DATA_PACKAGE,
    ] {
        if read(&ours.join(name))? != read(&out.join(name))? {
            return Err(Failure::failed(format!(
                "{name}: `python -m eamadm reproduce --quick` from the wheel differs from the \
                 main job's"
            )));
        }
    }
    announce("python -m eamadm report <the main job's folder> (installed wheel)");
    let report = python_m(
        &["report".as_ref(), out.as_os_str()],
        "python -m eamadm report",
    )?;
    if report != read(&out.join(eamadm::output_names::REPORT))? {
        return Err(Failure::failed(
            "REPORT.md: `python -m eamadm report` from the wheel differs from the main job's",
        ));
    }
    println!(
        "the wheel reproduces the --quick plan's tables and renders its REPORT.md byte for byte"
    );
    Ok(())
}

/// The wheel's metadata (`*.dist-info/METADATA`, read with Python's `zipfile`) must carry the
/// README as its description and the project URLs.
fn check_metadata(wheel: &Path) -> Result<(), Failure> {
    let script = "import sys, zipfile\n\
        wheel = zipfile.ZipFile(sys.argv[1])\n\
        name = next(n for n in wheel.namelist() if n.endswith('.dist-info/METADATA'))\n\
        sys.stdout.write(wheel.read(name).decode('utf-8'))\n";
    let output = Command::new("python3")
        .args(["-c", script])
        .arg(wheel)
        .output()
        .map_err(|error| Failure::failed(format!("cannot start python3: {error}")))?;
    if !output.status.success() {
        return Err(Failure::failed(format!(
            "cannot read the metadata of {}: {}",
            wheel.display(),
            String::from_utf8_lossy(&output.stderr)
        )));
    }
    let metadata = String::from_utf8_lossy(&output.stdout);
    let missing = metadata_missing(&metadata);
    if missing.is_empty() {
        Ok(())
    } else {
        Err(Failure::failed(format!(
            "the wheel's metadata lacks {}",
            missing.join(", ")
        )))
    }
}

/// What a wheel's `METADATA` text lacks of what we ship: the README (Markdown) as its
/// description, the project URLs, the typing classifier.
fn metadata_missing(metadata: &str) -> Vec<&'static str> {
    let mut missing = Vec::new();
    if !metadata.contains("Description-Content-Type: text/markdown") {
        missing.push("the README as a Markdown description");
    }
    if !metadata.contains("# eamadm (Python)") {
        missing.push("the package README's text");
    }
    if !metadata.contains("Project-URL: ") {
        missing.push("the project URLs");
    }
    if !metadata.contains("Classifier: Typing :: Typed") {
        missing.push("the `Typing :: Typed` classifier");
    }
    missing
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
    fn metadata_without_readme_or_urls_is_named() {
        let full = "Metadata-Version: 2.4\nClassifier: Typing :: Typed\n\
                    Project-URL: Paper, https://doi.org/x\n\
                    Description-Content-Type: text/markdown; charset=UTF-8\n\n# eamadm (Python)\n";
        assert!(metadata_missing(full).is_empty());
        assert_eq!(metadata_missing("Metadata-Version: 2.4\n").len(), 4);
    }

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
