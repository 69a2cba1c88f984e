//! The momentum, continuity, density-diffusion and shifting terms of one pair, evaluated together.

use crate::sim::*;
use crate::sweep::{Block, CheckedList, PairInteraction, Slot, Sweep, SweepSlots};
use crate::terms::*;

/// The density rate of the coupled pass, chosen once per run: none (summation density), or
/// the continuity equation dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (Monaghan 1992) with or
/// without a δ-SPH diffusion term.
pub(crate) trait DensityRateTerm: Sync {
    /// The continuity equation is summed.
    const CONTINUITY: bool;
    /// A diffusion term ψ_ij is added to it.
    const DIFFUSION: bool;
    /// The density of particle i the diffusion term differences, from the fluid's density
    /// `rho` and the hydrostatic density `rho_h` (kg/m³).
    fn diffused_density(rho: &[f64], rho_h: &[f64], i: usize) -> f64;
}

/// Summation density: the force pass adds no density rate.
pub(crate) struct NoDensityRate;
/// The continuity equation without diffusion.
pub(crate) struct ContinuityOnly;
/// The continuity equation with the diffusion of Molteni & Colagrossi (2009): ψ_ij
/// differences ρ_j − ρ_i.
pub(crate) struct MolteniColagrossiDiffusion;
/// The continuity equation with the diffusion of Fourtakas et al. (2019): ψ_ij differences
/// the dynamic densities ρ − ρ_H, the hydrostatic part taken out.
pub(crate) struct FourtakasDiffusion;

impl DensityRateTerm for NoDensityRate {
    const CONTINUITY: bool = false;
    const DIFFUSION: bool = false;
    #[inline(always)]
    fn diffused_density(_: &[f64], _: &[f64], _: usize) -> f64 {
        0.0
    }
}

impl DensityRateTerm for ContinuityOnly {
    const CONTINUITY: bool = true;
    const DIFFUSION: bool = false;
    #[inline(always)]
    fn diffused_density(_: &[f64], _: &[f64], _: usize) -> f64 {
        0.0
    }
}

impl DensityRateTerm for MolteniColagrossiDiffusion {
    const CONTINUITY: bool = true;
    const DIFFUSION: bool = true;
    #[inline(always)]
    fn diffused_density(rho: &[f64], _: &[f64], i: usize) -> f64 {
        rho[i]
    }
}

impl DensityRateTerm for FourtakasDiffusion {
    const CONTINUITY: bool = true;
    const DIFFUSION: bool = true;
    #[inline(always)]
    fn diffused_density(rho: &[f64], rho_h: &[f64], i: usize) -> f64 {
        rho[i] - rho_h[i]
    }
}

/// What a wall particle adds to the momentum of the coupled pass besides its pressure,
/// chosen once per run.
pub(crate) trait WallForceTerm: Sync {
    /// Dynamic walls: the wall enters the artificial viscosity (at rest) and the paper's
    /// viscous term as a fluid particle would (paper §2.5).
    const AS_FLUID: bool;
    /// No-slip Adami walls of a viscous liquid: the laminar viscous force against the
    /// mirrored wall velocity.
    const NO_SLIP_VISCOUS: bool;
}

/// Dynamic wall particles (paper §2.5).
pub(crate) struct DynamicWallForce;
/// Adami walls with free slip: pressure only.
pub(crate) struct AdamiFreeSlipForce;
/// Adami walls with no slip for a viscous liquid.
pub(crate) struct AdamiNoSlipForce;

impl WallForceTerm for DynamicWallForce {
    const AS_FLUID: bool = true;
    const NO_SLIP_VISCOUS: bool = false;
}

impl WallForceTerm for AdamiFreeSlipForce {
    const AS_FLUID: bool = false;
    const NO_SLIP_VISCOUS: bool = false;
}

impl WallForceTerm for AdamiNoSlipForce {
    const AS_FLUID: bool = false;
    const NO_SLIP_VISCOUS: bool = true;
}

