//! The output folder of `reproduce-paper`: one process at a time (an exclusive lock), and one
//! consistent set of output files (staged, committed, then swapped in).
//!
//! Layout of `<out>/` beside the outputs themselves (all hidden names, which no experiment name
//! can take):
//!
//! - `.reproduce-paper.lock` — locked exclusively for the whole invocation (the operating
//!   system's advisory lock, released when the process ends, even when it is killed);
//! - `.staging/` — the set being written; removed at the next start if a kill left it;
//! - `.committed/` — a complete set whose swap into `<out>/` has begun; the next start finishes
//!   the swap before anything else;
//! - `.outputs` — the manifest: every file of the current set, one relative path per line.
//!
//! The mechanism knows nothing of the files' formats: the set is whatever the invocation writes
//! into the staging folder. Files of the previous set that the new one does not have are removed,
//! so a run of other arguments in the same folder leaves no stale curves or figures behind.
//! Files the manifest never listed (a user's own files, the run store `runs/`) are left alone.

use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::atomic::{AtomicWriteError, sync_folder, write_atomic};
pub use crate::names::{COMMITTED, LOCK_FILE, MANIFEST, STAGING};

/// The output folder cannot be used.
#[derive(Debug, Error)]
pub enum OutputFolderError {
    /// Another process holds the lock.
    #[error(
        "{}: another reproduce-paper is using this output folder (it holds {}); wait for it to \
         finish, choose another --out, or pass --wait to wait for it",
        out.display(),
        LOCK_FILE
    )]
    Busy {
        /// The output folder.
        out: PathBuf,
    },
    /// A file-system operation failed.
    #[error("{}: {what}: {source}", path.display())]
    Io {
        /// What was being done.
        what: &'static str,
        /// The path it was done to.
        path: PathBuf,
        /// Why it failed.
        #[source]
        source: io::Error,
    },
    /// Writing the manifest failed.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
}

fn io_error(what: &'static str, path: &Path) -> impl FnOnce(io::Error) -> OutputFolderError {
    let path = path.to_path_buf();
    move |source| OutputFolderError::Io { what, path, source }
}

/// An output folder this process holds the lock of. Dropping it releases the lock.
#[derive(Debug)]
pub struct OutputFolder {
    root: PathBuf,
    /// Held for the lifetime of the value: the lock lives as long as the open file.
    _lock: File,
}

