//! Codes of practice: convective period, impulsive/convective masses and heights, sloshing
//! wave height, freeboard check, and the Eurocode 8 elastic response spectrum.
//!
//! Sources: API 650 (12th ed.) Annex E; ACI 350.3-06 ch. 9; ASCE 7-16 §15.7.6;
//! EN 1998-1:2004 §3.2.2.2 (spectrum); EN 1998-4:2006 Annex A (wave height).
//! Accelerations "in g" are dimensionless fractions of g; everything else SI.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Convective (first sloshing) period of a rectangular tank, ACI 350.3-06 Eq. 9-30 form (s):
/// T_c = 2π √(L/(3.16 g tanh(3.16 H/L))), L the inside length along the excitation (m),
/// H the liquid depth (m). (3.16 ≈ √10 approximates π of exact theory; within 0.5 % of it.)
pub fn rectangular_convective_period(length: f64, depth: f64, gravity: f64) -> f64 {
    let lambda = 3.16;
    2.0 * PI * (length / (lambda * gravity * (lambda * depth / length).tanh())).sqrt()
}

/// Convective period of a circular tank, API 650 Annex E / ACI 350.3 (s):
/// T_c = 2π √(D/(3.68 g tanh(3.68 H/D))), D the diameter (m). (3.68 = 2·1.84 ≈ 2ξ₁₁.)
pub fn circular_convective_period(diameter: f64, depth: f64, gravity: f64) -> f64 {
    let lambda = 3.68;
    2.0 * PI * (diameter / (lambda * gravity * (lambda * depth / diameter).tanh())).sqrt()
}

/// API 650 Annex E sloshing period coefficient K_s = 0.578/√(tanh(3.68 H/D)) (dimensionless).
pub fn api650_ks(diameter: f64, depth: f64) -> f64 {
    0.578 / (3.68 * depth / diameter).tanh().sqrt()
}

/// API 650 Annex E convective period in its SI form T_c = 1.8 K_s √D (s, D in metres).
/// This is the g = 9.81 m/s² specialisation of [`circular_convective_period`]:
/// 2π/√(3.68·9.81) = 1.0457 ≈ 1.8·0.578 = 1.0404. (The US-customary form is T_c = K_s √D with
/// D in feet, since 2π/√(3.68·32.2) = 0.577.) Agrees with the exact expression within 0.6 %.
pub fn api650_convective_period_si(diameter: f64, depth: f64) -> f64 {
    1.8 * api650_ks(diameter, depth) * diameter.sqrt()
}

/// Code impulsive/convective masses (as fractions of the liquid mass) and heights above the
/// bottom (as fractions of H, bottom pressure excluded).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CodeMasses {
    /// m_i/m.
    pub impulsive_mass_ratio: f64,
    /// m_c/m.
    pub convective_mass_ratio: f64,
    /// h_i/H.
    pub impulsive_height_ratio: f64,
    /// h_c/H.
    pub convective_height_ratio: f64,
}

fn convective_height_ratio(x: f64) -> f64 {
    1.0 - (x.cosh() - 1.0) / (x * x.sinh())
}

/// ACI 350.3-06 §9.2 rectangular tank (Housner-based), L along the excitation:
/// m_i/m = tanh(0.866 L/H)/(0.866 L/H); m_c/m = 0.264 (L/H) tanh(3.16 H/L);
/// h_i/H = 0.375 for L/H ≥ 1.333, else 0.5 − 0.09375 L/H;
/// h_c/H = 1 − (cosh(3.16 H/L) − 1)/(3.16 (H/L) sinh(3.16 H/L)).
pub fn aci350_rectangular_masses(length: f64, depth: f64) -> CodeMasses {
    let ratio = length / depth;
    let xi = 0.866 * ratio;
    CodeMasses {
        impulsive_mass_ratio: xi.tanh() / xi,
        convective_mass_ratio: 0.264 * ratio * (3.16 / ratio).tanh(),
        impulsive_height_ratio: if ratio >= 1.333 {
            0.375
        } else {
            0.5 - 0.09375 * ratio
        },
        convective_height_ratio: convective_height_ratio(3.16 / ratio),
    }
}

