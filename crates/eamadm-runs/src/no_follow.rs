//! Paths inside an output folder, opened without following symbolic links and without hanging
//! on special files: a link, FIFO, socket or device where the project expects its own file or
//! folder is refused with an error naming it, so nothing is read, written, moved or deleted
//! outside `--out` through a planted link.
//!
//! On Unix a file is opened with `O_NOFOLLOW` (a link at the last component fails) and
//! `O_NONBLOCK` (opening a FIFO does not wait for a writer), then checked to be a regular file
//! with `fstat` on the open descriptor, so a swap between a check and the open cannot slip a
//! link or FIFO in. Folders are checked with `symlink_metadata`, which does not follow links.

use std::fs::File;
use std::io;
use std::path::{Component, Path};

/// The error for a path that is not what the project expects there.
#[must_use]
pub fn refused(path: &Path, what: &str) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "{}: {what} where eamadm expects its own {}; it is refused (nothing is read, \
             written or removed through it) — move it away",
            path.display(),
            if what.contains("folder") {
                "file"
            } else {
                "file or folder"
            }
        ),
    )
}

fn describe(kind: std::fs::FileType) -> &'static str {
    if kind.is_symlink() {
        "a symbolic link"
    } else if kind.is_dir() {
        "a folder"
    } else if kind.is_file() {
        "a file"
    } else {
        "a special file (FIFO, socket or device)"
    }
}

/// Opens the regular file `path` for reading, refusing a link or a special file.
pub fn open_regular(path: &Path) -> io::Result<File> {
    let kind = std::fs::symlink_metadata(path)?.file_type();
    if !kind.is_file() {
        return Err(refused(path, describe(kind)));
    }
    let mut options = File::options();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        // O_NOFOLLOW | O_NONBLOCK, the same values on Linux and macOS for the first; the second
        // is 0o4000 on Linux and 0x4 on macOS.
        #[cfg(target_os = "linux")]
        options.custom_flags(0o400_000 | 0o4000);
        #[cfg(target_os = "macos")]
        options.custom_flags(0x100 | 0x4);
    }
    let file = options.open(path).map_err(|error| {
        // ELOOP: the last component became a link after the check.
        if error.raw_os_error() == Some(40) || error.raw_os_error() == Some(62) {
            refused(path, "a symbolic link")
        } else {
            error
        }
    })?;
    let kind = file.metadata()?.file_type();
    if !kind.is_file() {
        return Err(refused(path, describe(kind)));
    }
    Ok(file)
}

/// Makes sure `path` is a real folder (creating it, but not its parents, when missing),
/// refusing a link or anything else in its place.
pub fn ensure_folder(path: &Path) -> io::Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_dir() => Ok(()),
        Ok(meta) => Err(refused(path, describe(meta.file_type()))),
        Err(error) if error.kind() == io::ErrorKind::NotFound => {
            match std::fs::create_dir(path) {
                Ok(()) => Ok(()),
                // Made by another process in between: check what it is.
                Err(error) if error.kind() == io::ErrorKind::AlreadyExists => ensure_folder(path),
                Err(error) => Err(error),
            }
        }
        Err(error) => Err(error),
    }
}

/// Makes sure every folder from `root` (created with its parents if missing; `root` itself
/// may be a link, as the user chose it) down to `root/relative` is a real folder.
pub fn ensure_folders(root: &Path, relative: &Path) -> io::Result<()> {
    std::fs::create_dir_all(root)?;
    let mut path = root.to_path_buf();
    for part in relative.components() {
        let Component::Normal(name) = part else {
            return Err(refused(&root.join(relative), "a path leaving the folder"));
        };
        path.push(name);
        ensure_folder(&path)?;
    }
    Ok(())
}

/// Checks that no existing component of `root/relative` below `root` is a link, and that the
/// last one, if it exists, is of the kind wanted (`want_file`: a regular file, else a folder).
/// Missing components are fine (nothing is there to follow).
pub fn check_under(root: &Path, relative: &Path, want_file: bool) -> io::Result<()> {
    let mut path = root.to_path_buf();
    let parts: Vec<Component<'_>> = relative.components().collect();
    for (index, part) in parts.iter().enumerate() {
        let Component::Normal(name) = part else {
            return Err(refused(&root.join(relative), "a path leaving the folder"));
        };
        path.push(name);
        let kind = match std::fs::symlink_metadata(&path) {
            Ok(meta) => meta.file_type(),
            Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(()),
            Err(error) => return Err(error),
        };
        let last = index + 1 == parts.len();
        let fine = if last && want_file {
            kind.is_file()
        } else {
            kind.is_dir()
        };
        if !fine {
            return Err(refused(&path, describe(kind)));
        }
    }
    Ok(())
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn links_and_fifos_are_refused_by_name_and_files_open() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("file");
        std::fs::write(&file, b"x").unwrap();
        assert!(open_regular(&file).is_ok());
        let link = dir.path().join("link");
        std::os::unix::fs::symlink(&file, &link).unwrap();
        let error = open_regular(&link).unwrap_err();
        assert!(
            error.to_string().contains("link: a symbolic link"),
            "{error}"
        );
        let fifo = dir.path().join("fifo");
        assert!(
            std::process::Command::new("mkfifo")
                .arg(&fifo)
                .status()
                .unwrap()
                .success()
        );
        let error = open_regular(&fifo).unwrap_err();
        assert!(error.to_string().contains("special file"), "{error}");
        let folder_link = dir.path().join("folder");
        std::os::unix::fs::symlink(dir.path(), &folder_link).unwrap();
        let error = ensure_folder(&folder_link).unwrap_err();
        assert!(
            error.to_string().contains("folder: a symbolic link"),
            "{error}"
        );
        let error = check_under(dir.path(), Path::new("folder/x"), true).unwrap_err();
        assert!(error.to_string().contains("a symbolic link"), "{error}");
        assert!(check_under(dir.path(), Path::new("missing/x"), true).is_ok());
        ensure_folders(dir.path(), Path::new("a/b")).unwrap();
        assert!(dir.path().join("a/b").is_dir());
    }
}
