//! Checkpoints continue a run bit for bit: every configuration of the golden fingerprints,
//! the paper scheme, and both neighbour backends, 2D and 3D, run straight through and run
//! with a stop part-way, the state written out as text (RON) and read back into a simulation
//! built again from the same tank and parameters. The fingerprints (sums over all particles
//! of density, position and velocity, wall densities, the largest wall pressure) and the
//! load peaks must be identical.

use crate::test_tank::{box_tank, box_tank_for};
use crate::tests_golden::configurations;
use crate::tests_modern::fingerprint;
use crate::{NeighbourBackend, SimState, Simulation, SphParams, Vector};

/// The ground acceleration of the runs (m/s²): varying, so that a resume at a wrong time
/// would show.
fn ground<const D: usize>(t: f64) -> Vector<D> {
    let mut a = Vector::<D>::zeros();
    a[0] = 2.0 * (10.0 * t).sin();
    if D == 3 {
        a[1] = 1.0;
    }
    a
}

/// Fingerprint and load peaks after `steps` steps, straight through or with a stop after
/// `stop` steps.
fn run<const D: usize>(params: &SphParams, steps: u64, stop: Option<u64>) -> (Vec<u64>, Vec<u64>) {
    let setup = || {
        if D == 2 {
            box_tank_for::<D>(params, std::array::from_fn(|_| 0.4), 0.2, 0.02, 0.02)
        } else {
            box_tank_for::<D>(
                params,
                std::array::from_fn(|k| [0.2, 0.1, 0.2][k]),
                0.1,
                0.01,
                0.02,
            )
        }
    };
    let mut sim = Simulation::new(setup(), params.clone()).unwrap();
    while sim.steps() < steps {
        if Some(sim.steps()) == stop {
            let text = ron::to_string(&sim.state()).unwrap();
            let state: SimState<D> = ron::from_str(&text).unwrap();
            sim = Simulation::new(setup(), params.clone()).unwrap();
            sim.restore(state).unwrap();
        }
        let t = sim.time();
        sim.step(ground::<D>(t)).unwrap();
    }
    let p = sim.loads().peaks();
    let peaks = [
        p.max_roof_p,
        p.max_roof_force_up,
        p.max_abs_base_shear_x,
        sim.time(),
    ]
    .iter()
    .map(|v| v.to_bits())
    .collect();
    (fingerprint(&sim), peaks)
}

fn all_configurations() -> Vec<(String, SphParams)> {
    let mut list: Vec<(String, SphParams)> = configurations()
        .into_iter()
        .map(|(n, p)| (n.to_string(), p))
        .collect();
    list.push(("paper".into(), SphParams::paper().with_paper_stiffness()));
    for (name, base) in [
        ("paper, k-d tree", SphParams::paper()),
        ("modern, k-d tree", SphParams::modern()),
    ] {
        list.push((
            name.into(),
            SphParams {
                neighbour_backend: NeighbourBackend::KdTree,
                ..base.with_paper_stiffness()
            },
        ));
    }
    list
}

#[test]
fn resumed_runs_are_bit_for_bit_the_same() {
    for (name, params) in all_configurations() {
        assert_eq!(
            run::<2>(&params, 60, None),
            run::<2>(&params, 60, Some(27)),
            "2D, {name}"
        );
        assert_eq!(
            run::<3>(&params, 20, None),
            run::<3>(&params, 20, Some(9)),
            "3D, {name}"
        );
    }
}

#[test]
fn a_state_of_another_tank_is_refused() {
    let params = SphParams::paper().with_paper_stiffness();
    let sim = Simulation::new(box_tank::<2>([0.4, 0.4], 0.2, 0.0, 0.02), params.clone()).unwrap();
    let mut other = Simulation::new(box_tank::<2>([0.4, 0.4], 0.1, 0.0, 0.02), params).unwrap();
    let before = fingerprint(&other);
    let err = other.restore(sim.state()).unwrap_err().to_string();
    assert!(err.contains("does not belong to this tank"), "{err}");
    assert_eq!(
        fingerprint(&other),
        before,
        "a refused state leaves the simulation as it was"
    );
}
