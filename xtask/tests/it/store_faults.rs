//! The store under faults and hostile writers (issue 35), through the `xtask` binary: a closed
//! pipe, run-jobs beside lock holders, a FIFO where the manifest belongs.

use std::process::{Command, Stdio};

fn xtask() -> Command {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
}

/// `reproduce-paper --list-jobs | head -1`: the reader leaves after one line and the listing
/// ends quietly (9dc06af panicked "Broken pipe", exit 101).
#[test]
fn list_jobs_into_a_closed_pipe_exits_quietly() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut child = xtask()
        .arg("reproduce-paper")
        .arg("--list-jobs")
        .arg("--out")
        .arg(dir.path().join("out"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("xtask starts");
    // Read one line, as `head -1` does, then close the pipe: the 2000 lines of the default plan
    // are far more than a pipe holds, so the child writes into a closed pipe.
    let mut stdout = std::io::BufReader::new(child.stdout.take().expect("piped"));
    let mut first = String::new();
    std::io::BufRead::read_line(&mut stdout, &mut first).expect("a line");
    assert!(first.starts_with("{\"key\":"), "{first}");
    drop(stdout);
    let output = child.wait_with_output().expect("the child ends");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success() || output.status.code().is_none(),
        "{:?}: {stderr}",
        output.status
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}
