//! Peak sloshing pressure on a fixed roof: Malhotra (2005) and Kurihara et al. (1991), the
//! paper's Eq. 27 and Eq. 28. Evaluated, as in the paper §3.2, from the crest geometry and
//! velocity of the liquid just before it hits the roof.

use std::f64::consts::FRAC_PI_4;

/// The paper's choice of Malhotra's angle θ (§3.2): π/4.
pub const MALHOTRA_DEFAULT_ANGLE: f64 = FRAC_PI_4;

/// Malhotra (2005) peak roof pressure, paper Eq. 27 (Pa): P_max = ρ g x_f tan θ.
///
/// `contact_extent` x_f (m) is the horizontal extent of the roof in contact with the liquid
/// measured from the wall (Fig. 6), `angle` θ (rad) the free-surface inclination (paper: π/4).
/// Source: P. K. Malhotra, "Sloshing loads in liquid-storage tanks with insufficient
/// freeboard", Earthquake Spectra 21(4) (2005) 1185–1192. A quasi-static (hydrostatic-like)
/// estimate; it does not capture impact peaks at resonance (paper §3.2).
pub fn malhotra_roof_pressure(density: f64, gravity: f64, contact_extent: f64, angle: f64) -> f64 {
    density * gravity * contact_extent * angle.tan()
}

/// Kurihara, Masuko & Sakurai (1991) peak roof impact pressure, paper Eq. 28 (Pa), with the
/// unit reading of `docs/roof-loads.md` (the "ρ/g" of Eq. 28 is the mass density ρ_m):
///
/// P = 6.63 ρ_m (H+H′) l/H′ · (0.2l + H + H′)/(0.4l + H + H′)² · v²
///   + 0.35 ρ_m l (H+H′)/(0.4l + H + H′) · ω v
///
/// `density` ρ_m (kg/m³), `depth` H (m), `freeboard` H′ (m, still surface to roof),
/// `half_width` l (m; half-width of a 2D tank or the radius), `crest_velocity` v (m/s, crest
/// just before impact), `omega` ω (rad/s, sloshing circular frequency).
/// Source: "Sloshing impact pressures of roofed liquid storage tanks", Structural Eng./
/// Earthquake Eng. (JSCE) 8(2) (1991) 95–102; derived for flat roofs, H′ > 0.
pub fn kurihara_roof_pressure(
    density: f64,
    depth: f64,
    freeboard: f64,
    half_width: f64,
    crest_velocity: f64,
    omega: f64,
) -> f64 {
    let (h, hp, l, v) = (depth, freeboard, half_width, crest_velocity);
    let total = h + hp;
    let denom = 0.4 * l + total;
    6.63 * density * total * l / hp * (0.2 * l + total) / (denom * denom) * v * v
        + 0.35 * density * l * total / denom * omega * v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn malhotra_by_hand() {
        // ρ g x_f tan(π/4) = 1000·9.81·0.1·1 = 981 Pa; 1e-9 = round-off of tan(π/4).
        assert!(
            (malhotra_roof_pressure(1000.0, 9.81, 0.1, MALHOTRA_DEFAULT_ANGLE) - 981.0).abs()
                < 1e-9
        );
        // θ = π/3: tan = 1.732051 → 1699.14 Pa
        assert!(
            (malhotra_roof_pressure(1000.0, 9.81, 0.1, std::f64::consts::FRAC_PI_3) - 1699.14)
                .abs()
                < 0.01
        );
    }

    #[test]
    fn kurihara_paper_tank_by_hand() {
        // Paper §3.2 tank, roof at 0.6 m: l = 0.5, H = 0.5, H′ = 0.1, v = 1 m/s, ω = 5.311.
        // term 1 = 6.63·1000·(0.6·0.5/0.1)·0.7/0.8² = 6630·3·1.09375 = 21754.69 Pa
        // term 2 = 0.35·1000·0.5·0.6/0.8·5.311 = 131.25·5.311 = 697.07 Pa; total 22451.76 Pa.
        // 0.01 Pa: rounding of the hand arithmetic.
        let p = kurihara_roof_pressure(1000.0, 0.5, 0.1, 0.5, 1.0, 5.311);
        assert!((p - 22451.76).abs() < 0.01, "{p}");
        // v = 0: no impact, no pressure
        assert_eq!(
            kurihara_roof_pressure(1000.0, 0.5, 0.1, 0.5, 0.0, 5.311),
            0.0
        );
        // quadratic term dominates: doubling v ≈ 4× term 1 + 2× term 2 = 87018.75 + 1394.14
        let p2 = kurihara_roof_pressure(1000.0, 0.5, 0.1, 0.5, 2.0, 5.311);
        assert!((p2 - 88412.89).abs() < 0.01, "{p2}");
    }
}
