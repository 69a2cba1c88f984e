//! Running one case script into its run folder, as every front end does (`slosh run`,
//! `slosh resume`, the cases of a sweep or an assessment, the Python package, the end-to-end
//! tests).
//!
//! [`run_case_with_stop`] takes a [`slosh_script::Case`] (a script read with its `--set`
//! overrides, [`slosh_script::parse_sets`]) and:
//! 1. claims the output folder ([`run_folder`]: locked while the run writes it, an earlier
//!    run's outputs removed, or kept to resume);
//! 2. fits the tank to the particle lattice and builds the particles ([`build`]), after
//!    checking the memory the run will need ([`memory`]);
//! 3. runs them through the time loop of `slosh-run` with the run's files as its observer
//!    (`series.csv` row by row, frames, checkpoints ([`checkpoint`]), progress ([`progress`]));
//! 4. writes what is known at the end: `series.csv` with the low-pass load columns, the roof
//!    files ([`roof_files`]), the input spectrum ([`spectrum`]), the script's `post(run)`
//!    outputs ([`post`]), the plots and the [`Summary`] (`summary.ron`).
//!
//! Signals are not handled here: the caller passes a [`slosh_run::StopRequest`] and a stopped
//! run ends with the error [`Interrupted`]. Nothing is printed but the warnings of the run
//! (stderr), the progress and, with `verbose`, the particle counts and the result line.
//! `docs/design.md` says where this crate sits between the run loop and the front ends.
#![warn(missing_docs)]

pub mod build;
pub mod checkpoint;
mod files;
pub mod memory;
pub mod post;
pub mod progress;
pub mod roof_files;
pub mod run_folder;
mod runner;
pub mod spectrum;
mod stop;
mod summary;

pub use runner::{run_case_with_stop, RunOptions, NOTHING_TO_RESUME};
pub use stop::{Interrupted, TEST_STOP_AT_ENV};
pub use summary::{Summary, TheoryNumbers};
