//! The error type shared by all writers of this crate.

use std::path::{Path, PathBuf};

/// Anything that can go wrong while writing (or reading back) an output file.
///
/// Every variant names the file it concerns, so a message can tell the user where to look,
/// and carries the system's or the library's reason in its message (not also as a `source`,
/// which an error chain would print a second time).
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused a file operation (create, write, rename).
    #[error("cannot write `{path}`: {reason}")]
    Io {
        /// The file or directory concerned.
        path: PathBuf,
        /// The underlying error.
        reason: std::io::Error,
    },
    /// The operating system refused to read a file (missing, unreadable).
    #[error("cannot read `{path}`: {reason}")]
    Read {
        /// The file concerned.
        path: PathBuf,
        /// The underlying error.
        reason: std::io::Error,
    },
    /// The CSV writer failed.
    #[error("cannot write CSV file `{path}`: {reason}")]
    Csv {
        /// The CSV file.
        path: PathBuf,
        /// The underlying error.
        reason: csv::Error,
    },
    /// A value could not be serialised to RON.
    #[error("cannot serialise `{path}` as RON: {reason}")]
    RonSerialize {
        /// The RON file.
        path: PathBuf,
        /// The underlying error.
        reason: ron::Error,
    },
    /// A RON file could not be parsed back.
    #[error("cannot parse RON file `{path}`: {reason}")]
    RonParse {
        /// The RON file.
        path: PathBuf,
        /// The underlying error (with line and column).
        reason: Box<ron::error::SpannedError>,
    },
    /// The caller passed data of inconsistent shape (wrong row length, mismatched array
    /// lengths, duplicate column names, ...).
    #[error("invalid data for `{path}`: {message}")]
    InvalidData {
        /// The file that was to be written.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The plotting library failed to draw or encode a figure.
    #[error("cannot draw plot `{path}`: {message}")]
    Plot {
        /// The image file.
        path: PathBuf,
        /// The plotting library's message.
        message: String,
    },
}

/// Short for `std::result::Result<T, IoError>`.
pub type Result<T> = std::result::Result<T, IoError>;

impl IoError {
    /// The file this error concerns.
    pub fn path(&self) -> &Path {
        match self {
            IoError::Io { path, .. }
            | IoError::Read { path, .. }
            | IoError::Csv { path, .. }
            | IoError::RonSerialize { path, .. }
            | IoError::RonParse { path, .. }
            | IoError::InvalidData { path, .. }
            | IoError::Plot { path, .. } => path,
        }
    }

    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        IoError::Io {
            path: path.to_path_buf(),
            reason: source,
        }
    }

    pub(crate) fn read(path: &Path, source: std::io::Error) -> Self {
        IoError::Read {
            path: path.to_path_buf(),
            reason: source,
        }
    }

    pub(crate) fn invalid(path: &Path, message: impl Into<String>) -> Self {
        IoError::InvalidData {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }
}

/// Creates the parent directory of `path` if it does not exist yet.
pub(crate) fn ensure_parent(path: &Path) -> Result<()> {
    if let Some(parent) = path.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent).map_err(|e| IoError::io(parent, e))?;
        }
    }
    Ok(())
}

/// Creates `path` as a new, empty file for writing, never through a link: a link (or a
/// folder, a device) at `path` is an error; an earlier regular file there is replaced. The file
/// is created with `O_EXCL` (`create_new`), which does not follow a link planted between the
/// check and the creation either.
pub fn create_fresh(path: &Path) -> std::io::Result<std::fs::File> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => {
            return Err(std::io::Error::other(
                "it is a link; slosh writes no file through a link",
            ))
        }
        Ok(m) if m.is_file() => std::fs::remove_file(path)?,
        Ok(_) => return Err(std::io::Error::other("it is not a file")),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(e),
    }
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)
}

/// Opens `path` with `options`, never through a link: the last component is opened with
/// `O_NOFOLLOW`, so a link there (even one planted after a check) is an error that says so.
/// The one place that opens an existing file of a run folder for writing (the case's lock and
/// log, a summary overwritten in place).
pub fn open_no_follow(
    path: &Path,
    options: &mut std::fs::OpenOptions,
) -> std::io::Result<std::fs::File> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW);
    }
    options.open(path).map_err(|e| {
        #[cfg(unix)]
        if e.raw_os_error() == Some(libc::ELOOP) {
            return std::io::Error::other(format!(
                "{} is a link; slosh writes no file through a link",
                path.display()
            ));
        }
        e
    })
}

/// Refuses a link (or anything but a file) at `path`, the target of a rename or of a writer
/// that opens the file itself.
pub(crate) fn refuse_link(path: &Path) -> Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() || !m.is_file() => Err(IoError::io(
            path,
            std::io::Error::other(
                "it is a link or not a file; slosh writes no file through a link",
            ),
        )),
        _ => Ok(()),
    }
}

/// Writes `bytes` to `path` atomically: first to a fresh temporary sibling ([`create_fresh`]),
/// then renamed over `path`, so a reader (or an aborted run) never sees a half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    ensure_parent(path)?;
    let mut tmp_name = path.as_os_str().to_owned();
    tmp_name.push(".tmp");
    let tmp = PathBuf::from(tmp_name);
    refuse_link(path)?;
    let written = create_fresh(&tmp).and_then(|mut f| f.write_all(bytes));
    if let Err(e) = written {
        // A part left behind by a full disk would starve the other files; a link refused at
        // `tmp` is not ours to remove.
        if e.kind() != std::io::ErrorKind::Other {
            let _ = std::fs::remove_file(&tmp);
        }
        return Err(IoError::io(&tmp, e));
    }
    std::fs::rename(&tmp, path).map_err(|e| IoError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A full disk's error names the file and the system's reason once: the reason is in the
    /// message and not also the error's source, which chain printers (`{:#}`) would append.
    #[test]
    fn the_reason_is_printed_once_in_an_error_chain() {
        let e = IoError::io(
            Path::new("out/series.csv"),
            std::io::Error::from_raw_os_error(28),
        );
        let shown = e.to_string();
        assert!(
            shown.starts_with("cannot write `out/series.csv`: ") && shown.contains("(os error 28)"),
            "{shown}"
        );
        assert!(std::error::Error::source(&e).is_none());
    }
}
