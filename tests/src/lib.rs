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

/// Reads a column of `series.csv` in `out`.
pub fn series_column(out: &Path, name: &str) -> Vec<f64> {
    let table = slosh_io::read_table(out.join("series.csv")).expect("read series.csv");
    table
        .column(name)
        .unwrap_or_else(|| panic!("series.csv has no column {name}"))
}

/// Mean period (s) of a signal from its upward crossings of its mean value, linearly
/// interpolated between samples; `None` with fewer than two crossings.
pub fn period_from_crossings(t: &[f64], y: &[f64]) -> Option<f64> {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let mut crossings = Vec::new();
    for i in 1..y.len() {
        let (a, b) = (y[i - 1] - mean, y[i] - mean);
        if a < 0.0 && b >= 0.0 {
            crossings.push(t[i - 1] + (t[i] - t[i - 1]) * (-a) / (b - a));
        }
    }
    if crossings.len() < 2 {
        return None;
    }
    Some((crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64)
}
