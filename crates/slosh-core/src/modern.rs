//! The "modern" step: continuity density with δ-SPH diffusion, Adami walls,
//! symplectic position Verlet, optional particle shifting — each switchable on its own.
//!
//! A child module of `sim` (it reaches the simulation's private state). The paper's step
//! (`SphParams::default()`) never enters this file: `Simulation::step` hands over here only
//! when [`SphParams::uses_modern_step`] is true, so the paper path stays bit-for-bit as it was.
//!
//! Step order here:
//! 1. re-sort (every few steps; with the cell grid every step, at step 3, for the pair
//!    sweeps of the paper step that evaluate each fluid pair once);
//! 2. symplectic: time step from the state at n (v^n, a^{n−½}), predictor to n+½;
//! 3. re-index; density stage: summation (paper Eq. 19–20) or nothing (continuity: the
//!    density is integrated), the strain rate of Eq. 5 when μ > 0, the hydrostatic density of
//!    Fourtakas' diffusion, then the wall pass (dynamic summation or Adami extrapolation);
//! 4. force pass: momentum (Eq. 8–16) and, with continuity, dρ/dt in the same pair loop;
//! 5. loads of this state; leap-frog: time step, update; symplectic: corrector;
//! 6. optional shifting, blow-up checks.

use super::*;
use crate::params::{BoundaryMethod, DensityDiffusion, DensityMethod, Integrator};

/// Flags and constants of the modern passes, fixed for a run.
#[derive(Clone, Copy)]
pub(super) struct ModernConstants {
    continuity: bool,
    /// 0: none, 1: Molteni–Colagrossi, 2: Fourtakas.
    diffusion: u8,
    /// δ h c0 (m²/s) of the diffusion term.
    diffusion_coeff: f64,
    adami: bool,
    no_slip: bool,
    symplectic: bool,
    shifting: Option<f64>,
    /// 1/γ of the inverse EOS.
    inv_gamma: f64,
}

/// Per-run buffers of the modern step, allocated once in `Simulation::new`.
pub(super) struct ModernState<const D: usize> {
    pub(super) k: ModernConstants,
    /// ρ^n, the density at the start of a symplectic step (kg/m³).
    density_start: Vec<f64>,
    /// Hydrostatic density ρ_H of Fourtakas' diffusion (kg/m³).
    hydro_density: Vec<f64>,
    /// ∇C of the shifting (1/m) and the kernel sum Σ V_j W_ij.
    shift_gradient: Vec<Vector<D>>,
    shift_kernel_sum: Vec<f64>,
    /// Wall velocity seen by the fluid with no-slip Adami walls (m/s).
    wall_velocity: Vec<Vector<D>>,
    wall_pressure_next: Vec<f64>,
    /// The fluid's neighbour lists hold the pairs of the current positions (filled by the
    /// sorted strain sweep, void after each re-sort).
    lists_fresh: bool,
}

impl<const D: usize> ModernState<D> {
    pub(super) fn new(params: &SphParams, h: f64, c0: f64, n: usize, n_wall: usize) -> Self {
        let (diffusion, delta) = match params.density_diffusion {
            DensityDiffusion::None => (0, 0.0),
            DensityDiffusion::MolteniColagrossi { delta } => (1, delta),
            DensityDiffusion::Fourtakas { delta } => (2, delta),
        };
        let continuity = params.density == DensityMethod::Continuity;
        let k = ModernConstants {
            continuity,
            diffusion: if continuity && delta > 0.0 {
                diffusion
            } else {
                0
            },
            diffusion_coeff: delta * h * c0,
            adami: params.boundary == BoundaryMethod::Adami,
            no_slip: params.wall_no_slip,
            symplectic: params.integrator == Integrator::Symplectic,
            shifting: params.shifting.filter(|a| *a > 0.0),
            inv_gamma: 1.0 / params.eos_gamma,
        };
        let shift_len = if k.shifting.is_some() { n } else { 0 };
        ModernState {
            k,
            density_start: vec![params.rest_density; if k.symplectic { n } else { 0 }],
            hydro_density: vec![params.rest_density; if k.diffusion == 2 { n } else { 0 }],
            shift_gradient: vec![Vector::<D>::zeros(); shift_len],
            shift_kernel_sum: vec![1.0; shift_len],
            wall_velocity: vec![Vector::<D>::zeros(); if k.no_slip { n_wall } else { 0 }],
            wall_pressure_next: vec![0.0; n_wall],
            lists_fresh: false,
        }
    }
}

impl PassConstants {
    /// Inverse of the Tait EOS (Eq. 18): ρ = ρ0 (1 + p/B)^(1/γ).
    #[inline(always)]
    fn density_of(&self, pressure: f64, inv_gamma: f64) -> f64 {
        self.rest_density
            * (1.0 + pressure / self.eos_stiffness)
                .max(1e-6)
                .powf(inv_gamma)
    }
}

/// Hydrostatic Tait density at depth d below the level z_s: ρ0 (1 + ρ0 g d / B)^(1/γ).
#[inline(always)]
fn hydrostatic_density(c: &PassConstants, g: f64, inv_gamma: f64, depth: f64) -> f64 {
    c.density_of(c.rest_density * g * depth, inv_gamma)
}

impl<const D: usize> Simulation<D> {
    /// Sorts every fluid array (and the per-particle buffers of the modern step) by cell with
    /// the search grid, re-indexes the grid and splits the fluid into sweep blocks (the modern
    /// step with the cell grid does this every step, for the pair sweeps).
    pub(super) fn sort_all_and_index(&mut self) {
        let Search::Grid(grid) = &mut self.search else {
            return;
        };
        let order = grid.sort_order(&self.fluid.position);
        let f = &mut self.fluid;
        let (sv, sf, su) = (
            &mut self.scratch_vec,
            &mut self.scratch_f64,
            &mut self.scratch_u32,
        );
        // The arrays the step reads before it writes them. Not moved, since the passes after
        // the sort overwrite them whole before anything reads them: the acceleration and dρ/dt
        // and the shifting sums (force pass), the strain rate (strain or density pass; all
        // zeros without viscosity) and the hydrostatic density (density stage).
        permute_par(&mut f.position, order, sv);
        permute_par(&mut f.velocity, order, sv);
        permute_par(&mut f.velocity_half, order, sv);
        permute_par(&mut f.density, order, sf);
        permute_par(&mut f.inverse_density, order, sf);
        permute_par(&mut f.pressure, order, sf);
        permute_par(&mut f.kernel_sum, order, sf);
        permute_par(&mut f.id, order, su);
        if let Some(m) = &mut self.modern {
            m.lists_fresh = false;
            if !m.density_start.is_empty() {
                permute_par(&mut m.density_start, order, sf);
            }
        }
        grid.mark_sorted();
        let target = (f.position.len() / 32).max(512);
        grid.colour_blocks(target, &mut self.blocks);
    }