/// The momentum and continuity pair of the coupled pass, chosen once per run: Eq. 8 with
/// Monaghan's continuity equation ([`Eq8Pair`]) or the Riemann-solver pair of Zhang, Hu &
/// Adams 2017 ([`crate::terms::RiemannPair`]). The density diffusion, the no-slip wall force
/// and the shifting sums are added around it by [`ModernPairTerms`].
pub(crate) trait MomentumContinuityPair<const D: usize>: Sync + Sized {
    /// The pair's constants for a run.
    fn new(c: &PassConstants) -> Self;

    /// Fluid particles i (`o`) and j (its values `nb`) at x_ij = x_i − x_j, distance `r` (m),
    /// ∇_i W_ij = `grad_w`, with the pair factors (∇W factor, 1/s, 1/ρ̄) of
    /// [`ForceSweep::pair_factors`]:
    /// the acceleration of i (m/s²; j gets its negative) and, with `continuity`, the density
    /// rates of i and of j (kg/(m³·s)).
    // The pair's operands are passed one by one, as the inner loop holds them.
    #[allow(clippy::too_many_arguments)]
    fn fluid(
        &self,
        base: &ForceSweep<'_, D>,
        o: &ForceOwner<D>,
        j: usize,
        nb: &FluidNeighbour<D>,
        xij: Vector<D>,
        r: f64,
        grad_w: Vector<D>,
        factors: (f64, f64, f64),
        continuity: bool,
    ) -> (Vector<D>, f64, f64);

    /// Fluid particle `o` and wall particle `w` at x_iw = x_i − x_w, squared distance r2
    /// (m²): the acceleration of i, the pair's factors and, with `continuity`, dρ_i/dt; the
    /// wall in the artificial viscosity
    /// (`with_av`) and the fluid's viscous stress against it (`with_viscous`) as for
    /// dynamic walls.
    #[allow(clippy::too_many_arguments)]
    fn wall(
        &self,
        base: &ForceSweep<'_, D>,
        o: &ForceOwner<D>,
        w: usize,
        xiw: Vector<D>,
        r2: f64,
        with_av: bool,
        with_viscous: bool,
        continuity: bool,
    ) -> WallPairFlux<D>;
}

/// What a fluid–wall pair gives the coupled pass ([`MomentumContinuityPair::wall`]).
pub(crate) struct WallPairFlux<const D: usize> {
    /// Acceleration of i (m/s²).
    pub(crate) acc: Vector<D>,
    /// The pair's factors.
    pub(crate) factors: WallPairFactors<D>,
    /// dρ_i/dt of the pair (kg/(m³·s)).
    pub(crate) drho: f64,
}

/// Paper Eq. 8 (pressure, artificial viscosity, viscous stress) with the continuity equation
/// dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (Monaghan 1992; walls at rest in the tank frame).
pub(crate) struct Eq8Pair;

impl<const D: usize> MomentumContinuityPair<D> for Eq8Pair {
    #[inline(always)]
    fn new(_: &PassConstants) -> Self {
        Eq8Pair
    }

    #[inline(always)]
    fn fluid(
        &self,
        base: &ForceSweep<'_, D>,
        o: &ForceOwner<D>,
        j: usize,
        nb: &FluidNeighbour<D>,
        xij: Vector<D>,
        _r: f64,
        grad_w: Vector<D>,
        factors: (f64, f64, f64),
        continuity: bool,
    ) -> (Vector<D>, f64, f64) {
        // Eq. 8: the paper's pair term, as the paper's force pass evaluates it (it reads j's
        // strain rate besides `nb`).
        let acc = base.fluid_term_with(o, j, xij, factors);
        if continuity {
            let vij = o.v - nb.v;
            let d = base.c.mass * vij.dot(&grad_w);
            (acc, d, d)
        } else {
            (acc, 0.0, 0.0)
        }
    }

    #[inline(always)]
    fn wall(
        &self,
        base: &ForceSweep<'_, D>,
        o: &ForceOwner<D>,
        w: usize,
        xiw: Vector<D>,
        r2: f64,
        with_av: bool,
        with_viscous: bool,
        continuity: bool,
    ) -> WallPairFlux<D> {
        let (acc, factors) = base.wall_momentum(o, w, xiw, r2, with_av, with_viscous);
        let drho = if continuity {
            base.c.mass * o.v.dot(&factors.grad_w)
        } else {
            0.0
        };
        WallPairFlux { acc, factors, drho }
    }
}

