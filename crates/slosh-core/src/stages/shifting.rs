//! Particle shifting.

use crate::sim::*;
use rayon::prelude::*;

impl<const D: usize> Simulation<D> {
    /// Particle shifting (Lind et al. 2012; the |v| dt scaling of Skillen et al. 2013):
    /// δx_i = −A h |v_i| dt ∇C_i, capped at 0.1 dx, skipped near the free surface.
    pub(crate) fn apply_shifting(&mut self, dt: f64) {
        let st = &self.buffers;
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
}
