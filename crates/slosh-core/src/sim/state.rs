//! The particle arrays and the per-run constants of the passes.

use crate::kernel::Kernel;
use crate::params::{DensityDiffusion, DensityMethod, Integrator, SphParams};
use crate::sim::*;
use crate::sound_speed::TaitColumn;

/// Chunk length for rayon loops: large enough to amortise scheduling.
pub(crate) const PAR_CHUNK: usize = 256;

/// Candidates gathered before evaluation in the sorted density pass.
pub(crate) const BATCH: usize = 32;
/// Marks a wall particle in a neighbour list (the low 31 bits hold its index).
pub(crate) const WALL_NEIGHBOUR: u32 = 1 << 31;
/// Count value meaning "the list overflowed: search again".
pub(crate) const LIST_OVERFLOW: u16 = u16::MAX;

/// Per-particle neighbour lists filled by the density pass and read by the force pass, so the
/// force pass does not scan and reject the grid's candidates again (in 3D only ≈ 15 % of the
/// 27-cell candidates are neighbours). Fixed capacity per particle, allocated once; a particle
/// with more neighbours is marked and searched again.
#[derive(Clone, Debug, Default)]
pub struct NeighbourLists {
    pub(crate) capacity: usize,
    pub(crate) entries: Vec<u32>,
    pub(crate) count: Vec<u16>,
    /// Sorted sweeps: where each particle's list starts in `entries`. The lists of a sweep
    /// block are packed one after the other in the block's share of `entries` (its particles
    /// × capacity), so the force sweep reads them as one stream; empty for the other passes,
    /// whose lists start at i × capacity.
    pub(crate) start: Vec<u32>,
}

impl NeighbourLists {
    /// Lists for `n` particles with room for `capacity` neighbours each.
    pub(crate) fn new(n: usize, capacity: usize) -> Self {
        NeighbourLists {
            capacity,
            entries: vec![0; n * capacity],
            count: vec![LIST_OVERFLOW; n],
            start: Vec::new(),
        }
    }

    /// Bytes held by the lists.
    pub fn heap_bytes(&self) -> usize {
        self.entries.len() * 4 + self.count.len() * 2 + self.start.len() * 4
    }
}

/// Fluid particles, struct of arrays. Index i is the same particle in every array; the order
/// changes when particles are re-sorted by cell (`id` keeps the original index).
#[derive(Clone, Debug, Default)]
pub struct Fluid<const D: usize> {
    /// Position (m).
    pub position: Vec<Vector<D>>,
    /// Velocity at the current integer time (m/s), leap-frog estimate.
    pub velocity: Vec<Vector<D>>,
    /// Velocity at the last half step (m/s), the leap-frog state.
    pub velocity_half: Vec<Vector<D>>,
    /// Acceleration of the last force pass (m/s²).
    pub acceleration: Vec<Vector<D>>,
    /// Density (kg/m³).
    pub density: Vec<f64>,
    /// 1/density (m³/kg), kept beside the density so the pair loops multiply instead of divide.
    pub inverse_density: Vec<f64>,
    /// Pressure (Pa).
    pub pressure: Vec<f64>,
    /// Kernel sum Σ (m/ρ) W of Eq. 20 (dimensionless, ≈ 1 inside the liquid).
    pub kernel_sum: Vec<f64>,
    /// Strain-rate tensor V of Eq. 4–5 (1/s).
    pub strain_rate: Vec<Tensor<D>>,
    /// Density rate dρ/dt of the continuity equation with its diffusion term (kg/(m³·s));
    /// zero with summation density.
    pub density_rate: Vec<f64>,
    /// Original particle index (stable through re-sorting).
    pub id: Vec<u32>,
    /// Neighbours found by the last density pass (fluid and wall, within the support).
    pub neighbours: NeighbourLists,
}

