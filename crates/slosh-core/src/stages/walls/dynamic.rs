//! Dynamic walls (paper §2.5): wall particles with summation density (Eq. 19), the
//! free-surface reset (Eq. 20) and the EOS (Eq. 18), as fluid particles that do not move.
//! With summation density they are summed in the density pass itself, before the fluid's
//! EOS (`summation.rs`); this pass serves the other density models.

use crate::neighbours::NeighbourSearch;
use crate::sim::*;
use crate::stages::summation::{wall_densities, wall_eos};
use crate::terms::*;

/// Density and pressure of every wall particle from its fluid and wall neighbours, and its
/// nearest fluid particle (for the paper's load evaluation).
pub(crate) fn dynamic_walls<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &Fluid<D>,
    walls: &mut Walls<D>,
    next_wall_density: &mut [f64],
) {
    let (pos, inv_rho) = (&fluid.position, &fluid.inverse_density);
    let (wall_pos, wall_inv_rho) = (&walls.position, &walls.inverse_density);
    // Eq. 19 with the Eq. 20 reset, then Eq. 18: as in the density pass of summation density.
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
    wall_eos(c, walls, next_wall_density);
}
