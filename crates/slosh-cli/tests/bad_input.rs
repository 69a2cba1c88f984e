//! Bad input gives a clear one-paragraph error and a non-zero exit code, never a panic;
//! a blow-up keeps the outputs written so far and says when it happened.

use std::path::{Path, PathBuf};
use std::process::Command;

fn slosh() -> Command {
    Command::new(env!("CARGO_BIN_EXE_slosh"))
}

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-cli-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small, fast 2D case (0.4 m × 0.2 m of water at dx = 0.04 m: 50 fluid particles) whose
/// ground motion and extra lines can be replaced.
fn small_case(dir: &Path, ground_accel_body: &str, extra: &str) -> PathBuf {
    let script = format!(
        r#"
let width = param("width", 0.4);
let tank_height = param("tank_height", 0.4);
let depth = param("depth", 0.2);
let dx = param("dx", 0.04);
let dt = param("dt", 0.0);
let allow_unstable_dt = param("allow_unstable_dt", false);
let duration = param("duration", 0.05);
tank(#{{ shape: "rect", width: width, height: tank_height, depth: depth }});
let eos_b = param("eos_b", 0.0); let nm = #{{ dx: dx, dt: dt, allow_unstable_dt: allow_unstable_dt }}; if eos_b > 0.0 {{ nm.eos_b = eos_b; }} numerics(nm);
run(#{{ settle: 0.0, duration: duration, output_interval: 0.005 }});
{extra}
fn ground_accel(t) {{ {ground_accel_body} }}
"#
    );
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

/// Runs `slosh` in the folder of the case script among `args` and returns (success, stderr).
/// A run given no `--out` writes to `out/<case>` under its working folder: run from the
/// test's own folder, tests that run at the same time never share (and lock) one run folder.
fn run(args: &[&str]) -> (bool, String) {
    let cwd = args
        .iter()
        .find(|a| a.ends_with(".rhai"))
        .and_then(|a| Path::new(a).parent())
        .map_or_else(std::env::temp_dir, Path::to_path_buf);
    let out = slosh()
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run slosh");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"),
        "slosh panicked: {stderr}"
    );
    (out.status.success(), stderr)
}

#[test]
fn small_case_runs() {
    let dir = temp("small_case_runs");
    let case = small_case(&dir, "0.0", "");
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{err}");
    assert!(out.join("series.csv").exists() && out.join("summary.ron").exists());
}

#[test]
fn syntax_error_reports_file_line_column() {
    let dir = temp("syntax_error");
    let case = small_case(&dir, "0.0", "let x = (1 + ;");
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    // The extra line is line 12 of the generated script (it starts with a newline), column 14.
    assert!(err.contains("case.rhai:12:14:"), "{err}");
}

#[test]
fn unknown_set_name_lists_the_parameters() {
    let dir = temp("unknown_set");
    let case = small_case(&dir, "0.0", "");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--set",
        "widht=0.5",
        "--quiet",
    ]);
    assert!(!ok);
    assert!(
        err.contains("widht") && err.contains("width = 0.4"),
        "{err}"
    );
}

#[test]
fn non_numeric_value_is_refused() {
    let dir = temp("non_numeric");
    let case = small_case(&dir, "0.0", "");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--set",
        "width=abc",
        "--quiet",
    ]);
    assert!(!ok);
    assert!(
        err.contains("width") && err.contains("expects a number"),
        "{err}"
    );
}

#[test]
fn zero_width_is_refused() {
    let dir = temp("zero_width");
    let case = small_case(&dir, "0.0", "");
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--set", "width=0", "--quiet"]);
    assert!(!ok);
    assert!(err.contains("width"), "{err}");
}

#[test]
fn depth_above_tank_height_is_refused() {
    let dir = temp("depth_above");
    let case = small_case(&dir, "0.0", "");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--set",
        "depth=0.6",
        "--quiet",
    ]);
    assert!(!ok);
    assert!(err.contains("above the tank height"), "{err}");
}

