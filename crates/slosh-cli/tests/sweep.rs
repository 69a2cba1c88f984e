//! `slosh sweep`: the cartesian product runs in its own folders, `sweep.csv` has one row per
//! case, a second sweep reruns nothing, and a failing case does not stop the others.

use slosh_cli::sweep::{cli_sweep, CaseStatus};
use std::path::{Path, PathBuf};
use std::time::SystemTime;

fn exe() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_slosh"))
}

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-cli-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small, fast 2D case: 0.4 m × 0.2 m of water at dx = 0.04 m for 0.05 s under a gentle
/// sine, with a `post` that returns one number. The duration's default follows the depth
/// (depth/4 s), as a script's excitation frequency may follow its tank.
fn small_case(dir: &Path) -> PathBuf {
    let script = r#"
let width = param("width", 0.4);
let tank_height = param("tank_height", 0.4);
let depth = param("depth", 0.2);
let dx = param("dx", 0.04);
let duration = param("duration", depth / 4.0);
tank(#{ shape: "rect", width: width, height: tank_height, depth: depth });
numerics(#{ dx: dx });
run(#{ settle: 0.0, duration: duration, output_interval: 0.005 });
fn ground_accel(t) { 0.5 * sin(20.0 * t) }
fn post(run) { #{ double_depth: 2.0 * run.params.depth } }
"#;
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

/// Reads sweep.csv as (header, rows).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut reader = csv_rows(&text);
    let header = reader.remove(0);
    (header, reader)
}

/// A minimal CSV reader (fields may be quoted, with "" for a quote).
fn csv_rows(text: &str) -> Vec<Vec<String>> {
    let mut rows = Vec::new();
    let mut row = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
            }
            (false, '\r') => {}
            (false, c) => field.push(c),
        }
    }
    if !field.is_empty() || !row.is_empty() {
        row.push(field);
        rows.push(row);
    }
    rows
}

fn column<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    &row[i]
}

fn mtime(path: &Path) -> SystemTime {
    std::fs::metadata(path).unwrap().modified().unwrap()
}

#[test]
fn sweep_runs_the_product_and_resumes() {
    let dir = temp("sweep_product");
    let case = small_case(&dir);
    let out = dir.join("sweep");
    let vary = vec![
        "width=0.4,0.48".to_string(),
        "depth=0.16:0.2:0.04".to_string(),
    ];
    let outcome = cli_sweep(exe(), &case, &vary, Some(out.clone()), 2, true).unwrap();
    assert_eq!(outcome.cases.len(), 4);
    assert_eq!(outcome.failed(), 0, "{:?}", outcome.cases);
    assert_eq!(outcome.completed(), 4);

    // First --vary slowest.
    let folders: Vec<&str> = outcome.cases.iter().map(|c| c.folder.as_str()).collect();
    assert_eq!(
        folders,
        [
            "width-0.4__depth-0.16",
            "width-0.4__depth-0.2",
            "width-0.48__depth-0.16",
            "width-0.48__depth-0.2",
        ]
    );
    for f in &folders {
        let summary = std::fs::read_to_string(out.join(f).join("summary.ron")).unwrap();
        assert!(summary.contains("status: \"completed\""), "{f}: {summary}");
        assert!(out.join(f).join("series.csv").exists());
    }

    let (header, rows) = read_csv(&out.join("sweep.csv"));
    assert_eq!(rows.len(), 4, "{rows:?}");
    for name in [
        "case",
        "width",
        "depth",
        "status",
        "error",
        "steps",
        "max_eta_left",
        "theory_omega_1",
        "post_double_depth",
    ] {
        assert!(
            header.iter().any(|h| h == name),
            "no column {name} in {header:?}"
        );
    }
    let expect = [
        ("0.4", "0.16"),
        ("0.4", "0.2"),
        ("0.48", "0.16"),
        ("0.48", "0.2"),
    ];
    for (row, (w, d)) in rows.iter().zip(expect) {
        assert_eq!(column(&header, row, "width"), w);
        assert_eq!(column(&header, row, "depth"), d);
        assert_eq!(column(&header, row, "status"), "completed");
        assert!(column(&header, row, "steps").parse::<u64>().unwrap() > 0);
        let post: f64 = column(&header, row, "post_double_depth").parse().unwrap();
        assert!(
            (post - 2.0 * d.parse::<f64>().unwrap()).abs() < 1e-12,
            "{post}"
        );
    }

    // The second call finds every case done and runs none of them (those at depth 0.16 m
    // with the duration their depth gives, not the default's 0.05 s).
    let before: Vec<SystemTime> = folders
        .iter()
        .map(|f| mtime(&out.join(f).join("summary.ron")))
        .collect();
    let again = cli_sweep(exe(), &case, &vary, Some(out.clone()), 2, true).unwrap();
    assert_eq!(again.skipped(), 4, "{:?}", again.cases);
    assert!(again.cases.iter().all(|c| c.status == CaseStatus::Skipped));
    let after: Vec<SystemTime> = folders
        .iter()
        .map(|f| mtime(&out.join(f).join("summary.ron")))
        .collect();
    assert_eq!(before, after, "a finished case was run again");
    let (header2, rows2) = read_csv(&out.join("sweep.csv"));
    assert_eq!(
        (header2, rows2),
        (header, rows),
        "the resumed table is the same"
    );

    // A new value runs only the new cases.
    let more = vec![
        "width=0.4,0.48".to_string(),
        "depth=0.16,0.2,0.12".to_string(),
    ];
    let third = cli_sweep(exe(), &case, &more, Some(out.clone()), 2, true).unwrap();
    assert_eq!(
        (third.skipped(), third.completed()),
        (4, 2),
        "{:?}",
        third.cases
    );
}

