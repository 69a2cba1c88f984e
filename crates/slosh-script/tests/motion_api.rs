//! The Rhai ground-motion API: records read relative to the script's folder, processed, and
//! evaluated by `ground_accel`; sines with the paper's sign; refused and missing paths.

use slosh_script::{load_case, Case, CaseOptions, ScriptError};
use std::path::{Path, PathBuf};

const G: f64 = 9.81;
/// The samples of the small AT2 file, in g, every 0.01 s.
const SAMPLES_G: [f64; 10] = [
    0.0, 0.01, -0.02, 0.035, -0.05, 0.04, -0.025, 0.015, -0.005, 0.0,
];

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("slosh-script-motion-{}", std::process::id()))
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_at2(path: &Path) {
    let mut text = String::from(
        "small test record\nwritten by the test\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=   10, DT= .01000 SEC\n",
    );
    for chunk in SAMPLES_G.chunks(4) {
        for v in chunk {
            text.push_str(&format!("{v:10.5}"));
        }
        text.push('\n');
    }
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A case script with `body` before the tank and `ground_accel` returning `accel`; the run
/// (0.02 s, no settling) is no longer than the test records, which would otherwise end before it.
fn case_script(dir: &Path, body: &str, accel: &str) -> PathBuf {
    let script = format!(
        "{body}\ntank(#{{ shape: \"rect\", width: 1.0, height: 1.0, depth: 0.5 }});\nrun(#{{ settle: 0.0, duration: 0.02 }});\nfn ground_accel(t) {{ {accel} }}\n"
    );
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

fn load(path: &Path) -> Result<Case, ScriptError> {
    load_case(path, &CaseOptions::default())
}

#[test]
fn scaled_record_is_returned_at_its_sample_times() {
    let dir = temp_dir("scaled");
    write_at2(&dir.join("records/small.at2"));
    let path = case_script(
        &dir,
        "let gm = load_record(\"records/small.at2\", #{ units: \"g\", format: \"at2\" }).scale(2.5);",
        "gm.at(t)",
    );
    let mut case = load(&path).unwrap();
    for (i, v) in SAMPLES_G.iter().enumerate() {
        let t = i as f64 * 0.01;
        let a = case.excitation.ground_accel(t).unwrap();
        assert!(
            (a[0] - 2.5 * v * G).abs() < 1e-12,
            "t = {t}: {} vs {}",
            a[0],
            2.5 * v * G
        );
        assert_eq!((a[1], a[2]), (0.0, 0.0));
    }
    // Linear between samples, zero outside.
    let mid = case.excitation.ground_accel(0.035).unwrap()[0];
    assert!((mid - 2.5 * G * 0.5 * (0.035 - 0.05)).abs() < 1e-12);
    assert_eq!(case.excitation.ground_accel(0.2).unwrap()[0], 0.0);

    // The log: one entry, with the hash, the samples and the scaling.
    assert_eq!(case.motions.len(), 1, "{:?}", case.motions);
    let m = &case.motions[0];
    assert_eq!(m.file, "records/small.at2");
    assert_eq!(m.format, "PEER AT2");
    assert_eq!(m.sha256.len(), 64);
    assert_eq!((m.npts, m.dt_s, m.units.as_str()), (10, 0.01, "g"));
    assert!((m.scale_factor - 2.5).abs() < 1e-15);
    assert!((m.pga_m_s2 - 2.5 * 0.05 * G).abs() < 1e-12);
    assert!(
        m.processing.last().unwrap().contains("scale by 2.5"),
        "{:?}",
        m.processing
    );
}

#[test]
fn scale_to_pga_queries_and_processing_chain() {
    let dir = temp_dir("pga");
    write_at2(&dir.join("small.at2"));
    let path = case_script(
        &dir,
        r#"
let raw = load_record("small.at2");
let gm = raw.remove_mean().detrend(1).scale_to_pga(3);
if (gm.pga() - 3.0).abs() > 1e-12 { throw "pga " + gm.pga(); }
if gm.npts() != 10 || (gm.dt() - 0.01).abs() > 1e-15 || (gm.duration() - 0.09).abs() > 1e-12 {
    throw "queries " + gm;
}
let later = raw.shift(2.0).trim(2.02, 2.06);
if later.npts() != 5 { throw "trim " + later; }
"#,
        "gm.at(t)",
    );
    let mut case = load(&path).unwrap();
    let peak = (0..10)
        .map(|i| case.excitation.ground_accel(i as f64 * 0.01).unwrap()[0].abs())
        .fold(0.0, f64::max);
    assert!((peak - 3.0).abs() < 1e-12, "peak {peak}");
    // Two branches from the same file: two log entries, each with its own chain.
    assert_eq!(case.motions.len(), 2, "{:?}", case.motions);
    assert!(case.motions[0]
        .processing
        .iter()
        .any(|p| p.starts_with("scale_to_pga 3")));
    assert!(case.motions[1]
        .processing
        .iter()
        .any(|p| p.starts_with("trim")));
    assert_eq!(case.motions[1].scale_factor, 1.0);
}

#[test]
fn sines_use_the_papers_sign_and_add_to_records() {
    let dir = temp_dir("sines");
    write_at2(&dir.join("small.at2"));
    let (a, w) = (0.0093, 5.311);
    let path = case_script(
        &dir,
        &format!(
            "let s = sine({a}, {w});\nlet s3 = sine({a}, {w}, 0.5);\nlet many = sines([[{a}, {w}], [0.002, 10.0, 0.25]]);\nlet both = load_record(\"small.at2\") + s;"
        ),
        "[s.at(t), many.at(t), s3.at(t) + both.at(t)]",
    );
    // Three components, one per excitation: a 3D tank (a 2D one takes two).
    let text = std::fs::read_to_string(&path).unwrap().replace(
        "shape: \"rect\", width: 1.0,",
        "shape: \"box\", length: 1.0, breadth: 0.5,",
    );
    std::fs::write(&path, text).unwrap();
    let mut case = load(&path).unwrap();
    for t in [0.0, 0.01, 0.05, 0.37, 1.0] {
        let g = case.excitation.ground_accel(t).unwrap();
        let paper = a * w * w * (w * t).sin();
        assert!(
            (g[0] - paper).abs() < 1e-12,
            "sine at {t}: {} vs {paper}",
            g[0]
        );
        let sum = paper + 0.002 * 100.0 * (10.0 * t + 0.25).sin();
        assert!((g[1] - sum).abs() < 1e-12);
        let rec = if t <= 0.09 {
            let x = t / 0.01;
            let i = (x.floor() as usize).min(8);
            G * (SAMPLES_G[i] + (SAMPLES_G[i + 1] - SAMPLES_G[i]) * (x - i as f64))
        } else {
            0.0
        };
        let expected = a * w * w * (w * t + 0.5).sin() + rec + paper;
        assert!(
            (g[2] - expected).abs() < 1e-12,
            "sum at {t}: {} vs {expected}",
            g[2]
        );
    }
}

fn load_error(test: &str, body: &str) -> String {
    let dir = temp_dir(test);
    write_at2(&dir.join("small.at2"));
    let path = case_script(&dir, body, "0.0");
    match load(&path) {
        Ok(_) => panic!("{test}: the script should fail"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn paths_leaving_the_script_folder_are_refused() {
    let msg = load_error("dotdot", "let gm = load_record(\"../small.at2\");");
    assert!(msg.contains("\"../small.at2\""), "{msg}");
    assert!(msg.contains("may only read files"), "{msg}");
    assert!(msg.contains("case.rhai:1:"), "no script position: {msg}");

    let msg = load_error("sneaky", "let gm = load_record(\"sub/../../small.at2\");");
    assert!(msg.contains("sub/../../small.at2"), "{msg}");

    let abs = std::env::temp_dir().join("small.at2");
    let msg = load_error(
        "absolute",
        &format!("let gm = load_record(\"{}\");", abs.display()),
    );
    assert!(msg.contains(&abs.display().to_string()), "{msg}");
    assert!(msg.contains("may only read files"), "{msg}");
}

#[test]
fn missing_and_bad_files_are_named() {
    let msg = load_error(
        "missing",
        "\n\nlet gm = load_record(\"records/missing.at2\");",
    );
    assert!(msg.contains("missing.at2"), "{msg}");
    assert!(msg.contains("case.rhai:3:"), "{msg}");

    let msg = load_error(
        "units",
        "let gm = load_record(\"small.at2\", #{ units: \"gal\" });",
    );
    assert!(msg.contains("small.at2") && msg.contains("in g"), "{msg}");

    let dir = temp_dir("plain");
    std::fs::write(dir.join("rec.csv"), "0.0, 0.1\n0.01, 0.2\n0.02, 0.3\n").unwrap();
    let path = case_script(&dir, "let gm = load_record(\"rec.csv\");", "gm.at(t)");
    let msg = load(&path).err().unwrap().to_string();
    assert!(msg.contains("rec.csv") && msg.contains("units"), "{msg}");
    let path = case_script(
        &dir,
        "let gm = load_record(\"rec.csv\", #{ units: \"gal\", format: \"csv\" });",
        "gm.at(t)",
    );
    let mut case = load(&path).unwrap();
    assert!((case.excitation.ground_accel(0.01).unwrap()[0] - 0.002).abs() < 1e-15);

    let msg = load_error(
        "typo",
        "let gm = load_record(\"small.at2\", #{ unit: \"g\" });",
    );
    assert!(msg.contains("unit") && msg.contains("small.at2"), "{msg}");
    let msg = load_error(
        "bad-pga",
        "let gm = load_record(\"small.at2\").scale_to_pga(-1.0);",
    );
    assert!(msg.contains("small.at2") && msg.contains("PGA"), "{msg}");
}
