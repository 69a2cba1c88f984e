//! The Riemann-solver momentum and continuity pair of Zhang, Hu & Adams 2017 (*J. Comput.
//! Phys.* 335, 605–620), weakly compressible, with its low-dissipation limiter.
//!
//! For a pair (i, j) the states of the two particles are projected on the line of the pair and
//! the linearised (acoustic) 1D Riemann problem between them is solved. With e_ij = x_ij/r the
//! unit vector from j to i, the left state is i and the right state j, their velocities along
//! the pair U_L = −v_i·e_ij, U_R = −v_j·e_ij (positive towards the other particle, so that
//! U_L − U_R > 0 when the pair approaches). The interface pressure and velocity are
//!
//!   P* = P̄ + ½ β ρ̄ (U_L − U_R),  β = min(η max(U_L − U_R, 0), c̄),  η = 3,
//!   U* = Ū + (P_L − P_R)/(2 ρ̄ c̄),
//!
//! (the acoustic solution ρc-averaged with ρ_L c_L ≈ ρ_R c_R = ρ̄ c̄; β = c̄ is the full
//! acoustic dissipation, the limiter keeps only what a compression of speed U_L − U_R needs)
//! and the interface velocity vector v*_ij = U* d + (v̄ − Ū d), d = −e_ij, keeps the mean
//! transverse velocity. The pair terms are
//!
//!   dv_i/dt = −2 Σ_j m_j P*/(ρ_i ρ_j) ∇_i W_ij,
//!   dρ_i/dt = 2 ρ_i Σ_j (m_j/ρ_j) (v_i − v*_ij)·∇_i W_ij,
//!
//! which reduce to the pressure term of Eq. 8 and to the continuity equation ρ_i Σ_j V_j
//! (v_i − v_j)·∇_i W_ij without the dissipative parts. The dissipative part of U* is a
//! density diffusion of the pressure jump, (P_i − P_j)/(ρ̄ c̄); the limiter acts on P* only.
//! The same pair is implemented in SPHinXsys (`AcousticRiemannSolver`, with the limiter of
//! `DissipativeRiemannSolver` truncated at c̄). c̄ is the EOS reference speed c0: the Tait
//! speed c0 (ρ/ρ0)^{(γ−1)/2} differs from it by 3 δρ/ρ0 ≈ 3 % at most in weakly compressible
//! flow. Against an Adami wall (Adami, Hu & Adams 2012) the right state is the wall's
//! extrapolated pressure and its velocity, zero in the tank frame, as SPHinXsys takes the
//! wall's pressure and velocity. The viscous stress of Eq. 8 is added when μ > 0; the
//! artificial viscosity Π_ij is replaced by the limiter.

use super::coupled::{MomentumContinuityPair, WallPairFlux};
use super::momentum::{FluidNeighbour, ForceOwner, ForceSweep};
use crate::sim::*;

/// η of the low-dissipation limiter β = min(η max(U_L − U_R, 0), c̄) (Zhang, Hu & Adams 2017).
pub(crate) const RIEMANN_LIMITER_ETA: f64 = 3.0;

/// The Riemann-solver pair (module documentation).
pub(crate) struct RiemannPair {
    /// c̄ = c0 of the EOS (m/s).
    c_bar: f64,
    /// 1/c̄ (s/m).
    inv_c_bar: f64,
}

impl RiemannPair {
    /// The limited dissipative pressure ½ β ρ̄ (U_L − U_R) of P* (Pa), for the approach speed
    /// `du` = U_L − U_R (m/s) and ρ̄ (kg/m³).
    #[inline(always)]
    pub(crate) fn limited_pressure_jump(&self, du: f64, rho_mean: f64) -> f64 {
        let beta = (RIEMANN_LIMITER_ETA * du.max(0.0)).min(self.c_bar);
        0.5 * beta * rho_mean * du
    }

    /// U* − Ū = (P_L − P_R)/(2 ρ̄ c̄) (m/s), for the pressure jump `dp` = P_L − P_R (Pa) and
    /// 1/ρ̄ = `inv_rho_mean`.
    #[inline(always)]
    pub(crate) fn velocity_jump(&self, dp: f64, inv_rho_mean: f64) -> f64 {
        0.5 * dp * inv_rho_mean * self.inv_c_bar
    }

    /// The scalars of a pair: with the approach speed U_L − U_R = −v_ij·x_ij/r (`v_dot_x` =
    /// v_ij·x_ij, `r` the distance), the pressure jump P_L − P_R = `dp`, P_L + P_R = `p_sum`,
    /// 1/ρ̄ and F = (dW/dr)/r: returns 2 P* (Pa) and 2 (U* − Ū) d·∇_i W_ij (1/s… times m/s:
    /// the dissipative part of 2 (v_L − v*)·∇_i W_ij, d·∇_i W_ij = −r F).
    #[inline(always)]
    fn interface(
        &self,
        v_dot_x: f64,
        r: f64,
        dp: f64,
        p_sum: f64,
        inv_rho_mean: f64,
        f: f64,
    ) -> (f64, f64) {
        let inv_r = 1.0 / r;
        let du = -v_dot_x * inv_r;
        let rho_mean = 1.0 / inv_rho_mean;
        let two_p_star = p_sum + 2.0 * self.limited_pressure_jump(du, rho_mean);
        // v_L − v* = ½ v_ij − (U* − Ū) d, and d·∇_i W_ij = −e_ij·x_ij F = −r F.
        let dissipative = 2.0 * self.velocity_jump(dp, inv_rho_mean) * r * f;
        (two_p_star, dissipative)
    }
}

impl<const D: usize> MomentumContinuityPair<D> for RiemannPair {
    fn new(c: &PassConstants) -> Self {
        RiemannPair {
            c_bar: c.eos_sound_speed,
            inv_c_bar: 1.0 / c.eos_sound_speed,
        }
    }

