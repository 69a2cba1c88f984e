//! Viscous damping of free sloshing in a two-dimensional rectangular tank (laminar, small
//! amplitude, clean free surface, contact line free to slide).
//!
//! The method is the energy balance of Landau & Lifshitz (Fluid Mechanics, §24–25): the
//! liquid moves as the inviscid standing wave φ ∝ cosh k(y + H) cos kx cos ωt, and viscosity
//! dissipates its energy in two places.
//! - In the interior, 2μ Σ (∂²φ/∂x_i∂x_k)² (LL Eq. 25.1): amplitude decay rate 2νk², the
//!   same as for a progressive deep-water wave.
//! - In the Stokes layers of thickness δ = √(2ν/ω) on the no-slip floor and end walls, where
//!   the slip velocity of amplitude U is brought to rest: ½ ρ √(νω/2) U² per unit wall area,
//!   time-averaged (LL Eq. 24.14).
//!
//! With E the wave energy (twice the mean kinetic energy) the amplitude decays as e^{−γt},
//! γ = D̄ / (2E). Over x ∈ [0, L] and y ∈ [−H, 0], with k = nπ/L and s = sinh 2kH:
//! - 2E ∝ ρ k L s / 4;
//! - the floor gives ∝ ρ √(νω/2) k² L / 4;
//! - the two end walls give ∝ ρ √(νω/2) (k s − 2k²H) / 4.
//!
//! Together:
//!
//! γ = 2νk² + √(νω/2) [ k / s + (1 − 2kH/s) / L ].
//!
//! The long-wave limit (kH → 0) is √(νω/8)/H, the floor's share in the damping of long waves in
//! a channel of Landau & Lifshitz §25, problem 1, with the channel infinitely wide. The
//! deep-water limit (kH → ∞) is 2νk² + √(νω/2)/L: the end walls alone.
//!
//! Validity: the Stokes layer is thin, δ ≪ H and δ ≪ L. The neglected terms are of relative
//! order δk (the boundary layer's displacement, and the meniscus and corner flows).
//!
//! With free-slip walls the problem has an exact linear solution, [`free_slip_viscous_mode`]:
//! the standing wave cos kx in a tank of width L is the periodic wave of period 2L (the end
//! walls are its planes of symmetry, where u = 0 and the shear stress vanish), so Lamb's
//! (1932, §349) analysis of a viscous wave carries over with a stress-free floor at depth H.
//! Velocity u = ∇φ + ∇×(ψ ẑ), φ ∝ cosh k(y + H) cos kx, ψ ∝ sinh m(y + H) sin kx with
//! m² = k² + s/ν and e^{st} in time; the stress-free floor removes the other two terms, and
//! the kinematic, shear-free and normal-stress conditions at the surface give
//!
//! (s + 2νk²)² + g k tanh kH = 4ν²k³ m tanh kH coth mH,
//!
//! which for H → ∞ is Lamb's equation (s + 2νk²)² + gk = 4ν²k³m.

use crate::natural::{rectangular_omega, rectangular_wavenumber};
use num_complex::Complex64;

/// Amplitude decay rates (1/s) of a free sloshing mode, by where the energy is dissipated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViscousDecay {
    /// Natural circular frequency ω of the mode (rad/s, inviscid).
    pub omega: f64,
    /// Interior (irrotational) dissipation: 2νk² (1/s).
    pub interior: f64,
    /// The floor's Stokes layer (1/s).
    pub floor: f64,
    /// The two end walls' Stokes layers (1/s).
    pub end_walls: f64,
}

impl ViscousDecay {
    /// Total amplitude decay rate γ (1/s): the amplitude falls as e^{−γt}.
    pub fn rate(&self) -> f64 {
        self.interior + self.floor + self.end_walls
    }

    /// Damping ratio ζ = γ/ω (fraction of critical; the logarithmic decrement is 2πζ).
    pub fn damping_ratio(&self) -> f64 {
        self.rate() / self.omega
    }

    /// Stokes-layer thickness δ = √(2ν/ω) (m) of the liquid `kinematic_viscosity` ν (m²/s).
    pub fn stokes_layer(&self, kinematic_viscosity: f64) -> f64 {
        (2.0 * kinematic_viscosity / self.omega).sqrt()
    }
}

