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

/// Most worker threads per core that `--threads` may ask for: more only adds switching, and a
/// typo (`--threads 99999999999`) must not start threads until the system refuses.
pub const MAX_THREADS_PER_CORE: usize = 8;

/// Reads a `--threads` value (every command's, also a sweep's or an assessment's array task,
/// checked before anything starts): at least 1, at most [`MAX_THREADS_PER_CORE`] per core.
pub fn thread_count(text: &str) -> Result<usize, String> {
    let n: usize = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a whole number of threads"))?;
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    if n == 0 {
        return Err("must be at least 1".into());
    }
    if n > MAX_THREADS_PER_CORE * cores {
        return Err(format!(
            "{n} is more than {MAX_THREADS_PER_CORE} per core of this machine ({cores} cores); \
             give at most {}",
            MAX_THREADS_PER_CORE * cores
        ));
    }
    Ok(n)
}

/// Parses `--set NAME=VALUE` arguments into the overrides of a case
/// ([`slosh_script::parse_sets`], as an error of the command line).
pub fn parse_sets(sets: &[String]) -> anyhow::Result<slosh_script::CaseOptions> {
    Ok(slosh_script::parse_sets(sets)?)
}