    /// Initial state of a modern run: with continuity density the fluid starts at the
    /// hydrostatic density of its depth below the fill level (no settling pressure wave).
    pub(super) fn modern_init(&mut self) {
        let Some(st) = &self.modern else { return };
        let k = st.k;
        let c = self.constants;
        if k.continuity {
            let (g, level) = (self.params.gravity, self.fill_level);
            for ((rho, inv), (x, p)) in self
                .fluid
                .density
                .iter_mut()
                .zip(self.fluid.inverse_density.iter_mut())
                .zip(
                    self.fluid
                        .position
                        .iter()
                        .zip(self.fluid.pressure.iter_mut()),
                )
            {
                *rho = hydrostatic_density(&c, g, k.inv_gamma, (level - x[D - 1]).max(0.0));
                *inv = 1.0 / *rho;
                *p = c.pressure(*rho);
            }
        }
        let mut body = Vector::<D>::zeros();
        body[D - 1] = -self.params.gravity;
        self.modern_density_stage(body);
    }

    /// One time step of the modern scheme (see the module notes).
    pub(super) fn step_modern(&mut self, ground_accel: Vector<D>) -> Result<(), SimError> {
        let k = self.modern.as_ref().expect("modern state").k;
        let clock = std::time::Instant::now();
        let reorder = self.params.reorder_interval;
        let sweeps = matches!(self.search, Search::Grid(_));
        if !sweeps && reorder > 0 && self.step > 0 && self.step.is_multiple_of(reorder as u64) {
            self.sort_by_cell();
        }
        let mut body_force = -ground_accel;
        body_force[D - 1] -= self.params.gravity;

        let mut dt = 0.0;
        if k.symplectic {
            dt = self.time_step();
            self.symplectic_predictor(dt);
        }
        let t1 = std::time::Instant::now();
        if self.step > 0 || k.symplectic {
            if sweeps {
                self.sort_all_and_index();
            } else {
                self.rebuild_search();
            }
            let t_search = std::time::Instant::now();
            self.phase_times.neighbour_search += (t_search - clock).as_secs_f64();
            self.modern_density_stage(body_force);
            self.phase_times.density += t_search.elapsed().as_secs_f64();
        } else {
            self.phase_times.integration += (t1 - clock).as_secs_f64();
        }
        let t2 = std::time::Instant::now();
        self.modern_forces(body_force);
        let t3 = std::time::Instant::now();
        self.phase_times.forces += (t3 - t2).as_secs_f64();
        let load_time = if k.symplectic {
            self.time + 0.5 * dt
        } else {
            self.time
        };
        self.record_loads_at(body_force, load_time);
        let t4 = std::time::Instant::now();
        self.phase_times.loads += (t4 - t3).as_secs_f64();

        if k.symplectic {
            self.symplectic_corrector(dt);
            self.apply_shifting(dt);
            self.check_particles(dt)?;
        } else {
            dt = self.time_step();
            self.integrate(dt, self.dt_previous)?;
            if k.continuity {
                self.continuity_euler(dt);
            }
            self.apply_shifting(dt);
        }
        self.finish_step(dt, t4);
        Ok(())
    }

    /// Symplectic predictor: x^{n+½} = x^n + dt/2 v^n; the mid-step velocity estimate
    /// v^n + dt/2 a^{n−½} for the velocity-dependent terms (artificial viscosity, strain rate,
    /// dρ/dt); with continuity ρ^{n+½} = ρ^n + dt/2 Dρ, Dρ the latest rate (that of n−½: one
    /// pair loop per step, an O(dt²) difference in the mid-step pressure only).
    /// Afterwards `velocity` holds the mid-step estimate and `velocity_half` holds v^n.
    fn symplectic_predictor(&mut self, dt: f64) {
        let half = 0.5 * dt;
        let st = self.modern.as_mut().expect("modern state");
        self.fluid
            .position
            .par_iter_mut()
            .zip(self.fluid.velocity_half.par_iter_mut())
            .zip(self.fluid.velocity.par_iter())
            .zip(self.fluid.acceleration.par_iter())
            .with_min_len(PAR_CHUNK)
            .for_each(|(((x, vh), v), a)| {
                *x += half * v;
                *vh = v + half * a;
            });
        std::mem::swap(&mut self.fluid.velocity, &mut self.fluid.velocity_half);
        if st.k.continuity {
            let c = self.constants;
            self.fluid
                .density
                .par_iter_mut()
                .zip(self.fluid.inverse_density.par_iter_mut())
                .zip(self.fluid.pressure.par_iter_mut())
                .zip(st.density_start.par_iter_mut())
                .zip(self.fluid.density_rate.par_iter())
                .with_min_len(PAR_CHUNK)
                .for_each(|((((rho, inv), p), rho0), &drho)| {
                    *rho0 = *rho;
                    *rho += half * drho;
                    *inv = 1.0 / *rho;
                    *p = c.pressure(*rho);
                });
        }
    }

