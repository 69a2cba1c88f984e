//! A compute device that runs the modern step in place of the CPU stages: the interface the
//! GPU backend (`slosh-gpu`) implements. The [`crate::Simulation`] keeps its host arrays, the
//! time, the step statistics and the load evaluation; the device advances the particles and
//! hands back, every step, what the host needs every step (the step length, the largest speed
//! and acceleration, the blow-up counts and the wall pressures the loads are read from).
//! The fluid arrays come back only when a caller asks for them
//! ([`crate::Simulation::sync_host`]): at an output row, a frame or a checkpoint.

use crate::error::SimError;
use crate::kernel::KernelKind;
use crate::params::SphParams;
use crate::sim::{Fluid, Vector, Walls};

/// What a device needs to run the step of a simulation: its parameters as the run uses them
/// (the stiffness chosen for the tank), the derived constants, the domain and the particles.
pub struct DeviceSetup<'a, const D: usize> {
    /// The run's parameters (`eos_stiffness` as chosen for the tank).
    pub params: &'a SphParams,
    /// Smoothing length h (m).
    pub smoothing_length: f64,
    /// Particle mass m = ρ0 dx^D (kg, 2D: kg per m of depth).
    pub mass: f64,
    /// Lattice spacing dx (m).
    pub spacing: f64,
    /// EOS sound speed c0 (m/s).
    pub sound_speed: f64,
    /// Sound speed of the artificial viscosity (m/s).
    pub av_sound_speed: f64,
    /// δ h c0 of the density diffusion (m²/s); 0 without diffusion.
    pub diffusion_coeff: f64,
    /// Whether the diffusion differences the dynamic density ρ − ρ_H (Fourtakas et al. 2019).
    pub hydrostatic_diffusion: bool,
    /// Still level z_s (m), from which the hydrostatic density of the diffusion is measured.
    pub still_level: f64,
    /// Lower and upper corners of the computational domain (m): a particle leaving it is a
    /// blow-up.
    pub domain_min: Vector<D>,
    /// See `domain_min`.
    pub domain_max: Vector<D>,
    /// The fluid particles (the host arrays, in their current order).
    pub fluid: &'a Fluid<D>,
    /// The wall particles.
    pub walls: &'a Walls<D>,
}

/// What a device step hands back to the host.
#[derive(Clone, Copy, Debug, Default)]
pub struct DeviceStepReport<const D: usize> {
    /// The step length taken (s).
    pub dt: f64,
    /// The largest fluid speed |v| at the start of the step (m/s), from which dt was chosen.
    pub max_speed: f64,
    /// The largest acceleration |a| of the previous force pass (m/s²).
    pub max_acceleration: f64,
    /// Fluid particles with a non-finite position or velocity after the step.
    pub non_finite: u32,
    /// Fluid particles outside the domain after the step.
    pub outside: u32,
    /// One of them, when any (m).
    pub first_outside: Option<Vector<D>>,
}

/// A device that advances the modern step (the GPU backend).
pub trait StepDevice<const D: usize>: Send {
    /// Which device and precision, for summaries (e.g. "llvmpipe (Vulkan), f64").
    fn description(&self) -> String;

    /// Loads the state of the host arrays (after the simulation was built or restored).
    fn upload(&mut self, setup: &DeviceSetup<'_, D>) -> Result<(), SimError>;

    /// One step under the body force `body_force` (m/s², gravity and the ground
    /// acceleration's inertia force): the particles advance on the device, and the wall
    /// particles' pressure and density of this step are written into `walls` (the loads of
    /// the step are read from them).
    fn step(
        &mut self,
        body_force: Vector<D>,
        walls: &mut Walls<D>,
    ) -> Result<DeviceStepReport<D>, SimError>;

    /// Copies the fluid state (positions, velocities, accelerations, densities, pressures,
    /// density rates, ids) into the host arrays, in the device's order.
    fn download(&mut self, fluid: &mut Fluid<D>) -> Result<(), SimError>;

    /// Device time of each kernel summed over the run (name, s), for `slosh bench`: each
    /// kernel's own while profiling ([`Self::set_profiling`]), else the whole step's.
    fn kernel_times(&self) -> Vec<(String, f64)>;

    /// Profiling: each kernel submitted and waited for alone, so that its time can be told
    /// apart (slower than one submission per step).
    fn set_profiling(&mut self, on: bool);
}

/// Why the parameters of a run cannot go to a device, or `None` when they can: the device
/// runs the modern step as the preset builds it, with each of its parts switchable only
/// within what the device implements.
pub fn device_unsupported(params: &SphParams) -> Option<String> {
    use crate::params::*;
    let mut reasons = Vec::new();
    if params.density != DensityMethod::Continuity {
        reasons.push("continuity density (density \"continuity\")");
    }
    if matches!(
        params.density_diffusion,
        DensityDiffusion::MolteniColagrossi { .. }
    ) {
        reasons.push("the Fourtakas density diffusion or none (not \"molteni_colagrossi\")");
    }
    if params.boundary != BoundaryMethod::Adami || params.wall_no_slip {
        reasons.push("free-slip Adami walls (boundary \"adami\", wall_no_slip false)");
    }
    if params.integrator != Integrator::Symplectic {
        reasons.push("the symplectic integrator");
    }
    if params.kernel != KernelKind::WendlandC2 {
        reasons.push("the Wendland C2 kernel");
    }
    if params.pair_scheme != PairScheme::Standard {
        reasons.push("the standard pair (pair_scheme \"standard\")");
    }
    if params.viscous_operator != ViscousOperator::MonaghanCleary && params.dynamic_viscosity > 0.0
    {
        reasons.push("the single-sum viscous operator (viscous_operator \"monaghan_cleary\")");
    }
    if params.shifting.is_some_and(|a| a > 0.0) {
        reasons.push("no particle shifting");
    }
    if params.wall_pressure != WallPressureMethod::WallParticle {
        reasons.push("wall loads from the wall particles (wall_pressure \"wall_particle\")");
    }
    if params.clamp_negative_pressure {
        reasons.push("no clamp of negative pressure");
    }
    if params.neighbour_backend != crate::neighbours::NeighbourBackend::CellGrid {
        reasons.push("the cell-grid neighbour search");
    }
    let gamma = params.eos_gamma;
    if !(gamma.fract() == 0.0 && (2.0..=15.0).contains(&gamma)) {
        reasons.push("a whole EOS exponent γ between 2 and 15");
    }
    (!reasons.is_empty()).then(|| {
        format!(
            "the GPU backend runs the modern step; this run needs {}",
            reasons.join(", ")
        )
    })
}
