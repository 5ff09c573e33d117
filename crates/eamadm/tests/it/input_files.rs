//! Input files are read with bounds (issue 14, item 4): regular files up to
//! `MAX_INPUT_FILE_BYTES` only, so a device never fills memory and a FIFO never hangs.

use std::path::Path;

use eamadm::read_input_file;
use eamadm::{ConfigError, Experiment, ExperimentConfig, MAX_INPUT_FILE_BYTES, PAPER_TASK1_TOML};

fn read_error(path: &Path) -> String {
    match read_input_file(path, "--config").unwrap_err() {
        ConfigError::Read { field, .. } if field == "--config" => {}
        other => panic!("expected a read error naming --config, got {other}"),
    }
    read_input_file(path, "--config").unwrap_err().to_string()
}

#[cfg(unix)]
#[test]
fn devices_are_refused_without_reading_them() {
    let message = read_error(Path::new("/dev/zero"));
    assert!(message.contains("not a regular file"), "{message}");
}

#[cfg(unix)]
#[test]
fn a_fifo_is_refused_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|status| status.success()) {
        // No mkfifo on this system: nothing to test.
        return;
    }
    // Before the fix this open blocked forever (no writer ever comes).
    let message = read_error(&fifo);
    assert!(message.contains("not a regular file"), "{message}");
}

#[test]
fn folders_and_oversized_files_are_refused_and_the_limit_is_inclusive() {
    let dir = tempfile::tempdir().unwrap();
    let message = read_error(dir.path());
    assert!(message.contains("not a regular file"), "{message}");

    let limit = usize::try_from(MAX_INPUT_FILE_BYTES).unwrap();
    let big = dir.path().join("big.toml");
    std::fs::write(&big, vec![b'#'; limit + 1]).unwrap();
    let message = read_error(&big);
    assert!(message.contains("1 MiB"), "{message}");

    std::fs::write(&big, vec![b'#'; limit]).unwrap();
    assert_eq!(read_input_file(&big, "--config").unwrap().len(), limit);
}

#[test]
fn invalid_utf8_is_a_read_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("latin1.toml");
    std::fs::write(&path, b"name = \"caf\xe9\"").unwrap();
    let message = read_error(&path);
    assert!(message.contains("UTF-8"), "{message}");
}

#[cfg(unix)]
#[test]
fn a_task_file_naming_a_device_is_refused_at_loading() {
    let text = PAPER_TASK1_TOML.replacen(
        "kind = \"maze\"\npreset = \"task1\"",
        "kind = \"maze_file\"\npath = \"/dev/zero\"\nrewards = \"task1\"",
        1,
    );
    let config = ExperimentConfig::from_toml_str(&text).unwrap();
    let error = Experiment::new(config).unwrap_err();
    assert_eq!(error.field(), Some("task.path"));
    assert!(error.to_string().contains("not a regular file"), "{error}");
}
