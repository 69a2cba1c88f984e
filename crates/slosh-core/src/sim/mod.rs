//! The simulation: its state, its construction from a tank's particles, and what a caller
//! reads from it. The time step is in `step.rs`, made of the stages of `crate::stages`;
//! the pair sweeps are driven by `crate::sweep`, the pair terms are in `crate::terms`.

use crate::device::{device_unsupported, DeviceSetup, StepDevice};
use crate::error::SimError;
use crate::kernel::Kernel;
use crate::loads::LoadEvaluator;
use crate::neighbours::{CellGrid, KdTreeSearch, NeighbourBackend, NeighbourSearch};
use crate::params::{ArtificialSoundSpeed, SphParams};
use crate::setup::{ParticleSetup, TankInterior};
use crate::sound_speed::{choose_sound_speed, SoundSpeedChoice, TaitColumn};
use crate::stages::*;
use crate::sweep::*;
use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;
use state::settle_into_compression;

/// A position, velocity or force vector in D dimensions.
pub type Vector<const D: usize> = SVector<f64, D>;
/// A D×D tensor (strain rate).
pub type Tensor<const D: usize> = SMatrix<f64, D, D>;

mod checkpoint;
mod sorting;
pub use checkpoint::SimState;
mod state;
mod step;
pub use state::*;

/// Neighbour search chosen at run time; each pass is monomorphised for both.
pub(crate) enum Search<const D: usize> {
    Grid(CellGrid<D>),
    KdTree(KdTreeSearch<D>),
}

