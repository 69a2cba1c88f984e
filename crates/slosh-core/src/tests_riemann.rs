//! The Riemann-solver pair of Zhang, Hu & Adams 2017 (`PairScheme::Riemann`) in the modern
//! step: short stability checks in 2D and 3D against closed forms, and its refusal where it
//! has no right state.

use crate::test_tank::box_tank_for;
use crate::tests_modern::{free_sloshing_period, hydrostatics, modern_params};
use crate::{BoundaryMethod, DensityMethod, SimError, Simulation, SphParams, Vector};

/// The modern preset with the Riemann pair in place of Eq. 8 and the continuity equation.
fn riemann_params() -> SphParams {
    modern_params().with_riemann_pair()
}

/// 2D, settled 1 s from a hydrostatic start (1.0 × 1.0 m tank, 0.5 m of water, dx = 0.02 m):
/// the pressure follows ρ0 g d (slope within 2 %, scatter below 2 % of ρ0 g H, the modern
/// preset's own tolerances in `modern_hydrostatics`), and the first-mode period of free
/// sloshing in the 0.6 × 0.3 m tank is within 1.5 % of potential theory
/// ω² = g k tanh kH (Lamb 1932, §257), the modern preset's period tolerance.
#[test]
fn riemann_pair_2d_hydrostatics_and_period() {
    let (slope, scatter) = hydrostatics(riemann_params(), 1.0);
    eprintln!(
        "Riemann pair hydrostatics: slope {slope:.4}, scatter {:.3} % of rho g H",
        100.0 * scatter
    );
    assert!((slope - 1.0).abs() < 0.02, "slope {slope}");
    assert!(scatter < 0.02, "scatter {scatter}");
    let (t, th, err) = free_sloshing_period(riemann_params(), 0.6, 0.3, 0.02);
    eprintln!(
        "Riemann pair 0.6x0.3: T = {t:.4} s, theory {th:.4} s, error {:+.2} %",
        100.0 * err
    );
    assert!(err.abs() < 0.015, "period error {err}");
}

/// 3D, a 0.2 × 0.1 × 0.2 m box with 0.1 m of water (dx = 0.02 m) shaken at 2 m/s² along x
/// and 1 m/s² along y for 600 steps: no particle leaves the tank and the mean density stays
/// within 0.5 % of its value at the start (the liquid keeps its volume; the still column
/// compresses by g H/c0² ≈ 0.1 % at this c0).
#[test]
fn riemann_pair_3d_stays_stable() {
    let setup = box_tank_for::<3>(&riemann_params(), [0.2, 0.1, 0.2], 0.1, 0.01, 0.02);
    let mut sim = Simulation::new(setup, riemann_params()).unwrap();
    let mean =
        |s: &Simulation<3>| s.fluid().density.iter().sum::<f64>() / s.fluid().density.len() as f64;
    let rho_start = mean(&sim);
    for _ in 0..600 {
        let t = sim.time();
        sim.step(Vector::<3>::new(2.0 * (10.0 * t).sin(), 1.0, 0.0))
            .unwrap();
    }
    assert_eq!(sim.fluid_inside(), sim.fluid().position.len());
    let drift = mean(&sim) / rho_start - 1.0;
    eprintln!(
        "Riemann pair 3D: t = {:.3} s, mean density drift {drift:+.2e}",
        sim.time()
    );
    assert!(drift.abs() < 5e-3, "mean density drift {drift}");
    assert!(sim.step_description().contains("Riemann"));
}

/// The Riemann pair needs continuity density and Adami walls: any other choice is refused
/// with a message that names the keys to change.
#[test]
fn riemann_pair_without_its_parts_is_refused() {
    for params in [
        SphParams {
            boundary: BoundaryMethod::Dynamic,
            ..riemann_params()
        },
        SphParams {
            density: DensityMethod::Summation,
            ..riemann_params()
        },
    ] {
        let setup = box_tank_for::<2>(&params, [0.4, 0.4], 0.2, 0.0, 0.02);
        match Simulation::new(setup, params) {
            Err(SimError::InvalidSetup(msg)) => {
                assert!(msg.contains("adami") && msg.contains("continuity"), "{msg}")
            }
            Err(e) => panic!("unexpected error {e}"),
            Ok(_) => panic!("the Riemann pair was accepted without its parts"),
        }
    }
}
