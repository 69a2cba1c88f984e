//! The simulation state and the time step, written once for 2D and 3D.
//!
//! One step (paper §2):
//! 1. sort the fluid arrays by cell and re-index them (k-d tree backend: re-index every step,
//!    re-sort every few steps);
//! 2. density pass: summation density (Eq. 19) of fluid and wall particles, the kernel sum of
//!    the free-surface test (Eq. 20) and the strain rate V of Eq. 5; then the EOS (Eq. 18);
//! 3. force pass: the symmetric momentum equation with artificial viscosity (Eq. 8–16).
//!
//!    With the cell grid both passes evaluate each fluid pair once and add it to both
//!    particles (the pair terms are symmetric or antisymmetric in i and j): the sorted fluid
//!    is cut into blocks of whole cells at least one stencil reach long, each particle pairs
//!    with the particles of the forward half of its stencil, and an odd block runs once the
//!    even blocks on both sides of it are done, so no two threads write the same particle
//!    and each particle's sums are added in an order that does not depend on the threads
//!    (`colour_sweep`). The density pass keeps the pairs it found (forward fluid neighbours
//!    and all wall neighbours) for the force pass;
//! 4. time step from the CFL bounds (or the fixed dt), leap-frog update (Eq. 21–22);
//! 5. wall pressures for loads (§2.6) and their time window.
//!
//! The switchable parts of the modern scheme (continuity density with δ-SPH, Adami walls,
//! symplectic integration, shifting) run in their own step, `modern.rs`, entered
//! only when one of them is switched on.

use crate::error::SimError;
use crate::kernel::Kernel;
use crate::loads::LoadEvaluator;
use crate::neighbours::{CellGrid, KdTreeSearch, NeighbourBackend, NeighbourSearch};
use crate::params::{ArtificialSoundSpeed, SphParams};
use crate::setup::{ParticleSetup, TankInterior};
use crate::sound_speed::{choose_sound_speed, compressed_depth, SoundSpeedChoice};
use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;

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

#[path = "modern.rs"]
mod modern;

/// A position, velocity or force vector in D dimensions.
pub type Vector<const D: usize> = SVector<f64, D>;
/// A D×D tensor (strain rate).
pub type Tensor<const D: usize> = SMatrix<f64, D, D>;

/// Strain rate V = G + Gᵀ − (2/3) tr(G) I of a velocity gradient G (Eq. 4–5), 1/s.
#[inline(always)]
pub(crate) fn strain_rate_of<const D: usize>(grad_v: &Tensor<D>) -> Tensor<D> {
    let trace = grad_v.trace();
    let mut v_tensor = grad_v + grad_v.transpose();
    for k in 0..D {
        v_tensor[(k, k)] -= 2.0 / 3.0 * trace;
    }
    v_tensor
}

/// Chunk length for rayon loops: large enough to amortise scheduling.
const PAR_CHUNK: usize = 256;

/// Candidates gathered before evaluation in the sorted density pass.
const BATCH: usize = 32;
/// Marks a wall particle in a neighbour list (the low 31 bits hold its index).
const WALL_NEIGHBOUR: u32 = 1 << 31;
/// Count value meaning "the list overflowed: search again".
const LIST_OVERFLOW: u16 = u16::MAX;

/// Per-particle neighbour lists filled by the density pass and read by the force pass, so the
/// force pass does not scan and reject the grid's candidates again (in 3D only ≈ 15 % of the
/// 27-cell candidates are neighbours). Fixed capacity per particle, allocated once; a particle
/// with more neighbours is marked and searched again.
#[derive(Clone, Debug, Default)]
pub struct NeighbourLists {
    capacity: usize,
    entries: Vec<u32>,
    count: Vec<u16>,
    /// Sorted sweeps: where each particle's list starts in `entries`. The lists of a sweep
    /// block are packed one after the other in the block's share of `entries` (its particles
    /// × capacity), so the force sweep reads them as one stream; empty for the other passes,
    /// whose lists start at i × capacity.
    start: Vec<u32>,
}

