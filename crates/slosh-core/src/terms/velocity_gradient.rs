//! The velocity gradient and strain rate of Eq. 4–5.

use crate::sim::*;


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
