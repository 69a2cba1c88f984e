//! Natural sloshing frequencies of rigid tanks (linear potential theory).
//!
//! Rectangular tank of full width L (along the excitation), still depth H:
//! ω_n² = g k_n tanh(k_n H), k_n = nπ/L (Lamb 1932 §257; Ibrahim 2005 Eq. 2.37).
//! Only odd n are excited by a horizontal ground motion; all n are natural modes.
//!
//! Upright circular cylinder of radius R, depth H:
//! ω_mn² = (g ξ_mn / R) tanh(ξ_mn H / R), ξ_mn the n-th zero of J_m′
//! (Lamb 1932 §191; Ibrahim 2005 Eq. 2.52). The horizontal excitation drives m = 1 only.

use crate::bessel::bessel_j_derivative_zero;
use std::f64::consts::PI;

/// Standard gravity g = 9.81 m/s² (the paper's value).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Wavenumber k_n = nπ/L (1/m) of mode n ≥ 1 in a rectangular tank of full width L (m).
pub fn rectangular_wavenumber(width: f64, mode: usize) -> f64 {
    mode as f64 * PI / width
}

/// Natural circular frequency ω_n (rad/s) of mode n ≥ 1 of a rectangular tank:
/// ω_n² = g k_n tanh(k_n H), k_n = nπ/L. `width` L (m, full width), `depth` H (m), `gravity` g (m/s²).
/// Source: linear potential theory (Lamb 1932; Ibrahim 2005 Eq. 2.37); valid for small amplitude.
pub fn rectangular_omega(width: f64, depth: f64, gravity: f64, mode: usize) -> f64 {
    let k = rectangular_wavenumber(width, mode);
    (gravity * k * (k * depth).tanh()).sqrt()
}

/// Natural period T_n = 2π/ω_n (s) of mode n of a rectangular tank (see [`rectangular_omega`]).
pub fn rectangular_period(width: f64, depth: f64, gravity: f64, mode: usize) -> f64 {
    2.0 * PI / rectangular_omega(width, depth, gravity, mode)
}

/// Dimensionless eigenvalue ξ_mn of an upright cylinder: the n-th positive zero of J_m′
/// (ξ_11 = 1.841184, ξ_12 = 5.331443, ξ_13 = 8.536316, ξ_01 = 3.831706).
pub fn cylinder_eigenvalue(circumferential: u32, radial: usize) -> f64 {
    bessel_j_derivative_zero(circumferential, radial)
}

/// Natural circular frequency ω_mn (rad/s) of an upright circular cylinder of radius R (m),
/// depth H (m): ω_mn² = (g ξ_mn/R) tanh(ξ_mn H/R).
/// Source: Lamb 1932 §191; Ibrahim 2005 Eq. 2.52. Linear, rigid tank, flat bottom.
pub fn cylinder_omega(
    radius: f64,
    depth: f64,
    gravity: f64,
    circumferential: u32,
    radial: usize,
) -> f64 {
    let xi = cylinder_eigenvalue(circumferential, radial);
    (gravity * xi / radius * (xi * depth / radius).tanh()).sqrt()
}

/// Natural period T_mn = 2π/ω_mn (s) of an upright cylinder (see [`cylinder_omega`]).
pub fn cylinder_period(
    radius: f64,
    depth: f64,
    gravity: f64,
    circumferential: u32,
    radial: usize,
) -> f64 {
    2.0 * PI / cylinder_omega(radius, depth, gravity, circumferential, radial)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_tank_first_mode() {
        // The paper's tank: L = 1, H = 0.5, g = 9.81 → ω₁ = 5.3166 rad/s, T₁ = 1.1818 s
        // (hand: k = π, tanh(π/2) = 0.917152, ω² = 9.81·π·0.917152 = 28.2660).
        // Tolerance 1e-4: the quoted values have 5 significant digits.
        let w = rectangular_omega(1.0, 0.5, 9.81, 1);
        assert!((w - 5.3166).abs() < 1e-4, "{w}");
        let t = rectangular_period(1.0, 0.5, 9.81, 1);
        assert!((t - 1.1818).abs() < 1e-4, "{t}");
    }

    #[test]
    fn rectangular_deep_water_limit() {
        // For kH ≫ 1, tanh → 1 and ω² = g k (deep-water dispersion). H = 50 m, L = 1 m:
        // tanh(50π) = 1 to machine precision, so agreement to 1e-12 relative.
        let w = rectangular_omega(1.0, 50.0, 9.81, 3);
        let deep = (9.81 * 3.0 * PI).sqrt();
        assert!((w / deep - 1.0).abs() < 1e-12);
    }

    #[test]
    fn cylinder_first_mode() {
        // R = 0.5, H = 0.5: ω² = 9.81·1.841184/0.5·tanh(1.841184) = 36.1240·0.950909 → ω = 5.8609
        // (hand calculation with the A&S zero); tolerance 1e-3 = 4 significant digits.
        let w = cylinder_omega(0.5, 0.5, 9.81, 1, 1);
        assert!((w - 5.861).abs() < 1e-3, "{w}");
    }
}
