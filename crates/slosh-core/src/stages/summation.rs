//! Summation density (Eq. 19) with the free-surface reset (Eq. 20) and the EOS (Eq. 18).

use crate::kernel::Kernel;
use crate::neighbours::{CellGrid, NeighbourSearch};
use crate::sim::*;
use crate::stages::PairSweep;
use crate::sweep::*;
use crate::terms::*;
use rayon::prelude::*;

impl<const D: usize> Simulation<D> {
    /// Summation density of the fluid (Eq. 19–20, with the strain rate of Eq. 4–5) and, with
    /// `dynamic_walls`, of the wall particles, then the EOS (Eq. 18) of what was summed.
    pub(crate) fn summation_density(&mut self, sweep: PairSweep, dynamic_walls: bool) {
        let c = self.constants;
        match (sweep, &self.search) {
            (PairSweep::Half, Search::Grid(s)) => {
                debug_assert!(dynamic_walls, "the half sweep sums the dynamic walls");
                density_pass_sorted(
                    s,
                    &self.blocks,
                    &c,
                    &mut self.fluid,
                    &mut self.walls,
                    &mut self.next_density,
                    &mut self.next_wall_density,
                    &mut self.wall_scatter,
                )
            }
            (_, search) => with_search!(search, s => density_pass(
                s,
                &c,
                &mut self.fluid,
                &mut self.walls,
                &mut self.next_density,
                &mut self.next_wall_density,
                dynamic_walls,
            )),
        }
    }
}

/// Density pass (Eq. 19, 20, 18, 5) over fluid and wall particles.
pub(crate) fn density_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &mut Walls<D>,
    next_density: &mut Vec<f64>,
    next_wall_density: &mut [f64],
    dynamic_walls: bool,
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
                            grad_v += velocity_gradient_share(vel[j] - vi, grad_w, volume);
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
    if dynamic_walls {
        wall_density_and_eos(search, c, fluid, walls, next_density, next_wall_density);
    } else {
        // The wall stage that follows sets the walls' state.
        fluid_eos(c, fluid, next_density, false);
    }
}

/// The wall half of the density pass (Eq. 19 and 20 at wall particles), then the
/// free-surface reset (Eq. 20) and the EOS (Eq. 18) of fluid and walls, once the fluid sums
/// are in `next_density` and `fluid.kernel_sum`.
pub(crate) fn wall_density_and_eos<const D: usize, S: NeighbourSearch<D>>(
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
pub(crate) fn wall_densities<F: Fn(usize) -> (f64, f64, u32) + Sync>(
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
pub(crate) fn eos_pass<const D: usize>(
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &mut Walls<D>,
    next_density: &[f64],
    next_wall_density: &[f64],
    strain_from_gradient: bool,
) {
    fluid_eos(c, fluid, next_density, strain_from_gradient);
    wall_eos(c, walls, next_wall_density);
}

/// What the fluid pairs of the sorted density sweep read and write, so that the batch
/// evaluation can be an always-inlined method (a closure called from two places is compiled
/// as a function, with its sums in memory).
pub(crate) struct DensitySweep<'a, 'id, const D: usize> {
    pub(crate) kernel: Kernel,
    pub(crate) m: f64,
    pub(crate) pos: &'a [Vector<D>],
    pub(crate) vel: &'a [Vector<D>],
    pub(crate) inv_rho: &'a [f64],
    pub(crate) rho_acc: &'a SweepSlots<'a, 'id, f64>,
    pub(crate) ksum_acc: &'a SweepSlots<'a, 'id, f64>,
    pub(crate) grad_acc: &'a SweepSlots<'a, 'id, Tensor<D>>,
}

/// The running sums of one particle in the sorted density sweep, and its list's fill.
pub(crate) struct DensitySums<const D: usize> {
    pub(crate) rho: f64,
    pub(crate) kernel_sum: f64,
    pub(crate) grad_v: Tensor<D>,
    pub(crate) fill: ListFill,
}

impl<'id, const D: usize> DensitySweep<'_, 'id, D> {
    /// Evaluates a batch of fluid pairs (i, j) within the support, `owner` = (x_i, v_i,
    /// m/ρ_i), in a loop without unpredictable branches: adds them to i's `sums` and to j's
    /// accumulators, and appends the j to i's list.
    #[inline(always)]
    pub(crate) fn batch(
        &self,
        block: &Block<'id>,
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
        for (((j, slot), &w), &grad_factor) in
            block.check_list(batch_j).iter().zip(&batch_w).zip(&batch_f)
        {
            let xij = xi - self.pos[j];
            let volume_j = m * self.inv_rho[j];
            let mw = m * w;
            rho_sum += mw;
            kernel_sum += volume_j * w;
            // (v_j − v_i) ⊗ ∇_i W_ij; for j the pair gives (v_i − v_j) ⊗ ∇_j W_ji, the same
            // tensor.
            let outer = velocity_gradient_pair(self.vel[j] - vi, xij * grad_factor);
            grad_v += outer * volume_j;
            self.rho_acc.add(&slot, mw);
            self.ksum_acc.add(&slot, volume_i * w);
            self.grad_acc.add(&slot, outer * volume_i);
        }
        (sums.rho, sums.kernel_sum, sums.grad_v) = (rho_sum, kernel_sum, grad_v);
        sums.fill.append(list, batch_j);
    }
}

/// One particle of the sorted density sweep: its data, its neighbour list and its running
/// sums.
pub(crate) struct DensityOwner<'s, 'a, 'id, const D: usize> {
    pub(crate) sweep: &'s DensitySweep<'a, 'id, D>,
    pub(crate) block: &'s Block<'id>,
    /// (x_i, v_i, m/ρ_i).
    pub(crate) owner: (Vector<D>, Vector<D>, f64),
    pub(crate) list: &'s mut [u32],
    pub(crate) sums: DensitySums<D>,
}

