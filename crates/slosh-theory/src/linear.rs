//! Linear forced sloshing of a rigid rectangular tank (2D, per metre of tank depth).
//!
//! ## Derivation (Ibrahim 2005 ch. 2; Faltinsen & Timokha 2009 ch. 5)
//! Tank frame, x′ ∈ [0, L] from the left wall, z ∈ [−H, 0] upward from the still surface,
//! uniform body force f(t) along +x per unit mass (f = −a_g). The relative flow has a potential
//! φ with ∇²φ = 0, φ_n = 0 on walls and bottom; linearised Bernoulli gives
//! p/ρ = −φ_t − g z + f (x′ − L/2) (the constant fixed by mass conservation), and at z = 0
//! ζ_t = φ_z, φ_t + g ζ − f (x′ − L/2) = 0. With
//! φ = Σ a_n cos(k_n x′) C_n(z), C_n = cosh k_n(z+H)/cosh k_n H, ζ = Σ β_n cos(k_n x′),
//! k_n = nπ/L, and the cosine series x′ − L/2 = Σ_{n odd} c_n cos(k_n x′), c_n = −4L/(nπ)²,
//! one gets ȧ_n = f c_n − g β_n, β̇_n = k_n tanh(k_n H) a_n, hence
//! β̈_n + ω_n² β_n = (ω_n²/g) c_n f,  ω_n² = g k_n tanh(k_n H)   (odd n only are forced).
//!
//! Hydrodynamic pressure (hydrostatic −ρ g z excluded):
//! p = ρ f (x′ − L/2) − ρ Σ (f c_n − g β_n) cos(k_n x′) C_n(z).
//! Its part proportional to f alone (β ≡ 0) is the *impulsive* (rigid-lid, p = 0 on z = 0)
//! pressure, which is summed here in its fast form over vertical eigenfunctions
//! p_i = −(2ρf/H) Σ_m sin(λ_m z)/λ_m² · sinh λ_m(x′−L/2)/cosh(λ_m L/2), λ_m = (2m−1)π/(2H);
//! the rest is *convective*. Horizontal force of the liquid on the tank (base shear, N/m):
//! F = ρ f L H + 2ρ Σ (f c_n − g β_n) tanh(k_n H)/k_n = ρ L H f + 2ρ Σ β̈_n/k_n²,
//! impulsive part F_i = (4ρ f/H) Σ_m tanh(λ_m L/2)/λ_m³.
//!
//! ## Truncation
//! With N modes carried, the modes above N are taken as quasi-static (β_n = c_n f/g; the
//! "modal acceleration" method). Then ζ, p and F above are exact sums truncated at N, and the
//! result is exact both for slow loads (any N) and resonant loads (dominated by n = 1).
//! Valid while ζ ≪ H and ζ ≪ L (small slopes); no damping unless a modal ratio is given.

use crate::modal::{ModalState, ModalTank};
use crate::natural::{rectangular_omega, rectangular_wavenumber};
use std::f64::consts::PI;

/// Number of vertical eigenfunctions summed for the impulsive (rigid-lid) pressure:
/// the series converges like 1/m², truncation error ≲ 2/(π² M) ≈ 1e-4 of ρ|f|H at the wall top.
const IMPULSIVE_TERMS: usize = 2000;

/// A rigid rectangular tank of full width `width` L (m) along the excitation, still liquid
/// depth `depth` H (m), liquid density `density` ρ (kg/m³) and gravity `gravity` g (m/s²).
/// All forces are per metre of tank length normal to the plane (N/m), masses kg/m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectangularTank {
    /// Full width L (m) in the direction of excitation (L = 2l in the paper).
    pub width: f64,
    /// Still liquid depth H (m).
    pub depth: f64,
    /// Liquid density ρ (kg/m³).
    pub density: f64,
    /// Gravity g (m/s²).
    pub gravity: f64,
}

/// cosh(k(z+H))/cosh(kH) evaluated without overflow (z ≤ 0).
pub(crate) fn cosh_ratio(k: f64, z: f64, depth: f64) -> f64 {
    ((k * z).exp() + (-k * (z + 2.0 * depth)).exp()) / (1.0 + (-2.0 * k * depth).exp())
}

impl RectangularTank {
    /// Tank with water (ρ = 1000 kg/m³) and g = 9.81 m/s².
    pub fn water(width: f64, depth: f64) -> Self {
        Self {
            width,
            depth,
            density: 1000.0,
            gravity: crate::natural::STANDARD_GRAVITY,
        }
    }