/// Wall-clock time spent in each phase of the step (s), summed over the run.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
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
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
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
    pub(crate) params: SphParams,
    pub(crate) constants: PassConstants,
    pub(crate) spacing: f64,
    /// EOS sound speed c0 (m/s).
    pub(crate) sound_speed: f64,
    pub(crate) fluid: Fluid<D>,
    pub(crate) walls: Walls<D>,
    pub(crate) part_names: Vec<String>,
    pub(crate) search: Search<D>,
    pub(crate) sort_grid: CellGrid<D>,
    pub(crate) interior: Box<dyn TankInterior<D>>,
    pub(crate) interior_min: Vector<D>,
    pub(crate) interior_max: Vector<D>,
    pub(crate) fill_level: f64,
    pub(crate) domain_min: Vector<D>,
    pub(crate) domain_max: Vector<D>,
    pub(crate) time: f64,
    pub(crate) step: u64,
    pub(crate) dt_previous: f64,
    pub(crate) dt_last: f64,
    pub(crate) stats: StepStats,
    pub(crate) phase_times: PhaseTimes,
    pub(crate) loads: LoadEvaluator<D>,
    // Scratch buffers, allocated once.
    pub(crate) scratch_vec: Vec<Vector<D>>,
    /// A second vector scratch for the one-loop sort of the paper step (empty otherwise).
    pub(crate) scratch_vec2: Vec<Vector<D>>,
    pub(crate) scratch_f64: Vec<f64>,
    pub(crate) scratch_tensor: Vec<Tensor<D>>,
    pub(crate) scratch_u32: Vec<u32>,
    pub(crate) order: Vec<u32>,
    pub(crate) next_density: Vec<f64>,
    pub(crate) next_wall_density: Vec<f64>,
    /// Buffers of the stages beyond the paper's (empty when unused).
    pub(crate) buffers: StageBuffers<D>,
    /// The stages of the step, chosen once.
    pub(crate) plan: StepPlan,
    /// `still_level()`, computed once (m).
    pub(crate) still_level_cached: f64,
    /// The sound speed and stiffness chosen for this tank, and why.
    pub(crate) sound_choice: SoundSpeedChoice,
    /// Block bounds of the colour sweeps ([`CellGrid::colour_blocks`]).
    pub(crate) blocks: Vec<u32>,
    /// Fluid → wall density sums of the sorted density pass.
    pub(crate) wall_scatter: WallScatter,
    /// The device that runs the step instead of the CPU stages, when one is attached.
    pub(crate) device: Option<Box<dyn StepDevice<D>>>,
    /// The device has stepped since the fluid arrays were last copied back.
    pub(crate) host_stale: bool,
    /// The tank's rotation of the last step, when the ground turns it.
    pub(crate) rotation: Option<crate::frame::TankRotation>,
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
        if params.pair_scheme == crate::params::PairScheme::Riemann
            && (params.density != crate::params::DensityMethod::Continuity
                || params.boundary != crate::params::BoundaryMethod::Adami)
        {
            return Err(SimError::InvalidSetup(
                "the Riemann pair (pair_scheme \"riemann\") integrates the density with its own \
                 continuity flux against Adami walls: use it with density \"continuity\" and \
                 boundary \"adami\" (as in scheme \"modern\")"
                    .into(),
            ));
        }
        if params.viscous_operator == crate::params::ViscousOperator::MonaghanCleary
            && (params.pair_scheme != crate::params::PairScheme::Standard
                || params.boundary != crate::params::BoundaryMethod::Adami)
        {
            return Err(SimError::InvalidSetup(
                "the single-sum viscous operator (viscous_operator \"monaghan_cleary\") is a \
                 term of the modern step's standard pair against Adami walls: use it with \
                 boundary \"adami\" and pair_scheme \"standard\" (as in scheme \"modern\")"
                    .into(),
            ));
        }
        if params.dynamic_viscosity < 0.0 || params.av_alpha < 0.0 || params.av_beta < 0.0 {
            return Err(SimError::InvalidSetup(
                "viscosity coefficients (dynamic_viscosity, av_alpha, av_beta) must be ≥ 0".into(),
            ));
        }
        let layers_needed = params.wall_layers();
        let layers = setup.wall_layer.iter().copied().max().unwrap_or(0);
        if layers < layers_needed {
            return Err(SimError::InvalidSetup(format!(
                "the walls are {layers} particle layers thick but the kernel reaches {} spacings \
                 (support 2h, h/dx = {}): a fluid particle next to a wall would find the wall \
                 missing from part of its support and could pass through it; build the tank \
                 with at least {layers_needed} wall layers (`with_layers`) or lower h/dx",
                2.0 * params.smoothing_ratio,
                params.smoothing_ratio
            )));
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
            eos_sound_speed: sound_speed,
        };

        let mut setup = setup;
        if params.density == crate::params::DensityMethod::Continuity {
            settle_into_compression(
                &mut setup.fluid_positions,
                setup.fill_level,
                setup.interior_min[D - 1],
                &params,
            );
        }
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
        // The stages of the run: they depend on the parameters and on the kind of search.
        let plan = StepPlan::choose(
            &params,
            matches!(params.neighbour_backend, NeighbourBackend::CellGrid),
        );
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
            // 2D: ≈ 21 neighbours within 2.6 dx; 3D: ≈ 74 (more in compressed or splashing
            // flow); none when no pass of the plan lists them.
            neighbours: NeighbourLists::new(
                n,
                match (plan.lists_neighbours(), D) {
                    (false, _) => 0,
                    (true, 2) => 48,
                    (true, _) => 128,
                },
            ),
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
        let buffers = StageBuffers::new(&params, h, sound_speed, n, walls.position.len());
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
            buffers,
            plan,
            still_level_cached: 0.0,
            sound_choice,
            blocks: Vec::new(),
            wall_scatter: WallScatter::default(),
            device: None,
            host_stale: false,
            rotation: None,
            params,
        };
        sim.still_level_cached = sim.still_level();
        if let Search::Grid(grid) = &sim.search {
            // Room for the most blocks colour_blocks can make (one per stencil reach of cells).
            let cells: usize = grid.dims().iter().product();
            sim.blocks.reserve(cells / grid.stencil_reach().max(1) + 2);
        }
        match plan.sorting {
            Sorting::GatherEveryStep => {
                sim.wall_scatter = WallScatter::new(n_wall);
                // The sorted sweeps pack their lists by block (see `density_pass_sorted`).
                sim.fluid.neighbours.start = vec![0; n];
                sim.scratch_vec2 = vec![Vector::<D>::zeros(); n];
                sim.sort_and_index();
            }
            Sorting::AllArraysEveryStep => {
                sim.fluid.neighbours.start = vec![0; n];
                sim.sort_all_and_index();
            }
            Sorting::Periodic => {
                sim.sort_by_cell();
                sim.rebuild_search();
            }
        }
        sim.initial_state();
        Ok(sim)
    }

    /// Ends a step of `dt` (s), both schemes: the time, the step count, the step lengths the
    /// next step reads, and the integration phase's time since `integration_start`.
    pub(crate) fn finish_step(&mut self, dt: f64, integration_start: std::time::Instant) {
        self.dt_previous = dt;
        self.dt_last = dt;
        self.time += dt;
        self.step += 1;
        self.phase_times.integration += integration_start.elapsed().as_secs_f64();
    }

    /// The step (s): the acoustic, force and viscous bounds (`docs/paper-scheme.md`, item 4) from the current
    /// velocities and the last accelerations, or the fixed dt; updates the statistics. Both
    /// schemes.
    pub(crate) fn time_step(&mut self) -> f64 {
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

    /// The tank's rotation applied by the last step ([`Self::step_turning`]); `None` when the
    /// tank only translates.
    pub fn rotation(&self) -> Option<&crate::frame::TankRotation> {
        self.rotation.as_ref()
    }

    /// Wall pressures for loads of the state the forces were computed on, labelled `time`.
    pub(crate) fn record_loads_at(&mut self, body: &crate::frame::BodyForce<D>, time: f64) {
        let (kernel, mass, dx) = (self.constants.kernel, self.constants.mass, self.spacing);
        let step = self.step;
        with_search!(&self.search, s => self.loads.record_step(
            s,
            &self.fluid,
            &self.walls,
            &kernel,
            mass,
            &self.params,
            body,
            step,
            time,
            dx,
        ))
    }

    /// Mutable access to the load evaluator (to flush the time window at the end of a run).
    pub fn loads_mut(&mut self) -> &mut LoadEvaluator<D> {
        &mut self.loads
    }

    pub(crate) fn max_speed_and_acceleration(&self) -> (f64, f64) {
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

    /// The stages of the step this run takes (density model, wall model, force pass,
    /// integrator, shifting, and how the pair sweeps visit the pairs), in one line.
    pub fn step_description(&self) -> String {
        self.plan.describe()
    }

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
    /// Bytes of the cell grids of the neighbour search (capacities): the grid that sorts the
    /// fluid and, when the run searches on a grid, the search grid; the k-d trees of
    /// [`NeighbourBackend::KdTree`] are not counted.
    pub fn grid_bytes(&self) -> usize {
        let search = match &self.search {
            Search::Grid(grid) => grid.heap_bytes(),
            Search::KdTree(_) => 0,
        };
        search + self.sort_grid.heap_bytes()
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
    /// compression of the Tait EOS under its own weight ([`TaitColumn::compressed_depth`]). Wave
    /// elevations are measured from this level. Exact for walls that are vertical over the
    /// liquid depth.
    pub fn still_level(&self) -> f64 {
        let floor = self.interior_min[D - 1];
        floor + TaitColumn::of(&self.params).compressed_depth(self.fill_level - floor)
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

    /// What a device needs to run this simulation's step ([`DeviceSetup`]), or why it cannot
    /// (the device runs the modern step only; [`device_unsupported`]).
    pub fn device_setup(&self) -> Result<DeviceSetup<'_, D>, SimError> {
        if let Some(why) = device_unsupported(&self.params) {
            return Err(SimError::InvalidSetup(why));
        }
        let diffusion = match self.params.density_diffusion {
            crate::params::DensityDiffusion::Fourtakas { delta } => delta,
            _ => 0.0,
        };
        Ok(DeviceSetup {
            params: &self.params,
            smoothing_length: self.constants.kernel.h,
            mass: self.constants.mass,
            spacing: self.spacing,
            sound_speed: self.sound_speed,
            av_sound_speed: self.constants.av_sound_speed,
            diffusion_coeff: diffusion * self.constants.kernel.h * self.sound_speed,
            hydrostatic_diffusion: diffusion > 0.0,
            still_level: self.still_level_cached,
            domain_min: self.domain_min,
            domain_max: self.domain_max,
            fluid: &self.fluid,
            walls: &self.walls,
        })
    }

    /// Hands the step to `device` (the GPU backend) from now on: the device is loaded with the
    /// current state, and every later [`Self::step`] runs on it. The host's fluid arrays are
    /// then current only after [`Self::sync_host`].
    pub fn attach_device(&mut self, mut device: Box<dyn StepDevice<D>>) -> Result<(), SimError> {
        self.sync_host()?;
        device.upload(&self.device_setup()?)?;
        self.device = Some(device);
        Ok(())
    }

    /// The attached device's description (`None`: the step runs on the CPU).
    pub fn device_description(&self) -> Option<String> {
        self.device.as_ref().map(|d| d.description())
    }

    /// Device time of each kernel summed over the run (empty on the CPU).
    pub fn device_kernel_times(&self) -> Vec<(String, f64)> {
        self.device
            .as_ref()
            .map(|d| d.kernel_times())
            .unwrap_or_default()
    }

    /// Makes the host's fluid arrays current: with a device attached, copies them back if the
    /// device has stepped since, then sorts them by cell for the host's neighbour search (the
    /// wave gauges, the frames and the checkpoints read them); a no-op on the CPU.
    pub fn sync_host(&mut self) -> Result<(), SimError> {
        if self.host_stale {
            if let Some(device) = self.device.as_mut() {
                device.download(&mut self.fluid)?;
            }
            self.host_stale = false;
            self.sort_device_copy();
        }
        Ok(())
    }

    /// Profiling of the attached device's kernels ([`StepDevice::set_profiling`]).
    pub fn set_device_profiling(&mut self, on: bool) {
        if let Some(device) = self.device.as_mut() {
            device.set_profiling(on);
        }
    }

    /// Whether the host's fluid arrays are current ([`Self::sync_host`]).
    pub fn host_is_current(&self) -> bool {
        !self.host_stale
    }

    /// Loads the host state into the attached device, if any (after a restore).
    pub(crate) fn upload_to_device(&mut self) -> Result<(), SimError> {
        if let Some(mut device) = self.device.take() {
            let result = self.device_setup().and_then(|s| device.upload(&s));
            self.device = Some(device);
            result?;
            self.host_stale = false;
        }
        Ok(())
    }

    /// Changes every fluid particle's velocity by `dv` (m/s, tank frame) between steps: the
    /// tank's velocity jumps by −`dv` at this instant, and the liquid, which cannot follow it
    /// in no time, is left moving at `dv` relative to it (a sway x = A sin ωt started at t = 0
    /// leaves the liquid at −A ω). Refused for a non-finite `dv`.
    pub fn jump_velocity(&mut self, dv: Vector<D>) -> Result<(), SimError> {
        self.sync_host()?;
        if !dv.iter().all(|v| v.is_finite()) {
            return Err(SimError::InvalidSetup(format!(
                "the velocity jump must be finite (got {:?})",
                dv.as_slice()
            )));
        }
        for (v, vh) in self
            .fluid
            .velocity
            .iter_mut()
            .zip(self.fluid.velocity_half.iter_mut())
        {
            *v += dv;
            *vh += dv;
        }
        self.upload_to_device()
    }
}

pub(crate) fn check_positive(name: &str, value: f64) -> Result<(), SimError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SimError::InvalidSetup(format!(
            "{name} must be a positive number (got {value})"
        )))
    }
}