/// What the pair terms of the coupled force pass read: the density rate `R`, the wall force
/// `W`, the momentum and continuity pair `F` and the shifting sums (`SHIFT`) are types, so
/// that the pair loop carries no switch of its own.
pub(crate) struct ModernPairTerms<'a, const D: usize, R, W, F, const SHIFT: bool> {
    /// The paper sweep's constants and fluid and wall arrays (pressure and viscous terms).
    pub(crate) base: ForceSweep<'a, D>,
    /// −2 δ h c0 (m²/s): ψ_ij·∇_i W_ij = 2 (ρ_j − ρ_i) x_ji·x_ij F/r² = −2 (ρ_j − ρ_i) F,
    /// F = (dW/dr)/r, so the diffusion term is this factor times (ρ_j − ρ_i) F.
    pub(crate) diff_coeff: f64,
    /// Hydrostatic density of Fourtakas' diffusion (kg/m³).
    pub(crate) rho_h: &'a [f64],
    /// Wall velocity seen by the fluid with no-slip Adami walls (m/s).
    pub(crate) wall_vel: &'a [Vector<D>],
    /// The momentum and continuity pair.
    pub(crate) pair: F,
    _parts: std::marker::PhantomData<(R, W)>,
}

/// Fluid particle i of a row of modern pairs.
pub(crate) struct ModernOwner<const D: usize> {
    pub(crate) f: ForceOwner<D>,
    /// m/ρ_i (m³, 2D: m²).
    pub(crate) volume: f64,
    /// The density the diffusion term differences: ρ_i, or ρ_i − ρ_H,i (Fourtakas).
    pub(crate) rho_dyn: f64,
}

/// One fluid pair's shares (i within the support of j).
pub(crate) struct FluidPairTerm<const D: usize> {
    /// Acceleration of i (Eq. 8); j gets its negative.
    pub(crate) acc: Vector<D>,
    /// dρ_i/dt and dρ_j/dt: continuity m (v_i − v_j)·∇_i W_ij plus the diffusion terms.
    pub(crate) drho_i: f64,
    pub(crate) drho_j: f64,
    /// ∇_i W_ij and W_ij (the latter only with shifting) and m/ρ_j, for the shifting sums.
    pub(crate) grad_w: Vector<D>,
    pub(crate) w: f64,
    pub(crate) volume_j: f64,
}

/// The shares of a batch of fluid pairs ([`ModernPairTerms::fluid_pairs`]), one array per
/// component and pair k.
pub(crate) struct PairShareBatch<const D: usize> {
    /// Acceleration of i (m/s²), per component.
    pub(crate) acc: [[f64; BATCH]; D],
    /// dρ_i/dt and dρ_j/dt (kg/(m³·s)).
    pub(crate) drho_i: [f64; BATCH],
    pub(crate) drho_j: [f64; BATCH],
    /// W_ij (with shifting).
    pub(crate) w: [f64; BATCH],
}

impl<const D: usize> PairShareBatch<D> {
    pub(crate) fn new() -> Self {
        PairShareBatch {
            acc: [[0.0; BATCH]; D],
            drho_i: [0.0; BATCH],
            drho_j: [0.0; BATCH],
            w: [0.0; BATCH],
        }
    }
}

/// One fluid–wall pair's shares of i's sums: acceleration, dρ/dt, and the shifting's ∇C and
/// kernel sum.
pub(crate) struct WallPairTerm<const D: usize> {
    pub(crate) acc: Vector<D>,
    pub(crate) drho: f64,
    pub(crate) grad_c: Vector<D>,
    pub(crate) kernel_sum: f64,
}

