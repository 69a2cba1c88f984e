//! The two drivers of the force-type passes: the half sweep over cell-sorted blocks (each
//! fluid pair once, its share for the second particle scattered) and the full sweep (each
//! pair from both of its particles). A pass is a [`PairInteraction`]: what a particle owns,
//! what a fluid pair and a wall pair add; the drivers decide which pairs it sees and in
//! which order.

use super::{
    colour_sweep, forward_pairs_batched, split_walls, Block, CheckedList, ForwardPairBatch, Slot,
    Sweep,
};
use crate::neighbours::{CellGrid, NeighbourSearch};
use crate::sim::{NeighbourLists, Vector, BATCH, LIST_OVERFLOW, PAR_CHUNK, WALL_NEIGHBOUR};
use crate::terms::{ForceSweep, PairBatch};
use rayon::prelude::*;

/// The terms of a pass over pairs, composed per scheme, evaluated by [`half_sweep`] and
/// [`full_sweep`].
pub(crate) trait PairInteraction<'a, 'id, const D: usize>: Sync {
    /// What a particle reads of itself once per row of pairs.
    type Owner;
    /// Its running sums over its pairs.
    type Sums;

    /// The momentum terms and the arrays they read (positions, densities, pair factors).
    fn momentum(&self) -> &ForceSweep<'a, D>;
    /// Fluid particle `i` as the owner of a row of pairs, with its position and density.
    fn owner(&self, i: usize) -> (Self::Owner, Vector<D>, f64);
    /// The sums before any pair; with `itself`, including the particle's own share (r = 0).
    fn start(&self, owner: &Self::Owner, itself: bool) -> Self::Sums;
    /// The particle's own share, where a full sweep meets it among its candidates.
    fn itself(&self, owner: &Self::Owner, sums: &mut Self::Sums);
    /// A fluid pair (i, j) within the support, at x_ij = x_i − x_j, distance `r` (m), with
    /// the pair factors of [`ForceSweep::pair_factors`]: i's share to `sums`; with j's slot
    /// (`j_slot`, the half sweep) also j's share, to that slot.
    #[allow(clippy::too_many_arguments)]
    fn fluid_pair(
        &self,
        owner: &Self::Owner,
        sums: &mut Self::Sums,
        j: usize,
        xij: Vector<D>,
        r: f64,
        factors: (f64, f64, f64),
        j_slot: Option<Slot<'_, 'id>>,
    );
    /// The fluid pairs of owner i (at `xi`, density `rho_i`) in `batch` (at most [`BATCH`],
    /// within the support, their r² in `factors.r2`): each pair's shares as
    /// [`Self::fluid_pair`] with j's slot adds them, in the batch's order. By default one
    /// pair at a time; a pass may compute the batch's pair terms together.
    #[inline(always)]
    fn fluid_batch(
        &self,
        owner: &Self::Owner,
        sums: &mut Self::Sums,
        xi: Vector<D>,
        rho_i: f64,
        batch: CheckedList<'_, 'id>,
        factors: &mut PairBatch<D>,
    ) {
        let m = self.momentum();
        m.batch_factors(rho_i, batch.indices(), factors);
        for (k, (j, slot)) in batch.iter().enumerate() {
            let xij = xi - m.pos[j];
            self.fluid_pair(
                owner,
                sums,
                j,
                xij,
                factors.r[k],
                factors.get(k),
                Some(slot),
            );
        }
    }

    /// A pair of fluid particle i and wall particle `w` within the support, at
    /// x_iw = x_i − x_w, squared distance `r2` (m²).
    fn wall_pair(
        &self,
        owner: &Self::Owner,
        sums: &mut Self::Sums,
        w: usize,
        xiw: Vector<D>,
        r2: f64,
    );
    /// Writes i's sums: added to the shares the half sweep scattered (`HALF`), or set.
    fn finish<const HALF: bool>(&self, i: usize, sums: Self::Sums, block: &Block<'id>);
}

/// A fluid pair found by a search or a forward range: its pair factors computed on their own.
// The pair's operands are passed one by one, as the inner loop holds them.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn unbatched_pair<'a, 'id, const D: usize, P: PairInteraction<'a, 'id, D>, const HALF: bool>(
    p: &P,
    owner: &P::Owner,
    sums: &mut P::Sums,
    rho_i: f64,
    j: usize,
    xij: Vector<D>,
    r2: f64,
    block: &Block<'id>,
) {
    let m = p.momentum();
    let factors = m.pair_factors(r2, rho_i + m.rho[j]);
    let j_slot = HALF.then(|| block.slot(j));
    p.fluid_pair(owner, sums, j, xij, r2.sqrt().max(1e-150), factors, j_slot);
}

/// The fluid pairs of owner i that the half sweep finds in the grid, fed to the interaction a
/// batch at a time ([`forward_pairs_batched`]).
struct GridPairs<'s, 'a, 'id, const D: usize, P: PairInteraction<'a, 'id, D>> {
    p: &'s P,
    owner: &'s P::Owner,
    sums: &'s mut P::Sums,
    factors: &'s mut PairBatch<D>,
    block: &'s Block<'id>,
    xi: Vector<D>,
    rho_i: f64,
}

