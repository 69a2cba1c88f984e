//! Dynamic walls (paper §2.5): wall particles with summation density (Eq. 19), the
//! free-surface reset (Eq. 20) and the EOS (Eq. 18), as fluid particles that do not move.
//! With summation density they are summed in the density pass itself, before the fluid's
//! EOS (`summation.rs`); this pass serves the other density models.

use super::commit_wall_state;
use crate::neighbours::NeighbourSearch;
use crate::sim::*;
use crate::terms::*;
use rayon::prelude::*;

/// Density and pressure of every wall particle from its fluid and wall neighbours, and its
/// nearest fluid particle (for the paper's load evaluation).
pub(crate) fn dynamic_walls<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &Fluid<D>,
    walls: &mut Walls<D>,
    next_wall_density: &mut [f64],
    wall_pressure_next: &mut [f64],
) {
    let (pos, inv_rho) = (&fluid.position, &fluid.inverse_density);
    let (wall_pos, wall_inv_rho) = (&walls.position, &walls.inverse_density);
    next_wall_density
        .par_iter_mut()
        .zip(wall_pressure_next.par_iter_mut())
        .zip(walls.nearest_fluid.par_iter_mut())
        .enumerate()
        .with_min_len(PAR_CHUNK)
        .for_each(|(w_i, ((rho_out, p_out), nearest_out))| {
            // Eq. 19 with the Eq. 20 reset, then Eq. 18.
            let (rho_sum, kernel_sum, nearest) =
                wall_summation(search, c, &wall_pos[w_i], pos, inv_rho, wall_pos, wall_inv_rho);
            let r = if kernel_sum < c.free_surface_threshold {
                c.rest_density
            } else {
                rho_sum
            };
            *rho_out = r;
            *p_out = c.pressure(r);
            *nearest_out = nearest.1;
        });
    commit_wall_state(walls, next_wall_density, wall_pressure_next);
}
