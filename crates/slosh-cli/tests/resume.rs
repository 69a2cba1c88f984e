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
        if [
            "wall_time_s",
            "particle_steps_per_s",
            "checkpoints_written",
            "phase_",
        ]
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
fn interrupted_run_resumes_to_the_same_files(
    test: &str,
    args: &[&str],
    rows: usize,
    files: &[&str],
) {
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

    let o = slosh(&["resume", resumed.to_str().unwrap(), "--quiet"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in files {
        same_file(&straight.join(f), &resumed.join(f));
    }
    assert_eq!(comparable_summary(&straight), comparable_summary(&resumed));
    let summary = std::fs::read_to_string(resumed.join("summary.ron")).unwrap();
    assert!(
        summary.contains("from_step:"),
        "the resumption is recorded: {summary}"
    );
    assert!(summary.contains("status: \"completed\""), "{summary}");

    // A complete run has nothing to resume.
    let o = slosh(&["resume", resumed.to_str().unwrap(), "--quiet"])
        .output()
        .unwrap();
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
            "dx=0.0625",
            "--set",
            "settle=0.2",
            "--set",
            "duration=0.6",
            "--set",
            "frame_interval=0",
        ],
        30,
        &["series.csv", "roof_pressure.csv", "roof_points.csv"],
    );
}

/// A tank the ground turns as well as shakes (a record and its foundation's rocking): the
/// rotation is a function of time, so a resumed run takes the same steps.
#[test]
fn a_rocking_tank_resumes_bit_for_bit() {
    interrupted_run_resumes_to_the_same_files(
        "rocking-2d",
        &[
            "run",
            "scripts/tank_rocking_2d.rhai",
            "--set",
            "dx=0.5",
            "--set",
            "duration=12",
        ],
        200,
        &["series.csv", "series_units.csv"],
    );
}

