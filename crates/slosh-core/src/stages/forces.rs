//! The force pass: momentum (Eq. 8–16), with continuity, diffusion and shifting sums.

use crate::neighbours::{CellGrid, NeighbourSearch};
use crate::sim::*;
use crate::sweep::*;
use crate::terms::*;
use rayon::prelude::*;

/// Force pass: Eq. 8–9 with the Newtonian stress σ = −p I + μ V (Eq. 3) and Monaghan's
/// artificial viscosity (Eq. 10–16), plus the body force.
pub(crate) fn force_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    body_force: Vector<D>,
) {
    // The acceleration leaves the fluid while the sweep reads the rest of it (no allocation:
    // an empty Vec stands in).
    let mut acceleration = std::mem::take(&mut fluid.acceleration);
    let sweep = ForceSweep::new(c, fluid, walls);
    let support_sq = c.support_sq;
    let lists = &fluid.neighbours;
    let capacity = lists.capacity;
    acceleration
        .par_iter_mut()
        .enumerate()
        .with_min_len(PAR_CHUNK)
        .for_each(|(i, acc_out)| {
            let s = &sweep;
            let o = s.owner(i);
            let mut acc = Vector::<D>::zeros();
            // Every pair seen from both sides, each side adding its own share (Eq. 8–16).
            let fluid_pair = |acc: &mut Vector<D>, j: usize| {
                let xij = o.x - s.pos[j];
                let r2 = xij.norm_squared();
                if j != i && r2 < support_sq {
                    *acc += s.fluid_term(&o, j, xij, r2);
                }
            };
            let wall_pair = |acc: &mut Vector<D>, w: usize| {
                let xiw = o.x - s.wall_pos[w];
                let r2 = xiw.norm_squared();
                if r2 < support_sq {
                    *acc += s.wall_term(&o, w, xiw, r2);
                }
            };
            let count = lists.count[i];
            if count != LIST_OVERFLOW {
                // The density pass's list: the same neighbours in the same order as a search.
                for &entry in &lists.entries[i * capacity..i * capacity + count as usize] {
                    if entry & WALL_NEIGHBOUR == 0 {
                        fluid_pair(&mut acc, entry as usize);
                    } else {
                        wall_pair(&mut acc, (entry & !WALL_NEIGHBOUR) as usize);
                    }
                }
            } else {
                search.for_each_fluid_candidate(&o.x, |j| fluid_pair(&mut acc, j));
                search.for_each_wall_candidate(&o.x, |w| wall_pair(&mut acc, w));
            }
            *acc_out = acc + body_force;
        });
    fluid.acceleration = acceleration;
}

