//! The momentum equation of a pair (Eq. 8–16).

use crate::sim::*;
use crate::sweep::{Block, CheckedList, PairInteraction, Slot, SweepSlots};
use crate::terms::PairShareBatch;

/// What the sorted force sweep reads, gathered so that its pair terms can be functions that
/// are always inlined (closures called from two places are not, and a call per pair costs
/// as much as the pair's arithmetic).
pub(crate) struct ForceSweep<'a, const D: usize> {
    pub(crate) c: PassConstants,
    /// 0.01 h² of Eq. 11.
    pub(crate) eps_h2: f64,
    pub(crate) viscous: bool,
    pub(crate) av_on: bool,
    pub(crate) pos: &'a [Vector<D>],
    pub(crate) vel: &'a [Vector<D>],
    pub(crate) rho: &'a [f64],
    pub(crate) inv_rho: &'a [f64],
    pub(crate) p: &'a [f64],
    pub(crate) strain: &'a [Tensor<D>],
    pub(crate) wall_pos: &'a [Vector<D>],
    pub(crate) wall_rho: &'a [f64],
    pub(crate) wall_inv_rho: &'a [f64],
    pub(crate) wall_p: &'a [f64],
}

/// A batch of fluid pairs of one owner: their factors ([`ForceSweep::pair_factors_batch`]),
/// and for a pass that computes its pair terms a batch at a time, the neighbours' gathered
/// values and the pairs' shares ([`crate::terms::Coupled`]).
pub(crate) struct PairBatch<const D: usize> {
    /// Squared distance r² (m²): input.
    pub(crate) r2: [f64; BATCH],
    /// ρ_i + ρ_j (kg/m³): input.
    pub(crate) rho_pair: [f64; BATCH],
    /// Distance r (m), floored as in [`ForceSweep::pair_factors`].
    pub(crate) r: [f64; BATCH],
    /// (dW/dr)/r.
    pub(crate) grad: [f64; BATCH],
    /// 1/(r² + 0.01 h²) of Eq. 11.
    pub(crate) inv_s: [f64; BATCH],
    /// 1/ρ̄ = 2/(ρ_i + ρ_j).
    pub(crate) inv_rho_mean: [f64; BATCH],
    /// The neighbours' values the pair terms read.
    pub(crate) neighbours: NeighbourBatch<D>,
    /// The pairs' shares.
    pub(crate) shares: PairShareBatch<D>,
}

impl<const D: usize> PairBatch<D> {
    pub(crate) fn new() -> Self {
        PairBatch {
            r2: [0.0; BATCH],
            rho_pair: [0.0; BATCH],
            r: [0.0; BATCH],
            grad: [0.0; BATCH],
            inv_s: [0.0; BATCH],
            inv_rho_mean: [0.0; BATCH],
            neighbours: NeighbourBatch::new(),
            shares: PairShareBatch::new(),
        }
    }

    /// The factors of pair k as [`ForceSweep::pair_factors`] returns them.
    #[inline(always)]
    pub(crate) fn get(&self, k: usize) -> (f64, f64, f64) {
        (self.grad[k], self.inv_s[k], self.inv_rho_mean[k])
    }
}

/// The fluid neighbours of a batch of pairs, one array per component and pair k, gathered by
/// index ([`ForceSweep::gather_batch`]) before the loop over the pair terms, so that this
/// loop reads consecutive values and the compiler vectorises it.
pub(crate) struct NeighbourBatch<const D: usize> {
    /// x_ij = x_i − x_j (m), per component.
    pub(crate) xij: [[f64; BATCH]; D],
    /// v_j (m/s), per component.
    pub(crate) v: [[f64; BATCH]; D],
    /// 1/ρ_j (m³/kg).
    pub(crate) inv_rho: [f64; BATCH],
    /// p_j (Pa).
    pub(crate) p: [f64; BATCH],
    /// ρ_j (kg/m³).
    pub(crate) rho: [f64; BATCH],
    /// The density of j that a density-diffusion term differences (kg/m³).
    pub(crate) rho_dyn: [f64; BATCH],
}

