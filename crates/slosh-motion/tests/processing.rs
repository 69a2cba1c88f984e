//! Processing tests: scaling, baseline correction, filtering, trimming, shifting, interpolation.

mod common;

use common::elcentro_path;
use slosh_motion::*;
use std::f64::consts::PI;

fn sine_record(freq_hz: f64, dt_s: f64, duration_s: f64) -> Record {
    let n = (duration_s / dt_s).round() as usize + 1;
    let a = (0..n)
        .map(|i| (2.0 * PI * freq_hz * i as f64 * dt_s).sin())
        .collect();
    Record::from_samples(dt_s, a).unwrap()
}

/// Largest |value| of samples whose time lies in [t0, t1].
fn amplitude_between(r: &Record, t0: f64, t1: f64) -> f64 {
    (0..r.len())
        .filter(|&i| r.time_s(i) >= t0 && r.time_s(i) <= t1)
        .map(|i| r.accel_m_s2[i].abs())
        .fold(0.0, f64::max)
}

#[test]
fn scale_to_pga_hits_target_and_logs() {
    // Tolerance 1e-12 m/s²: one multiplication.
    let mut r = read_at2(elcentro_path()).unwrap();
    r.scale_to_pga(3.0).unwrap();
    assert!((r.pga_m_s2() - 3.0).abs() < 1e-12);
    let last = r.processing_log.last().unwrap();
    assert!(
        last.starts_with("scale_to_pga 3 m/s2 (factor 0.95"),
        "{last}"
    );
    r.scale(2.0);
    assert!((r.pga_m_s2() - 6.0).abs() < 1e-12);
    assert!(Record::from_samples(0.01, vec![0.0; 4])
        .unwrap()
        .scale_to_pga(1.0)
        .is_err());
}

#[test]
fn polynomial_detrend_removes_cubic_and_keeps_orthogonal_part() {
    // Tolerance 1e-9: a cubic trend is removed exactly up to rounding of the 4×4 normal equations.
    let dt = 0.01;
    let n = 1001;
    let trend = |t: f64| 0.3 - 0.2 * t + 0.05 * t * t - 0.004 * t * t * t;
    let a: Vec<f64> = (0..n).map(|i| trend(i as f64 * dt)).collect();
    let mut r = Record::from_samples(dt, a).unwrap();
    r.detrend_polynomial(3).unwrap();
    assert!(r.pga_m_s2() < 1e-9, "residual {}", r.pga_m_s2());
    // Linear detrend of a pure line; mean removal of a constant.
    let mut line =
        Record::from_samples(dt, (0..n).map(|i| 1.0 + 2.0 * i as f64 * dt).collect()).unwrap();
    line.detrend_linear();
    assert!(line.pga_m_s2() < 1e-9);
    let mut c = Record::from_samples(dt, vec![0.7; 10]).unwrap();
    c.remove_mean();
    assert!(c.pga_m_s2() < 1e-15);
    assert!(r.detrend_polynomial(4).is_err());
}

#[test]
fn bandpass_passes_mid_band_sine() {
    // Tolerance 1 % amplitude: a 2 Hz sine lies far inside the 0.1–25 Hz band (gain 1 − 1e-9).
    let mut r = sine_record(2.0, 0.005, 60.0);
    r.bandpass(0.1, 25.0).unwrap();
    let amp = amplitude_between(&r, 20.0, 40.0);
    assert!((amp - 1.0).abs() < 0.01, "amplitude {amp}");
}

#[test]
fn bandpass_attenuates_sine_below_low_corner() {
    // Criterion > 95 % attenuation: 0.1 Hz is 1/10 of the 1 Hz corner (|H|² ≈ 1e-8).
    let mut r = sine_record(0.1, 0.01, 200.0);
    r.bandpass(1.0, 20.0).unwrap();
    let amp = amplitude_between(&r, 50.0, 150.0);
    assert!(amp < 0.05, "amplitude {amp}");
    // And the low-pass side: 40 Hz against a 4 Hz corner.
    let mut hi = sine_record(40.0, 0.002, 20.0);
    hi.lowpass(4.0).unwrap();
    assert!(amplitude_between(&hi, 5.0, 15.0) < 0.05);
    assert!(
        hi.bandpass(5.0, 300.0).is_err(),
        "corner above Nyquist must be refused"
    );
}

#[test]
fn filter_is_zero_phase_and_half_power_at_corner() {
    // Tolerance 2 %: after forward+backward passes the gain at the corner is |H|² = 1/2, no lag.
    let mut r = sine_record(1.0, 0.005, 80.0);
    r.highpass(1.0).unwrap();
    let amp = amplitude_between(&r, 30.0, 50.0);
    assert!((amp - 0.5).abs() < 0.01, "gain at corner {amp}");
    // Zero phase: the output at a crest of the input (t = 40.25 s) is the crest of the output.
    let i = (40.25 / 0.005_f64).round() as usize;
    assert!((r.accel_m_s2[i] - amp).abs() < 0.01 * amp);
}

#[test]
fn trim_shift_and_interpolate() {
    // Tolerance 1e-12: linear interpolation of a linear ramp is exact.
    let dt = 0.1;
    let mut r = Record::from_samples(dt, (0..11).map(|i| i as f64).collect()).unwrap();
    assert!((r.at(0.25) - 2.5).abs() < 1e-12);
    assert_eq!(r.at(-0.01), 0.0);
    assert_eq!(r.at(1.01), 0.0);
    assert!(
        (r.at(1.0) - 10.0).abs() < 1e-12,
        "the last sample is inside the record"
    );
    assert!((r.end_time_s() - 1.0).abs() < 1e-12);
    r.trim(0.3, 0.75).unwrap();
    assert_eq!(r.accel_m_s2, vec![3.0, 4.0, 5.0, 6.0, 7.0]);
    assert_eq!(r.start_time_s, 0.0);
    r.shift(2.0);
    assert_eq!(r.at(1.9), 0.0);
    assert!((r.at(2.05) - 3.5).abs() < 1e-12);
    assert!((r.end_time_s() - 2.4).abs() < 1e-12);
    assert!(r.trim(5.0, 6.0).is_err());
    assert!(r.processing_log.iter().any(|l| l.starts_with("trim")));
    assert!(r.processing_log.iter().any(|l| l.starts_with("shift")));
}
