//! Checkpoints and `slosh resume`: a run interrupted by a signal and resumed from its
//! checkpoint writes the same files, bit for bit, as the same run done without
//! interruption (2D paper scheme with a roof and frames; 3D modern scheme with a recorded
//! ground motion and a cone roof); the summary lists the resumption; bad resumes are refused
//! with a reason.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-resume-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn slosh(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_slosh"));
    c.args(args).current_dir(repo());
    c
}

fn run_to_end(args: &[&str], out: &Path) -> Output {
    let o = slosh(args)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// Waits until `file` holds at least `lines` lines (at most 120 s).
fn wait_for_lines(file: &Path, lines: usize) {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(120) {
        if std::fs::read_to_string(file).is_ok_and(|t| t.lines().count() >= lines) {
            return;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    panic!("{} did not reach {lines} lines", file.display());
}

fn interrupt(child: &Child) {
    // SAFETY: kill(2) on the id of a child not yet reaped.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGINT);
    }
}

/// The summary without what differs between an interrupted-and-resumed run and a straight
/// one: wall times, throughputs, the resumption record and the checkpoint count.
fn comparable_summary(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("summary.ron")).unwrap();
    let mut kept = Vec::new();
    let mut skipping = false;
    for line in text.lines() {
        if skipping {
            if line.starts_with("    ]") {
                skipping = false;
            }
            continue;
        }
        if line.starts_with("    resumes: [") {
            skipping = !line.ends_with("],");
            continue;
        }
        if ["wall_time_s", "particle_steps_per_s", "checkpoints_written", "phase_"]
            .iter()
            .any(|k| line.contains(k))
        {
            continue;
        }
        kept.push(line.to_string());
    }
    kept.join("\n")
}

fn same_file(a: &Path, b: &Path) {
    let (x, y) = (std::fs::read(a).unwrap(), std::fs::read(b).unwrap());
    assert!(x == y, "{} and {} differ", a.display(), b.display());
}

/// Runs `args` straight into one folder, and into another interrupted once `rows` series
/// rows exist, then resumed; compares the files.
fn interrupted_run_resumes_to_the_same_files(test: &str, args: &[&str], rows: usize, files: &[&str]) {
    let dir = temp(test);
    let (straight, resumed) = (dir.join("straight"), dir.join("resumed"));
    run_to_end(args, &straight);

    let child = slosh(args)
        .arg("--out")
        .arg(&resumed)
        .arg("--quiet")
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_lines(&resumed.join("series.csv"), rows);
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    let summary = std::fs::read_to_string(resumed.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"interrupted\""), "{summary}");
    assert!(resumed.join("checkpoint/state.bin").exists());

    let o = slosh(&["resume", resumed.to_str().unwrap(), "--quiet"]).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in files {
        same_file(&straight.join(f), &resumed.join(f));
    }
    assert_eq!(comparable_summary(&straight), comparable_summary(&resumed));
    let summary = std::fs::read_to_string(resumed.join("summary.ron")).unwrap();
    assert!(summary.contains("from_step:"), "the resumption is recorded: {summary}");
    assert!(summary.contains("status: \"completed\""), "{summary}");

    // A complete run has nothing to resume.
    let o = slosh(&["resume", resumed.to_str().unwrap(), "--quiet"]).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("nothing to resume"));
}

#[test]
fn paper_2d_roof_with_frames_resumes_bit_for_bit() {
    interrupted_run_resumes_to_the_same_files(
        "paper-2d",
        &[
            "run",
            "scripts/paper_2d_roof.rhai",
            "--set",
            "settle=0.5",
            "--set",
            "duration=3.0",
            "--set",
            "frame_interval=0.5",
        ],
        250,
        &[
            "series.csv",
            "series_units.csv",
            "roof_pressure.csv",
            "frames/frames.pvd",
            "frames/frame_000001.vtp",
            "frames/frame_000006.vtp",
        ],
    );
}