    /// Symplectic corrector: v^{n+1} = v^n + dt a^{n+½}; x^{n+1} = x^{n+½} + dt/2 v^{n+1};
    /// ρ^{n+1} = ρ^n (2 − ε)/(2 + ε), ε = −(Dρ^{n+½}/ρ^{n+½}) dt (DualSPHysics' symplectic,
    /// Domínguez et al. 2022 Eq. 20–22). `velocity_half` keeps the mid-step estimate.
    fn symplectic_corrector(&mut self, dt: f64) {
        let half = 0.5 * dt;
        let st = self.modern.as_mut().expect("modern state");
        std::mem::swap(&mut self.fluid.velocity, &mut self.fluid.velocity_half);
        self.fluid
            .position
            .par_iter_mut()
            .zip(self.fluid.velocity.par_iter_mut())
            .zip(self.fluid.acceleration.par_iter())
            .with_min_len(PAR_CHUNK)
            .for_each(|((x, v), a)| {
                *v += dt * a;
                *x += half * *v;
            });
        if st.k.continuity {
            let c = self.constants;
            self.fluid
                .density
                .par_iter_mut()
                .zip(self.fluid.inverse_density.par_iter_mut())
                .zip(self.fluid.pressure.par_iter_mut())
                .zip(st.density_start.par_iter())
                .zip(self.fluid.density_rate.par_iter())
                .with_min_len(PAR_CHUNK)
                .for_each(|((((rho, inv), p), &rho_n), &drho)| {
                    let eps = -drho * *inv * dt;
                    *rho = rho_n * (2.0 - eps) / (2.0 + eps);
                    *inv = 1.0 / *rho;
                    *p = c.pressure(*rho);
                });
        }
    }

    /// Leap-frog with continuity density: ρ(t + dt) = ρ(t) + dt Dρ(t), then the EOS.
    fn continuity_euler(&mut self, dt: f64) {
        let c = self.constants;
        self.fluid
            .density
            .par_iter_mut()
            .zip(self.fluid.inverse_density.par_iter_mut())
            .zip(self.fluid.pressure.par_iter_mut())
            .zip(self.fluid.density_rate.par_iter())
            .with_min_len(PAR_CHUNK)
            .for_each(|(((rho, inv), p), &drho)| {
                *rho += dt * drho;
                *inv = 1.0 / *rho;
                *p = c.pressure(*rho);
            });
    }

    /// Particle shifting (Lind et al. 2012; the |v| dt scaling of Skillen et al. 2013):
    /// δx_i = −A h |v_i| dt ∇C_i, capped at 0.1 dx, skipped near the free surface.
    fn apply_shifting(&mut self, dt: f64) {
        let st = self.modern.as_ref().expect("modern state");
        let Some(a) = st.k.shifting else { return };
        let scale = a * self.constants.kernel.h * dt;
        let cap = 0.1 * self.spacing;
        let threshold = self.params.free_surface_threshold;
        self.fluid
            .position
            .par_iter_mut()
            .zip(self.fluid.velocity.par_iter())
            .zip(st.shift_gradient.par_iter())
            .zip(st.shift_kernel_sum.par_iter())
            .with_min_len(PAR_CHUNK)
            .for_each(|(((x, v), grad), &ksum)| {
                if ksum >= threshold {
                    let mut dx = grad * (-scale * v.norm());
                    let len = dx.norm();
                    if len > cap {
                        dx *= cap / len;
                    }
                    *x += dx;
                }
            });
    }

    /// Non-finite and out-of-domain checks after a symplectic update.
    fn check_particles(&self, dt: f64) -> Result<(), SimError> {
        let lo = self.domain_min;
        let hi = self.domain_max;
        let status = self
            .fluid
            .position
            .par_iter()
            .zip(self.fluid.velocity.par_iter())
            .with_min_len(PAR_CHUNK)
            .map(|(x, v)| particle_status(x, v, &lo, &hi))
            .reduce(|| (0, 0, None), merge_status);
        self.blow_up_check(dt, status)
    }

    /// Density stage: summation (Eq. 19–20, the paper's pass, which also sums the dynamic
    /// walls) or, with continuity, the strain rate of Eq. 5 alone (when μ > 0); then the
    /// hydrostatic density of Fourtakas' diffusion and the wall pass.
    fn modern_density_stage(&mut self, body_force: Vector<D>) {
        let st = self.modern.as_mut().expect("modern state");
        let k = st.k;
        let c = self.constants;
        if !k.continuity {
            with_search!(&self.search, s => density_pass(
                s,
                &c,
                &mut self.fluid,
                &mut self.walls,
                &mut self.next_density,
                &mut self.next_wall_density,
            ));
        } else if c.viscosity > 0.0 {
            match &self.search {
                Search::Grid(s) => {
                    strain_pass_sorted(s, &self.blocks, &c, &mut self.fluid, &self.walls.position);
                    st.lists_fresh = true;
                }
                Search::KdTree(s) => strain_pass(s, &c, &mut self.fluid),
            }
        }
        if k.diffusion == 2 {
            let (g, level) = (self.params.gravity, self.still_level_cached);
            st.hydro_density
                .par_iter_mut()
                .zip(self.fluid.position.par_iter())
                .with_min_len(PAR_CHUNK)
                .for_each(|(rho_h, x)| {
                    *rho_h = hydrostatic_density(&c, g, k.inv_gamma, level - x[D - 1]);
                });
        }
        if k.continuity || k.adami {
            with_search!(&self.search, s => wall_pass(
                s,
                &c,
                &k,
                &mut self.fluid,
                &mut self.walls,
                &mut self.next_wall_density,
                st,
                body_force,
            ));
        }
        if k.adami && k.no_slip && c.viscosity > 0.0 {
            with_search!(&self.search, s => wall_strain_pass(
                s,
                &c,
                &mut self.fluid,
                &self.walls,
                &st.wall_velocity,
            ));
        }
    }

    fn modern_forces(&mut self, body_force: Vector<D>) {
        let c = self.constants;
        let st = self.modern.as_mut().expect("modern state");
        match &self.search {
            Search::Grid(s) => {
                let lists = st.lists_fresh;
                modern_force_pass_sorted(
                    s,
                    &self.blocks,
                    &c,
                    &mut self.fluid,
                    &self.walls,
                    st,
                    body_force,
                    lists,
                )
            }
            Search::KdTree(s) => {
                modern_force_pass(s, &c, &mut self.fluid, &self.walls, st, body_force)
            }
        }
    }
}

/// Strain rate V of Eq. 4–5 over the fluid neighbours (the continuity path's share of the
/// paper's density pass).
fn strain_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
) {
    let kernel = c.kernel;
    let m = c.mass;
    let pos = &fluid.position;
    let vel = &fluid.velocity;
    let inv_rho = &fluid.inverse_density;
    fluid
        .strain_rate
        .par_iter_mut()
        .enumerate()
        .with_min_len(PAR_CHUNK)
        .for_each(|(i, strain_out)| {
            let xi = pos[i];
            let vi = vel[i];
            let mut grad_v = Tensor::<D>::zeros();
            search.for_each_fluid_candidate(&xi, |j| {
                let xij = xi - pos[j];
                let r2 = xij.norm_squared();
                if r2 < c.support_sq && j != i {
                    let r = r2.sqrt();
                    let grad_w = xij * kernel.gradient_factor(r);
                    grad_v += (vel[j] - vi) * (grad_w * (m * inv_rho[j])).transpose();
                }
            });
            // Eq. 4–5: V = G + Gᵀ − (2/3) tr(G) I.
            *strain_out = strain_rate_of(&grad_v);
        });
}