#[test]
fn dx_larger_than_the_tank_is_refused() {
    let dir = temp("dx_too_large");
    let case = small_case(&dir, "0.0", "");
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--set", "dx=2.0", "--quiet"]);
    assert!(!ok);
    assert!(err.contains("dx"), "{err}");
}

#[test]
fn nan_ground_motion_is_reported() {
    let dir = temp("nan_motion");
    let case = small_case(&dir, "0.0 / 0.0", "");
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!ok);
    assert!(err.contains("non-finite"), "{err}");
}

#[test]
fn fixed_dt_above_the_bound_is_refused_with_the_bound() {
    let dir = temp("dt_bound");
    let case = small_case(&dir, "0.0", "");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--set",
        "dt=0.001",
        "--quiet",
    ]);
    assert!(!ok);
    assert!(
        err.contains("stability bound") && err.contains("allow_unstable_dt"),
        "{err}"
    );
}

/// A violent excitation (100 g) with a sound speed too low for it (the paper's stiffness,
/// c0 = 26.6 m/s, where the rule would take 10 × √(2 a L) = 283 m/s) throws the liquid out of
/// the domain: the run stops with the time of the blow-up and keeps series.csv and summary.ron.
#[test]
fn blow_up_keeps_outputs_and_says_when() {
    let dir = temp("blow_up");
    let case = small_case(&dir, "if t > 0.01 { 1000.0 } else { 0.0 }", "");
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--set",
        "duration=2.0",
        "--set",
        "eos_b=101300",
        "--quiet",
    ]);
    assert!(!ok);
    assert!(err.contains("blew up at t ="), "{err}");
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert!(
        series.lines().count() > 2,
        "rows written before the blow-up are kept"
    );
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"failed\""), "{summary}");
}

#[test]
fn set_twice_names_the_parameter() {
    let dir = temp("set_twice");
    let case = small_case(&dir, "0.0", "");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--set",
        "depth=0.2",
        "--set",
        "depth=0.3",
        "--quiet",
    ]);
    assert!(!ok);
    assert!(err.contains("--set depth is given twice"), "{err}");
}

#[test]
fn non_finite_set_value_is_refused() {
    let dir = temp("set_inf");
    let case = small_case(&dir, "0.0", "");
    for value in ["duration=inf", "depth=nan"] {
        let (ok, err) = run(&["run", case.to_str().unwrap(), "--set", value, "--quiet"]);
        assert!(!ok);
        assert!(err.contains("must be a finite number"), "{err}");
    }
}

#[test]
fn list_params_prints_the_declared_parameters() {
    let out = slosh()
        .args([
            "run",
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../../scripts/paper_2d_sloshing.rhai"
            ),
            "--list-params",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for name in [
        "width",
        "tank_height",
        "depth",
        "amplitude",
        "omega",
        "dx",
        "settle",
        "duration",
        "initial_tilt",
        "scheme",
        "layout",
    ] {
        assert!(text.contains(name), "missing {name} in\n{text}");
    }
    assert!(
        text.contains("wall parts") && text.contains("the flat roof"),
        "parts in\n{text}"
    );
    let width = text.lines().find(|l| l.starts_with("width ")).unwrap();
    assert!(
        width.contains(" m ") && width.contains("inner tank width"),
        "unit and description: {width}"
    );
}

/// A `post(run)` that throws reports the script line and keeps the run's other outputs.
#[test]
fn failing_post_reports_the_line_and_keeps_outputs() {
    let dir = temp("post_throws");
    let case = small_case(&dir, "0.0", "fn post(run) {\n    throw \"no result\";\n}");
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!ok);
    // `throw` is on line 13 of the generated script.
    assert!(
        err.contains("case.rhai:13:") && err.contains("no result"),
        "{err}"
    );
    assert!(out.join("series.csv").exists());
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("post_error: Some("), "{summary}");
}

