//! Bessel functions of the first kind J_m(x) of integer order and the zeros of J_m′.
//!
//! J_m is evaluated from Bessel's integral (Watson 1944, §2.2; Abramowitz & Stegun 9.1.21)
//! J_m(x) = (1/2π) ∫₀^{2π} cos(mτ − x sin τ) dτ.
//! The integrand is smooth and 2π-periodic, so the trapezoidal rule with N nodes is exact up
//! to terms of order J_{N−m}(x) (aliasing), i.e. it converges faster than geometrically once
//! N exceeds |x| + m. With N = 64 + 2(|x| + m) the result is at round-off level (≈1e-15) for
//! all |x| ≲ 1000, which covers every tank problem here.

use std::f64::consts::PI;

/// Bessel function of the first kind J_m(x), integer order m ≥ 0, any real x.
///
/// Source: Bessel's integral (Abramowitz & Stegun 1964, Eq. 9.1.21) evaluated with the
/// periodic trapezoidal rule (exponentially convergent). Accuracy ≈ 1e-15 absolute for |x| ≤ 1000.
pub fn bessel_j(order: u32, x: f64) -> f64 {
    let m = order as f64;
    let nodes = 64 + 2 * (x.abs().ceil() as usize + order as usize);
    let step = 2.0 * PI / nodes as f64;
    let mut sum = 0.0;
    for i in 0..nodes {
        let tau = i as f64 * step;
        sum += (m * tau - x * tau.sin()).cos();
    }
    sum / nodes as f64
}

/// Derivative J_m′(x) of the Bessel function of the first kind.
///
/// Source: recurrence 2J_m′ = J_{m−1} − J_{m+1} (A&S 9.1.27), J_0′ = −J_1. Accuracy as [`bessel_j`].
pub fn bessel_j_derivative(order: u32, x: f64) -> f64 {
    if order == 0 {
        -bessel_j(1, x)
    } else {
        0.5 * (bessel_j(order - 1, x) - bessel_j(order + 1, x))
    }
}

/// The k-th positive zero ξ_{m,k} (k = 1, 2, …) of J_m′, excluding x = 0.
///
/// These are the sloshing eigenvalues of an upright circular cylinder (free-surface modes
/// cos(mθ) J_m(ξ r/R)); ξ_{1,1} = 1.841184 is the fundamental antisymmetric mode.
/// Method: scan for sign changes with step 0.05, then bisection to 1e-14 relative.
/// Panics if k = 0.
pub fn bessel_j_derivative_zero(order: u32, k: usize) -> f64 {
    assert!(k >= 1, "zeros are numbered from 1");
    let step = 0.05;
    let mut a = 1e-3;
    let mut fa = bessel_j_derivative(order, a);
    let mut found = 0;
    loop {
        let b = a + step;
        let fb = bessel_j_derivative(order, b);
        if fa == 0.0 || fa.signum() != fb.signum() {
            found += 1;
            if found == k {
                return bisect(|x| bessel_j_derivative(order, x), a, b);
            }
        }
        a = b;
        fa = fb;
    }
}

fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let mut f_lo = f(lo);
    if f_lo == 0.0 {
        return lo;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let f_mid = f(mid);
        if f_mid == 0.0 {
            return mid;
        }
        if f_mid.signum() == f_lo.signum() {
            lo = mid;
            f_lo = f_mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-14 * hi.abs() {
            break;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bessel_values_match_abramowitz_stegun_tables() {
        // A&S Table 9.1 (10 significant digits); tolerance 1e-9 = the tables' rounding.
        assert!((bessel_j(0, 1.0) - 0.7651976866).abs() < 1e-9);
        assert!((bessel_j(1, 1.0) - 0.4400505857).abs() < 1e-9);
        assert!((bessel_j(0, 10.0) - (-0.2459357645)).abs() < 1e-9);
        assert!((bessel_j(1, 10.0) - 0.0434727462).abs() < 1e-9);
        assert!((bessel_j(2, 5.0) - 0.0465651163).abs() < 1e-9);
        // J_1 is odd: J_1(−x) = −J_1(x)
        assert!((bessel_j(1, -2.0) + bessel_j(1, 2.0)).abs() < 1e-14);
    }

    #[test]
    fn derivative_zeros_match_published_values() {
        // A&S Table 9.5 (j′_{m,k}, 6 decimals); tolerance 1e-6 = the table's rounding.
        let cases = [
            (1, 1, 1.841184),
            (1, 2, 5.331443),
            (1, 3, 8.536316),
            (0, 1, 3.831706),
            (0, 2, 7.015587),
            (2, 1, 3.054237),
        ];
        for (m, k, want) in cases {
            let got = bessel_j_derivative_zero(m, k);
            assert!((got - want).abs() < 1e-6, "j'_{m},{k}: {got} vs {want}");
        }
    }

    #[test]
    fn derivative_matches_finite_difference() {
        // central difference with h = 1e-5 has truncation error ~h² ≈ 1e-10
        let h = 1e-5;
        for &x in &[0.3, 2.0, 7.5] {
            let fd = (bessel_j(1, x + h) - bessel_j(1, x - h)) / (2.0 * h);
            assert!((bessel_j_derivative(1, x) - fd).abs() < 1e-9);
        }
    }
}
