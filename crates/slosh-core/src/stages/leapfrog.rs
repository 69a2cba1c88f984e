//! Leap-frog integration (Eq. 21–22).

use crate::error::SimError;
use crate::sim::*;
use rayon::prelude::*;

impl<const D: usize> Simulation<D> {
    /// Eq. 21–22: leap-frog, v(t+dt/2) = v(t−dt/2) + dt a(t), x(t+dt) = x(t) + dt v(t+dt/2);
    /// with a variable step the kick spans (dt_prev + dt)/2. The velocity at the new integer
    /// time, needed by the viscous terms, is estimated as v(t+dt/2) + dt/2 a(t).
    pub(crate) fn integrate(&mut self, dt: f64, dt_previous: f64) -> Result<(), SimError> {
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
}