/// Fixed wall particles, struct of arrays.
#[derive(Clone, Debug, Default)]
pub struct Walls<const D: usize> {
    /// Position (m).
    pub position: Vec<Vector<D>>,
    /// Density from summation (kg/m³).
    pub density: Vec<f64>,
    /// 1/density (m³/kg).
    pub inverse_density: Vec<f64>,
    /// Pressure from the EOS (Pa), what the fluid feels.
    pub pressure: Vec<f64>,
    /// Index of the nearest fluid particle within the kernel support (u32::MAX: none).
    pub nearest_fluid: Vec<u32>,
    /// Part index (into `part_names`).
    pub part: Vec<u16>,
    /// Outward unit normal of the boundary (from the liquid into the wall).
    pub normal: Vec<Vector<D>>,
    /// Boundary area represented in load integration (m², 2D: m per m depth).
    pub area: Vec<f64>,
    /// Layer, 1 = next to the liquid.
    pub layer: Vec<u8>,
}

#[derive(Clone, Copy)]
pub(crate) struct PassConstants {
    pub(crate) kernel: Kernel,
    pub(crate) support_sq: f64,
    pub(crate) mass: f64,
    pub(crate) rest_density: f64,
    pub(crate) eos_stiffness: f64,
    pub(crate) eos_gamma: f64,
    pub(crate) eos_gamma_int: Option<i32>,
    pub(crate) clamp_negative: bool,
    /// Floor the Adami wall pressure at zero (`SphParams::wall_separation`).
    pub(crate) wall_separation: bool,
    pub(crate) free_surface_threshold: f64,
    pub(crate) viscosity: f64,
    pub(crate) av_alpha: f64,
    pub(crate) av_beta: f64,
    pub(crate) av_sound_speed: f64,
    /// c0 = √(γ B/ρ0) of the EOS (m/s), the c̄ of the Riemann pair.
    pub(crate) eos_sound_speed: f64,
}

impl PassConstants {
    /// Eq. 18: Tait equation of state, with the optional clamp of negative pressure.
    #[inline(always)]
    pub(crate) fn pressure(&self, density: f64) -> f64 {
        let ratio = density / self.rest_density;
        let power = match self.eos_gamma_int {
            Some(g) => ratio.powi(g),
            None => ratio.powf(self.eos_gamma),
        };
        let p = self.eos_stiffness * (power - 1.0);
        if self.clamp_negative {
            p.max(0.0)
        } else {
            p
        }
    }
}

/// (non-finite particles, particles outside the domain, the first one outside).
pub(crate) type ParticleStatus<const D: usize> = (usize, usize, Option<Vector<D>>);

/// Classifies one particle after an update: non-finite position or velocity, or outside the
/// domain box [lo, hi].
#[inline(always)]
pub(crate) fn particle_status<const D: usize>(
    x: &Vector<D>,
    v: &Vector<D>,
    lo: &Vector<D>,
    hi: &Vector<D>,
) -> ParticleStatus<D> {
    if !x.iter().chain(v.iter()).all(|c| c.is_finite()) {
        return (1, 0, None);
    }
    if (0..D).all(|k| x[k] >= lo[k] && x[k] <= hi[k]) {
        (0, 0, None)
    } else {
        (0, 1, Some(*x))
    }
}

/// Adds two particle statuses (rayon reduction).
pub(crate) fn merge_status<const D: usize>(
    a: ParticleStatus<D>,
    b: ParticleStatus<D>,
) -> ParticleStatus<D> {
    (a.0 + b.0, a.1 + b.1, a.2.or(b.2))
}

/// Constants of the stages beyond the paper's, fixed for a run (which stages run is the
/// [`crate::stages::StepPlan`]'s).
#[derive(Clone, Copy)]
pub(crate) struct StageConstants {
    /// δ h c0 (m²/s) of the diffusion term.
    pub(crate) diffusion_coeff: f64,
    /// The shifting coefficient A, when shifting is on.
    pub(crate) shifting: Option<f64>,
    /// 1/γ of the inverse EOS.
    pub(crate) inv_gamma: f64,
    /// 1/(γ − 1), the exponent of the hydrostatic density ([`hydrostatic_density`]).
    pub(crate) inv_gamma_minus_one: f64,
    /// 1e-6^(1/γ): the floor of ρ/ρ0 that the inverse EOS's floor of 1e-6 on 1 + p/B gives.
    pub(crate) density_ratio_floor: f64,
}

