//! Loads on internal solids of a 2D section at rest, against hydrostatics: a plate lying on
//! the floor carries the weight of the liquid column above its top face, and a submerged
//! circular column the buoyancy of Archimedes.

use std::f64::consts::PI;

use slosh_core::{Simulation, SphParams};
use slosh_geometry::{SectionShape, SectionTank2, Solid2};
use slosh_run::{part_force_column, run_case, AtRest, LoadFilter, RoofTank, RunPlan, RunStatus};

const RHO: f64 = 1000.0;
const G: f64 = 9.81;

/// Mean of `column` over the rows with t ≥ `from` (s).
fn mean_after(t: &[f64], column: &[f64], from: f64) -> f64 {
    let values: Vec<f64> = t
        .iter()
        .zip(column)
        .filter(|(&t, _)| t >= from)
        .map(|(_, &v)| v)
        .collect();
    values.iter().sum::<f64>() / values.len() as f64
}

#[test]
fn plate_on_the_floor_and_column_carry_hydrostatic_loads() {
    // 0.6 m wide, 0.5 m high section, 0.3 m of water, dx = 1 cm; a plate 0.2 × 0.06 m half
    // sunk into the floor (its top face 0.03 m above it), a column of radius 5 cm at 0.15 m
    let (plate_len, plate_top, r) = (0.2, 0.03, 0.05);
    let setup = SectionTank2::new(
        SectionShape::Polygon(vec![[0.0, 0.0], [0.6, 0.0], [0.6, 0.5], [0.0, 0.5]]),
        0.3,
    )
    .with_solid(Solid2::plate("plate", [0.18, 0.0], plate_len, 0.06, 0.0))
    .with_solid(Solid2::circle("column", [0.45, 0.15], r))
    .with_layers(SphParams::modern().wall_layers())
    .build(0.01)
    .expect("the tank builds");
    let mut sim = Simulation::new(setup, SphParams::modern()).expect("the simulation starts");
    let still = sim.still_level();
    // 2 s, the loads averaged over the last 0.8 s: the liquid starts sunk into its own Tait
    // compression while the solids stay where they are, so the particles next to a solid
    // start up to 0.8 mm (8 % of dx) off their spacing at rest, and the first second is that
    // settling (the column's lift averaged over 0.4–0.8 s reads +10.8 %, over 1.2–2.0 s +7.7 %).
    let (settle, duration) = (0.0, 2.0);
    let plan = RunPlan {
        settle,
        duration,
        output_interval: 0.01,
        frame_interval: 0.0,
        gauges: Vec::new(),
        load_filter: LoadFilter::new(None, 6.0),
        roof_tank: RoofTank {
            density: RHO,
            gravity: G,
            depth: 0.3,
            freeboard: 0.2,
            half_width: 0.3,
            omega: 6.0,
        },
        wall_gauges: None,
        turns: false,
        roof_load: Default::default(),
    };
    let result = run_case(&mut sim, &plan, &mut AtRest, &mut (), &mut ()).expect("runs");
    assert!(matches!(result.status, RunStatus::Finished));
    let t = result.column("t").expect("t");
    let col = |name: &str| {
        result
            .column(name)
            .unwrap_or_else(|| panic!("column {name}"))
    };
    // the weight of the liquid above the plate's top face (its lower face and the floor under
    // it are dry), and Archimedes' buoyancy of the column (ρ g π r² per metre)
    let plate_down = RHO * G * (still - plate_top) * plate_len;
    let buoyancy = RHO * G * PI * r * r;
    let plate_y = mean_after(t, col(&part_force_column("plate", "y")), 1.2);
    let plate_x = mean_after(t, col(&part_force_column("plate", "x")), 1.2);
    let column_y = mean_after(t, col(&part_force_column("column", "y")), 1.2);
    let column_x = mean_after(t, col(&part_force_column("column", "x")), 1.2);
    eprintln!(
        "plate {plate_x:.2}, {plate_y:.2} N/m (−{plate_down:.2}); column {column_x:.2}, \
         {column_y:.2} N/m ({buoyancy:.2})"
    );
    // 3 %: the hydrostatic wall pressure of the modern scheme is within 1 % on a long wall;
    // a face 20 dx long with two corners carries the corners' extrapolation error
    assert!(
        ((-plate_y) / plate_down - 1.0).abs() < 0.03,
        "plate {plate_y} vs −{plate_down}"
    );
    assert!(plate_x.abs() < 0.02 * plate_down, "{plate_x}");
    // 10 % of the net buoyancy = 1.6 % of the pressure force round the column (ρ g d · 2πr)
    assert!(
        (column_y / buoyancy - 1.0).abs() < 0.10,
        "column {column_y} vs {buoyancy}"
    );
    assert!(column_x.abs() < 0.05 * buoyancy, "{column_x}");
    assert!(result.column("plate_force_y_lp").is_some());
}