#[test]
fn modern_3d_record_resumes_bit_for_bit() {
    interrupted_run_resumes_to_the_same_files(
        "modern-3d",
        &[
            "run",
            "scripts/elcentro_3d.rhai",
            "--set",
            "radius=0.5",
            "--set",
            "tank_height=0.7",
            "--set",
            "depth=0.4",
            "--set",
            "roof_rise=0.1",
            "--set",
            "dx=0.05",
            "--set",
            "settle=0.2",
            "--set",
            "duration=1.2",
            "--set",
            "frame_interval=0",
        ],
        60,
        &["series.csv", "roof_pressure.csv", "roof_points.csv"],
    );
}

#[test]
fn resume_refuses_what_it_cannot_continue() {
    let dir = temp("refusals");
    // A folder without a checkpoint.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let o = slosh(&["resume", empty.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("no checkpoint"));

    // A run whose script changed since it started.
    let script = dir.join("case.rhai");
    let text = "let amplitude = param(\"amplitude\", 0.005);\n\
                tank(#{ shape: \"rect\", width: 0.4, height: 0.4, depth: 0.2 });\n\
                numerics(#{ dx: 0.02 });\n\
                run(#{ settle: 0.0, duration: 60.0, output_interval: 0.01 });\n\
                fn ground_accel(t) { amplitude * 25.0 * sin(5.0 * t) }\n";
    std::fs::write(&script, text).unwrap();
    let out = dir.join("out");
    let child = slosh(&["run", script.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_lines(&out.join("series.csv"), 20);
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130));
    std::fs::write(&script, text.replace("0.005", "0.006")).unwrap();
    let o = slosh(&["resume", out.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("changed since the run"));

    // A corrupted checkpoint.
    std::fs::write(&script, text).unwrap();
    let state = out.join("checkpoint/state.bin");
    let mut bytes = std::fs::read(&state).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(&state, bytes).unwrap();
    let o = slosh(&["resume", out.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("corrupted"));
}

#[test]
fn an_interrupted_sweep_case_continues_from_its_checkpoint() {
    let dir = temp("sweep");
    let script = dir.join("case.rhai");
    std::fs::write(
        &script,
        "let amplitude = param(\"amplitude\", 0.005);\n\
         tank(#{ shape: \"rect\", width: 0.4, height: 0.4, depth: 0.2 });\n\
         numerics(#{ dx: 0.02 });\n\
         run(#{ settle: 0.0, duration: 4.0, output_interval: 0.01 });\n\
         fn ground_accel(t) { amplitude * 25.0 * sin(5.0 * t) }\n",
    )
    .unwrap();
    let out = dir.join("sweep");
    let args = [
        "sweep",
        script.to_str().unwrap(),
        "--vary",
        "amplitude=0.005",
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    let child = slosh(&args).stderr(Stdio::piped()).stdout(Stdio::piped()).spawn().unwrap();
    // The case folder appears once the sweep starts the case.
    let start = Instant::now();
    let case_dir = loop {
        let found = std::fs::read_dir(&out).ok().and_then(|entries| {
            entries
                .filter_map(|e| e.ok())
                .map(|e| e.path())
                .find(|p| p.join("series.csv").exists())
        });
        if let Some(p) = found {
            break p;
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no case folder");
        std::thread::sleep(Duration::from_millis(20));
    };
    wait_for_lines(&case_dir.join("series.csv"), 100);
    interrupt(&child);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(case_dir.join("checkpoint/state.bin").exists());

    let o = slosh(&args).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(case_dir.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"completed\""), "{summary}");
    assert!(summary.contains("from_step:"), "continued from its checkpoint: {summary}");
    let rows = std::fs::read_to_string(case_dir.join("series.csv")).unwrap().lines().count();
    assert!(rows > 400, "a header and the rows of 4 s at 0.01 s: {rows} lines");
}
