//! Recorded ground motion end to end, on a coarse, short run of `scripts/elcentro_2d.rhai`: `accel_x` in
//! series.csv is the record × scaling at the record's sample times from the end of settling,
//! its peak is 0.31882 g × scale, and the run writes the input spectrum and the record's log.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn elcentro_2d_applies_the_scaled_record() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = std::env::temp_dir()
        .join("slosh-cli-tests")
        .join(format!("elcentro-input-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let (settle, pga) = (2.0, 3.0);
    // dx = 0.1 m (300 fluid particles) and a fixed dt = 0.5 ms that divides the output interval
    // and the record's 0.02 s, so the rows fall on the record's samples; 2.5 s of the record
    // cover its peak at 2.02 s.
    let status = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .arg("run")
        .arg(root.join("scripts/elcentro_2d.rhai"))
        .arg("--out")
        .arg(&out)
        .args([
            "--set",
            "dx=0.1",
            "--set",
            "dt=0.0005",
            "--set",
            "duration=4.5",
        ])
        .args(["--set", "frame_interval=0", "--set", "pga=3.0", "--quiet"])
        .status()
        .unwrap();
    assert!(status.success());

    let record = slosh_motion::read_at2(root.join("data/elcentro_1940_ns.at2")).unwrap();
    let g = slosh_motion::GRAVITY_M_S2;
    let scale = pga / (0.31882 * g);
    let table = slosh_io::read_table(out.join("series.csv")).unwrap();
    let t = table.column("t").unwrap();
    let accel = table.column("accel_x").unwrap();
    let mut on_samples = 0;
    let mut peak: f64 = 0.0;
    for (&t, &a) in t.iter().zip(&accel) {
        if t < settle - 1e-9 {
            assert_eq!(a, 0.0, "no excitation while settling (t = {t})");
            continue;
        }
        peak = peak.max(a.abs());
        let k = ((t - settle) / record.dt_s).round();
        if ((t - settle) - k * record.dt_s).abs() < 1e-9 {
            let expected = record.accel_m_s2[k as usize] * scale;
            let tol = 1e-6 * expected.abs().max(1e-3 * pga);
            assert!((a - expected).abs() <= tol, "t = {t}: {a} vs {expected}");
            on_samples += 1;
        }
    }
    assert!(
        on_samples >= 120,
        "only {on_samples} rows on the record's samples"
    );
    assert!(
        (peak - 0.31882 * g * scale).abs() < 1e-9 * pga,
        "peak {peak}"
    );

    assert!(out.join("input_spectrum.csv").exists());
    assert!(out.join("plots/input_spectrum.png").exists());
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("elcentro_1940_ns.at2") && summary.contains("sha256"));
    assert!(summary.contains("scale_to_pga 3"));
    assert!(summary.contains("input_spectrum: Some"));
}
