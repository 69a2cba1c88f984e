//! Linear sloshing of a rigid rectangular tank turned (pitched or rolled) about a horizontal
//! axis through a pivot: the reference of the rotating-frame checks.
//!
//! ## Derivation (the modal method of Faltinsen & Timokha 2009, *Sloshing*, ch. 5)
//! Tank frame, x ∈ [−L/2, L/2] from the tank's centre, z ∈ [−H, 0] upward from the still
//! surface; the tank turns by a small angle θ(t) about the axis y through the pivot
//! (0, z_p), a positive θ lowering the +x wall (right-hand rule about y). The absolute flow
//! has the potential φ = θ̇ Ω₀ + Σ_n β̇_n φ_n, with φ_n = cos k_n(x + L/2) cosh k_n(z+H)/cosh k_n H
//! the natural modes (k_n = nπ/L) and Ω₀ the Stokes–Joukowski potential of the turning
//! tank (∂Ω₀/∂n = (ŷ × (r − r_p))·n on the walls, the bottom and the frozen surface):
//! Ω₀ = x (z − z_p) + Ω̃ with Ω̃ harmonic, ∂Ω̃/∂z = −2x on z = 0 and z = −H. The surface
//! relative to the tank is ζ = Σ_n b_n cos k_n(x + L/2), and the linearised dynamic condition
//! φ_t + g (ζ − θ x) = 0 on z = 0, projected on each mode, gives for odd n
//!
//! b̈_n + ω_n² b_n = (ω_n²/g) c_n f_n(t),   f_n = g θ + θ̈ Z_n,   Z_n = z_p + (2/k_n) tanh(k_n H/2),   (P1)
//!
//! with c_n = −4L/(nπ)² the modal coefficient of a horizontal body force
//! ([`crate::linear`]): a turn acts on mode n as the horizontal body force g θ (gravity
//! turned) plus the tangential acceleration θ̈ Z_n of the mode's lever arm about the pivot.
//! The static limit is the level surface, ζ = θ x; a pivot at height z_p with θ̈ alone is the
//! horizontal ground acceleration −z_p θ̈ of the surface's centre plus the rotation of the
//! liquid column (the tanh term). The centrifugal and Coriolis forces are second order in θ.

use crate::linear::RectangularTank;
use crate::modal::{oscillator_step, ModalTank, OscillatorState};

/// A rectangular tank turned about the y axis through a pivot `pivot_height` (m) above the
/// still surface (negative below it: −H at the bottom).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PitchedRectangularTank {
    /// The tank and its liquid.
    pub tank: RectangularTank,
    /// Height of the pivot above the still surface, z_p (m).
    pub pivot_height: f64,
}

impl PitchedRectangularTank {
    /// Lever arm Z_n (m) of excited mode j (n = 2j + 1) in (P1).
    pub fn modal_lever(&self, j: usize) -> f64 {
        let k = self.tank.modal_wavenumber(j);
        self.pivot_height + 2.0 / k * (0.5 * k * self.tank.depth).tanh()
    }

    /// The surface elevation relative to the tank (m) at `x_from_left` (m from the left wall)
    /// from rest, for the angle θ_k and angular acceleration θ̈_k sampled every `dt` (s): one
    /// value per sample. Each of the first `n_modes` excited modes is stepped exactly for its
    /// force taken linear between samples ([`oscillator_step`], undamped); the modes above
    /// follow their load quasi-statically with the lever of a high mode, Z → z_p (the
    /// truncation of [`crate::linear`]).
    pub fn elevation_history(
        &self,
        dt: f64,
        angle: &[f64],
        angular_acceleration: &[f64],
        x_from_left: f64,
        n_modes: usize,
    ) -> Vec<f64> {
        let g = self.tank.gravity;
        let modes: Vec<(f64, f64, f64, f64)> = (0..n_modes)
            .map(|j| {
                let w = self.tank.modal_omega(j);
                let c = self.tank.modal_coefficient(j);
                let shape = (self.tank.modal_wavenumber(j) * x_from_left).cos();
                (w, w * w / g * c, self.modal_lever(j), c * shape)
            })
            .collect();
        // Σ over all odd n of c_n cos k_n x′ is x′ − L/2; the carried modes' part is taken out
        // to leave the quasi-static tail.
        let carried: f64 = modes.iter().map(|m| m.3).sum();
        let tail = (x_from_left - 0.5 * self.tank.width) - carried;
        let force = |k: usize, lever: f64| g * angle[k] + angular_acceleration[k] * lever;
        let mut states = vec![OscillatorState::default(); n_modes];
        let mut out = Vec::with_capacity(angle.len());
        for k in 0..angle.len().min(angular_acceleration.len()) {
            if k > 0 {
                for (s, &(w, gain, lever, _)) in states.iter_mut().zip(&modes) {
                    *s = oscillator_step(
                        w,
                        0.0,
                        *s,
                        gain * force(k - 1, lever),
                        gain * force(k, lever),
                        dt,
                    );
                }
            }
            let shape_of = |j: usize| (self.tank.modal_wavenumber(j) * x_from_left).cos();
            let resonant: f64 = states
                .iter()
                .enumerate()
                .map(|(j, s)| s.displacement * shape_of(j))
                .sum();
            out.push(resonant + tail * force(k, self.pivot_height) / g);
        }
        out
    }
}

