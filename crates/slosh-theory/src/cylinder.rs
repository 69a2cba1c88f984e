//! Upright rigid circular cylindrical tank under horizontal excitation: linear modal
//! response, Veletsos (exact potential-theory) and Housner (1963) impulsive/convective masses.
//!
//! ## Derivation (Ibrahim 2005 §2.4; Veletsos & Yang 1977; Faltinsen & Timokha 2009 ch. 5)
//! Cylinder radius R, depth H, polar coordinates (r, θ) with θ = 0 along the excitation (+x),
//! z upward from the still surface. The body-force potential −f x = −f r cos θ is expanded in
//! the m = 1 sloshing modes: r = Σ_n d_n J₁(ξ_n r/R) on [0, R], with ξ_n the zeros of J₁′ and
//! d_n = 2R/((ξ_n² − 1) J₁(ξ_n)) (Dini series; uses J₀(ξ_n) = J₁(ξ_n)/ξ_n). Then, exactly as for
//! the rectangular tank ([`crate::linear`]), ζ = cos θ Σ β_n J₁(ξ_n r/R) with
//! β̈_n + ω_n² β_n = (ω_n²/g) d_n f, ω_n² = (g ξ_n/R) tanh(ξ_n H/R).
//! Hydrodynamic pressure: p = ρ cos θ [f r − Σ (f d_n − g β_n) J₁(ξ_n r/R) cosh k_n(z+H)/cosh k_nH],
//! k_n = ξ_n/R. Base shear (force of the liquid on the tank along +x):
//! F = ρ π R² H f − ρ π R Σ (f d_n − g β_n) J₁(ξ_n) tanh(k_n H)/k_n.
//! Modes above those carried are quasi-static (modal-acceleration method), as in `linear`.
//! Convective mass of mode n: m_n/m = 2 tanh(ξ_n H/R)/(ξ_n (ξ_n² − 1) H/R); impulsive mass
//! m_i = m − Σ m_n (Veletsos & Yang 1977; EN 1998-4 Annex A.3). Valid for small amplitude.

use crate::bessel::bessel_j;
use crate::linear::cosh_ratio;
use crate::modal::{ModalState, ModalTank};
use crate::natural::cylinder_eigenvalue;
use std::f64::consts::PI;

/// Number of J₁′ zeros found by root-finding; higher ones use McMahon's expansion.
const EXACT_ZEROS: usize = 12;
/// Number of modes summed for masses and heights (tail ~ 1/N², < 1e-6 relative).
const MASS_TERMS: usize = 2000;

/// n-th zero (n ≥ 1) of J₁′ from McMahon's asymptotic expansion (A&S 9.5.13, μ = 4m² = 4):
/// ξ ≈ β − (μ+3)/(8β) − 4(7μ² + 82μ − 9)/(3(8β)³), β = (n − 1/4)π.
/// Relative error < 1e-7 for n ≥ 12 (checked in the tests).
fn j1_derivative_zero_asymptotic(n: usize) -> f64 {
    let beta = (n as f64 - 0.25) * PI;
    // A&S 9.5.13 with μ = 4m² = 4: β' − (μ+3)/(8β') − 4(7μ² + 82μ − 9)/(3(8β')³)
    let mu = 4.0;
    let b8 = 8.0 * beta;
    beta - (mu + 3.0) / b8 - 4.0 * (7.0 * mu * mu + 82.0 * mu - 9.0) / (3.0 * b8.powi(3))
}

/// A rigid upright circular cylindrical tank (radius R, depth H) with its m = 1 sloshing
/// eigenvalues precomputed. Forces in N, masses in kg.
#[derive(Clone, Debug, PartialEq)]
pub struct CylindricalTank {
    /// Radius R (m).
    pub radius: f64,
    /// Still liquid depth H (m).
    pub depth: f64,
    /// Liquid density ρ (kg/m³).
    pub density: f64,
    /// Gravity g (m/s²).
    pub gravity: f64,
    eigenvalues: Vec<f64>,
    j1_at_eigenvalues: Vec<f64>,
}

impl CylindricalTank {
    /// Tank of radius R (m), depth H (m), density ρ (kg/m³), gravity g (m/s²).
    pub fn new(radius: f64, depth: f64, density: f64, gravity: f64) -> Self {
        let eigenvalues: Vec<f64> = (1..=EXACT_ZEROS)
            .map(|n| cylinder_eigenvalue(1, n))
            .collect();
        let j1_at_eigenvalues = eigenvalues.iter().map(|&x| bessel_j(1, x)).collect();
        Self {
            radius,
            depth,
            density,
            gravity,
            eigenvalues,
            j1_at_eigenvalues,
        }
    }