impl<'a, 'id, const D: usize, P: PairInteraction<'a, 'id, D>> ForwardPairBatch
    for GridPairs<'_, 'a, 'id, D, P>
{
    #[inline(always)]
    fn batch(&mut self, batch_j: &[u32], batch_r2: &[f64]) {
        let GridPairs {
            p,
            owner,
            sums,
            factors,
            block,
            xi,
            rho_i,
        } = self;
        let list = block.check_list(batch_j);
        factors.r2[..batch_r2.len()].copy_from_slice(batch_r2);
        p.fluid_batch(owner, sums, *xi, *rho_i, list, factors);
    }
}

/// Every pair once over the cell-sorted fluid cut into `blocks` (see [`colour_sweep`]):
/// each particle takes the pairs of the forward half of its stencil and its wall
/// neighbours, from `lists` (the half lists of a sweep on the same positions, their pair
/// factors computed a batch at a time) or, without lists or for a particle whose list
/// overflowed, from the grid. `sweep` covers the fluid particles.
pub(crate) fn half_sweep<'a, 'id, const D: usize, P: PairInteraction<'a, 'id, D>>(
    sweep: Sweep<'id>,
    grid: &CellGrid<D>,
    blocks: &[u32],
    lists: Option<&NeighbourLists>,
    support_sq: f64,
    p: &P,
) {
    let m = p.momentum();
    let (pos, wall_pos) = (m.pos, m.wall_pos);
    colour_sweep(sweep, blocks, |block| {
        let mut batch = PairBatch::new();
        for i in block.begin..block.end {
            let (o, xi, rho_i) = p.owner(i);
            let mut sums = p.start(&o, true);
            let listed = lists.and_then(|l| {
                let count = l.count[i];
                (count != LIST_OVERFLOW).then(|| {
                    let first = l.start[i] as usize;
                    split_walls(&l.entries[first..first + count as usize])
                })
            });
            if let Some((fluid_list, wall_list)) = listed {
                // The listed pairs are within the support (tested by the sweep that listed
                // them, on the same positions).
                for chunk in block.check_list(fluid_list).chunks(BATCH) {
                    m.batch_distances(xi, chunk, &mut batch);
                    p.fluid_batch(&o, &mut sums, xi, rho_i, chunk, &mut batch);
                }
                for &entry in wall_list {
                    let w = (entry & !WALL_NEIGHBOUR) as usize;
                    let xiw = xi - wall_pos[w];
                    p.wall_pair(&o, &mut sums, w, xiw, xiw.norm_squared());
                }
            } else {
                // The forward candidates within the support, a batch at a time, in the grid's
                // order: their pair factors are computed together as for listed pairs.
                let mut pairs = GridPairs {
                    p,
                    owner: &o,
                    sums: &mut sums,
                    factors: &mut batch,
                    block,
                    xi,
                    rho_i,
                };
                forward_pairs_batched(grid, pos, i, support_sq, &mut pairs);
                grid.for_each_wall_candidate(&xi, |w| {
                    let xiw = xi - wall_pos[w];
                    let r2 = xiw.norm_squared();
                    if r2 < support_sq {
                        p.wall_pair(&o, &mut sums, w, xiw, r2);
                    }
                });
            }
            p.finish::<true>(i, sums, block);
        }
    });
}

/// Every pair from both of its particles, each adding its own share: the candidates of
/// `search`, or the lists a density pass filled on the same positions (`lists`: the same
/// neighbours in the same order as a search).
pub(crate) fn full_sweep<
    'a,
    'id,
    const D: usize,
    S: NeighbourSearch<D>,
    P: PairInteraction<'a, 'id, D>,
>(
    sweep: Sweep<'id>,
    search: &S,
    lists: Option<&NeighbourLists>,
    support_sq: f64,
    p: &P,
) {
    let m = p.momentum();
    let (pos, wall_pos) = (m.pos, m.wall_pos);
    (0..pos.len())
        .into_par_iter()
        .with_min_len(PAR_CHUNK)
        .for_each(|i| {
            // The particle's own slot: the only one a full sweep writes for it.
            let block = sweep.single(i);
            let (o, xi, rho_i) = p.owner(i);
            let mut sums = p.start(&o, false);
            let fluid_pair = |sums: &mut P::Sums, j: usize| {
                if j == i {
                    p.itself(&o, sums);
                    return;
                }
                let xij = xi - pos[j];
                let r2 = xij.norm_squared();
                if r2 < support_sq {
                    unbatched_pair::<D, P, false>(p, &o, sums, rho_i, j, xij, r2, &block);
                }
            };
            let wall_pair = |sums: &mut P::Sums, w: usize| {
                let xiw = xi - wall_pos[w];
                let r2 = xiw.norm_squared();
                if r2 < support_sq {
                    p.wall_pair(&o, sums, w, xiw, r2);
                }
            };
            let listed = lists.and_then(|l| {
                let count = l.count[i];
                let first = i * l.capacity;
                (count != LIST_OVERFLOW).then(|| &l.entries[first..first + count as usize])
            });
            if let Some(list) = listed {
                for &entry in list {
                    if entry & WALL_NEIGHBOUR == 0 {
                        fluid_pair(&mut sums, entry as usize);
                    } else {
                        wall_pair(&mut sums, (entry & !WALL_NEIGHBOUR) as usize);
                    }
                }
            } else {
                search.for_each_fluid_candidate(&xi, |j| fluid_pair(&mut sums, j));
                search.for_each_wall_candidate(&xi, |w| wall_pair(&mut sums, w));
            }
            p.finish::<false>(i, sums, &block);
        });
}
