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


use crate::error::SimError;
use crate::sim::*;

impl<const D: usize> Simulation<D> {

    /// Initial state of a modern run: with continuity density the fluid starts at the
    /// hydrostatic density of its depth below the fill level (no settling pressure wave).
    pub(crate) fn modern_init(&mut self) {
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
    pub(crate) fn step_modern(&mut self, ground_accel: Vector<D>) -> Result<(), SimError> {
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


    /// Density stage: summation (Eq. 19–20, the paper's pass, which also sums the dynamic
    /// walls) or, with continuity, the strain rate of Eq. 5 alone (when μ > 0); then the
    /// hydrostatic density of Fourtakas' diffusion and the wall pass.
    pub(crate) fn modern_density_stage(&mut self, body_force: Vector<D>) {
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

    pub(crate) fn modern_forces(&mut self, body_force: Vector<D>) {
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