/// The no-slip walls' share of the strain rate V (Eq. 4–5): the mirrored wall velocity
/// (Adami et al. 2012 Eq. 22) in the velocity gradient of the fluid particles near a wall.
/// V is linear in the gradient G, so the wall share is added to the fluid share as is.
fn wall_strain_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    wall_velocity: &[Vector<D>],
) {
    let kernel = c.kernel;
    let m = c.mass;
    let pos = &fluid.position;
    let vel = &fluid.velocity;
    fluid
        .strain_rate
        .par_iter_mut()
        .enumerate()
        .with_min_len(PAR_CHUNK)
        .for_each(|(i, strain_out)| {
            let xi = pos[i];
            let vi = vel[i];
            let mut grad_v = Tensor::<D>::zeros();
            search.for_each_wall_candidate(&xi, |w| {
                let xiw = xi - walls.position[w];
                let r2 = xiw.norm_squared();
                if r2 < c.support_sq {
                    let grad_w = xiw * kernel.gradient_factor(r2.sqrt());
                    grad_v += (wall_velocity[w] - vi)
                        * (grad_w * (m * walls.inverse_density[w])).transpose();
                }
            });
            *strain_out += strain_rate_of(&grad_v);
        });
}

/// Wall pass of the modern step: dynamic walls (summation density with the Eq. 20 reset,
/// EOS) or Adami's extrapolated pressure; the nearest fluid particle of each wall particle
/// (for the paper's load evaluation) and, for no-slip Adami walls, the mirrored velocity.
#[allow(clippy::too_many_arguments)]
fn wall_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    k: &ModernConstants,
    fluid: &mut Fluid<D>,
    walls: &mut Walls<D>,
    next_wall_density: &mut [f64],
    st: &mut ModernState<D>,
    body_force: Vector<D>,
) {
    let kernel = c.kernel;
    let pos = &fluid.position;
    let vel = &fluid.velocity;
    let rho = &fluid.density;
    let inv_rho = &fluid.inverse_density;
    let p = &fluid.pressure;
    let wall_pos = &walls.position;
    let wall_inv_rho = &walls.inverse_density;
    let adami = k.adami;
    let no_slip = k.no_slip;
    let mut dummy: [Vector<D>; 0] = [];
    let wall_vel: &mut [Vector<D>] = if no_slip {
        &mut st.wall_velocity
    } else {
        &mut dummy
    };
    let fill = |w_i: usize,
                rho_out: &mut f64,
                p_out: &mut f64,
                nearest_out: &mut u32,
                vel_out: Option<&mut Vector<D>>| {
        let xw = wall_pos[w_i];
        let mut nearest = (f64::INFINITY, u32::MAX);
        if adami {
            // Adami, Hu & Adams (2012) Eq. 27 (and Eq. 22 for the velocity).
            let (mut sum_w, mut sum_pw) = (0.0, 0.0);
            let mut sum_rx = Vector::<D>::zeros();
            let mut sum_v = Vector::<D>::zeros();
            search.for_each_fluid_candidate(&xw, |j| {
                let d = xw - pos[j];
                let r2 = d.norm_squared();
                if r2 < c.support_sq {
                    let w = kernel.value(r2.sqrt());
                    sum_w += w;
                    sum_pw += p[j] * w;
                    sum_rx += d * (rho[j] * w);
                    if no_slip {
                        sum_v += vel[j] * w;
                    }
                    if r2 < nearest.0 {
                        nearest = (r2, j as u32);
                    }
                }
            });
            if sum_w > 1e-12 {
                let mut pw = (sum_pw + body_force.dot(&sum_rx)) / sum_w;
                if c.clamp_negative || c.wall_separation {
                    pw = pw.max(0.0);
                }
                *p_out = pw;
                *rho_out = c.density_of(pw, k.inv_gamma);
                if let Some(v) = vel_out {
                    // No-slip: v_w = 2 v_wall − ṽ_w with the wall at rest in the tank frame.
                    *v = -sum_v / sum_w;
                }
            } else {
                *p_out = 0.0;
                *rho_out = c.rest_density;
                if let Some(v) = vel_out {
                    *v = Vector::<D>::zeros();
                }
            }
        } else {
            // Dynamic walls: Eq. 19 with the Eq. 20 reset, then Eq. 18.
            let (rho_sum, kernel_sum, near) =
                wall_summation(search, c, &xw, pos, inv_rho, wall_pos, wall_inv_rho);
            nearest = near;
            let r = if kernel_sum < c.free_surface_threshold {
                c.rest_density
            } else {
                rho_sum
            };
            *rho_out = r;
            *p_out = c.pressure(r);
        }
        *nearest_out = nearest.1;
    };
    if no_slip {
        next_wall_density
            .par_iter_mut()
            .zip(st.wall_pressure_next.par_iter_mut())
            .zip(walls.nearest_fluid.par_iter_mut())
            .zip(wall_vel.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_CHUNK)
            .for_each(|(w_i, (((r, pw), nf), v))| fill(w_i, r, pw, nf, Some(v)));
    } else {
        next_wall_density
            .par_iter_mut()
            .zip(st.wall_pressure_next.par_iter_mut())
            .zip(walls.nearest_fluid.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_CHUNK)
            .for_each(|(w_i, ((r, pw), nf))| fill(w_i, r, pw, nf, None));
    }
    walls
        .density
        .par_iter_mut()
        .zip(walls.inverse_density.par_iter_mut())
        .zip(walls.pressure.par_iter_mut())
        .zip(next_wall_density.par_iter())
        .zip(st.wall_pressure_next.par_iter())
        .with_min_len(PAR_CHUNK)
        .for_each(|((((rho_w, inv), p_w), &r), &pn)| {
            *rho_w = r;
            *inv = 1.0 / r;
            *p_w = pn;
        });
}

