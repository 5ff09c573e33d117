//! The figure checks ([`eamadm_present::checks`]) on the figures the main job writes: every
//! SVG of a `reproduce-paper --quick` run's output folder (black box: the built binary), or of
//! a folder named by `EAMADM_FIGURES`.

use std::path::Path;
use std::process::{Command, Stdio};

use eamadm_present::checks::check_figures;

use crate::tree;

/// Every SVG file under `folder`, relative path → text.
fn svg_files(folder: &Path) -> Vec<(String, String)> {
    tree(folder)
        .into_iter()
        .filter(|(name, _)| name.ends_with(".svg"))
        .map(|(name, bytes)| (name, String::from_utf8(bytes).expect("an SVG is UTF-8")))
        .collect()
}

/// Every figure of the default `--quick` run passes every check.
#[test]
fn every_figure_of_the_quick_run_passes_the_checks() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("out");
    let status = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["reproduce-paper", "--quick", "--keep-trajectories=figures"])
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::null())
        .status()
        .expect("xtask starts");
    assert!(status.success(), "{status}");
    let figures = svg_files(&out);
    assert!(figures.len() >= 24, "{} figures", figures.len());
    let problems = check_figures(&figures);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The same checks on any output folder, e.g. a default run's:
/// `EAMADM_FIGURES=target/reproduce-paper cargo test -p xtask --test it figure_checks -- --ignored`.
#[test]
#[ignore = "checks the output folder named by EAMADM_FIGURES"]
fn every_figure_of_a_named_folder_passes_the_checks() {
    let folder = std::env::var("EAMADM_FIGURES").expect("set EAMADM_FIGURES to an output folder");
    let figures = svg_files(Path::new(&folder));
    assert!(!figures.is_empty(), "no SVG under {folder}");
    let problems = check_figures(&figures);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