impl<
        'a,
        const D: usize,
        R: DensityRateTerm,
        W: WallForceTerm,
        F: MomentumContinuityPair<D>,
        const SHIFT: bool,
    > ModernPairTerms<'a, D, R, W, F, SHIFT>
{
    /// The terms over `fluid` (its acceleration and density rate are not read), `walls` and
    /// the stage buffers' hydrostatic density and wall velocity.
    pub(crate) fn new(
        c: &PassConstants,
        fluid: &'a Fluid<D>,
        walls: &'a Walls<D>,
        st: &'a StageBuffers<D>,
    ) -> Self {
        ModernPairTerms {
            diff_coeff: -2.0 * st.k.diffusion_coeff,
            rho_h: &st.hydro_density,
            wall_vel: &st.wall_velocity,
            pair: F::new(c),
            base: ForceSweep::new(c, fluid, walls),
            _parts: std::marker::PhantomData,
        }
    }

    /// The density of particle i the diffusion term differences.
    #[inline(always)]
    pub(crate) fn rho_dyn(&self, i: usize) -> f64 {
        R::diffused_density(self.base.rho, self.rho_h, i)
    }

    #[inline(always)]
    pub(crate) fn owner(&self, i: usize) -> ModernOwner<D> {
        let f = self.base.owner(i);
        ModernOwner {
            volume: self.base.c.mass * f.inv_rho,
            rho_dyn: self.rho_dyn(i),
            f,
        }
    }

    /// The pair of fluid particles i (`o`) and j (its values `nb`, and `rho_dyn_j` the density
    /// the diffusion term differences) within the support: the momentum and continuity pair
    /// `F` (Eq. 8 with dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij, Monaghan 1992, or the
    /// Riemann-solver pair) with the δ-SPH diffusion term (Molteni & Colagrossi 2009;
    /// Fourtakas et al. 2019), and what the shifting sums need. `r` is the distance and
    /// `factors` the pair's (∇W factor, 1/s, 1/ρ̄) of [`ForceSweep::pair_factors`].
    // The pair's operands are passed one by one, as the inner loop holds them.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn fluid_pair(
        &self,
        o: &ModernOwner<D>,
        j: usize,
        nb: &FluidNeighbour<D>,
        rho_dyn_j: f64,
        xij: Vector<D>,
        r: f64,
        (f, inv_s, inv_rho_mean): (f64, f64, f64),
    ) -> FluidPairTerm<D> {
        let c = &self.base.c;
        let m = c.mass;
        let grad_w = xij * f;
        let (acc, mut drho_i, mut drho_j) = self.pair.fluid(
            &self.base,
            &o.f,
            j,
            nb,
            xij,
            r,
            grad_w,
            (f, inv_s, inv_rho_mean),
            R::CONTINUITY,
        );
        let volume_j = m * nb.inv_rho;
        if R::CONTINUITY && R::DIFFUSION {
            let psi = self.diff_coeff * (rho_dyn_j - o.rho_dyn) * f;
            drho_i += psi * volume_j;
            drho_j -= psi * o.volume;
        }
        let w = if SHIFT { c.kernel.value(r) } else { 0.0 };
        FluidPairTerm {
            acc,
            drho_i,
            drho_j,
            grad_w,
            w,
            volume_j,
        }
    }

    /// [`Self::fluid_pair`] of fluid particle j alone, its values read from the fluid.
    #[inline(always)]
    pub(crate) fn fluid_pair_of(
        &self,
        o: &ModernOwner<D>,
        j: usize,
        xij: Vector<D>,
        r: f64,
        factors: (f64, f64, f64),
    ) -> FluidPairTerm<D> {
        let nb = self.base.neighbour(j);
        self.fluid_pair(o, j, &nb, self.rho_dyn(j), xij, r, factors)
    }

    /// [`Self::fluid_pair`] of the neighbours `indices` (at most [`BATCH`]) of owner `o`,
    /// with their factors, r and gathered values in `b`: the shares into `b.shares`, each
    /// pair's arithmetic that of `fluid_pair` (one loop over the batch, which the compiler
    /// vectorises where the pair `F` reads nothing by index).
    #[inline(always)]
    // One index over the batch's arrays: the form the compiler vectorises.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn fluid_pairs(&self, o: &ModernOwner<D>, indices: &[u32], b: &mut PairBatch<D>) {
        let n = indices.len().min(BATCH);
        let (nbs, shares) = (&b.neighbours, &mut b.shares);
        for k in 0..n {
            let pair = self.fluid_pair(
                o,
                indices[k] as usize,
                &nbs.get(k),
                nbs.rho_dyn[k],
                nbs.xij(k),
                b.r[k],
                (b.grad[k], b.inv_s[k], b.inv_rho_mean[k]),
            );
            for d in 0..D {
                shares.acc[d][k] = pair.acc[d];
            }
            shares.drho_i[k] = pair.drho_i;
            shares.drho_j[k] = pair.drho_j;
            shares.w[k] = pair.w;
        }
    }

    /// Pair k of a batch that [`Self::fluid_pairs`] computed, as `fluid_pair` returns it.
    #[inline(always)]
    pub(crate) fn batch_pair(&self, b: &PairBatch<D>, k: usize) -> FluidPairTerm<D> {
        let (nbs, shares) = (&b.neighbours, &b.shares);
        FluidPairTerm {
            acc: Vector::<D>::from_fn(|d, _| shares.acc[d][k]),
            drho_i: shares.drho_i[k],
            drho_j: shares.drho_j[k],
            grad_w: nbs.xij(k) * b.grad[k],
            w: shares.w[k],
            volume_j: self.base.c.mass * nbs.inv_rho[k],
        }
    }

    /// The pair of fluid particle `o` and wall particle `w` within the support, at
    /// x_iw = x_i − x_w and squared distance r2 (m²): Eq. 8 with the wall's pressure (and
    /// velocity when mirrored), the continuity term of the wall's velocity (zero: the tank
    /// frame), and the shifting sums.
    #[inline(always)]
    pub(crate) fn wall_term(
        &self,
        o: &ForceOwner<D>,
        w: usize,
        xiw: Vector<D>,
        r2: f64,
    ) -> WallPairTerm<D> {
        let c = &self.base.c;
        let m = c.mass;
        let b = &self.base;
        let WallPairFlux {
            mut acc,
            factors:
                WallPairFactors {
                    grad_w,
                    f,
                    inv_s,
                    inv_rho_iw,
                    ..
                },
            drho,
        } = self.pair.wall(
            b,
            o,
            w,
            xiw,
            r2,
            W::AS_FLUID && b.av_on,
            W::AS_FLUID && b.viscous,
            R::CONTINUITY,
        );
        if W::NO_SLIP_VISCOUS {
            // No-slip Adami wall: the laminar viscous force of Morris et al. (1997),
            // m (μ_i + μ_w) (x_iw·∇_i W) v_iw / (ρ_i ρ_w (r² + 0.01 h²)), against the mirrored
            // wall velocity (Adami et al. 2012 Eq. 22; x_iw·∇_i W = r² F).
            let v_iw = o.v - self.wall_vel[w];
            acc += v_iw * (m * 2.0 * c.viscosity * inv_rho_iw * r2 * f * inv_s);
        }
        let (grad_c, kernel_sum) = if SHIFT {
            let volume_w = m * b.wall_inv_rho[w];
            (grad_w * volume_w, volume_w * c.kernel.value(r2.sqrt()))
        } else {
            (Vector::<D>::zeros(), 0.0)
        };
        WallPairTerm {
            acc,
            drho,
            grad_c,
            kernel_sum,
        }
    }
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