/// Per-run buffers of the stages beyond the paper's, allocated once in `Simulation::new`.
pub(crate) struct StageBuffers<const D: usize> {
    pub(crate) k: StageConstants,
    /// ρ^n, the density at the start of a symplectic step (kg/m³).
    pub(crate) density_start: Vec<f64>,
    /// Hydrostatic density ρ_H of Fourtakas' diffusion (kg/m³).
    pub(crate) hydro_density: Vec<f64>,
    /// ∇C of the shifting (1/m) and the kernel sum Σ V_j W_ij.
    pub(crate) shift_gradient: Vec<Vector<D>>,
    pub(crate) shift_kernel_sum: Vec<f64>,
    /// Wall velocity seen by the fluid with no-slip Adami walls (m/s).
    pub(crate) wall_velocity: Vec<Vector<D>>,
    pub(crate) wall_pressure_next: Vec<f64>,
}

impl<const D: usize> StageBuffers<D> {
    pub(crate) fn new(params: &SphParams, h: f64, c0: f64, n: usize, n_wall: usize) -> Self {
        let continuity = params.density == DensityMethod::Continuity;
        let delta = match params.density_diffusion {
            DensityDiffusion::None => 0.0,
            DensityDiffusion::MolteniColagrossi { delta }
            | DensityDiffusion::Fourtakas { delta } => delta,
        };
        let fourtakas = continuity
            && matches!(params.density_diffusion, DensityDiffusion::Fourtakas { delta } if delta > 0.0);
        let k = StageConstants {
            diffusion_coeff: delta * h * c0,
            shifting: params.shifting.filter(|a| *a > 0.0),
            inv_gamma: 1.0 / params.eos_gamma,
            inv_gamma_minus_one: 1.0 / (params.eos_gamma - 1.0),
            density_ratio_floor: 1e-6f64.powf(1.0 / params.eos_gamma),
        };
        let shift_len = if k.shifting.is_some() { n } else { 0 };
        let symplectic = params.integrator == Integrator::Symplectic;
        let no_slip = params.wall_no_slip;
        StageBuffers {
            k,
            density_start: vec![params.rest_density; if symplectic { n } else { 0 }],
            hydro_density: vec![params.rest_density; if fourtakas { n } else { 0 }],
            shift_gradient: vec![Vector::<D>::zeros(); shift_len],
            shift_kernel_sum: vec![1.0; shift_len],
            wall_velocity: vec![Vector::<D>::zeros(); if no_slip { n_wall } else { 0 }],
            wall_pressure_next: vec![0.0; n_wall],
        }
    }
}

impl PassConstants {
    /// Inverse of the Tait EOS (Eq. 18): ρ = ρ0 (1 + p/B)^(1/γ).
    #[inline(always)]
    pub(crate) fn density_of(&self, pressure: f64, inv_gamma: f64) -> f64 {
        self.rest_density
            * (1.0 + pressure / self.eos_stiffness)
                .max(1e-6)
                .powf(inv_gamma)
    }
}

/// Hydrostatic Tait density at depth d (m) below the still level z_s of the compressed
/// liquid: ρ0 (1 + p/B)^(1/γ) with p the exact hydrostatic pressure there
/// ([`TaitColumn::hydrostatic_pressure`], the weight of the liquid above),
/// p = B (β^(γ/(γ−1)) − 1) with β = 1 + ρ0 g d (γ−1)/(γ B) (floored at 0), so ρ0 β^(1/(γ−1)):
/// one power where the pressure and the inverse EOS take two (a particle's every step, for
/// Fourtakas' diffusion). ρ/ρ0 = (1 + p/B)^(1/γ) grows with 1 + p/B for every γ > 0, so the
/// inverse EOS's floor of 1e-6 on 1 + p/B ([`PassConstants::density_of`]) is the floor
/// 1e-6^(1/γ) on ρ/ρ0.
#[inline(always)]
pub(crate) fn hydrostatic_density(
    c: &PassConstants,
    k: &StageConstants,
    g: f64,
    depth: f64,
) -> f64 {
    let column = TaitColumn {
        eos_stiffness: c.eos_stiffness,
        eos_gamma: c.eos_gamma,
        rest_density: c.rest_density,
        gravity: g,
    };
    c.rest_density
        * column
            .pressure_base(depth)
            .powf(k.inv_gamma_minus_one)
            .max(k.density_ratio_floor)
}