    /// Water tank, ρ = 1000 kg/m³, g = 9.81 m/s².
    pub fn water(radius: f64, depth: f64) -> Self {
        Self::new(radius, depth, 1000.0, crate::natural::STANDARD_GRAVITY)
    }

    /// Eigenvalue ξ_1n (n = j + 1), the (j+1)-th zero of J₁′ (exact for j < 12, else McMahon).
    pub fn eigenvalue(&self, j: usize) -> f64 {
        self.eigenvalues
            .get(j)
            .copied()
            .unwrap_or_else(|| j1_derivative_zero_asymptotic(j + 1))
    }

    fn j1_at_eigenvalue(&self, j: usize) -> f64 {
        self.j1_at_eigenvalues
            .get(j)
            .copied()
            .unwrap_or_else(|| bessel_j(1, self.eigenvalue(j)))
    }

    /// Liquid mass m = ρ π R² H (kg).
    pub fn liquid_mass(&self) -> f64 {
        self.density * PI * self.radius * self.radius * self.depth
    }

    /// Free-surface elevation ζ (m) at radius r (m) and azimuth θ (rad, 0 = +x).
    pub fn elevation(&self, s: &ModalState, r: f64, theta: f64) -> f64 {
        let g = self.gravity;
        let mut zeta = r * s.body_force / g;
        for (j, &beta) in s.amplitude.iter().enumerate() {
            let shape = bessel_j(1, self.eigenvalue(j) * r / self.radius);
            zeta += (beta - self.modal_coefficient(j) * s.body_force / g) * shape;
        }
        zeta * theta.cos()
    }

    /// Wall elevation (m) on the excitation axis at θ = 0 (the +x wall); the −x wall is its negative.
    pub fn wall_elevation(&self, s: &ModalState) -> f64 {
        let g = self.gravity;
        let mut zeta = self.radius * s.body_force / g;
        for (j, &beta) in s.amplitude.iter().enumerate() {
            zeta +=
                (beta - self.modal_coefficient(j) * s.body_force / g) * self.j1_at_eigenvalue(j);
        }
        zeta
    }

    /// Vertical surface velocity ∂ζ/∂t (m/s) at the wall, θ = 0.
    pub fn wall_elevation_rate(&self, s: &ModalState) -> f64 {
        let g = self.gravity;
        let mut rate = self.radius * s.body_force_rate / g;
        for (j, &beta_rate) in s.amplitude_rate.iter().enumerate() {
            rate += (beta_rate - self.modal_coefficient(j) * s.body_force_rate / g)
                * self.j1_at_eigenvalue(j);
        }
        rate
    }

    /// Hydrodynamic pressure (Pa, hydrostatic excluded) at (r, θ, z), z ∈ [−H, 0] from the still surface.
    pub fn pressure(&self, s: &ModalState, r: f64, theta: f64, z: f64) -> f64 {
        let (rho, g, f) = (self.density, self.gravity, s.body_force);
        let mut p = f * r;
        for (j, &beta) in s.amplitude.iter().enumerate() {
            let xi = self.eigenvalue(j);
            let k = xi / self.radius;
            p -= (f * self.modal_coefficient(j) - g * beta)
                * bessel_j(1, xi * r / self.radius)
                * cosh_ratio(k, z, self.depth);
        }
        rho * p * theta.cos()
    }

    /// Horizontal force of the liquid on the tank along +x (N), "base shear".
    pub fn base_shear(&self, s: &ModalState) -> f64 {
        let (rho, g, f) = (self.density, self.gravity, s.body_force);
        let mut force = f * self.liquid_mass();
        for (j, &beta) in s.amplitude.iter().enumerate() {
            let k = self.eigenvalue(j) / self.radius;
            force -= rho
                * PI
                * self.radius
                * (f * self.modal_coefficient(j) - g * beta)
                * self.j1_at_eigenvalue(j)
                * (k * self.depth).tanh()
                / k;
        }
        force
    }

    /// Convective mass of mode (1, j+1) (kg): m_n = m · 2 tanh(ξ_n H/R)/(ξ_n(ξ_n² − 1) H/R)
    /// (Veletsos & Yang 1977; EN 1998-4 Eq. A.12 form).
    pub fn convective_mass(&self, j: usize) -> f64 {
        let xi = self.eigenvalue(j);
        let hr = self.depth / self.radius;
        self.liquid_mass() * 2.0 * (xi * hr).tanh() / (xi * (xi * xi - 1.0) * hr)
    }

