//! The Rhai case-script engine of slosh.
//!
//! A case script declares its parameters with `param(name, default)`, describes the tank
//! (`tank(#{...})`), the numerics (`numerics(#{...})`) and the run (`run(#{...})`), and may
//! define `fn ground_accel(t)` (ground acceleration in m/s² at time `t` since the excitation
//! started) and `fn post(run)` (post-processing). The engine is sandboxed: no module imports,
//! no `eval`, limits on operations, call depth, sizes and the script's total memory; files
//! are read only through host functions, below the script's folder, its project folder or an
//! `--allow-read` folder ([`ReadSandbox`]), and paths that leave them are refused.
//!
//! Ground motion in scripts: `load_record(path, #{units, dt, format})` reads a PEER AT2,
//! K-NET or plain-text record (m/s², 1 g = 9.81 m/s²) with processing methods (`scale`,
//! `scale_to_pga`, `remove_mean`, `detrend`, `bandpass`, `highpass`, `lowpass`, `trim`,
//! `shift`) and `at(t)`; `sine(A, ω[, φ])` and `sines([[A, ω], ...])` give the paper's
//! a_g(t) = +A ω² sin(ωt + φ); `+` adds records and sines. Every record read is listed as a
//! [`MotionInfo`] (file, SHA-256, scaling, processing).
#![warn(missing_docs)]

mod case;
mod checks;
mod engine;
mod error;
mod memory;
mod motion_api;
mod params;
mod sandbox;
mod spec;

pub use case::{
    list_params, list_params_with, load_case, Case, CaseOptions, Excitation, PostResult, RunData,
};
pub use engine::{resolve_script_path, PlotRequest};
pub use error::ScriptError;
pub use memory::{stop_flag, stop_requested, SCRIPT_MEMORY_BUDGET_BYTES};
pub use motion_api::MotionInfo;
pub use params::{parse_set_value, parse_sets, ParamDecl, ParamValue, SetArgumentError};
pub use sandbox::{ReadSandbox, PROJECT_MARKER};
pub use spec::{
    GaugeSpec, MeshExtent, PressureSensorSpec, Resolution, RunSpec, SectionOutlineSpec,
    SectionRoofSpec, TankSpec, DEFAULT_ROOF_DAMPING, DEFAULT_ROOF_PERIODS,
};
