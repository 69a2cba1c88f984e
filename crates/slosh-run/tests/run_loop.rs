//! The run loop on a small 2D tank: step counts, stop requests, failures of the ground motion,
//! and the rows of a case run.

use slosh_core::{Simulation, SphParams};
use slosh_geometry::RectTank2;
use slosh_run::{
    advance, advance_with, run_case, AtRest, Gauge, GroundMotion, LoadFilter, MotionError,
    RoofTank, RunPlan, RunStatus, StepError, Until,
};

fn small_tank() -> Simulation<2> {
    let setup = RectTank2::new(0.4, 0.3, 0.2)
        .build(0.02)
        .expect("the tank builds");
    Simulation::new(setup, SphParams::default()).expect("the simulation starts")
}

fn plan(duration: f64) -> RunPlan {
    RunPlan {
        settle: 0.01,
        duration,
        output_interval: 0.005,
        frame_interval: 0.0,
        gauges: vec![Gauge {
            name: "centre".into(),
            horizontal: vec![0.2],
        }],
        load_filter: LoadFilter::new(None, 8.0),
        roof_tank: RoofTank {
            density: 1000.0,
            gravity: 9.81,
            depth: 0.2,
            freeboard: 0.1,
            half_width: 0.2,
            omega: 8.0,
        },
        wall_gauges: None,
        turns: false,
        roof_load: Default::default(),
    }
}

#[test]
fn takes_the_steps_asked_for_and_stops_on_request() {
    let mut sim = small_tank();
    advance(&mut sim, &mut AtRest, Until::Steps(5), &mut (), &mut ()).expect("steps");
    assert_eq!(sim.steps(), 5);
    let mut asked = 0;
    let mut stop = || {
        asked += 1;
        (asked == 3).then_some(15)
    };
    let err = advance(&mut sim, &mut AtRest, Until::Steps(10), &mut (), &mut stop)
        .expect_err("the stop request ends the loop");
    assert!(matches!(err, StepError::Stopped { code: 15, .. }));
    assert_eq!(sim.steps(), 8);
}

#[test]
fn a_failing_motion_ends_the_loop_with_its_message() {
    struct Broken;
    impl GroundMotion for Broken {
        fn ground_accel(&mut self, t: f64) -> Result<[f64; 3], MotionError> {
            if t > 0.0 {
                Err("the record ended".into())
            } else {
                Ok([0.0; 3])
            }
        }
    }
    let mut sim = small_tank();
    let err = advance_with(&mut sim, &mut Broken, Until::Time(1.0), |_| Ok(()))
        .expect_err("the motion fails");
    assert!(err.to_string().contains("the record ended"), "{err}");
    assert_eq!(sim.steps(), 1);
}

#[test]
fn a_case_run_keeps_one_row_per_output_interval() {
    let mut sim = small_tank();
    let mut motion = |t: f64| [0.5 * (10.0 * t).sin(), 0.0, 0.0];
    let result =
        run_case(&mut sim, &plan(0.05), &mut motion, &mut (), &mut ()).expect("no observer error");
    assert!(matches!(result.status, RunStatus::Finished));
    let t = result.column("t").expect("a time column");
    assert_eq!(t.len(), 10, "{t:?}");
    assert!(result.column("eta_centre").is_some());
    assert!(result.column("base_shear_x_lp").is_some());
    // No ground acceleration during the settling time.
    assert_eq!(result.column("accel_x").expect("accel_x")[0], 0.0);
    assert!(result.series.iter().all(|c| c.len() == t.len()));
    assert_eq!(result.steps, sim.steps());
}
