//! Adami walls: the wall pressure extrapolated from the fluid (Adami, Hu & Adams 2012,
//! Eq. 27), and with no-slip walls the mirrored wall velocity (their Eq. 22) and its share
//! of the strain rate.

use super::commit_wall_state;
use crate::neighbours::NeighbourSearch;
use crate::sim::*;
use crate::terms::*;
use rayon::prelude::*;

/// Wall pressure and density (through the inverse EOS) of every wall particle from its fluid
/// neighbours, with the body force `body_force` (m/s²) in the hydrostatic part; its nearest
/// fluid particle (for the paper's load evaluation); with `no_slip` the mirrored velocity
/// the fluid sees in `st.wall_velocity`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn adami_walls<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    inv_gamma: f64,
    no_slip: bool,
    fluid: &Fluid<D>,
    walls: &mut Walls<D>,
    next_wall_density: &mut [f64],
    st: &mut StageBuffers<D>,
    body_force: Vector<D>,
) {
    let kernel = c.kernel;
    let pos = &fluid.position;
    let vel = &fluid.velocity;
    let rho = &fluid.density;
    let p = &fluid.pressure;
    let wall_pos = &walls.position;
    let fill = |w_i: usize,
                rho_out: &mut f64,
                p_out: &mut f64,
                nearest_out: &mut u32,
                vel_out: Option<&mut Vector<D>>| {
        let xw = wall_pos[w_i];
        let mut nearest = (f64::INFINITY, u32::MAX);
        // Adami, Hu & Adams (2012) Eq. 27 (and Eq. 22 for the velocity).
        let (mut sum_w, mut sum_pw) = (0.0, 0.0);
        let mut sum_rx = Vector::<D>::zeros();
        let mut sum_v = Vector::<D>::zeros();
        search.for_each_fluid_candidate(&xw, |j| {
            let d = xw - pos[j];
            let r2 = d.norm_squared();
            if r2 < c.support_sq {
                let w = kernel.value(r2.sqrt());
                sum_w += w;
                sum_pw += p[j] * w;
                sum_rx += d * (rho[j] * w);
                if no_slip {
                    sum_v += vel[j] * w;
                }
                if r2 < nearest.0 {
                    nearest = (r2, j as u32);
                }
            }
        });
        if sum_w > 1e-12 {
            let mut pw = (sum_pw + body_force.dot(&sum_rx)) / sum_w;
            if c.clamp_negative || c.wall_separation {
                pw = pw.max(0.0);
            }
            *p_out = pw;
            *rho_out = c.density_of(pw, inv_gamma);
            if let Some(v) = vel_out {
                // No-slip: v_w = 2 v_wall − ṽ_w with the wall at rest in the tank frame.
                *v = -sum_v / sum_w;
            }
        } else {
            *p_out = 0.0;
            *rho_out = c.rest_density;
            if let Some(v) = vel_out {
                *v = Vector::<D>::zeros();
            }
        }
        *nearest_out = nearest.1;
    };
    if no_slip {
        next_wall_density
            .par_iter_mut()
            .zip(st.wall_pressure_next.par_iter_mut())
            .zip(walls.nearest_fluid.par_iter_mut())
            .zip(st.wall_velocity.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_CHUNK)
            .for_each(|(w_i, (((r, pw), nf), v))| fill(w_i, r, pw, nf, Some(v)));
    } else {
        next_wall_density
            .par_iter_mut()
            .zip(st.wall_pressure_next.par_iter_mut())
            .zip(walls.nearest_fluid.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_CHUNK)
            .for_each(|(w_i, ((r, pw), nf))| fill(w_i, r, pw, nf, None));
    }
    commit_wall_state(walls, next_wall_density, &st.wall_pressure_next);
}

/// The no-slip walls' share of the strain rate V (Eq. 4–5): the mirrored wall velocity
/// (Adami et al. 2012 Eq. 22) in the velocity gradient of the fluid particles near a wall.
/// V is linear in the gradient G, so the wall share is added to the fluid share as is.
pub(crate) fn wall_strain_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    wall_velocity: &[Vector<D>],
) {
    let kernel = c.kernel;
    let m = c.mass;
    let pos = &fluid.position;
    let vel = &fluid.velocity;
    fluid
        .strain_rate
        .par_iter_mut()
        .enumerate()
        .with_min_len(PAR_CHUNK)
        .for_each(|(i, strain_out)| {
            let xi = pos[i];
            let vi = vel[i];
            let mut grad_v = Tensor::<D>::zeros();
            search.for_each_wall_candidate(&xi, |w| {
                let xiw = xi - walls.position[w];
                let r2 = xiw.norm_squared();
                if r2 < c.support_sq {
                    let grad_w = xiw * kernel.gradient_factor(r2.sqrt());
                    grad_v += velocity_gradient_share(
                        wall_velocity[w] - vi,
                        grad_w,
                        m * walls.inverse_density[w],
                    );
                }
            });
            *strain_out += strain_rate_of(&grad_v);
        });
}