/// API 650 Annex E.6.1.1 circular tank (D/H ≥ 1.333 and slender branches):
/// m_i/m = tanh(0.866 D/H)/(0.866 D/H) for D/H ≥ 1.333, else 1 − 0.218 D/H;
/// m_c/m = 0.230 (D/H) tanh(3.67 H/D); h_i/H = 0.375 (D/H ≥ 1.333) else 0.5 − 0.094 D/H;
/// h_c/H = 1 − (cosh(3.67 H/D) − 1)/((3.67 H/D) sinh(3.67 H/D)).
/// (ACI 350.3 uses the same expressions with 3.68.)
pub fn api650_circular_masses(diameter: f64, depth: f64) -> CodeMasses {
    let ratio = diameter / depth;
    let xi = 0.866 * ratio;
    let broad = ratio >= 1.333;
    CodeMasses {
        impulsive_mass_ratio: if broad {
            xi.tanh() / xi
        } else {
            1.0 - 0.218 * ratio
        },
        convective_mass_ratio: 0.230 * ratio * (3.67 / ratio).tanh(),
        impulsive_height_ratio: if broad { 0.375 } else { 0.5 - 0.094 * ratio },
        convective_height_ratio: convective_height_ratio(3.67 / ratio),
    }
}

/// API 650 E.7.2 / ASCE 7 §15.7.6.1.2 sloshing wave height of a circular tank (m):
/// δ_s = 0.42 D A_f, A_f the convective spectral acceleration in g (incl. importance factor).
pub fn api650_wave_height(diameter: f64, convective_accel_g: f64) -> f64 {
    0.42 * diameter * convective_accel_g
}

/// ACI 350.3-06 Eq. 7-1 sloshing wave height of a rectangular tank (m): d_max = (L/2) C_c I,
/// here with C_c I = A_f the convective spectral acceleration in g.
pub fn aci350_rectangular_wave_height(length: f64, convective_accel_g: f64) -> f64 {
    0.5 * length * convective_accel_g
}

/// ACI 350.3-06 §7.1 Eq. 7-2 sloshing wave height of a circular tank (m): d_max = (D/2) C_c I,
/// D the inner diameter, here with C_c I = A_f the convective spectral acceleration in g (the
/// record's S_a(T_c)/g at 0.5 % damping). The circular form of Eq. 7-1 with D for L. (The
/// stored public pages searched quote ACI 350.3-06's freeboard chapter but not this
/// equation's text; the form is the standard's, as for Eq. 7-1 above.)
pub fn aci350_circular_wave_height(diameter: f64, convective_accel_g: f64) -> f64 {
    0.5 * diameter * convective_accel_g
}

/// EN 1998-4 Annex A (Eq. A.9) peak sloshing wave height of a circular tank (m):
/// d_max = 0.84 R S_e(T_c)/g, `spectral_accel_g` = S_e(T_c)/g at the convective damping (0.5 %).
/// (0.84 R ≈ 2R/(ξ₁₁² − 1) = 0.837 R, the first-mode participation at the wall.)
pub fn ec8_circular_wave_height(radius: f64, spectral_accel_g: f64) -> f64 {
    0.84 * radius * spectral_accel_g
}

/// EN 1998-4 Annex A rectangular tank peak wave height (m): d_max = 0.5 L S_e(T_c)/g, L the
/// length along the excitation (first-mode linear theory gives 4L/π² = 0.405 L; the code's
/// 0.5 L is conservative).
pub fn ec8_rectangular_wave_height(length: f64, spectral_accel_g: f64) -> f64 {
    0.5 * length * spectral_accel_g
}

/// Freeboard verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FreeboardVerdict {
    /// Available ≥ required.
    Ok,
    /// Available < required: the crest reaches the roof.
    Insufficient,
    /// No roof height or no wave height given.
    NotEvaluated,
}

impl std::fmt::Display for FreeboardVerdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FreeboardVerdict::Ok => "OK",
            FreeboardVerdict::Insufficient => "INSUFFICIENT",
            FreeboardVerdict::NotEvaluated => "NOT EVALUATED",
        })
    }
}

/// Freeboard check: available (m, roof height − depth) vs required (m, wave height).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FreeboardCheck {
    /// Available freeboard H′ (m), if the tank height is known.
    pub available: Option<f64>,
    /// Required freeboard (m) = design sloshing wave height, if known.
    pub required: Option<f64>,
    /// Verdict.
    pub verdict: FreeboardVerdict,
}

/// Compare available and required freeboard (m). API 650 E.7.2 and ACI 350.3 §7.1 require
/// the freeboard to be at least the sloshing wave height (API also allows a reduced
/// freeboard for some seismic use groups when the roof is designed for the slosh load).
pub fn freeboard_check(available: Option<f64>, required: Option<f64>) -> FreeboardCheck {
    let verdict = match (available, required) {
        (Some(a), Some(r)) if a >= r => FreeboardVerdict::Ok,
        (Some(_), Some(_)) => FreeboardVerdict::Insufficient,
        _ => FreeboardVerdict::NotEvaluated,
    };
    FreeboardCheck {
        available,
        required,
        verdict,
    }
}