/// Viscous amplitude decay of mode n ≥ 1 of a two-dimensional rectangular tank of full width
/// `width` L (m) and still depth `depth` H (m), with no-slip floor and end walls, for a liquid
/// of kinematic viscosity `kinematic_viscosity` ν (m²/s) under `gravity` g (m/s²). See the
/// module documentation for the formula, its source and its validity (δ ≪ H, L).
pub fn rectangular_viscous_decay(
    width: f64,
    depth: f64,
    kinematic_viscosity: f64,
    gravity: f64,
    mode: usize,
) -> ViscousDecay {
    let k = rectangular_wavenumber(width, mode);
    let omega = rectangular_omega(width, depth, gravity, mode);
    let nu = kinematic_viscosity;
    let s = (2.0 * k * depth).sinh();
    let stokes = (nu * omega / 2.0).sqrt();
    ViscousDecay {
        omega,
        interior: 2.0 * nu * k * k,
        floor: stokes * k / s,
        end_walls: stokes * (1.0 - 2.0 * k * depth / s) / width,
    }
}

/// The exact linear free mode of a viscous liquid in a two-dimensional rectangular tank with
/// free-slip (stress-free) floor and end walls: the complex rate s (1/s) of e^{st}, from the
/// dispersion relation in the module documentation. The amplitude decays as e^{Re(s) t} and
/// oscillates at Im(s) rad/s. `width` L (m), `depth` H (m), `kinematic_viscosity` ν (m²/s),
/// `gravity` g (m/s²), mode n ≥ 1. The oscillating root, found from the inviscid frequency
/// with the decay 2νk²; `None` if no root is found there (ν so large that the mode does not
/// oscillate: ν²k³/g of order one and more).
pub fn free_slip_viscous_mode(
    width: f64,
    depth: f64,
    kinematic_viscosity: f64,
    gravity: f64,
    mode: usize,
) -> Option<Complex64> {
    let k = rectangular_wavenumber(width, mode);
    let omega = rectangular_omega(width, depth, gravity, mode);
    let guess = Complex64::new(-2.0 * kinematic_viscosity * k * k, omega);
    let root = free_slip_root(k, depth, kinematic_viscosity, gravity, guess)?;
    (root.im > 1e-8 * root.norm()).then_some(root)
}