impl OutputFolder {
    /// Creates `out` if needed, takes its lock (waiting for another process to release it when
    /// `wait`, failing with [`OutputFolderError::Busy`] otherwise), then repairs what a killed
    /// earlier invocation left: finishes a committed swap, removes an unfinished staging folder.
    pub fn open(out: &Path, wait: bool) -> Result<Self, OutputFolderError> {
        std::fs::create_dir_all(out).map_err(io_error("cannot create the folder", out))?;
        let lock_path = out.join(LOCK_FILE);
        crate::no_follow::check_under(out, Path::new(LOCK_FILE), true)
            .map_err(io_error("cannot use the lock file", &lock_path))?;
        let mut options = File::options();
        options.create(true).truncate(false).write(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt as _;
            // Not through a link planted after the check, and no wait on a FIFO.
            #[cfg(target_os = "linux")]
            options.custom_flags(0o400_000 | 0o4000);
            #[cfg(target_os = "macos")]
            options.custom_flags(0x100 | 0x4);
        }
        let lock = options
            .open(&lock_path)
            .map_err(io_error("cannot open the lock file", &lock_path))?;
        if !lock
            .metadata()
            .map_err(io_error("cannot open the lock file", &lock_path))?
            .is_file()
        {
            return Err(io_error("cannot use the lock file", &lock_path)(
                crate::no_follow::refused(&lock_path, "a special file"),
            ));
        }
        if wait {
            lock.lock()
                .map_err(io_error("cannot lock the output folder", &lock_path))?;
        } else {
            match lock.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => {
                    return Err(OutputFolderError::Busy {
                        out: out.to_path_buf(),
                    });
                }
                Err(std::fs::TryLockError::Error(source)) => {
                    return Err(io_error("cannot lock the output folder", &lock_path)(
                        source,
                    ));
                }
            }
        }
        let folder = Self {
            root: out.to_path_buf(),
            _lock: lock,
        };
        folder.recover()?;
        Ok(folder)
    }

    /// The output folder.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// A fresh, empty staging folder to write the new set into.
    pub fn staging(&self) -> Result<PathBuf, OutputFolderError> {
        let staging = self.root.join(STAGING);
        remove_dir_if_present(&staging)?;
        std::fs::create_dir(&staging)
            .map_err(io_error("cannot create the staging folder", &staging))?;
        Ok(staging)
    }

    /// Makes the staged set the folder's set: lists it in a manifest, commits it (one atomic
    /// rename of the staging folder), then swaps it in and removes the previous set's files
    /// that it does not have.
    pub fn commit(&self) -> Result<(), OutputFolderError> {
        let staging = self.root.join(STAGING);
        let mut files = Vec::new();
        list_files(&staging, Path::new(""), &mut files)?;
        files.sort();
        let mut manifest = String::new();
        for file in &files {
            manifest.push_str(&slash_path(file));
            manifest.push('\n');
        }
        write_atomic(&staging.join(MANIFEST), manifest.as_bytes())?;
        let committed = self.root.join(COMMITTED);
        remove_dir_if_present(&committed)?;
        std::fs::rename(&staging, &committed)
            .map_err(io_error("cannot commit the staging folder", &staging))?;
        sync_folder(&self.root).map_err(io_error("cannot sync the folder", &self.root))?;
        self.swap_in()
    }

    /// Repairs what a killed invocation left behind (see the module docs).
    fn recover(&self) -> Result<(), OutputFolderError> {
        for hidden in [COMMITTED, STAGING] {
            crate::no_follow::check_under(&self.root, Path::new(hidden), false)
                .map_err(io_error("cannot use the folder", &self.root.join(hidden)))?;
        }
        if self.root.join(COMMITTED).is_dir() {
            self.swap_in()?;
        }
        remove_dir_if_present(&self.root.join(STAGING))?;
        // Temporary files of writers killed while this folder's outputs were written: in the
        // folder itself only the holder of this lock writes, in the run store other processes
        // do too (coordinated by the store's writers' lock).
        let runs = self.root.join(crate::names::RUNS_FOLDER);
        let writers = crate::atomic::WritersLock::in_folder(&runs);
        for (folder, coordinated) in [
            (self.root.clone(), false),
            (runs.clone(), true),
            (runs.join(crate::names::LOOSE_RUNS), true),
            (runs.join(crate::names::PRETRAINED), true),
        ] {
            if crate::no_follow::check_under(
                &self.root,
                folder.strip_prefix(&self.root).unwrap_or(Path::new("")),
                false,
            )
            .is_ok()
                && folder.is_dir()
            {
                crate::atomic::remove_stale_temporary_files(
                    &folder,
                    coordinated.then_some(&writers),
                )
                .map_err(io_error("cannot remove temporary files", &folder))?;
            }
        }
        Ok(())
    }

    /// Moves the committed set into the folder. Idempotent: a kill at any point is finished by
    /// running it again (the previous manifest is replaced only after every file has moved).
    fn swap_in(&self) -> Result<(), OutputFolderError> {
        let committed = self.root.join(COMMITTED);
        if !committed.join(MANIFEST).is_file() {
            // The manifest moves last: without it the swap had finished, only the (empty)
            // folder was left.
            return remove_dir_if_present(&committed);
        }
        let new_files = read_manifest(&committed.join(MANIFEST))?;
        let old_files = read_manifest(&self.root.join(MANIFEST))?;
        for file in old_files.iter().chain(&new_files) {
            // A manifest line through a linked folder (or to a link) would act elsewhere.
            crate::no_follow::check_under(&self.root, file, true).map_err(io_error(
                "refusing to replace an output",
                &self.root.join(file),
            ))?;
        }
        for stale in old_files.iter().filter(|old| !new_files.contains(old)) {
            let path = self.root.join(stale);
            match std::fs::remove_file(&path) {
                Ok(()) => remove_empty_parents(&self.root, &path),
                Err(error) if error.kind() == io::ErrorKind::NotFound => {}
                Err(error) => return Err(io_error("cannot remove a stale output", &path)(error)),
            }
        }
        for file in &new_files {
            let from = committed.join(file);
            if !from.exists() {
                // Moved by an earlier, interrupted swap.
                continue;
            }
            let to = self.root.join(file);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent)
                    .map_err(io_error("cannot create an output folder", parent))?;
            }
            std::fs::rename(&from, &to)
                .map_err(io_error("cannot move an output into place", &to))?;
        }
        let manifest = self.root.join(MANIFEST);
        std::fs::rename(committed.join(MANIFEST), &manifest)
            .map_err(io_error("cannot move the manifest into place", &manifest))?;
        sync_folder(&self.root).map_err(io_error("cannot sync the folder", &self.root))?;
        remove_dir_if_present(&committed)
    }
}