/// Ground type of EN 1998-1 Table 3.2 (Type 1 spectrum, M_s > 5.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Ec8GroundType {
    /// Rock.
    A,
    /// Very dense sand/gravel or very stiff clay.
    B,
    /// Dense/medium-dense sand, gravel or stiff clay.
    C,
    /// Loose-to-medium cohesionless soil or soft-to-firm cohesive soil.
    D,
    /// Surface alluvium over stiffer material.
    E,
}

/// Parameters of an EC8 elastic spectrum shape: soil factor S and corner periods (s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ec8SpectrumShape {
    /// Soil factor S (–).
    pub soil_factor: f64,
    /// T_B (s), start of the constant-acceleration plateau.
    pub t_b: f64,
    /// T_C (s), end of the plateau.
    pub t_c: f64,
    /// T_D (s), start of the constant-displacement branch.
    pub t_d: f64,
}

impl Ec8GroundType {
    /// Type 1 spectrum parameters, EN 1998-1 Table 3.2.
    pub fn type1_shape(self) -> Ec8SpectrumShape {
        let (s, tb, tc) = match self {
            Ec8GroundType::A => (1.0, 0.15, 0.4),
            Ec8GroundType::B => (1.2, 0.15, 0.5),
            Ec8GroundType::C => (1.15, 0.20, 0.6),
            Ec8GroundType::D => (1.35, 0.20, 0.8),
            Ec8GroundType::E => (1.4, 0.15, 0.5),
        };
        Ec8SpectrumShape {
            soil_factor: s,
            t_b: tb,
            t_c: tc,
            t_d: 2.0,
        }
    }
}

/// Damping correction η = √(10/(5 + ξ[%])) ≥ 0.55 (EN 1998-1 Eq. 3.6); `damping_ratio` ξ as a
/// fraction (0.005 for convective sloshing per EN 1998-4 A.3.2.1 → η = 1.348).
pub fn ec8_damping_correction(damping_ratio: f64) -> f64 {
    (10.0 / (5.0 + 100.0 * damping_ratio)).sqrt().max(0.55)
}