#[test]
fn resume_refuses_what_it_cannot_continue() {
    let dir = temp("refusals");
    // A folder without a checkpoint.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let o = slosh(&["resume", empty.to_str().unwrap()])
        .output()
        .unwrap();
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
    let child = slosh(&[
        "run",
        script.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ])
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

    // The run's record edited after the state was written (another amplitude in its sets):
    // refused, the excitation would jump at the resume point.
    std::fs::write(&script, text).unwrap();
    let record = out.join("checkpoint/run.ron");
    let kept = std::fs::read_to_string(&record).unwrap();
    assert!(kept.contains("sets: ["), "{kept}");
    std::fs::write(
        &record,
        kept.replace("sets: [", "sets: [\"amplitude=5.0\", "),
    )
    .unwrap();
    let o = slosh(&["resume", out.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("was changed after the run's state"), "{err}");
    std::fs::write(&record, kept).unwrap();

    // A corrupted checkpoint (one bit flipped in the payload), then one cut short (as a full
    // disk would leave it): both refused with the reason, the file named.
    let state = out.join("checkpoint/state.bin");
    let good = std::fs::read(&state).unwrap();
    let mut bytes = good.clone();
    let last = bytes.len() - 1;
    bytes[last] ^= 1;
    std::fs::write(&state, bytes).unwrap();
    let o = slosh(&["resume", out.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("corrupted") && err.contains("state.bin"),
        "{err}"
    );
    std::fs::write(&state, &good[..good.len() / 2]).unwrap();
    let o = slosh(&["resume", out.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("cut short") && err.contains("state.bin"),
        "{err}"
    );
    std::fs::write(&state, &good[..10]).unwrap();
    let o = slosh(&["resume", out.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("not a slosh checkpoint"), "{err}");
    // The state deleted by hand: said as a file that cannot be read (it said "cannot write").
    std::fs::remove_file(&state).unwrap();
    let o = slosh(&["resume", out.to_str().unwrap()]).output().unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("cannot read") && err.contains("state.bin") && !err.contains("cannot write"),
        "{err}"
    );
}

/// A one-case sweep of a 4 s sloshing run, stopped by SIGINT once its case has written 100
/// rows: the sweep's arguments and the case folder, which holds a checkpoint.
fn sweep_stopped_part_way(test: &str) -> (Vec<String>, PathBuf) {
    let dir = temp(test);
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
    let args: Vec<String> = [
        "sweep",
        script.to_str().unwrap(),
        "--vary",
        "amplitude=0.005",
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]
    .map(String::from)
    .to_vec();
    let arg_refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let child = slosh(&arg_refs)
        .stderr(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
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
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(case_dir.join("checkpoint/state.bin").exists());
    (args, case_dir)
}

/// Runs the sweep of `args` again: it succeeds and the case in `case_dir` is completed.
/// Returns the case's summary.
fn sweep_again(args: &[String], case_dir: &Path) -> String {
    let arg_refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = slosh(&arg_refs).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(case_dir.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"completed\""), "{summary}");
    summary
}

/// The sweep run again on the folder of [`sweep_stopped_part_way`] completes its case from
/// the checkpoint, to the rows of the whole 4 s.
fn sweep_continues_the_case(args: &[String], case_dir: &Path) {
    let summary = sweep_again(args, case_dir);
    assert!(
        summary.contains("from_step:"),
        "continued from its checkpoint: {summary}"
    );
    let rows = std::fs::read_to_string(case_dir.join("series.csv"))
        .unwrap()
        .lines()
        .count();
    assert!(
        rows > 400,
        "a header and the rows of 4 s at 0.01 s: {rows} lines"
    );
}

#[test]
fn an_interrupted_sweep_case_continues_from_its_checkpoint() {
    let (args, case_dir) = sweep_stopped_part_way("sweep");
    sweep_continues_the_case(&args, &case_dir);
}

/// A case killed outright (SIGKILL, the machine gone) leaves what a run leaves between two
/// checkpoints: its last checkpoint, the summary of a run in progress ("running", the pid
/// of a process that no longer exists), its lock, and series rows past the checkpoint. The
/// sweep run again continues it from the checkpoint rather than from the start.
#[test]
fn a_sweep_case_killed_outright_continues_from_its_checkpoint() {
    let (args, case_dir) = sweep_stopped_part_way("sweep-killed");
    leave_as_killed(&case_dir);
    let mut series = std::fs::OpenOptions::new()
        .append(true)
        .open(case_dir.join("series.csv"))
        .unwrap();
    std::io::Write::write_all(&mut series, b"99.0,1,2,3\n").unwrap();
    drop(series);
    sweep_continues_the_case(&args, &case_dir);
    let series = std::fs::read_to_string(case_dir.join("series.csv")).unwrap();
    assert!(
        !series.contains("99.0,1,2,3"),
        "the rows past the checkpoint are rewritten from it"
    );
}

/// Leaves `case_dir` as a run killed outright leaves it: the summary of a run in progress
/// ("running", the pid of a process that no longer exists) and its lock.
fn leave_as_killed(case_dir: &Path) {
    // A pid above the kernel's limit (2²² at most) names no process.
    let dead_pid = 1u32 << 30;
    std::fs::write(
        case_dir.join("summary.ron"),
        format!(
            "(\n    version: \"{}\",\n    case: \"case\",\n    script: \"case.rhai\",\n    \
             status: \"running\",\n    pid: {dead_pid},\n    error: None,\n)\n",
            env!("CARGO_PKG_VERSION")
        ),
    )
    .unwrap();
    std::fs::write(case_dir.join(".slosh.lock"), dead_pid.to_string()).unwrap();
}

/// A case killed after its checkpoint at the end of the run (while it wrote its summary and
/// plots) cannot be resumed: the sweep runs it again from the start, in the same call.
#[test]
fn a_sweep_case_killed_after_its_last_checkpoint_runs_again() {
    let (args, case_dir) = sweep_stopped_part_way("sweep-killed-at-end");
    sweep_continues_the_case(&args, &case_dir);
    assert!(
        case_dir.join("checkpoint/state.bin").exists(),
        "a finished run keeps the checkpoint of its end"
    );
    leave_as_killed(&case_dir);
    let summary = sweep_again(&args, &case_dir);
    assert!(
        !summary.contains("from_step:"),
        "run again from the start: {summary}"
    );
}

/// The roof impacts of a finished run's summary.
fn impacts(dir: &Path) -> Vec<(f64, f64, f64)> {
    #[derive(serde::Deserialize)]
    struct Impact {
        t_start: f64,
        t_peak: f64,
        p_max_sph: f64,
    }
    #[derive(serde::Deserialize)]
    struct Summary {
        impacts: Vec<Impact>,
    }
    let text = std::fs::read_to_string(dir.join("summary.ron")).unwrap();
    let s: Summary = ron::from_str(&text).unwrap();
    s.impacts
        .iter()
        .map(|i| (i.t_start, i.t_peak, i.p_max_sph))
        .collect()
}

/// The files of `dir/frames`, sorted.
fn frame_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| format!("frames/{}", e.unwrap().file_name().to_string_lossy()))
        .collect();
    names.sort();
    names
}

/// The 2D roof case of the paper (0.5 s settling, then the resonant sine until t = 2.3 s; the
/// liquid strikes the roof at about 1.5 s and, harder, at 2.05–2.12 s) stopped at three set steps —
/// during settling, in the middle of the excitation, and inside the largest roof impact of
/// the uninterrupted run — and resumed: every finished output is byte for byte the
/// uninterrupted run's.
#[test]
fn stops_in_settling_mid_run_and_in_a_roof_impact_resume_bit_for_bit() {
    let dir = temp("three-points");
    let args = [
        "run",
        "scripts/paper_2d_roof.rhai",
        "--set",
        "settle=0.5",
        "--set",
        "duration=2.3",
        "--set",
        "frame_interval=0.5",
        "--threads",
        "1",
    ];
    let straight = dir.join("straight");
    run_to_end(&args, &straight);
    // The largest impact of the uninterrupted run; the stop falls between its first row
    // with roof pressure and its peak.
    let (t_start, t_peak, _) = impacts(&straight)
        .into_iter()
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .expect("the liquid reaches the roof of the 0.6 m tank");
    let in_impact = 0.5 * (t_start + t_peak);
    let points = [("settling", 0.25), ("middle", 1.2), ("impact", in_impact)];
    assert!(
        1.2 < t_start,
        "the impact comes after the mid-run stop: {t_start} s"
    );

    let mut children = Vec::new();
    for (name, t) in points {
        let out = dir.join(name);
        let child = slosh(&args)
            .arg("--out")
            .arg(&out)
            .arg("--quiet")
            .env("SLOSH_TEST_STOP_AT", t.to_string())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        children.push((name, t, out, child));
    }
    let mut names = vec!["series.csv", "series_units.csv", "roof_pressure.csv"]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
    names.extend(frame_files(&straight));
    assert!(
        names.len() > 8,
        "frames at 0, 0.5, ..., 2 s, the last and the index: {names:?}"
    );
    for (name, t, out, child) in children {
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(143), "{name}: {err}");
        let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
        assert!(
            summary.contains("status: \"interrupted\""),
            "{name}: {summary}"
        );

        let o = slosh(&["resume", out.to_str().unwrap(), "--quiet", "--threads", "1"])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        for f in &names {
            same_file(&straight.join(f), &out.join(f));
        }
        assert_eq!(frame_files(&straight), frame_files(&out), "{name}");
        assert_eq!(
            comparable_summary(&straight),
            comparable_summary(&out),
            "{name}"
        );
        // The stop came one step (dt < 1 ms here) after the chosen time.
        let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
        let from = summary
            .split("from_time: ")
            .nth(1)
            .and_then(|s| s.split(|c: char| c == ',' || c.is_whitespace()).next())
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("{name}: no resume record in {summary}"));
        assert!(
            from >= t && from < t + 0.01,
            "{name}: stopped at {from} s for {t} s"
        );
    }
}