impl NeighbourLists {
    /// Lists for `n` particles with room for `capacity` neighbours each.
    fn new(n: usize, capacity: usize) -> Self {
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

/// Neighbour search chosen at run time; each pass is monomorphised for both.
enum Search<const D: usize> {
    Grid(CellGrid<D>),
    KdTree(KdTreeSearch<D>),
}

/// Per-step constants of the passes.
#[derive(Clone, Copy)]
struct PassConstants {
    kernel: Kernel,
    support_sq: f64,
    mass: f64,
    rest_density: f64,
    eos_stiffness: f64,
    eos_gamma: f64,
    eos_gamma_int: Option<i32>,
    clamp_negative: bool,
    /// Floor the Adami wall pressure at zero (`SphParams::wall_separation`).
    pub(crate) wall_separation: bool,
    free_surface_threshold: f64,
    viscosity: f64,
    av_alpha: f64,
    av_beta: f64,
    av_sound_speed: f64,
}

impl PassConstants {
    /// Eq. 18: Tait equation of state, with the optional clamp of negative pressure.
    #[inline(always)]
    fn pressure(&self, density: f64) -> f64 {
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

/// Wall-clock time spent in each phase of the step (s), summed over the run.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct PhaseTimes {
    /// Re-sorting and re-indexing the fluid particles (neighbour search).
    pub neighbour_search: f64,
    /// Density pass and EOS.
    pub density: f64,
    /// Force pass.
    pub forces: f64,
    /// Time step choice and leap-frog update.
    pub integration: f64,
    /// Wall-load evaluation and its time window.
    pub loads: f64,
}

impl PhaseTimes {
    /// Sum of all phases (s).
    pub fn total(&self) -> f64 {
        self.neighbour_search + self.density + self.forces + self.integration + self.loads
    }
}

/// Time-step statistics of a run.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct StepStats {
    /// Smallest time step taken (s).
    pub dt_min: f64,
    /// Largest time step taken (s).
    pub dt_max: f64,
    /// Smallest stability bound seen (s).
    pub dt_bound_min: f64,
    /// Steps whose fixed dt exceeded the bound of that step.
    pub steps_above_bound: u64,
    /// Largest Mach number max|v|/c0 seen at a step.
    pub max_mach: f64,
    /// Steps whose Mach number exceeded [`crate::sound_speed::MACH_LIMIT`].
    pub steps_above_mach_limit: u64,
    /// Time (s) of the first step above that limit (0 when none).
    pub first_time_above_mach_limit: f64,
}

impl StepStats {
    /// The warning a user should read when the flow outran the sound speed's assumption
    /// (Mach above [`crate::sound_speed::MACH_LIMIT`] for more than a few steps).
    pub fn mach_warning(&self, sound_speed: f64) -> Option<String> {
        (self.steps_above_mach_limit > crate::sound_speed::MACH_STEPS_TOLERATED).then(|| {
            format!(
                "the flow reached Mach {:.3} (max|v|/c0, c0 = {:.1} m/s) and stayed above {} \
                 for {} steps from t = {:.3} s: density errors exceed 1 %; raise the sound \
                 speed (sound_speed_coefficient, or sound_speed ≥ 10 × the largest flow speed)",
                self.max_mach,
                sound_speed,
                crate::sound_speed::MACH_LIMIT,
                self.steps_above_mach_limit,
                self.first_time_above_mach_limit
            )
        })
    }
}

/// An SPH simulation of liquid in a fixed tank under gravity and a ground acceleration.
pub struct Simulation<const D: usize> {
    params: SphParams,
    constants: PassConstants,
    spacing: f64,
    /// EOS sound speed c0 (m/s).
    sound_speed: f64,
    fluid: Fluid<D>,
    walls: Walls<D>,
    part_names: Vec<String>,
    search: Search<D>,
    sort_grid: CellGrid<D>,
    interior: Box<dyn TankInterior<D>>,
    interior_min: Vector<D>,
    interior_max: Vector<D>,
    fill_level: f64,
    domain_min: Vector<D>,
    domain_max: Vector<D>,
    time: f64,
    step: u64,
    dt_previous: f64,
    dt_last: f64,
    stats: StepStats,
    phase_times: PhaseTimes,
    loads: LoadEvaluator<D>,
    // Scratch buffers, allocated once.
    scratch_vec: Vec<Vector<D>>,
    /// A second vector scratch for the one-loop sort of the paper step (empty otherwise).
    scratch_vec2: Vec<Vector<D>>,
    scratch_f64: Vec<f64>,
    scratch_tensor: Vec<Tensor<D>>,
    scratch_u32: Vec<u32>,
    order: Vec<u32>,
    next_density: Vec<f64>,
    next_wall_density: Vec<f64>,
    /// Buffers and flags of the modern step; `None` runs the paper's step.
    modern: Option<modern::ModernState<D>>,
    /// `still_level()`, computed once (m).
    still_level_cached: f64,
    /// The sound speed and stiffness chosen for this tank, and why.
    sound_choice: SoundSpeedChoice,
    /// The paper step with the cell grid keeps the fluid sorted by cell every step and sweeps
    /// each pair once ([`density_pass_sorted`], [`force_pass_sorted`]).
    sorted_every_step: bool,
    /// Block bounds of the colour sweeps ([`CellGrid::colour_blocks`]).
    blocks: Vec<u32>,
    /// Fluid → wall density sums of the sorted density pass.
    wall_scatter: WallScatter,
}

impl<const D: usize> Simulation<D> {
    /// Builds a simulation from a tank's particles and the solver parameters.
    pub fn new(setup: ParticleSetup<D>, params: SphParams) -> Result<Self, SimError> {
        assert!(D == 2 || D == 3, "slosh simulates 2D and 3D tanks only");
        let dx = setup.spacing;
        if !(dx.is_finite() && dx > 0.0) {
            return Err(SimError::InvalidSetup(format!(
                "particle spacing dx must be a positive number (got {dx})"
            )));
        }
        if setup.fluid_positions.is_empty() {
            return Err(SimError::InvalidSetup(
                "the tank holds no fluid particle: the fill depth is below one particle spacing"
                    .into(),
            ));
        }
        let n_wall = setup.wall_positions.len();
        for (name, len) in [
            ("wall_part", setup.wall_part.len()),
            ("wall_normal", setup.wall_normal.len()),
            ("wall_area", setup.wall_area.len()),
            ("wall_layer", setup.wall_layer.len()),
        ] {
            if len != n_wall {
                return Err(SimError::InvalidSetup(format!(
                    "{name} has {len} entries for {n_wall} wall particles"
                )));
            }
        }
        check_positive("smoothing_ratio", params.smoothing_ratio)?;
        check_positive("rest_density", params.rest_density)?;
        check_positive("eos_stiffness", params.eos_stiffness)?;
        check_positive("eos_gamma", params.eos_gamma)?;
        check_positive("cfl_number", params.cfl_number)?;
        match params.density_diffusion {
            crate::params::DensityDiffusion::None => {}
            crate::params::DensityDiffusion::MolteniColagrossi { delta }
            | crate::params::DensityDiffusion::Fourtakas { delta } => {
                if !(delta.is_finite() && delta >= 0.0) {
                    return Err(SimError::InvalidSetup(format!(
                        "density diffusion delta must be a number ≥ 0 (got {delta})"
                    )));
                }
            }
        }
        if let Some(a) = params.shifting {
            if !(a.is_finite() && a >= 0.0) {
                return Err(SimError::InvalidSetup(format!(
                    "shifting coefficient must be a number ≥ 0 (got {a})"
                )));
            }
        }
        if params.dynamic_viscosity < 0.0 || params.av_alpha < 0.0 || params.av_beta < 0.0 {
            return Err(SimError::InvalidSetup(
                "viscosity coefficients (dynamic_viscosity, av_alpha, av_beta) must be ≥ 0".into(),
            ));
        }
        let h = params.smoothing_ratio * dx;
        let kernel = Kernel::new(params.kernel, h, D);
        let depth = setup.fill_level - setup.interior_min[D - 1];
        let interior_height = setup.interior_max[D - 1] - setup.interior_min[D - 1];
        let sound_choice = choose_sound_speed(&params, depth, interior_height)?;
        let mut params = params;
        params.eos_stiffness = sound_choice.eos_stiffness;
        let sound_speed = sound_choice.sound_speed;
        let av_sound_speed = match params.av_sound_speed {
            // Eq. 17: c = η √(200 g H).
            ArtificialSoundSpeed::Eq17 => {
                params.av_eta * (200.0 * params.gravity * depth.max(0.0)).sqrt()
            }
            ArtificialSoundSpeed::Eos => sound_speed,
            ArtificialSoundSpeed::Fixed(c) => c,
        };
        check_positive("av_sound_speed", av_sound_speed.max(f64::MIN_POSITIVE))?;
        if let Some(dt) = params.fixed_dt {
            check_positive("dt", dt)?;
            let bound = params.cfl_number * h / sound_speed;
            if dt > bound && !params.allow_unstable_dt {
                return Err(SimError::DtAboveBound {
                    dt,
                    bound,
                    cfl: params.cfl_number,
                    h,
                    c0: sound_speed,
                });
            }
        }
        let gamma_int = if params.eos_gamma.fract() == 0.0 && params.eos_gamma.abs() < 64.0 {
            Some(params.eos_gamma as i32)
        } else {
            None
        };
        let mass = params.rest_density * dx.powi(D as i32);
        let constants = PassConstants {
            kernel,
            support_sq: kernel.support() * kernel.support(),
            mass,
            rest_density: params.rest_density,
            eos_stiffness: params.eos_stiffness,
            eos_gamma: params.eos_gamma,
            eos_gamma_int: gamma_int,
            clamp_negative: params.clamp_negative_pressure,
            wall_separation: params.wall_separation,
            free_surface_threshold: params.free_surface_threshold,
            viscosity: params.dynamic_viscosity,
            av_alpha: params.av_alpha,
            av_beta: params.av_beta,
            av_sound_speed,
        };

        // Domain: the bounding box of all particles, with room above for waves in open tanks.
        let mut lo = setup.interior_min;
        let mut hi = setup.interior_max;
        for p in setup.wall_positions.iter().chain(&setup.fluid_positions) {
            for k in 0..D {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let margin = 2.0 * kernel.support();
        let tank_height = setup.interior_max[D - 1] - setup.interior_min[D - 1];
        let mut domain_min = lo;
        let mut domain_max = hi;
        for k in 0..D {
            domain_min[k] -= margin;
            domain_max[k] += margin;
        }
        domain_max[D - 1] += tank_height.max(depth); // splashes above an open tank

        let n = setup.fluid_positions.len();
        let fluid = Fluid {
            position: setup.fluid_positions,
            velocity: vec![Vector::<D>::zeros(); n],
            velocity_half: vec![Vector::<D>::zeros(); n],
            acceleration: vec![Vector::<D>::zeros(); n],
            density: vec![params.rest_density; n],
            inverse_density: vec![1.0 / params.rest_density; n],
            pressure: vec![0.0; n],
            kernel_sum: vec![1.0; n],
            strain_rate: vec![Tensor::<D>::zeros(); n],
            density_rate: vec![0.0; n],
            id: (0..n as u32).collect(),
            // 2D: ≈ 21 neighbours within 2.6 dx; 3D: ≈ 74 (more in compressed or splashing flow).
            neighbours: NeighbourLists::new(n, if D == 2 { 48 } else { 128 }),
        };
        let walls = Walls {
            density: vec![params.rest_density; n_wall],
            inverse_density: vec![1.0 / params.rest_density; n_wall],
            pressure: vec![0.0; n_wall],
            nearest_fluid: vec![u32::MAX; n_wall],
            position: setup.wall_positions,
            part: setup.wall_part,
            normal: setup.wall_normal,
            area: setup.wall_area,
            layer: setup.wall_layer,
        };
        // The sweeps cut the fluid into slabs across the grid's slowest axis: the axis of
        // the tank's largest extent (besides x, the rows), the last one on ties.
        let slow_axis = (1..D)
            .rev()
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])).then(a.cmp(&b)))
            .unwrap_or(D - 1);
        let search = match params.neighbour_backend {
            NeighbourBackend::CellGrid => Search::Grid(CellGrid::with_slow_axis(
                domain_min,
                domain_max,
                kernel.support(),
                &walls.position,
                slow_axis,
            )),
            NeighbourBackend::KdTree => {
                Search::KdTree(KdTreeSearch::new(kernel.support(), &walls.position))
            }
        };
        let sort_grid = CellGrid::new(domain_min, domain_max, kernel.support(), &[]);
        let mut loads = LoadEvaluator::new(&walls, setup.part_names.len(), params.smoothing_steps);
        loads.set_roof_part(&setup.part_names);
        let modern = if params.uses_modern_step() {
            Some(modern::ModernState::new(
                &params,
                h,
                sound_speed,
                n,
                walls.position.len(),
            ))
        } else {
            None
        };
        let mut sim = Simulation {
            constants,
            spacing: dx,
            sound_speed,
            fluid,
            walls,
            part_names: setup.part_names,
            search,
            sort_grid,
            interior: setup.interior,
            interior_min: setup.interior_min,
            interior_max: setup.interior_max,
            fill_level: setup.fill_level,
            domain_min,
            domain_max,
            time: 0.0,
            step: 0,
            dt_previous: 0.0,
            dt_last: 0.0,
            stats: StepStats {
                dt_min: f64::INFINITY,
                dt_max: 0.0,
                dt_bound_min: f64::INFINITY,
                steps_above_bound: 0,
                max_mach: 0.0,
                steps_above_mach_limit: 0,
                first_time_above_mach_limit: 0.0,
            },
            phase_times: PhaseTimes::default(),
            loads,
            scratch_vec: vec![Vector::<D>::zeros(); n],
            scratch_vec2: Vec::new(),
            scratch_f64: vec![0.0; n],
            scratch_tensor: vec![Tensor::<D>::zeros(); n],
            scratch_u32: vec![0; n],
            order: vec![0; n],
            next_density: vec![0.0; n],
            next_wall_density: vec![0.0; n_wall],
            sorted_every_step: modern.is_none()
                && params.neighbour_backend == NeighbourBackend::CellGrid,
            modern,
            still_level_cached: 0.0,
            sound_choice,
            blocks: Vec::new(),
            wall_scatter: WallScatter::default(),
            params,
        };
        sim.still_level_cached = sim.still_level();
        if let Search::Grid(grid) = &sim.search {
            // Room for the most blocks colour_blocks can make (one per stencil reach of cells).
            let cells: usize = grid.dims().iter().product();
            sim.blocks.reserve(cells / grid.stencil_reach().max(1) + 2);
        }
        if sim.sorted_every_step {
            sim.wall_scatter = WallScatter::new(n_wall);
            sim.fluid.neighbours.start = vec![0; n];
            sim.scratch_vec2 = vec![Vector::<D>::zeros(); n];
            sim.sort_and_index();
        } else if sim.modern.is_some() && matches!(sim.search, Search::Grid(_)) {
            // The sorted strain sweep packs its lists by block (see `density_pass_sorted`).
            sim.fluid.neighbours.start = vec![0; n];
            sim.sort_all_and_index();
        } else {
            sim.sort_by_cell();
            sim.rebuild_search();
        }
        if sim.modern.is_some() {
            sim.modern_init();
        } else {
            sim.compute_density_and_pressure();
        }
        Ok(sim)
    }

    /// Advances one time step with the ground acceleration `ground_accel` (m/s², tank frame:
    /// the fluid feels −ground_accel as a body force besides gravity).
    pub fn step(&mut self, ground_accel: Vector<D>) -> Result<(), SimError> {
        if !ground_accel.iter().all(|a| a.is_finite()) {
            return Err(SimError::BadExcitation {
                time: self.time,
                value: format!("{:?}", ground_accel.as_slice()),
            });
        }
        if self.modern.is_some() {
            return self.step_modern(ground_accel);
        }
        let clock = std::time::Instant::now();
        let reorder = self.params.reorder_interval;
        if !self.sorted_every_step
            && reorder > 0
            && self.step > 0
            && self.step.is_multiple_of(reorder as u64)
        {
            self.sort_by_cell();
        }
        if self.step > 0 {
            if self.sorted_every_step {
                self.sort_and_index();
            } else {
                self.rebuild_search();
            }
            let t1 = std::time::Instant::now();
            self.phase_times.neighbour_search += (t1 - clock).as_secs_f64();
            self.compute_density_and_pressure();
            self.phase_times.density += t1.elapsed().as_secs_f64();
        }
        let mut body_force = -ground_accel;
        body_force[D - 1] -= self.params.gravity;
        let t2 = std::time::Instant::now();
        self.compute_forces(body_force);
        let t3 = std::time::Instant::now();
        self.phase_times.forces += (t3 - t2).as_secs_f64();
        self.record_loads(body_force);
        let t4 = std::time::Instant::now();
        self.phase_times.loads += (t4 - t3).as_secs_f64();

        let dt = self.time_step();

        self.integrate(dt, self.dt_previous)?;
        self.finish_step(dt, t4);
        Ok(())
    }

