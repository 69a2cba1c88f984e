//! Density terms: summation at a wall particle (Eq. 19).

use crate::neighbours::NeighbourSearch;
use crate::sim::*;

/// Eq. 19 at a wall particle at `xw`: the density sum Σ m W and the kernel sum Σ (m/ρ) W
/// over fluid and wall neighbours, and the nearest fluid particle within the support
/// (squared distance, index; u32::MAX when none).
#[inline(always)]
pub(crate) fn wall_summation<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    xw: &Vector<D>,
    fluid_pos: &[Vector<D>],
    fluid_inv_rho: &[f64],
    wall_pos: &[Vector<D>],
    wall_inv_rho: &[f64],
) -> (f64, f64, (f64, u32)) {
    let (kernel, m) = (c.kernel, c.mass);
    let mut rho_sum = 0.0;
    let mut kernel_sum = 0.0;
    let mut nearest = (f64::INFINITY, u32::MAX);
    search.for_each_fluid_candidate(xw, |j| {
        let r2 = (xw - fluid_pos[j]).norm_squared();
        if r2 < c.support_sq {
            let w = kernel.value(r2.sqrt());
            rho_sum += m * w;
            kernel_sum += m * fluid_inv_rho[j] * w;
            if r2 < nearest.0 {
                nearest = (r2, j as u32);
            }
        }
    });
    search.for_each_wall_candidate(xw, |k| {
        let r2 = (xw - wall_pos[k]).norm_squared();
        if r2 < c.support_sq {
            let w = kernel.value(r2.sqrt());
            rho_sum += m * w;
            kernel_sum += m * wall_inv_rho[k] * w;
        }
    });
    (rho_sum, kernel_sum, nearest)
}
