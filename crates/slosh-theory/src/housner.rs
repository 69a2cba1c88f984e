//! Housner's (1957) approximate hydrodynamic pressures, base shear, masses and heights for a
//! rigid rectangular tank (the paper's Eq. 25–26), per metre of tank length.
//!
//! Coordinates as in the paper's Fig. 1: x from the tank centre (−l ≤ x ≤ l, l = half-width),
//! depth h below the still surface for the impulsive part, height y above the bottom for the
//! convective part; H the liquid depth. Housner's "membrane" approximation assumes the fluid
//! moves in thin vertical (impulsive) or horizontal-slice (convective) layers and a plane free
//! surface of slope θ_H; it is within a few per cent of exact potential theory
//! ([`crate::linear`]) for the masses and frequencies. Source: G. W. Housner, "Dynamic
//! pressures on accelerated fluid containers", BSSA 47 (1957) 15–35; TID-7024 (1963) ch. 6.

/// √(5/2), the convective shape constant of Housner's rectangular-tank theory.
const C5: f64 = 1.5811388300841898;

/// Impulsive pressure, paper Eq. 25 (Pa): p = ρ a H √3 [h/H − ½(h/H)²] sinh(√3 x/H)/cosh(√3 l/H).
/// `accel` a is the inertial body force per unit mass on the fluid (m/s², along +x; a = −a_g),
/// `x` (m) from the centre, `depth_below_surface` h ∈ [0, H] (m). Positive on the +x wall for a > 0.
pub fn impulsive_pressure(
    density: f64,
    accel: f64,
    depth: f64,
    half_width: f64,
    x: f64,
    depth_below_surface: f64,
) -> f64 {
    let s3 = 3f64.sqrt();
    let r = depth_below_surface / depth;
    density * accel * depth * s3 * (r - 0.5 * r * r) * (s3 * x / depth).sinh()
        / (s3 * half_width / depth).cosh()
}

/// Convective pressure, paper Eq. 26 (Pa), written with the free-surface slope
/// `surface_slope` s = dζ/dx (positive when the surface rises toward +x):
/// p = ρ (l²/2) √(5/2) [x/l − ⅓(x/l)³] cosh(√(5/2) y/l)/sinh(√(5/2) H/l) ω² s.
/// The paper prints a minus sign with θ_H; that matches this function for θ_H = −dζ/dx (the
/// physical requirement is p ≈ ρ g ζ > 0 near the top of the wall where the surface is raised).
/// `omega` ω (rad/s) is the first natural circular frequency, `height_above_bottom` y ∈ [0, H].
pub fn convective_pressure(
    density: f64,
    half_width: f64,
    depth: f64,
    omega: f64,
    surface_slope: f64,
    x: f64,
    height_above_bottom: f64,
) -> f64 {
    let l = half_width;
    let xi = x / l;
    density * 0.5 * l * l * C5 * (xi - xi.powi(3) / 3.0) * (C5 * height_above_bottom / l).cosh()
        / (C5 * depth / l).sinh()
        * omega
        * omega
        * surface_slope
}

/// Housner (1957) first convective circular frequency (rad/s): ω² = (g/l)√(5/2) tanh(√(5/2) H/l).
pub fn convective_omega(half_width: f64, depth: f64, gravity: f64) -> f64 {
    (gravity / half_width * C5 * (C5 * depth / half_width).tanh()).sqrt()
}

/// Impulsive base shear (N/m), Eq. 25 integrated over both walls:
/// V_i = (2/√3) ρ a H² tanh(√3 l/H) = m_i a.
pub fn impulsive_base_shear(density: f64, accel: f64, depth: f64, half_width: f64) -> f64 {
    let s3 = 3f64.sqrt();
    2.0 / s3 * density * accel * depth * depth * (s3 * half_width / depth).tanh()
}

/// Convective base shear (N/m), Eq. 26 integrated over both walls: V_c = (2/3) ρ l³ ω² s,
/// s = dζ/dx the surface slope (sign as in [`convective_pressure`]).
pub fn convective_base_shear(density: f64, half_width: f64, omega: f64, surface_slope: f64) -> f64 {
    2.0 / 3.0 * density * half_width.powi(3) * omega * omega * surface_slope
}

/// Housner impulsive mass (kg/m): m_i = m tanh(√3 l/H)/(√3 l/H), m = 2ρlH.
pub fn impulsive_mass(density: f64, half_width: f64, depth: f64) -> f64 {
    let x = 3f64.sqrt() * half_width / depth;
    2.0 * density * half_width * depth * x.tanh() / x
}

/// Housner convective mass (kg/m): m_1 = m (1/3)√(5/2)(l/H) tanh(√(5/2) H/l) = 0.527 m (l/H) tanh(1.58 H/l).
pub fn convective_mass(density: f64, half_width: f64, depth: f64) -> f64 {
    2.0 * density * half_width * depth * C5 / 3.0 * half_width / depth
        * (C5 * depth / half_width).tanh()
}

