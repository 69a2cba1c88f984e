//! The Rhai case-script engine of slosh.
//!
//! A case script declares its parameters with `param(name, default)`, describes the tank
//! (`tank(#{...})`), the numerics (`numerics(#{...})`) and the run (`run(#{...})`), and may
//! define `fn ground_accel(t)` (ground acceleration in m/s² at time `t` since the excitation
//! started) and `fn post(run)` (post-processing). The engine is sandboxed: no module imports,
//! no `eval`, limits on operations, call depth and sizes; files are read only through host
//! functions, relative to the script's folder, and paths that leave it are refused.

mod case;
mod engine;
mod error;
mod motion_api;
mod params;
mod spec;

pub use case::{list_params, load_case, Case, CaseOptions, Excitation, PostResult, RunData};
pub use engine::{resolve_script_path, PlotRequest};
pub use error::ScriptError;
pub use motion_api::MotionInfo;
pub use params::{parse_set_value, ParamDecl, ParamValue};
pub use spec::{GaugeSpec, RunSpec, TankSpec};