    /// Ends a step of `dt` (s), both schemes: the time, the step count, the step lengths the
    /// next step reads, and the integration phase's time since `integration_start`.
    fn finish_step(&mut self, dt: f64, integration_start: std::time::Instant) {
        self.dt_previous = dt;
        self.dt_last = dt;
        self.time += dt;
        self.step += 1;
        self.phase_times.integration += integration_start.elapsed().as_secs_f64();
    }

    /// The step (s): the acoustic, force and viscous bounds (README, *The "paper" scheme*, item 4) from the current
    /// velocities and the last accelerations, or the fixed dt; updates the statistics. Both
    /// schemes.
    fn time_step(&mut self) -> f64 {
        let (max_speed, max_accel) = self.max_speed_and_acceleration();
        let h = self.constants.kernel.h;
        let c = self.params.cfl_number;
        let acoustic = c * h / (self.sound_speed + max_speed);
        let force = if max_accel > 0.0 {
            c * (h / max_accel).sqrt()
        } else {
            f64::INFINITY
        };
        // Viscous bound dt ≤ C h² ρ0/μ of the Newtonian term (Morris et al. 1997, with C the
        // Courant number in place of their 0.125): never active for water at this scale.
        let viscous = if self.params.dynamic_viscosity > 0.0 {
            c * h * h * self.params.rest_density / self.params.dynamic_viscosity
        } else {
            f64::INFINITY
        };
        let bound = acoustic.min(force).min(viscous);
        self.stats.dt_bound_min = self.stats.dt_bound_min.min(bound);
        let mach = max_speed / self.sound_speed;
        self.stats.max_mach = self.stats.max_mach.max(mach);
        if mach > crate::sound_speed::MACH_LIMIT {
            self.stats.steps_above_mach_limit += 1;
            if self.stats.steps_above_mach_limit == 1 {
                self.stats.first_time_above_mach_limit = self.time;
            }
        }
        let dt = match self.params.fixed_dt {
            Some(dt) => {
                if dt > bound {
                    self.stats.steps_above_bound += 1;
                }
                dt
            }
            None => bound,
        };
        self.stats.dt_min = self.stats.dt_min.min(dt);
        self.stats.dt_max = self.stats.dt_max.max(dt);
        dt
    }

    /// Wall pressures for loads (§2.6) of the state the forces were computed on.
    fn record_loads(&mut self, body_force: Vector<D>) {
        self.record_loads_at(body_force, self.time);
    }

    /// Wall pressures for loads of the state the forces were computed on, labelled `time`.
    fn record_loads_at(&mut self, body_force: Vector<D>, time: f64) {
        let (kernel, mass, dx) = (self.constants.kernel, self.constants.mass, self.spacing);
        let step = self.step;
        with_search!(&self.search, s => self.loads.record_step(
            s,
            &self.fluid,
            &self.walls,
            &kernel,
            mass,
            &self.params,
            body_force,
            step,
            time,
            dx,
        ))
    }

    /// Mutable access to the load evaluator (to flush the time window at the end of a run).
    pub fn loads_mut(&mut self) -> &mut LoadEvaluator<D> {
        &mut self.loads
    }

    fn rebuild_search(&mut self) {
        with_search!(&mut self.search, s => s.rebuild_fluid(&self.fluid.position))
    }

    /// Re-sorts the fluid arrays along the cell order, for memory locality.
    fn sort_by_cell(&mut self) {
        self.sort_grid.rebuild_fluid(&self.fluid.position);
        let mut k = 0;
        let order = &mut self.order;
        self.sort_grid.for_each_sorted(|i| {
            order[k] = i as u32;
            k += 1;
        });
        let order = &self.order;
        permute(&mut self.fluid.position, order, &mut self.scratch_vec);
        permute(&mut self.fluid.velocity, order, &mut self.scratch_vec);
        permute(&mut self.fluid.velocity_half, order, &mut self.scratch_vec);
        permute(&mut self.fluid.acceleration, order, &mut self.scratch_vec);
        permute(&mut self.fluid.density, order, &mut self.scratch_f64);
        permute(
            &mut self.fluid.inverse_density,
            order,
            &mut self.scratch_f64,
        );
        permute(&mut self.fluid.pressure, order, &mut self.scratch_f64);
        permute(&mut self.fluid.kernel_sum, order, &mut self.scratch_f64);
        permute(&mut self.fluid.strain_rate, order, &mut self.scratch_tensor);
        permute(&mut self.fluid.id, order, &mut self.scratch_u32);
        if self.params.density == crate::params::DensityMethod::Continuity {
            permute(&mut self.fluid.density_rate, order, &mut self.scratch_f64);
        }
        // Wall → nearest-fluid links refer to the old order; they are recomputed in the next
        // density pass before anything reads them.
    }

    /// Sorts the fluid arrays by cell with the search grid (the arrays the paper step reads
    /// before writing: position, velocity, half-step velocity, 1/ρ and the id; the rest is
    /// recomputed from them), re-indexes the grid, zeroes the sums of the density sweep and
    /// splits the fluid into sweep blocks.
    fn sort_and_index(&mut self) {
        let Search::Grid(grid) = &mut self.search else {
            return;
        };
        let order = grid.sort_order(&self.fluid.position);
        let f = &mut self.fluid;
        // One parallel loop gathers the arrays into scratch buffers (the acceleration, which
        // the force pass recomputes, serves as the velocity's) and zeroes the accumulators of
        // the density sweep.
        {
            let (x, v, vh, inv, id) = (
                &f.position,
                &f.velocity,
                &f.velocity_half,
                &f.inverse_density,
                &f.id,
            );
            self.scratch_vec
                .par_iter_mut()
                .zip(f.acceleration.par_iter_mut())
                .zip(self.scratch_vec2.par_iter_mut())
                .zip(self.scratch_f64.par_iter_mut())
                .zip(self.scratch_u32.par_iter_mut())
                .zip(order.par_iter())
                .zip(self.next_density.par_iter_mut())
                .zip(f.kernel_sum.par_iter_mut())
                .zip(f.strain_rate.par_iter_mut())
                .with_min_len(PAR_CHUNK)
                .for_each(
                    |((((((((x_new, v_new), vh_new), inv_new), id_new), &o), rho), ksum), g)| {
                        let o = o as usize;
                        *x_new = x[o];
                        *v_new = v[o];
                        *vh_new = vh[o];
                        *inv_new = inv[o];
                        *id_new = id[o];
                        *rho = 0.0;
                        *ksum = 0.0;
                        *g = Tensor::<D>::zeros();
                    },
                );
        }
        std::mem::swap(&mut f.position, &mut self.scratch_vec);
        std::mem::swap(&mut f.velocity, &mut f.acceleration);
        std::mem::swap(&mut f.velocity_half, &mut self.scratch_vec2);
        std::mem::swap(&mut f.inverse_density, &mut self.scratch_f64);
        std::mem::swap(&mut f.id, &mut self.scratch_u32);
        grid.mark_sorted();
        // Blocks of ≈ n/32 particles whatever the thread count, so the order of the sums (and
        // the result) does not depend on it.
        let target = (f.position.len() / 32).max(512);
        grid.colour_blocks(target, &mut self.blocks);
    }

    fn compute_density_and_pressure(&mut self) {
        let c = self.constants;
        match &self.search {
            Search::Grid(s) if self.sorted_every_step => density_pass_sorted(
                s,
                &self.blocks,
                &c,
                &mut self.fluid,
                &mut self.walls,
                &mut self.next_density,
                &mut self.next_wall_density,
                &mut self.wall_scatter,
            ),
            search => with_search!(search, s => density_pass(
                s,
                &c,
                &mut self.fluid,
                &mut self.walls,
                &mut self.next_density,
                &mut self.next_wall_density,
            )),
        }
    }

    fn compute_forces(&mut self, body_force: Vector<D>) {
        let c = self.constants;
        match &self.search {
            Search::Grid(s) if self.sorted_every_step => force_pass_sorted(
                s,
                &self.blocks,
                &c,
                &mut self.fluid,
                &self.walls,
                body_force,
            ),
            search => {
                with_search!(search, s => force_pass(s, &c, &mut self.fluid, &self.walls, body_force))
            }
        }
    }

    fn max_speed_and_acceleration(&self) -> (f64, f64) {
        let (v2, a2) = self
            .fluid
            .velocity
            .par_iter()
            .zip(self.fluid.acceleration.par_iter())
            .with_min_len(PAR_CHUNK)
            .map(|(v, a)| (v.norm_squared(), a.norm_squared()))
            .reduce(|| (0.0, 0.0), |x, y| (x.0.max(y.0), x.1.max(y.1)));
        (v2.sqrt(), a2.sqrt())
    }

    /// Eq. 21–22: leap-frog, v(t+dt/2) = v(t−dt/2) + dt a(t), x(t+dt) = x(t) + dt v(t+dt/2);
    /// with a variable step the kick spans (dt_prev + dt)/2. The velocity at the new integer
    /// time, needed by the viscous terms, is estimated as v(t+dt/2) + dt/2 a(t).
    fn integrate(&mut self, dt: f64, dt_previous: f64) -> Result<(), SimError> {
        let kick = 0.5 * (dt + dt_previous);
        let lo = self.domain_min;
        let hi = self.domain_max;
        let status = self
            .fluid
            .position
            .par_iter_mut()
            .zip(self.fluid.velocity_half.par_iter_mut())
            .zip(self.fluid.velocity.par_iter_mut())
            .zip(self.fluid.acceleration.par_iter())
            .with_min_len(PAR_CHUNK)
            .map(|(((x, vh), v), a)| {
                *vh += kick * a;
                *x += dt * *vh;
                *v = *vh + 0.5 * dt * a;
                particle_status(x, vh, &lo, &hi)
            })
            .reduce(|| (0, 0, None), merge_status);
        self.blow_up_check(dt, status)
    }

    /// Turns the particle counts of [`particle_status`] into the blow-up error of the step
    /// that ends at time + dt.
    pub(crate) fn blow_up_check(
        &self,
        dt: f64,
        (bad, outside, first_out): ParticleStatus<D>,
    ) -> Result<(), SimError> {
        if bad > 0 {
            return Err(SimError::NonFinite {
                time: self.time + dt,
                step: self.step + 1,
                count: bad,
            });
        }
        if outside > 0 {
            let p = first_out.unwrap_or_else(Vector::<D>::zeros);
            return Err(SimError::LeftDomain {
                time: self.time + dt,
                step: self.step + 1,
                count: outside,
                position: format!("{:?} m", p.as_slice()),
            });
        }
        Ok(())
    }

