//! `slosh converge` and the roof load outputs from the command line: the levels run as a
//! sweep (a second call reruns nothing), `convergence.csv` holds each level's summary value
//! and the Celik et al. (2008) numbers computed from them; a roof sensor over the whole flat
//! roof reads the roof force over the roof's length; a sensor off the roof stops the run with
//! its name.

use std::path::{Path, PathBuf};
use std::process::Command;

fn exe() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_slosh"))
}

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-cli-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small 2D tank filled to its flat roof and shaken hard for 0.1 s, so that the liquid
/// presses on the roof from the first steps; a sensor over the whole roof (x = 0.2 m, 0.4 m
/// long) and one at `sensor_x`.
fn roofed_case(dir: &Path) -> PathBuf {
    let script = r#"
let dx = param("dx", 0.04);
let sensor_x = param("sensor_x", 0.1);
tank(#{ shape: "rect", width: 0.4, height: 0.24, depth: 0.24, roof: true });
numerics(#{ scheme: "modern", dx: dx });
run(#{ settle: 0.0, duration: 0.1, output_interval: 0.005, roof_periods: [0.01, 0.05] });
roof_sensor("all", 0.2, 0.4);
roof_sensor("side", sensor_x, 0.05);
fn ground_accel(t) { 6.0 }
"#;
    let path = dir.join("roofed.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

/// Reads a CSV file as (header, rows of text).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header = reader.headers().unwrap().iter().map(String::from).collect();
    let rows = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

/// The three levels' `max_eta_left` and `roof_impulse` in `convergence.csv` are the levels'
/// own summary values, its order and GCI follow from them by Celik et al. (2008) Eq. 3–9, and
/// a second call runs no level again.
#[test]
fn three_levels_give_the_report_and_a_second_call_reruns_nothing() {
    let dir = temp("converge-three-levels");
    let case = roofed_case(&dir);
    let out = dir.join("study");
    let run = || {
        Command::new(exe())
            .args(["converge"])
            .arg(&case)
            .args([
                "--param", "dx", "--levels", "3", "--ratio", "2", "--jobs", "1", "--out",
            ])
            .arg(&out)
            .output()
            .unwrap()
    };
    let first = run();
    let stderr = String::from_utf8_lossy(&first.stderr);
    assert!(first.status.success(), "{stderr}");
    assert!(out.join("convergence.md").is_file());
    let (header, rows) = read_csv(&out.join("convergence.csv"));
    assert_eq!(
        &header[..4],
        &["quantity", "dx=0.04", "dx=0.02", "dx=0.01"].map(String::from)
    );
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    for quantity in [
        "max_eta_left",
        "roof_impulse",
        "roof_f_eq_50ms",
        "p_all_peak",
    ] {
        let row = rows
            .iter()
            .find(|r| r[0] == quantity)
            .unwrap_or_else(|| panic!("{quantity} missing from convergence.csv"));
        let values: Vec<f64> = (1..=3).map(|k| row[k].parse().unwrap()).collect();
        // Each level's value is that of its own summary (via sweep.csv's row).
        let (sh, srows) = read_csv(&out.join("sweep.csv"));
        let sc = sh.iter().position(|h| h == quantity).unwrap();
        for (k, r) in srows.iter().enumerate() {
            let v: f64 = r[sc].parse().unwrap();
            assert!(
                (v - values[k]).abs() <= 1e-12 * v.abs().max(1.0),
                "{quantity}"
            );
        }
        let u = slosh_validate::gci::uncertainty(&values, &[0.04, 0.02, 0.01]);
        assert_eq!(row[col("behaviour")], u.behaviour.word(), "{quantity}");
        let gci: f64 = row[col("gci_fine")].parse().unwrap();
        assert!(
            (gci.is_nan() && u.gci_fine.is_nan()) || (gci - u.gci_fine).abs() < 1e-9,
            "{quantity}: {gci} against {}",
            u.gci_fine
        );
    }
    let summaries = |out: &Path| -> Vec<std::time::SystemTime> {
        let mut times: Vec<_> = std::fs::read_dir(out)
            .unwrap()
            .filter_map(|e| {
                let p = e.unwrap().path().join("summary.ron");
                p.is_file()
                    .then(|| std::fs::metadata(&p).unwrap().modified().unwrap())
            })
            .collect();
        times.sort();
        times
    };
    let before = summaries(&out);
    assert_eq!(before.len(), 3, "one folder per level");
    let second = run();
    assert!(second.status.success());
    assert_eq!(summaries(&out), before, "a second call runs no level again");
}

/// A sensor over the whole flat roof (unit normals) reads the roof force over the roof's
/// length at every step: its peak × 0.4 m is the roof's peak force (to rounding), and the
/// outputs name it. A sensor off the roof stops the run with its name.
#[test]
fn a_sensor_over_the_whole_roof_reads_the_roof_force() {
    let dir = temp("converge-roof-sensor");
    let case = roofed_case(&dir);
    let out = dir.join("run");
    let o = Command::new(exe())
        .arg("run")
        .arg(&case)
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    #[derive(serde::Deserialize)]
    struct Head {
        roof_load: Option<slosh_run::RoofLoadSummary>,
    }
    let head: Head = ron::from_str(&text).unwrap();
    let load = head.roof_load.expect("a roofed tank has a roof load");
    assert!(load.roof.peak > 0.0, "the liquid presses on the roof");
    let all = &load.sensors[0];
    assert!(
        (all.area - 0.4).abs() < 1e-9,
        "the whole roof: {}",
        all.area
    );
    assert!(
        (all.load.peak * all.area - load.roof.peak).abs() <= 1e-9 * load.roof.peak,
        "{} × {} against {}",
        all.load.peak,
        all.area,
        load.roof.peak
    );
    assert!((load.sensors[1].area - 0.05).abs() < 1e-9, "a 5 cm segment");
    let (header, rows) = read_csv(&out.join("roof_spectrum.csv"));
    assert_eq!(
        header,
        [
            "period",
            "roof_f_eq",
            "roof_dlf",
            "p_all_eq",
            "p_all_dlf",
            "p_side_eq",
            "p_side_dlf"
        ]
        .map(String::from)
    );
    assert_eq!(rows.len(), slosh_run::roof_load::SPECTRUM_POINTS);
    let (series, _) = read_csv(&out.join("series.csv"));
    for c in ["p_all", "p_side", "roof_impulse"] {
        assert!(series.iter().any(|h| h == c), "series.csv has {c}");
    }

    let o = Command::new(exe())
        .arg("run")
        .arg(&case)
        .args(["--quiet", "--set", "sensor_x=5.0", "--out"])
        .arg(dir.join("off"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("roof_sensor \"side\"") && err.contains("covers no point of the roof"),
        "{err}"
    );
}