/// The largest manifest read: a set lists a few hundred files.
const MAX_MANIFEST_BYTES: u64 = 1 << 20;

/// The files a manifest lists (none when it does not exist), opened without following a link
/// or waiting on a FIFO ([`crate::no_follow`]). A line is a name read back from stored bytes,
/// so it is a path only if it is an output's: a top-level output file, or `<experiment>/<file>`
/// with a safe experiment name ([`eamadm::is_safe_slug`], the rule of a config's names) and a
/// file name of the same characters. Any other line (absolute, `..`, into `runs/`, hidden,
/// deeper) is ignored: a hand-edited or forged manifest cannot make us delete or move anything
/// else.
fn read_manifest(path: &Path) -> Result<Vec<PathBuf>, OutputFolderError> {
    use std::io::Read as _;
    let file = match crate::no_follow::open_regular(path) {
        Ok(file) => file,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(error) => return Err(io_error("cannot read the manifest", path)(error)),
    };
    let mut bytes = Vec::new();
    file.take(MAX_MANIFEST_BYTES)
        .read_to_end(&mut bytes)
        .map_err(io_error("cannot read the manifest", path))?;
    let text = String::from_utf8_lossy(&bytes);
    Ok(text
        .lines()
        .filter(|line| is_output_path(line))
        .map(PathBuf::from)
        .collect())
}

/// Whether `line` of a manifest names an output: a top-level output file (not the run store),
/// or a file in an experiment's folder (see [`read_manifest`]).
fn is_output_path(line: &str) -> bool {
    let file_name = |name: &str| {
        !name.is_empty()
            && name.len() <= 128
            && !name.starts_with('.')
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
    };
    match line.split('/').collect::<Vec<_>>().as_slice() {
        [top] => {
            *top != crate::names::RUNS_FOLDER
                && (crate::names::TOP_LEVEL.contains(top) || eamadm::is_safe_slug(top))
        }
        [experiment, file] => eamadm::is_safe_slug(experiment) && file_name(file),
        _ => false,
    }
}

/// Every file under `folder` (recursively), as paths relative to it, prefixed with `prefix`.
fn list_files(
    folder: &Path,
    prefix: &Path,
    files: &mut Vec<PathBuf>,
) -> Result<(), OutputFolderError> {
    let entries = std::fs::read_dir(folder).map_err(io_error("cannot list the folder", folder))?;
    for entry in entries {
        let entry = entry.map_err(io_error("cannot list the folder", folder))?;
        let relative = prefix.join(entry.file_name());
        let kind = entry
            .file_type()
            .map_err(io_error("cannot inspect an output", &entry.path()))?;
        if kind.is_dir() {
            list_files(&entry.path(), &relative, files)?;
        } else {
            files.push(relative);
        }
    }
    Ok(())
}