    /// Mode number n = 2j + 1 of the j-th excited (antisymmetric) mode.
    pub fn mode_number(j: usize) -> usize {
        2 * j + 1
    }

    /// Wavenumber k_n = nπ/L (1/m) of the j-th excited mode (n = 2j+1).
    pub fn modal_wavenumber(&self, j: usize) -> f64 {
        rectangular_wavenumber(self.width, Self::mode_number(j))
    }

    /// Liquid mass per metre of tank length, ρ L H (kg/m).
    pub fn liquid_mass(&self) -> f64 {
        self.density * self.width * self.depth
    }

    /// Free-surface elevation ζ(x′, t) (m) above the still level, x′ (m) from the left wall.
    pub fn elevation(&self, s: &ModalState, x: f64) -> f64 {
        let g = self.gravity;
        let mut zeta = (x - 0.5 * self.width) * s.body_force / g;
        for (j, &beta) in s.amplitude.iter().enumerate() {
            let c = self.modal_coefficient(j);
            zeta += (beta - c * s.body_force / g) * (self.modal_wavenumber(j) * x).cos();
        }
        zeta
    }

    /// Vertical free-surface velocity ∂ζ/∂t (m/s) at x′ (m).
    pub fn elevation_rate(&self, s: &ModalState, x: f64) -> f64 {
        let g = self.gravity;
        let mut rate = (x - 0.5 * self.width) * s.body_force_rate / g;
        for (j, &beta_rate) in s.amplitude_rate.iter().enumerate() {
            let c = self.modal_coefficient(j);
            rate += (beta_rate - c * s.body_force_rate / g) * (self.modal_wavenumber(j) * x).cos();
        }
        rate
    }

    /// Elevations (m) at the left (x′ = 0) and right (x′ = L) walls.
    pub fn wall_elevations(&self, s: &ModalState) -> (f64, f64) {
        (self.elevation(s, 0.0), self.elevation(s, self.width))
    }

    /// Hydrodynamic pressure (Pa, hydrostatic −ρ g z excluded) at x′ ∈ [0, L] (m) and
    /// z ∈ [−H, 0] (m, upward from the still surface): impulsive + convective.
    pub fn pressure(&self, s: &ModalState, x: f64, z: f64) -> f64 {
        let (rho, g, f) = (self.density, self.gravity, s.body_force);
        let mut p = rho * f * (x - 0.5 * self.width);
        for (j, &beta) in s.amplitude.iter().enumerate() {
            let k = self.modal_wavenumber(j);
            let c = self.modal_coefficient(j);
            p -= rho * (f * c - g * beta) * (k * x).cos() * cosh_ratio(k, z, self.depth);
        }
        p
    }

    /// Impulsive (rigid-lid) hydrodynamic pressure (Pa) for body force f (m/s²) at (x′, z).
    pub fn impulsive_pressure(&self, body_force: f64, x: f64, z: f64) -> f64 {
        let h = self.depth;
        let half = 0.5 * self.width;
        let mut sum = 0.0;
        for m in 1..=IMPULSIVE_TERMS {
            let lambda = (2 * m - 1) as f64 * PI / (2.0 * h);
            // sinh(λ(x−L/2))/cosh(λL/2) without overflow
            let shape = ((lambda * (x - 2.0 * half)).exp() - (-lambda * x).exp())
                / (1.0 + (-2.0 * lambda * half).exp());
            sum += (lambda * z).sin() / (lambda * lambda) * shape;
        }
        -2.0 * self.density * body_force / h * sum
    }

    /// Convective hydrodynamic pressure (Pa) = total − impulsive, at (x′, z).
    pub fn convective_pressure(&self, s: &ModalState, x: f64, z: f64) -> f64 {
        self.pressure(s, x, z) - self.impulsive_pressure(s.body_force, x, z)
    }

    /// Horizontal force of the liquid on the tank (N/m, +x), "base shear":
    /// F = ρ f L H + 2ρ Σ (f c_n − g β_n) tanh(k_n H)/k_n.
    pub fn base_shear(&self, s: &ModalState) -> f64 {
        let (rho, g, f) = (self.density, self.gravity, s.body_force);
        let mut force = rho * f * self.width * self.depth;
        for (j, &beta) in s.amplitude.iter().enumerate() {
            let k = self.modal_wavenumber(j);
            let c = self.modal_coefficient(j);
            force += 2.0 * rho * (f * c - g * beta) * (k * self.depth).tanh() / k;
        }
        force
    }