#[test]
fn a_failing_case_does_not_stop_the_others() {
    let dir = temp("sweep_failure");
    let case = small_case(&dir);
    let out = dir.join("sweep");
    // depth 0.6 m is above the 0.4 m tank: that case fails before it starts. A one-value
    // --vary fixes a parameter; `duration` is also a summary field (column summary_duration).
    let vary = vec![
        "depth=0.16,0.6,0.2".to_string(),
        "duration=0.04".to_string(),
    ];
    let outcome = cli_sweep(exe(), &case, &vary, Some(out.clone()), 2, true).unwrap();
    assert_eq!(outcome.failed(), 1, "{:?}", outcome.cases);
    assert_eq!(outcome.completed(), 2);
    let failed = &outcome.cases[1];
    assert_eq!(failed.status, CaseStatus::Failed);
    assert!(
        failed
            .error
            .as_deref()
            .unwrap()
            .contains("above the tank height"),
        "{failed:?}"
    );

    let (header, rows) = read_csv(&out.join("sweep.csv"));
    assert_eq!(rows.len(), 3);
    let statuses: Vec<&str> = rows.iter().map(|r| column(&header, r, "status")).collect();
    assert_eq!(statuses, ["completed", "failed", "completed"]);
    assert!(column(&header, &rows[1], "error").contains("above the tank height"));
    assert_eq!(column(&header, &rows[1], "depth"), "0.6");
    assert_eq!(column(&header, &rows[0], "duration"), "0.04");
    assert_eq!(column(&header, &rows[0], "summary_duration"), "0.04");
    assert_eq!(
        column(&header, &rows[1], "summary_duration"),
        "",
        "no summary for the failed case"
    );
    assert_eq!(outcome.cases[0].folder, "depth-0.16__duration-0.04");

    // Resuming reruns the failed case only (and it fails again).
    let again = cli_sweep(exe(), &case, &vary, Some(out), 2, true).unwrap();
    assert_eq!((again.skipped(), again.failed()), (2, 1));
}

#[test]
fn bad_vary_arguments_are_refused_before_running() {
    let dir = temp("sweep_bad_args");
    let case = small_case(&dir);
    let out = dir.join("sweep");
    let err = |vary: &[&str]| {
        let vary: Vec<String> = vary.iter().map(|s| s.to_string()).collect();
        format!(
            "{:#}",
            cli_sweep(exe(), &case, &vary, Some(out.clone()), 1, true).unwrap_err()
        )
    };
    let e = err(&["widht=0.4,0.5"]);
    assert!(e.contains("widht") && e.contains("width = 0.4"), "{e}");
    let e = err(&["width=0.4,abc"]);
    assert!(e.contains("width") && e.contains("expects a number"), "{e}");
    let e = err(&["width=0.4", "width=0.5"]);
    assert!(e.contains("twice"), "{e}");
    let e = err(&[]);
    assert!(e.contains("--vary"), "{e}");
    assert!(!out.join("sweep.csv").exists(), "nothing ran");
}
