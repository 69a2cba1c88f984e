//! The slosh run loop as a library, for every front end (the command line, the validation
//! suite, the benchmark, tests, a Python package).
//!
//! - [`advance`] is the one time loop: it asks a [`GroundMotion`] for the ground acceleration
//!   once per step, steps the solver, and calls [`StepHooks`] around each step.
//! - [`run_case`] runs a case on that loop: the measurements of every output interval (the
//!   columns of `series.csv`), the time-windowed loads, the roof pressure map and impacts
//!   (paper §3.2) and the low-pass load columns, handed row by row to an [`Observer`] and
//!   returned as an in-memory [`RunResult`].
//!
//! No files are written here and no signals are handled: a front end writes files from its
//! observer and asks for a stop through a [`StopRequest`]. `docs/design.md` describes how the
//! pieces fit.

#![warn(missing_docs)]

pub mod load_filter;
pub mod motion;
pub mod roof;
pub mod roof_load;
pub mod run;
pub mod stepping;

pub use load_filter::{LoadFilter, LoadPeak};
pub use motion::{to_vector, AfterSettling, AtRest, GroundMotion, MotionError};
pub use roof::{RoofImpact, RoofMonitor, RoofSnapshot, RoofTank};
pub use roof_load::{PressureSensor, RoofLoadPlan, RoofLoadResult, RoofLoadSummary, Spread};
pub use run::{
    part_force_column, run_case, run_case_from, sensor_column, wall_gauges, Gauge, Observer,
    RunCheckpoint, RunPlan, RunResult, RunStatus,
};
pub use stepping::{
    advance, advance_with, AfterEachStep, EachStep, HookError, StepError, StepHooks, StepPhase,
    StopRequest, Until,
};