impl<const D: usize> NeighbourBatch<D> {
    fn new() -> Self {
        NeighbourBatch {
            xij: [[0.0; BATCH]; D],
            v: [[0.0; BATCH]; D],
            inv_rho: [0.0; BATCH],
            p: [0.0; BATCH],
            rho: [0.0; BATCH],
            rho_dyn: [0.0; BATCH],
        }
    }

    /// x_ij of pair k.
    #[inline(always)]
    pub(crate) fn xij(&self, k: usize) -> Vector<D> {
        Vector::<D>::from_fn(|d, _| self.xij[d][k])
    }

    /// Neighbour k.
    #[inline(always)]
    pub(crate) fn get(&self, k: usize) -> FluidNeighbour<D> {
        FluidNeighbour {
            v: Vector::<D>::from_fn(|d, _| self.v[d][k]),
            inv_rho: self.inv_rho[k],
            p: self.p[k],
            rho: self.rho[k],
        }
    }
}

/// What a fluid pair term reads of its neighbour j besides its position, gathered once
/// ([`ForceSweep::neighbour`], or a batch's [`NeighbourBatch`]).
#[derive(Clone, Copy)]
pub(crate) struct FluidNeighbour<const D: usize> {
    /// Velocity v_j (m/s).
    pub(crate) v: Vector<D>,
    /// 1/ρ_j (m³/kg).
    pub(crate) inv_rho: f64,
    /// Pressure p_j (Pa).
    pub(crate) p: f64,
    /// Density ρ_j (kg/m³).
    pub(crate) rho: f64,
}

/// The fluid particle i of a row of pairs in a force sweep (paper and modern steps).
pub(crate) struct ForceOwner<const D: usize> {
    pub(crate) x: Vector<D>,
    pub(crate) v: Vector<D>,
    pub(crate) rho: f64,
    pub(crate) inv_rho: f64,
    pub(crate) p: f64,
    pub(crate) strain: Tensor<D>,
}

impl<'a, const D: usize> ForceSweep<'a, D> {
    /// The sweep over `fluid` (its acceleration is not read) and `walls`.
    pub(crate) fn new(c: &PassConstants, fluid: &'a Fluid<D>, walls: &'a Walls<D>) -> Self {
        let h = c.kernel.h;
        ForceSweep {
            c: *c,
            eps_h2: 0.01 * h * h, // φ of Eq. 11
            viscous: c.viscosity > 0.0,
            av_on: c.av_alpha > 0.0 || c.av_beta > 0.0,
            pos: &fluid.position,
            vel: &fluid.velocity,
            rho: &fluid.density,
            inv_rho: &fluid.inverse_density,
            p: &fluid.pressure,
            strain: &fluid.strain_rate,
            wall_pos: &walls.position,
            wall_rho: &walls.density,
            wall_inv_rho: &walls.inverse_density,
            wall_p: &walls.pressure,
        }
    }

    /// Fluid particle i as the owner of a row of pairs.
    #[inline(always)]
    pub(crate) fn owner(&self, i: usize) -> ForceOwner<D> {
        ForceOwner {
            x: self.pos[i],
            v: self.vel[i],
            rho: self.rho[i],
            inv_rho: self.inv_rho[i],
            p: self.p[i],
            strain: self.strain[i],
        }
    }

    /// 1/r (the kernel gradient), 1/(r² + 0.01 h²) (Eq. 11) and 1/ρ̄ of a pair at squared
    /// distance r2 with ρ_i + ρ_j = rho_pair, from one division: `inv` = 1/(r s (ρ_i + ρ_j))
    /// with s = r² + 0.01 h². r is floored (far below the kernel's r = 0 cut-off) so that
    /// coincident particles give finite factors. Returns (∇W factor, 1/s, 1/ρ̄).
    #[inline(always)]
    pub(crate) fn pair_factors(&self, r2: f64, rho_pair: f64) -> (f64, f64, f64) {
        let r = r2.sqrt().max(1e-150);
        let s = r2 + self.eps_h2;
        let inv = 1.0 / (r * s * rho_pair);
        let grad_factor = self
            .c
            .kernel
            .gradient_factor_with_inverse(r, inv * (s * rho_pair));
        (grad_factor, inv * (r * rho_pair), inv * (2.0 * r * s))
    }

