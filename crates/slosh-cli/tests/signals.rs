//! SIGINT and SIGTERM: a run ends its step, keeps its outputs, says "interrupted" and exits
//! with 128 + the signal; a sweep passes the signal on to its running case, waits for it and
//! starts no other.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-signal-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A 2D case long enough to be interrupted (0.8 m × 0.4 m of water, dx = 0.02 m, 60 s).
fn long_case(dir: &Path) -> PathBuf {
    let script = "let amplitude = param(\"amplitude\", 0.005); // ground displacement (m)\n\
                  tank(#{ shape: \"rect\", width: 0.8, height: 0.6, depth: 0.4 });\n\
                  numerics(#{ dx: 0.02 });\n\
                  run(#{ settle: 0.0, duration: 60.0, output_interval: 0.01 });\n\
                  fn ground_accel(t) { amplitude * 25.0 * sin(5.0 * t) }\n";
    let path = dir.join("long.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

/// Waits until `file` exists and holds at least `lines` lines (at most 60 s).
fn wait_for_lines(file: &Path, lines: usize) {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(60) {
        if std::fs::read_to_string(file).is_ok_and(|t| t.lines().count() >= lines) {
            return;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    panic!("{} did not reach {lines} lines", file.display());
}

fn signal(child: &Child, sig: i32) {
    // SAFETY: kill(2) on the id of a child not yet reaped.
    unsafe {
        libc::kill(child.id() as i32, sig);
    }
}

#[test]
fn sigterm_ends_a_run_cleanly_with_143() {
    let dir = temp("run");
    let case = long_case(&dir);
    let out = dir.join("out");
    let child = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["run", case.to_str().unwrap(), "--quiet", "--out"])
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_lines(&out.join("series.csv"), 20);
    signal(&child, libc::SIGTERM);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(143), "{err}");
    assert!(err.contains("interrupted by SIGTERM"), "{err}");
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"interrupted\""), "{summary}");
    let series = std::fs::read_to_string(out.join("series.csv")).unwrap();
    assert!(series.lines().count() >= 20);
    assert!(!out.join(".slosh.lock").exists(), "the lock is released");
}

#[test]
fn sigint_to_a_sweep_reaches_its_case_and_no_case_is_left_running() {
    let dir = temp("sweep");
    let case = long_case(&dir);
    let out = dir.join("sweep");
    let child = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args([
            "sweep",
            case.to_str().unwrap(),
            "--vary",
            "amplitude=0.004,0.006",
        ])
        .args(["--jobs", "1", "--quiet", "--out"])
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_lines(&out.join("amplitude-0.004/series.csv"), 20);
    signal(&child, libc::SIGINT);
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("run the same command again"), "{err}");
    // The case that was running ended cleanly (its summary says so, its lock is gone); the
    // other never started.
    let first = out.join("amplitude-0.004");
    let summary = std::fs::read_to_string(first.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"interrupted\""), "{summary}");
    assert!(!first.join(".slosh.lock").exists());
    assert!(!out.join("amplitude-0.006/series.csv").exists());
    let table = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(table.contains("interrupted"), "{table}");
}

/// SIGTERM while the script's top level is still running (a long loop before `tank(...)`)
/// stops the evaluation within a fraction of a second: the run ends with the signal named,
/// long before the loop's own operation limit would have ended it.
#[test]
fn sigterm_stops_a_long_script_evaluation() {
    let dir = temp("script-evaluation");
    let script = dir.join("loop.rhai");
    std::fs::write(
        &script,
        "let a = [];\nfor i in 0..5000000 { a.push(i); a.pop(); }\n\
         tank(#{ shape: \"rect\", width: 0.4, height: 0.4, depth: 0.2 });\n\
         run(#{ settle: 0.0, duration: 0.01 });\n",
    )
    .unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .arg("run")
        .arg(&script)
        .arg("--out")
        .arg(dir.join("out"))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(700));
    let sent = Instant::now();
    signal(&child, libc::SIGTERM);
    let out = child.wait_with_output().unwrap();
    let waited = sent.elapsed();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("stopped by a signal"), "{err}");
    assert!(
        waited < Duration::from_secs(3),
        "stopped {waited:?} after the signal: {err}"
    );
}

