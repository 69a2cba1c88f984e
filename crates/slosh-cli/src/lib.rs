//! The library behind the `slosh` command: building tanks from scripts, running cases and
//! writing their outputs. The binary, `slosh validate` and the validation tests share it.

pub mod build;
pub mod post;
pub mod runner;

pub use runner::{run_case, RunOptions, Summary};