/// Force pass (Eq. 8–16, as [`force_pass`]) on cell-sorted fluid arrays with the half lists
/// of [`density_pass_sorted`]: the fluid pair term is antisymmetric (∇_j W_ji = −∇_i W_ij,
/// every other factor symmetric in i and j), so each pair is evaluated once and added to i
/// and subtracted from j.
pub(crate) fn force_pass_sorted<const D: usize>(
    grid: &CellGrid<D>,
    blocks: &[u32],
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    body_force: Vector<D>,
) {
    // The acceleration leaves the fluid while the sweep reads the rest of it (no allocation:
    // an empty Vec stands in).
    let mut acceleration = std::mem::take(&mut fluid.acceleration);
    let sweep = ForceSweep::new(c, fluid, walls);
    let support_sq = c.support_sq;
    let list_entries = fluid.neighbours.entries.as_slice();
    let list_count = fluid.neighbours.count.as_slice();
    let list_start = fluid.neighbours.start.as_slice();
    acceleration
        .par_iter_mut()
        .with_min_len(PAR_CHUNK)
        .for_each(|a| *a = body_force);
    let acc_shared = SharedSlice::new(&mut acceleration);
    colour_sweep(blocks, |_, begin, end| {
        let s = &sweep;
        let (pos, wall_pos) = (s.pos, s.wall_pos);
        let mut batch = PairFactorBatch::new();
        for i in begin..end {
            let o = s.owner(i);
            let xi = o.x;
            let mut acc = Vector::<D>::zeros();
            let count = list_count[i];
            if count != LIST_OVERFLOW {
                // The listed pairs are within the support (tested by the density sweep on
                // the same positions).
                let first = list_start[i] as usize;
                let (fluid_list, wall_list) =
                    split_walls(&list_entries[first..first + count as usize]);
                s.for_each_listed_pair(xi, o.rho, fluid_list, &mut batch, |j, xij, _, f| {
                    let term = s.fluid_term_with(&o, j, xij, f);
                    acc += term;
                    // SAFETY: j is in this block or the next (colour_blocks).
                    unsafe {
                        *acc_shared.at(j) -= term;
                    }
                });
                for &entry in wall_list {
                    let w = (entry & !WALL_NEIGHBOUR) as usize;
                    let xiw = xi - wall_pos[w];
                    acc += s.wall_term(&o, w, xiw, xiw.norm_squared());
                }
            } else {
                grid.for_each_forward_range(i, &xi, |j0, j1| {
                    for (j, xj) in (j0..j1).zip(&pos[j0..j1]) {
                        let xij = xi - xj;
                        let r2 = xij.norm_squared();
                        if r2 < support_sq {
                            let term = s.fluid_term(&o, j, xij, r2);
                            acc += term;
                            // SAFETY: as above.
                            unsafe {
                                *acc_shared.at(j) -= term;
                            }
                        }
                    }
                });
                grid.for_each_wall_candidate(&xi, |w| {
                    let xiw = xi - wall_pos[w];
                    let r2 = xiw.norm_squared();
                    if r2 < support_sq {
                        acc += s.wall_term(&o, w, xiw, r2);
                    }
                });
            }
            // SAFETY: slot i belongs to this block.
            unsafe {
                *acc_shared.at(i) += acc;
            }
        }
    });
    fluid.acceleration = acceleration;
}

/// The arrays the modern force pass writes, taken out of the fluid and the state while the
/// pair terms read the rest (no allocation: empty Vecs stand in until [`Self::restore`]).
pub(crate) struct ForceOutputs<const D: usize> {
    pub(crate) acceleration: Vec<Vector<D>>,
    pub(crate) density_rate: Vec<f64>,
    pub(crate) shift_gradient: Vec<Vector<D>>,
    pub(crate) shift_kernel_sum: Vec<f64>,
}

impl<const D: usize> ForceOutputs<D> {
    pub(crate) fn take(fluid: &mut Fluid<D>, st: &mut StageBuffers<D>) -> Self {
        ForceOutputs {
            acceleration: std::mem::take(&mut fluid.acceleration),
            density_rate: std::mem::take(&mut fluid.density_rate),
            shift_gradient: std::mem::take(&mut st.shift_gradient),
            shift_kernel_sum: std::mem::take(&mut st.shift_kernel_sum),
        }
    }

    pub(crate) fn restore(self, fluid: &mut Fluid<D>, st: &mut StageBuffers<D>) {
        fluid.acceleration = self.acceleration;
        fluid.density_rate = self.density_rate;
        st.shift_gradient = self.shift_gradient;
        st.shift_kernel_sum = self.shift_kernel_sum;
    }
}

