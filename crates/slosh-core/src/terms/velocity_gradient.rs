//! The velocity gradient and strain rate of Eq. 4–5.
//!
//! G_ab = Σ_j (m_j/ρ_j) (v_j − v_i)_a ∂W_ij/∂x_i,b, then V = G + Gᵀ − (2/3) tr(G) I. A pass
//! that sees each pair from both of its particles adds [`velocity_gradient_share`]; a half
//! sweep computes the pair's tensor once ([`velocity_gradient_pair`]), which is the same
//! seen from j ((v_i − v_j) ⊗ ∇_j W_ji), and scales it by each side's neighbour volume.

use crate::sim::*;

/// Eq. 5 term of one neighbour: (v_j − v_i) ⊗ (V_j ∇_i W_ij), with `v_ji` = v_j − v_i (m/s),
/// `grad_w` = ∇_i W_ij (1/m^(D+1)) and `volume_j` = m_j/ρ_j (m^D).
#[inline(always)]
pub(crate) fn velocity_gradient_share<const D: usize>(
    v_ji: Vector<D>,
    grad_w: Vector<D>,
    volume_j: f64,
) -> Tensor<D> {
    v_ji * (grad_w * volume_j).transpose()
}

/// The tensor (v_j − v_i) ⊗ ∇_i W_ij of a pair, to be scaled by V_j for i and by V_i for j.
#[inline(always)]
pub(crate) fn velocity_gradient_pair<const D: usize>(
    v_ji: Vector<D>,
    grad_w: Vector<D>,
) -> Tensor<D> {
    v_ji * grad_w.transpose()
}

/// Strain rate V = G + Gᵀ − (2/3) tr(G) I of a velocity gradient G (Eq. 4–5), 1/s.
#[inline(always)]
pub(crate) fn strain_rate_of<const D: usize>(grad_v: &Tensor<D>) -> Tensor<D> {
    let trace = grad_v.trace();
    let mut v_tensor = grad_v + grad_v.transpose();
    for k in 0..D {
        v_tensor[(k, k)] -= 2.0 / 3.0 * trace;
    }
    v_tensor
}