    /// Height (m) above the bottom of mode j's wall force, bottom pressure excluded:
    /// h_n = H[1 − tanh(ξ_n H/(2R))/(ξ_n H/R)].
    pub fn convective_height(&self, j: usize) -> f64 {
        let x = self.eigenvalue(j) * self.depth / self.radius;
        self.depth * (1.0 - (0.5 * x).tanh() / x)
    }

    /// Impulsive mass m_i = m − Σ_n m_n (kg), exact potential theory (Veletsos & Yang 1977).
    pub fn impulsive_mass(&self) -> f64 {
        let mut m = self.liquid_mass();
        for j in 0..MASS_TERMS {
            m -= self.convective_mass(j);
        }
        m
    }

    /// Impulsive height (m) above the bottom, bottom pressure excluded, from the moment of the
    /// quasi-static wall pressure (arm H/2): h_i = (m H/2 − Σ m_n h_n)/m_i.
    pub fn impulsive_height(&self) -> f64 {
        let mut moment = self.liquid_mass() * 0.5 * self.depth;
        for j in 0..MASS_TERMS {
            moment -= self.convective_mass(j) * self.convective_height(j);
        }
        moment / self.impulsive_mass()
    }
}

impl ModalTank for CylindricalTank {
    fn gravity(&self) -> f64 {
        self.gravity
    }
    /// ω_n² = (g ξ_n/R) tanh(ξ_n H/R).
    fn modal_omega(&self, j: usize) -> f64 {
        let xi = self.eigenvalue(j);
        (self.gravity * xi / self.radius * (xi * self.depth / self.radius).tanh()).sqrt()
    }
    /// d_n = 2R/((ξ_n² − 1) J₁(ξ_n)).
    fn modal_coefficient(&self, j: usize) -> f64 {
        let xi = self.eigenvalue(j);
        2.0 * self.radius / ((xi * xi - 1.0) * self.j1_at_eigenvalue(j))
    }
}

/// Housner (1963, TID-7024 ch. 6) cylinder: impulsive mass ratio m_i/m = tanh(√3 R/H)/(√3 R/H).
/// Approximate ("membrane") theory; valid for all H/R, within ≈ 5–10 % of exact theory.
pub fn housner_cylinder_impulsive_mass_ratio(radius: f64, depth: f64) -> f64 {
    let x = 3f64.sqrt() * radius / depth;
    x.tanh() / x
}

/// Housner (1963) cylinder: first convective mass ratio m_1/m = (1/4)√(27/8)(R/H) tanh(√(27/8) H/R)
/// = 0.4593 (R/H) tanh(1.837 H/R).
pub fn housner_cylinder_convective_mass_ratio(radius: f64, depth: f64) -> f64 {
    let c = (27.0f64 / 8.0).sqrt();
    0.25 * c * radius / depth * (c * depth / radius).tanh()
}

/// Housner (1963) cylinder: convective circular frequency ω² = (g/R)√(27/8) tanh(√(27/8) H/R) (rad/s).
pub fn housner_cylinder_convective_omega(radius: f64, depth: f64, gravity: f64) -> f64 {
    let c = (27.0f64 / 8.0).sqrt();
    (gravity / radius * c * (c * depth / radius).tanh()).sqrt()
}