/// Two sweeps into one folder: the second is refused before it touches a case (the cases would
/// share folders); a case folder a live `slosh run` writes is left alone by a sweep (its
/// summary is not replaced, no run.log is made there), and that case is reported failed.
#[test]
fn a_second_sweep_into_a_busy_folder_is_refused_and_touches_nothing() {
    let dir = temp("two-sweeps");
    let case = long_case(&dir);
    let out = dir.join("sweep");
    let first = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args([
            "sweep",
            case.to_str().unwrap(),
            "--vary",
            "amplitude=0.004,0.006",
        ])
        .args(["--jobs", "1", "--quiet", "--out"])
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let running = out.join("amplitude-0.004");
    wait_for_lines(&running.join("series.csv"), 20);
    let log_before = std::fs::read(running.join("run.log")).unwrap();
    let second = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args([
            "sweep",
            case.to_str().unwrap(),
            "--vary",
            "amplitude=0.004,0.006",
        ])
        .args(["--jobs", "1", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&second.stderr);
    assert!(!second.status.success(), "{err}");
    assert!(
        err.contains("in use by another slosh command (a sweep"),
        "{err}"
    );
    signal(&first, libc::SIGINT);
    let o = first.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let summary = std::fs::read_to_string(running.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"interrupted\""), "{summary}");
    assert!(std::fs::read(running.join("run.log"))
        .unwrap()
        .starts_with(&log_before));

    // A case folder held by a run started by hand.
    let by_hand = out.join("amplitude-0.006");
    let run = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args([
            "run",
            case.to_str().unwrap(),
            "--set",
            "amplitude=0.006",
            "--quiet",
            "--out",
        ])
        .arg(&by_hand)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_lines(&by_hand.join("series.csv"), 20);
    let sweep = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["sweep", case.to_str().unwrap(), "--vary", "amplitude=0.006"])
        .args(["--jobs", "1", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&sweep.stderr);
    assert!(!sweep.status.success(), "{err}");
    let table = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(
        table.contains("being written by another slosh run"),
        "{table}"
    );
    let summary = std::fs::read_to_string(by_hand.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"running\""), "{summary}");
    assert!(
        !by_hand.join("run.log").exists(),
        "the sweep made a run.log in a busy folder"
    );
    signal(&run, libc::SIGTERM);
    let o = run.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(143),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A second assessment into a folder an assessment is running in is refused before it writes
/// anything there: the running one's manifest (`assess.ron`) is not replaced.
#[test]
fn a_second_assessment_into_a_busy_folder_keeps_the_manifest() {
    let dir = temp("two-assessments");
    let case = long_case(&dir);
    let first_suite = dir.join("first.csv");
    std::fs::write(&first_suite, "name,amplitude\nfirst_motion,0.004\n").unwrap();
    let second_suite = dir.join("second.csv");
    std::fs::write(&second_suite, "name,amplitude\nsecond_motion,0.006\n").unwrap();
    let out = dir.join("assessment");
    let first = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["assess", case.to_str().unwrap(), "--motions"])
        .arg(&first_suite)
        .args(["--jobs", "1", "--quiet", "--out"])
        .arg(&out)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_lines(&out.join("runs/first_motion/series.csv"), 20);
    let second = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["assess", case.to_str().unwrap(), "--motions"])
        .arg(&second_suite)
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&second.stderr);
    assert!(!second.status.success(), "{err}");
    assert!(
        err.contains("in use by another slosh command (an assessment"),
        "{err}"
    );
    let manifest = std::fs::read_to_string(out.join("assess.ron")).unwrap();
    assert!(
        manifest.contains("first_motion") && !manifest.contains("second_motion"),
        "{manifest}"
    );
    signal(&first, libc::SIGINT);
    let o = first.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
