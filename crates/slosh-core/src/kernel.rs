//! Smoothing kernels W(r, h) with support radius 2h.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Which smoothing function the solver uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum KernelKind {
    /// Cubic B-spline of Monaghan & Lattanzio (1985), the paper's kernel (§2.1).
    CubicSpline,
    /// Wendland C2 (Wendland 1995), smoother pressure fields, no pairing instability.
    /// Support 2h like the spline. It needs more neighbours than the spline: measured in
    /// `tests_modern` (modern scheme, 0.6 × 0.3 m tank, dx = 0.02 m) the first sloshing period
    /// was −4.7 % off at h = 1.3 dx, −4.0 % at 1.4 dx and −0.4 % at 1.5 dx; the free decay of
    /// the first mode damps by ζ = 1.0, 1.8, 0.45, 0.37 and 0.21 % at h = 1.3, 1.4, 1.5, 1.7
    /// and 2 dx (40 particles per depth, `docs/validation.md`), so the modern preset uses
    /// h = 2 dx, with walls of [`crate::SphParams::wall_layers`] layers.
    WendlandC2,
}

/// A kernel of a given smoothing length, with its dimension-dependent normalisation.
#[derive(Clone, Copy, Debug)]
pub struct Kernel {
    /// Which function.
    pub kind: KernelKind,
    /// Smoothing length h (m); the support radius is 2h.
    pub h: f64,
    inv_h: f64,
    /// Normalisation σ_D / h^D.
    norm: f64,
}

impl Kernel {
    /// Kernel of smoothing length `h` (m) in `dim` space dimensions (2 or 3).
    pub fn new(kind: KernelKind, h: f64, dim: usize) -> Self {
        let sigma = match (kind, dim) {
            // Cubic B-spline: 10/(7π h²) in 2D, 1/(π h³) in 3D.
            (KernelKind::CubicSpline, 2) => 10.0 / (7.0 * PI),
            (KernelKind::CubicSpline, _) => 1.0 / PI,
            // Wendland C2: 7/(4π h²) in 2D, 21/(16π h³) in 3D.
            (KernelKind::WendlandC2, 2) => 7.0 / (4.0 * PI),
            (KernelKind::WendlandC2, _) => 21.0 / (16.0 * PI),
        };
        Kernel {
            kind,
            h,
            inv_h: 1.0 / h,
            norm: sigma / h.powi(dim as i32),
        }
    }

    /// Support radius 2h (m).
    #[inline(always)]
    pub fn support(&self) -> f64 {
        2.0 * self.h
    }

    /// W(r) (1/m^D).
    #[inline(always)]
    pub fn value(&self, r: f64) -> f64 {
        self.norm * self.shape(r * self.inv_h).0
    }

    /// W(r) and (dW/dr)/r together, with one evaluation of q = r/h (the density pass needs
    /// both for every pair). Equal to `(self.value(r), self.gradient_factor(r))`.
    #[inline(always)]
    pub fn value_and_gradient_factor(&self, r: f64) -> (f64, f64) {
        let q = r * self.inv_h;
        let (w, d_dq) = self.shape(q);
        (self.norm * w, self.factor_from(d_dq, q, r))
    }

    /// (dW/dr)/r (1/m^(D+2)), so that ∇_i W_ij = x_ij · gradient_factor(r_ij).
    #[inline(always)]
    pub fn gradient_factor(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        self.factor_from(self.shape(q).1, q, r)
    }

    /// (dW/dr)/r as [`Self::gradient_factor`], with 1/r given by the caller (who may get it
    /// from a division it needs anyway); 0 at r = 0 whatever `inv_r` is.
    #[inline(always)]
    pub fn gradient_factor_with_inverse(&self, r: f64, inv_r: f64) -> f64 {
        let q = r * self.inv_h;
        let d_dq = self.shape(q).1;
        if q > 1e-12 {
            self.norm * d_dq * self.inv_h * inv_r
        } else {
            0.0
        }
    }