/// What the pair terms of the modern force pass read: one copy for both neighbour backends,
/// its methods always inlined into their sweeps.
struct ModernPairTerms<'a, const D: usize> {
    /// The paper sweep's constants and fluid and wall arrays (pressure and viscous terms).
    base: ForceSweep<'a, D>,
    /// Walls in the artificial viscosity and the paper's viscous term: dynamic walls only
    /// (wall at rest, as the paper). Adami walls take neither: free slip has no wall stress,
    /// no-slip the physical viscous stress of the mirrored velocity (`no_slip_viscous`).
    wall_av: bool,
    wall_viscous: bool,
    no_slip_viscous: bool,
    continuity: bool,
    /// 0: none, 1: Molteni–Colagrossi, 2: Fourtakas.
    diffusion: u8,
    /// ψ_ij·∇_i W_ij = 2 (ρ_j − ρ_i) x_ji·x_ij F/r² = −2 (ρ_j − ρ_i) F, F = (dW/dr)/r: the
    /// factor −2 δ h c0 of (ρ_j − ρ_i) F.
    diff_coeff: f64,
    shifting: bool,
    /// Hydrostatic density of Fourtakas' diffusion (kg/m³).
    rho_h: &'a [f64],
    /// Wall velocity seen by the fluid with no-slip Adami walls (m/s).
    wall_vel: &'a [Vector<D>],
}

/// Fluid particle i of a row of modern pairs.
struct ModernOwner<const D: usize> {
    f: ForceOwner<D>,
    /// m/ρ_i (m³, 2D: m²).
    volume: f64,
    /// The density the diffusion term differences: ρ_i, or ρ_i − ρ_H,i (Fourtakas).
    rho_dyn: f64,
}

/// One fluid pair's shares (i within the support of j).
struct FluidPairTerm<const D: usize> {
    /// Acceleration of i (Eq. 8); j gets its negative.
    acc: Vector<D>,
    /// dρ_i/dt and dρ_j/dt: continuity m (v_i − v_j)·∇_i W_ij plus the diffusion terms.
    drho_i: f64,
    drho_j: f64,
    /// ∇_i W_ij and W_ij (the latter only with shifting) and m/ρ_j, for the shifting sums.
    grad_w: Vector<D>,
    w: f64,
    volume_j: f64,
}

/// One fluid–wall pair's shares of i's sums: acceleration, dρ/dt, and the shifting's ∇C and
/// kernel sum.
struct WallPairTerm<const D: usize> {
    acc: Vector<D>,
    drho: f64,
    grad_c: Vector<D>,
    kernel_sum: f64,
}

impl<'a, const D: usize> ModernPairTerms<'a, D> {
    /// The terms over `fluid` (its acceleration and density rate are not read), `walls` and
    /// the modern state's hydrostatic density and wall velocity.
    fn new(
        c: &PassConstants,
        fluid: &'a Fluid<D>,
        walls: &'a Walls<D>,
        st: &'a ModernState<D>,
    ) -> Self {
        let k = &st.k;
        let base = ForceSweep::new(c, fluid, walls);
        ModernPairTerms {
            wall_av: base.av_on && !k.adami,
            wall_viscous: base.viscous && !k.adami,
            no_slip_viscous: base.viscous && k.adami && k.no_slip,
            continuity: k.continuity,
            diffusion: k.diffusion,
            diff_coeff: -2.0 * k.diffusion_coeff,
            shifting: k.shifting.is_some(),
            rho_h: &st.hydro_density,
            wall_vel: &st.wall_velocity,
            base,
        }
    }

    /// The density of particle i the diffusion term differences.
    #[inline(always)]
    fn rho_dyn(&self, i: usize) -> f64 {
        if self.diffusion == 2 {
            self.base.rho[i] - self.rho_h[i]
        } else {
            self.base.rho[i]
        }
    }

    #[inline(always)]
    fn owner(&self, i: usize) -> ModernOwner<D> {
        let f = self.base.owner(i);
        ModernOwner {
            volume: self.base.c.mass * f.inv_rho,
            rho_dyn: self.rho_dyn(i),
            f,
        }
    }

    /// The pair of fluid particles i (`o`) and j at squared distance r2 within the support:
    /// Eq. 8 (pressure, artificial viscosity, viscous stress), the continuity equation
    /// dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (Monaghan 1992) with the δ-SPH diffusion term
    /// (Molteni & Colagrossi 2009; Fourtakas et al. 2019), and what the shifting sums need.
    /// `r` is the distance and `factors` the pair's (∇W factor, 1/s, 1/ρ̄) of
    /// [`ForceSweep::pair_factors`].
    #[inline(always)]
    fn fluid_pair(
        &self,
        o: &ModernOwner<D>,
        j: usize,
        xij: Vector<D>,
        r: f64,
        (f, inv_s, inv_rho_mean): (f64, f64, f64),
    ) -> FluidPairTerm<D> {
        let c = &self.base.c;
        let m = c.mass;
        let grad_w = xij * f;
        let inv_rho_j = self.base.inv_rho[j];
        let volume_j = m * inv_rho_j;
        let inv_rho_ij = o.f.inv_rho * inv_rho_j;
        let vij = o.f.v - self.base.vel[j];
        // Pressure part of (σ_i + σ_j)/(ρ_i ρ_j) ∇W (Eq. 8).
        let mut scalar = -(o.f.p + self.base.p[j]) * inv_rho_ij;
        if self.base.av_on {
            scalar -= self
                .base
                .artificial_viscosity(vij, xij, inv_s, inv_rho_mean);
        }
        let mut acc = grad_w * (m * scalar);
        if self.base.viscous {
            // Viscous part μ (V_i + V_j)/(ρ_i ρ_j) ∇W (Eq. 8, 3).
            acc += (o.f.strain + self.base.strain[j]) * grad_w * (m * c.viscosity * inv_rho_ij);
        }
        let (mut drho_i, mut drho_j) = (0.0, 0.0);
        if self.continuity {
            let d = m * vij.dot(&grad_w);
            (drho_i, drho_j) = (d, d);
            if self.diffusion != 0 {
                let psi = self.diff_coeff * (self.rho_dyn(j) - o.rho_dyn) * f;
                drho_i += psi * volume_j;
                drho_j -= psi * o.volume;
            }
        }
        let w = if self.shifting {
            c.kernel.value(r)
        } else {
            0.0
        };
        FluidPairTerm {
            acc,
            drho_i,
            drho_j,
            grad_w,
            w,
            volume_j,
        }
    }