    // ----- accessors -----

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.time
    }
    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.step
    }
    /// Last time step (s).
    pub fn last_dt(&self) -> f64 {
        self.dt_last
    }
    /// Time-step statistics.
    pub fn step_stats(&self) -> StepStats {
        self.stats
    }
    /// Wall-clock time per phase of the step so far.
    pub fn phase_times(&self) -> PhaseTimes {
        self.phase_times
    }
    /// The parameters in use.
    pub fn params(&self) -> &SphParams {
        &self.params
    }
    /// Lattice spacing dx (m).
    pub fn spacing(&self) -> f64 {
        self.spacing
    }
    /// Smoothing length h (m).
    pub fn smoothing_length(&self) -> f64 {
        self.constants.kernel.h
    }
    /// The kernel in use.
    pub fn kernel(&self) -> Kernel {
        self.constants.kernel
    }
    /// Mass of one particle (kg; 2D: kg per m of depth).
    pub fn particle_mass(&self) -> f64 {
        self.constants.mass
    }
    /// EOS sound speed c0 (m/s).
    pub fn sound_speed(&self) -> f64 {
        self.sound_speed
    }
    /// The sound speed and stiffness chosen for this tank (rule, H_ref, compression).
    pub fn sound_speed_choice(&self) -> &SoundSpeedChoice {
        &self.sound_choice
    }

    /// Volume-weighted compression of the liquid now: 1 − Σ(m/ρ)/V0, V0 the volume of the
    /// particles at ρ0 (a fraction; with vertical walls, the still surface's drop over the
    /// depth times the depth-to-mean ratio). Positive when the liquid is squeezed.
    pub fn mean_compression(&self) -> f64 {
        let rho0 = self.params.rest_density;
        let n = self.fluid.density.len().max(1) as f64;
        let volume_ratio: f64 = self
            .fluid
            .density
            .par_iter()
            .with_min_len(PAR_CHUNK)
            .map(|rho| rho0 / rho)
            .sum();
        1.0 - volume_ratio / n
    }

    /// Sound speed of the artificial viscosity (m/s).
    pub fn av_sound_speed(&self) -> f64 {
        self.constants.av_sound_speed
    }
    /// The fluid particles.
    pub fn fluid(&self) -> &Fluid<D> {
        &self.fluid
    }
    /// Bytes of the buffers of the pair sweeps of the paper step (fluid → wall density sums
    /// and block bounds), beside the arrays of [`Fluid`] and [`Walls`].
    pub fn sweep_buffer_bytes(&self) -> usize {
        self.wall_scatter.heap_bytes()
            + self.blocks.capacity() * 4
            + self.scratch_vec2.capacity() * size_of::<Vector<D>>()
    }
    /// The wall particles.
    pub fn walls(&self) -> &Walls<D> {
        &self.walls
    }
    /// Names of the wall parts.
    pub fn part_names(&self) -> &[String] {
        &self.part_names
    }
    /// Still-surface level (m).
    pub fn fill_level(&self) -> f64 {
        self.fill_level
    }
    /// Height (m) of the free surface of this liquid at rest: the fill level lowered by the
    /// compression of the Tait EOS under its own weight ([`compressed_depth`]). Wave
    /// elevations are measured from this level. Exact for walls that are vertical over the
    /// liquid depth.
    pub fn still_level(&self) -> f64 {
        let floor = self.interior_min[D - 1];
        let p = &self.params;
        floor
            + compressed_depth(
                self.fill_level - floor,
                p.eos_stiffness,
                p.eos_gamma,
                p.rest_density,
                p.gravity,
            )
    }

    /// Bounding box of the tank interior (m).
    pub fn interior_bounds(&self) -> (Vector<D>, Vector<D>) {
        (self.interior_min, self.interior_max)
    }
    /// The wall-load evaluator (pressures on the innermost wall layer, time-windowed).
    pub fn loads(&self) -> &LoadEvaluator<D> {
        &self.loads
    }

    /// Number of fluid particles inside the tank: within one lattice spacing of the interior
    /// (a particle pressed against a wall may sit a fraction of dx past the inner face, where
    /// the first wall layer stands; one past that layer has leaked).
    pub fn fluid_inside(&self) -> usize {
        let margin = self.spacing;
        self.fluid
            .position
            .par_iter()
            .with_min_len(PAR_CHUNK)
            .filter(|p| self.interior.contains(p) || self.interior.distance_outside(p) <= margin)
            .count()
    }

    /// Kinetic energy Σ ½ m |v|² (J; 2D: J per m of depth).
    pub fn kinetic_energy(&self) -> f64 {
        let m = self.constants.mass;
        self.fluid
            .velocity
            .par_iter()
            .with_min_len(PAR_CHUNK)
            .map(|v| 0.5 * m * v.norm_squared())
            .sum()
    }

    /// Free-surface level (m) on the vertical line through the horizontal point `horizontal`
    /// (D−1 coordinates): the height where the fluid kernel sum Σ (m/ρ) W falls to half its
    /// value at mid-depth on that line. `None` when no liquid is on the line.
    pub fn surface_level_at(&self, horizontal: &[f64]) -> Option<f64> {
        crate::gauge::surface_level(self, horizontal)
    }

    /// Calls `visit(j)` for each fluid particle within the kernel support of `x`.
    pub fn for_each_fluid_neighbour<F: FnMut(usize)>(&self, x: &Vector<D>, mut visit: F) {
        let r2max = self.constants.support_sq;
        let pos = &self.fluid.position;
        let mut f = |j: usize| {
            if (pos[j] - x).norm_squared() < r2max {
                visit(j)
            }
        };
        with_search!(&self.search, s => s.for_each_fluid_candidate(x, &mut f))
    }

    /// Simulation state for a restart-free check: the largest |v| (m/s).
    pub fn max_speed(&self) -> f64 {
        self.max_speed_and_acceleration().0
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

fn check_positive(name: &str, value: f64) -> Result<(), SimError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SimError::InvalidSetup(format!(
            "{name} must be a positive number (got {value})"
        )))
    }
}

/// Reorders `values` by `order` (new[k] = old[order[k]]) through a scratch buffer.
fn permute<T: Copy + Send + Sync>(values: &mut Vec<T>, order: &[u32], scratch: &mut Vec<T>) {
    // The scratch vector has the right length but possibly another element type's buffer
    // is kept elsewhere; here each type has its own.
    scratch.clear();
    scratch.extend(order.iter().map(|&i| values[i as usize]));
    std::mem::swap(values, scratch);
}

/// Eq. 19 at a wall particle at `xw`: the density sum Σ m W and the kernel sum Σ (m/ρ) W
/// over fluid and wall neighbours, and the nearest fluid particle within the support
/// (squared distance, index; u32::MAX when none).
#[inline(always)]
fn wall_summation<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    xw: &Vector<D>,
    fluid_pos: &[Vector<D>],
    fluid_inv_rho: &[f64],
    wall_pos: &[Vector<D>],
    wall_inv_rho: &[f64],
) -> (f64, f64, (f64, u32)) {
    let (kernel, m) = (c.kernel, c.mass);
    let mut rho_sum = 0.0;
    let mut kernel_sum = 0.0;
    let mut nearest = (f64::INFINITY, u32::MAX);
    search.for_each_fluid_candidate(xw, |j| {
        let r2 = (xw - fluid_pos[j]).norm_squared();
        if r2 < c.support_sq {
            let w = kernel.value(r2.sqrt());
            rho_sum += m * w;
            kernel_sum += m * fluid_inv_rho[j] * w;
            if r2 < nearest.0 {
                nearest = (r2, j as u32);
            }
        }
    });
    search.for_each_wall_candidate(xw, |k| {
        let r2 = (xw - wall_pos[k]).norm_squared();
        if r2 < c.support_sq {
            let w = kernel.value(r2.sqrt());
            rho_sum += m * w;
            kernel_sum += m * wall_inv_rho[k] * w;
        }
    });
    (rho_sum, kernel_sum, nearest)
}

/// Density pass (Eq. 19, 20, 18, 5) over fluid and wall particles.
fn density_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &mut Walls<D>,
    next_density: &mut Vec<f64>,
    next_wall_density: &mut [f64],
) {
    let kernel = c.kernel;
    let m = c.mass;
    {
        let pos = &fluid.position;
        let vel = &fluid.velocity;
        let inv_rho = &fluid.inverse_density;
        let wall_pos = &walls.position;
        let wall_inv_rho = &walls.inverse_density;
        let capacity = fluid.neighbours.capacity;
        next_density
            .par_iter_mut()
            .zip(fluid.kernel_sum.par_iter_mut())
            .zip(fluid.strain_rate.par_iter_mut())
            .zip(fluid.neighbours.entries.par_chunks_mut(capacity))
            .zip(fluid.neighbours.count.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_CHUNK)
            .for_each(
                |(i, ((((rho_out, ksum_out), strain_out), list), count_out))| {
                    let xi = pos[i];
                    let vi = vel[i];
                    let mut fill = ListFill::default();
                    let mut rho_sum = 0.0;
                    let mut kernel_sum = 0.0;
                    // Velocity gradient G_ab = Σ (m/ρ_j)(v_j − v_i)_a ∂W/∂x_i,b (Eq. 5 terms).
                    let mut grad_v = Tensor::<D>::zeros();
                    search.for_each_fluid_candidate(&xi, |j| {
                        let xij = xi - pos[j];
                        let r2 = xij.norm_squared();
                        if r2 < c.support_sq {
                            let r = r2.sqrt();
                            let (w, grad_factor) = kernel.value_and_gradient_factor(r);
                            let volume = m * inv_rho[j];
                            rho_sum += m * w;
                            kernel_sum += volume * w;
                            let grad_w = xij * grad_factor;
                            grad_v += (vel[j] - vi) * (grad_w * volume).transpose();
                            fill.push(list, j as u32);
                        }
                    });
                    search.for_each_wall_candidate(&xi, |w_idx| {
                        let xiw = xi - wall_pos[w_idx];
                        let r2 = xiw.norm_squared();
                        if r2 < c.support_sq {
                            let w = kernel.value(r2.sqrt());
                            rho_sum += m * w;
                            kernel_sum += m * wall_inv_rho[w_idx] * w;
                            fill.push(list, w_idx as u32 | WALL_NEIGHBOUR);
                        }
                    });
                    *count_out = fill.stored_count();
                    *rho_out = rho_sum;
                    *ksum_out = kernel_sum;
                    // Eq. 4–5: V = G + Gᵀ − (2/3) tr(G) I.
                    *strain_out = strain_rate_of(&grad_v);
                },
            );
    }
    wall_density_and_eos(search, c, fluid, walls, next_density, next_wall_density);
}