    /// W and (dW/dr)/r at the distances √r2[k], into w[k] and f[k] (the first r2.len()
    /// entries), equal to [`Self::value_and_gradient_factor`] of each: one loop per kernel
    /// kind, without branches, which the compiler turns into vector instructions (square roots
    /// and divisions two or more at a time).
    #[inline(always)]
    pub fn values_and_gradient_factors(&self, r2: &[f64], w: &mut [f64], f: &mut [f64]) {
        let n = r2.len();
        let (w, f) = (&mut w[..n], &mut f[..n]);
        match self.kind {
            KernelKind::CubicSpline => {
                for k in 0..n {
                    let r = r2[k].sqrt();
                    let q = r * self.inv_h;
                    let (shape, d_dq) = cubic_spline_shape(q);
                    w[k] = self.norm * shape;
                    f[k] = self.factor_from(d_dq, q, r);
                }
            }
            KernelKind::WendlandC2 => {
                for k in 0..n {
                    let r = r2[k].sqrt();
                    let q = r * self.inv_h;
                    let (shape, d_dq) = wendland_c2_shape(q);
                    w[k] = self.norm * shape;
                    f[k] = self.factor_from(d_dq, q, r);
                }
            }
        }
    }

    /// W at the distances √r2[k], into w[k] (the first r2.len() entries): [`Self::value`] of
    /// each, bit for bit, in one branch-free loop per kernel kind that the compiler vectorises.
    #[inline(always)]
    pub fn values(&self, r2: &[f64], w: &mut [f64]) {
        let n = r2.len();
        let w = &mut w[..n];
        macro_rules! values {
            ($shape:ident) => {
                for k in 0..n {
                    w[k] = self.norm * $shape(r2[k].sqrt() * self.inv_h).0;
                }
            };
        }
        match self.kind {
            KernelKind::CubicSpline => values!(cubic_spline_shape),
            KernelKind::WendlandC2 => values!(wendland_c2_shape),
        }
    }

    /// (dW/dr)/r at the distances r[k] with 1/r[k] given, into f[k] (the first r.len()
    /// entries): [`Self::gradient_factor_with_inverse`] of each, bit for bit, in one
    /// branch-free loop per kernel kind that the compiler vectorises.
    #[inline(always)]
    pub fn gradient_factors_with_inverse(&self, r: &[f64], inv_r: &[f64], f: &mut [f64]) {
        let n = r.len();
        let (inv_r, f) = (&inv_r[..n], &mut f[..n]);
        macro_rules! factors {
            ($shape:ident) => {
                for k in 0..n {
                    let q = r[k] * self.inv_h;
                    let d_dq = $shape(q).1;
                    f[k] = if q > 1e-12 {
                        self.norm * d_dq * self.inv_h * inv_r[k]
                    } else {
                        0.0
                    };
                }
            };
        }
        match self.kind {
            KernelKind::CubicSpline => factors!(cubic_spline_shape),
            KernelKind::WendlandC2 => factors!(wendland_c2_shape),
        }
    }

    /// The dimensionless shape f(q) (W = norm · f) and its derivative df/dq, without branches
    /// on q: the pair loops see q < 1 and q > 1 about equally often, in no order a branch
    /// predictor could follow.
    #[inline(always)]
    fn shape(&self, q: f64) -> (f64, f64) {
        match self.kind {
            KernelKind::CubicSpline => cubic_spline_shape(q),
            KernelKind::WendlandC2 => wendland_c2_shape(q),
        }
    }

    /// (dW/dr)/r from df/dq: dW/dr = norm · df/dq / h, divided by r = q h (0 at r = 0).
    #[inline(always)]
    fn factor_from(&self, d_dq: f64, q: f64, r: f64) -> f64 {
        if q > 1e-12 {
            self.norm * d_dq * self.inv_h / r
        } else {
            0.0
        }
    }
}

/// Cubic spline: f = 1 − 3q²/2 + 3q³/4 for q < 1, (2 − q)³/4 for 1 ≤ q < 2, 0 beyond; with
/// t = max(2 − q, 0) and u = max(1 − q, 0) this is f = t³/4 − u³, and df/dq = 3u² − 3t²/4
/// (= −3q + 9q²/4 for q < 1, −3(2 − q)²/4 for 1 ≤ q < 2).
#[inline(always)]
fn cubic_spline_shape(q: f64) -> (f64, f64) {
    let t = (2.0 - q).max(0.0);
    let u = (1.0 - q).max(0.0);
    (0.25 * t * t * t - u * u * u, 3.0 * u * u - 0.75 * t * t)
}