/// Force pass of the modern step: the momentum equation of the paper (Eq. 8–16) with the
/// wall treatment chosen, and in the same pair loop the continuity equation
/// dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (Monaghan 1992; walls at rest) with the δ-SPH
/// diffusion term (Molteni & Colagrossi 2009; Fourtakas et al. 2019), and the shifting
/// gradient ∇C_i = Σ_j V_j ∇_i W_ij. Every pair is seen from both of its particles.
pub(crate) fn modern_force_pass<const D: usize, S: NeighbourSearch<D>>(
    search: &S,
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    st: &mut StageBuffers<D>,
    body_force: Vector<D>,
) {
    let shifting = st.k.shifting.is_some();
    let w0 = c.kernel.value(0.0);
    let mut out = ForceOutputs::take(fluid, st);
    {
        let terms = ModernPairTerms::new(c, fluid, walls, st);
        let pair_loop =
            |i: usize, acc_out: &mut Vector<D>, drho_out: &mut f64| -> (Vector<D>, f64) {
                let t = &terms;
                let o = t.owner(i);
                let mut sums = OwnerSums::new(0.0);
                search.for_each_fluid_candidate(&o.f.x, |j| {
                    if j == i {
                        if shifting {
                            sums.ksum += o.volume * w0;
                        }
                        return;
                    }
                    let xij = o.f.x - t.base.pos[j];
                    let r2 = xij.norm_squared();
                    if r2 < c.support_sq {
                        sums.add_fluid(&t.fluid_pair_at(&o, j, xij, r2), shifting);
                    }
                });
                search.for_each_wall_candidate(&o.f.x, |w| {
                    if let Some(wall) = t.wall_term(&o.f, w) {
                        sums.add_wall(&wall);
                    }
                });
                *acc_out = sums.acc + body_force;
                *drho_out = sums.drho;
                (sums.grad_c, sums.ksum)
            };
        if shifting {
            out.acceleration
                .par_iter_mut()
                .zip(out.density_rate.par_iter_mut())
                .zip(out.shift_gradient.par_iter_mut())
                .zip(out.shift_kernel_sum.par_iter_mut())
                .enumerate()
                .with_min_len(PAR_CHUNK)
                .for_each(|(i, (((acc, drho), g), ks))| {
                    (*g, *ks) = pair_loop(i, acc, drho);
                });
        } else {
            out.acceleration
                .par_iter_mut()
                .zip(out.density_rate.par_iter_mut())
                .enumerate()
                .with_min_len(PAR_CHUNK)
                .for_each(|(i, (acc, drho))| {
                    pair_loop(i, acc, drho);
                });
        }
    }
    out.restore(fluid, st);
}


/// The slots of the sorted modern force sweep that a fluid pair writes for its second
/// particle j.
pub(crate) struct PairScatter<'a, const D: usize> {
    pub(crate) acc: &'a SharedSlice<Vector<D>>,
    pub(crate) drho: &'a SharedSlice<f64>,
    pub(crate) grad_c: &'a SharedSlice<Vector<D>>,
    pub(crate) ksum: &'a SharedSlice<f64>,
    pub(crate) shifting: bool,
}

impl<const D: usize> PairScatter<'_, D> {
    /// A fluid pair's shares: i's to its sums, j's to j's slots.
    #[inline(always)]
    pub(crate) fn add(&self, sums: &mut OwnerSums<D>, o: &ModernOwner<D>, j: usize, pair: &FluidPairTerm<D>) {
        sums.add_fluid(pair, self.shifting);
        // SAFETY (all four): j is in this block or the next (colour_blocks).
        unsafe {
            *self.acc.at(j) -= pair.acc;
            *self.drho.at(j) += pair.drho_j;
            if self.shifting {
                *self.grad_c.at(j) -= pair.grad_w * o.volume;
                *self.ksum.at(j) += o.volume * pair.w;
            }
        }
    }
}