/// A relative path with `/` between its parts, whatever the platform.
fn slash_path(path: &Path) -> String {
    path.components()
        .map(|part| part.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

fn remove_dir_if_present(folder: &Path) -> Result<(), OutputFolderError> {
    match std::fs::remove_dir_all(folder) {
        Ok(()) => Ok(()),
        Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(error) => Err(io_error("cannot remove the folder", folder)(error)),
    }
}

/// Removes the folders between `file` and `root` that became empty (best effort: a folder that
/// still holds something, such as a user's file, stays).
fn remove_empty_parents(root: &Path, file: &Path) {
    let mut folder = file.parent();
    while let Some(current) = folder {
        if current == root || !current.starts_with(root) || std::fs::remove_dir(current).is_err() {
            break;
        }
        folder = current.parent();
    }
}

/// How much an output folder takes: what `du -sb` and `find -type f | wc -l` report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Footprint {
    /// The apparent size of everything under the folder, the folder itself included: files'
    /// lengths and folders' own sizes (a folder that once listed many files keeps its size).
    pub bytes: u64,
    /// The regular files under the folder.
    pub files: u64,
}

/// The [`Footprint`] of the folder `root`, symbolic links counted as themselves (never
/// followed), so the budget of issue 35 (the default run's folder at most 25 MB in 100 files)
/// is checked as a reader measures it.
///
/// # Errors
/// [`OutputFolderError::Io`] when a folder cannot be listed or an entry's metadata read.
pub fn footprint(root: &Path) -> Result<Footprint, OutputFolderError> {
    let mut total = Footprint { bytes: 0, files: 0 };
    let mut pending = vec![root.to_path_buf()];
    while let Some(path) = pending.pop() {
        let metadata =
            std::fs::symlink_metadata(&path).map_err(io_error("reading the metadata of", &path))?;
        total.bytes += metadata.len();
        if metadata.is_file() {
            total.files += 1;
        } else if metadata.is_dir() {
            for entry in std::fs::read_dir(&path).map_err(io_error("listing", &path))? {
                pending.push(entry.map_err(io_error("listing", &path))?.path());
            }
        }
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_footprint_counts_every_file_and_folder_like_du_and_find() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("out");
        write_atomic(&root.join("REPORT.md"), b"12345").unwrap();
        write_atomic(&root.join("task1/curves.csv.gz"), b"123").unwrap();
        std::fs::create_dir_all(root.join("runs/loose")).unwrap();
        let folders: u64 = ["", "task1", "runs", "runs/loose"]
            .iter()
            .map(|folder| std::fs::metadata(root.join(folder)).unwrap().len())
            .sum();
        assert_eq!(
            footprint(&root).unwrap(),
            Footprint {
                bytes: 8 + folders,
                files: 2
            }
        );
        let missing = footprint(&root.join("absent")).unwrap_err().to_string();
        assert!(missing.contains("absent"), "{missing}");
    }

    /// Writes `files` (relative path, contents) into a staging folder and commits them.
    fn write_set(folder: &OutputFolder, files: &[(&str, &str)]) {
        let staging = folder.staging().unwrap();
        for (path, contents) in files {
            write_atomic(&staging.join(path), contents.as_bytes()).unwrap();
        }
        folder.commit().unwrap();
    }

    fn visible_files(root: &Path) -> Vec<String> {
        let mut files = Vec::new();
        list_files(root, Path::new(""), &mut files).unwrap();
        let mut names: Vec<String> = files
            .iter()
            .map(|f| slash_path(f))
            .filter(|f| f != LOCK_FILE)
            .collect();
        names.sort();
        names
    }

    /// The next invocation on `out` after this process dropped its `OutputFolder`, waiting for
    /// the lock. A lock belongs to the open file, and a child that another test of this binary
    /// forks at that moment (`mkfifo` in `no_follow`) holds a copy of every open file until it
    /// execs, so for a moment the dropped lock may still be held: refusing then (`wait =
    /// false`) made these tests fail now and then under load, a race of the test binary and not
    /// of the invocations the tests stand for.
    fn reopen_after_drop(out: &Path) -> OutputFolder {
        OutputFolder::open(out, true).unwrap()
    }

    #[test]
    fn a_second_set_replaces_the_first_and_leaves_no_stale_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let folder = OutputFolder::open(&out, false).unwrap();
        write_set(
            &folder,
            &[
                ("REPORT.md", "one"),
                ("first/curves.csv", "1"),
                ("results.json", "[1]"),
            ],
        );
        std::fs::write(out.join("notes.txt"), "the user's own file").unwrap();
        write_set(&folder, &[("REPORT.md", "two"), ("second/curves.csv", "2")]);
        assert_eq!(
            visible_files(&out),
            [".outputs", "REPORT.md", "notes.txt", "second/curves.csv"]
        );
        assert_eq!(
            std::fs::read_to_string(out.join("REPORT.md")).unwrap(),
            "two"
        );
        assert_eq!(
            std::fs::read_to_string(out.join(MANIFEST)).unwrap(),
            "REPORT.md\nsecond/curves.csv\n"
        );
        assert!(!out.join("first").exists(), "the emptied folder is removed");
    }

    #[test]
    fn a_kill_while_staging_leaves_the_previous_set_whole() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let folder = OutputFolder::open(&out, false).unwrap();
        write_set(&folder, &[("REPORT.md", "old"), ("a/curves.csv", "old")]);
        // A new set half written, then the process dies.
        let staging = folder.staging().unwrap();
        write_atomic(&staging.join("REPORT.md"), b"new").unwrap();
        drop(folder);
        assert_eq!(
            std::fs::read_to_string(out.join("REPORT.md")).unwrap(),
            "old"
        );
        // The next invocation throws the half-written set away. It waits for the lock (see
        // `reopen_after_drop`).
        let _folder = reopen_after_drop(&out);
        assert!(!out.join(STAGING).exists());
        assert_eq!(
            visible_files(&out),
            [".outputs", "REPORT.md", "a/curves.csv"]
        );
    }

    #[test]
    fn a_kill_during_the_swap_is_finished_by_the_next_invocation() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let folder = OutputFolder::open(&out, false).unwrap();
        write_set(&folder, &[("REPORT.md", "old"), ("a/curves.csv", "old")]);
        // Commit a new set, then simulate a kill after one file has moved.
        let staging = folder.staging().unwrap();
        write_atomic(&staging.join("REPORT.md"), b"new").unwrap();
        write_atomic(&staging.join("b/curves.csv"), b"new").unwrap();
        write_atomic(&staging.join(MANIFEST), b"REPORT.md\nb/curves.csv\n").unwrap();
        std::fs::rename(&staging, out.join(COMMITTED)).unwrap();
        std::fs::rename(out.join(COMMITTED).join("REPORT.md"), out.join("REPORT.md")).unwrap();
        drop(folder);
        let _folder = reopen_after_drop(&out);
        assert_eq!(
            visible_files(&out),
            [".outputs", "REPORT.md", "b/curves.csv"]
        );
        assert_eq!(
            std::fs::read_to_string(out.join("REPORT.md")).unwrap(),
            "new"
        );
        assert!(!out.join(COMMITTED).exists());
    }

    #[test]
    fn a_second_process_is_refused_or_waits() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let first = OutputFolder::open(&out, false).unwrap();
        // Locks belong to open files, so a second open in this process stands for a second
        // process.
        let error = OutputFolder::open(&out, false).unwrap_err();
        assert!(matches!(error, OutputFolderError::Busy { .. }), "{error}");
        assert!(error.to_string().contains("--wait"), "{error}");
        let waiter = std::thread::spawn({
            let out = out.clone();
            move || OutputFolder::open(&out, true).map(|_| ())
        });
        std::thread::sleep(std::time::Duration::from_millis(100));
        assert!(!waiter.is_finished(), "--wait waits while the lock is held");
        drop(first);
        waiter.join().unwrap().unwrap();
    }

    #[test]
    fn a_manifest_cannot_point_outside_the_folder_or_into_the_store() {
        let dir = tempfile::tempdir().unwrap();
        let manifest = dir.path().join(MANIFEST);
        std::fs::write(
            &manifest,
            "../escape\n/etc/passwd\n\nok/file.csv\nruns/task1.jsonl.zst\nruns\n\
             a/b/c.svg\n.hidden\nx/.lock\nREPORT.md\ntask1/../../x\n",
        )
        .unwrap();
        assert_eq!(
            read_manifest(&manifest).unwrap(),
            [PathBuf::from("ok/file.csv"), PathBuf::from("REPORT.md")]
        );
    }

    /// A FIFO where the manifest belongs is refused by name (9dc06af opened it to read and
    /// blocked for ever, holding the folder's lock).
    #[cfg(unix)]
    #[test]
    fn a_fifo_at_the_manifest_is_refused_not_waited_on() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        std::fs::create_dir(&out).unwrap();
        assert!(
            std::process::Command::new("mkfifo")
                .arg(out.join(MANIFEST))
                .status()
                .unwrap()
                .success()
        );
        let (sender, receiver) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let folder = OutputFolder::open(&out, false).unwrap();
            let staging = folder.staging().unwrap();
            write_atomic(&staging.join("REPORT.md"), b"new").unwrap();
            let _ = sender.send(folder.commit().map_err(|e| e.to_string()));
        });
        let error = receiver
            .recv_timeout(std::time::Duration::from_secs(30))
            .expect("the commit returns instead of waiting on the FIFO")
            .unwrap_err();
        assert!(error.contains("special file"), "{error}");
    }
}
