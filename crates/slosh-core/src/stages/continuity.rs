//! Continuity density: the strain-rate passes and the leap-frog density update.

use crate::kernel::Kernel;
use crate::neighbours::{CellGrid, NeighbourSearch};
use crate::sim::*;
use crate::sweep::*;
use crate::terms::*;
use rayon::prelude::*;

impl<const D: usize> Simulation<D> {
    /// Leap-frog with continuity density: ρ(t + dt) = ρ(t) + dt Dρ(t), then the EOS.
    pub(crate) fn continuity_euler(&mut self, dt: f64) {
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
}

/// Strain rate V of Eq. 4–5 over the fluid neighbours (the continuity path's share of the
/// paper's density pass).
pub(crate) fn strain_pass<const D: usize, S: NeighbourSearch<D>>(
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
                    grad_v += velocity_gradient_share(vel[j] - vi, grad_w, m * inv_rho[j]);
                }
            });
            // Eq. 4–5: V = G + Gᵀ − (2/3) tr(G) I.
            *strain_out = strain_rate_of(&grad_v);
        });
}

/// What the sorted strain sweep reads and writes, so that its batch evaluation is an
/// always-inlined method (a closure called from two places is compiled as a function).
pub(crate) struct StrainSweep<'a, 'id, const D: usize> {
    pub(crate) kernel: Kernel,
    pub(crate) m: f64,
    pub(crate) pos: &'a [Vector<D>],
    pub(crate) vel: &'a [Vector<D>],
    pub(crate) inv_rho: &'a [f64],
    pub(crate) grad_acc: &'a SweepSlots<'a, 'id, Tensor<D>>,
}

impl<'id, const D: usize> StrainSweep<'_, 'id, D> {
    /// A batch of pairs (i, j) within the support: (v_j − v_i) ⊗ ∇_i W_ij to i's sum and to
    /// j's, with the kernel factors of the batch from one vectorised loop.
    #[inline(always)]
    pub(crate) fn batch(
        &self,
        block: &Block<'id>,
        i: usize,
        batch_j: &[u32],
        batch_r2: &[f64],
        grad_v: &mut Tensor<D>,
    ) {
        let m = self.m;
        let (xi, vi, volume_i) = (self.pos[i], self.vel[i], m * self.inv_rho[i]);
        let mut batch_w = [0.0f64; BATCH];
        let mut batch_f = [0.0f64; BATCH];
        self.kernel
            .values_and_gradient_factors(batch_r2, &mut batch_w, &mut batch_f);
        for ((j, slot), &f) in block.check_list(batch_j).iter().zip(&batch_f) {
            let grad_w = (xi - self.pos[j]) * f;
            let outer = velocity_gradient_pair(self.vel[j] - vi, grad_w);
            *grad_v += outer * (m * self.inv_rho[j]);
            self.grad_acc.add(&slot, outer * volume_i);
        }
    }
}

/// One particle of the sorted strain sweep: its index, its neighbour list with fill and
/// overflow flag, and its velocity-gradient sum.
pub(crate) struct StrainOwner<'s, 'a, 'id, const D: usize> {
    pub(crate) sweep: &'s StrainSweep<'a, 'id, D>,
    pub(crate) block: &'s Block<'id>,
    pub(crate) i: usize,
    pub(crate) list: &'s mut [u32],
    pub(crate) fill: ListFill,
    pub(crate) grad_v: Tensor<D>,
}

impl<const D: usize> ForwardPairBatch for StrainOwner<'_, '_, '_, D> {
    #[inline(always)]
    fn batch(&mut self, batch_j: &[u32], batch_r2: &[f64]) {
        self.sweep
            .batch(self.block, self.i, batch_j, batch_r2, &mut self.grad_v);
        self.fill.append(self.list, batch_j);
    }
}

/// Strain rate V of Eq. 4–5 over the fluid neighbours (as [`strain_pass`]) on cell-sorted
/// arrays, each pair once: (v_j − v_i) ⊗ ∇_i W_ij is the same tensor seen from j. Fills the
/// half neighbour lists (forward fluid neighbours, then all wall neighbours) that the force
/// sweep of the same positions reads, as the paper's density sweep does.
pub(crate) fn strain_pass_sorted<const D: usize>(
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
    Sweep::scope(pos.len(), |sweep| {
        let grad_acc = sweep.slots(&mut fluid.strain_rate);
        let counts = sweep.slots(&mut fluid.neighbours.count);
        let starts = sweep.slots(&mut fluid.neighbours.start);
        let pairs = StrainSweep {
            kernel,
            m,
            pos,
            vel,
            inv_rho,
            grad_acc: &grad_acc,
        };
        colour_sweep_listing(
            sweep,
            blocks,
            &mut fluid.neighbours.entries,
            capacity,
            |block, region| {
                let (begin, end) = (block.begin, block.end);
                // The block's lists are packed from the start of its share of the entries (see
                // `density_pass_sorted`).
                let mut cursor = 0;
                for i in begin..end {
                    let xi = pos[i];
                    let list = &mut region[cursor..cursor + capacity];
                    let mut this = StrainOwner {
                        sweep: &pairs,
                        block,
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
                    let slot = block.slot(i);
                    grad_acc.add(&slot, grad_v);
                    counts.set(&slot, fill.stored_count());
                    starts.set(&slot, (begin * capacity + cursor) as u32);
                    cursor += fill.listed;
                }
            },
        );
    });
    // Eq. 4–5: V = G + Gᵀ − (2/3) tr(G) I.
    fluid
        .strain_rate
        .par_iter_mut()
        .with_min_len(PAR_CHUNK)
        .for_each(|g| *g = strain_rate_of(g));
}
