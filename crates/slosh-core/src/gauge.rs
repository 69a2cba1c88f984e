//! Wave gauges: the free-surface level on a vertical line.

use crate::sim::{Simulation, Vector};

/// Free-surface level (m) on the vertical line through `horizontal` (the D−1 horizontal
/// coordinates): the highest height where the fluid kernel sum S(z) = Σ_j (m_j/ρ_j) W falls to
/// half of its value S_ref at mid-depth on the same line.
///
/// Normalising by S_ref makes the gauge usable next to a wall, where the kernel is cut by the
/// wall and S stays below 1 even inside the liquid; at a flat surface S drops to S_ref/2 at the
/// surface itself (half the kernel is in the liquid). `None` when the line holds no liquid.
pub fn surface_level<const D: usize>(sim: &Simulation<D>, horizontal: &[f64]) -> Option<f64> {
    assert_eq!(
        horizontal.len(),
        D - 1,
        "a gauge needs D−1 horizontal coordinates"
    );
    let kernel = sim.kernel();
    let support = kernel.support();
    let mass = sim.particle_mass();
    let fluid = sim.fluid();
    // Candidates: fluid particles within the support of the line.
    let mut column: Vec<(Vector<D>, f64)> = Vec::new();
    let mut top = f64::NEG_INFINITY;
    for (x, rho) in fluid.position.iter().zip(&fluid.density) {
        let mut d2 = 0.0;
        for k in 0..D - 1 {
            let d = x[k] - horizontal[k];
            d2 += d * d;
        }
        if d2 < support * support {
            column.push((*x, mass / rho));
            top = top.max(x[D - 1]);
        }
    }
    if column.is_empty() {
        return None;
    }
    let kernel_sum = |z: f64| -> f64 {
        let mut p = Vector::<D>::zeros();
        p.as_mut_slice()[..D - 1].copy_from_slice(horizontal);
        p[D - 1] = z;
        column
            .iter()
            .map(|(x, vol)| vol * kernel.value((p - x).norm()))
            .sum()
    };
    let (lo, _) = sim.interior_bounds();
    let floor = lo[D - 1];
    let z_ref = floor + 0.5 * (sim.fill_level() - floor);
    let s_ref = kernel_sum(z_ref);
    if s_ref < 0.05 {
        return None;
    }
    let target = 0.5 * s_ref;
    // March down from above the highest particle, then bisect the crossing.
    let step = 0.25 * sim.spacing();
    let mut z_hi = top + support;
    let mut z_lo = z_hi - step;
    while kernel_sum(z_lo) < target {
        z_hi = z_lo;
        z_lo -= step;
        if z_lo < floor - support {
            return None;
        }
    }
    for _ in 0..40 {
        let mid = 0.5 * (z_lo + z_hi);
        if kernel_sum(mid) >= target {
            z_lo = mid;
        } else {
            z_hi = mid;
        }
    }
    Some(0.5 * (z_lo + z_hi))
}