    /// [`Self::pair_factors`] of the first `n` pairs of a batch (r² and ρ_i + ρ_j given),
    /// bit for bit, in branch-free loops the compiler vectorises.
    #[inline(always)]
    // One index over six arrays: the form the compiler vectorises.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn pair_factors_batch(&self, n: usize, b: &mut PairBatch<D>) {
        let mut inv_r = [0.0f64; BATCH];
        for k in 0..n {
            let rk = b.r2[k].sqrt().max(1e-150);
            let s = b.r2[k] + self.eps_h2;
            let rho_pair = b.rho_pair[k];
            let inv = 1.0 / (rk * s * rho_pair);
            b.r[k] = rk;
            inv_r[k] = inv * (s * rho_pair);
            b.inv_s[k] = inv * (rk * rho_pair);
            b.inv_rho_mean[k] = inv * (2.0 * rk * s);
        }
        self.c
            .kernel
            .gradient_factors_with_inverse(&b.r[..n], &inv_r[..n], &mut b.grad[..n]);
    }

    /// The squared distances from `xi` of the fluid neighbours in `batch` (at most
    /// [`BATCH`]) into `b.r2`, for [`Self::batch_factors`].
    #[inline(always)]
    pub(crate) fn batch_distances(
        &self,
        xi: Vector<D>,
        batch: CheckedList<'_, '_>,
        b: &mut PairBatch<D>,
    ) {
        for (k, &j) in batch.indices().iter().enumerate() {
            b.r2[k] = (xi - self.pos[j as usize]).norm_squared();
        }
    }

    /// The pair factors of [`Self::pair_factors`] for the fluid neighbours `indices` (at
    /// most [`BATCH`]) of a particle of density `rho_i`, their squared distances in `b.r2`
    /// already, computed together.
    #[inline(always)]
    pub(crate) fn batch_factors(&self, rho_i: f64, indices: &[u32], b: &mut PairBatch<D>) {
        for (k, &j) in indices.iter().enumerate() {
            b.rho_pair[k] = rho_i + self.rho[j as usize];
        }
        self.pair_factors_batch(indices.len(), b);
    }

    /// What a fluid pair term reads of fluid particle j besides its position.
    #[inline(always)]
    pub(crate) fn neighbour(&self, j: usize) -> FluidNeighbour<D> {
        FluidNeighbour {
            v: self.vel[j],
            inv_rho: self.inv_rho[j],
            p: self.p[j],
            rho: self.rho[j],
        }
    }

    /// The neighbours `indices` (at most [`BATCH`]) of a particle at `xi` into `b`: x_ij,
    /// [`Self::neighbour`] and the density `rho_dyn(j)` a diffusion term differences.
    #[inline(always)]
    pub(crate) fn gather_batch(
        &self,
        xi: Vector<D>,
        indices: &[u32],
        rho_dyn: impl Fn(usize) -> f64,
        b: &mut NeighbourBatch<D>,
    ) {
        for (k, &j) in indices.iter().enumerate() {
            let j = j as usize;
            let xij = xi - self.pos[j];
            let nb = self.neighbour(j);
            for d in 0..D {
                b.xij[d][k] = xij[d];
                b.v[d][k] = nb.v[d];
            }
            b.inv_rho[k] = nb.inv_rho;
            b.p[k] = nb.p;
            b.rho[k] = nb.rho;
            b.rho_dyn[k] = rho_dyn(j);
        }
    }

    /// Eq. 10: Π_ij = (−α c̄ φ + β φ²)/ρ̄ for approaching pairs, 0 otherwise. Without a
    /// branch: a receding pair has φ = 0 and so Π = 0.
    #[inline(always)]
    pub(crate) fn artificial_viscosity(
        &self,
        vij: Vector<D>,
        xij: Vector<D>,
        inv_s: f64,
        inv_rho_mean: f64,
    ) -> f64 {
        let c = &self.c;
        let v_dot_x = vij.dot(&xij).min(0.0);
        let phi = c.kernel.h * v_dot_x * inv_s; // Eq. 11
        (-c.av_alpha * c.av_sound_speed * phi + c.av_beta * phi * phi) * inv_rho_mean
    }

    /// The acceleration of i from fluid particle j within the support (Eq. 8–9), at
    /// x_ij = x_i − x_j, with the pair's factors (∇W factor, 1/s, 1/ρ̄) of
    /// [`Self::pair_factors`]: added to i, subtracted from j.
    #[inline(always)]
    pub(crate) fn fluid_term_with(
        &self,
        o: &ForceOwner<D>,
        j: usize,
        xij: Vector<D>,
        (grad_factor, inv_s, inv_rho_mean): (f64, f64, f64),
    ) -> Vector<D> {
        let c = &self.c;
        let m = c.mass;
        let grad_w = xij * grad_factor;
        let inv_rho_ij = o.inv_rho * self.inv_rho[j];
        // Pressure part of (σ_i + σ_j)/(ρ_i ρ_j) ∇W (Eq. 8).
        let mut scalar = -(o.p + self.p[j]) * inv_rho_ij;
        if self.av_on {
            scalar -= self.artificial_viscosity(o.v - self.vel[j], xij, inv_s, inv_rho_mean);
        }
        let mut term = grad_w * (m * scalar);
        if self.viscous {
            term += self.viscous_stress(o, j, grad_w, inv_rho_ij);
        }
        term
    }

    /// The viscous part of Eq. 8 for fluid particles i (`o`) and j, m μ (V_i + V_j)/(ρ_i ρ_j)
    /// ∇_i W_ij (m/s²), with ∇_i W_ij = `grad_w` and 1/(ρ_i ρ_j) = `inv_rho_ij`.
    #[inline(always)]
    pub(crate) fn viscous_stress(
        &self,
        o: &ForceOwner<D>,
        j: usize,
        grad_w: Vector<D>,
        inv_rho_ij: f64,
    ) -> Vector<D> {
        let c = &self.c;
        (o.strain + self.strain[j]) * grad_w * (c.mass * c.viscosity * inv_rho_ij)
    }

    /// The factors of the pair of fluid particle `o` and wall particle `w` at x_iw = x_i − x_w
    /// and squared distance r2 (m²) that every wall term builds on.
    #[inline(always)]
    pub(crate) fn wall_pair_factors(
        &self,
        o: &ForceOwner<D>,
        w: usize,
        xiw: Vector<D>,
        r2: f64,
    ) -> WallPairFactors<D> {
        let (f, inv_s, inv_rho_mean) = self.pair_factors(r2, o.rho + self.wall_rho[w]);
        WallPairFactors {
            grad_w: xiw * f,
            f,
            inv_s,
            inv_rho_mean,
            inv_rho_iw: o.inv_rho * self.wall_inv_rho[w],
        }
    }

    /// The acceleration of i from wall particle w within the support, at x_iw = x_i − x_w and
    /// squared distance r2 (m²): Eq. 8 with σ_w = −p_w I and the wall at rest in the
    /// artificial viscosity (`with_av`), and the fluid's own viscous stress against the wall
    /// (`with_viscous`). Returns the acceleration and the pair's factors, for the terms that
    /// build on them.
    #[inline(always)]
    pub(crate) fn wall_momentum(
        &self,
        o: &ForceOwner<D>,
        w: usize,
        xiw: Vector<D>,
        r2: f64,
        with_av: bool,
        with_viscous: bool,
    ) -> (Vector<D>, WallPairFactors<D>) {
        let c = &self.c;
        let m = c.mass;
        let k = self.wall_pair_factors(o, w, xiw, r2);
        let mut scalar = -(o.p + self.wall_p[w]) * k.inv_rho_iw;
        if with_av {
            scalar -= self.artificial_viscosity(o.v, xiw, k.inv_s, k.inv_rho_mean);
        }
        let mut term = k.grad_w * (m * scalar);
        if with_viscous {
            term += o.strain * k.grad_w * (m * c.viscosity * k.inv_rho_iw);
        }
        (term, k)
    }
}

