//! Zero-phase Butterworth filtering of uniformly sampled signals.
//!
//! The filter: a 4th-order Butterworth high-pass and/or low-pass, each made of two
//! second-order sections (biquads) with the Butterworth pole quality factors
//! Q = 1/(2 cos(π/8)) ≈ 0.5412 and Q = 1/(2 cos(3π/8)) ≈ 1.3066, discretised by the bilinear
//! transform pre-warped at the corner frequency. The cascade is run forward, then backward
//! over the reversed output, so the phase cancels (zero phase) and the gain is |H(f)|²: at a
//! corner the gain is 1/2 (−6 dB), and the magnitude roll-off is that of an 8th-order filter.
//!
//! Before filtering, the signal is padded with zeros at both ends, T_pad = 1.5·n/f_c with n = 4
//! the order and f_c the lowest corner (Converse & Brady 1992), so the filter transients decay
//! in the padding; the padding is removed afterwards and the output has the input's length.

/// One second-order section, normalised so that a0 = 1.
#[derive(Debug, Clone, Copy)]
struct Biquad {
    b0: f64,
    b1: f64,
    b2: f64,
    a1: f64,
    a2: f64,
}

impl Biquad {
    fn new(kind: Pass, corner_hz: f64, dt_s: f64, q: f64) -> Self {
        let w0 = 2.0 * std::f64::consts::PI * corner_hz * dt_s;
        let (s, c) = w0.sin_cos();
        let alpha = s / (2.0 * q);
        let a0 = 1.0 + alpha;
        let (b0, b1, b2) = match kind {
            Pass::Low => ((1.0 - c) / 2.0, 1.0 - c, (1.0 - c) / 2.0),
            Pass::High => ((1.0 + c) / 2.0, -(1.0 + c), (1.0 + c) / 2.0),
        };
        Biquad {
            b0: b0 / a0,
            b1: b1 / a0,
            b2: b2 / a0,
            a1: -2.0 * c / a0,
            a2: (1.0 - alpha) / a0,
        }
    }

    /// Filters `x` in place (direct form II transposed, zero initial state).
    fn run(&self, x: &mut [f64]) {
        let (mut z1, mut z2) = (0.0, 0.0);
        for v in x.iter_mut() {
            let input = *v;
            let out = self.b0 * input + z1;
            z1 = self.b1 * input - self.a1 * out + z2;
            z2 = self.b2 * input - self.a2 * out;
            *v = out;
        }
    }
}

#[derive(Debug, Clone, Copy)]
enum Pass {
    Low,
    High,
}

/// Quality factors of the two pole pairs of a 4th-order Butterworth filter.
const BUTTERWORTH4_Q: [f64; 2] = [0.541_196_100_146_197, 1.306_562_964_876_376_5];

/// Filter order of each pass (high or low).
pub const BUTTERWORTH_ORDER: usize = 4;

/// Zero-phase 4th-order Butterworth filter of `signal` sampled at `dt_s`: high-pass at
/// `low_corner_hz` if given, low-pass at `high_corner_hz` if given (both: band-pass).
/// Corners must lie in (0, Nyquist); callers check this.
pub fn butterworth_zero_phase(
    signal: &[f64],
    dt_s: f64,
    low_corner_hz: Option<f64>,
    high_corner_hz: Option<f64>,
) -> Vec<f64> {
    let mut sections = Vec::new();
    if let Some(f) = low_corner_hz {
        for q in BUTTERWORTH4_Q {
            sections.push(Biquad::new(Pass::High, f, dt_s, q));
        }
    }
    if let Some(f) = high_corner_hz {
        for q in BUTTERWORTH4_Q {
            sections.push(Biquad::new(Pass::Low, f, dt_s, q));
        }
    }
    let lowest = low_corner_hz.or(high_corner_hz);
    let Some(lowest) = lowest else {
        return signal.to_vec();
    };
    let pad = (1.5 * BUTTERWORTH_ORDER as f64 / lowest / dt_s).ceil() as usize;
    let mut work = vec![0.0; signal.len() + 2 * pad];
    work[pad..pad + signal.len()].copy_from_slice(signal);
    for s in &sections {
        s.run(&mut work);
    }
    work.reverse();
    for s in &sections {
        s.run(&mut work);
    }
    work.reverse();
    work[pad..pad + signal.len()].to_vec()
}