/// Housner (1963) cylinder heights above the bottom (m), bottom pressure excluded:
/// (impulsive h_0 = 3H/8, convective h_1 = H[1 − (cosh x − 1)/(x sinh x)], x = √(27/8) H/R).
pub fn housner_cylinder_heights(radius: f64, depth: f64) -> (f64, f64) {
    let x = (27.0f64 / 8.0).sqrt() * depth / radius;
    (
        0.375 * depth,
        depth * (1.0 - (x.cosh() - 1.0) / (x * x.sinh())),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modal::{sine_response, time_history_response};

    #[test]
    fn eigenvalues_and_asymptotics() {
        // A&S Table 9.5: j′_{1,1..3}; McMahon at n = 12 vs root-finding, 1e-7 relative.
        let tank = CylindricalTank::water(0.5, 0.5);
        assert!((tank.eigenvalue(0) - 1.841184).abs() < 1e-6);
        assert!((tank.eigenvalue(1) - 5.331443).abs() < 1e-6);
        assert!((tank.eigenvalue(2) - 8.536316).abs() < 1e-6);
        let exact = cylinder_eigenvalue(1, 12);
        assert!((j1_derivative_zero_asymptotic(12) / exact - 1.0).abs() < 1e-7);
        // first-mode frequency of R = H = 0.5: 5.8609 rad/s (hand, see natural.rs)
        assert!((tank.modal_omega(0) - 5.8609).abs() < 1e-3);
    }

    #[test]
    fn masses_match_eurocode_table() {
        // EN 1998-4 Table A.2 (Veletsos exact theory), H/R = 0.5: m_i/m = 0.300;
        // H/R = 1.0: m_i/m = 0.548. Tolerance 0.002: the table's 3-decimal rounding.
        let t = CylindricalTank::water(1.0, 0.5);
        assert!((t.impulsive_mass() / t.liquid_mass() - 0.300).abs() < 0.002);
        let t = CylindricalTank::water(1.0, 1.0);
        assert!((t.impulsive_mass() / t.liquid_mass() - 0.548).abs() < 0.002);
        // first convective mass, hand: 2 tanh(1.841184)/(1.841184·2.389958) = 0.432195
        assert!((t.convective_mass(0) / t.liquid_mass() - 0.432195).abs() < 1e-5);
    }

    #[test]
    fn housner_cylinder_formulas_by_hand() {
        // R = H: m_i/m = tanh(√3)/√3 = 0.939296/1.732051 = 0.542304;
        // m_1/m = 0.25·1.837117·tanh(1.837117) = 0.459279·0.950517 = 0.436553 (hand; 1e-5).
        assert!((housner_cylinder_impulsive_mass_ratio(1.0, 1.0) - 0.542304).abs() < 1e-5);
        assert!((housner_cylinder_convective_mass_ratio(1.0, 1.0) - 0.436553).abs() < 1e-5);
        let (hi, hc) = housner_cylinder_heights(1.0, 1.0);
        assert!((hi - 0.375).abs() < 1e-12);
        // h_1 = 1 − (cosh x − 1)/(x sinh x), x = 1.837117: 1 − 2.218845/(1.837117·3.059569)
        // = 0.605243 (hand); 1e-5.
        assert!((hc - 0.605243).abs() < 1e-5, "{hc}");
    }

    #[test]
    fn static_tilt_and_rigid_base_shear() {
        // A constant body force f (reached slowly, damped) tilts the surface to ζ = f x/g and
        // the whole mass acts rigidly: f = 0.981 → ζ_wall = 0.1 R = 0.05 m, F = m f.
        // 1e-5 m: decayed transient; 1e-3 relative for F.
        let tank = CylindricalTank::water(0.5, 0.5);
        let dt = 0.01;
        let f: Vec<f64> = (0..3000)
            .map(|k| 0.981 * (k as f64 * dt / 2.0).min(1.0))
            .collect();
        let last = time_history_response(&tank, dt, &f, 6, 0.1).pop().unwrap();
        assert!((tank.wall_elevation(&last) - 0.05).abs() < 1e-5);
        let m = tank.liquid_mass();
        assert!((tank.base_shear(&last) - m * 0.981).abs() < 1e-3 * m * 0.981);
    }

    #[test]
    fn resonant_wall_elevation_envelope() {
        // At Ω = ω₁ the first mode grows as |Q₁| t/(2ω₁) J₁(ξ₁), Q₁ = (ω₁²/g) d₁ F, so the wall
        // amplitude envelope is (ω₁/(2g)) · 2R/(ξ₁² − 1) · F · t = ω₁ R F t/(g (ξ₁² − 1)).
        // R = H = 0.5, F = 0.1: 5.8609·0.5·0.1·t/(9.81·2.389958) = 0.012499 t (hand).
        // Tolerance 3 %: non-resonant modes add a bounded oscillation of a few mm.
        let tank = CylindricalTank::water(0.5, 0.5);
        let w1 = tank.modal_omega(0);
        let t = 20.0;
        let s = sine_response(&tank, 0.1, w1, t, 6);
        let z = tank.wall_elevation(&s);
        let zd = tank.wall_elevation_rate(&s);
        let env = (z * z + (zd / w1).powi(2)).sqrt();
        assert!((env - 0.012499 * t).abs() < 0.03 * 0.012499 * t, "{env}");
    }

    #[test]
    fn pressure_integrates_to_base_shear() {
        // F = ∫∫ p(R,θ,z) cos θ R dθ dz = π R ∫ p(R,0,z) dz; Simpson, 200 panels (error ~1e-10).
        let tank = CylindricalTank::water(0.5, 0.5);
        let s = sine_response(&tank, 0.3, 5.0, 2.7, 5);
        let n = 200;
        let h = tank.depth / n as f64;
        let mut integral = 0.0;
        for i in 0..=n {
            let z = -tank.depth + i as f64 * h;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            integral += w * tank.pressure(&s, tank.radius, 0.0, z);
        }
        integral *= h / 3.0 * PI * tank.radius;
        assert!((integral - tank.base_shear(&s)).abs() < 1e-6 * tank.base_shear(&s).abs());
    }
}
