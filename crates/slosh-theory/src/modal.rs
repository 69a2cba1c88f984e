//! Modal (generalised-coordinate) response of linear sloshing, shared by the rectangular
//! ([`crate::linear`]) and cylindrical ([`crate::cylinder`]) tanks.
//!
//! In the tank frame a uniform horizontal body force f(t) per unit mass (m/s², along +x;
//! f = −a_g for a ground acceleration a_g) has the potential −f x. Expanding x over the
//! sloshing mode shapes S_j of the free surface, x = Σ_j d_j S_j (+ a constant), the linearised
//! free-surface conditions give, for each excited mode j with natural frequency ω_j,
//!
//! β̈_j + 2 ζ_j ω_j β̇_j + ω_j² β_j = (ω_j²/g) d_j f(t)                                   (M1)
//!
//! with β_j the modal free-surface amplitude (m) and ζ_j an optional modal damping ratio
//! (Ibrahim 2005, §2.3; Faltinsen & Timokha 2009, ch. 5). The quasi-static response is
//! β_j = d_j f/g, i.e. the surface tilts to ζ = f x/g (a hydrostatic tilt), as it must.
//!
//! This module integrates (M1) exactly: the closed form for a sine load started from rest
//! (undamped, valid at and near resonance), and exact piecewise-linear-load steps
//! (Nigam & Jennings 1969) for a sampled f(t).

/// A tank whose linear sloshing modes driven by a horizontal body force are known.
///
/// Mode index j = 0, 1, 2, … runs over the *excited* modes only (odd n for a rectangular
/// tank, (m = 1, n = j + 1) for a cylinder).
pub trait ModalTank {
    /// Gravitational acceleration g (m/s²).
    fn gravity(&self) -> f64;
    /// Natural circular frequency ω_j (rad/s) of excited mode j.
    fn modal_omega(&self, j: usize) -> f64;
    /// Expansion coefficient d_j (m) of the body-force potential coordinate x over mode j
    /// (the quasi-static amplitude per unit f/g).
    fn modal_coefficient(&self, j: usize) -> f64;
}

/// The modal amplitudes of a linear sloshing solution at one instant.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalState {
    /// Time t (s) since the start of the excitation.
    pub time: f64,
    /// Body force per unit mass f(t) along +x (m/s²), f = −a_g.
    pub body_force: f64,
    /// Its rate ḟ(t) (m/s³) (slope of the current load segment for sampled input).
    pub body_force_rate: f64,
    /// Modal free-surface amplitudes β_j (m), j = 0 … n_modes − 1.
    pub amplitude: Vec<f64>,
    /// Modal rates β̇_j (m/s).
    pub amplitude_rate: Vec<f64>,
}

impl ModalState {
    /// Number of modes carried.
    pub fn n_modes(&self) -> usize {
        self.amplitude.len()
    }
}

/// Displacement and velocity of a single-degree-of-freedom oscillator.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct OscillatorState {
    /// Displacement x (any unit u).
    pub displacement: f64,
    /// Velocity ẋ (u/s).
    pub velocity: f64,
}

/// One exact step of ẍ + 2ζωẋ + ω²x = p(t) with p varying linearly from `load_start` to
/// `load_end` (u/s²) over `dt` (s). Source: Nigam & Jennings (1969), "Calculation of response
/// spectra from strong-motion earthquake records", BSSA 59(2) — the solution is the sum of
/// the particular solution for a linear load and the free damped response, so it is exact
/// for piecewise-linear loads. Valid for ω > 0 and 0 ≤ ζ < 1.
pub fn oscillator_step(
    omega: f64,
    damping_ratio: f64,
    state: OscillatorState,
    load_start: f64,
    load_end: f64,
    dt: f64,
) -> OscillatorState {
    assert!(omega > 0.0 && (0.0..1.0).contains(&damping_ratio));
    let w2 = omega * omega;
    let slope = (load_end - load_start) / dt;
    // particular solution x_p(τ) = a + b τ
    let b = slope / w2;
    let a = load_start / w2 - 2.0 * damping_ratio * slope / (w2 * omega);
    let decay = damping_ratio * omega;
    let omega_d = omega * (1.0 - damping_ratio * damping_ratio).sqrt();
    let c = state.displacement - a;
    let d = (state.velocity - b + decay * c) / omega_d;
    let e = (-decay * dt).exp();
    let (s, co) = (omega_d * dt).sin_cos();
    let free = c * co + d * s;
    let free_rate = -c * omega_d * s + d * omega_d * co;
    OscillatorState {
        displacement: e * free + a + b * dt,
        velocity: e * (free_rate - decay * free) + b,
    }
}

