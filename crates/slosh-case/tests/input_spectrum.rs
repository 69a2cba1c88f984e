//! The input response spectrum writer: a pure sine input peaks at the sine's period.

use slosh_case::spectrum::write_input_spectrum;
use std::f64::consts::PI;

#[test]
fn sine_input_spectrum_peaks_at_the_sine_period() {
    let out = std::env::temp_dir()
        .join("slosh-case-tests")
        .join(format!("input-spectrum-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();

    // 1 m/s² at T0 = 1.5 s for 40 s, sampled every 0.005 s.
    let period = 1.5;
    let amplitude = 1.0;
    let dt = 0.005;
    let times: Vec<f64> = (0..=8000).map(|i| i as f64 * dt).collect();
    let accel: Vec<f64> = times
        .iter()
        .map(|t| amplitude * (2.0 * PI * t / period).sin())
        .collect();
    let s = write_input_spectrum(&out, &times, &accel, period, 3.0, false, 0.123).unwrap();

    // The 5 % spectrum peaks at the sine's period (grid step 3 %), at ≈ 1/(2ζ) = 10 × the input.
    assert!(
        (s.peak_period_5pct_s / period - 1.0).abs() < 0.04,
        "peak at {} s",
        s.peak_period_5pct_s
    );
    let ratio = s.sa_tc_5pct_m_s2 / amplitude;
    assert!((9.5..=10.05).contains(&ratio), "S_a(T0)/a = {ratio}");
    // 0.5 % damping: far larger (not yet steady after 40 s, bounded by 1/(2ζ) = 100).
    assert!(s.sa_tc_0p5pct_m_s2 > 5.0 * s.sa_tc_5pct_m_s2);
    assert!(s.sa_tc_0p5pct_m_s2 < 100.0 * amplitude);
    assert!((s.input_pga_m_s2 - amplitude).abs() < 1e-6);
    assert_eq!(s.sph_max_eta_m, 0.123);
    // Rectangular codes: 0.5 L S_a(T_c, 0.5 %)/g with L = 3 m.
    let expected = 0.5 * 3.0 * s.sa_tc_0p5pct_g;
    assert_eq!(s.code_wave_heights.len(), 2);
    for c in &s.code_wave_heights {
        assert!((c.wave_height_m - expected).abs() < 1e-12, "{c:?}");
    }

    // The CSV: header and the peak row.
    let csv = std::fs::read_to_string(out.join("input_spectrum.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "period_s,sa_m_s2,sa_g,sa_0p5pct_m_s2,sa_0p5pct_g"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 200);
    let peak = rows.iter().max_by(|a, b| a[1].total_cmp(&b[1])).unwrap();
    assert!((peak[0] / period - 1.0).abs() < 0.04);
    assert!((peak[2] - peak[1] / 9.81).abs() < 1e-9);
    assert!(out.join("plots/input_spectrum.png").exists());
    assert!(out.join("plots/input_spectrum.svg").exists());

    // Uneven rows (as series.csv has them) give the same peak period.
    let uneven_t: Vec<f64> = (0..=4000)
        .map(|i| i as f64 * 0.01 + if i % 3 == 1 { 0.0004 } else { 0.0 })
        .collect();
    let uneven_a: Vec<f64> = uneven_t
        .iter()
        .map(|t| amplitude * (2.0 * PI * t / period).sin())
        .collect();
    let s2 = write_input_spectrum(&out, &uneven_t, &uneven_a, period, 3.0, true, 0.0).unwrap();
    assert!((s2.peak_period_5pct_s / period - 1.0).abs() < 0.04);
    assert!((s2.sa_tc_5pct_m_s2 / s.sa_tc_5pct_m_s2 - 1.0).abs() < 0.02);
    // Cylinder codes with D = 3 m: API 650 0.42 D A_f, ACI 350.3-06 Eq. 7-2 (D/2) C_c I and
    // EC8 0.84 R S_e/g.
    let code = |name: &str| {
        s2.code_wave_heights
            .iter()
            .find(|c| c.code.starts_with(name))
            .unwrap_or_else(|| panic!("no {name} in {:?}", s2.code_wave_heights))
            .wave_height_m
    };
    let sa = s2.sa_tc_0p5pct_g;
    assert_eq!(s2.code_wave_heights.len(), 3);
    assert!((code("API 650") - 0.42 * 3.0 * sa).abs() < 1e-12);
    assert!((code("ACI 350.3-06 (7-2)") - 0.5 * 3.0 * sa).abs() < 1e-12);
    assert!((code("EN 1998-4") - 0.84 * 1.5 * sa).abs() < 1e-12);
}
