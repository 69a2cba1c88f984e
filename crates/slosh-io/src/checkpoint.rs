//! Checkpoint files: a value (any serde type) in a compact binary container with a format
//! version and a checksum, written atomically.
//!
//! Layout: the 8 bytes `SLOSHCKP`, the container version (u32, little-endian), the length of
//! the payload in bytes (u64 LE), its CRC-32 (IEEE, u32 LE), then the payload in postcard
//! encoding (<https://postcard.jamesmunns.com>; f64 values are stored as their 8 bytes, so
//! they come back bit for bit). The file is written to `NAME.part`, flushed to disk and
//! renamed over `NAME`: a crash while writing leaves the previous checkpoint whole.

use crate::error::{IoError, Result};
use serde::{de::DeserializeOwned, Serialize};
use std::io::Write;
use std::path::Path;

/// The first bytes of every checkpoint file.
pub const CHECKPOINT_MAGIC: &[u8; 8] = b"SLOSHCKP";
/// The version of the container layout (not of what it holds).
pub const CHECKPOINT_VERSION: u32 = 1;
const HEADER_BYTES: usize = 8 + 4 + 8 + 4;

fn io_error(path: &Path, source: std::io::Error) -> IoError {
    IoError::Io {
        path: path.to_path_buf(),
        reason: source,
    }
}

fn invalid(path: &Path, message: impl Into<String>) -> IoError {
    IoError::InvalidData {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// Writes `value` to `path` as a checkpoint, atomically (see the module notes); returns the
/// number of bytes written.
pub fn write_checkpoint<T: Serialize>(path: &Path, value: &T) -> Result<u64> {
    let payload = postcard::to_stdvec(value)
        .map_err(|e| invalid(path, format!("cannot encode the checkpoint: {e}")))?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
    }
    let mut part = path.as_os_str().to_owned();
    part.push(".part");
    let part = std::path::PathBuf::from(part);
    let write = || -> std::io::Result<()> {
        let mut file = crate::error::create_fresh(&part)?;
        file.write_all(CHECKPOINT_MAGIC)?;
        file.write_all(&CHECKPOINT_VERSION.to_le_bytes())?;
        file.write_all(&(payload.len() as u64).to_le_bytes())?;
        file.write_all(&crc32fast::hash(&payload).to_le_bytes())?;
        file.write_all(&payload)?;
        file.sync_all()
    };
    if let Err(e) = write() {
        // A part left behind by a full disk would starve the run's other files; a link
        // refused at `part` is not ours to remove.
        if e.kind() != std::io::ErrorKind::Other {
            let _ = std::fs::remove_file(&part);
        }
        return Err(io_error(&part, e));
    }
    std::fs::rename(&part, path).map_err(|e| io_error(path, e))?;
    Ok((HEADER_BYTES + payload.len()) as u64)
}

/// Reads a checkpoint written by [`write_checkpoint`]; a file that is not a checkpoint, of
/// another container version, cut short or corrupted is refused with a message saying which.
pub fn read_checkpoint<T: DeserializeOwned>(path: &Path) -> Result<T> {
    let bytes = std::fs::read(path).map_err(|e| IoError::read(path, e))?;
    if bytes.len() < HEADER_BYTES || &bytes[..8] != CHECKPOINT_MAGIC {
        return Err(invalid(path, "not a slosh checkpoint file"));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if version != CHECKPOINT_VERSION {
        return Err(invalid(
            path,
            format!(
                "checkpoint container version {version}; this program reads version \
                 {CHECKPOINT_VERSION}"
            ),
        ));
    }
    let length = u64::from_le_bytes(bytes[12..20].try_into().expect("8 bytes"));
    let checksum = u32::from_le_bytes(bytes[20..24].try_into().expect("4 bytes"));
    let payload = &bytes[HEADER_BYTES..];
    if payload.len() as u64 != length {
        return Err(invalid(
            path,
            format!(
                "the checkpoint is cut short or padded: {} payload bytes where the header \
                 says {length}",
                payload.len()
            ),
        ));
    }
    if crc32fast::hash(payload) != checksum {
        return Err(invalid(
            path,
            "the checkpoint is corrupted (checksum mismatch)",
        ));
    }
    postcard::from_bytes(payload).map_err(|e| {
        invalid(
            path,
            format!(
                "cannot decode the checkpoint ({e}): it was written by a slosh build whose \
                     run state differs from this one's; rerun the case from the start, or \
                     resume with the build that wrote it"
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Serialize, serde::Deserialize, PartialEq, Debug)]
    struct Sample {
        values: Vec<f64>,
        step: u64,
        name: String,
    }

    fn sample() -> Sample {
        Sample {
            // Values whose decimal forms do not round-trip in few digits, and the extremes.
            values: vec![0.1 + 0.2, -1e-310, f64::MAX, f64::INFINITY, -0.0, 1.0 / 3.0],
            step: 1 << 40,
            name: "état".into(),
        }
    }

    #[test]
    fn round_trip_is_bit_for_bit() {
        let dir = std::env::temp_dir().join(format!("slosh-ckp-{}", std::process::id()));
        let path = dir.join("state.bin");
        write_checkpoint(&path, &sample()).unwrap();
        let back: Sample = read_checkpoint(&path).unwrap();
        let bits = |s: &Sample| s.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&sample()));
        assert_eq!(
            back,
            Sample {
                values: back.values.clone(),
                ..sample()
            }
        );
        assert!(!dir.join("state.bin.part").exists());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn damaged_files_are_refused() {
        let dir = std::env::temp_dir().join(format!("slosh-ckp-bad-{}", std::process::id()));
        let path = dir.join("state.bin");
        write_checkpoint(&path, &sample()).unwrap();
        let good = std::fs::read(&path).unwrap();
        let cases: Vec<(Vec<u8>, &str)> = vec![
            (b"not a checkpoint".to_vec(), "not a slosh checkpoint"),
            (good[..good.len() - 3].to_vec(), "cut short"),
            (
                {
                    let mut b = good.clone();
                    let last = b.len() - 1;
                    b[last] ^= 0x40;
                    b
                },
                "corrupted",
            ),
            (
                {
                    let mut b = good.clone();
                    b[8] = 99;
                    b
                },
                "version 99",
            ),
        ];
        for (bytes, expected) in cases {
            std::fs::write(&path, bytes).unwrap();
            let err = read_checkpoint::<Sample>(&path).unwrap_err().to_string();
            assert!(err.contains(expected), "{err}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
