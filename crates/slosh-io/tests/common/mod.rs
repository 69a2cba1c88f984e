//! Helpers shared by the integration tests.

use std::path::PathBuf;

/// A fresh, empty folder under the system temp dir, one per test name (emptied at the start
/// of the test and left afterwards so its files, e.g. the plots, can be looked at).
pub fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join("slosh-io-tests").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}
