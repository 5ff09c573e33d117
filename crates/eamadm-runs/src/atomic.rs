//! Atomic file writes: every output goes through [`write_atomic`], so a reader (or a resumed
//! run) sees either the old file or the complete new one, never half a file.

use std::io::{self, Write as _};
use std::path::{Path, PathBuf};

use thiserror::Error;

/// A failed atomic write, naming the file.
#[derive(Debug, Error)]
#[error("could not write {}: {source}", path.display())]
pub struct AtomicWriteError {
    /// The file we were writing.
    pub path: PathBuf,
    /// What went wrong.
    #[source]
    pub source: io::Error,
}

/// Writes `contents` to `path` atomically: creates the parent folders, writes a temporary file in
/// the same folder (same file system, so the rename is atomic), flushes it to disk, renames it
/// over `path` and syncs the folder so that the rename itself is on disk. On error the temporary
/// file is removed and `path` is untouched. A process killed mid-write may leave a hidden
/// `.<name>.*.tmp` file behind; nothing reads those.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), AtomicWriteError> {
    write_to(AtomicFile::create(path)?, contents)
}

/// [`write_atomic`] into a folder other processes write and sweep too, coordinated by
/// `writers` ([`WritersLock`]).
pub fn write_atomic_among_writers(
    path: &Path,
    contents: &[u8],
    writers: &WritersLock,
) -> Result<(), AtomicWriteError> {
    write_to(AtomicFile::create_among_writers(path, writers)?, contents)
}

fn write_to(mut file: AtomicFile, contents: &[u8]) -> Result<(), AtomicWriteError> {
    let path = file.path().to_path_buf();
    file.write_all(contents)
        .map_err(|source| AtomicWriteError { path, source })?;
    file.commit()
}

/// The name of the file in a folder of a shared store ([`WritersLock`]).
pub const WRITERS_LOCK_FILE: &str = ".writers.lock";

/// How a temporary file is never removed under a live writer: writers that other processes
/// may sweep after (the run store's loose runs, its bundles, the pre-trained artefacts) hold
/// this file's lock *shared* from before they create their temporary file until they have
/// locked it, and [`remove_stale_temporary_files`] holds it *exclusively* while it sweeps. So
/// during a sweep every live writer's temporary file is locked (and skipped), and an unlocked
/// one belongs to a writer that is gone (its lock went with its process). The file itself is
/// empty and never removed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WritersLock {
    path: PathBuf,
}

impl WritersLock {
    /// The writers' lock of the temporary files in `folder` (and in the folders a caller
    /// chooses to coordinate with it), `folder/.writers.lock`.
    #[must_use]
    pub fn in_folder(folder: &Path) -> Self {
        Self {
            path: folder.join(WRITERS_LOCK_FILE),
        }
    }

    /// The lock file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The lock file, opened (made if missing) without following a link or waiting on a FIFO.
    fn open(&self) -> io::Result<std::fs::File> {
        if let Some(folder) = self.path.parent() {
            std::fs::create_dir_all(folder)?;
        }
        let mut options = std::fs::File::options();
        options.read(true).write(true).create(true).truncate(false);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt as _;
            #[cfg(target_os = "linux")]
            options.custom_flags(0o400_000 | 0o4000);
            #[cfg(target_os = "macos")]
            options.custom_flags(0x100 | 0x4);
        }
        let file = options.open(&self.path).map_err(|error| {
            if error.raw_os_error() == Some(40) || error.raw_os_error() == Some(62) {
                crate::no_follow::refused(&self.path, "a symbolic link")
            } else {
                error
            }
        })?;
        if !file.metadata()?.is_file() {
            return Err(crate::no_follow::refused(&self.path, "a special file"));
        }
        Ok(file)
    }
}

/// How long a sweep waits for the writers inside their few microseconds between creating and
/// locking a temporary file before it gives up (and sweeps next time).
const SWEEP_PATIENCE: std::time::Duration = std::time::Duration::from_secs(2);

