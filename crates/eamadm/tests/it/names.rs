//! Experiment names and method labels become file and folder names, so they must be safe slugs
//! and not the names the output folder uses itself (issue 14, item 3).

use eamadm::{ExperimentConfig, PAPER_TASK1_TOML, RESERVED_NAMES, is_safe_slug};

fn with_name(name: &str) -> String {
    PAPER_TASK1_TOML.replacen("name = \"task1\"", &format!("name = {name:?}"), 1)
}

fn with_label(label: &str) -> String {
    PAPER_TASK1_TOML.replacen("label = \"softmax\"", &format!("label = {label:?}"), 1)
}

const UNSAFE: &[&str] = &[
    "..",
    ".",
    "runs",
    "Runs",
    "REPORT.md",
    "report.md",
    "results.json",
    "datapackage.json",
    "DataPackage.json",
    ".hidden",
    "a/b",
    "..\\x",
    "x.",
    "",
    "con",
    "NUL",
    "a b",
    "-starts-with-dash",
    "_x",
];

#[test]
fn names_that_escape_or_collide_with_outputs_are_refused() {
    for name in UNSAFE {
        assert!(!is_safe_slug(name), "{name:?}");
        let error = ExperimentConfig::from_toml_str(&with_name(name)).unwrap_err();
        assert_eq!(error.field(), Some("name"), "{name:?}: {error}");
        let error = ExperimentConfig::from_toml_str(&with_label(name)).unwrap_err();
        assert_eq!(error.field(), Some("methods[3].label"), "{name:?}: {error}");
    }
}

#[test]
fn ordinary_slugs_are_accepted() {
    for name in ["task1", "my-run_2", "v1.2", "A", "x..y"] {
        assert!(is_safe_slug(name), "{name:?}");
        ExperimentConfig::from_toml_str(&with_name(name)).unwrap();
    }
    assert!(
        RESERVED_NAMES
            .iter()
            .all(|reserved| !is_safe_slug(reserved))
    );
}
