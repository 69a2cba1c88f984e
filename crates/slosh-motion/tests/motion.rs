//! Motion tests: sine convention, sums, three components.

use slosh_motion::*;

#[test]
fn sine_follows_paper_convention() {
    // Tolerance 1e-12: closed form; acceleration is the second derivative of A sin(ωt + φ).
    let s = Sine {
        amplitude_m: 0.01,
        omega_rad_s: 5.0,
        phase: 0.3,
    };
    let t = 0.7;
    assert!((s.displacement_m(t) - 0.01 * (3.5_f64 + 0.3).sin()).abs() < 1e-12);
    assert!((s.accel_m_s2(t) + 0.01 * 25.0 * (3.5_f64 + 0.3).sin()).abs() < 1e-12);
    // Finite-difference check of the acceleration (tolerance 1e-6: O(h²) with h = 1e-4).
    let h = 1e-4;
    let fd =
        (s.displacement_m(t + h) - 2.0 * s.displacement_m(t) + s.displacement_m(t - h)) / (h * h);
    assert!((fd - s.accel_m_s2(t)).abs() < 1e-6);
    assert!((s.peak_accel_m_s2() - 0.25).abs() < 1e-12);
}

#[test]
fn motion_combines_components() {
    // Tolerance 1e-12: sums of closed forms and a linear record.
    let s1 = Sine::new(0.01, 2.0);
    let s2 = Sine {
        amplitude_m: 0.002,
        omega_rad_s: 7.0,
        phase: 1.0,
    };
    let rec = Record::from_samples(0.5, vec![0.0, 1.0, 2.0]).unwrap();
    let m = Motion::along_x(vec![s1, s2])
        .with_y(Excitation::Sum(vec![s1.into(), rec.clone().into()]))
        .with_z(rec);
    let t = 0.75;
    let a = m.at(t);
    assert!((a[0] - (s1.accel_m_s2(t) + s2.accel_m_s2(t))).abs() < 1e-12);
    assert!((a[1] - (s1.accel_m_s2(t) + 1.5)).abs() < 1e-12);
    assert!((a[2] - 1.5).abs() < 1e-12);
    assert_eq!(m.at(5.0)[2], 0.0);
    assert_eq!(m.end_time_s(), None);
    let recorded = Motion::default().with_z(Record::from_samples(0.5, vec![1.0; 5]).unwrap());
    assert_eq!(recorded.end_time_s(), Some(2.0));
    assert_eq!(Motion::default().at(1.0), [0.0; 3]);
}