/// The force pass of the modern step (as [`modern_force_pass`]) on cell-sorted arrays,
/// each fluid pair once: the momentum term and the shifting gradient are antisymmetric in
/// i and j (∇_j W_ji = −∇_i W_ij), the continuity term m (v_i − v_j)·∇_i W_ij symmetric, and
/// the diffusion term of j is that of i with i and j exchanged. With `lists` (the strain
/// sweep's, of these positions) the pairs come from the lists, their factors in vectorised
/// batches; otherwise, or for a particle whose list overflowed, from the grid.
#[allow(clippy::too_many_arguments)]
pub(crate) fn modern_force_pass_sorted<const D: usize>(
    grid: &CellGrid<D>,
    blocks: &[u32],
    c: &PassConstants,
    fluid: &mut Fluid<D>,
    walls: &Walls<D>,
    st: &mut StageBuffers<D>,
    body_force: Vector<D>,
    lists: bool,
) {
    let shifting = st.k.shifting.is_some();
    let w0 = c.kernel.value(0.0);
    let n = fluid.position.len();
    let mut out = ForceOutputs::take(fluid, st);
    out.acceleration
        .par_iter_mut()
        .zip(out.density_rate.par_iter_mut())
        .with_min_len(PAR_CHUNK)
        .for_each(|(a, d)| {
            *a = body_force;
            *d = 0.0;
        });
    if shifting {
        out.shift_gradient
            .par_iter_mut()
            .zip(out.shift_kernel_sum.par_iter_mut())
            .with_min_len(PAR_CHUNK)
            .for_each(|(g, s)| {
                *g = Vector::<D>::zeros();
                *s = 0.0;
            });
    }
    debug_assert!(!shifting || out.shift_gradient.len() == n);
    {
        let acc_shared = SharedSlice::new(&mut out.acceleration);
        let drho_shared = SharedSlice::new(&mut out.density_rate);
        let grad_c_shared = SharedSlice::new(&mut out.shift_gradient);
        let ksum_shared = SharedSlice::new(&mut out.shift_kernel_sum);
        let terms = ModernPairTerms::new(c, fluid, walls, st);
        let list_entries = fluid.neighbours.entries.as_slice();
        let list_count = fluid.neighbours.count.as_slice();
        let list_start = fluid.neighbours.start.as_slice();
        let scatter = PairScatter {
            acc: &acc_shared,
            drho: &drho_shared,
            grad_c: &grad_c_shared,
            ksum: &ksum_shared,
            shifting,
        };
        colour_sweep(blocks, |_, begin, end| {
            let t = &terms;
            let pos = t.base.pos;
            let mut batch = PairFactorBatch::new();
            for i in begin..end {
                let o = t.owner(i);
                let xi = o.f.x;
                let mut sums = OwnerSums::new(if shifting { o.volume * w0 } else { 0.0 });
                let count = if lists { list_count[i] } else { LIST_OVERFLOW };
                if count != LIST_OVERFLOW {
                    let first = list_start[i] as usize;
                    let (fluid_list, wall_list) =
                        split_walls(&list_entries[first..first + count as usize]);
                    t.base.for_each_listed_pair(
                        xi,
                        o.f.rho,
                        fluid_list,
                        &mut batch,
                        |j, xij, r, f| {
                            scatter.add(&mut sums, &o, j, &t.fluid_pair(&o, j, xij, r, f));
                        },
                    );
                    for &entry in wall_list {
                        if let Some(wall) = t.wall_term(&o.f, (entry & !WALL_NEIGHBOUR) as usize) {
                            sums.add_wall(&wall);
                        }
                    }
                } else {
                    grid.for_each_forward_range(i, &xi, |j0, j1| {
                        for (j, xj) in (j0..j1).zip(&pos[j0..j1]) {
                            let xij = xi - xj;
                            let r2 = xij.norm_squared();
                            if r2 < c.support_sq {
                                scatter.add(&mut sums, &o, j, &t.fluid_pair_at(&o, j, xij, r2));
                            }
                        }
                    });
                    grid.for_each_wall_candidate(&xi, |w| {
                        if let Some(wall) = t.wall_term(&o.f, w) {
                            sums.add_wall(&wall);
                        }
                    });
                }
                // SAFETY: slot i belongs to this block.
                unsafe {
                    *acc_shared.at(i) += sums.acc;
                    *drho_shared.at(i) += sums.drho;
                    if shifting {
                        *grad_c_shared.at(i) += sums.grad_c;
                        *ksum_shared.at(i) += sums.ksum;
                    }
                }
            }
        });
    }
    out.restore(fluid, st);
}
