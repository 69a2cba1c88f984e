//! No silent no-op script: a misspelled or mis-declared `ground_accel` or `post` is refused
//! with the name slosh expected and the place of the wrong definition; a script without any
//! excitation, and a record that ends before the run, are warnings on the case (an error when
//! the record covers less than 10 % of the excitation).

use slosh_script::{load_case, Case, CaseOptions};
use std::path::{Path, PathBuf};

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("slosh-script-noop-{}", std::process::id()))
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Loads a case made of a tank, a run of `duration` s (no settling) and `tail`.
fn load(test: &str, duration: f64, tail: &str) -> Result<Case, String> {
    load_case_from(test, duration, tail)
}

/// The error of a case that must be refused.
fn refused(test: &str, duration: f64, tail: &str) -> String {
    match load_case_from(test, duration, tail) {
        Ok(_) => panic!("{test}: the case should have been refused"),
        Err(e) => e,
    }
}

fn load_case_from(test: &str, duration: f64, tail: &str) -> Result<Case, String> {
    let dir = temp_dir(test);
    write_records(&dir);
    let path = dir.join("case.rhai");
    let script = format!(
        "tank(#{{ shape: \"rect\", width: 1.0, height: 1.0, depth: 0.5 }});\n\
         run(#{{ settle: 0.0, duration: {duration} }});\n{tail}"
    );
    std::fs::write(&path, script).unwrap();
    load_case(&path, &CaseOptions::default()).map_err(|e| e.to_string())
}

/// `short.at2`: 10 samples every 0.01 s (ends at 0.09 s); `cut.NS`: a K-NET file stating
/// 300 s and holding 1 s.
fn write_records(dir: &Path) {
    let mut at2 =
        String::from("t\nt\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 10, DT= 0.01\n");
    at2.push_str("0.0 0.1 0.2 0.1 0.0\n-0.1 -0.2 -0.1 0.0 0.0\n");
    std::fs::write(dir.join("short.at2"), at2).unwrap();
    let mut knet = String::new();
    for (label, value) in [
        ("Origin Time", "2011/03/11 14:46:00"),
        ("Lat.", "38.103"),
        ("Lon.", "142.860"),
        ("Depth. (km)", "24"),
        ("Mag.", "9.0"),
        ("Station Code", "MYG004"),
        ("Station Lat.", "37.6973"),
        ("Station Lon.", "141.0108"),
        ("Station Height(m)", "85"),
        ("Record Time", "2011/03/11 14:46:15"),
        ("Sampling Freq(Hz)", "100Hz"),
        ("Duration Time(s)", "300"),
        ("Dir.", "N-S"),
        ("Scale Factor", "7845(gal)/8223790"),
        ("Max. Acc. (gal)", "2699.943"),
        ("Last Correction", "2011/03/11 14:46:00"),
        ("Memo.", ""),
    ] {
        knet.push_str(&format!("{label:<18}{value}\n"));
    }
    for i in 0..100 {
        knet.push_str(&format!("{:>9}", (i % 5) * 100));
        if i % 8 == 7 {
            knet.push('\n');
        }
    }
    knet.push('\n');
    std::fs::write(dir.join("cut.NS"), knet).unwrap();
}

#[test]
fn misspelled_ground_accel_is_refused_at_its_definition() {
    let message = refused("typo", 1.0, "\nfn ground_acel(t) { 1.0 }\n");
    assert!(message.contains("fn ground_accel(t)"), "{message}");
    assert!(message.contains("ground_acel(t)"), "{message}");
    assert!(message.contains("case.rhai:4:4:"), "{message}");
}

#[test]
fn ground_accel_with_two_parameters_is_refused() {
    let message = refused("arity", 1.0, "fn ground_accel(t, u) { 1.0 }\n");
    assert!(
        message.contains("2 parameters") && message.contains("fn ground_accel(t)"),
        "{message}"
    );
    assert!(message.contains("case.rhai:3:4:"), "{message}");
}

#[test]
fn misspelled_or_mis_declared_post_is_refused() {
    let accel = "fn ground_accel(t) { 0.0 }\n";
    for (tail, found) in [
        ("fn pots(run) { #{} }", "pots(run)"),
        ("fn post(a, b) { #{} }", "post(a, b)"),
        ("fn Post(run) { #{} }", "Post(run)"),
    ] {
        let message = refused("post", 1.0, &format!("{accel}{tail}\n"));
        assert!(
            message.contains("fn post(run)") && message.contains(found),
            "{tail}: {message}"
        );
    }
}

#[test]
fn helpers_with_similar_names_that_the_script_calls_are_fine() {
    let tail = "fn cost(x) { x * 2.0 }\nlet c = cost(1.0);\nfn ground_accel(t) { cost(t) }\n\
                fn host(run) { 1 }\nfn post(run) { #{ h: host(run) } }\n";
    let case = load("helpers", 1.0, tail).unwrap();
    assert!(case.excitation.has_ground_accel() && case.excitation.has_post());
    assert!(case.warnings.is_empty(), "{:?}", case.warnings);
}

#[test]
fn no_excitation_is_a_warning() {
    let case = load("none", 1.0, "").unwrap();
    assert_eq!(case.warnings.len(), 1, "{:?}", case.warnings);
    assert!(
        case.warnings[0].contains("no fn ground_accel(t)"),
        "{:?}",
        case.warnings
    );
}

#[test]
fn a_record_that_ends_before_the_run_is_a_warning() {
    let tail = "let gm = load_record(\"short.at2\");\nfn ground_accel(t) { gm.at(t) }\n";
    // 0.09 s of record in a 0.5 s excitation: 18 %.
    let case = load("short_warning", 0.5, tail).unwrap();
    assert_eq!(case.warnings.len(), 1, "{:?}", case.warnings);
    let w = &case.warnings[0];
    assert!(
        w.contains("short.at2") && w.contains("0.09") && w.contains("0.5"),
        "{w}"
    );
    assert!((case.motions[0].end_time_s - 0.09).abs() < 1e-12);
    // The whole record inside the excitation: no warning.
    let case = load("short_ok", 0.09, tail).unwrap();
    assert!(case.warnings.is_empty(), "{:?}", case.warnings);
}

#[test]
fn a_record_covering_under_a_tenth_of_the_excitation_is_an_error() {
    let tail = "let gm = load_record(\"short.at2\");\nfn ground_accel(t) { gm.at(t) }\n";
    let message = refused("short_error", 2.0, tail);
    assert!(
        message.contains("short.at2") && message.contains("10 %"),
        "{message}"
    );
}

#[test]
fn a_knet_file_cut_short_of_its_header_warns_through_the_case() {
    let tail = "let gm = load_record(\"cut.NS\", #{ format: \"knet\" });\nfn ground_accel(t) { gm.at(t) }\n";
    let case = load("knet_cut", 1.0, tail).unwrap();
    assert_eq!(
        case.motions[0].warnings.len(),
        1,
        "{:?}",
        case.motions[0].warnings
    );
    assert!(
        case.warnings.iter().any(|w| w.contains("300 s")),
        "{:?}",
        case.warnings
    );
}