    /// [`Self::fluid_pair`] with the pair factors computed here (the paths without a batch).
    #[inline(always)]
    fn fluid_pair_at(
        &self,
        o: &ModernOwner<D>,
        j: usize,
        xij: Vector<D>,
        r2: f64,
    ) -> FluidPairTerm<D> {
        let factors = self.base.pair_factors(r2, o.f.rho + self.base.rho[j]);
        self.fluid_pair(o, j, xij, r2.sqrt().max(1e-150), factors)
    }

    /// The pair of fluid particle `o` and wall particle `w` if within the support: Eq. 8 with
    /// the wall's pressure (and velocity when mirrored), the continuity term of the wall's
    /// velocity (zero: the tank frame), and the shifting sums.
    #[inline(always)]
    fn wall_term(&self, o: &ForceOwner<D>, w: usize) -> Option<WallPairTerm<D>> {
        let c = &self.base.c;
        let m = c.mass;
        let xiw = o.x - self.base.wall_pos[w];
        let r2 = xiw.norm_squared();
        if r2 >= c.support_sq {
            return None;
        }
        let (f, inv_s, inv_rho_mean) = self.base.pair_factors(r2, o.rho + self.base.wall_rho[w]);
        let grad_w = xiw * f;
        let inv_rho_iw = o.inv_rho * self.base.wall_inv_rho[w];
        let mut scalar = -(o.p + self.base.wall_p[w]) * inv_rho_iw;
        if self.wall_av {
            scalar -= self
                .base
                .artificial_viscosity(o.v, xiw, inv_s, inv_rho_mean);
        }
        let mut acc = grad_w * (m * scalar);
        if self.wall_viscous {
            acc += o.strain * grad_w * (m * c.viscosity * inv_rho_iw);
        }
        if self.no_slip_viscous {
            // No-slip Adami wall: the laminar viscous force of Morris et al. (1997),
            // m (μ_i + μ_w) (x_iw·∇_i W) v_iw / (ρ_i ρ_w (r² + 0.01 h²)), against the mirrored
            // wall velocity (Adami et al. 2012 Eq. 22; x_iw·∇_i W = r² F).
            let v_iw = o.v - self.wall_vel[w];
            acc += v_iw * (m * 2.0 * c.viscosity * inv_rho_iw * r2 * f * inv_s);
        }
        let drho = if self.continuity {
            m * o.v.dot(&grad_w)
        } else {
            0.0
        };
        let (grad_c, kernel_sum) = if self.shifting {
            let volume_w = m * self.base.wall_inv_rho[w];
            (grad_w * volume_w, volume_w * c.kernel.value(r2.sqrt()))
        } else {
            (Vector::<D>::zeros(), 0.0)
        };
        Some(WallPairTerm {
            acc,
            drho,
            grad_c,
            kernel_sum,
        })
    }
}

/// The arrays the modern force pass writes, taken out of the fluid and the state while the
/// pair terms read the rest (no allocation: empty Vecs stand in until [`Self::restore`]).
struct ForceOutputs<const D: usize> {
    acceleration: Vec<Vector<D>>,
    density_rate: Vec<f64>,
    shift_gradient: Vec<Vector<D>>,
    shift_kernel_sum: Vec<f64>,
}

impl<const D: usize> ForceOutputs<D> {
    fn take(fluid: &mut Fluid<D>, st: &mut ModernState<D>) -> Self {
        ForceOutputs {
            acceleration: std::mem::take(&mut fluid.acceleration),
            density_rate: std::mem::take(&mut fluid.density_rate),
            shift_gradient: std::mem::take(&mut st.shift_gradient),
            shift_kernel_sum: std::mem::take(&mut st.shift_kernel_sum),
        }
    }

    fn restore(self, fluid: &mut Fluid<D>, st: &mut ModernState<D>) {
        fluid.acceleration = self.acceleration;
        fluid.density_rate = self.density_rate;
        st.shift_gradient = self.shift_gradient;
        st.shift_kernel_sum = self.shift_kernel_sum;
    }
}

/// Owner i's running sums over its pairs: acceleration, dρ/dt, and the shifting's ∇C and
/// kernel sum.
struct OwnerSums<const D: usize> {
    acc: Vector<D>,
    drho: f64,
    grad_c: Vector<D>,
    ksum: f64,
}

impl<const D: usize> OwnerSums<D> {
    fn new(ksum: f64) -> Self {
        OwnerSums {
            acc: Vector::<D>::zeros(),
            drho: 0.0,
            grad_c: Vector::<D>::zeros(),
            ksum,
        }
    }

    /// i's share of a fluid pair.
    #[inline(always)]
    fn add_fluid(&mut self, pair: &FluidPairTerm<D>, shifting: bool) {
        self.acc += pair.acc;
        self.drho += pair.drho_i;
        if shifting {
            self.grad_c += pair.grad_w * pair.volume_j;
            self.ksum += pair.volume_j * pair.w;
        }
    }

    /// A fluid–wall pair.
    #[inline(always)]
    fn add_wall(&mut self, wall: &WallPairTerm<D>) {
        self.acc += wall.acc;
        self.drho += wall.drho;
        self.grad_c += wall.grad_c;
        self.ksum += wall.kernel_sum;
    }
}