    #[inline(always)]
    fn fluid(
        &self,
        base: &ForceSweep<'_, D>,
        o: &ForceOwner<D>,
        j: usize,
        nb: &FluidNeighbour<D>,
        xij: Vector<D>,
        r: f64,
        grad_w: Vector<D>,
        (f, _inv_s, inv_rho_mean): (f64, f64, f64),
        continuity: bool,
    ) -> (Vector<D>, f64, f64) {
        let m = base.c.mass;
        let vij = o.v - nb.v;
        let p_j = nb.p;
        let inv_rho_j = nb.inv_rho;
        let inv_rho_ij = o.inv_rho * inv_rho_j;
        let (two_p_star, dissipative) =
            self.interface(vij.dot(&xij), r, o.p - p_j, o.p + p_j, inv_rho_mean, f);
        // dv_i/dt = −2 m P*/(ρ_i ρ_j) ∇_i W_ij; j gets its negative.
        let mut acc = grad_w * (-m * two_p_star * inv_rho_ij);
        if base.viscous {
            // The viscous part of Eq. 8.
            acc += base.viscous_stress(o, j, grad_w, inv_rho_ij);
        }
        if !continuity {
            return (acc, 0.0, 0.0);
        }
        // 2 (v_i − v*)·∇W = v_ij·∇W + dissipative; 2 (v* − v_j)·∇W = v_ij·∇W − dissipative.
        let flux = vij.dot(&grad_w);
        let rho_j = nb.rho;
        (
            acc,
            o.rho * m * inv_rho_j * (flux + dissipative),
            rho_j * m * o.inv_rho * (flux - dissipative),
        )
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
        // Simulation::new refuses the Riemann pair with dynamic walls, the only walls that
        // take part in the artificial viscosity and the fluid's viscous stress.
        debug_assert!(!with_av && !with_viscous);
        let m = base.c.mass;
        let factors = base.wall_pair_factors(o, w, xiw, r2);
        let inv_rho_w = base.wall_inv_rho[w];
        let p_w = base.wall_p[w];
        // Right state: the wall's pressure and its velocity, zero in the tank frame.
        let (two_p_star, dissipative) = self.interface(
            o.v.dot(&xiw),
            r2.sqrt().max(1e-150),
            o.p - p_w,
            o.p + p_w,
            factors.inv_rho_mean,
            factors.f,
        );
        let acc = factors.grad_w * (-m * two_p_star * factors.inv_rho_iw);
        let drho = if continuity {
            o.rho * m * inv_rho_w * (o.v.dot(&factors.grad_w) + dissipative)
        } else {
            0.0
        };
        WallPairFlux { acc, factors, drho }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(c_bar: f64) -> RiemannPair {
        RiemannPair {
            c_bar,
            inv_c_bar: 1.0 / c_bar,
        }
    }

    /// The linearised (acoustic) Riemann problem of two equal states colliding at ±u has the
    /// interface pressure P̄ + ρ c u (Toro 2009, *Riemann Solvers and Numerical Methods for
    /// Fluid Dynamics*, §4.2 and the two-shock approximation): the limiter's cap β = c̄ gives
    /// it exactly once η ΔU ≥ c̄, and ½ η ρ ΔU² below (to round-off).
    #[test]
    fn limiter_caps_at_the_acoustic_solution() {
        let rp = pair(20.0);
        let (rho, u) = (1000.0, 10.0); // ΔU = 2u = 20 m/s: η ΔU = 60 > c̄
        let dp = rp.limited_pressure_jump(2.0 * u, rho);
        assert!((dp - rho * 20.0 * u).abs() < 1e-9 * dp, "{dp}");
        let small = 0.1; // η ΔU = 0.6 < c̄
        let dp = rp.limited_pressure_jump(small, rho);
        assert!((dp - 0.5 * RIEMANN_LIMITER_ETA * rho * small * small).abs() < 1e-12);
        // A receding pair gets no dissipative pressure.
        assert_eq!(rp.limited_pressure_jump(-1.0, rho), 0.0);
    }

    /// U* of the acoustic problem between two states at rest with pressures P_L and P_R is
    /// (P_L − P_R)/(ρ_L c_L + ρ_R c_R) (Toro 2009 §4.2), here with ρ_L c_L = ρ_R c_R = ρ c.
    #[test]
    fn interface_velocity_of_a_pressure_jump() {
        let rp = pair(25.0);
        let (rho, dp) = (1000.0, 5000.0);
        let u = rp.velocity_jump(dp, 1.0 / rho);
        assert!((u - dp / (2.0 * rho * 25.0)).abs() < 1e-15, "{u}");
    }

    /// Without relative motion or pressure jump, the pair's momentum is the pressure term of
    /// Eq. 8 (2 P* = P_i + P_j) and the dissipative density rate vanishes; a higher pressure on
    /// the left lowers the left particle's density rate (dissipation, F < 0).
    #[test]
    fn interface_reduces_to_eq8_without_jumps() {
        let rp = pair(25.0);
        let (two_p, diss) = rp.interface(0.0, 0.01, 0.0, 3000.0, 1e-3, -50.0);
        assert_eq!((two_p, diss), (3000.0, 0.0));
        let (_, diss) = rp.interface(0.0, 0.01, 100.0, 3000.0, 1e-3, -50.0);
        assert!(diss < 0.0, "{diss}");
        // Approaching (v_ij·x_ij < 0): P* above P̄.
        let (two_p, _) = rp.interface(-0.01 * 0.5, 0.01, 0.0, 3000.0, 1e-3, -50.0);
        assert!(two_p > 3000.0, "{two_p}");
    }
}
