//! Wall models, one file each: dynamic walls (`dynamic.rs`) and Adami walls (`adami.rs`).
//! A wall model sets the density, 1/ρ and pressure of every wall particle and its nearest
//! fluid particle, from the fluid's state after the density stage; a new model is a new
//! file here and a variant of [`super::WallStage`].

mod adami;
mod dynamic;
pub(crate) use adami::*;
pub(crate) use dynamic::*;

use crate::sim::*;
use rayon::prelude::*;

/// Copies the new wall densities and pressures into the walls' state.
fn commit_wall_state<const D: usize>(walls: &mut Walls<D>, density: &[f64], pressure: &[f64]) {
    walls
        .density
        .par_iter_mut()
        .zip(walls.inverse_density.par_iter_mut())
        .zip(walls.pressure.par_iter_mut())
        .zip(density.par_iter())
        .zip(pressure.par_iter())
        .with_min_len(PAR_CHUNK)
        .for_each(|((((rho_w, inv), p_w), &r), &pn)| {
            *rho_w = r;
            *inv = 1.0 / r;
            *p_w = pn;
        });
}