/// `slosh run --help` and `slosh help run` list the shipped scripts with their purpose, found
/// from the executable's repository when the current folder has no `scripts/`.
#[test]
fn run_help_lists_the_shipped_scripts() {
    let elsewhere = temp("help_elsewhere");
    for args in [["run", "--help"], ["help", "run"]] {
        let out = slosh().args(args).current_dir(&elsewhere).output().unwrap();
        assert!(out.status.success());
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            text.contains("paper_2d_sloshing.rhai")
                && text.contains("Paper §3.1: resonant sloshing"),
            "{args:?}: {text}"
        );
        assert!(text.contains("cylinder_3d.rhai"), "{text}");
    }
}

/// Every script shipped in `scripts/` reads, declares its parameters and describes its tank
/// (`--list-params` evaluates the whole script, meshes and motion records included), so a
/// user starting from any of them meets no error the repository could have caught.
#[test]
fn every_shipped_script_lists_its_parameters() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut checked = 0;
    for entry in std::fs::read_dir(root.join("scripts")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("rhai") {
            continue;
        }
        let out = slosh()
            .args(["run", path.to_str().unwrap(), "--list-params"])
            .current_dir(&root)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && !stdout.trim().is_empty(),
            "{}: {stderr}",
            path.display()
        );
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} scripts found");
}

