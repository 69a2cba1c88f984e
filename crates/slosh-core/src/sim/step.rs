//! The time step: one pipeline of the stages of [`crate::stages::StepPlan`], chosen once per
//! run.
//!
//! 1. sorting: re-sort the fluid by cell (every step with the cell grid, for the pair
//!    sweeps that visit each pair once; every few steps with the k-d tree) and re-index;
//! 2. symplectic integration only: the time step from the state at n, predictor to n+½;
//! 3. density stage: summation (Eq. 19–20, 18, with the strain rate of Eq. 4–5) or, with
//!    continuity density, the strain rate alone and the hydrostatic density of Fourtakas'
//!    diffusion;
//! 4. wall stage: dynamic walls (summed in the density pass with summation density) or
//!    Adami's extrapolated pressure;
//! 5. force stage: momentum (Eq. 8–16) and, in the same pair loop, the continuity equation,
//!    the density diffusion and the shifting sums of the parts switched on;
//! 6. wall pressures for loads (§2.6) of this state;
//! 7. leap-frog: time step, update (Eq. 21–22) and the continuity density update;
//!    symplectic: corrector; then shifting, and the blow-up checks.

use crate::error::SimError;
use crate::frame::{BodyForce, RotatingFrame, TankRotation};
use crate::sim::*;

impl<const D: usize> Simulation<D> {
    /// Advances one time step with the ground acceleration `ground_accel` (m/s², tank frame:
    /// the fluid feels −ground_accel as a body force besides gravity).
    pub fn step(&mut self, ground_accel: Vector<D>) -> Result<(), SimError> {
        self.step_turning(ground_accel, None)
    }

    /// Advances one time step with the ground acceleration `ground_accel` (m/s², world frame)
    /// and, when given, the tank's rotation about a pivot ([`crate::frame`]: gravity turning
    /// with the tank and the Euler, centrifugal and Coriolis forces). Without a rotation this
    /// is [`Self::step`].
    pub fn step_turning(
        &mut self,
        ground_accel: Vector<D>,
        rotation: Option<&TankRotation>,
    ) -> Result<(), SimError> {
        if !ground_accel.iter().all(|a| a.is_finite()) {
            return Err(SimError::BadExcitation {
                time: self.time,
                value: format!("{:?}", ground_accel.as_slice()),
            });
        }
        if let Some(r) = rotation {
            if !r.is_valid() {
                return Err(SimError::BadExcitation {
                    time: self.time,
                    value: format!(
                        "rotation angle {} rad, rate {} rad/s, acceleration {} rad/s², axis {:?}, pivot {:?}",
                        r.angle, r.rate, r.acceleration, r.axis, r.pivot
                    ),
                });
            }
            if D == 2 && (r.axis[0] != 0.0 || r.axis[2] != 0.0) {
                return Err(SimError::InvalidSetup(format!(
                    "a 2D tank turns about the y axis only (the axis out of its x–z section); got \
                     the axis {:?}",
                    r.axis
                )));
            }
            if self.device.is_some() {
                return Err(SimError::InvalidSetup(
                    "a rotating tank runs on the CPU backend only (backend = \"cpu\"); the device \
                     backends apply a uniform body force"
                        .into(),
                ));
            }
        }
        self.rotation = rotation.copied();
        let body = BodyForce::new(self.params.gravity, ground_accel, rotation);
        if self.device.is_some() {
            return self.device_step(body);
        }
        let plan = self.plan;
        let symplectic = plan.integration == TimeIntegration::Symplectic;
        let clock = std::time::Instant::now();
        let reorder = self.params.reorder_interval;
        if plan.sorting == Sorting::Periodic
            && reorder > 0
            && self.step > 0
            && self.step.is_multiple_of(reorder as u64)
        {
            self.sort_by_cell();
        }
        let body_force = body.uniform;

        let mut dt = 0.0;
        if symplectic {
            dt = self.time_step();
            self.symplectic_predictor(dt);
        }
        let t1 = std::time::Instant::now();
        // The state of step 0 was evaluated by `new`; the predictor moves the particles.
        if self.step > 0 || symplectic {
            self.reindex();
            let t_search = std::time::Instant::now();
            self.phase_times.neighbour_search += (t_search - clock).as_secs_f64();
            self.density_and_wall_stages(&body);
            self.phase_times.density += t_search.elapsed().as_secs_f64();
        } else {
            self.phase_times.integration += (t1 - clock).as_secs_f64();
        }
        let t2 = std::time::Instant::now();
        self.force_stage(body_force);
        if let Some(frame) = &body.rotating {
            self.add_frame_forces(frame);
        }
        let t3 = std::time::Instant::now();
        self.phase_times.forces += (t3 - t2).as_secs_f64();
        let load_time = if symplectic {
            self.time + 0.5 * dt
        } else {
            self.time
        };
        self.record_loads_at(&body, load_time);
        let t4 = std::time::Instant::now();
        self.phase_times.loads += (t4 - t3).as_secs_f64();

        match plan.integration {
            TimeIntegration::Symplectic => {
                self.symplectic_corrector(dt);
                self.apply_shifting(dt);
                self.check_particles(dt)?;
            }
            TimeIntegration::LeapFrog => {
                dt = self.time_step();
                self.integrate(dt, self.dt_previous)?;
                if matches!(plan.density, DensityStage::Continuity { .. }) {
                    self.continuity_euler(dt);
                }
                self.apply_shifting(dt);
            }
        }
        self.finish_step(dt, t4);
        Ok(())
    }

