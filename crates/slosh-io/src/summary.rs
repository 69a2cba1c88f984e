//! Pretty RON files (a run's `summary.ron`, and any other structured record).

use std::path::Path;

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::error::{write_atomic, IoError, Result};

/// Writes `value` to `path` as pretty-printed RON (creating the folder). The file is written
/// to a temporary sibling first and then renamed, so it is never seen half-written.
pub fn write_ron<T: Serialize + ?Sized>(path: impl AsRef<Path>, value: &T) -> Result<()> {
    let path = path.as_ref();
    write_atomic(path, ron_text(path, value)?.as_bytes())
}

/// `value` as the pretty-printed RON text of the file `path` (named in errors), with a final
/// newline.
fn ron_text<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<String> {
    let mut text =
        ron::ser::to_string_pretty(value, ron::ser::PrettyConfig::new()).map_err(|source| {
            IoError::RonSerialize {
                path: path.to_path_buf(),
                reason: source,
            }
        })?;
    text.push('\n');
    Ok(text)
}

/// Overwrites the existing file `path` with `value` in place, for a full disk where
/// [`write_ron`]'s temporary sibling cannot be written: cutting the old file first frees the
/// space the new text needs. Refuses a link or anything but an existing regular file. A
/// reader may see the file half-written while this runs; use [`write_ron`] wherever it can.
pub fn overwrite_ron_in_place<T: Serialize + ?Sized>(
    path: impl AsRef<Path>,
    value: &T,
) -> Result<()> {
    use std::io::Write;
    let path = path.as_ref();
    let text = ron_text(path, value)?;
    crate::error::refuse_link(path)?;
    let written = crate::open_no_follow(path, std::fs::OpenOptions::new().write(true)).and_then(
        |mut file| {
            file.set_len(0)?;
            file.write_all(text.as_bytes())?;
            file.sync_all()
        },
    );
    written.map_err(|e| IoError::io(path, e))
}

/// Reads a RON file written by [`write_ron`] (or by hand) back into a `T`.
pub fn read_ron<T: DeserializeOwned>(path: impl AsRef<Path>) -> Result<T> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| IoError::read(path, e))?;
    ron::from_str(&text).map_err(|source| IoError::RonParse {
        path: path.to_path_buf(),
        reason: Box::new(source),
    })
}
