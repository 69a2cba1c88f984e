//! The error type shared by all writers of this crate.

use std::path::{Path, PathBuf};

/// Anything that can go wrong while writing (or reading back) an output file.
///
/// Every variant names the file it concerns, so a message can tell the user where to look.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused a file operation (create, write, rename, read).
    #[error("cannot write `{path}`: {source}")]
    Io {
        /// The file or directory concerned.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The CSV writer failed.
    #[error("cannot write CSV file `{path}`: {source}")]
    Csv {
        /// The CSV file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: csv::Error,
    },
    /// A value could not be serialised to RON.
    #[error("cannot serialise `{path}` as RON: {source}")]
    RonSerialize {
        /// The RON file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: ron::Error,
    },
    /// A RON file could not be parsed back.
    #[error("cannot parse RON file `{path}`: {source}")]
    RonParse {
        /// The RON file.
        path: PathBuf,
        /// The underlying error (with line and column).
        #[source]
        source: Box<ron::error::SpannedError>,
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
            source,
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

/// Writes `bytes` to `path` atomically: first to a temporary sibling, then renamed over
/// `path`, so a reader (or an aborted run) never sees a half-written file.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    ensure_parent(path)?;
    let mut tmp_name = path.as_os_str().to_owned();
    tmp_name.push(".tmp");
    let tmp = PathBuf::from(tmp_name);
    std::fs::write(&tmp, bytes).map_err(|e| IoError::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| IoError::io(path, e))
}