/// Wendland C2: f = (1 − q/2)^4 (2q + 1); d/dq [(1 − q/2)^4 (2q + 1)] = −5 q (1 − q/2)^3; 0
/// beyond q = 2.
#[inline(always)]
fn wendland_c2_shape(q: f64) -> (f64, f64) {
    let t = (1.0 - 0.5 * q).max(0.0);
    let t2 = t * t;
    (t2 * t2 * (2.0 * q + 1.0), -5.0 * q * t2 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ W dV over the plane/space by a fine Riemann sum must be 1 (normalisation);
    /// tolerance 1e-4 because the midpoint sum on a 1/200 h grid has that accuracy.
    fn integral(kind: KernelKind, dim: usize) -> f64 {
        let h = 1.0;
        let k = Kernel::new(kind, h, dim);
        let n = 200;
        let d = 2.0 * h / n as f64;
        let mut sum = 0.0;
        if dim == 2 {
            for i in -n..n {
                for j in -n..n {
                    let x = (i as f64 + 0.5) * d;
                    let y = (j as f64 + 0.5) * d;
                    sum += k.value((x * x + y * y).sqrt()) * d * d;
                }
            }
        } else {
            // radial integral 4π ∫ r² W dr
            let m = 20000;
            let dr = 2.0 * h / m as f64;
            for i in 0..m {
                let r = (i as f64 + 0.5) * dr;
                sum += 4.0 * PI * r * r * k.value(r) * dr;
            }
        }
        sum
    }

    #[test]
    fn kernels_are_normalised() {
        for kind in [KernelKind::CubicSpline, KernelKind::WendlandC2] {
            for dim in [2, 3] {
                let s = integral(kind, dim);
                assert!((s - 1.0).abs() < 1e-4, "{kind:?} {dim}D integrates to {s}");
            }
        }
    }

    /// The batched, vectorised factors and values are the scalar ones bit for bit (the force
    /// sweeps use either, by whether a particle's neighbour list overflowed, and results must
    /// not depend on it; the wall extrapolation took the scalar values before it took the
    /// batched ones), over the whole support, beyond it, and at r = 0.
    #[test]
    fn batched_gradient_factors_equal_the_scalar_ones() {
        for kind in [KernelKind::CubicSpline, KernelKind::WendlandC2] {
            for dim in [2, 3] {
                let k = Kernel::new(kind, 0.0065, dim);
                let r: Vec<f64> = (0..37).map(|i| i as f64 * 0.06 * k.h).collect();
                let inv_r: Vec<f64> = r.iter().map(|&r| 1.0 / r.max(1e-150)).collect();
                let mut f = vec![f64::NAN; r.len()];
                k.gradient_factors_with_inverse(&r, &inv_r, &mut f);
                for i in 0..r.len() {
                    let scalar = k.gradient_factor_with_inverse(r[i], inv_r[i]);
                    assert_eq!(
                        f[i].to_bits(),
                        scalar.to_bits(),
                        "{kind:?} {dim}D r = {}",
                        r[i]
                    );
                }
                // W and the factor together from r², as the density and strain sweeps take them.
                let r2: Vec<f64> = r.iter().map(|r| r * r).collect();
                let mut w = vec![f64::NAN; r.len()];
                k.values_and_gradient_factors(&r2, &mut w, &mut f);
                for i in 0..r.len() {
                    let (w_scalar, f_scalar) = k.value_and_gradient_factor(r2[i].sqrt());
                    assert_eq!(f[i].to_bits(), f_scalar.to_bits(), "{kind:?} {dim}D");
                    assert_eq!(w[i].to_bits(), w_scalar.to_bits(), "{kind:?} {dim}D");
                }
                // W alone from r², as the wall-pressure extrapolation takes it.
                k.values(&r2, &mut w);
                for i in 0..r.len() {
                    let w_scalar = k.value(r2[i].sqrt());
                    assert_eq!(w[i].to_bits(), w_scalar.to_bits(), "{kind:?} {dim}D");
                }
            }
        }
    }

    /// The analytic gradient must match a central finite difference of W
    /// (tolerance 1e-6 relative: the O(δ²) error of the difference with δ = 1e-6 h).
    #[test]
    fn gradient_matches_finite_difference() {
        for kind in [KernelKind::CubicSpline, KernelKind::WendlandC2] {
            let k = Kernel::new(kind, 0.026, 2);
            for i in 1..40 {
                let r = i as f64 * 0.05 * 0.026;
                let d = 1e-6 * 0.026;
                let fd = (k.value(r + d) - k.value(r - d)) / (2.0 * d);
                let an = k.gradient_factor(r) * r;
                assert!(
                    (fd - an).abs() <= 1e-6 * (an.abs() + k.value(0.0) / 0.026),
                    "{kind:?} r={r}: fd {fd} analytic {an}"
                );
            }
        }
    }
}
