//! Pressure transducers on walls (`wall_sensor`), run as `slosh run` runs them, against the
//! hydrostatic pressure ρ g (h − z) of still liquid: on the side walls and the bottom of an
//! open 2D tank and on the curved shell of an open 3D cylinder. A sensor whose centre is off
//! every wall stops the run with its name and the nearest face.

use slosh_case::{run_case_with_stop, RunOptions};
use slosh_script::{load_case, CaseOptions};
use std::path::PathBuf;

const GRAVITY: f64 = 9.81;
const DENSITY: f64 = 1000.0;

fn out_dir(name: &str) -> PathBuf {
    let out = std::env::temp_dir()
        .join("slosh-case-tests")
        .join(format!("wall-sensor-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    out
}

/// Runs `script`; returns the summary and the series columns `names`.
fn run(name: &str, script: &str, names: &[&str]) -> (slosh_case::Summary, Vec<Vec<f64>>) {
    let out = out_dir(name);
    let path = out.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    let case = load_case(&path, &CaseOptions::default()).unwrap();
    let run_out = out.join("run");
    let opts = RunOptions {
        out_dir: run_out.clone(),
        plots: false,
        ..RunOptions::default()
    };
    let summary = run_case_with_stop(case, &opts, &mut ()).unwrap();
    assert_eq!(summary.status, "completed", "{:?}", summary.error);
    let table = slosh_io::read_table(run_out.join("series.csv")).unwrap();
    let columns = names.iter().map(|n| table.column(n).unwrap()).collect();
    let _ = std::fs::remove_dir_all(&out);
    (summary, columns)
}

/// Mean of `y` over the rows whose time `t` is at or after `from` (s).
fn mean_after(t: &[f64], y: &[f64], from: f64) -> f64 {
    let v: Vec<f64> = t
        .iter()
        .zip(y)
        .filter(|(ti, _)| **ti >= from)
        .map(|(_, yi)| *yi)
        .collect();
    v.iter().sum::<f64>() / v.len() as f64
}

/// Still water 0.3 m deep in an open 2D tank 0.4 m wide, 30 particles per depth: sensors
/// 5 cm long on the left wall at mid-depth, on the right wall near the bottom and on the
/// bottom read ρ g (h − z) at their centres (the pressure is linear along a wall, so the mean
/// over the face is its centre's value; on the bottom it is uniform). Tolerance 2 %: the
/// still pressure at the wall, extrapolated from the liquid to the wall face, carries the
/// lattice's error of order dx/h of a spacing in depth (1 cm in 15–30 cm here) and the
/// weakly compressible liquid's small acoustic ripple, which the mean over 0.5 s removes.
/// The summary carries the sensors of the open tank with their heights. A centre a little off
/// the wall is taken onto it.
#[test]
fn wall_sensors_read_hydrostatic_pressure_in_2d() {
    let script = r#"
tank(#{ shape: "rect", width: 0.4, height: 0.4, depth: 0.3, roof: false });
numerics(#{ scheme: "modern", dx: 0.01, rest_density: 1000.0 });
run(#{ settle: 0.0, duration: 1.0, output_interval: 0.01 });
wall_sensor("left", 0.0, 0.15, 0.05);
wall_sensor("right", 0.4, 0.05, 0.05);
wall_sensor("floor", 0.2, 0.0, 0.05);
wall_sensor("beside", 0.006, 0.15, 0.05);
"#;
    let (summary, c) = run(
        "2d",
        script,
        &["t", "p_left", "p_right", "p_floor", "p_beside"],
    );
    let level = summary.still_level;
    assert!((level - 0.3).abs() < 0.011, "still level {level}");
    for (k, (name, z)) in [("left", 0.15), ("right", 0.05), ("floor", 0.0)]
        .iter()
        .enumerate()
    {
        let measured = mean_after(&c[0], &c[k + 1], 0.5);
        let expected = DENSITY * GRAVITY * (level - z);
        assert!(
            (measured / expected - 1.0).abs() < 0.02,
            "{name}: {measured:.1} Pa against ρ g (h − z) = {expected:.1} Pa"
        );
    }
    let load = summary
        .roof_load
        .as_ref()
        .expect("an open tank with wall sensors has their loads in the summary");
    assert_eq!(load.sensors.len(), 4);
    // A centre 0.6 dx off the left wall is taken onto it: the same face and reading.
    assert!(
        (load.sensors[3].area - 0.05).abs() < 1e-9,
        "{}",
        load.sensors[3].area
    );
    assert_eq!(c[4], c[1]);
    assert_eq!(load.sensors[0].sensor.height, Some(0.15));
    assert!((load.sensors[0].area - 0.05).abs() < 1e-9, "a 5 cm face");
    assert_eq!(load.impacts, 0);
    assert!(load.sensors[2].load.peak > 0.0);
}

/// An open upright cylinder R = 0.15 m with 0.15 m of still water, 15 particles per depth: a
/// sensor 4 cm across on the curved shell at (R, 0, 0.05) reads ρ g (h − 0.05). Tolerance 2 %,
/// as in 2D (the shell is a polygon of wall particles at this spacing; at 10 per depth the
/// reading is 3 % high, a lattice error that halves and more with each refinement).
#[test]
fn a_wall_sensor_on_a_curved_shell_reads_hydrostatic_pressure() {
    let script = r#"
tank(#{ shape: "cylinder", radius: 0.15, height: 0.2, depth: 0.15, roof: "none" });
numerics(#{ scheme: "modern", dx: 0.01, rest_density: 1000.0 });
run(#{ settle: 0.0, duration: 0.4, output_interval: 0.01, frame_interval: 0.0 });
wall_sensor("shell", 0.15, 0.0, 0.05, 0.04);
"#;
    let (summary, c) = run("3d", script, &["t", "p_shell"]);
    let measured = mean_after(&c[0], &c[1], 0.2);
    let expected = DENSITY * GRAVITY * (summary.still_level - 0.05);
    assert!(
        (measured / expected - 1.0).abs() < 0.02,
        "{measured:.1} Pa against ρ g (h − z) = {expected:.1} Pa"
    );
}

/// A sensor whose centre is inside the liquid, away from every wall, is refused before the
/// run with its name and the nearest wall face; so is one at the top of an open tank's wall,
/// more than half of whose face would hang past the wall's end.
#[test]
fn a_wall_sensor_off_the_walls_stops_the_run_with_its_name() {
    refused(
        "off",
        r#"wall_sensor("mid", 0.2, 0.15, 0.05);"#,
        &["wall_sensor \"mid\"", "from the nearest wall face"],
    );
    refused(
        "wall-end",
        r#"wall_sensor("top", 0.0, 0.405, 0.1);"#,
        &["wall_sensor \"top\"", "the wall ends within its radius"],
    );
}

/// Runs a small tank with `sensor` and checks that the run is refused with every text of
/// `expected` in its message.
fn refused(name: &str, sensor: &str, expected: &[&str]) {
    let out = out_dir(name);
    let path = out.join("case.rhai");
    std::fs::write(
        &path,
        format!(
            r#"
tank(#{{ shape: "rect", width: 0.4, height: 0.4, depth: 0.3, roof: false }});
numerics(#{{ scheme: "modern", dx: 0.02 }});
run(#{{ settle: 0.0, duration: 0.05 }});
{sensor}
"#
        ),
    )
    .unwrap();
    let case = load_case(&path, &CaseOptions::default()).unwrap();
    let opts = RunOptions {
        out_dir: out.join("run"),
        plots: false,
        ..RunOptions::default()
    };
    let message = match run_case_with_stop(case, &opts, &mut ()) {
        Ok(summary) => format!("{:?}", summary.error),
        Err(e) => format!("{e:#}"),
    };
    assert!(expected.iter().all(|e| message.contains(e)), "{message}");
    let _ = std::fs::remove_dir_all(&out);
}