/// Force pass of the modern step: the momentum equation of the paper (Eq. 8–16) with the
/// wall treatment chosen, and in the same pair loop the continuity equation
/// dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (Monaghan 1992; walls at rest) with the δ-SPH
/// diffusion term (Molteni & Colagrossi 2009; Fourtakas et al. 2019), and the shifting
/// gradient ∇C_i = Σ_j V_j ∇_i W_ij. Every pair is seen from both of its particles.
fn modern_force_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    st: &mut ModernState<D>,
    body_force: Vector<D>,
) {
    let shifting = st.k.shifting.is_some();
    let w0 = c.kernel.value(0.0);
    let mut out = ForceOutputs::take(fluid, st);
    {
        let terms = ModernPairTerms::new(c, fluid, walls, st);
        let pair_loop =
            |i: usize, acc_out: &mut Vector<D>, drho_out: &mut f64| -> (Vector<D>, f64) {
                let t = &terms;
                let o = t.owner(i);
                let mut sums = OwnerSums::new(0.0);
                search.for_each_fluid_candidate(&o.f.x, |j| {
                    if j == i {
                        if shifting {
                            sums.ksum += o.volume * w0;
                        }
                        return;
                    }
                    let xij = o.f.x - t.base.pos[j];
                    let r2 = xij.norm_squared();
                    if r2 < c.support_sq {
                        sums.add_fluid(&t.fluid_pair_at(&o, j, xij, r2), shifting);
                    }
                });
                search.for_each_wall_candidate(&o.f.x, |w| {
                    if let Some(wall) = t.wall_term(&o.f, w) {
                        sums.add_wall(&wall);
                    }
                });
                *acc_out = sums.acc + body_force;
                *drho_out = sums.drho;
                (sums.grad_c, sums.ksum)
            };
        if shifting {
            out.acceleration
                .par_iter_mut()
                .zip(out.density_rate.par_iter_mut())
                .zip(out.shift_gradient.par_iter_mut())
                .zip(out.shift_kernel_sum.par_iter_mut())
                .enumerate()
                .with_min_len(PAR_CHUNK)
                .for_each(|(i, (((acc, drho), g), ks))| {
                    (*g, *ks) = pair_loop(i, acc, drho);
                });
        } else {
            out.acceleration
                .par_iter_mut()
                .zip(out.density_rate.par_iter_mut())
                .enumerate()
                .with_min_len(PAR_CHUNK)
                .for_each(|(i, (acc, drho))| {
                    pair_loop(i, acc, drho);
                });
        }
    }
    out.restore(fluid, st);
}

/// What the sorted strain sweep reads and writes, so that its batch evaluation is an
/// always-inlined method (a closure called from two places is compiled as a function).
struct StrainSweep<'a, const D: usize> {
    kernel: Kernel,
    m: f64,
    pos: &'a [Vector<D>],
    vel: &'a [Vector<D>],
    inv_rho: &'a [f64],
    grad_acc: &'a SharedSlice<Tensor<D>>,
}

impl<const D: usize> StrainSweep<'_, D> {
    /// A batch of pairs (i, j) within the support: (v_j − v_i) ⊗ ∇_i W_ij to i's sum and to
    /// j's, with the kernel factors of the batch from one vectorised loop.
    #[inline(always)]
    fn batch(&self, i: usize, batch_j: &[u32], batch_r2: &[f64], grad_v: &mut Tensor<D>) {
        let m = self.m;
        let (xi, vi, volume_i) = (self.pos[i], self.vel[i], m * self.inv_rho[i]);
        let mut batch_w = [0.0f64; BATCH];
        let mut batch_f = [0.0f64; BATCH];
        self.kernel
            .values_and_gradient_factors(batch_r2, &mut batch_w, &mut batch_f);
        for (&j, &f) in batch_j.iter().zip(&batch_f) {
            let j = j as usize;
            let grad_w = (xi - self.pos[j]) * f;
            let outer = (self.vel[j] - vi) * grad_w.transpose();
            *grad_v += outer * (m * self.inv_rho[j]);
            // SAFETY: j is in this block or the next (colour_blocks).
            unsafe {
                *self.grad_acc.at(j) += outer * volume_i;
            }
        }
    }
}

/// One particle of the sorted strain sweep: its index, its neighbour list with fill and
/// overflow flag, and its velocity-gradient sum.
struct StrainOwner<'s, 'a, const D: usize> {
    sweep: &'s StrainSweep<'a, D>,
    i: usize,
    list: &'s mut [u32],
    fill: ListFill,
    grad_v: Tensor<D>,
}

impl<const D: usize> ForwardPairBatch for StrainOwner<'_, '_, D> {
    #[inline(always)]
    fn batch(&mut self, batch_j: &[u32], batch_r2: &[f64]) {
        self.sweep
            .batch(self.i, batch_j, batch_r2, &mut self.grad_v);
        self.fill.append(self.list, batch_j);
    }
}

/// Strain rate V of Eq. 4–5 over the fluid neighbours (as [`strain_pass`]) on cell-sorted
/// arrays, each pair once: (v_j − v_i) ⊗ ∇_i W_ij is the same tensor seen from j. Fills the
/// half neighbour lists (forward fluid neighbours, then all wall neighbours) that the force
/// sweep of the same positions reads, as the paper's density sweep does.
fn strain_pass_sorted<const D: usize>(
    grid: &CellGrid<D>,
    blocks: &[u32],
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    wall_pos: &[Vector<D>],
) {
    let kernel = c.kernel;
    let m = c.mass;
    let pos = &fluid.position;
    let vel = &fluid.velocity;
    let inv_rho = &fluid.inverse_density;
    let capacity = fluid.neighbours.capacity;
    fluid
        .strain_rate
        .par_iter_mut()
        .with_min_len(PAR_CHUNK)
        .for_each(|g| *g = Tensor::<D>::zeros());
    let grad_acc = SharedSlice::new(&mut fluid.strain_rate);
    let entries = SharedSlice::new(&mut fluid.neighbours.entries);
    let counts = SharedSlice::new(&mut fluid.neighbours.count);
    let starts = SharedSlice::new(&mut fluid.neighbours.start);
    let sweep = StrainSweep {
        kernel,
        m,
        pos,
        vel,
        inv_rho,
        grad_acc: &grad_acc,
    };
    colour_sweep(blocks, |_, begin, end| {
        // The block's lists are packed from the start of its share of the entries (see
        // `density_pass_sorted`).
        let mut cursor = begin * capacity;
        for i in begin..end {
            let xi = pos[i];
            // SAFETY: entries begin·capacity..end·capacity belong to this block, and
            // cursor + capacity ≤ (i + 1)·capacity.
            let list = unsafe { entries.slice(cursor, capacity) };
            let mut this = StrainOwner {
                sweep: &sweep,
                i,
                list: &mut *list,
                fill: ListFill::default(),
                grad_v: Tensor::<D>::zeros(),
            };
            forward_pairs_batched(grid, pos, i, c.support_sq, &mut this);
            let StrainOwner {
                mut fill, grad_v, ..
            } = this;
            grid.for_each_wall_candidate(&xi, |w| {
                if (xi - wall_pos[w]).norm_squared() < c.support_sq {
                    fill.push(list, w as u32 | WALL_NEIGHBOUR);
                }
            });
            // SAFETY: slot i belongs to this block.
            unsafe {
                *grad_acc.at(i) += grad_v;
                *counts.at(i) = fill.stored_count();
                *starts.at(i) = cursor as u32;
            }
            cursor += fill.listed;
        }
    });
    // Eq. 4–5: V = G + Gᵀ − (2/3) tr(G) I.
    fluid
        .strain_rate
        .par_iter_mut()
        .with_min_len(PAR_CHUNK)
        .for_each(|g| *g = strain_rate_of(g));
}

