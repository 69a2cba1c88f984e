//! The polar lattice of an upright cylinder (`lattice = "polar"`: liquid and shell on rings
//! about the axis) run end to end through `cylinder_3d.rhai`: the liquid it lays out holds
//! the tank's volume and sloshes at the cylinder's first natural period.

use slosh_theory::cylinder::CylindricalTank;
use slosh_theory::modal::ModalTank;
use slosh_validation::{out_dir, period_from_crossings, run_script, series_column};

/// Free sloshing of the open cylinder R = 0.5 m, H = 0.5 m on the polar lattice at 8
/// particles per depth (dx = 0.0625 m, modern scheme), started in its first mode, 2.6 periods.
/// (a) The liquid's volume, particles × dx³, within 1 % of πR²H: each ring's point count is
/// rounded to a whole number (≤ ½ point in ≥ 3), the columns' rows by error diffusion; the
/// cubic lattice's count, cut by the curved wall, is 3.6 % over at this size.
/// (b) The period of the wall elevation within 3 % of potential theory, ω₁² = (g ξ₁/R)
/// tanh(ξ₁H/R) (Ibrahim 2005, §1.3): the tolerance of the suite's 3D period checks, for the
/// kernel's truncation at the free surface at this coarse resolution.
#[test]
fn polar_cylinder_holds_its_volume_and_sloshes_at_its_period() {
    let (radius, depth, dx) = (0.5, 0.5, 0.0625);
    let theory = 2.0 * std::f64::consts::PI
        / CylindricalTank::new(radius, depth, 1000.0, 9.81).modal_omega(0);
    let out = out_dir("polar_cylinder_free");
    let sets = [
        "lattice=polar".to_string(),
        "roof=none".to_string(),
        "amplitude=0".to_string(),
        "initial_tilt=0.02".to_string(),
        "settle=0".to_string(),
        format!("dx={dx}"),
        format!("duration={}", 2.6 * theory),
        "frame_interval=0".to_string(),
        "output_interval=0.005".to_string(),
    ];
    let sets: Vec<&str> = sets.iter().map(|s| s.as_str()).collect();
    let summary = run_script("cylinder_3d.rhai", &sets, &out).unwrap();
    assert_eq!(summary.lost_particles, 0);
    let volume = summary.particles_fluid as f64 * dx * dx * dx;
    let exact = std::f64::consts::PI * radius * radius * depth;
    eprintln!(
        "polar cylinder: {} liquid particles, volume {volume:.5} m³ against πR²H = {exact:.5} m³",
        summary.particles_fluid
    );
    assert!(
        (volume / exact - 1.0).abs() < 0.01,
        "volume {volume} m³ against {exact} m³"
    );
    let t = series_column(&out, "t");
    let eta = series_column(&out, "eta_left");
    let measured = period_from_crossings(&t, &eta).expect("at least two crossings");
    let error = measured / theory - 1.0;
    eprintln!(
        "polar cylinder: period {measured:.4} s, theory {theory:.4} s, error {:+.2} %",
        100.0 * error
    );
    assert!(error.abs() < 0.03, "period error {:.2} %", 100.0 * error);
}