/// The wall half of the density pass (Eq. 19 and 20 at wall particles), then the
/// free-surface reset (Eq. 20) and the EOS (Eq. 18) of fluid and walls, once the fluid sums
/// are in `next_density` and `fluid.kernel_sum`.
fn wall_density_and_eos<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &mut Walls<D>,
    next_density: &[f64],
    next_wall_density: &mut [f64],
) {
    {
        let pos = &fluid.position;
        let inv_rho = &fluid.inverse_density;
        let wall_pos = &walls.position;
        let wall_inv_rho = &walls.inverse_density;
        wall_densities(c, next_wall_density, &mut walls.nearest_fluid, |w_i| {
            let (rho_sum, kernel_sum, nearest) = wall_summation(
                search,
                c,
                &wall_pos[w_i],
                pos,
                inv_rho,
                wall_pos,
                wall_inv_rho,
            );
            (rho_sum, kernel_sum, nearest.1)
        });
    }
    eos_pass(c, fluid, walls, next_density, next_wall_density, false);
}

/// Wall densities from `sums(w) = (Σ m W, Σ (m/ρ) W, nearest fluid particle)` over the fluid
/// and wall neighbours of wall particle w (Eq. 19), with the Eq. 20 reset.
fn wall_densities<F: Fn(usize) -> (f64, f64, u32) + Sync>(
    c: &PassConstants,
    next_wall_density: &mut [f64],
    nearest_fluid: &mut [u32],
    sums: F,
) {
    next_wall_density
        .par_iter_mut()
        .zip(nearest_fluid.par_iter_mut())
        .enumerate()
        .with_min_len(PAR_CHUNK)
        .for_each(|(w_i, (rho_out, nearest_out))| {
            let (rho_sum, kernel_sum, nearest) = sums(w_i);
            // Eq. 20 applies to wall particles too: a wall particle with too few
            // neighbours (outer layers, above the liquid) keeps ρ0.
            *rho_out = if kernel_sum < c.free_surface_threshold {
                c.rest_density
            } else {
                rho_sum
            };
            *nearest_out = nearest;
        });
}

/// The free-surface reset (Eq. 20) and the EOS (Eq. 18) of fluid and wall particles from
/// the density sums; with `strain_from_gradient` the fluid's `strain_rate` holds the velocity
/// gradient G and is turned into V here.
fn eos_pass<const D: usize>(
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &mut Walls<D>,
    next_density: &[f64],
    next_wall_density: &[f64],
    strain_from_gradient: bool,
) {
    // Eq. 20: free-surface reset, then Eq. 18: pressure.
    fluid
        .density
        .par_iter_mut()
        .zip(fluid.inverse_density.par_iter_mut())
        .zip(next_density.par_iter())
        .zip(fluid.kernel_sum.par_iter())
        .zip(fluid.pressure.par_iter_mut())
        .zip(fluid.strain_rate.par_iter_mut())
        .with_min_len(PAR_CHUNK)
        .for_each(|(((((rho, inv), &rho_new), &ksum), p), g)| {
            *rho = if ksum < c.free_surface_threshold {
                c.rest_density
            } else {
                rho_new
            };
            *inv = 1.0 / *rho;
            *p = c.pressure(*rho);
            if strain_from_gradient {
                // Eq. 4–5: V = G + Gᵀ − (2/3) tr(G) I.
                *g = strain_rate_of(g);
            }
        });
    walls
        .density
        .par_iter_mut()
        .zip(walls.inverse_density.par_iter_mut())
        .zip(next_wall_density.par_iter())
        .zip(walls.pressure.par_iter_mut())
        .with_min_len(PAR_CHUNK)
        .for_each(|(((rho, inv), &rho_new), p)| {
            *rho = rho_new;
            *inv = 1.0 / rho_new;
            *p = c.pressure(rho_new);
        });
}

/// Force pass: Eq. 8–9 with the Newtonian stress σ = −p I + μ V (Eq. 3) and Monaghan's
/// artificial viscosity (Eq. 10–16), plus the body force.
fn force_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    body_force: Vector<D>,
) {
    // The acceleration leaves the fluid while the sweep reads the rest of it (no allocation:
    // an empty Vec stands in).
    let mut acceleration = std::mem::take(&mut fluid.acceleration);
    let sweep = ForceSweep::new(c, fluid, walls);
    let support_sq = c.support_sq;
    let lists = &fluid.neighbours;
    let capacity = lists.capacity;
    acceleration
        .par_iter_mut()
        .enumerate()
        .with_min_len(PAR_CHUNK)
        .for_each(|(i, acc_out)| {
            let s = &sweep;
            let o = s.owner(i);
            let mut acc = Vector::<D>::zeros();
            // Every pair seen from both sides, each side adding its own share (Eq. 8–16).
            let fluid_pair = |acc: &mut Vector<D>, j: usize| {
                let xij = o.x - s.pos[j];
                let r2 = xij.norm_squared();
                if j != i && r2 < support_sq {
                    *acc += s.fluid_term(&o, j, xij, r2);
                }
            };
            let wall_pair = |acc: &mut Vector<D>, w: usize| {
                let xiw = o.x - s.wall_pos[w];
                let r2 = xiw.norm_squared();
                if r2 < support_sq {
                    *acc += s.wall_term(&o, w, xiw, r2);
                }
            };
            let count = lists.count[i];
            if count != LIST_OVERFLOW {
                // The density pass's list: the same neighbours in the same order as a search.
                for &entry in &lists.entries[i * capacity..i * capacity + count as usize] {
                    if entry & WALL_NEIGHBOUR == 0 {
                        fluid_pair(&mut acc, entry as usize);
                    } else {
                        wall_pair(&mut acc, (entry & !WALL_NEIGHBOUR) as usize);
                    }
                }
            } else {
                search.for_each_fluid_candidate(&o.x, |j| fluid_pair(&mut acc, j));
                search.for_each_wall_candidate(&o.x, |w| wall_pair(&mut acc, w));
            }
            *acc_out = acc + body_force;
        });
    fluid.acceleration = acceleration;
}

/// A slice written through by the blocks of one colour of a pair sweep (`colour_sweep`),
/// which touch disjoint slots.
struct SharedSlice<T> {
    ptr: *mut T,
    len: usize,
}

// SAFETY: a SharedSlice is only dereferenced at slots that no other thread touches at the
// same time (see `at`); the element type itself moves between threads.
unsafe impl<T: Send> Send for SharedSlice<T> {}
unsafe impl<T: Send> Sync for SharedSlice<T> {}

impl<T> SharedSlice<T> {
    fn new(values: &mut [T]) -> Self {
        SharedSlice {
            ptr: values.as_mut_ptr(),
            len: values.len(),
        }
    }

    /// The element at `i`.
    ///
    /// # Safety
    /// No other thread may access slot `i` while the reference lives: in a colour sweep,
    /// slot `i` belongs to the running block or to the next one, and blocks of one colour are
    /// two apart.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    unsafe fn at(&self, i: usize) -> &mut T {
        debug_assert!(i < self.len);
        &mut *self.ptr.add(i)
    }

    /// The `len` elements from `start`.
    ///
    /// # Safety
    /// As for [`Self::at`], for every slot of the range.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    unsafe fn slice(&self, start: usize, len: usize) -> &mut [T] {
        debug_assert!(start + len <= self.len);
        std::slice::from_raw_parts_mut(self.ptr.add(start), len)
    }
}

/// Runs `block(b, begin, end)` for every block b of slots given by `bounds` (see
/// [`CellGrid::colour_blocks`]). A block may write its own slots and those of the next block,
/// so two neighbouring blocks never run at the same time, and each slot receives its shares
/// in one fixed order: the even blocks come first (each may run at any time), and an odd
/// block runs once both its even neighbours are done. The result is therefore that of a
/// sweep over all even blocks followed by one over all odd blocks, whatever the number of
/// threads, but without a barrier between the two colours: a thread that finds no block
/// ready waits only for the neighbours of the next one (with two threads on 32 blocks, the
/// barrier between colours left each thread idle ≈ 10 % of a sweep).
fn colour_sweep<F: Fn(usize, usize, usize) + Sync>(bounds: &[u32], block: F) {
    let n_blocks = bounds.len().saturating_sub(1);
    let run = |b: usize| block(b, bounds[b] as usize, bounds[b + 1] as usize);
    if rayon::current_num_threads() <= 1 || n_blocks <= 2 {
        (0..n_blocks)
            .step_by(2)
            .chain((1..n_blocks).step_by(2))
            .for_each(run);
        return;
    }
    if n_blocks > BlockStates::MAX_BLOCKS {
        for parity in 0..2 {
            (parity..n_blocks)
                .into_par_iter()
                .step_by(2)
                .with_max_len(1)
                .for_each(run);
        }
        return;
    }
    let states = BlockStates::new(n_blocks);
    rayon::broadcast(|ctx| {
        while let Some(b) = states.claim(ctx.index(), ctx.num_threads()) {
            run(b);
            states.finish(b);
        }
    });
}

/// The progress of the blocks of one [`colour_sweep`], shared by its threads (no allocation:
/// at most [`Self::MAX_BLOCKS`] blocks, which `colour_blocks` with ≈ n/32 particles a block
/// never exceeds).
struct BlockStates {
    /// Per block: `TODO`, `RUNNING` or `DONE`.
    state: [std::sync::atomic::AtomicU8; Self::MAX_BLOCKS],
    n_blocks: usize,
}

impl BlockStates {
    const MAX_BLOCKS: usize = 128;
    const TODO: u8 = 0;
    const RUNNING: u8 = 1;
    const DONE: u8 = 2;

    fn new(n_blocks: usize) -> Self {
        BlockStates {
            state: std::array::from_fn(|_| std::sync::atomic::AtomicU8::new(Self::TODO)),
            n_blocks,
        }
    }

    fn is_done(&self, b: usize) -> bool {
        b >= self.n_blocks || self.state[b].load(std::sync::atomic::Ordering::Acquire) == Self::DONE
    }

    /// Claims block `b` if it is still to do and may run now (an odd block reads what its
    /// even neighbours wrote into its slots, so it waits until both are done).
    fn try_claim(&self, b: usize) -> bool {
        use std::sync::atomic::Ordering;
        self.state[b].load(Ordering::Relaxed) == Self::TODO
            && (b.is_multiple_of(2) || (self.is_done(b - 1) && self.is_done(b + 1)))
            && self.state[b]
                .compare_exchange(
                    Self::TODO,
                    Self::RUNNING,
                    Ordering::Acquire,
                    Ordering::Relaxed,
                )
                .is_ok()
    }