/// Writes `script` as `case.rhai` in `dir`.
fn write_case(dir: &Path, script: &str) -> PathBuf {
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

#[test]
fn self_intersecting_outline_is_refused_at_the_tank_call() {
    let dir = temp("self_intersecting_outline");
    let case = write_case(
        &dir,
        "// a bow tie\nlet d = 0.5;\ntank(#{ shape: \"polygon\", depth: d,\n  outline: [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]] });\n",
    );
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    assert!(err.contains("case.rhai:3:1:"), "{err}");
    assert!(err.contains("side 0") && err.contains("side 2"), "{err}");
}

#[test]
fn cone_roof_section_runs_and_the_summary_names_its_parts() {
    let dir = temp("cone_roof_section");
    let case = write_case(
        &dir,
        "// cone roof\ntank(#{ shape: \"rect\", width: 0.4, height: 0.4, depth: 0.2, roof: \"cone\", roof_rise: 0.1 });\n\
         numerics(#{ dx: 0.04 });\nrun(#{ settle: 0.0, duration: 0.02, output_interval: 0.005 });\n",
    );
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{err}");
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    // roof: two slopes of √(0.2² + 0.1²) m
    let roof = 2.0 * 0.2f64.hypot(0.1);
    let line = summary
        .lines()
        .find(|l| l.contains("(\"roof\","))
        .unwrap_or_else(|| panic!("no roof part in {summary}"));
    let value: f64 = line
        .trim()
        .trim_start_matches("(\"roof\",")
        .trim_end_matches("),")
        .trim()
        .parse()
        .unwrap();
    assert!((value - roof).abs() < 1e-9 * roof, "{line}");
    assert!(summary.contains("(\"bottom\",") && summary.contains("(\"wall\","));
}

/// `slosh validate` refuses a checkpoint interval it cannot read before it runs anything,
/// naming the option and the forms it takes.
#[test]
fn validate_refuses_a_bad_checkpoint_interval() {
    let dir = temp("validate_checkpoint_every");
    let out = dir.join("validate");
    let (ok, stderr) = run(&[
        "validate",
        "--quick",
        "--only",
        "no such stage",
        "--out",
        out.to_str().unwrap(),
        "--checkpoint-every",
        "5 fortnights",
    ]);
    assert!(!ok);
    assert!(stderr.contains("--checkpoint-every"), "{stderr}");
    assert!(stderr.contains("10m"), "{stderr}");
    assert!(!out.join("report.md").exists());
}

/// `slosh validate --only` with text that names no stage stops with the list of stages
/// instead of writing an empty report.
#[test]
fn validate_refuses_an_only_that_matches_no_stage() {
    let dir = temp("validate_only");
    let out = dir.join("validate");
    let (ok, stderr) = run(&[
        "validate",
        "--quick",
        "--only",
        "no such stage",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(stderr.contains("matches no stage"), "{stderr}");
    assert!(stderr.contains("dam break: front"), "{stderr}");
    assert!(!out.join("report.md").exists());
}

/// A cylinder's `lattice` other than "cubic" or "polar" is refused at the `tank` call; the
/// polar lattice with an internal solid is refused with the reason; a box has no `lattice`.
#[test]
fn bad_cylinder_lattice_is_refused() {
    let dir = temp("bad_lattice");
    let case = write_case(
        &dir,
        "let r = 0.5;\ntank(#{ shape: \"cylinder\", radius: r, height: 0.6, depth: 0.4,\n  lattice: \"hexagonal\" });\n",
    );
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    assert!(err.contains("case.rhai:2:1:"), "{err}");
    assert!(
        err.contains("\"hexagonal\"") && err.contains("\"polar\""),
        "{err}"
    );
    let case = write_case(
        &dir,
        "tank(#{ shape: \"cylinder\", radius: 0.5, height: 0.6, depth: 0.4, lattice: \"polar\",\n  \
         solids: [#{ name: \"column\", shape: \"column\", centre: [0.0, 0.0], radius: 0.1, bottom: 0.0, top: 0.6 }] });\n\
         numerics(#{ dx: 0.05 });\nrun(#{ duration: 0.01 });\n",
    );
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    assert!(
        err.contains("polar lattice") && err.contains("internal solids"),
        "{err}"
    );
    let case = write_case(
        &dir,
        "tank(#{ shape: \"box\", length: 1.0, breadth: 0.2, height: 0.6, depth: 0.4, lattice: \"polar\" });\n",
    );
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    assert!(
        err.contains("lattice") && err.contains("unknown key"),
        "{err}"
    );
}

/// A thread count far beyond the machine (a typo) is refused at once with the largest it
/// takes, instead of starting threads until the system refuses; 0 is refused too.
#[test]
fn absurd_thread_counts_are_refused() {
    let dir = temp("threads");
    let c = small_case(&dir, "0.0", "");
    for n in ["99999999999", "0"] {
        let (ok, err) = run(&[
            "run",
            c.to_str().unwrap(),
            "--threads",
            n,
            "--out",
            dir.join("out").to_str().unwrap(),
        ]);
        assert!(!ok, "--threads {n} accepted");
        assert!(err.contains("--threads"), "{n}: {err}");
    }
    // The array tasks of a sweep or an assessment check it before anything starts: no
    // folder is made.
    for n in ["99999999999", "0"] {
        let sweep_out = dir.join(format!("sweep{n}"));
        let (ok, err) = run(&[
            "sweep",
            c.to_str().unwrap(),
            "--vary",
            "duration=0.05,0.06",
            "--task",
            "0",
            "--threads",
            n,
            "--out",
            sweep_out.to_str().unwrap(),
        ]);
        assert!(!ok && err.contains("--threads"), "sweep task, {n}: {err}");
        assert!(
            !sweep_out.exists(),
            "the sweep task made {}",
            sweep_out.display()
        );
        let (ok, err) = run(&[
            "assess",
            "--task",
            "0",
            "--threads",
            n,
            "--out",
            sweep_out.to_str().unwrap(),
        ]);
        assert!(!ok && err.contains("--threads"), "assess task, {n}: {err}");
    }
}

/// Numbers no run can mean are refused with what to give instead, never a panic or a run that
/// "completes" without physics: gravity of zero (or negative, or not a number), a checkpoint
/// interval beyond any clock, a sweep of 10¹² cases.
#[test]
fn impossible_numbers_are_refused() {
    let dir = temp("impossible_numbers");
    for g in ["0.0", "-9.81"] {
        let script = dir.join(format!("g{}.rhai", g.len()));
        std::fs::write(
            &script,
            format!(
                "tank(#{{ shape: \"rect\", width: 0.4, height: 0.4, depth: 0.2 }});\n\
                 numerics(#{{ dx: 0.04, gravity: {g} }});\n\
                 run(#{{ settle: 0.0, duration: 0.1 }});\n"
            ),
        )
        .unwrap();
        let (ok, err) = run(&[
            "run",
            script.to_str().unwrap(),
            "--out",
            dir.join("g").to_str().unwrap(),
        ]);
        assert!(!ok, "gravity {g} accepted");
        assert!(err.contains("gravity"), "{g}: {err}");
    }
    let c = small_case(&dir, "0.0", "");
    for every in ["1e20", "1e300s", "1e17h"] {
        let (ok, err) = run(&[
            "run",
            c.to_str().unwrap(),
            "--checkpoint-every",
            every,
            "--out",
            dir.join("every").to_str().unwrap(),
        ]);
        assert!(!ok, "--checkpoint-every {every} accepted");
        assert!(err.contains("checkpoint"), "{every}: {err}");
    }
    let (ok, err) = run(&[
        "sweep",
        c.to_str().unwrap(),
        "--vary",
        "width=1:10000:1",
        "--vary",
        "depth=1:10000:1",
        "--vary",
        "dx=1:10000:1",
        "--slurm",
        "--out",
        dir.join("sweep").to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("at most"), "{err}");
    assert!(
        !dir.join("sweep").exists(),
        "the sweep folder was made before the refusal"
    );
}

/// A run that ends before its excitation starts (the §3.1 script, whose 2 s of settling come
/// first, cut to 1.5 s) completes with a warning that the tank was never shaken.
#[test]
fn a_run_that_ends_before_the_excitation_is_warned() {
    let dir = temp("never_shaken");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/paper_2d_sloshing.rhai");
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        script.to_str().unwrap(),
        "--set",
        "duration=1.5",
        "--set",
        "dx=0.05",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(err.contains("never shaken"), "{err}");
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("never shaken"), "{summary}");
}

/// `ground_accel` returning an array of the wrong length for the tank (3 values in 2D, 2 in
/// 3D) is an error naming what to return, not a dropped or reinterpreted component.
#[test]
fn ground_accel_arrays_must_fit_the_tank() {
    let dir = temp("accel_length");
    for (tank, accel, dim) in [
        (
            "shape: \"rect\", width: 0.4, height: 0.4, depth: 0.2",
            "[1.0, 2.0, 3.0]",
            "2D",
        ),
        (
            "shape: \"box\", length: 0.4, breadth: 0.2, height: 0.4, depth: 0.2",
            "[1.0, 2.0]",
            "3D",
        ),
    ] {
        let script = dir.join(format!("case{}.rhai", dim));
        std::fs::write(
            &script,
            format!(
                "tank(#{{ {tank} }});\nnumerics(#{{ dx: 0.05 }});\n\
                 run(#{{ settle: 0.0, duration: 0.01 }});\nfn ground_accel(t) {{ {accel} }}\n"
            ),
        )
        .unwrap();
        let (ok, err) = run(&[
            "run",
            script.to_str().unwrap(),
            "--out",
            dir.join(format!("out{dim}")).to_str().unwrap(),
        ]);
        assert!(!ok, "{dim} {accel} accepted");
        assert!(err.contains(&format!("for a {dim} tank")), "{err}");
    }
}

/// A gauge placed outside the tank (or at a position that is not a number) is refused with
/// the tank's extent, instead of a column of NaN for the whole run.
#[test]
fn gauges_outside_the_tank_are_refused() {
    let dir = temp("gauge_outside");
    for x in ["5.0", "-1.0"] {
        let c = small_case(&dir, "0.0", &format!("gauge(\"g\", {x});"));
        let (ok, err) = run(&[
            "run",
            c.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
        ]);
        assert!(!ok, "gauge at {x} accepted");
        assert!(
            err.contains("gauge \"g\"") && err.contains("outside the tank"),
            "{err}"
        );
    }
    let c = small_case(&dir, "0.0", "gauge(\"g\", 0.2);");
    let (ok, err) = run(&[
        "run",
        c.to_str().unwrap(),
        "--out",
        dir.join("ok").to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
}

/// A 2D roof whose points share an x (a cone whose rise is the width: its slopes are 63°, so
/// the lattice puts roof points above each other) still writes its roof pressure map, by point
/// index with the points in `roof_points.csv`.
#[test]
fn a_steep_cone_roof_writes_its_pressure_map() {
    let dir = temp("steep_cone");
    let case = write_case(
        &dir,
        "// steep cone roof\ntank(#{ shape: \"rect\", width: 0.4, height: 0.4, depth: 0.2, roof: \"cone\", roof_rise: 0.4 });\n\
         numerics(#{ dx: 0.04 });\nrun(#{ settle: 0.0, duration: 0.02, output_interval: 0.005 });\n",
    );
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{err}");
    let map = std::fs::read_to_string(out.join("roof_pressure.csv")).unwrap();
    let header: Vec<&str> = map.lines().next().unwrap().split(',').collect();
    let mut names = header.clone();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), header.len(), "duplicate columns: {header:?}");
    let points = std::fs::read_to_string(out.join("roof_points.csv")).unwrap();
    assert!(
        points.starts_with("index,x,y,area,p_peak,t_peak"),
        "{points}"
    );
    assert_eq!(
        points.lines().count(),
        header.len(),
        "one row per roof point column"
    );
}

/// A size the script computes as NaN is refused where the tank reads it (not reported as a
/// memory need of "NaN GB"); an acceleration far beyond any ground motion is refused as a
/// units mistake (not reported as a sound speed of 10¹⁵¹ m/s).
#[test]
fn computed_nan_sizes_and_absurd_accelerations_say_what_is_wrong() {
    let dir = temp("nan_and_absurd");
    let case = small_case(&dir, "0.0", "");
    let text = std::fs::read_to_string(&case)
        .unwrap()
        .replace("width: width,", "width: sqrt(width - 1.0),");
    std::fs::write(&case, text).unwrap();
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    assert!(
        err.contains("'width' must be a finite number") && !err.contains("GB"),
        "{err}"
    );

    let dir = temp("absurd_accel");
    let case = small_case(&dir, "1e300", "");
    let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
    assert!(!ok);
    assert!(
        err.contains("beyond any ground motion") && !err.contains("EOS"),
        "{err}"
    );
}

/// `post` outputs: a table without columns, and a second table or plot with one name (its file
/// would replace the first), stop `post` at the call with its line; the run's own outputs stay.
#[test]
fn empty_or_duplicate_post_tables_are_refused_at_their_line() {
    let cases = [
        (
            "empty",
            "fn post(run) { write_table(\"bad\", #{}); }",
            "table 'bad' has no columns",
        ),
        (
            "twice",
            "fn post(run) { write_table(\"t\", #{ a: [1.0] }); write_table(\"t\", #{ b: [2.0] }); }",
            "the name \"t\" is used twice",
        ),
        (
            "plot_twice",
            "fn post(run) { line_plot(\"p\", \"T\", \"x\", \"y\", [0.0, 1.0], [0.0, 1.0]); \
             line_plot(\"p\", \"T\", \"x\", \"y\", [0.0, 1.0], [1.0, 0.0]); }",
            "the name \"p\" is used twice",
        ),
    ];
    for (name, post, expected) in cases {
        let dir = temp(&format!("post_{name}"));
        let case = small_case(&dir, "0.0", post);
        let out = dir.join("out");
        let (ok, err) = run(&[
            "run",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(!ok, "{name}: {err}");
        assert!(err.contains(expected), "{name}: {err}");
        assert!(
            err.contains("case.rhai:12:"),
            "{name}: the script line is named: {err}"
        );
        assert!(out.join("series.csv").is_file() && out.join("summary.ron").is_file());
    }
    // A table and a plot may share a name (post/NAME.csv and post/NAME.png).
    let dir = temp("post_table_and_plot");
    let case = small_case(
        &dir,
        "0.0",
        "fn post(run) { write_table(\"eta\", #{ t: [0.0, 1.0] }); \
         line_plot(\"eta\", \"T\", \"x\", \"y\", [0.0, 1.0], [0.0, 1.0]); }",
    );
    let out = dir.join("out");
    let (ok, err) = run(&[
        "run",
        case.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(ok, "{err}");
    assert!(out.join("post/eta.csv").is_file() && out.join("post/eta.png").is_file());
}

/// A solid wholly outside the tank would be silently left out of the run; a solid that fills
/// the liquid's place is named as such (it was reported as "dx larger than the fill depth").
#[test]
fn solids_outside_the_tank_or_filling_it_are_refused_by_name() {
    let cases = [
        (
            "outside_2d",
            "tank(#{ shape: \"rect\", width: 0.8, height: 0.6, depth: 0.3, roof: true, \
             solids: [#{ name: \"baffle\", shape: \"circle\", centre: [5.0, 0.45], radius: 0.05 }] });\n\
             numerics(#{ dx: 0.02 });",
            "solid \"baffle\" lies outside the tank",
        ),
        (
            "outside_3d",
            "tank(#{ shape: \"cylinder\", radius: 0.3, height: 0.5, depth: 0.25, roof: \"flat\", \
             solids: [#{ name: \"column\", shape: \"column\", centre: [2.0, 0.0], radius: 0.05, \
             bottom: 0.0, top: 0.5 }] });\n numerics(#{ dx: 0.04 });",
            "solid \"column\" lies outside the tank",
        ),
        (
            "filling_2d",
            "tank(#{ shape: \"rect\", width: 0.8, height: 0.6, depth: 0.3, roof: true, \
             solids: [#{ name: \"block\", shape: \"plate\", centre: [0.4, 0.3], length: 0.9, \
             thickness: 0.7, angle: 0.0 }] });\n numerics(#{ dx: 0.02 });",
            "every lattice point at dx = 0.02 m lies inside a solid",
        ),
        (
            "filling_3d",
            "tank(#{ shape: \"box\", length: 0.6, breadth: 0.4, height: 0.5, depth: 0.25, \
             roof: true, solids: [#{ name: \"block\", shape: \"block\", min: [-1.0, -1.0, -0.1], \
             max: [1.0, 1.0, 0.4] }] });\n numerics(#{ dx: 0.05 });",
            "every lattice point at dx = 0.05 m lies inside a solid",
        ),
    ];
    for (name, tank, expected) in cases {
        let dir = temp(&format!("solid_{name}"));
        let case = dir.join("case.rhai");
        std::fs::write(
            &case,
            format!(
                "{tank}\nrun(#{{ settle: 0.0, duration: 0.01 }});\nfn ground_accel(t) {{ 0.0 }}\n"
            ),
        )
        .unwrap();
        let out = dir.join("out");
        let (ok, err) = run(&[
            "run",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(!ok, "{name}: {err}");
        assert!(err.contains(expected), "{name}: {err}");
    }
}

/// `case_name("…")` names the default output folder `out/<name>`; a name that is a path is
/// refused (it would put the run outside `out/`).
#[test]
fn case_name_sets_the_folder_and_refuses_a_path() {
    let dir = temp("case_name");
    for (name, ok_expected) in [("my_named", true), ("../escape", false)] {
        let case = small_case(&dir, "0.0", &format!("case_name(\"{name}\");"));
        let (ok, err) = run(&["run", case.to_str().unwrap(), "--quiet"]);
        assert_eq!(ok, ok_expected, "{name}: {err}");
        if ok {
            assert!(dir.join("out/my_named/summary.ron").is_file());
        } else {
            assert!(err.contains("must be a plain folder name"), "{err}");
            assert!(!dir.join("escape").exists());
        }
    }
}