/// Owner i's running sums over its pairs: acceleration, dρ/dt, and the shifting's ∇C and
/// kernel sum.
pub(crate) struct OwnerSums<const D: usize> {
    pub(crate) acc: Vector<D>,
    pub(crate) drho: f64,
    pub(crate) grad_c: Vector<D>,
    pub(crate) ksum: f64,
}

impl<const D: usize> OwnerSums<D> {
    pub(crate) fn new(ksum: f64) -> Self {
        OwnerSums {
            acc: Vector::<D>::zeros(),
            drho: 0.0,
            grad_c: Vector::<D>::zeros(),
            ksum,
        }
    }

    /// i's share of a fluid pair.
    #[inline(always)]
    pub(crate) fn add_fluid<const SHIFT: bool>(&mut self, pair: &FluidPairTerm<D>) {
        self.acc += pair.acc;
        self.drho += pair.drho_i;
        if SHIFT {
            self.grad_c += pair.grad_w * pair.volume_j;
            self.ksum += pair.volume_j * pair.w;
        }
    }

    /// A fluid–wall pair.
    #[inline(always)]
    pub(crate) fn add_wall(&mut self, wall: &WallPairTerm<D>) {
        self.acc += wall.acc;
        self.drho += wall.drho;
        self.grad_c += wall.grad_c;
        self.ksum += wall.kernel_sum;
    }
}

