//! The SPH solver of slosh, written once and generic over the dimension `D` (2 or 3).
//!
//! The scheme is the paper's (Ono, Iwamoto & Scawthorn 2007, §2): weakly compressible SPH
//! with the cubic B-spline kernel, Tait EOS, summation density with a free-surface reset,
//! the symmetric momentum equation with Newtonian viscous stress and Monaghan artificial
//! viscosity, three layers of fixed wall particles and leap-frog time integration. Beside it,
//! switchable one by one: continuity density with δ-SPH diffusion, Adami walls,
//! the Wendland C2 kernel, symplectic time integration and particle shifting. No file,
//! printing or scripting here: the crate takes particles and parameters and returns numbers.
//!
//! Layout (`docs/design.md` has the whole picture):
//! - `sim/`: the particle arrays, the construction of a [`Simulation`], the step pipeline;
//! - `stages/`: the stages of a step, one file each, chosen once per run;
//! - `sweep/`: the pair-sweep drivers and their scheduling (every `unsafe` line is there);
//! - `terms/`: each pair term once (momentum, the coupled continuity/diffusion/shifting
//!   sums, the velocity gradient, wall summation);
//! - `kernel.rs`, `neighbours.rs`, `loads.rs`, `gauge.rs`, `sound_speed.rs`, `params.rs`.
#![warn(missing_docs)]

/// Evaluates `$body` with `$s` bound to the search of whichever backend `$search` holds (the
/// body is compiled once per backend).
macro_rules! with_search {
    ($search:expr, $s:ident => $body:expr) => {
        match $search {
            Search::Grid($s) => $body,
            Search::KdTree($s) => $body,
        }
    };
}

pub mod device;
pub mod error;
pub mod frame;
pub mod gauge;
pub mod kernel;
pub mod loads;
pub mod neighbours;
pub mod params;
pub mod setup;
pub mod sim;
pub mod sound_speed;
mod stages;
mod sweep;
mod terms;

pub use device::{device_unsupported, DeviceSetup, DeviceStepReport, StepDevice};
pub use error::SimError;
pub use frame::TankRotation;
pub use kernel::{Kernel, KernelKind};
pub use loads::{LoadEvaluator, LoadPeaks, LoadState, PartLoads};
pub use neighbours::{CellGrid, KdTreeSearch, NeighbourBackend, NeighbourSearch};
pub use params::{
    ArtificialSoundSpeed, Backend, BoundaryMethod, DensityDiffusion, DensityMethod, Integrator,
    PairScheme, SoundSpeedRule, SphParams, ViscousOperator, WallPressureMethod,
    PAPER_EOS_STIFFNESS,
};
pub use setup::{ParticleSetup, TankInterior, PART_BOTTOM, PART_ROOF, PART_WALL};
pub use sim::{Fluid, PhaseTimes, SimState, Simulation, StepStats, Tensor, Vector, Walls};
pub use sound_speed::SoundSpeedChoice;

#[cfg(test)]
mod test_tank;
#[cfg(test)]
mod tests_checkpoint;
#[cfg(test)]
mod tests_golden;
#[cfg(test)]
mod tests_modern;
#[cfg(test)]
mod tests_physics;
#[cfg(test)]
mod tests_riemann;
