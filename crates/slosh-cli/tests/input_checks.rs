//! Input checks of the commands besides `slosh run`: `slosh theory` refuses sizes that cannot
//! exist (negative numbers reach the check as values), `slosh sweep --plot` names an unknown
//! column before any case runs, and the sandbox and no-op-script checks reach the user.

use std::path::PathBuf;
use std::process::Command;

fn slosh() -> Command {
    Command::new(env!("CARGO_BIN_EXE_slosh"))
}

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("slosh-cli-input-checks")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs slosh and returns (success, stdout, stderr); fails the test on a panic.
fn run(args: &[&str]) -> (bool, String, String) {
    let out = slosh().args(args).output().expect("run slosh");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"),
        "slosh panicked: {stderr}"
    );
    (out.status.success(), stdout, stderr)
}

#[test]
fn theory_refuses_impossible_tanks_with_a_message() {
    for (args, name) in [
        (vec!["--width", "1", "--depth=-0.5"], "depth"),
        (vec!["--width", "1", "--depth", "-0.5"], "depth"),
        (vec!["--width", "0", "--depth", "0.5"], "width"),
        (vec!["--width", "nan", "--depth", "0.5"], "width"),
        (vec!["--width", "1", "--depth", "0.5", "--pga=-3"], "pga"),
        (
            vec!["--width", "1", "--depth", "0.5", "--tank-height", "0.4"],
            "roof",
        ),
    ] {
        let mut all = vec!["theory", "rect"];
        all.extend(&args);
        let (ok, stdout, stderr) = run(&all);
        assert!(!ok, "{args:?} was accepted: {stdout}");
        assert!(stderr.contains(name), "{args:?}: {stderr}");
        assert!(!stdout.contains("NaN"), "{args:?}: {stdout}");
    }
    let (ok, _, stderr) = run(&["theory", "rect", "--width", "1", "--depth", "0.5"]);
    assert!(ok, "{stderr}");
}

/// A small, fast 2D case: 0.4 m × 0.2 m of water at dx = 0.04 m for 0.05 s.
const SMALL_CASE: &str = r#"
let depth = param("depth", 0.2);
let duration = param("duration", 0.05);
tank(#{ shape: "rect", width: 0.4, height: 0.4, depth: depth });
numerics(#{ dx: 0.04 });
run(#{ settle: 0.0, duration: duration, output_interval: 0.005 });
fn ground_accel(t) { 0.5 * sin(20.0 * t) }
"#;

#[test]
fn sweep_plot_columns_are_checked_before_the_first_case() {
    let dir = temp("sweep_plot_columns");
    let case = dir.join("case.rhai");
    std::fs::write(&case, SMALL_CASE).unwrap();
    let out = dir.join("sweep");
    let (ok, _, stderr) = run(&[
        "sweep",
        case.to_str().unwrap(),
        "--vary",
        "duration=0.05,0.06",
        "--plot",
        "duration:no_such_col",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("no_such_col") && stderr.contains("max_roof_p"),
        "{stderr}"
    );
    assert!(!out.exists(), "a case ran before the plot was checked");
}

#[test]
fn sweep_plot_accepts_summary_theory_varied_and_post_columns() {
    let known = slosh_cli::sweep::known_columns(&["duration".to_string()]);
    for column in [
        "duration",
        "summary_duration",
        "max_roof_p",
        "theory_period_1",
        "status",
    ] {
        assert!(known.iter().any(|c| c == column), "{column}: {known:?}");
    }
    let plot = slosh_cli::sweep_plot::SweepPlot::parse("duration:max_roof_p,post_x").unwrap();
    plot.check_columns(&known).unwrap();
}

#[test]
fn warnings_reach_stderr_and_the_summary() {
    let dir = temp("warnings");
    let case = dir.join("case.rhai");
    std::fs::write(
        &case,
        SMALL_CASE.replace("fn ground_accel(t) { 0.5 * sin(20.0 * t) }", ""),
    )
    .unwrap();
    let out = dir.join("out");
    let (ok, _, stderr) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("warning: ") && stderr.contains("no fn ground_accel(t)"),
        "{stderr}"
    );
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(
        summary.contains("warnings") && summary.contains("no fn ground_accel(t)"),
        "{summary}"
    );
}

#[test]
fn misspelled_ground_accel_is_refused_by_slosh_run() {
    let dir = temp("typo");
    let case = dir.join("case.rhai");
    std::fs::write(
        &case,
        SMALL_CASE.replace("fn ground_accel(t)", "fn ground_acel(t)"),
    )
    .unwrap();
    let (ok, _, stderr) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("case.rhai:7:4:") && stderr.contains("fn ground_accel(t)"),
        "{stderr}"
    );
}

#[test]
fn allow_read_opens_a_folder_for_run_and_list_params() {
    let dir = temp("allow_read");
    let shared = temp("allow_read_records");
    let record = shared.join("r.at2");
    let mut at2 =
        String::from("t\nt\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 11, DT= 0.01\n");
    at2.push_str("0.0 0.1 0.2 0.1 0.0 -0.1 -0.2 -0.1 0.0 0.0 0.0\n");
    std::fs::write(&record, at2).unwrap();
    let case = dir.join("case.rhai");
    let script = SMALL_CASE.replace(
        "fn ground_accel(t) { 0.5 * sin(20.0 * t) }",
        &format!(
            "let gm = load_record(\"{}\");\nfn ground_accel(t) {{ gm.at(t) }}",
            record.display()
        ),
    );
    std::fs::write(&case, script).unwrap();
    let out = dir.join("out");
    let case = case.to_str().unwrap();
    let (ok, _, stderr) = run(&["run", case, "--out", out.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    assert!(
        stderr.contains("leaves the folders") && stderr.contains("--allow-read"),
        "{stderr}"
    );
    let allow = shared.to_str().unwrap();
    let (ok, stdout, stderr) = run(&["run", case, "--list-params", "--allow-read", allow]);
    assert!(ok && stdout.contains("duration"), "{stderr}");
    let (ok, _, stderr) = run(&[
        "run",
        case,
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--allow-read",
        allow,
    ]);
    assert!(ok, "{stderr}");
}

#[test]
fn sweep_passes_allow_read_to_its_cases() {
    let dir = temp("sweep_allow_read");
    let shared = temp("sweep_allow_read_records");
    let record = shared.join("r.at2");
    let mut at2 =
        String::from("t\nt\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 11, DT= 0.01\n");
    at2.push_str("0.0 0.1 0.2 0.1 0.0 -0.1 -0.2 -0.1 0.0 0.0 0.0\n");
    std::fs::write(&record, at2).unwrap();
    let case = dir.join("case.rhai");
    let script = SMALL_CASE.replace(
        "fn ground_accel(t) { 0.5 * sin(20.0 * t) }",
        &format!(
            "let gm = load_record(\"{}\");\nfn ground_accel(t) {{ gm.at(t) }}",
            record.display()
        ),
    );
    std::fs::write(&case, script).unwrap();
    let out = dir.join("sweep");
    let args = [
        "sweep",
        case.to_str().unwrap(),
        "--vary",
        "depth=0.2",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    let (ok, _, stderr) = run(&args);
    assert!(!ok && stderr.contains("--allow-read"), "{stderr}");
    let mut widened = args.to_vec();
    widened.extend(["--allow-read", shared.to_str().unwrap()]);
    let (ok, _, stderr) = run(&widened);
    assert!(ok, "{stderr}");
}