    /// One step on the attached device: the particles advance there; the host takes the step
    /// length and its statistics, the blow-up counts and this step's wall pressures, from
    /// which it records the loads as the CPU step does (at the mid-step time of the
    /// symplectic integrator).
    fn device_step(&mut self, body: BodyForce<D>) -> Result<(), SimError> {
        let clock = std::time::Instant::now();
        let body_force = body.uniform;
        let Some(device) = self.device.as_mut() else {
            return Ok(());
        };
        let report = device.step(body_force, &mut self.walls)?;
        self.host_stale = true;
        let dt = report.dt;
        let h = self.constants.kernel.h;
        let c = self.params.cfl_number;
        let bound = {
            let acoustic = c * h / (self.sound_speed + report.max_speed);
            let force = if report.max_acceleration > 0.0 {
                c * (h / report.max_acceleration).sqrt()
            } else {
                f64::INFINITY
            };
            let viscous = if self.params.dynamic_viscosity > 0.0 {
                c * h * h * self.params.rest_density / self.params.dynamic_viscosity
            } else {
                f64::INFINITY
            };
            acoustic.min(force).min(viscous)
        };
        self.stats.dt_bound_min = self.stats.dt_bound_min.min(bound);
        if dt > bound * (1.0 + 1e-9) {
            self.stats.steps_above_bound += 1;
        }
        let mach = report.max_speed / self.sound_speed;
        self.stats.max_mach = self.stats.max_mach.max(mach);
        if mach > crate::sound_speed::MACH_LIMIT {
            self.stats.steps_above_mach_limit += 1;
            if self.stats.steps_above_mach_limit == 1 {
                self.stats.first_time_above_mach_limit = self.time;
            }
        }
        self.stats.dt_min = self.stats.dt_min.min(dt);
        self.stats.dt_max = self.stats.dt_max.max(dt);
        let t_loads = std::time::Instant::now();
        self.phase_times.forces += (t_loads - clock).as_secs_f64();
        self.record_loads_at(&body, self.time + 0.5 * dt);
        let t_end = std::time::Instant::now();
        self.phase_times.loads += (t_end - t_loads).as_secs_f64();
        self.blow_up_check(
            dt,
            (
                report.non_finite as usize,
                report.outside as usize,
                report.first_outside,
            ),
        )?;
        self.finish_step(dt, t_end);
        Ok(())
    }