    /// Impulsive base shear (N/m) F_i = (4ρf/H) Σ_m tanh(λ_m L/2)/λ_m³ = m_i f.
    pub fn impulsive_base_shear(&self, body_force: f64) -> f64 {
        body_force * self.impulsive_mass()
    }

    /// Convective base shear (N/m) = total − impulsive.
    pub fn convective_base_shear(&self, s: &ModalState) -> f64 {
        self.base_shear(s) - self.impulsive_base_shear(s.body_force)
    }

    /// Exact (potential-theory) impulsive mass m_i (kg/m): (4ρ/H) Σ_m tanh(λ_m L/2)/λ_m³.
    /// Equals ρLH − Σ_n m_n (checked in tests). Graham & Rodriguez (1952) / Ibrahim 2005 §2.
    pub fn impulsive_mass(&self) -> f64 {
        let h = self.depth;
        let mut sum = 0.0;
        for m in 1..=IMPULSIVE_TERMS {
            let lambda = (2 * m - 1) as f64 * PI / (2.0 * h);
            sum += (0.5 * lambda * self.width).tanh() / lambda.powi(3);
        }
        4.0 * self.density / h * sum
    }

    /// Exact convective mass of excited mode j (kg/m):
    /// m_n = 8 ρ L² tanh(k_n H)/(nπ)³, n = 2j+1 (Graham & Rodriguez 1952).
    pub fn convective_mass(&self, j: usize) -> f64 {
        let n = Self::mode_number(j) as f64;
        let k = self.modal_wavenumber(j);
        8.0 * self.density * self.width * self.width * (k * self.depth).tanh() / (n * PI).powi(3)
    }

    /// Height above the bottom (m) of the resultant wall force of convective mode j,
    /// excluding the bottom pressure: h_n = H[1 − tanh(k_n H/2)/(k_n H)].
    pub fn convective_height(&self, j: usize) -> f64 {
        let kh = self.modal_wavenumber(j) * self.depth;
        self.depth * (1.0 - (0.5 * kh).tanh() / kh)
    }

    /// Height above the bottom (m) of the impulsive wall force (bottom pressure excluded):
    /// from moment balance of the quasi-static state (uniform wall pressure ρ f L/2 ⇒ arm H/2),
    /// h_i = (ρLH·H/2 − Σ_n m_n h_n)/m_i, summed over 2000 modes.
    pub fn impulsive_height(&self) -> f64 {
        let mut moment = self.liquid_mass() * 0.5 * self.depth;
        for j in 0..IMPULSIVE_TERMS {
            moment -= self.convective_mass(j) * self.convective_height(j);
        }
        moment / self.impulsive_mass()
    }
}

