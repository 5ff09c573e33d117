//! What `cargo xtask gc` removes: what no plan of this code needs any more. Stored runs of
//! another results format or crate version ([`crate::RunStore::stale_runs`]), entries set
//! aside longer ago than the age given, artefacts of the cache that the plan given does not
//! pre-train, the artefacts an earlier version kept inside the output folder
//! (`runs/pretrained/`, moved into the cache first), and temporary files of writers that are
//! gone. Every removal is returned, to be printed.

use std::collections::HashSet;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use crate::key::RunKey;
use crate::pretrained::PretrainedStore;
use crate::store::StoreError;

/// One file removed, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Removed {
    /// The file.
    pub path: PathBuf,
    /// Why, for people.
    pub why: String,
}

/// Removes the entries of `out`'s `runs/.set-aside/` last modified more than `age` ago.
///
/// # Errors
/// [`StoreError`] if the folder cannot be listed or a file removed.
pub fn remove_set_aside_older_than(out: &Path, age: Duration) -> Result<Vec<Removed>, StoreError> {
    let folder = out
        .join(crate::names::RUNS_FOLDER)
        .join(crate::names::SET_ASIDE);
    crate::no_follow::check_under(
        out,
        &Path::new(crate::names::RUNS_FOLDER).join(crate::names::SET_ASIDE),
        false,
    )
    .map_err(|source| StoreError::Read {
        path: folder.clone(),
        source,
    })?;
    let listing = match std::fs::read_dir(&folder) {
        Ok(listing) => listing,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(source) => {
            return Err(StoreError::Read {
                path: folder,
                source,
            });
        }
    };
    let now = SystemTime::now();
    let mut removed = Vec::new();
    let mut paths: Vec<PathBuf> = listing.flatten().map(|entry| entry.path()).collect();
    paths.sort();
    for path in paths {
        let Ok(meta) = std::fs::symlink_metadata(&path) else {
            continue;
        };
        if meta.is_dir() {
            continue;
        }
        let modified = meta.modified().unwrap_or(now);
        let old = now.duration_since(modified).unwrap_or_default();
        if old <= age {
            continue;
        }
        std::fs::remove_file(&path).map_err(|source| StoreError::Write {
            path: path.clone(),
            source,
        })?;
        removed.push(Removed {
            path,
            why: format!("set aside {} days ago", old.as_secs() / 86_400),
        });
    }
    Ok(removed)
}

/// Removes the artefacts of `cache` whose keys are not in `needed`.
///
/// # Errors
/// [`StoreError`] if the cache cannot be listed or an artefact removed.
pub fn remove_artefacts_except(
    cache: &PretrainedStore,
    needed: &HashSet<RunKey>,
) -> Result<Vec<Removed>, StoreError> {
    let mut removed = Vec::new();
    for key in cache.keys()? {
        if needed.contains(&key) {
            continue;
        }
        cache.remove(&key)?;
        removed.push(Removed {
            path: cache.path(&key),
            why: "an artefact no run of the plan pre-trains".to_owned(),
        });
    }
    Ok(removed)
}

/// Moves the artefacts an earlier version kept in `out` (`runs/pretrained/`) into `cache`
/// (checked, as `merge` adopts them), then removes that folder's artefacts and the folder.
///
/// # Errors
/// [`StoreError`] if the artefacts cannot be copied or removed.
pub fn move_legacy_artefacts(
    out: &Path,
    cache: &PretrainedStore,
    warn: &mut dyn FnMut(&str),
) -> Result<Vec<Removed>, StoreError> {
    let legacy = PretrainedStore::legacy(out);
    if !legacy.folder().is_dir() {
        return Ok(Vec::new());
    }
    crate::no_follow::check_under(
        out,
        &Path::new(crate::names::RUNS_FOLDER).join(crate::names::PRETRAINED),
        false,
    )
    .map_err(|source| StoreError::Read {
        path: legacy.folder().to_path_buf(),
        source,
    })?;
    cache.adopt(&legacy, warn)?;
    let mut removed = Vec::new();
    for key in legacy.keys()? {
        legacy.remove(&key)?;
        removed.push(Removed {
            path: legacy.path(&key),
            why: format!(
                "an artefact of an earlier version's place (now in {})",
                cache.folder().display()
            ),
        });
    }
    legacy.remove_stale_temporary_files()?;
    let lock = crate::atomic::WritersLock::in_folder(legacy.folder());
    let _ = std::fs::remove_file(lock.path());
    // Empty now, unless it holds something not ours, which stays.
    let _ = std::fs::remove_dir(legacy.folder());
    Ok(removed)
}