/// sin(u)/u with a series near 0.
fn sinc(u: f64) -> f64 {
    if u.abs() < 1e-4 {
        1.0 - u * u / 6.0
    } else {
        u.sin() / u
    }
}

/// Response from rest of the undamped oscillator ẍ + ω²x = Q sin(Ωt): returns (x, ẋ) per unit Q.
///
/// Off resonance x = (sin Ωt − (Ω/ω) sin ωt)/(ω² − Ω²); written here as
/// x = −t cos(σt) sinc(δt/2)/(ω+Ω) + sin(ωt)/(ω(ω+Ω)), σ = (ω+Ω)/2, δ = Ω − ω,
/// which is the same function without cancellation and reduces at Ω = ω exactly to the
/// secular solution (sin ωt − ωt cos ωt)/(2ω²). Valid for any Ω ≥ 0, ω > 0.
pub fn sine_from_rest(omega: f64, forcing_omega: f64, t: f64) -> OscillatorState {
    let sum = omega + forcing_omega;
    let sigma = 0.5 * sum;
    let delta = forcing_omega - omega;
    let envelope = t * sinc(0.5 * delta * t) / sum;
    OscillatorState {
        displacement: -envelope * (sigma * t).cos() + (omega * t).sin() / (omega * sum),
        velocity: forcing_omega * envelope * (sigma * t).sin(),
    }
}

/// Closed-form modal state at time t (s) for f(t) = F sin(Ωt) started from rest, undamped.
/// `force_amplitude` F (m/s²), `forcing_omega` Ω (rad/s). Exact for (M1) with ζ = 0.
pub fn sine_response<T: ModalTank + ?Sized>(
    tank: &T,
    force_amplitude: f64,
    forcing_omega: f64,
    t: f64,
    n_modes: usize,
) -> ModalState {
    let g = tank.gravity();
    let mut amplitude = Vec::with_capacity(n_modes);
    let mut amplitude_rate = Vec::with_capacity(n_modes);
    for j in 0..n_modes {
        let w = tank.modal_omega(j);
        let q = w * w / g * tank.modal_coefficient(j) * force_amplitude;
        let unit = sine_from_rest(w, forcing_omega, t);
        amplitude.push(q * unit.displacement);
        amplitude_rate.push(q * unit.velocity);
    }
    ModalState {
        time: t,
        body_force: force_amplitude * (forcing_omega * t).sin(),
        body_force_rate: force_amplitude * forcing_omega * (forcing_omega * t).cos(),
        amplitude,
        amplitude_rate,
    }
}

