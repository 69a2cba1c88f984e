//! The library behind the `slosh` command: building tanks from scripts, running cases through
//! the run loop of `slosh-run` and writing their outputs. The binary and the end-to-end tests
//! share it; the validation suite lives in `slosh-validate`.

pub mod assess;
pub mod bench;
pub mod build;
pub mod checkpoint;
pub mod interrupt;
pub mod memory;
pub mod post;
pub mod progress;
pub mod roof_files;
pub mod run_folder;
pub mod runner;
pub mod shipped_scripts;
pub mod slurm;
pub mod spectrum;
pub mod sweep;
pub mod sweep_plot;
pub mod validate;

pub use runner::{run_case, run_case_with_stop, RunOptions, Summary};

/// Parses `--set NAME=VALUE` arguments into the overrides of a case (the value as
/// [`slosh_script::parse_set_value`] reads it).
pub fn parse_sets(sets: &[String]) -> anyhow::Result<slosh_script::CaseOptions> {
    let mut options = slosh_script::CaseOptions::default();
    for s in sets {
        let Some((name, value)) = s.split_once('=') else {
            anyhow::bail!("--set {s}: expected NAME=VALUE, e.g. --set duration=6");
        };
        let name = name.trim();
        if name.is_empty() {
            anyhow::bail!("--set {s}: the parameter name is empty");
        }
        options
            .overrides
            .push((name.to_string(), slosh_script::parse_set_value(value)));
    }
    Ok(options)
}
