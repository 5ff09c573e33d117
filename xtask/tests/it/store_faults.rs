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

/// A tiny plan: 2 methods × 4 seeds of Task I, shortened by --quick, without the readings.
const PLAN: [&str; 11] = [
    "--quick",
    "--task",
    "task1",
    "--method",
    "epsilon-greedy",
    "--method",
    "softmax",
    "--seeds",
    "4",
    "--readings",
    "none",
];

fn keys(out: &std::path::Path) -> Vec<String> {
    let listed = xtask()
        .arg("reproduce-paper")
        .args(PLAN)
        .arg("--out")
        .arg(out)
        .arg("--list-jobs")
        .output()
        .expect("xtask starts");
    assert!(listed.status.success());
    String::from_utf8(listed.stdout)
        .expect("UTF-8")
        .lines()
        .map(|line| {
            let value: serde_json::Value = serde_json::from_str(line).expect("a JSON line");
            value["key"].as_str().expect("a key").to_owned()
        })
        .collect()
}

/// `run-job`s beside holders of the folder's lock (`reproduce-paper` and `merge`, whose
/// sweeps remove the temporary files of dead writers), every writer stretched by the test hook
/// between making its temporary file and locking it (what a delayed writer does): no `run-job`
/// fails and no run is lost. On 9dc06af the holder's sweep deleted such a file before its
/// writer locked it: the `run-job` exited 1 and its run was lost.
#[test]
fn run_jobs_beside_lock_holders_lose_no_run() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("out");
    let keys = keys(&out);
    assert_eq!(keys.len(), 8);
    for round in 0..3 {
        let holders: Vec<std::process::Child> = (0..2)
            .map(|i| {
                let mut holder = xtask();
                holder.arg("reproduce-paper").arg("--quick");
                holder.args(["--task", "task1", "--method", "softmax", "--seeds", "2"]);
                holder.args(["--readings", "none", "--runs-only", "--wait", "--out"]);
                holder.arg(&out);
                if i == 1 {
                    holder.env("EAMADM_TEST_TEMP_LOCK_DELAY_MS", "40");
                }
                holder
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .expect("xtask starts")
            })
            .collect();
        let jobs: Vec<(String, std::process::Child)> = keys
            .iter()
            .map(|key| {
                let child = xtask()
                    .arg("run-job")
                    .arg("--key")
                    .arg(key)
                    .args(PLAN)
                    .arg("--out")
                    .arg(&out)
                    .env("EAMADM_TEST_TEMP_LOCK_DELAY_MS", "150")
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .expect("xtask starts");
                (key.clone(), child)
            })
            .collect();
        for (key, child) in jobs {
            let output = child.wait_with_output().expect("the child ends");
            assert!(
                output.status.success(),
                "round {round}: run-job {key} failed: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        for holder in holders {
            let output = holder.wait_with_output().expect("the child ends");
            assert!(
                output.status.success(),
                "round {round}: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        // Every run is stored: the merge accepts the whole plan.
        let merged = xtask()
            .arg("merge")
            .args(PLAN)
            .arg("--out")
            .arg(dir.path().join(format!("merged{round}")))
            .arg(&out)
            .output()
            .expect("xtask starts");
        assert!(
            merged.status.success(),
            "round {round}: {}",
            String::from_utf8_lossy(&merged.stderr)
        );
        std::fs::remove_dir_all(out.join("runs")).expect("the store can be removed");
    }
}

/// The highest resident memory (`VmHWM`, KiB) seen of a running process, polled until it
/// exits; with its output.
#[cfg(target_os = "linux")]
fn peak_memory_kib(mut command: Command) -> (u64, std::process::Output) {
    let child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("xtask starts");
    let status = std::path::PathBuf::from(format!("/proc/{}/status", child.id()));
    let peak = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let poller = {
        let (peak, done) = (peak.clone(), done.clone());
        std::thread::spawn(move || {
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                if let Ok(text) = std::fs::read_to_string(&status) {
                    let kib = text
                        .lines()
                        .find_map(|line| line.strip_prefix("VmHWM:"))
                        .and_then(|rest| rest.trim().trim_end_matches("kB").trim().parse().ok())
                        .unwrap_or(0);
                    peak.fetch_max(kib, std::sync::atomic::Ordering::Relaxed);
                }
                std::thread::sleep(std::time::Duration::from_millis(2));
            }
        })
    };
    let output = child.wait_with_output().expect("the child ends");
    done.store(true, std::sync::atomic::Ordering::Relaxed);
    poller.join().expect("the poller ends");
    (peak.load(std::sync::atomic::Ordering::Relaxed), output)
}

/// A 1 MB loose file that inflates to a gibibyte: refused while streaming, at the cost of a
/// few MiB (9dc06af's cap held too, but every process opening the store peaked at 268 MB).
#[cfg(target_os = "linux")]
#[test]
fn a_decompression_bomb_in_the_store_costs_a_few_mib() {
    use std::io::Write as _;
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().join("out");
    let loose = out.join("runs/loose");
    std::fs::create_dir_all(&loose).expect("a folder");
    let mut bomb = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    let block = vec![b' '; 1 << 20];
    for _ in 0..1024 {
        bomb.write_all(&block).expect("compressed");
    }
    let bomb = bomb.finish().expect("compressed");
    assert!(bomb.len() < 2 << 20, "{}", bomb.len());
    std::fs::write(
        loose.join(format!("{}.figures.run.gz", "ab".repeat(32))),
        bomb,
    )
    .expect("written");
    let key = keys(&out).remove(0);
    let mut run_job = xtask();
    run_job
        .arg("run-job")
        .arg("--key")
        .arg(&key)
        .args(PLAN)
        .arg("--out")
        .arg(&out);
    let (peak, output) = peak_memory_kib(run_job);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("the cap of one entry"), "{stderr}");
    assert!(peak > 0, "the poller saw the process");
    assert!(peak < 96 << 10, "peak resident memory {peak} KiB");
}
