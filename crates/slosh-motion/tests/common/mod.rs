//! Shared helpers for the tests: unique temporary files.

#![allow(dead_code)] // each test binary uses only some helpers

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// Writes `contents` to a fresh file named `<stem>-<pid>-<n>-<nanos>.<ext>` in the temp dir.
pub fn temp_file(stem: &str, ext: &str, contents: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::SeqCst);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let dir = std::env::temp_dir().join(format!("slosh-motion-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create temp dir");
    let path = dir.join(format!("{stem}-{n}-{nanos}.{ext}"));
    std::fs::write(&path, contents).expect("write temp file");
    path
}

/// The El Centro record shipped in the workspace's data folder.
pub fn elcentro_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/elcentro_1940_ns.at2")
}