/// Housner heights above the bottom (m), bottom pressure excluded:
/// (h_i = 3H/8, h_c = H[1 − (cosh x − 1)/(x sinh x)], x = √(5/2) H/l).
pub fn heights(half_width: f64, depth: f64) -> (f64, f64) {
    let x = C5 * depth / half_width;
    (
        0.375 * depth,
        depth * (1.0 - (x.cosh() - 1.0) / (x * x.sinh())),
    )
}

/// Surface slope s (rad, = dζ/dx) of Housner's convective mode for a convective-mass
/// displacement A₁ (m): s = √(5/2) tanh(√(5/2) H/l) A₁/l (Housner 1963, Eq. 6.13 form).
pub fn slope_from_convective_displacement(half_width: f64, depth: f64, displacement: f64) -> f64 {
    C5 * (C5 * depth / half_width).tanh() * displacement / half_width
}

#[cfg(test)]
mod tests {
    use super::*;

    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut s = f(a) + f(b);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(a + i as f64 * h);
        }
        s * h / 3.0
    }

    #[test]
    fn impulsive_base_shear_equals_integrated_pressure() {
        // Paper tank l = H = 0.5, a = AΩ² = 0.0093·5.311² = 0.262322 m/s².
        // Hand: (2/√3)·1000·0.262322·0.25·tanh(√3) = 1.154701·65.5806·0.939296 = 71.1293 N/m.
        // Simpson of a quadratic in h is exact: 1e-9 relative.
        let (rho, a, h, l) = (1000.0, 0.0093 * 5.311f64.powi(2), 0.5, 0.5);
        let closed = impulsive_base_shear(rho, a, h, l);
        assert!((closed - 71.1293).abs() < 1e-3, "{closed}");
        let right = simpson(|d| impulsive_pressure(rho, a, h, l, l, d), 0.0, h, 10);
        let left = simpson(|d| impulsive_pressure(rho, a, h, l, -l, d), 0.0, h, 10);
        assert!(((right - left) - closed).abs() < 1e-9 * closed);
        // equals m_i a with m_i = 500·0.542304 = 271.152 kg/m
        assert!((impulsive_mass(rho, l, h) - 271.152).abs() < 1e-2);
        assert!((impulsive_mass(rho, l, h) * a - closed).abs() < 1e-9 * closed);
    }

    #[test]
    fn convective_base_shear_equals_integrated_pressure() {
        // Simpson with 200 panels on cosh (error ~1e-10); closed form (2/3)ρl³ω²s.
        let (rho, l, h) = (1000.0, 0.5, 0.5);
        let w = convective_omega(l, h, 9.81);
        // hand: ω² = 19.62·1.581139·tanh(1.581139) = 31.0219·0.918784 = 28.5024 → ω = 5.33876
        assert!((w - 5.33876).abs() < 1e-4, "{w}");
        let s = 0.1;
        let closed = convective_base_shear(rho, l, w, s);
        let right = simpson(|y| convective_pressure(rho, l, h, w, s, l, y), 0.0, h, 200);
        let left = simpson(|y| convective_pressure(rho, l, h, w, s, -l, y), 0.0, h, 200);
        assert!(((right - left) - closed).abs() < 1e-8 * closed.abs());
        // Force = m_1 ω² A₁ with A₁ from the slope relation (Housner 1963): consistency, 1e-12
        let a1 = s / slope_from_convective_displacement(l, h, 1.0);
        assert!((convective_mass(rho, l, h) * w * w * a1 - closed).abs() < 1e-9 * closed);
        // top of wall: p ≈ ρ g (5/6) l s (plane surface ζ = l s at the wall, cubic shape factor)
        let top = convective_pressure(rho, l, h, w, s, l, h);
        assert!((top - rho * 9.81 * 5.0 / 6.0 * l * s).abs() < 1e-9 * top);
    }

    #[test]
    fn masses_and_heights_by_hand() {
        // m_1/m = 0.527046·(l/H)·tanh(1.581139 H/l) = 0.527046·0.918784 = 0.484241 (l = H); 1e-5.
        let m = 500.0;
        assert!((convective_mass(1000.0, 0.5, 0.5) / m - 0.484241).abs() < 1e-5);
        // h_c = H[1 − (cosh 1.581139 − 1)/(1.581139 sinh 1.581139)] = 0.5(1 − 1.533114/(1.581139·2.327374))
        //     = 0.291691 m (hand); 1e-5.
        let (hi, hc) = heights(0.5, 0.5);
        assert!((hi - 0.1875).abs() < 1e-12);
        assert!((hc - 0.291691).abs() < 1e-5, "{hc}");
    }
}