    /// Claims a block for thread `thread` of `threads`, waiting while blocks remain but none
    /// may run; `None` once every block is claimed. Each thread has a home range of blocks,
    /// the same in every sweep (`thread`/`threads` of the slots), which it takes lowest
    /// first, so that its particles stay in its core's cache from sweep to sweep; with its
    /// range exhausted it takes the highest block that may run elsewhere, the one its owner
    /// would reach last.
    fn claim(&self, thread: usize, threads: usize) -> Option<usize> {
        let n = self.n_blocks;
        let (home_lo, home_hi) = (thread * n / threads, (thread + 1) * n / threads);
        let mut spins = 0u32;
        loop {
            if let Some(b) = (home_lo..home_hi).find(|&b| self.try_claim(b)) {
                return Some(b);
            }
            if let Some(b) = (home_hi..n)
                .chain(0..home_lo)
                .rev()
                .find(|&b| self.try_claim(b))
            {
                return Some(b);
            }
            let any_todo = (0..n)
                .any(|b| self.state[b].load(std::sync::atomic::Ordering::Relaxed) == Self::TODO);
            if !any_todo {
                return None;
            }
            spins += 1;
            if spins < 64 {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }

    /// Marks block `b` done: its writes become visible to the threads that see the mark.
    fn finish(&self, b: usize) {
        self.state[b].store(Self::DONE, std::sync::atomic::Ordering::Release);
    }
}

/// What the fluid pairs of the sorted density sweep read and write, so that the batch
/// evaluation can be an always-inlined method (a closure called from two places is compiled
/// as a function, with its sums in memory).
struct DensitySweep<'a, const D: usize> {
    kernel: Kernel,
    m: f64,
    pos: &'a [Vector<D>],
    vel: &'a [Vector<D>],
    inv_rho: &'a [f64],
    rho_acc: &'a SharedSlice<f64>,
    ksum_acc: &'a SharedSlice<f64>,
    grad_acc: &'a SharedSlice<Tensor<D>>,
}

/// The running sums of one particle in the sorted density sweep, and its list's fill.
struct DensitySums<const D: usize> {
    rho: f64,
    kernel_sum: f64,
    grad_v: Tensor<D>,
    fill: ListFill,
}

impl<const D: usize> DensitySweep<'_, D> {
    /// Evaluates a batch of fluid pairs (i, j) within the support, `owner` = (x_i, v_i,
    /// m/ρ_i), in a loop without unpredictable branches: adds them to i's `sums` and to j's
    /// accumulators, and appends the j to i's list.
    #[inline(always)]
    fn batch(
        &self,
        (xi, vi, volume_i): (Vector<D>, Vector<D>, f64),
        batch_j: &[u32],
        batch_r2: &[f64],
        list: &mut [u32],
        sums: &mut DensitySums<D>,
    ) {
        let m = self.m;
        let mut batch_w = [0.0f64; BATCH];
        let mut batch_f = [0.0f64; BATCH];
        self.kernel
            .values_and_gradient_factors(batch_r2, &mut batch_w, &mut batch_f);
        let (mut rho_sum, mut kernel_sum, mut grad_v) = (sums.rho, sums.kernel_sum, sums.grad_v);
        for ((&j, &w), &grad_factor) in batch_j.iter().zip(&batch_w).zip(&batch_f) {
            let j = j as usize;
            let xij = xi - self.pos[j];
            let volume_j = m * self.inv_rho[j];
            let mw = m * w;
            rho_sum += mw;
            kernel_sum += volume_j * w;
            // (v_j − v_i) ⊗ ∇_i W_ij; for j the pair gives (v_i − v_j) ⊗ ∇_j W_ji, the same
            // tensor.
            let outer = (self.vel[j] - vi) * (xij * grad_factor).transpose();
            grad_v += outer * volume_j;
            // SAFETY: j is in this block or the next (colour_blocks).
            unsafe {
                *self.rho_acc.at(j) += mw;
                *self.ksum_acc.at(j) += volume_i * w;
                *self.grad_acc.at(j) += outer * volume_i;
            }
        }
        (sums.rho, sums.kernel_sum, sums.grad_v) = (rho_sum, kernel_sum, grad_v);
        sums.fill.append(list, batch_j);
    }
}

/// One particle's consumer of its forward fluid pairs in the sorted sweeps, fed by
/// [`forward_pairs_batched`].
trait ForwardPairBatch {
    /// A batch of at most [`BATCH`] pairs within the support: neighbour indices and squared
    /// distances (m²).
    fn batch(&mut self, batch_j: &[u32], batch_r2: &[f64]);
}

/// Hands the forward fluid neighbours of sorted particle `i` (those it finds in its forward
/// half stencil) within the support (`support_sq`, m²) to `sink`, in batches of [`BATCH`] and
/// a last, shorter one. The candidate loop has no unpredictable branch: every candidate is
/// written into the batch and only those within the support advance its fill.
#[inline(always)]
fn forward_pairs_batched<const D: usize, S: ForwardPairBatch>(
    grid: &CellGrid<D>,
    pos: &[Vector<D>],
    i: usize,
    support_sq: f64,
    sink: &mut S,
) {
    let xi = pos[i];
    let mut batch_j = [0u32; BATCH];
    let mut batch_r2 = [0.0f64; BATCH];
    let mut batched = 0usize;
    grid.for_each_forward_range(i, &xi, |j0, j1| {
        for (j, xj) in (j0..j1).zip(&pos[j0..j1]) {
            let r2 = (xi - xj).norm_squared();
            batch_j[batched] = j as u32;
            batch_r2[batched] = r2;
            batched += (r2 < support_sq) as usize;
            if batched == BATCH {
                sink.batch(&batch_j, &batch_r2);
                batched = 0;
            }
        }
    });
    sink.batch(&batch_j[..batched], &batch_r2[..batched]);
}

/// One particle of the sorted density sweep: its data, its neighbour list and its running
/// sums.
struct DensityOwner<'s, 'a, const D: usize> {
    sweep: &'s DensitySweep<'a, D>,
    /// (x_i, v_i, m/ρ_i).
    owner: (Vector<D>, Vector<D>, f64),
    list: &'s mut [u32],
    sums: DensitySums<D>,
}

impl<const D: usize> ForwardPairBatch for DensityOwner<'_, '_, D> {
    #[inline(always)]
    fn batch(&mut self, batch_j: &[u32], batch_r2: &[f64]) {
        self.sweep
            .batch(self.owner, batch_j, batch_r2, self.list, &mut self.sums);
    }
}

/// How far a neighbour list is filled, and whether an entry did not fit.
#[derive(Clone, Copy, Default)]
struct ListFill {
    listed: usize,
    overflow: bool,
}

impl ListFill {
    /// Appends `entry` if `list` has room.
    #[inline(always)]
    fn push(&mut self, list: &mut [u32], entry: u32) {
        if self.listed < list.len() {
            list[self.listed] = entry;
            self.listed += 1;
        } else {
            self.overflow = true;
        }
    }

    /// Appends `found` as far as `list` has room.
    #[inline(always)]
    fn append(&mut self, list: &mut [u32], found: &[u32]) {
        let room = found.len().min(list.len() - self.listed);
        list[self.listed..self.listed + room].copy_from_slice(&found[..room]);
        self.listed += room;
        self.overflow |= room < found.len();
    }

    /// The count stored for the list: its fill, or [`LIST_OVERFLOW`].
    #[inline(always)]
    fn stored_count(self) -> u16 {
        if self.overflow {
            LIST_OVERFLOW
        } else {
            self.listed as u16
        }
    }
}