/// Moves liquid particles laid on the undistorted lattice (fill level `fill`, m, floor at
/// `floor`, m) to where the Tait liquid sits at rest: each particle sinks by the compression
/// of the liquid between it and the fill level, so that a particle under a fill depth d ends
/// at [`TaitColumn::compressed_depth`] (d) below the still level. With continuity density
/// each particle keeps the density it starts with; starting from the hydrostatic density on
/// the undistorted lattice, the particle volumes m/ρ would be smaller than the spacing by the
/// compression, and the symmetric pressure gradient of Eq. 8 would balance gravity with
/// pressures too high by a few times ρ0 g d/(γB) (measured under 20 m of water: a floor force
/// of 1.019 times the weight, 1.005 with this start; `docs/scheme.md`, *Starting at rest*).
/// Particles above the fill level (a tilted start) move with the surface.
pub(crate) fn settle_into_compression<const D: usize>(
    positions: &mut [SVector<f64, D>],
    fill: f64,
    floor: f64,
    params: &SphParams,
) {
    let column = TaitColumn::of(params);
    let sunk = |depth: f64| column.compressed_depth(depth);
    let still = floor + sunk(fill - floor);
    for x in positions {
        let depth = fill - x[D - 1];
        x[D - 1] = still - if depth > 0.0 { sunk(depth) } else { depth };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::KernelKind;

    /// The one-power hydrostatic density against its definition, the inverse EOS (Eq. 18) of
    /// the column's exact pressure (two powers), for stiff and soft Tait liquids (γ = 7, 1.5,
    /// and 0.5 where 1/(γ − 1) is negative) from 30 m below the surface to far above it, where
    /// the inverse EOS's floor holds: within 1e-10 relative, the round-off of the two-power
    /// form, whose 1 + p/B = 1 + (β^(γ/(γ−1)) − 1) cancels where β^(γ/(γ−1)) is small (2e-5
    /// at γ = 0.5, 1 km above the surface: 5e-12 relative, doubled by the power 1/γ = 2).
    #[test]
    fn hydrostatic_density_is_the_inverse_eos_of_the_hydrostatic_pressure() {
        for gamma in [7.0, 1.5, 0.5] {
            let params = SphParams {
                eos_gamma: gamma,
                eos_stiffness: 2.0e5,
                ..SphParams::modern()
            };
            let c = PassConstants {
                kernel: Kernel::new(KernelKind::WendlandC2, 0.02, 2),
                support_sq: 0.0016,
                mass: 0.1,
                rest_density: 1000.0,
                eos_stiffness: params.eos_stiffness,
                eos_gamma: gamma,
                eos_gamma_int: None,
                clamp_negative: false,
                wall_separation: true,
                free_surface_threshold: 0.75,
                viscosity: 0.0,
                av_alpha: 0.0,
                av_beta: 3.0,
                av_sound_speed: 10.0,
                eos_sound_speed: 10.0,
            };
            let k = StageBuffers::<2>::new(&params, 0.02, 10.0, 0, 0).k;
            let column = TaitColumn {
                eos_stiffness: c.eos_stiffness,
                eos_gamma: gamma,
                rest_density: c.rest_density,
                gravity: 9.81,
            };
            for depth in [30.0, 5.0, 0.3, 0.0, -0.3, -5.0, -1e3, -1e6] {
                let one = hydrostatic_density(&c, &k, 9.81, depth);
                let two = c.density_of(column.hydrostatic_pressure(depth), k.inv_gamma);
                // Both infinite where β ≤ 0 under a soft liquid (γ < 1).
                assert!(
                    one == two || (one / two - 1.0).abs() < 1e-10,
                    "γ = {gamma}, depth {depth} m: {one} against {two}"
                );
            }
        }
    }
}
