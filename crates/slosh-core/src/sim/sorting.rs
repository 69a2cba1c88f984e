//! Re-sorting the fluid arrays along the cell order and re-indexing the neighbour search.

use crate::neighbours::NeighbourSearch;
use crate::sim::*;

impl<const D: usize> Simulation<D> {
    pub(crate) fn rebuild_search(&mut self) {
        with_search!(&mut self.search, s => s.rebuild_fluid(&self.fluid.position))
    }

    /// Re-sorts the fluid arrays along the cell order, for memory locality.
    pub(crate) fn sort_by_cell(&mut self) {
        self.sort_grid.rebuild_fluid(&self.fluid.position);
        let mut k = 0;
        let order = &mut self.order;
        self.sort_grid.for_each_sorted(|i| {
            order[k] = i as u32;
            k += 1;
        });
        let order = &self.order;
        permute(&mut self.fluid.position, order, &mut self.scratch_vec);
        permute(&mut self.fluid.velocity, order, &mut self.scratch_vec);
        permute(&mut self.fluid.velocity_half, order, &mut self.scratch_vec);
        permute(&mut self.fluid.acceleration, order, &mut self.scratch_vec);
        permute(&mut self.fluid.density, order, &mut self.scratch_f64);
        permute(
            &mut self.fluid.inverse_density,
            order,
            &mut self.scratch_f64,
        );
        permute(&mut self.fluid.pressure, order, &mut self.scratch_f64);
        permute(&mut self.fluid.kernel_sum, order, &mut self.scratch_f64);
        permute(&mut self.fluid.strain_rate, order, &mut self.scratch_tensor);
        permute(&mut self.fluid.id, order, &mut self.scratch_u32);
        if self.params.density == crate::params::DensityMethod::Continuity {
            permute(&mut self.fluid.density_rate, order, &mut self.scratch_f64);
        }
        // Wall → nearest-fluid links refer to the old order; they are recomputed in the next
        // density pass before anything reads them.
    }

    /// Sorts the fluid arrays by cell with the search grid (the arrays the paper step reads
    /// before writing: position, velocity, half-step velocity, 1/ρ and the id; the rest is
    /// recomputed from them), re-indexes the grid, zeroes the sums of the density sweep and
    /// splits the fluid into sweep blocks.
    pub(crate) fn sort_and_index(&mut self) {
        let Search::Grid(grid) = &mut self.search else {
            return;
        };
        let order = grid.sort_order(&self.fluid.position);
        let f = &mut self.fluid;
        // One parallel loop gathers the arrays into scratch buffers (the acceleration, which
        // the force pass recomputes, serves as the velocity's) and zeroes the accumulators of
        // the density sweep.
        {
            let (x, v, vh, inv, id) = (
                &f.position,
                &f.velocity,
                &f.velocity_half,
                &f.inverse_density,
                &f.id,
            );
            self.scratch_vec
                .par_iter_mut()
                .zip(f.acceleration.par_iter_mut())
                .zip(self.scratch_vec2.par_iter_mut())
                .zip(self.scratch_f64.par_iter_mut())
                .zip(self.scratch_u32.par_iter_mut())
                .zip(order.par_iter())
                .zip(self.next_density.par_iter_mut())
                .zip(f.kernel_sum.par_iter_mut())
                .zip(f.strain_rate.par_iter_mut())
                .with_min_len(PAR_CHUNK)
                .for_each(
                    |((((((((x_new, v_new), vh_new), inv_new), id_new), &o), rho), ksum), g)| {
                        let o = o as usize;
                        *x_new = x[o];
                        *v_new = v[o];
                        *vh_new = vh[o];
                        *inv_new = inv[o];
                        *id_new = id[o];
                        *rho = 0.0;
                        *ksum = 0.0;
                        *g = Tensor::<D>::zeros();
                    },
                );
        }
        std::mem::swap(&mut f.position, &mut self.scratch_vec);
        std::mem::swap(&mut f.velocity, &mut f.acceleration);
        std::mem::swap(&mut f.velocity_half, &mut self.scratch_vec2);
        std::mem::swap(&mut f.inverse_density, &mut self.scratch_f64);
        std::mem::swap(&mut f.id, &mut self.scratch_u32);
        grid.mark_sorted();
        // Blocks of ≈ n/32 particles whatever the thread count, so the order of the sums (and
        // the result) does not depend on it.
        let target = (f.position.len() / 32).max(512);
        grid.colour_blocks(target, &mut self.blocks);
    }

    /// Sorts every fluid array (and the per-particle buffers of the modern step) by cell with
    /// the search grid, re-indexes the grid and splits the fluid into sweep blocks (the modern
    /// step with the cell grid does this every step, for the pair sweeps).
    pub(crate) fn sort_all_and_index(&mut self) {
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
        if !self.buffers.density_start.is_empty() {
            permute_par(&mut self.buffers.density_start, order, sf);
        }
        grid.mark_sorted();
        let target = (f.position.len() / 32).max(512);
        grid.colour_blocks(target, &mut self.blocks);
    }
}

impl<const D: usize> Simulation<D> {
    /// Sorts the host's copy of a device's state by cell and indexes the host's search (for
    /// the wave gauges and what else reads the particles): every array the device copied back,
    /// the acceleration and dρ/dt included, since the next upload (a restore) reads them.
    pub(crate) fn sort_device_copy(&mut self) {
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
        permute_par(&mut f.position, order, sv);
        permute_par(&mut f.velocity, order, sv);
        permute_par(&mut f.velocity_half, order, sv);
        permute_par(&mut f.acceleration, order, sv);
        permute_par(&mut f.density, order, sf);
        permute_par(&mut f.inverse_density, order, sf);
        permute_par(&mut f.pressure, order, sf);
        permute_par(&mut f.density_rate, order, sf);
        permute_par(&mut f.id, order, su);
        grid.mark_sorted();
        let target = (f.position.len() / 32).max(512);
        grid.colour_blocks(target, &mut self.blocks);
    }
}

/// Reorders `values` by `order` (new[k] = old[order[k]]) through a scratch buffer.
pub(crate) fn permute<T: Copy + Send + Sync>(
    values: &mut Vec<T>,
    order: &[u32],
    scratch: &mut Vec<T>,
) {
    // The scratch vector has the right length but possibly another element type's buffer
    // is kept elsewhere; here each type has its own.
    scratch.clear();
    scratch.extend(order.iter().map(|&i| values[i as usize]));
    std::mem::swap(values, scratch);
}

/// Reorders `values` by `order` (new[k] = old[order[k]]) through a scratch buffer of the same
/// length, in parallel.
pub(crate) fn permute_par<T: Copy + Send + Sync>(
    values: &mut Vec<T>,
    order: &[u32],
    scratch: &mut Vec<T>,
) {
    debug_assert_eq!(scratch.len(), values.len());
    let source = &*values;
    scratch
        .par_iter_mut()
        .zip(order.par_iter())
        .with_min_len(4 * PAR_CHUNK)
        .for_each(|(s, &o)| *s = source[o as usize]);
    std::mem::swap(values, scratch);
}
