//! `TankInput::check` refuses a tank or excitation that cannot exist, naming each bad value.

use slosh_theory::{SineExcitation, TankInput};

#[test]
fn a_real_tank_passes() {
    let mut input = TankInput::rectangular(1.0, 0.5);
    input.tank_height = Some(1.0);
    input.peak_ground_accel = Some(0.0);
    input.spectral_accel_g = Some(0.3);
    input.sine = Some(SineExcitation {
        amplitude: 0.01,
        omega: 5.3,
        duration: 10.0,
    });
    assert_eq!(input.check(), Ok(()));
    assert_eq!(TankInput::cylindrical(10.0, 8.0).check(), Ok(()));
}

#[test]
fn sizes_must_be_positive_and_finite() {
    for (width, depth, bad) in [
        (1.0, -0.5, "depth"),
        (0.0, 0.5, "width"),
        (f64::NAN, 0.5, "width"),
        (f64::INFINITY, 0.5, "width"),
        (1.0, 0.0, "depth"),
    ] {
        let message = TankInput::rectangular(width, depth).check().unwrap_err();
        assert!(message.contains(bad), "{width} x {depth}: {message}");
    }
    let message = TankInput::cylindrical(-1.0, 0.5).check().unwrap_err();
    assert!(
        message.contains("radius") && message.contains("-1"),
        "{message}"
    );
}

#[test]
fn roof_must_be_above_the_liquid() {
    let mut input = TankInput::rectangular(1.0, 0.5);
    input.tank_height = Some(0.4);
    let message = input.check().unwrap_err();
    assert!(
        message.contains("roof") && message.contains("0.4"),
        "{message}"
    );
}

#[test]
fn accelerations_and_sine_are_checked() {
    let mut input = TankInput::rectangular(1.0, 0.5);
    input.peak_ground_accel = Some(-3.0);
    input.spectral_accel_g = Some(f64::NAN);
    input.sine = Some(SineExcitation {
        amplitude: 0.01,
        omega: 0.0,
        duration: 10.0,
    });
    let message = input.check().unwrap_err();
    for name in ["pga", "sa", "omega"] {
        assert!(message.contains(name), "{name}: {message}");
    }
}