/// A pitch from rest, θ(t) = θ₀ (1 − cos Ωt)/2 (its rate and angle both start at zero), sampled
/// every `dt` (s) at `n` times from 0: the angles θ_k (rad) and angular accelerations
/// θ̈_k = θ₀ Ω² cos(Ωt_k)/2 (rad/s²) that [`PitchedRectangularTank::elevation_history`] takes.
/// `amplitude` is θ₀ (rad), `omega` Ω (rad/s).
pub fn pitch_from_rest(amplitude: f64, omega: f64, dt: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let half = 0.5 * amplitude;
    (0..n)
        .map(|k| {
            let c = (omega * k as f64 * dt).cos();
            (half * (1.0 - c), half * omega * omega * c)
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tank(pivot_height: f64) -> PitchedRectangularTank {
        PitchedRectangularTank {
            tank: RectangularTank::water(1.0, 0.5),
            pivot_height,
        }
    }

    /// A tank tilted slowly to θ keeps its surface level: ζ = θ (x − L/2) relative to the
    /// tank (to the O(θ) of linear theory), whatever the pivot.
    #[test]
    fn slow_tilt_leaves_the_surface_level() {
        for zp in [-0.5, 0.3] {
            let t = tank(zp);
            let dt = 1e-3;
            // A tilt over 40 s (≈ 34 periods), then held.
            let n = 45_000;
            let ramp = 40.0;
            let theta0 = 0.01;
            let (angle, accel): (Vec<f64>, Vec<f64>) = (0..n)
                .map(|k| {
                    let s = (k as f64 * dt / ramp).min(1.0);
                    let w = std::f64::consts::PI / ramp;
                    let th = 0.5 * theta0 * (1.0 - (std::f64::consts::PI * s).cos());
                    let a = if s < 1.0 {
                        0.5 * theta0 * w * w * (std::f64::consts::PI * s).cos()
                    } else {
                        0.0
                    };
                    (th, a)
                })
                .unzip();
            let right = t.elevation_history(dt, &angle, &accel, 1.0, 20);
            let last = *right.last().unwrap();
            // θ L/2 = 5 mm; the slow ramp leaves a free oscillation of order (T₁/ramp)² of it.
            assert!((last - 0.005).abs() < 0.005 * 0.01, "{last}");
        }
    }

    /// With the pivot's lever the angular acceleration acts as the horizontal ground
    /// acceleration of the pivot's height: a turn with θ̈ only (g → 0 in the force) about a
    /// pivot far below the surface drives mode 1 as the body force θ̈ Z₁, checked against the
    /// horizontal-excitation closed form of `crate::modal::sine_response`.
    #[test]
    fn angular_acceleration_acts_through_the_lever() {
        let t = tank(-0.5);
        let z1 = t.modal_lever(0);
        // Z₁ = −H + (2L/π) tanh(πH/2L), from (P1).
        let expected = -0.5 + 2.0 / std::f64::consts::PI * (std::f64::consts::PI * 0.25).tanh();
        assert!((z1 - expected).abs() < 1e-12);
        // θ = θ0 sin Ωt: force g θ + θ̈ Z₁ = θ0 (g − Ω² Z₁) sin Ωt on mode 1.
        let omega = 0.6 * t.tank.modal_omega(0);
        let theta0 = 0.01;
        let dt = 2e-4;
        let n = 20_000;
        let (angle, accel): (Vec<f64>, Vec<f64>) = (0..n)
            .map(|k| {
                let s = (omega * k as f64 * dt).sin();
                (theta0 * s, -theta0 * omega * omega * s)
            })
            .unzip();
        let x = 1.0;
        let pitched = t.elevation_history(dt, &angle, &accel, x, 1);
        let k = n - 1;
        let time = k as f64 * dt;
        let w1 = t.tank.modal_omega(0);
        let gain = w1 * w1 / t.tank.gravity * t.tank.modal_coefficient(0);
        let unit = crate::modal::sine_from_rest(w1, omega, time);
        let force_amplitude = theta0 * (t.tank.gravity - omega * omega * z1);
        let mode1 =
            gain * force_amplitude * unit.displacement * (t.tank.modal_wavenumber(0) * x).cos();
        // The tail (modes above the first, quasi-static).
        let tail = ((x - 0.5)
            - t.tank.modal_coefficient(0) * (t.tank.modal_wavenumber(0) * x).cos())
            * (t.tank.gravity * angle[k] + accel[k] * t.pivot_height)
            / t.tank.gravity;
        assert!(
            (pitched[k] - (mode1 + tail)).abs() < 1e-6 * theta0,
            "{} {}",
            pitched[k],
            mode1 + tail
        );
    }
}