/// Density pass (Eq. 19, 20, 18, 5) on cell-sorted fluid arrays: each fluid pair is
/// evaluated once, from the particle that finds the other in its forward half stencil, and
/// adds to both. Fills the half neighbour lists (forward fluid neighbours and all wall
/// neighbours) for [`force_pass_sorted`].
#[allow(clippy::too_many_arguments)]
fn density_pass_sorted<const D: usize>(
    grid: &CellGrid<D>,
    blocks: &[u32],
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &mut Walls<D>,
    next_density: &mut [f64],
    next_wall_density: &mut [f64],
    scatter: &mut WallScatter,
) {
    let kernel = c.kernel;
    let m = c.mass;
    let w0 = kernel.value(0.0);
    let n_wall = walls.position.len();
    // The fluid sums start at zero (zeroed by `sort_and_index`), the wall sums too (zeroed
    // when read, below).
    {
        let pos = &fluid.position;
        let vel = &fluid.velocity;
        let inv_rho = &fluid.inverse_density;
        let wall_pos = &walls.position;
        let wall_inv_rho = &walls.inverse_density;
        let capacity = fluid.neighbours.capacity;
        let rho_acc = SharedSlice::new(next_density);
        let ksum_acc = SharedSlice::new(&mut fluid.kernel_sum);
        // Velocity gradient G_ab = Σ (m/ρ_j)(v_j − v_i)_a ∂W/∂x_i,b (Eq. 5 terms); turned
        // into V below.
        let grad_acc = SharedSlice::new(&mut fluid.strain_rate);
        let entries = SharedSlice::new(&mut fluid.neighbours.entries);
        let counts = SharedSlice::new(&mut fluid.neighbours.count);
        let starts = SharedSlice::new(&mut fluid.neighbours.start);
        let wall_rho_acc = SharedSlice::new(&mut scatter.rho);
        let wall_ksum_acc = SharedSlice::new(&mut scatter.kernel_sum);
        let wall_near_r2 = SharedSlice::new(&mut scatter.nearest_r2);
        let wall_near = SharedSlice::new(&mut scatter.nearest);
        let sweep = DensitySweep {
            kernel,
            m,
            pos,
            vel,
            inv_rho,
            rho_acc: &rho_acc,
            ksum_acc: &ksum_acc,
            grad_acc: &grad_acc,
        };
        colour_sweep(blocks, |b, begin, end| {
            // This block's set of wall sums (see WallScatter).
            let set = (b % WallScatter::SETS) * n_wall;
            // The block's lists are packed from the start of its share of the entries; a
            // particle always has room for `capacity` entries (those before it used at most
            // as many each).
            let mut cursor = begin * capacity;
            for i in begin..end {
                let xi = pos[i];
                let vi = vel[i];
                let volume_i = m * inv_rho[i];
                // SAFETY: entries begin·capacity..end·capacity belong to this block, and
                // cursor + capacity ≤ (i + 1)·capacity.
                let list = unsafe { entries.slice(cursor, capacity) };
                // The particle itself (r = 0, no gradient).
                let rho_sum = m * w0;
                let kernel_sum = volume_i * w0;
                let grad_v = Tensor::<D>::zeros();
                let sums = DensitySums {
                    rho: rho_sum,
                    kernel_sum,
                    grad_v,
                    fill: ListFill::default(),
                };
                let mut this = DensityOwner {
                    sweep: &sweep,
                    owner: (xi, vi, volume_i),
                    list: &mut *list,
                    sums,
                };
                forward_pairs_batched(grid, pos, i, c.support_sq, &mut this);
                let DensitySums {
                    rho: mut rho_sum,
                    mut kernel_sum,
                    grad_v,
                    mut fill,
                } = this.sums;
                grid.for_each_wall_candidate(&xi, |w_idx| {
                    let xiw = xi - wall_pos[w_idx];
                    let r2 = xiw.norm_squared();
                    if r2 < c.support_sq {
                        let w = kernel.value(r2.sqrt());
                        rho_sum += m * w;
                        kernel_sum += m * wall_inv_rho[w_idx] * w;
                        // The pair's share of the wall particle's sums (Eq. 19 at the wall).
                        // SAFETY: blocks using one set are ≥ 3 stencil reaches apart, farther
                        // than two fluid neighbours of one wall particle can be.
                        unsafe {
                            let k = set + w_idx;
                            *wall_rho_acc.at(k) += m * w;
                            *wall_ksum_acc.at(k) += volume_i * w;
                            let near = wall_near_r2.at(k);
                            if r2 < *near {
                                *near = r2;
                                *wall_near.at(k) = i as u32;
                            }
                        }
                        fill.push(list, w_idx as u32 | WALL_NEIGHBOUR);
                    }
                });
                // SAFETY: slot i belongs to this block.
                unsafe {
                    *counts.at(i) = fill.stored_count();
                    *starts.at(i) = cursor as u32;
                    *rho_acc.at(i) += rho_sum;
                    *ksum_acc.at(i) += kernel_sum;
                    *grad_acc.at(i) += grad_v;
                }
                cursor += fill.listed;
            }
        });
    }
    {
        let wall_pos = &walls.position;
        let wall_inv_rho = &walls.inverse_density;
        let set_rho = SharedSlice::new(&mut scatter.rho);
        let set_ksum = SharedSlice::new(&mut scatter.kernel_sum);
        let set_near_r2 = SharedSlice::new(&mut scatter.nearest_r2);
        let set_near = SharedSlice::new(&mut scatter.nearest);
        wall_densities(c, next_wall_density, &mut walls.nearest_fluid, |w_i| {
            // Fluid neighbours: the sets of the sweep, in a fixed order, left zeroed for the
            // next step.
            let (mut rho_sum, mut kernel_sum) = (0.0, 0.0);
            let mut nearest = (f64::INFINITY, u32::MAX);
            for s in 0..WallScatter::SETS {
                let k = s * n_wall + w_i;
                // SAFETY: entry k belongs to wall particle w_i, visited once.
                let candidate = unsafe {
                    rho_sum += std::mem::take(set_rho.at(k));
                    kernel_sum += std::mem::take(set_ksum.at(k));
                    (
                        std::mem::replace(set_near_r2.at(k), f64::INFINITY),
                        std::mem::replace(set_near.at(k), u32::MAX),
                    )
                };
                if candidate.0 < nearest.0 || (candidate.0 == nearest.0 && candidate.1 < nearest.1)
                {
                    nearest = candidate;
                }
            }
            // Wall neighbours.
            let xw = wall_pos[w_i];
            grid.for_each_wall_candidate(&xw, |k| {
                let r2 = (xw - wall_pos[k]).norm_squared();
                if r2 < c.support_sq {
                    let w = kernel.value(r2.sqrt());
                    rho_sum += m * w;
                    kernel_sum += m * wall_inv_rho[k] * w;
                }
            });
            (rho_sum, kernel_sum, nearest.1)
        });
    }
    eos_pass(c, fluid, walls, next_density, next_wall_density, true);
}

/// The fluid particles' shares of the wall particles' density sums (Eq. 19 at walls),
/// scattered by the density sweep: one set of sums per block residue modulo [`Self::SETS`],
/// so that blocks running at the same time never add to the same entry.
#[derive(Clone, Debug, Default)]
struct WallScatter {
    /// Σ m W per set and wall particle (set-major).
    rho: Vec<f64>,
    /// Σ (m/ρ_j) W per set and wall particle.
    kernel_sum: Vec<f64>,
    /// Squared distance of the nearest fluid particle per set and wall particle.
    nearest_r2: Vec<f64>,
    /// That fluid particle (u32::MAX: none).
    nearest: Vec<u32>,
}

impl WallScatter {
    /// Sets: blocks b and b + 4 of one colour are ≥ 3 stencil reaches apart, while two fluid
    /// neighbours of one wall particle are at most 2 apart.
    const SETS: usize = 4;

    fn new(n_wall: usize) -> Self {
        let len = Self::SETS * n_wall;
        WallScatter {
            rho: vec![0.0; len],
            kernel_sum: vec![0.0; len],
            nearest_r2: vec![f64::INFINITY; len],
            nearest: vec![u32::MAX; len],
        }
    }

    /// Bytes held.
    fn heap_bytes(&self) -> usize {
        self.rho.len() * 28
    }
}

/// What the sorted force sweep reads, gathered so that its pair terms can be functions that
/// are always inlined (closures called from two places are not, and a call per pair costs
/// as much as the pair's arithmetic).
struct ForceSweep<'a, const D: usize> {
    c: PassConstants,
    /// 0.01 h² of Eq. 11.
    eps_h2: f64,
    viscous: bool,
    av_on: bool,
    pos: &'a [Vector<D>],
    vel: &'a [Vector<D>],
    rho: &'a [f64],
    inv_rho: &'a [f64],
    p: &'a [f64],
    strain: &'a [Tensor<D>],
    wall_pos: &'a [Vector<D>],
    wall_rho: &'a [f64],
    wall_inv_rho: &'a [f64],
    wall_p: &'a [f64],
}

/// A batch of fluid pairs of one owner and their factors ([`ForceSweep::pair_factors_batch`]).
struct PairFactorBatch {
    /// Squared distance r² (m²): input.
    r2: [f64; BATCH],
    /// ρ_i + ρ_j (kg/m³): input.
    rho_pair: [f64; BATCH],
    /// Distance r (m), floored as in [`ForceSweep::pair_factors`].
    r: [f64; BATCH],
    /// (dW/dr)/r.
    grad: [f64; BATCH],
    /// 1/(r² + 0.01 h²) of Eq. 11.
    inv_s: [f64; BATCH],
    /// 1/ρ̄ = 2/(ρ_i + ρ_j).
    inv_rho_mean: [f64; BATCH],
}

impl PairFactorBatch {
    fn new() -> Self {
        PairFactorBatch {
            r2: [0.0; BATCH],
            rho_pair: [0.0; BATCH],
            r: [0.0; BATCH],
            grad: [0.0; BATCH],
            inv_s: [0.0; BATCH],
            inv_rho_mean: [0.0; BATCH],
        }
    }

    /// The factors of pair k as [`ForceSweep::pair_factors`] returns them.
    #[inline(always)]
    fn get(&self, k: usize) -> (f64, f64, f64) {
        (self.grad[k], self.inv_s[k], self.inv_rho_mean[k])
    }
}

/// A neighbour list of the sorted sweeps split into its fluid neighbours (first) and its
/// wall neighbours (flagged, last).
#[inline(always)]
fn split_walls(list: &[u32]) -> (&[u32], &[u32]) {
    list.split_at(list.partition_point(|&e| e & WALL_NEIGHBOUR == 0))
}

/// The fluid particle i of a row of pairs in a force sweep (paper and modern steps).
struct ForceOwner<const D: usize> {
    x: Vector<D>,
    v: Vector<D>,
    rho: f64,
    inv_rho: f64,
    p: f64,
    strain: Tensor<D>,
}

impl<'a, const D: usize> ForceSweep<'a, D> {
    /// The sweep over `fluid` (its acceleration is not read) and `walls`.
    fn new(c: &PassConstants, fluid: &'a Fluid<D>, walls: &'a Walls<D>) -> Self {
        let h = c.kernel.h;
        ForceSweep {
            c: *c,
            eps_h2: 0.01 * h * h, // φ of Eq. 11
            viscous: c.viscosity > 0.0,
            av_on: c.av_alpha > 0.0 || c.av_beta > 0.0,
            pos: &fluid.position,
            vel: &fluid.velocity,
            rho: &fluid.density,
            inv_rho: &fluid.inverse_density,
            p: &fluid.pressure,
            strain: &fluid.strain_rate,
            wall_pos: &walls.position,
            wall_rho: &walls.density,
            wall_inv_rho: &walls.inverse_density,
            wall_p: &walls.pressure,
        }
    }

    /// Fluid particle i as the owner of a row of pairs.
    #[inline(always)]
    fn owner(&self, i: usize) -> ForceOwner<D> {
        ForceOwner {
            x: self.pos[i],
            v: self.vel[i],
            rho: self.rho[i],
            inv_rho: self.inv_rho[i],
            p: self.p[i],
            strain: self.strain[i],
        }
    }

    /// 1/r (the kernel gradient), 1/(r² + 0.01 h²) (Eq. 11) and 1/ρ̄ of a pair at squared
    /// distance r2 with ρ_i + ρ_j = rho_pair, from one division: `inv` = 1/(r s (ρ_i + ρ_j))
    /// with s = r² + 0.01 h². r is floored (far below the kernel's r = 0 cut-off) so that
    /// coincident particles give finite factors. Returns (∇W factor, 1/s, 1/ρ̄).
    #[inline(always)]
    fn pair_factors(&self, r2: f64, rho_pair: f64) -> (f64, f64, f64) {
        let r = r2.sqrt().max(1e-150);
        let s = r2 + self.eps_h2;
        let inv = 1.0 / (r * s * rho_pair);
        let grad_factor = self
            .c
            .kernel
            .gradient_factor_with_inverse(r, inv * (s * rho_pair));
        (grad_factor, inv * (r * rho_pair), inv * (2.0 * r * s))
    }

    /// [`Self::pair_factors`] of the first `n` pairs of a batch (r² and ρ_i + ρ_j given),
    /// bit for bit, in branch-free loops the compiler vectorises.
    #[inline(always)]
    // One index over six arrays: the form the compiler vectorises.
    #[allow(clippy::needless_range_loop)]
    fn pair_factors_batch(&self, n: usize, b: &mut PairFactorBatch) {
        let mut inv_r = [0.0f64; BATCH];
        for k in 0..n {
            let rk = b.r2[k].sqrt().max(1e-150);
            let s = b.r2[k] + self.eps_h2;
            let rho_pair = b.rho_pair[k];
            let inv = 1.0 / (rk * s * rho_pair);
            b.r[k] = rk;
            inv_r[k] = inv * (s * rho_pair);
            b.inv_s[k] = inv * (rk * rho_pair);
            b.inv_rho_mean[k] = inv * (2.0 * rk * s);
        }
        self.c
            .kernel
            .gradient_factors_with_inverse(&b.r[..n], &inv_r[..n], &mut b.grad[..n]);
    }