/// EN 1998-1 §3.2.2.2 horizontal elastic response spectrum S_e(T) (m/s², same unit as a_g):
/// 0 ≤ T ≤ T_B: a_g S [1 + T/T_B (2.5η − 1)]; T_B–T_C: 2.5 a_g S η;
/// T_C–T_D: 2.5 a_g S η T_C/T; T > T_D: 2.5 a_g S η T_C T_D/T² (the code's range ends at 4 s;
/// the last branch is extended beyond it, as long-period sloshing needs).
/// `design_ground_accel` a_g (m/s², on rock), `period` T (s), `damping_ratio` ξ (fraction).
pub fn ec8_elastic_spectrum(
    period: f64,
    design_ground_accel: f64,
    shape: Ec8SpectrumShape,
    damping_ratio: f64,
) -> f64 {
    let eta = ec8_damping_correction(damping_ratio);
    let base = design_ground_accel * shape.soil_factor;
    let t = period.max(0.0);
    if t <= shape.t_b {
        base * (1.0 + t / shape.t_b * (2.5 * eta - 1.0))
    } else if t <= shape.t_c {
        2.5 * base * eta
    } else if t <= shape.t_d {
        2.5 * base * eta * shape.t_c / t
    } else {
        2.5 * base * eta * shape.t_c * shape.t_d / (t * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn convective_periods_by_hand() {
        // Rect L = 1, H = 0.5: 2π√(1/(3.16·9.81·tanh 1.58)) = 1.177438 s (hand); exact
        // potential theory 1.1818 s (0.4 % apart, the 3.16-vs-π approximation). 1e-5 s.
        assert!((rectangular_convective_period(1.0, 0.5, 9.81) - 1.177438).abs() < 1e-5);
        // Circle D = 1, H = 0.5: 1.072452 s (hand); exact theory 2π/5.8609 = 1.0720 s.
        assert!((circular_convective_period(1.0, 0.5, 9.81) - 1.072452).abs() < 1e-5);
        // D = 30 m, H = 15 m: K_s = 0.578/√tanh(1.84) = 0.592767, 1.8 K_s √30 = 5.844098 s;
        // the 2π form gives 5.874063 s — 0.5 % apart, as the SI constants predict.
        assert!((api650_ks(30.0, 15.0) - 0.592767).abs() < 1e-6);
        assert!((api650_convective_period_si(30.0, 15.0) - 5.844098).abs() < 1e-5);
        assert!((circular_convective_period(30.0, 15.0, 9.81) - 5.874063).abs() < 1e-5);
    }

    #[test]
    fn code_masses_by_hand() {
        // D/H = 2: m_i/m = tanh(1.732)/1.732 = 0.542316; m_c/m = 0.46 tanh(1.835) = 0.437144;
        // h_c/H = 0.605061 (hand). 1e-5: 6-digit hand values.
        let c = api650_circular_masses(1.0, 0.5);
        assert!((c.impulsive_mass_ratio - 0.542316).abs() < 1e-5);
        assert!((c.convective_mass_ratio - 0.437144).abs() < 1e-5);
        assert!((c.impulsive_height_ratio - 0.375).abs() < 1e-12);
        assert!((c.convective_height_ratio - 0.605061).abs() < 1e-5);
        // slender branch D/H = 1: m_i/m = 1 − 0.218 = 0.782, h_i/H = 0.406
        let s = api650_circular_masses(1.0, 1.0);
        assert!((s.impulsive_mass_ratio - 0.782).abs() < 1e-12);
        assert!((s.impulsive_height_ratio - 0.406).abs() < 1e-12);
        // ACI rect L/H = 2: m_c/m = 0.528 tanh(1.58) = 0.485022, h_c/H = 0.583285
        let r = aci350_rectangular_masses(1.0, 0.5);
        assert!((r.convective_mass_ratio - 0.485022).abs() < 1e-5);
        assert!((r.convective_height_ratio - 0.583285).abs() < 1e-5);
    }

    #[test]
    fn wave_heights_and_freeboard() {
        // δ_s = 0.42·30·0.1 = 1.26 m; EC8 0.84·15·0.1 = 1.26 m; rect 0.5·10·0.2 = 1.0 m.
        assert!((api650_wave_height(30.0, 0.1) - 1.26).abs() < 1e-12);
        assert!((ec8_circular_wave_height(15.0, 0.1) - 1.26).abs() < 1e-12);
        assert!((ec8_rectangular_wave_height(10.0, 0.2) - 1.0).abs() < 1e-12);
        assert!((aci350_rectangular_wave_height(10.0, 0.2) - 1.0).abs() < 1e-12);
        // ACI 350.3-06 Eq. 7-2, circular: (D/2) C_c I = (24/2)·0.15 = 1.8 m by hand; API's
        // 0.42 D A_f for the same tank is 0.42·24·0.15 = 1.512 m.
        assert!((aci350_circular_wave_height(24.0, 0.15) - 1.8).abs() < 1e-12);
        assert!((api650_wave_height(24.0, 0.15) - 1.512).abs() < 1e-12);
        assert_eq!(
            freeboard_check(Some(1.3), Some(1.26)).verdict,
            FreeboardVerdict::Ok
        );
        assert_eq!(
            freeboard_check(Some(1.0), Some(1.26)).verdict,
            FreeboardVerdict::Insufficient
        );
        assert_eq!(
            freeboard_check(None, Some(1.26)).verdict,
            FreeboardVerdict::NotEvaluated
        );
    }

    #[test]
    fn ec8_spectrum_branches() {
        // Ground B (S = 1.2, T_B 0.15, T_C 0.5, T_D 2), a_g = 2 m/s²:
        // ξ = 5 %: plateau 2.5·2·1.2 = 6.0; T = 0.05: 2.4(1 + (1/3)(1.5)) = 3.6 m/s².
        // ξ = 0.5 %: η = √(10/5.5) = 1.348400; T = 3 s: 2.5·2.4·1.3484·0.5·2/9 = 0.898933 m/s².
        let b = Ec8GroundType::B.type1_shape();
        assert!((ec8_elastic_spectrum(0.3, 2.0, b, 0.05) - 6.0).abs() < 1e-12);
        assert!((ec8_elastic_spectrum(0.05, 2.0, b, 0.05) - 3.6).abs() < 1e-12);
        assert!((ec8_damping_correction(0.005) - 1.348400).abs() < 1e-6);
        assert!((ec8_elastic_spectrum(3.0, 2.0, b, 0.005) - 0.898933).abs() < 1e-6);
        // T = 0: S_e = a_g S (rigid); η floor 0.55 at ξ = 30 %
        assert!((ec8_elastic_spectrum(0.0, 2.0, b, 0.005) - 2.4).abs() < 1e-12);
        assert!((ec8_damping_correction(0.30) - 0.55).abs() < 1e-12);
    }
}