/// The rows of a CSV table without the columns that depend on the wall clock.
fn table_without_timing(path: &Path) -> Vec<Vec<String>> {
    const TIMING: [&str; 3] = [
        "wall_time_s",
        "particle_steps_per_s",
        "fluid_particle_steps_per_s",
    ];
    let text = std::fs::read_to_string(path).unwrap();
    let rows: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let keep: Vec<bool> = rows[0]
        .iter()
        .map(|c| !TIMING.contains(&c.as_str()))
        .collect();
    rows.into_iter()
        .map(|r| {
            r.into_iter()
                .zip(&keep)
                .filter(|(_, k)| **k)
                .map(|(c, _)| c)
                .collect()
        })
        .collect()
}

/// SIGTERM (a cluster's time limit) to a running `slosh sweep`: the running case gets it,
/// checkpoints and ends, the sweep exits with 143; the same command again continues that
/// case from its checkpoint and runs the other, and every case's files and the sweep table
/// are those of the sweep run without interruption.
#[test]
fn a_sigtermed_sweep_continues_to_the_files_of_an_uninterrupted_one() {
    let dir = temp("sweep-sigterm");
    let script = dir.join("case.rhai");
    std::fs::write(
        &script,
        "let amplitude = param(\"amplitude\", 0.005);\n\
         tank(#{ shape: \"rect\", width: 0.8, height: 0.6, depth: 0.4 });\n\
         numerics(#{ dx: 0.02 });\n\
         run(#{ settle: 0.0, duration: 2.0, output_interval: 0.01 });\n\
         fn ground_accel(t) { amplitude * 25.0 * sin(5.0 * t) }\n",
    )
    .unwrap();
    let sweep = |out: &Path| -> Command {
        let mut c = slosh(&[
            "sweep",
            script.to_str().unwrap(),
            "--vary",
            "amplitude=0.004,0.006",
            "--jobs",
            "1",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        c.stderr(Stdio::piped()).stdout(Stdio::piped());
        c
    };
    let (straight, resumed) = (dir.join("straight"), dir.join("resumed"));
    let o = sweep(&straight).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let child = sweep(&resumed).spawn().unwrap();
    let first = resumed.join("amplitude-0.004");
    wait_for_lines(&first.join("series.csv"), 30);
    // SAFETY: kill(2) on the id of a child not yet reaped.
    unsafe {
        libc::kill(child.id() as i32, libc::SIGTERM);
    }
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(143), "{err}");
    let summary = std::fs::read_to_string(first.join("summary.ron")).unwrap();
    assert!(
        summary.contains("status: \"interrupted\""),
        "the case got the signal: {summary}"
    );
    assert!(summary.contains("SIGTERM"), "{summary}");
    assert!(first.join("checkpoint/state.bin").exists());
    assert!(!resumed.join("amplitude-0.006/series.csv").exists());

    let o = sweep(&resumed).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(first.join("summary.ron")).unwrap();
    assert!(
        summary.contains("from_step:"),
        "continued from its checkpoint: {summary}"
    );
    for case in ["amplitude-0.004", "amplitude-0.006"] {
        same_file(
            &straight.join(case).join("series.csv"),
            &resumed.join(case).join("series.csv"),
        );
        assert_eq!(
            comparable_summary(&straight.join(case)),
            comparable_summary(&resumed.join(case)),
            "{case}"
        );
    }
    assert_eq!(
        table_without_timing(&straight.join("sweep.csv")),
        table_without_timing(&resumed.join("sweep.csv"))
    );
}

/// The checkpoint of the 500k-particle 3D case of `slosh bench` (cylinder R = 0.5 m, 0.5 m of
/// water, flat roof at 0.6 m, dx = 0.01 m, the paper scheme) after one step: written and read
/// back bit for bit, each within 5 s of CPU time (the wall time, printed beside it, depends on
/// what else the machine runs; the disk adds about 0.8 s per 100 MB with its fsync). Too slow for the
/// suite (building the case takes most of a minute); run it with
/// `cargo test --release -p slosh-cli --test resume -- --ignored --nocapture checkpoint_of_500k`.
#[test]
#[ignore]
fn checkpoint_of_500k_particles_is_written_and_read_in_under_5_s() {
    use slosh_core::{SimState, Simulation, SphParams};
    use slosh_geometry::{CylinderTank, Roof};
    let setup = CylinderTank::new(0.5, 0.6, 0.5, Roof::Flat)
        .build(0.01)
        .unwrap();
    let params = SphParams::paper().with_paper_stiffness();
    let mut sim = Simulation::<3>::new(setup, params).unwrap();
    slosh_run::advance(
        &mut sim,
        &mut |_t: f64| [0.5, 0.0, 0.0],
        slosh_run::Until::Steps(1),
        &mut (),
        &mut (),
    )
    .unwrap();
    let particles = sim.fluid().position.len() + sim.walls().position.len();
    assert!(particles > 450_000, "{particles} particles");
    let path = temp("checkpoint-500k").join("state.bin");
    // CPU time of this thread (s): what the write and the read cost without the other work of
    // a shared machine; the wall time is reported beside it.
    let cpu_s = || {
        let mut t = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime(2) writes the timespec it is given.
        unsafe {
            libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t);
        }
        t.tv_sec as f64 + 1e-9 * t.tv_nsec as f64
    };

    let (start, cpu) = (Instant::now(), cpu_s());
    let bytes = slosh_io::write_checkpoint(&path, &sim.state()).unwrap();
    let (write_s, write_cpu_s) = (start.elapsed().as_secs_f64(), cpu_s() - cpu);
    let (start, cpu) = (Instant::now(), cpu_s());
    let back: SimState<3> = slosh_io::read_checkpoint(&path).unwrap();
    let (read_s, read_cpu_s) = (start.elapsed().as_secs_f64(), cpu_s() - cpu);
    println!(
        "checkpoint of {particles} particles ({} fluid): {bytes} bytes, {:.1} bytes/particle; \
         write {write_s:.2} s wall, {write_cpu_s:.2} s CPU (state copy, encoding, CRC-32, \
         write, fsync, rename); read {read_s:.2} s wall, {read_cpu_s:.2} s CPU (read, CRC-32, \
         decoding); load average {}",
        sim.fluid().position.len(),
        bytes as f64 / particles as f64,
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    // The same write into memory (/dev/shm, when there is one): the disk's share of the time.
    let shm = Path::new("/dev/shm");
    if shm.is_dir() {
        let in_memory = shm.join(format!("slosh-checkpoint-500k-{}.bin", std::process::id()));
        let start = Instant::now();
        slosh_io::write_checkpoint(&in_memory, &sim.state()).unwrap();
        println!(
            "the same write into /dev/shm: {:.2} s wall",
            start.elapsed().as_secs_f64()
        );
        std::fs::remove_file(&in_memory).ok();
    }
    // Bit for bit: the state read back encodes to the same bytes.
    let again = path.with_file_name("again.bin");
    slosh_io::write_checkpoint(&again, &back).unwrap();
    assert!(std::fs::read(&path).unwrap() == std::fs::read(&again).unwrap());
    assert!(
        write_cpu_s < 5.0 && read_cpu_s < 5.0,
        "write {write_cpu_s:.2} s, read {read_cpu_s:.2} s of CPU"
    );
    std::fs::remove_dir_all(path.parent().unwrap()).ok();
}
