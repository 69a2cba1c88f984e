//! The library behind the `slosh` command: building tanks from scripts, running cases and
//! writing their outputs. The binary, `slosh validate` and the validation tests share it.

pub mod assess;
pub mod bench;
pub mod build;
pub mod interrupt;
pub mod load_filter;
pub mod memory;
pub mod post;
pub mod progress;
pub mod roof;
pub mod run_folder;
pub mod runner;
pub mod shipped_scripts;
pub mod slurm;
pub mod spectrum;
pub mod sweep;
pub mod sweep_plot;
pub mod validate;

pub use runner::{run_case, RunOptions, Summary};