/// The factors of a fluid–wall pair (i, w) that the wall terms share.
pub(crate) struct WallPairFactors<const D: usize> {
    /// ∇_i W_iw (1/m³ in 2D per metre of depth, 1/m⁴ in 3D).
    pub(crate) grad_w: Vector<D>,
    /// (dW/dr)/r.
    pub(crate) f: f64,
    /// 1/(r² + 0.01 h²) of Eq. 11 (1/m²).
    pub(crate) inv_s: f64,
    /// 1/ρ̄ of Eq. 10 (m³/kg).
    pub(crate) inv_rho_mean: f64,
    /// 1/(ρ_i ρ_w) (m⁶/kg²).
    pub(crate) inv_rho_iw: f64,
}

/// The momentum equation alone (Eq. 8–16) as a pass over pairs: the paper's force pass.
/// Dynamic wall particles enter as fluid particles at rest (paper §2.5).
pub(crate) struct Momentum<'a, 'id, const D: usize> {
    terms: ForceSweep<'a, D>,
    acceleration: SweepSlots<'a, 'id, Vector<D>>,
    body_force: Vector<D>,
}

impl<'a, 'id, const D: usize> Momentum<'a, 'id, D> {
    /// The pass over `fluid` and `walls` writing `acceleration` (m/s²), with the body force
    /// (gravity and the ground acceleration's inertia force) added to every particle. A half
    /// sweep adds to `acceleration`, which must hold the body force already.
    pub(crate) fn new(
        c: &PassConstants,
        fluid: &'a Fluid<D>,
        walls: &'a Walls<D>,
        acceleration: SweepSlots<'a, 'id, Vector<D>>,
        body_force: Vector<D>,
    ) -> Self {
        Momentum {
            terms: ForceSweep::new(c, fluid, walls),
            acceleration,
            body_force,
        }
    }
}

