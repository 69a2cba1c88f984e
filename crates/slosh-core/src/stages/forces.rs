//! The force stage: the momentum equation (Eq. 8–16) alone, or coupled with the
//! continuity equation, the density diffusion and the shifting sums
//! ([`crate::terms::Momentum`], [`crate::terms::Coupled`]), over the pairs of the half or
//! the full sweep ([`crate::sweep::half_sweep`], [`crate::sweep::full_sweep`]).

use super::PairSweep;
use crate::sim::*;
use crate::sweep::{full_sweep, half_sweep};
use crate::terms::*;
use rayon::prelude::*;

impl<const D: usize> Simulation<D> {
    /// The momentum equation alone (Eq. 8–16) with the body force `body_force` (m/s²): the
    /// paper's force pass. The half sweep reads the density sweep's half lists; the full
    /// sweep the density pass's lists.
    pub(crate) fn momentum_stage(&mut self, sweep: PairSweep, body_force: Vector<D>) {
        let c = self.constants;
        // The acceleration leaves the fluid while the pass reads the rest of it (no
        // allocation: an empty Vec stands in).
        let mut acceleration = std::mem::take(&mut self.fluid.acceleration);
        match (sweep, &self.search) {
            (PairSweep::Half, Search::Grid(grid)) => {
                acceleration
                    .par_iter_mut()
                    .with_min_len(PAR_CHUNK)
                    .for_each(|a| *a = body_force);
                let pass = Momentum::new(&c, &self.fluid, &self.walls, &mut acceleration, body_force);
                half_sweep(grid, &self.blocks, Some(&self.fluid.neighbours), c.support_sq, &pass);
            }
            (_, search) => {
                let pass = Momentum::new(&c, &self.fluid, &self.walls, &mut acceleration, body_force);
                let lists = Some(&self.fluid.neighbours);
                with_search!(search, s => full_sweep(s, lists, c.support_sq, &pass));
            }
        }
        self.fluid.acceleration = acceleration;
    }

    /// The momentum equation coupled with the continuity, diffusion and shifting sums of
    /// the parts switched on. With `lists` (the strain-rate sweep's half lists of these
    /// positions) the half sweep reads its pairs from them, otherwise from the grid; the
    /// full sweep searches.
    pub(crate) fn coupled_stage(&mut self, sweep: PairSweep, lists: bool, body_force: Vector<D>) {
        let c = self.constants;
        let mut out = ForceOutputs::take(&mut self.fluid, &mut self.buffers);
        match (sweep, &self.search) {
            (PairSweep::Half, Search::Grid(grid)) => {
                out.acceleration
                    .par_iter_mut()
                    .zip(out.density_rate.par_iter_mut())
                    .with_min_len(PAR_CHUNK)
                    .for_each(|(a, d)| {
                        *a = body_force;
                        *d = 0.0;
                    });
                out.shift_gradient
                    .par_iter_mut()
                    .zip(out.shift_kernel_sum.par_iter_mut())
                    .with_min_len(PAR_CHUNK)
                    .for_each(|(g, s)| {
                        *g = Vector::<D>::zeros();
                        *s = 0.0;
                    });
                let pass = Coupled::new(&c, &self.fluid, &self.walls, &self.buffers, &mut out, body_force);
                let lists = lists.then_some(&self.fluid.neighbours);
                half_sweep(grid, &self.blocks, lists, c.support_sq, &pass);
            }
            (_, search) => {
                let pass = Coupled::new(&c, &self.fluid, &self.walls, &self.buffers, &mut out, body_force);
                with_search!(search, s => full_sweep(s, None, c.support_sq, &pass));
            }
        }
        out.restore(&mut self.fluid, &mut self.buffers);
    }
}