/// The momentum equation with, in the same pair loop, the continuity equation
/// dρ_i/dt = Σ_j m_j (v_i − v_j)·∇_i W_ij (Monaghan 1992; walls at rest), the δ-SPH
/// diffusion term (Molteni & Colagrossi 2009; Fourtakas et al. 2019) and the shifting
/// gradient ∇C_i = Σ_j V_j ∇_i W_ij with its kernel sum, as a pass over pairs. In a half
/// sweep the momentum term and the shifting gradient are antisymmetric in i and j, the
/// continuity term symmetric, and the diffusion term of j is that of i with i and j
/// exchanged.
pub(crate) struct Coupled<'a, 'id, const D: usize, R, W, F, const SHIFT: bool> {
    terms: ModernPairTerms<'a, D, R, W, F, SHIFT>,
    acceleration: SweepSlots<'a, 'id, Vector<D>>,
    density_rate: SweepSlots<'a, 'id, f64>,
    /// With `SHIFT`, the shifting gradient ∇C (1/m) and kernel sum (their arrays are empty
    /// without shifting).
    shifting: Option<(SweepSlots<'a, 'id, Vector<D>>, SweepSlots<'a, 'id, f64>)>,
    /// W(0), a particle's own share of its kernel sum.
    w0: f64,
    body_force: Vector<D>,
}

impl<
        'a,
        'id,
        const D: usize,
        R: DensityRateTerm,
        W: WallForceTerm,
        F: MomentumContinuityPair<D>,
        const SHIFT: bool,
    > Coupled<'a, 'id, D, R, W, F, SHIFT>
{
    /// The pass over `fluid`, `walls` and the stage buffers `st`, writing the acceleration
    /// (m/s², body force included), dρ/dt (kg/(m³·s)) and, with shifting, ∇C (1/m) and the
    /// kernel sum into `out`, whose arrays become slots of `sweep`. A half sweep adds to
    /// `out`, which must hold the body force and zeros already.
    pub(crate) fn new(
        c: &PassConstants,
        fluid: &'a Fluid<D>,
        walls: &'a Walls<D>,
        st: &'a StageBuffers<D>,
        out: &'a mut ForceOutputs<D>,
        sweep: Sweep<'id>,
        body_force: Vector<D>,
    ) -> Self {
        Coupled {
            terms: ModernPairTerms::new(c, fluid, walls, st),
            acceleration: sweep.slots(&mut out.acceleration),
            density_rate: sweep.slots(&mut out.density_rate),
            shifting: SHIFT.then(|| {
                (
                    sweep.slots(&mut out.shift_gradient),
                    sweep.slots(&mut out.shift_kernel_sum),
                )
            }),
            w0: c.kernel.value(0.0),
            body_force,
        }
    }

    /// A fluid pair's shares: i's to `sums`; with j's slot (the half sweep) j's to that slot.
    #[inline(always)]
    fn add_pair(
        &self,
        o: &ModernOwner<D>,
        sums: &mut OwnerSums<D>,
        pair: &FluidPairTerm<D>,
        j_slot: Option<Slot<'_, 'id>>,
    ) {
        sums.add_fluid::<SHIFT>(pair);
        if let Some(slot) = j_slot {
            self.acceleration.sub(&slot, pair.acc);
            self.density_rate.add(&slot, pair.drho_j);
            if let (true, Some((grad_c, ksum))) = (SHIFT, &self.shifting) {
                grad_c.sub(&slot, pair.grad_w * o.volume);
                ksum.add(&slot, o.volume * pair.w);
            }
        }
    }
}

