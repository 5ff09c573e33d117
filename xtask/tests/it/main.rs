//! Integration tests of the `xtask` binary, one module per subject.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

mod architecture;
mod concurrent_store;
mod family;
mod figure_checks;
mod gc;
mod jobs;
mod kill_resume;
mod markdown;
mod readings;
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
