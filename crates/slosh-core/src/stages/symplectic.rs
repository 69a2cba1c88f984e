//! Symplectic position Verlet.

use crate::error::SimError;
use crate::sim::*;
use crate::stages::DensityStage;
use rayon::prelude::*;

impl<const D: usize> Simulation<D> {
    /// Symplectic predictor: x^{n+½} = x^n + dt/2 v^n; the mid-step velocity estimate
    /// v^n + dt/2 a^{n−½} for the velocity-dependent terms (artificial viscosity, strain rate,
    /// dρ/dt); with continuity ρ^{n+½} = ρ^n + dt/2 Dρ, Dρ the latest rate (that of n−½: one
    /// pair loop per step, an O(dt²) difference in the mid-step pressure only).
    /// Afterwards `velocity` holds the mid-step estimate and `velocity_half` holds v^n.
    pub(crate) fn symplectic_predictor(&mut self, dt: f64) {
        let half = 0.5 * dt;
        let continuity = matches!(self.plan.density, DensityStage::Continuity { .. });
        let st = &mut self.buffers;
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
        if continuity {
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
    pub(crate) fn symplectic_corrector(&mut self, dt: f64) {
        let half = 0.5 * dt;
        let continuity = matches!(self.plan.density, DensityStage::Continuity { .. });
        let st = &mut self.buffers;
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
        if continuity {
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

    /// Non-finite and out-of-domain checks after a symplectic update.
    pub(crate) fn check_particles(&self, dt: f64) -> Result<(), SimError> {
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
}