impl ModalTank for RectangularTank {
    fn gravity(&self) -> f64 {
        self.gravity
    }
    /// ω_n² = g k_n tanh(k_n H), n = 2j+1.
    fn modal_omega(&self, j: usize) -> f64 {
        rectangular_omega(self.width, self.depth, self.gravity, Self::mode_number(j))
    }
    /// c_n = −4L/(nπ)², n = 2j+1.
    fn modal_coefficient(&self, j: usize) -> f64 {
        let n = Self::mode_number(j) as f64;
        -4.0 * self.width / (n * PI).powi(2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modal::{sine_response, time_history_response};

    fn paper_tank() -> RectangularTank {
        RectangularTank::water(1.0, 0.5)
    }

    #[test]
    fn closed_form_and_time_stepping_agree_for_a_sine() {
        // Same ODE, two exact methods; the stepping interpolates the sine linearly
        // (error ≈ (Ω dt)²/12 ≈ 2e-6 relative at dt = 1e-3), so 1e-4 relative of the peak.
        let tank = paper_tank();
        let (amp, big_w) = (0.3, 4.7);
        let dt = 1e-3;
        let n = 8000;
        let f: Vec<f64> = (0..n)
            .map(|k| amp * (big_w * k as f64 * dt).sin())
            .collect();
        let hist = time_history_response(&tank, dt, &f, 5, 0.0);
        let mut peak = 0.0f64;
        let mut worst = 0.0f64;
        for (k, s) in hist.iter().enumerate().step_by(7) {
            let exact = sine_response(&tank, amp, big_w, k as f64 * dt, 5);
            let (a, b) = (tank.elevation(&exact, 0.0), tank.elevation(s, 0.0));
            peak = peak.max(a.abs());
            worst = worst.max((a - b).abs());
            let (fa, fb) = (tank.base_shear(&exact), tank.base_shear(s));
            assert!((fa - fb).abs() < 1e-4 * 200.0, "base shear {fa} vs {fb}");
        }
        assert!(worst < 1e-4 * peak, "worst {worst}, peak {peak}");
    }

    #[test]
    fn paper_case_resonant_growth() {
        // The paper's §3.1 case, linear theory 0.058, 0.144, 0.288 m at 2, 5, 10 s. These are the first-mode
        // secular envelope |Q₁| t/(2ω₁), Q₁ = (ω₁²/g) c₁ AΩ² (hand: 28.266/9.81 · 0.405285 ·
        // 0.262329 = 0.306337 m/s² → 0.028810 m/s · t). With the paper's body force
        // f = −AΩ² sin Ωt (a = −Aω² sin ωt applied to the particles) the left-wall
        // elevation is ζ(0,t) ≈ −0.0288 t cos(ω₁t): crests at ω₁t = (2k+1)π, i.e. t = 1.77,
        // 5.32, 10.05 s with heights ≈ 0.051, 0.153, 0.289 m.
        let tank = paper_tank();
        let (a, w) = (0.0093, 5.311);
        let force = -a * w * w;
        let crest_near = |t_centre: f64| -> (f64, f64) {
            let mut best = (f64::MIN, 0.0);
            let mut t = t_centre - 0.6;
            while t < t_centre + 0.6 {
                let z = tank.elevation(&sine_response(&tank, force, w, t, 10), 0.0);
                if z > best.0 {
                    best = (z, t);
                }
                t += 1e-3;
            }
            best
        };
        // Tolerances: 3 % for height (higher modes and the 0.1 % detuning of Ω from ω₁ add
        // ≈ 1-2 % to the single-mode envelope), 0.01 s for the crest time (grid 1 ms).
        let (h10, t10) = crest_near(10.0);
        assert!((h10 - 0.289).abs() < 0.03 * 0.289, "crest {h10} at {t10}");
        assert!((t10 - 10.05).abs() < 0.02, "{t10}");
        let (h2, t2) = crest_near(1.9);
        assert!((h2 - 0.051).abs() < 0.005, "crest {h2} at {t2}");
        assert!((t2 - 1.77).abs() < 0.02);
        // Envelope at exactly 2, 5, 10 s after the start of the paper's §3.1 excitation: linear
        // theory's 0.058, 0.144 and 0.288 m, within 2 % (higher modes, detuning).
        for (t, want) in [(2.0, 0.058), (5.0, 0.144), (10.0, 0.288)] {
            let s = sine_response(&tank, force, w, t, 10);
            let z = tank.elevation(&s, 0.0);
            let zd = tank.elevation_rate(&s, 0.0);
            let w1 = tank.modal_omega(0);
            let envelope = (z * z + (zd / w1).powi(2)).sqrt();
            assert!(
                (envelope - want).abs() < 0.02 * want + 0.0015,
                "t={t}: {envelope}"
            );
        }
    }

    #[test]
    fn steady_body_force_gives_hydrostatic_tilt_and_rigid_base_shear() {
        // A constant f reached slowly, with damping, must settle to ζ = f(x′−L/2)/g and
        // F = ρ L H f (rigid mass): for f = 0.981 m/s², ζ(0) = −0.05 m, F = 490.5 N/m.
        // Residual transient e^{−ζωt} < 1e-6 after 30 s with ζ = 0.1, so 1e-5 tolerance.
        let tank = paper_tank();
        let dt = 0.01;
        let f: Vec<f64> = (0..3000)
            .map(|k| 0.981 * (k as f64 * dt / 2.0).min(1.0))
            .collect();
        let last = time_history_response(&tank, dt, &f, 4, 0.1).pop().unwrap();
        assert!((tank.elevation(&last, 0.0) + 0.05).abs() < 1e-5);
        assert!((tank.elevation(&last, 1.0) - 0.05).abs() < 1e-5);
        assert!((tank.base_shear(&last) - 490.5).abs() < 1e-2);
        // wall pressure = ρ g ζ at the surface: 1000·9.81·0.05 = 490.5 Pa at x′ = L, z = 0
        assert!((tank.pressure(&last, 1.0, 0.0) - 490.5).abs() < 1e-2);
    }

    #[test]
    fn impulsive_mass_two_representations_and_wide_tank_limit() {
        // (a) λ-series vs the cosine-mode series ρ[LH − 8L² Σ tanh(nπH/L)/(nπ)³]: independent
        //     forms of the same rigid-lid solution; both truncation errors < 1e-6 here.
        let tank = paper_tank();
        let mut via_modes = tank.liquid_mass();
        for j in 0..20000 {
            via_modes -= tank.convective_mass(j);
        }
        assert!(
            (tank.impulsive_mass() - via_modes).abs() < 1e-3,
            "{via_modes}"
        );
        // (b) L ≫ H: m_i → 4ρH² Σ (2/((2m−1)π))³ = 28 ζ(3) ρH²/π³ = 1.085509 ρH² (hand, ζ(3) =
        //     1.2020569). L/H = 100 leaves tanh(λL/2) = 1 to 1e-60; 1e-5 for the series tail.
        let wide = RectangularTank::water(100.0, 1.0);
        assert!((wide.impulsive_mass() / 1000.0 - 1.085509).abs() < 1e-5);
        // (c) Paper tank by hand: m_i/m = 1 − (16/π³)[tanh(π/2) + tanh(3π/2)/27 + (7ζ(3)/8 − 1 − 1/27)]
        //     = 1 − 0.516025·0.968946 = 0.500000 (tanh(nπ/2) = 1 to 2e-7 for n ≥ 5). Tol 1e-6.
        //     Housner's (1957) approximation tanh(√3 l/H)/(√3 l/H) = 0.54222 is 8 % above it.
        let ratio = tank.impulsive_mass() / tank.liquid_mass();
        assert!((ratio - 0.500000).abs() < 1e-6, "{ratio}");
    }

    #[test]
    fn first_convective_mass_graham_rodriguez() {
        // m₁/m = (8/π³)(L/H) tanh(πH/L) = 0.258012·2·0.917152 = 0.473272 (hand). 1e-5: round-off.
        let tank = paper_tank();
        assert!((tank.convective_mass(0) / tank.liquid_mass() - 0.473272).abs() < 1e-5);
        // h₁ = H[1 − tanh(π/4)/(π/2)] = 0.5·(1 − 0.655794/1.570796) = 0.291254 m (hand)
        assert!((tank.convective_height(0) - 0.291254).abs() < 1e-5);
        // impulsive height, Housner: 3H/8 = 0.1875 m; exact theory within 10 %
        assert!((tank.impulsive_height() - 0.1875).abs() < 0.1 * 0.1875);
    }

    #[test]
    fn pressure_integrates_to_base_shear() {
        // Independent check of the force formula: Simpson integration of p(L,z) − p(0,z)
        // over z ∈ [−H,0] (400 panels, error ~1e-9 of the smooth modal part) vs F.
        let tank = paper_tank();
        let s = sine_response(&tank, 0.26, 5.311, 3.3, 6);
        let n = 400;
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
            integral += w * (tank.pressure(&s, 1.0, z) - tank.pressure(&s, 0.0, z));
        }
        integral *= h / 3.0;
        assert!((integral - tank.base_shear(&s)).abs() < 1e-6 * tank.base_shear(&s).abs().max(1.0));
        // impulsive pressure integrates to the impulsive base shear (series truncation 1e-4)
        let mut imp = 0.0;
        for i in 0..=n {
            let z = -tank.depth + i as f64 * h;
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            imp +=
                w * (tank.impulsive_pressure(1.0, 1.0, z) - tank.impulsive_pressure(1.0, 0.0, z));
        }
        imp *= h / 3.0;
        assert!(
            (imp - tank.impulsive_base_shear(1.0)).abs() < 1e-3 * tank.impulsive_base_shear(1.0)
        );
    }

    #[test]
    fn impulsive_pressure_boundary_conditions() {
        // p_i = 0 on the free surface and ∂p_i/∂x = ρ f at the wall (rigid-wall condition);
        // tolerance: 1st-order finite difference with h = 1e-6, series truncation ~1e-4·ρf.
        let tank = paper_tank();
        assert!(tank.impulsive_pressure(1.0, 1.0, 0.0).abs() < 1e-9);
        let hfd = 1e-6;
        let z = -0.3;
        let dpdx = (tank.impulsive_pressure(1.0, 1.0, z)
            - tank.impulsive_pressure(1.0, 1.0 - hfd, z))
            / hfd;
        assert!((dpdx - 1000.0).abs() < 2.0, "{dpdx}");
    }
}