    /// Calls `visit(j, x_ij, r, factors)` for the fluid neighbours j of particle i (at
    /// `xi`, density `rho_i`) in `fluid_list`, with the pair factors of
    /// [`Self::pair_factors`] computed a batch at a time.
    #[inline(always)]
    fn for_each_listed_pair<F: FnMut(usize, Vector<D>, f64, (f64, f64, f64))>(
        &self,
        xi: Vector<D>,
        rho_i: f64,
        fluid_list: &[u32],
        b: &mut PairFactorBatch,
        mut visit: F,
    ) {
        for chunk in fluid_list.chunks(BATCH) {
            for (k, &j) in chunk.iter().enumerate() {
                let j = j as usize;
                b.r2[k] = (xi - self.pos[j]).norm_squared();
                b.rho_pair[k] = rho_i + self.rho[j];
            }
            self.pair_factors_batch(chunk.len(), b);
            for (k, &j) in chunk.iter().enumerate() {
                let j = j as usize;
                visit(j, xi - self.pos[j], b.r[k], b.get(k));
            }
        }
    }

    /// Eq. 10: Π_ij = (−α c̄ φ + β φ²)/ρ̄ for approaching pairs, 0 otherwise. Without a
    /// branch: a receding pair has φ = 0 and so Π = 0.
    #[inline(always)]
    fn artificial_viscosity(
        &self,
        vij: Vector<D>,
        xij: Vector<D>,
        inv_s: f64,
        inv_rho_mean: f64,
    ) -> f64 {
        let c = &self.c;
        let v_dot_x = vij.dot(&xij).min(0.0);
        let phi = c.kernel.h * v_dot_x * inv_s; // Eq. 11
        (-c.av_alpha * c.av_sound_speed * phi + c.av_beta * phi * phi) * inv_rho_mean
    }

    /// The acceleration of i from fluid particle j within the support (Eq. 8–9): added to i,
    /// subtracted from j.
    #[inline(always)]
    fn fluid_term(&self, o: &ForceOwner<D>, j: usize, xij: Vector<D>, r2: f64) -> Vector<D> {
        self.fluid_term_with(o, j, xij, self.pair_factors(r2, o.rho + self.rho[j]))
    }

    /// [`Self::fluid_term`] with the pair's factors (∇W factor, 1/s, 1/ρ̄) given.
    #[inline(always)]
    fn fluid_term_with(
        &self,
        o: &ForceOwner<D>,
        j: usize,
        xij: Vector<D>,
        (grad_factor, inv_s, inv_rho_mean): (f64, f64, f64),
    ) -> Vector<D> {
        let c = &self.c;
        let m = c.mass;
        let grad_w = xij * grad_factor;
        let inv_rho_ij = o.inv_rho * self.inv_rho[j];
        // Pressure part of (σ_i + σ_j)/(ρ_i ρ_j) ∇W (Eq. 8).
        let mut scalar = -(o.p + self.p[j]) * inv_rho_ij;
        if self.av_on {
            scalar -= self.artificial_viscosity(o.v - self.vel[j], xij, inv_s, inv_rho_mean);
        }
        let mut term = grad_w * (m * scalar);
        if self.viscous {
            // Viscous part μ (V_i + V_j)/(ρ_i ρ_j) ∇W.
            term += (o.strain + self.strain[j]) * grad_w * (m * c.viscosity * inv_rho_ij);
        }
        term
    }

    /// The acceleration of i from wall particle w within the support.
    #[inline(always)]
    fn wall_term(&self, o: &ForceOwner<D>, w: usize, xiw: Vector<D>, r2: f64) -> Vector<D> {
        let c = &self.c;
        let m = c.mass;
        let (grad_factor, inv_s, inv_rho_mean) = self.pair_factors(r2, o.rho + self.wall_rho[w]);
        let grad_w = xiw * grad_factor;
        let inv_rho_iw = o.inv_rho * self.wall_inv_rho[w];
        // Wall particles: σ_w = −p_w I (free slip: no viscous stress from the wall),
        // velocity zero in the artificial viscosity.
        let mut scalar = -(o.p + self.wall_p[w]) * inv_rho_iw;
        if self.av_on {
            scalar -= self.artificial_viscosity(o.v, xiw, inv_s, inv_rho_mean);
        }
        let mut term = grad_w * (m * scalar);
        if self.viscous {
            term += o.strain * grad_w * (m * c.viscosity * inv_rho_iw);
        }
        term
    }
}

/// Force pass (Eq. 8–16, as [`force_pass`]) on cell-sorted fluid arrays with the half lists
/// of [`density_pass_sorted`]: the fluid pair term is antisymmetric (∇_j W_ji = −∇_i W_ij,
/// every other factor symmetric in i and j), so each pair is evaluated once and added to i
/// and subtracted from j.
fn force_pass_sorted<const D: usize>(
    grid: &CellGrid<D>,
    blocks: &[u32],
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    body_force: Vector<D>,
) {
    // The acceleration leaves the fluid while the sweep reads the rest of it (no allocation:
    // an empty Vec stands in).
    let mut acceleration = std::mem::take(&mut fluid.acceleration);
    let sweep = ForceSweep::new(c, fluid, walls);
    let support_sq = c.support_sq;
    let list_entries = fluid.neighbours.entries.as_slice();
    let list_count = fluid.neighbours.count.as_slice();
    let list_start = fluid.neighbours.start.as_slice();
    acceleration
        .par_iter_mut()
        .with_min_len(PAR_CHUNK)
        .for_each(|a| *a = body_force);
    let acc_shared = SharedSlice::new(&mut acceleration);
    colour_sweep(blocks, |_, begin, end| {
        let s = &sweep;
        let (pos, wall_pos) = (s.pos, s.wall_pos);
        let mut batch = PairFactorBatch::new();
        for i in begin..end {
            let o = s.owner(i);
            let xi = o.x;
            let mut acc = Vector::<D>::zeros();
            let count = list_count[i];
            if count != LIST_OVERFLOW {
                // The listed pairs are within the support (tested by the density sweep on
                // the same positions).
                let first = list_start[i] as usize;
                let (fluid_list, wall_list) =
                    split_walls(&list_entries[first..first + count as usize]);
                s.for_each_listed_pair(xi, o.rho, fluid_list, &mut batch, |j, xij, _, f| {
                    let term = s.fluid_term_with(&o, j, xij, f);
                    acc += term;
                    // SAFETY: j is in this block or the next (colour_blocks).
                    unsafe {
                        *acc_shared.at(j) -= term;
                    }
                });
                for &entry in wall_list {
                    let w = (entry & !WALL_NEIGHBOUR) as usize;
                    let xiw = xi - wall_pos[w];
                    acc += s.wall_term(&o, w, xiw, xiw.norm_squared());
                }
            } else {
                grid.for_each_forward_range(i, &xi, |j0, j1| {
                    for (j, xj) in (j0..j1).zip(&pos[j0..j1]) {
                        let xij = xi - xj;
                        let r2 = xij.norm_squared();
                        if r2 < support_sq {
                            let term = s.fluid_term(&o, j, xij, r2);
                            acc += term;
                            // SAFETY: as above.
                            unsafe {
                                *acc_shared.at(j) -= term;
                            }
                        }
                    }
                });
                grid.for_each_wall_candidate(&xi, |w| {
                    let xiw = xi - wall_pos[w];
                    let r2 = xiw.norm_squared();
                    if r2 < support_sq {
                        acc += s.wall_term(&o, w, xiw, r2);
                    }
                });
            }
            // SAFETY: slot i belongs to this block.
            unsafe {
                *acc_shared.at(i) += acc;
            }
        }
    });
    fluid.acceleration = acceleration;
}

/// Reorders `values` by `order` (new[k] = old[order[k]]) through a scratch buffer of the same
/// length, in parallel.
fn permute_par<T: Copy + Send + Sync>(values: &mut Vec<T>, order: &[u32], scratch: &mut Vec<T>) {
    debug_assert_eq!(scratch.len(), values.len());
    let source = &*values;
    scratch
        .par_iter_mut()
        .zip(order.par_iter())
        .with_min_len(4 * PAR_CHUNK)
        .for_each(|(s, &o)| *s = source[o as usize]);
    std::mem::swap(values, scratch);
}

#[cfg(test)]
mod sweep_tests {
    use super::colour_sweep;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// The schedule of `colour_sweep` on three threads: every block runs once, no two
    /// neighbouring blocks overlap in time, and an odd block starts only after both its even
    /// neighbours have ended; for the dependency schedule (9 and 40 blocks) and the
    /// two-barrier fallback beyond `BlockStates::MAX_BLOCKS` (200 blocks).
    #[test]
    fn blocks_respect_their_neighbours() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        for n_blocks in [9usize, 40, 200] {
            let bounds: Vec<u32> = (0..=n_blocks as u32).map(|b| 10 * b).collect();
            let clock = AtomicUsize::new(0);
            let runs: Vec<AtomicUsize> = (0..n_blocks).map(|_| AtomicUsize::new(0)).collect();
            let start: Vec<AtomicUsize> = (0..n_blocks).map(|_| AtomicUsize::new(0)).collect();
            let end: Vec<AtomicUsize> = (0..n_blocks).map(|_| AtomicUsize::new(0)).collect();
            pool.install(|| {
                colour_sweep(&bounds, |b, begin, stop| {
                    assert_eq!((begin, stop), (10 * b, 10 * b + 10));
                    start[b].store(clock.fetch_add(1, Ordering::SeqCst), Ordering::SeqCst);
                    runs[b].fetch_add(1, Ordering::SeqCst);
                    // Some work, so that threads overlap.
                    let mut x = b as f64;
                    for _ in 0..20_000 {
                        x = std::hint::black_box(x.sin());
                    }
                    end[b].store(clock.fetch_add(1, Ordering::SeqCst), Ordering::SeqCst);
                })
            });
            let get = |v: &Vec<AtomicUsize>, b: usize| v[b].load(Ordering::SeqCst);
            for b in 0..n_blocks {
                assert_eq!(get(&runs, b), 1, "{n_blocks} blocks: block {b} ran once");
                if b % 2 == 1 {
                    assert!(get(&start, b) > get(&end, b - 1), "{n_blocks}: block {b}");
                    if b + 1 < n_blocks {
                        assert!(get(&start, b) > get(&end, b + 1), "{n_blocks}: block {b}");
                    }
                }
            }
        }
    }
}