/// Removes the temporary files (`.<name>.*.tmp`) that killed writers left in `folder`: those
/// whose lock can be taken. With `writers`, the sweep first holds that lock exclusively (see
/// [`WritersLock`]), so a temporary file another process has just created and not yet locked
/// is never taken for a dead writer's; a sweep that cannot get it within two seconds removes
/// nothing. Without it (a folder only the holder of the output folder's lock writes), an
/// unlocked temporary file is a dead writer's. Returns how many were removed. Links and
/// special files are left alone.
pub fn remove_stale_temporary_files(
    folder: &Path,
    writers: Option<&WritersLock>,
) -> io::Result<usize> {
    let entries = match std::fs::read_dir(folder) {
        Ok(entries) => entries,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(0),
        Err(error) => return Err(error),
    };
    let _exclusive = match writers {
        Some(writers) => {
            let lock = writers.open()?;
            let started = std::time::Instant::now();
            loop {
                match lock.try_lock() {
                    Ok(()) => break,
                    Err(std::fs::TryLockError::WouldBlock)
                        if started.elapsed() < SWEEP_PATIENCE =>
                    {
                        std::thread::sleep(std::time::Duration::from_millis(5));
                    }
                    Err(std::fs::TryLockError::WouldBlock) => return Ok(0),
                    Err(std::fs::TryLockError::Error(error)) => return Err(error),
                }
            }
            Some(lock)
        }
        None => None,
    };
    let mut removed = 0;
    for entry in entries {
        let entry = entry?;
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if !(name.starts_with('.') && name.ends_with(".tmp")) {
            continue;
        }
        let path = entry.path();
        let Ok(file) = crate::no_follow::open_regular(&path) else {
            continue;
        };
        if file.try_lock().is_ok() {
            std::fs::remove_file(&path)?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// For tests of concurrent writers and sweeps: the milliseconds in the environment variable
/// `EAMADM_TEST_TEMP_LOCK_DELAY_MS` are slept between making a temporary file and locking it,
/// stretching the moment a sweep could mistake it for a dead writer's (as a writer delayed by
/// the scheduler or a tracer would be). Unset, nothing happens.
fn test_hook_delay() {
    if let Some(millis) = std::env::var("EAMADM_TEST_TEMP_LOCK_DELAY_MS")
        .ok()
        .and_then(|text| text.parse::<u64>().ok())
    {
        std::thread::sleep(std::time::Duration::from_millis(millis.min(60_000)));
    }
}

/// Flushes a folder's entries (a rename, a new or removed file) to disk, so that a crash right
/// after a write returned cannot lose it. A no-op where folders cannot be opened as files.
pub fn sync_folder(folder: &Path) -> io::Result<()> {
    #[cfg(unix)]
    std::fs::File::open(folder)?.sync_all()?;
    #[cfg(not(unix))]
    let _ = folder;
    Ok(())
}

/// A file written in pieces and then put in place atomically, like [`write_atomic`] for output
/// too large to hold in memory: writes go to a temporary file in the same folder, and
/// [`AtomicFile::commit`] syncs it and renames it over the path. Dropped without a commit, the
/// temporary file is removed and the path is untouched.
pub struct AtomicFile {
    path: PathBuf,
    writer: io::BufWriter<tempfile::NamedTempFile>,
}

impl AtomicFile {
    /// Starts writing `path` (creating its parent folders).
    pub fn create(path: &Path) -> Result<Self, AtomicWriteError> {
        Self::create_with(path, None)
    }

    /// [`AtomicFile::create`] in a folder other processes write and sweep too: the temporary
    /// file is made and locked while `writers` is held shared ([`WritersLock`]), so no sweep
    /// can take it for a dead writer's.
    pub fn create_among_writers(
        path: &Path,
        writers: &WritersLock,
    ) -> Result<Self, AtomicWriteError> {
        Self::create_with(path, Some(writers))
    }

    fn create_with(path: &Path, writers: Option<&WritersLock>) -> Result<Self, AtomicWriteError> {
        let error = |source| AtomicWriteError {
            path: path.to_path_buf(),
            source,
        };
        let file_name = path.file_name().ok_or_else(|| {
            error(io::Error::new(
                io::ErrorKind::InvalidInput,
                "the path names no file",
            ))
        })?;
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        std::fs::create_dir_all(folder).map_err(error)?;
        // The folder itself must be a folder, not a link to one elsewhere.
        let kind = std::fs::symlink_metadata(folder)
            .map_err(error)?
            .file_type();
        if !kind.is_dir() {
            return Err(error(crate::no_follow::refused(folder, "a symbolic link")));
        }
        let mut prefix = std::ffi::OsString::from(".");
        prefix.push(file_name);
        prefix.push(".");
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).suffix(".tmp");
        // Outputs are for everyone to read, like files made by `std::fs::write` (tempfile's
        // default is owner-only).
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
        // Held shared from before the temporary file exists until it is locked (dropped at
        // the end of this function).
        let _shared = match writers {
            Some(writers) => {
                let lock = writers.open().map_err(error)?;
                lock.lock_shared().map_err(error)?;
                Some(lock)
            }
            None => None,
        };
        let temp = builder.tempfile_in(folder).map_err(error)?;
        if writers.is_some() {
            test_hook_delay();
        }
        // Locked while being written, so that the next holder of the output folder's lock can
        // tell the temporary file of a killed writer (unlocked) from a live one's.
        temp.as_file().try_lock().map_err(|e| match e {
            std::fs::TryLockError::Error(source) => error(source),
            std::fs::TryLockError::WouldBlock => error(io::Error::other("temp file locked")),
        })?;
        Ok(Self {
            path: path.to_path_buf(),
            writer: io::BufWriter::new(temp),
        })
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes, syncs and renames the temporary file over the path, then syncs the folder so
    /// that the rename itself is on disk.
    pub fn commit(self) -> Result<(), AtomicWriteError> {
        let path = self.path;
        let error = |source| AtomicWriteError {
            path: path.clone(),
            source,
        };
        let temp = self
            .writer
            .into_inner()
            .map_err(|e| error(e.into_error()))?;
        temp.as_file().sync_all().map_err(error)?;
        temp.persist(&path)
            .map_err(|persist| error(persist.error))?;
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        sync_folder(folder).map_err(error)?;
        Ok(())
    }

    /// Flushes the temporary file and renames it to the path, which must not exist yet, and
    /// returns it still open and still locked, to be appended to: a file that appears complete
    /// so far and that other processes can tell is being written while it stays locked (the
    /// run store's batch files, [`crate::store::LooseBatch`]). Neither the file nor the rename
    /// is synced. Fails, leaving nothing, if the path exists.
    pub fn publish_locked(self) -> Result<std::fs::File, AtomicWriteError> {
        let path = self.path;
        let error = |source| AtomicWriteError {
            path: path.clone(),
            source,
        };
        let temp = self
            .writer
            .into_inner()
            .map_err(|e| error(e.into_error()))?;
        temp.persist_noclobber(&path)
            .map_err(|persist| error(persist.error))
    }
}

impl io::Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.writer.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.writer.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(folder: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(folder)
            .unwrap()
            .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_the_file_creating_folders_and_leaves_no_temp_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a/b/figure.svg");
        write_atomic(&path, b"<svg/>").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"<svg/>");
        assert_eq!(entries(&dir.path().join("a/b")), vec!["figure.svg"]);
    }

    #[test]
    fn replaces_an_existing_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("REPORT.md");
        write_atomic(&path, b"old, longer contents").unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        assert_eq!(entries(dir.path()), vec!["REPORT.md"]);
    }

    /// An EA tree is saved as its JSON text through this one atomic write (`ea-tree` writes no
    /// file since issue 36): the file is readable by everyone (0644, not the temporary file's
    /// 0600), replacing it leaves one file, and it loads back as the same tree.
    #[test]
    fn a_saved_ea_tree_is_readable_by_everyone_and_loads_back() {
        use eamadm::ea_tree::{EaTree, EaTreeConfig, Sample};
        let mut tree: EaTree = EaTree::new(EaTreeConfig::new(0.3, 0.5).unwrap()).unwrap();
        for (state, action, q1, q2) in [([0_u32, 0], 0, 1.0, 2.0), ([2, 2], 1, -1.5, 0.0)] {
            tree.insert(Sample {
                state: &state,
                action,
                q1,
                q2,
            })
            .unwrap();
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tree.json");
        write_atomic(&path, tree.to_json().as_bytes()).unwrap();
        write_atomic(&path, tree.to_json().as_bytes()).unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt as _;
            let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o644);
        }
        assert_eq!(entries(dir.path()), vec!["tree.json"]);
        let back: EaTree = EaTree::load(&path).unwrap();
        assert!(back == tree);
    }

    #[test]
    fn failure_names_the_path_and_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        // A folder where the file should be: the rename fails.
        let path = dir.path().join("taken");
        std::fs::create_dir(&path).unwrap();
        std::fs::write(path.join("inside"), b"x").unwrap();
        let error = write_atomic(&path, b"data").unwrap_err();
        assert_eq!(error.path, path);
        assert!(error.to_string().contains("taken"), "{error}");
        assert_eq!(entries(dir.path()), vec!["taken"]);
    }

    #[test]
    fn a_streamed_file_appears_only_on_commit() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("runs/task1.jsonl");
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"one\n").unwrap();
        file.write_all(b"two\n").unwrap();
        assert!(!path.exists());
        file.commit().unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"one\ntwo\n");
        assert_eq!(entries(&dir.path().join("runs")), vec!["task1.jsonl"]);
        let mut dropped = AtomicFile::create(&path).unwrap();
        dropped.write_all(b"never").unwrap();
        drop(dropped);
        assert_eq!(std::fs::read(&path).unwrap(), b"one\ntwo\n");
        assert_eq!(entries(&dir.path().join("runs")), vec!["task1.jsonl"]);
    }

    #[test]
    fn only_the_temporary_files_of_dead_writers_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let live = AtomicFile::create(&dir.path().join("live")).unwrap();
        std::fs::write(dir.path().join(".dead.x1.tmp"), b"left by a kill").unwrap();
        std::fs::write(dir.path().join("kept.tmp"), b"not hidden: not ours").unwrap();
        assert_eq!(remove_stale_temporary_files(dir.path(), None).unwrap(), 1);
        let names = entries(dir.path());
        assert_eq!(names.len(), 2, "{names:?}");
        assert!(names.iter().any(|n| n.starts_with(".live.")), "{names:?}");
        live.commit().unwrap();
        assert_eq!(entries(dir.path()), vec!["kept.tmp", "live"]);
    }

    /// A writer between making its temporary file and locking it holds the writers' lock
    /// shared, so a sweep beside it removes nothing of it (9dc06af's sweep removed any unlocked
    /// temporary file, a live writer's included: its run was lost); once the writer is gone, the
    /// file is swept.
    #[test]
    fn a_temporary_file_in_its_writers_window_survives_a_sweep() {
        let dir = tempfile::tempdir().unwrap();
        let writers = WritersLock::in_folder(dir.path());
        let shared = writers.open().unwrap();
        shared.lock_shared().unwrap();
        let fresh = dir.path().join(".run.gz.Ab12Cd.tmp");
        std::fs::write(&fresh, b"being written").unwrap();
        let started = std::time::Instant::now();
        assert_eq!(
            remove_stale_temporary_files(dir.path(), Some(&writers)).unwrap(),
            0
        );
        assert!(
            started.elapsed() >= SWEEP_PATIENCE,
            "the sweep waited for the writer"
        );
        assert!(fresh.exists());
        // Locked by its writer, then released with the shared lock: still skipped while locked.
        let held = crate::no_follow::open_regular(&fresh).unwrap();
        held.try_lock().unwrap();
        drop(shared);
        assert_eq!(
            remove_stale_temporary_files(dir.path(), Some(&writers)).unwrap(),
            0
        );
        assert!(fresh.exists());
        // The writer gone (its lock with it): swept.
        drop(held);
        assert_eq!(
            remove_stale_temporary_files(dir.path(), Some(&writers)).unwrap(),
            1
        );
        assert!(!fresh.exists());
        // Files written among writers leave only their lock file behind.
        write_atomic_among_writers(&dir.path().join("loose.run.gz"), b"x", &writers).unwrap();
        assert_eq!(entries(dir.path()), vec![WRITERS_LOCK_FILE, "loose.run.gz"]);
    }

    #[cfg(unix)]
    #[test]
    fn a_linked_folder_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let elsewhere = tempfile::tempdir().unwrap();
        std::os::unix::fs::symlink(elsewhere.path(), dir.path().join("task1")).unwrap();
        let error = write_atomic(&dir.path().join("task1/curves.csv.gz"), b"x").unwrap_err();
        assert!(error.to_string().contains("symbolic link"), "{error}");
        assert!(entries(elsewhere.path()).is_empty());
    }

    #[test]
    fn a_path_without_file_name_is_refused() {
        let error = write_atomic(Path::new("/"), b"x").unwrap_err();
        assert_eq!(error.source.kind(), io::ErrorKind::InvalidInput);
    }
}