impl<
        'a,
        'id,
        const D: usize,
        R: DensityRateTerm,
        W: WallForceTerm,
        F: MomentumContinuityPair<D>,
        const SHIFT: bool,
    > PairInteraction<'a, 'id, D> for Coupled<'a, 'id, D, R, W, F, SHIFT>
{
    type Owner = ModernOwner<D>;
    type Sums = OwnerSums<D>;

    #[inline(always)]
    fn momentum(&self) -> &ForceSweep<'a, D> {
        &self.terms.base
    }

    #[inline(always)]
    fn owner(&self, i: usize) -> (ModernOwner<D>, Vector<D>, f64) {
        let o = self.terms.owner(i);
        let (x, rho) = (o.f.x, o.f.rho);
        (o, x, rho)
    }

    #[inline(always)]
    fn start(&self, o: &ModernOwner<D>, itself: bool) -> OwnerSums<D> {
        OwnerSums::new(if itself && SHIFT {
            o.volume * self.w0
        } else {
            0.0
        })
    }

    #[inline(always)]
    fn itself(&self, o: &ModernOwner<D>, sums: &mut OwnerSums<D>) {
        if SHIFT {
            sums.ksum += o.volume * self.w0;
        }
    }

    #[inline(always)]
    fn fluid_pair(
        &self,
        o: &ModernOwner<D>,
        sums: &mut OwnerSums<D>,
        j: usize,
        xij: Vector<D>,
        r: f64,
        factors: (f64, f64, f64),
        j_slot: Option<Slot<'_, 'id>>,
    ) {
        let pair = self.terms.fluid_pair_of(o, j, xij, r, factors);
        self.add_pair(o, sums, &pair, j_slot);
    }

    #[inline(always)]
    fn fluid_batch(
        &self,
        o: &ModernOwner<D>,
        sums: &mut OwnerSums<D>,
        xi: Vector<D>,
        rho_i: f64,
        batch: CheckedList<'_, 'id>,
        b: &mut PairBatch<D>,
    ) {
        // Gathered by index, computed in one loop over the batch, then added in the batch's
        // order: each pair's arithmetic and the order of every sum those of `fluid_pair`.
        let t = &self.terms;
        let indices = batch.indices();
        debug_assert!(indices.len() <= BATCH, "a batch holds at most BATCH pairs");
        t.base.batch_factors(rho_i, indices, b);
        t.base
            .gather_batch(xi, indices, |j| t.rho_dyn(j), &mut b.neighbours);
        t.fluid_pairs(o, indices, b);
        for (k, (_, slot)) in batch.iter().enumerate() {
            self.add_pair(o, sums, &t.batch_pair(b, k), Some(slot));
        }
    }

    #[inline(always)]
    fn wall_pair(
        &self,
        o: &ModernOwner<D>,
        sums: &mut OwnerSums<D>,
        w: usize,
        xiw: Vector<D>,
        r2: f64,
    ) {
        sums.add_wall(&self.terms.wall_term(&o.f, w, xiw, r2));
    }

    #[inline(always)]
    fn finish<const HALF: bool>(&self, i: usize, sums: OwnerSums<D>, block: &Block<'id>) {
        let slot = block.slot(i);
        if HALF {
            self.acceleration.add(&slot, sums.acc);
            self.density_rate.add(&slot, sums.drho);
            if let (true, Some((grad_c, ksum))) = (SHIFT, &self.shifting) {
                grad_c.add(&slot, sums.grad_c);
                ksum.add(&slot, sums.ksum);
            }
        } else {
            self.acceleration.set(&slot, sums.acc + self.body_force);
            self.density_rate.set(&slot, sums.drho);
            if let (true, Some((grad_c, ksum))) = (SHIFT, &self.shifting) {
                grad_c.set(&slot, sums.grad_c);
                ksum.set(&slot, sums.ksum);
            }
        }
    }
}
