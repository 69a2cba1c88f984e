//! The library behind the `slosh` command: building tanks from scripts, running cases through
//! the run loop of `slosh-run` and writing their outputs. The binary and the end-to-end tests
//! share it; the validation suite lives in `slosh-validate`.

pub mod assess;
pub mod bench;
pub mod checkpoint;
pub mod build;
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

pub use runner::{run_case, RunOptions, Summary};
