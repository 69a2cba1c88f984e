//! The library behind the `slosh` command: argument-level helpers, signal handling, sweeps,
//! assessments and their Slurm job arrays, the bench and the validation command. A case is
//! run by `slosh-case` (the binary and the end-to-end tests call it through [`run_case`]);
//! the validation suite lives in `slosh-validate`.

pub mod assess;
pub mod bench;
pub mod converge;
pub mod interrupt;
pub mod runner;
pub mod shipped_scripts;
pub mod slurm;
pub mod sweep;
pub mod sweep_plot;
pub mod validate;

pub use runner::{run_case, run_case_with_stop, RunOptions, Summary};

/// The environment variable through which `slosh sweep --backend` and `slosh assess
/// --backend` tell their runs where to step ("cpu", "gpu" or "gpu_f32"); `slosh run` without `--backend`
/// reads it.
pub const BACKEND_ENV: &str = "SLOSH_BACKEND";

/// Parses `--set NAME=VALUE` arguments into the overrides of a case
/// ([`slosh_script::parse_sets`], as an error of the command line).
pub fn parse_sets(sets: &[String]) -> anyhow::Result<slosh_script::CaseOptions> {
    Ok(slosh_script::parse_sets(sets)?)
}
