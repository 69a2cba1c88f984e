//! Adami walls: the wall pressure extrapolated from the fluid (Adami, Hu & Adams 2012,
//! Eq. 27), and with no-slip walls the mirrored wall velocity (their Eq. 22) and its share
//! of the strain rate.

use super::commit_wall_state;
use crate::kernel::Kernel;
use crate::neighbours::NeighbourSearch;
use crate::sim::*;
use crate::terms::*;
use rayon::prelude::*;

/// Wall pressure and density (through the inverse EOS) of every wall particle from its fluid
/// neighbours, with the body force at the wall particle (m/s²) in the hydrostatic part; its nearest
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
    body: &crate::frame::BodyForce<D>,
) {
    let wall_pos = &walls.position;
    let sums_of = WallSums {
        kernel: c.kernel,
        pos: &fluid.position,
        vel: &fluid.velocity,
        rho: &fluid.density,
        p: &fluid.pressure,
        no_slip,
    };
    let fill = |w_i: usize,
                rho_out: &mut f64,
                p_out: &mut f64,
                nearest_out: &mut u32,
                vel_out: Option<&mut Vector<D>>| {
        let xw = wall_pos[w_i];
        let mut sums = WallExtrapolation::<D>::new();
        // The candidates within the support, a batch at a time in the search's order: their
        // kernel values are computed together (the sums are those of one pair at a time).
        let mut batch_j = [0u32; BATCH];
        let mut batch_r2 = [0.0f64; BATCH];
        let mut batched = 0usize;
        search.for_each_fluid_candidate(&xw, |j| {
            let r2 = (xw - sums_of.pos[j]).norm_squared();
            batch_j[batched] = j as u32;
            batch_r2[batched] = r2;
            batched += (r2 < c.support_sq) as usize;
            if batched == BATCH {
                sums_of.add(&xw, &mut sums, &batch_j, &batch_r2);
                batched = 0;
            }
        });
        sums_of.add(&xw, &mut sums, &batch_j[..batched], &batch_r2[..batched]);
        let WallExtrapolation {
            sum_w,
            sum_pw,
            sum_rx,
            sum_v,
            nearest,
        } = sums;
        if sum_w > 1e-12 {
            let mut pw = (sum_pw + body.at(&xw).dot(&sum_rx)) / sum_w;
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

/// The running sums of one wall particle's extrapolation over its fluid neighbours (Adami,
/// Hu & Adams 2012, Eq. 27 and, for no-slip walls, Eq. 22), and its nearest fluid particle.
struct WallExtrapolation<const D: usize> {
    /// Σ W_wj (1/m^D).
    sum_w: f64,
    /// Σ p_j W_wj (Pa/m^D).
    sum_pw: f64,
    /// Σ ρ_j x_wj W_wj (kg/m² per m^D; dotted with the body force in m/s², Pa per m^D).
    sum_rx: Vector<D>,
    /// Σ v_j W_wj (m/s per m^D).
    sum_v: Vector<D>,
    /// Squared distance (m²) and index of the nearest fluid particle.
    nearest: (f64, u32),
}

impl<const D: usize> WallExtrapolation<D> {
    fn new() -> Self {
        WallExtrapolation {
            sum_w: 0.0,
            sum_pw: 0.0,
            sum_rx: Vector::<D>::zeros(),
            sum_v: Vector::<D>::zeros(),
            nearest: (f64::INFINITY, u32::MAX),
        }
    }
}

/// The fluid arrays the wall extrapolation reads.
struct WallSums<'a, const D: usize> {
    kernel: Kernel,
    pos: &'a [Vector<D>],
    vel: &'a [Vector<D>],
    rho: &'a [f64],
    p: &'a [f64],
    no_slip: bool,
}

impl<const D: usize> WallSums<'_, D> {
    /// Adds the fluid particles `batch_j` at squared distances `batch_r2` (m², within the
    /// support) from the wall particle at `xw` to its sums, in the order given.
    #[inline(always)]
    fn add(
        &self,
        xw: &Vector<D>,
        sums: &mut WallExtrapolation<D>,
        batch_j: &[u32],
        batch_r2: &[f64],
    ) {
        let mut batch_w = [0.0f64; BATCH];
        self.kernel.values(batch_r2, &mut batch_w);
        for ((&j, &r2), &w) in batch_j.iter().zip(batch_r2).zip(&batch_w) {
            let j = j as usize;
            sums.sum_w += w;
            sums.sum_pw += self.p[j] * w;
            sums.sum_rx += (xw - self.pos[j]) * (self.rho[j] * w);
            if self.no_slip {
                sums.sum_v += self.vel[j] * w;
            }
            if r2 < sums.nearest.0 {
                sums.nearest = (r2, j as u32);
            }
        }
    }
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