/// A root of the free-slip dispersion relation near `guess` (secant iteration on the complex
/// plane), or `None` if the iteration does not converge.
fn free_slip_root(
    k: f64,
    depth: f64,
    nu: f64,
    gravity: f64,
    guess: Complex64,
) -> Option<Complex64> {
    let tanh_kh = (k * depth).tanh();
    let residual = |s: Complex64| -> Complex64 {
        // Re m > 0: the rotational part decays away from the surface.
        let m = (Complex64::new(k * k, 0.0) + s / nu).sqrt();
        // coth mH = 1 to rounding once Re mH > 20 (and tanh would overflow further on).
        let mh = m * depth;
        let coth_mh = if mh.re > 20.0 {
            Complex64::new(1.0, 0.0)
        } else {
            mh.tanh().inv()
        };
        let lhs = (s + 2.0 * nu * k * k).powi(2) + gravity * k * tanh_kh;
        lhs - 4.0 * nu * nu * k.powi(3) * tanh_kh * m * coth_mh
    };
    let (mut s0, mut s1) = (guess, guess * Complex64::new(1.0 + 1e-3, 1e-3));
    let (mut f0, mut f1) = (residual(s0), residual(s1));
    for _ in 0..100 {
        let df = f1 - f0;
        if df.norm() == 0.0 {
            break;
        }
        let s2 = s1 - f1 * (s1 - s0) / df;
        if !(s2.re.is_finite() && s2.im.is_finite()) {
            return None;
        }
        (s0, f0) = (s1, f1);
        s1 = s2;
        f1 = residual(s1);
        if (s1 - s0).norm() <= 1e-13 * s1.norm().max(1e-300) {
            return Some(s1);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Long waves (kH → 0): Landau & Lifshitz §25 problem 1 give γ = √(νω/8)(a + 2H)/(aH)
    /// for a channel of width a and depth H; without side walls (a → ∞) it is √(νω/8)/H,
    /// all of it from the floor. At kH = π/1000 the end walls and the interior are O(kH)
    /// and O(k²δ²) smaller: within 0.5 %.
    #[test]
    fn long_wave_limit_is_landau_lifshitz_channel_floor() {
        let (width, depth, nu, g) = (1000.0, 1.0, 1.0e-6, 9.81);
        let d = rectangular_viscous_decay(width, depth, nu, g, 1);
        let omega = d.omega;
        let landau = (nu * omega / 8.0).sqrt() / depth;
        assert!(
            (d.rate() / landau - 1.0).abs() < 5e-3,
            "{} vs {landau}",
            d.rate()
        );
        assert!((d.floor / landau - 1.0).abs() < 1e-5);
    }

    /// Deep liquid (kH → ∞): no floor share; the end walls give √(νω/2)/L and the interior
    /// 2νk², the decay of a deep-water wave (Lamb 1932 §348). Exact to rounding at kH = 8π.
    #[test]
    fn deep_limit_is_end_walls_plus_lamb_interior() {
        let (width, depth, nu, g) = (1.0, 8.0, 1.0e-4, 9.81);
        let d = rectangular_viscous_decay(width, depth, nu, g, 1);
        let k = PI / width;
        assert!(((d.interior) - 2.0 * nu * k * k).abs() < 1e-15);
        assert!(d.floor < 1e-12);
        let walls = (nu * d.omega / 2.0).sqrt() / width;
        assert!((d.end_walls / walls - 1.0).abs() < 1e-9);
    }

    /// Lamb (1932) §349: for small ν the decay of a deep-water wave is 2νk² (the leading term
    /// of his root; the next is of relative order √(νk²/ω), here 1.3·10⁻³), the frequency
    /// √(gk). Deep tank (kH = 8π) of water: within 0.5 %.
    #[test]
    fn free_slip_small_viscosity_is_lamb_deep_water_decay() {
        let (width, depth, nu, g) = (1.0, 8.0, 1.0e-6, 9.81);
        let k = PI / width;
        let s = free_slip_viscous_mode(width, depth, nu, g, 1).unwrap();
        assert!((-s.re / (2.0 * nu * k * k) - 1.0).abs() < 5e-3, "{s}");
        assert!((s.im / (g * k).sqrt() - 1.0).abs() < 1e-4, "{s}");
    }

    /// Lamb (1932) §349: a very viscous deep liquid (ν²k³/g ≫ 1) does not oscillate; its slow
    /// root is s = −g/(2νk), the creeping relaxation of the surface. At ν²k³/g = 316 the next
    /// term is of relative order (g/(ν²k³))^{1/2}·… ≈ 3 %: within 5 %. The oscillating-root
    /// search reports no oscillating mode there.
    #[test]
    fn free_slip_very_viscous_is_lamb_creeping_relaxation() {
        let (width, depth, nu, g) = (1.0, 8.0, 10.0, 9.81);
        let k = PI / width;
        let creeping = -g / (2.0 * nu * k);
        let s = free_slip_root(k, depth, nu, g, Complex64::new(0.8 * creeping, 0.0)).unwrap();
        assert!(s.im.abs() < 1e-9 * s.re.abs(), "{s}");
        assert!((s.re / creeping - 1.0).abs() < 0.05, "{s} vs {creeping}");
        let osc = free_slip_viscous_mode(width, depth, nu, g, 1);
        assert!(osc.is_none(), "{osc:?}");
    }

    /// The finite-depth tank agrees with its own small-ν limit: decay 2νk², frequency
    /// √(gk tanh kH), for the 1.0 × 0.5 m tank with ν = 10⁻⁵ m²/s (relative order
    /// √(νk²/ω) ≈ 4·10⁻³): within 1 %.
    #[test]
    fn free_slip_finite_depth_small_viscosity_limit() {
        let (width, depth, nu, g) = (1.0, 0.5, 1.0e-5, 9.81);
        let k = PI / width;
        let s = free_slip_viscous_mode(width, depth, nu, g, 1).unwrap();
        assert!((-s.re / (2.0 * nu * k * k) - 1.0).abs() < 1e-2, "{s}");
        let omega = rectangular_omega(width, depth, g, 1);
        assert!((s.im / omega - 1.0).abs() < 1e-3, "{s}");
    }

    /// Water in a metre-wide tank half full: ζ of order 10⁻⁴, far below the 0.5 % that the
    /// codes assume for the convective mode (EN 1998-4 A.3.2) — the codes' damping is not
    /// laminar wall friction.
    #[test]
    fn water_in_a_metre_tank_is_lightly_damped() {
        let d = rectangular_viscous_decay(1.0, 0.5, 1.0e-6, 9.81, 1);
        assert!(
            d.damping_ratio() > 1e-4 && d.damping_ratio() < 5e-4,
            "{}",
            d.damping_ratio()
        );
        assert!((d.stokes_layer(1.0e-6) - (2.0e-6 / d.omega).sqrt()).abs() < 1e-15);
    }
}