/// The slots of the sorted modern force sweep that a fluid pair writes for its second
/// particle j.
struct PairScatter<'a, const D: usize> {
    acc: &'a SharedSlice<Vector<D>>,
    drho: &'a SharedSlice<f64>,
    grad_c: &'a SharedSlice<Vector<D>>,
    ksum: &'a SharedSlice<f64>,
    shifting: bool,
}

impl<const D: usize> PairScatter<'_, D> {
    /// A fluid pair's shares: i's to its sums, j's to j's slots.
    #[inline(always)]
    fn add(&self, sums: &mut OwnerSums<D>, o: &ModernOwner<D>, j: usize, pair: &FluidPairTerm<D>) {
        sums.add_fluid(pair, self.shifting);
        // SAFETY (all four): j is in this block or the next (colour_blocks).
        unsafe {
            *self.acc.at(j) -= pair.acc;
            *self.drho.at(j) += pair.drho_j;
            if self.shifting {
                *self.grad_c.at(j) -= pair.grad_w * o.volume;
                *self.ksum.at(j) += o.volume * pair.w;
            }
        }
    }
}

/// The force pass of the modern step (as [`modern_force_pass`]) on cell-sorted arrays,
/// each fluid pair once: the momentum term and the shifting gradient are antisymmetric in
/// i and j (∇_j W_ji = −∇_i W_ij), the continuity term m (v_i − v_j)·∇_i W_ij symmetric, and
/// the diffusion term of j is that of i with i and j exchanged. With `lists` (the strain
/// sweep's, of these positions) the pairs come from the lists, their factors in vectorised
/// batches; otherwise, or for a particle whose list overflowed, from the grid.
#[allow(clippy::too_many_arguments)]
fn modern_force_pass_sorted<const D: usize>(
    grid: &CellGrid<D>,
    blocks: &[u32],
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    st: &mut ModernState<D>,
    body_force: Vector<D>,
    lists: bool,
) {
    let shifting = st.k.shifting.is_some();
    let w0 = c.kernel.value(0.0);
    let n = fluid.position.len();
    let mut out = ForceOutputs::take(fluid, st);
    out.acceleration
        .par_iter_mut()
        .zip(out.density_rate.par_iter_mut())
        .with_min_len(PAR_CHUNK)
        .for_each(|(a, d)| {
            *a = body_force;
            *d = 0.0;
        });
    if shifting {
        out.shift_gradient
            .par_iter_mut()
            .zip(out.shift_kernel_sum.par_iter_mut())
            .with_min_len(PAR_CHUNK)
            .for_each(|(g, s)| {
                *g = Vector::<D>::zeros();
                *s = 0.0;
            });
    }
    debug_assert!(!shifting || out.shift_gradient.len() == n);
    {
        let acc_shared = SharedSlice::new(&mut out.acceleration);
        let drho_shared = SharedSlice::new(&mut out.density_rate);
        let grad_c_shared = SharedSlice::new(&mut out.shift_gradient);
        let ksum_shared = SharedSlice::new(&mut out.shift_kernel_sum);
        let terms = ModernPairTerms::new(c, fluid, walls, st);
        let list_entries = fluid.neighbours.entries.as_slice();
        let list_count = fluid.neighbours.count.as_slice();
        let list_start = fluid.neighbours.start.as_slice();
        let scatter = PairScatter {
            acc: &acc_shared,
            drho: &drho_shared,
            grad_c: &grad_c_shared,
            ksum: &ksum_shared,
            shifting,
        };
        colour_sweep(blocks, |_, begin, end| {
            let t = &terms;
            let pos = t.base.pos;
            let mut batch = PairFactorBatch::new();
            for i in begin..end {
                let o = t.owner(i);
                let xi = o.f.x;
                let mut sums = OwnerSums::new(if shifting { o.volume * w0 } else { 0.0 });
                let count = if lists { list_count[i] } else { LIST_OVERFLOW };
                if count != LIST_OVERFLOW {
                    let first = list_start[i] as usize;
                    let (fluid_list, wall_list) =
                        split_walls(&list_entries[first..first + count as usize]);
                    t.base.for_each_listed_pair(
                        xi,
                        o.f.rho,
                        fluid_list,
                        &mut batch,
                        |j, xij, r, f| {
                            scatter.add(&mut sums, &o, j, &t.fluid_pair(&o, j, xij, r, f));
                        },
                    );
                    for &entry in wall_list {
                        if let Some(wall) = t.wall_term(&o.f, (entry & !WALL_NEIGHBOUR) as usize) {
                            sums.add_wall(&wall);
                        }
                    }
                } else {
                    grid.for_each_forward_range(i, &xi, |j0, j1| {
                        for (j, xj) in (j0..j1).zip(&pos[j0..j1]) {
                            let xij = xi - xj;
                            let r2 = xij.norm_squared();
                            if r2 < c.support_sq {
                                scatter.add(&mut sums, &o, j, &t.fluid_pair_at(&o, j, xij, r2));
                            }
                        }
                    });
                    grid.for_each_wall_candidate(&xi, |w| {
                        if let Some(wall) = t.wall_term(&o.f, w) {
                            sums.add_wall(&wall);
                        }
                    });
                }
                // SAFETY: slot i belongs to this block.
                unsafe {
                    *acc_shared.at(i) += sums.acc;
                    *drho_shared.at(i) += sums.drho;
                    if shifting {
                        *grad_c_shared.at(i) += sums.grad_c;
                        *ksum_shared.at(i) += sums.ksum;
                    }
                }
            }
        });
    }
    out.restore(fluid, st);
}
