//! Integration tests of the `xtask` binary, one module per subject.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

mod architecture;
mod arguments;
mod claims_csv;
mod concurrent_store;
mod family;
mod figure_checks;
mod fixtures;
mod gc;
mod jobs;
mod kill_resume;
mod markdown;
mod plan_text;
mod readings;
mod reproduce;
mod shards;
mod slurm;
mod store_faults;
mod tidy;
mod tuning_suite;
mod verify;

/// The standard output of a command that must have succeeded (its standard error shown if not).
pub(crate) fn succeeds(output: &Output) -> String {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// Every file under `folder`: relative path → bytes (the outputs two runs must share).
pub(crate) fn tree(folder: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut stack = vec![folder.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("a readable folder") {
            let path = entry.expect("a folder entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let name = path
                    .strip_prefix(folder)
                    .expect("under the folder")
                    .display()
                    .to_string();
                files.insert(name, std::fs::read(&path).expect("a readable file"));
            }
        }
    }
    files
}

/// A temporary folder the `xtask` binary is started in (relative paths are taken from it).
pub(crate) struct Folder {
    _dir: tempfile::TempDir,
    root: std::path::PathBuf,
}

impl Folder {
    /// A new empty folder.
    pub(crate) fn new() -> Self {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let root = dir.path().canonicalize().expect("a real path");
        Self { _dir: dir, root }
    }

    /// `relative` under the folder.
    pub(crate) fn path(&self, relative: &str) -> std::path::PathBuf {
        self.root.join(relative)
    }

    /// Runs `xtask args` in the folder, without input.
    pub(crate) fn xtask<S: AsRef<std::ffi::OsStr>>(&self, args: &[S]) -> Output {
        std::process::Command::new(env!("CARGO_BIN_EXE_xtask"))
            .args(args)
            .current_dir(&self.root)
            .stdin(std::process::Stdio::null())
            .output()
            .expect("xtask starts")
    }

    /// Runs `xtask args` in the folder; it must succeed. Its standard output.
    pub(crate) fn succeeds<S: AsRef<std::ffi::OsStr>>(&self, args: &[S]) -> String {
        succeeds(&self.xtask(args))
    }
}

/// The standard error of a command that must have failed with exit code `code`.
pub(crate) fn fails(output: &Output, code: i32) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(code), "{stderr}");
    stderr
}

/// Both folders hold the same files with the same bytes.
pub(crate) fn assert_same_tree(a: &Path, b: &Path) {
    let (a, b) = (tree(a), tree(b));
    assert_eq!(
        a.keys().collect::<Vec<_>>(),
        b.keys().collect::<Vec<_>>(),
        "the same files"
    );
    for (name, bytes) in &a {
        assert!(b[name] == *bytes, "{name} differs");
    }
}