    /// The state a run starts from: with continuity density the fluid (already sunk into its
    /// compression, [`settle_into_compression`]) starts at the hydrostatic density of its depth
    /// below the still level (no settling pressure wave); then the density and wall stages
    /// under gravity alone.
    pub(crate) fn initial_state(&mut self) {
        let c = self.constants;
        if matches!(self.plan.density, DensityStage::Continuity { .. }) {
            let (g, level, k) = (self.params.gravity, self.still_level_cached, self.buffers.k);
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
                *rho = hydrostatic_density(&c, &k, g, (level - x[D - 1]).max(0.0));
                *inv = 1.0 / *rho;
                *p = c.pressure(*rho);
            }
        }
        let mut body = Vector::<D>::zeros();
        body[D - 1] = -self.params.gravity;
        self.density_and_wall_stages(&BodyForce::uniform(body));
    }

    /// Re-sorts and re-indexes the fluid as the plan's sorting asks.
    pub(crate) fn reindex(&mut self) {
        match self.plan.sorting {
            Sorting::GatherEveryStep => self.sort_and_index(),
            Sorting::AllArraysEveryStep => self.sort_all_and_index(),
            Sorting::Periodic => self.rebuild_search(),
        }
    }

    /// The density stage, then the wall stage.
    fn density_and_wall_stages(&mut self, body: &BodyForce<D>) {
        let c = self.constants;
        let summed_walls = self.plan.walls == WallStage::Dynamic;
        match self.plan.density {
            DensityStage::Summation { sweep } => self.summation_density(sweep, summed_walls),
            DensityStage::Continuity {
                velocity_gradient,
                hydrostatic,
            } => {
                match (velocity_gradient, &self.search) {
                    (Some(PairSweep::Half), Search::Grid(s)) => strain_pass_sorted(
                        s,
                        &self.blocks,
                        &c,
                        &mut self.fluid,
                        &self.walls.position,
                    ),
                    (Some(_), search) => {
                        with_search!(search, s => strain_pass(s, &c, &mut self.fluid))
                    }
                    (None, _) => {}
                }
                if hydrostatic {
                    let (g, level) = (self.params.gravity, self.still_level_cached);
                    let k = self.buffers.k;
                    self.buffers
                        .hydro_density
                        .par_iter_mut()
                        .zip(self.fluid.position.par_iter())
                        .with_min_len(PAR_CHUNK)
                        .for_each(|(rho_h, x)| {
                            *rho_h = hydrostatic_density(&c, &k, g, level - body.height(x));
                        });
                }
            }
        }
        match self.plan.walls {
            // Summed in the density pass with summation density.
            WallStage::Dynamic if matches!(self.plan.density, DensityStage::Summation { .. }) => {}
            WallStage::Dynamic => with_search!(&self.search, s => dynamic_walls(
                s,
                &c,
                &self.fluid,
                &mut self.walls,
                &mut self.next_wall_density,
            )),
            WallStage::Adami { no_slip_viscous } => {
                let (inv_gamma, no_slip) = (self.buffers.k.inv_gamma, self.params.wall_no_slip);
                with_search!(&self.search, s => adami_walls(
                    s,
                    &c,
                    inv_gamma,
                    no_slip,
                    &self.fluid,
                    &mut self.walls,
                    &mut self.next_wall_density,
                    &mut self.buffers,
                    body,
                ));
                if no_slip_viscous {
                    with_search!(&self.search, s => wall_strain_pass(
                        s,
                        &c,
                        &mut self.fluid,
                        &self.walls,
                        &self.buffers.wall_velocity,
                    ));
                }
            }
        }
    }

    /// Adds the Euler, centrifugal and Coriolis forces of a turning tank to every fluid
    /// particle's acceleration, at the positions and velocities the force stage used.
    fn add_frame_forces(&mut self, frame: &RotatingFrame<D>) {
        self.fluid
            .acceleration
            .par_iter_mut()
            .zip(self.fluid.position.par_iter())
            .zip(self.fluid.velocity.par_iter())
            .with_min_len(PAR_CHUNK)
            .for_each(|((a, x), v)| *a += frame.moving_terms(x, v));
    }

    /// The force stage.
    fn force_stage(&mut self, body_force: Vector<D>) {
        match self.plan.forces {
            ForceStage::Momentum { sweep } => self.momentum_stage(sweep, body_force),
            ForceStage::Coupled(force) => {
                // The strain-rate sweep of continuity density listed the pairs of these
                // positions; otherwise the pairs come from the grid.
                let lists = matches!(
                    self.plan.density,
                    DensityStage::Continuity {
                        velocity_gradient: Some(PairSweep::Half),
                        ..
                    }
                );
                self.coupled_stage(force, lists, body_force)
            }
        }
    }
}
