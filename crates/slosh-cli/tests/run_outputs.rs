//! What a run shows its user: filtered loads beside the raw ones, roof plots only after roof
//! contact, every gauge on the elevation plot, progress lines without a terminal.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("slosh-cli-run-outputs")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small 2D tank with a roof (0.4 m wide, 0.2 m of water, dx = 0.04 m) shaken at its
/// first sloshing frequency with `accel` m/s²; `tilt` is the initial elevation at the left
/// wall and `run_extra` goes into the `run(#{...})` map.
fn roofed_case(dir: &Path, tank_height: f64, tilt: f64, accel: f64, run_extra: &str) -> PathBuf {
    let script = format!(
        r#"
let duration = param("duration", 0.3); // total simulated time (s)
tank(#{{ shape: "rect", width: 0.4, height: {tank_height}, depth: 0.2, roof: true, tilt: {tilt} }});
numerics(#{{ dx: 0.04 }});
run(#{{ settle: 0.0, duration: duration, output_interval: 0.005 {run_extra} }});
gauge("mid", 0.2);
fn ground_accel(t) {{ {accel} * sin(8.5 * t) }}
"#
    );
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

fn slosh_run(case: &Path, out: &Path, extra: &[&str]) -> Output {
    let output = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args([
            "run",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(extra)
        .output()
        .expect("run slosh");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    output
}

fn read(path: PathBuf) -> String {
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn filtered_loads_are_appended_after_the_raw_columns() {
    let dir = temp("filtered");
    let case = roofed_case(&dir, 0.4, 0.0, 0.5, ", load_filter_hz: 12.5");
    let out = dir.join("out");
    slosh_run(&case, &out, &["--quiet"]);
    let series = read(out.join("series.csv"));
    let header: Vec<&str> = series.lines().next().unwrap().split(',').collect();
    let first_lp = header.iter().position(|c| c.ends_with("_lp")).unwrap();
    assert!(
        header[first_lp..].iter().all(|c| c.ends_with("_lp")),
        "{header:?}"
    );
    assert_eq!(
        &header[first_lp..],
        [
            "base_shear_x_lp",
            "roof_force_up_lp",
            "overturning_moment_lp"
        ]
    );
    let rows: Vec<Vec<f64>> = series
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert!(rows.iter().all(|r| r.len() == header.len()));
    let units = read(out.join("series_units.csv"));
    assert!(
        units.contains("base_shear_x_lp,\"N/m (low-pass 12.500 Hz"),
        "{units}"
    );
    let summary = read(out.join("summary.ron"));
    assert!(summary.contains("cutoff_hz: 12.5,"), "{summary}");
    assert!(summary.contains("max_abs_base_shear_x_lp:"), "{summary}");
    assert!(summary.contains("max_abs_base_shear_x:"), "{summary}");
    let shear_plot = read(out.join("plots/base_shear.svg"));
    assert!(shear_plot.contains("base_shear_x (raw)"), "legend: raw");
    assert!(shear_plot.contains("base_shear_x_lp (low-pass 12.50 Hz)"));
}

#[test]
fn no_roof_plots_without_roof_contact() {
    let dir = temp("no_contact");
    let case = roofed_case(&dir, 0.4, 0.0, 0.5, "");
    let out = dir.join("out");
    slosh_run(&case, &out, &["--quiet"]);
    let summary = read(out.join("summary.ron"));
    assert!(summary.contains("roof_contact: false"), "{summary}");
    assert!(summary.contains("no roof contact"), "{summary}");
    for plot in ["roof_force", "roof_pressure", "roof_pressure_map"] {
        assert!(!out.join(format!("plots/{plot}.png")).exists(), "{plot}");
    }
    assert!(out.join("plots/base_shear.png").exists());
}

#[test]
fn roof_plots_after_roof_contact() {
    let dir = temp("contact");
    // One spacing of clearance, the surface tilted up to the roof at the left wall, and a
    // strong resonant shake.
    let case = roofed_case(&dir, 0.24, 0.04, 3.0, "");
    let out = dir.join("out");
    slosh_run(&case, &out, &["--quiet"]);
    let summary = read(out.join("summary.ron"));
    assert!(summary.contains("roof_contact: true"), "{summary}");
    assert!(summary.contains("roof_note: None"), "{summary}");
    for plot in ["roof_force", "roof_pressure", "roof_pressure_map"] {
        assert!(out.join(format!("plots/{plot}.png")).exists(), "{plot}");
    }
}

#[test]
fn every_gauge_is_on_the_elevation_plot() {
    let dir = temp("gauges");
    let case = roofed_case(&dir, 0.4, 0.0, 0.5, "");
    let out = dir.join("out");
    slosh_run(&case, &out, &["--quiet", "--set", "duration=0.05"]);
    let plot = read(out.join("plots/eta.svg"));
    for gauge in ["eta_left", "eta_right", "eta_mid"] {
        assert!(plot.contains(gauge), "{gauge} missing from eta.svg");
    }
}

#[test]
fn every_gauge_is_on_the_elevation_plot_in_3d() {
    let dir = temp("gauges_3d");
    let case = dir.join("box.rhai");
    std::fs::write(
        &case,
        r#"
tank(#{ shape: "box", length: 0.4, breadth: 0.2, height: 0.4, depth: 0.2 });
numerics(#{ dx: 0.04 });
run(#{ settle: 0.0, duration: 0.03, output_interval: 0.005 });
gauge("mid", 0.2, 0.1);
fn ground_accel(t) { 0.5 * sin(8.5 * t) }
"#,
    )
    .unwrap();
    let out = dir.join("out");
    slosh_run(&case, &out, &["--quiet"]);
    let plot = read(out.join("plots/eta.svg"));
    for gauge in ["eta_left", "eta_right", "eta_mid"] {
        assert!(plot.contains(gauge), "{gauge} missing from eta.svg");
    }
    let series = read(out.join("series.csv"));
    let header = series.lines().next().unwrap();
    assert!(header.ends_with(
        "base_shear_x_lp,base_shear_y_lp,roof_force_up_lp,overturning_moment_y_lp,overturning_moment_x_lp"
    ), "{header}");
}

#[test]
fn progress_lines_without_a_terminal_and_none_with_quiet() {
    let dir = temp("progress");
    let case = roofed_case(&dir, 0.4, 0.0, 0.5, "");
    let out = dir.join("out");
    let output = slosh_run(&case, &out, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| l.contains("ETA")).collect();
    assert_eq!(lines.len(), 10, "{stderr}");
    assert!(lines[0].contains("(10 %)") && lines[0].contains("steps/s"));
    assert!(lines[9].contains("(100 %)"), "{stderr}");
    // --quiet: no progress; warnings (here the roof clearance of 5 spacings) still print.
    let quiet = slosh_run(&case, &out, &["--quiet"]);
    let quiet_err = String::from_utf8_lossy(&quiet.stderr);
    assert!(
        quiet_err.lines().all(|l| l.starts_with("warning: ")),
        "{quiet_err}"
    );
}