impl<const D: usize> ForwardPairBatch for DensityOwner<'_, '_, '_, D> {
    #[inline(always)]
    fn batch(&mut self, batch_j: &[u32], batch_r2: &[f64]) {
        self.sweep.batch(
            self.block,
            self.owner,
            batch_j,
            batch_r2,
            self.list,
            &mut self.sums,
        );
    }
}

/// Density pass (Eq. 19, 20, 18, 5) on cell-sorted fluid arrays: each fluid pair is
/// evaluated once, from the particle that finds the other in its forward half stencil, and
/// adds to both. Fills the half neighbour lists (forward fluid neighbours and all wall
/// neighbours) for [`force_pass_sorted`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn density_pass_sorted<const D: usize>(
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
    // The fluid sums start at zero (zeroed by `sort_and_index`), the wall sums too (zeroed
    // when read, below).
    {
        let pos = &fluid.position;
        let vel = &fluid.velocity;
        let inv_rho = &fluid.inverse_density;
        let wall_pos = &walls.position;
        let wall_inv_rho = &walls.inverse_density;
        let capacity = fluid.neighbours.capacity;
        Sweep::scope(pos.len(), |sweep| {
            let rho_acc = sweep.slots(next_density);
            let ksum_acc = sweep.slots(&mut fluid.kernel_sum);
            // Velocity gradient G_ab = Σ (m/ρ_j)(v_j − v_i)_a ∂W/∂x_i,b (Eq. 5 terms); turned
            // into V below.
            let grad_acc = sweep.slots(&mut fluid.strain_rate);
            let counts = sweep.slots(&mut fluid.neighbours.count);
            let starts = sweep.slots(&mut fluid.neighbours.start);
            let wall_sums = scatter.slots();
            let pairs = DensitySweep {
                kernel,
                m,
                pos,
                vel,
                inv_rho,
                rho_acc: &rho_acc,
                ksum_acc: &ksum_acc,
                grad_acc: &grad_acc,
            };
            let entries = &mut fluid.neighbours.entries;
            colour_sweep_listing(sweep, blocks, entries, capacity, |block, region| {
                let (begin, end) = (block.begin, block.end);
                // The block's lists are packed from the start of its share of the entries; a
                // particle always has room for `capacity` entries (those before it used at most
                // as many each).
                let mut cursor = 0;
                for i in begin..end {
                    let xi = pos[i];
                    let vi = vel[i];
                    let volume_i = m * inv_rho[i];
                    let list = &mut region[cursor..cursor + capacity];
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
                        sweep: &pairs,
                        block,
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
                            wall_sums.add(block, w_idx, m * w, volume_i * w, r2, i as u32);
                            fill.push(list, w_idx as u32 | WALL_NEIGHBOUR);
                        }
                    });
                    let slot = block.slot(i);
                    counts.set(&slot, fill.stored_count());
                    starts.set(&slot, (begin * capacity + cursor) as u32);
                    rho_acc.add(&slot, rho_sum);
                    ksum_acc.add(&slot, kernel_sum);
                    grad_acc.add(&slot, grad_v);
                    cursor += fill.listed;
                }
            });
        });
    }
    {
        let wall_pos = &walls.position;
        let wall_inv_rho = &walls.inverse_density;
        scatter.drain();
        wall_densities(c, next_wall_density, &mut walls.nearest_fluid, |w_i| {
            // Fluid neighbours: the sums the sweep scattered.
            let (mut rho_sum, mut kernel_sum, nearest) = scatter.total(w_i);
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

/// The free-surface reset (Eq. 20) and the EOS (Eq. 18) of the fluid from its density sums;
/// with `strain_from_gradient` the `strain_rate` holds the velocity gradient G and is turned
/// into V here.
fn fluid_eos<const D: usize>(
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    next_density: &[f64],
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
}

/// The EOS (Eq. 18) of the wall particles from their densities (Eq. 19 with the Eq. 20 reset,
/// [`wall_densities`]).
pub(crate) fn wall_eos<const D: usize>(
    c: &PassConstants,
    walls: &mut Walls<D>,
    next_wall_density: &[f64],
) {
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
