//! Every tunable number of the solver, with its unit and the paper's default.

use crate::kernel::KernelKind;
use crate::neighbours::NeighbourBackend;
use serde::{Deserialize, Serialize};

/// How the pressure acting on a wall particle is evaluated for loads (not for the fluid's
/// motion, which always sees the wall particles' own pressure).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum WallPressureMethod {
    /// Paper §2.6: the pressure of the nearest fluid particle, smoothed in space by Eq. 23.
    NearestFluid,
    /// Shepard-normalised kernel interpolation of the fluid pressure at the wall face, with
    /// the hydrostatic correction ρ f·(x_face − x_j) of Adami, Hu & Adams (2012).
    KernelExtrapolation,
    /// The wall particle's own pressure from its summed density through the EOS.
    WallParticle,
}

/// Solver parameters. Units are SI; defaults are the paper's values as SPEC.md reads them.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SphParams {
    /// Reference density ρ0 (kg/m³).
    pub rest_density: f64,
    /// Dynamic viscosity μ of the Newtonian stress (Pa·s), Eq. 3.
    pub dynamic_viscosity: f64,
    /// Tait EOS stiffness B (Pa), Eq. 18.
    pub eos_stiffness: f64,
    /// Tait EOS exponent γ, Eq. 18.
    pub eos_gamma: f64,
    /// Smoothing length over lattice spacing, h/dx (paper read as 1.3: h = 0.026 m).
    pub smoothing_ratio: f64,
    /// Smoothing kernel.
    pub kernel: KernelKind,
    /// Monaghan artificial viscosity α_Π (Eq. 10).
    pub av_alpha: f64,
    /// Monaghan artificial viscosity β_Π (Eq. 10).
    pub av_beta: f64,
    /// η of the artificial-viscosity sound speed c = η √(200 g H) (Eq. 17).
    pub av_eta: f64,
    /// Override of the artificial-viscosity sound speed (m/s); `None` uses Eq. 17.
    pub av_sound_speed: Option<f64>,
    /// β_s of the free-surface density reset (Eq. 20).
    pub free_surface_threshold: f64,
    /// Clamp negative pressure to zero (p = max(p, 0)) on all particles (SPEC.md §4).
    pub clamp_negative_pressure: bool,
    /// Gravitational acceleration g (m/s²), acting along −(last axis).
    pub gravity: f64,
    /// Courant number C of the acoustic and force time-step bounds.
    pub cfl_number: f64,
    /// Fixed time step (s); `None` = CFL-variable time step.
    pub fixed_dt: Option<f64>,
    /// Accept a fixed time step above the stability bound.
    pub allow_unstable_dt: bool,
    /// Neighbour-search implementation.
    pub neighbour_backend: NeighbourBackend,
    /// Re-sort the fluid particles by cell every this many steps (0 = never).
    pub reorder_interval: usize,
    /// How wall pressure is evaluated for loads.
    pub wall_pressure: WallPressureMethod,
    /// ε of the spatial pressure smoothing of Eq. 23 (used by `NearestFluid`).
    pub pressure_smoothing_eps: f64,
    /// N of the ±N-step centred rectangular time window applied to wall pressures (§2.6).
    pub smoothing_steps: usize,
}

impl Default for SphParams {
    fn default() -> Self {
        SphParams {
            rest_density: 1000.0,
            dynamic_viscosity: 1.0e-3,
            eos_stiffness: 1.013e5,
            eos_gamma: 7.0,
            smoothing_ratio: 1.3,
            kernel: KernelKind::CubicSpline,
            av_alpha: 0.01,
            av_beta: 0.0,
            av_eta: 0.1,
            av_sound_speed: None,
            free_surface_threshold: 0.95,
            clamp_negative_pressure: true,
            gravity: 9.81,
            cfl_number: 0.25,
            fixed_dt: None,
            allow_unstable_dt: false,
            neighbour_backend: NeighbourBackend::CellGrid,
            reorder_interval: 10,
            wall_pressure: WallPressureMethod::NearestFluid,
            pressure_smoothing_eps: 0.5,
            smoothing_steps: 20,
        }
    }
}

impl SphParams {
    /// Speed of sound of the Tait EOS, c0 = √(γ B / ρ0) (m/s).
    pub fn eos_sound_speed(&self) -> f64 {
        (self.eos_gamma * self.eos_stiffness / self.rest_density).sqrt()
    }
}
