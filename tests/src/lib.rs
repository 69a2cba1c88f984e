//! Helpers shared by the end-to-end validation tests: run a script from `scripts/` with
//! parameter overrides and read its outputs back.

use slosh_cli::{run_case, RunOptions, Summary};
use slosh_script::{load_case, parse_set_value, CaseOptions};
use std::path::{Path, PathBuf};

/// The repository root (the folder holding `scripts/`).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// A fresh output folder for a test, under the system temp folder.
pub fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-validation").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create test output folder");
    dir
}

/// Runs `scripts/<script>` with `NAME=VALUE` overrides into `out`, without plots or progress.
pub fn run_script(script: &str, sets: &[&str], out: &Path) -> anyhow::Result<Summary> {
    let mut options = CaseOptions::default();
    for s in sets {
        let (k, v) = s.split_once('=').expect("NAME=VALUE");
        options.overrides.push((k.to_string(), parse_set_value(v)));
    }
    let case = load_case(&repo_root().join("scripts").join(script), &options)?;
    run_case(
        case,
        &RunOptions {
            out_dir: out.to_path_buf(),
            progress: false,
            verbose: false,
            plots: false,
            max_memory_bytes: None,
            ..RunOptions::default()
        },
    )
}