/// Modal response to a sampled body force f_k = f(k·dt) (m/s², k = 0 … N−1), from rest,
/// with modal damping ratio ζ (0 ≤ ζ < 1, same for all modes). f is taken piecewise linear
/// between samples and each mode is stepped exactly ([`oscillator_step`]), so the only error
/// is the linear interpolation of the load (O(dt²) per cycle). Returns one state per sample.
pub fn time_history_response<T: ModalTank + ?Sized>(
    tank: &T,
    dt: f64,
    body_force: &[f64],
    n_modes: usize,
    damping_ratio: f64,
) -> Vec<ModalState> {
    let g = tank.gravity();
    let modes: Vec<(f64, f64)> = (0..n_modes)
        .map(|j| {
            let w = tank.modal_omega(j);
            (w, w * w / g * tank.modal_coefficient(j))
        })
        .collect();
    let mut states = vec![OscillatorState::default(); n_modes];
    let mut out = Vec::with_capacity(body_force.len());
    for (k, &f) in body_force.iter().enumerate() {
        if k > 0 {
            let f_prev = body_force[k - 1];
            for (s, &(w, gain)) in states.iter_mut().zip(&modes) {
                *s = oscillator_step(w, damping_ratio, *s, gain * f_prev, gain * f, dt);
            }
        }
        let rate = if k + 1 < body_force.len() {
            (body_force[k + 1] - f) / dt
        } else if k > 0 {
            (f - body_force[k - 1]) / dt
        } else {
            0.0
        };
        out.push(ModalState {
            time: k as f64 * dt,
            body_force: f,
            body_force_rate: rate,
            amplitude: states.iter().map(|s| s.displacement).collect(),
            amplitude_rate: states.iter().map(|s| s.velocity).collect(),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_closed_form_matches_textbook_off_resonance() {
        // Textbook form (Chopra 2012 Eq. 3.1.3 with x(0)=ẋ(0)=0): x = (sin Ωt − (Ω/ω) sin ωt)/(ω²−Ω²).
        // Far from resonance there is no cancellation, so agreement to 1e-12 absolute.
        let (w, big_w) = (3.0f64, 1.3f64);
        for &t in &[0.1f64, 1.0, 7.3] {
            let want = ((big_w * t).sin() - big_w / w * (w * t).sin()) / (w * w - big_w * big_w);
            let got = sine_from_rest(w, big_w, t).displacement;
            assert!((got - want).abs() < 1e-12);
            let want_v = big_w * ((big_w * t).cos() - (w * t).cos()) / (w * w - big_w * big_w);
            assert!((sine_from_rest(w, big_w, t).velocity - want_v).abs() < 1e-12);
        }
    }

    #[test]
    fn sine_closed_form_at_exact_resonance_is_secular() {
        // Chopra 2012 Eq. 3.1.13: x = (sin ωt − ωt cos ωt)/(2ω²) at Ω = ω; 1e-12 = round-off.
        let w = 5.0f64;
        for &t in &[0.5f64, 3.0, 20.0] {
            let want = ((w * t).sin() - w * t * (w * t).cos()) / (2.0 * w * w);
            assert!((sine_from_rest(w, w, t).displacement - want).abs() < 1e-12);
        }
        // Near resonance, Ω = ω(1 + 1e-4): the textbook form loses ≈ 4 digits to cancellation
        // (still ≈ 1e-12 relative), so both must agree to 1e-9 of the peak t/(2ω) = 2.
        let big_w = w * (1.0 + 1e-4);
        for &t in &[3.0f64, 20.0] {
            let want = ((big_w * t).sin() - big_w / w * (w * t).sin()) / (w * w - big_w * big_w);
            assert!((sine_from_rest(w, big_w, t).displacement - want).abs() < 2e-9);
        }
    }

    #[test]
    fn exact_step_reproduces_free_damped_vibration() {
        // Free vibration x = e^{−ζωt} cos(ω_d t) (+ matching velocity), Chopra Eq. 2.2.4:
        // the step is exact for zero load, so 1000 steps agree to 1e-12.
        let (w, z) = (4.0, 0.05);
        let wd = w * (1.0f64 - z * z).sqrt();
        let mut s = OscillatorState {
            displacement: 1.0,
            velocity: -z * w,
        };
        let dt = 0.01;
        for _ in 0..1000 {
            s = oscillator_step(w, z, s, 0.0, 0.0, dt);
        }
        let t = 10.0;
        let want = (-z * w * t).exp() * (wd * t).cos();
        assert!((s.displacement - want).abs() < 1e-12);
    }

    #[test]
    fn exact_step_for_ramp_load_matches_analytic() {
        // Undamped ramp p = r t from rest: x = (r/ω²)(t − sin(ωt)/ω) (Chopra Eq. 4.4.2).
        // One single step must be exact (1e-13), since the load is linear.
        let (w, r, t) = (2.0, 3.0, 1.7);
        let s = oscillator_step(w, 0.0, OscillatorState::default(), 0.0, r * t, t);
        let want = r / (w * w) * (t - (w * t).sin() / w);
        assert!((s.displacement - want).abs() < 1e-13);
    }
}