impl<'a, 'id, const D: usize> PairInteraction<'a, 'id, D> for Momentum<'a, 'id, D> {
    type Owner = ForceOwner<D>;
    type Sums = Vector<D>;

    #[inline(always)]
    fn momentum(&self) -> &ForceSweep<'a, D> {
        &self.terms
    }

    #[inline(always)]
    fn owner(&self, i: usize) -> (ForceOwner<D>, Vector<D>, f64) {
        let o = self.terms.owner(i);
        let (x, rho) = (o.x, o.rho);
        (o, x, rho)
    }

    #[inline(always)]
    fn start(&self, _: &ForceOwner<D>, _: bool) -> Vector<D> {
        Vector::<D>::zeros()
    }

    #[inline(always)]
    fn itself(&self, _: &ForceOwner<D>, _: &mut Vector<D>) {}

    #[inline(always)]
    fn fluid_pair(
        &self,
        o: &ForceOwner<D>,
        acc: &mut Vector<D>,
        j: usize,
        xij: Vector<D>,
        _r: f64,
        factors: (f64, f64, f64),
        j_slot: Option<Slot<'_, 'id>>,
    ) {
        // Antisymmetric: ∇_j W_ji = −∇_i W_ij, every other factor symmetric in i and j.
        let term = self.terms.fluid_term_with(o, j, xij, factors);
        *acc += term;
        if let Some(slot) = j_slot {
            self.acceleration.sub(&slot, term);
        }
    }

    #[inline(always)]
    fn wall_pair(&self, o: &ForceOwner<D>, acc: &mut Vector<D>, w: usize, xiw: Vector<D>, r2: f64) {
        let t = &self.terms;
        *acc += t.wall_momentum(o, w, xiw, r2, t.av_on, t.viscous).0;
    }

    #[inline(always)]
    fn finish<const HALF: bool>(&self, i: usize, acc: Vector<D>, block: &Block<'id>) {
        if HALF {
            self.acceleration.add(&block.slot(i), acc);
        } else {
            self.acceleration.set(&block.slot(i), acc + self.body_force);
        }
    }
}
