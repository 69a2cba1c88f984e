//! The sound speed follows the tank: a stiffness that squeezes the still liquid is refused or
//! warned about, a flow too fast for the sound speed is warned about, and the resolution can
//! be given per depth or per radius with the lattice fitted to the tank.

use std::path::{Path, PathBuf};
use std::process::Command;

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("slosh-real-scale-tests")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes a 2D case: `tank` and `numerics` map bodies, no excitation unless `accel` is given.
fn case(dir: &Path, tank: &str, numerics: &str, duration: f64, accel: &str) -> PathBuf {
    let script = format!(
        "tank(#{{ shape: \"rect\", {tank} }});\n\
         numerics(#{{ {numerics} }});\n\
         run(#{{ settle: 0.0, duration: {duration}, output_interval: 0.01 }});\n\
         fn ground_accel(t) {{ {accel} }}\n"
    );
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    path
}

/// Runs `slosh run CASE --out DIR --quiet`; returns (success, stderr, summary.ron text).
fn run(case: &Path, out: &Path) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args([
            "run",
            case.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .arg("--quiet")
        .output()
        .expect("run slosh");
    let stderr = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{stderr}");
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap_or_default();
    (o.status.success(), stderr, summary)
}

/// Waits until the run writing `out` has `lines` lines in its `series.csv` (at most 60 s).
fn wait_for_rows(out: &Path, lines: usize) {
    let started = std::time::Instant::now();
    while std::fs::read_to_string(out.join("series.csv"))
        .map_or(true, |t| t.lines().count() < lines)
    {
        assert!(started.elapsed().as_secs() < 60, "the run did not start");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// The number after `key: ` in a summary.
fn field(summary: &str, key: &str) -> f64 {
    let start = summary
        .find(&format!("    {key}: "))
        .unwrap_or_else(|| panic!("{key} not in the summary"));
    let rest = &summary[start + key.len() + 6..];
    rest[..rest.find(',').unwrap()].trim().parse().unwrap()
}

/// The paper's B in a 13 m deep tank compresses the water by 6.3 %: refused with the fix;
/// `allow_compressible` runs it with a warning in the summary.
#[test]
fn paper_stiffness_in_a_real_tank_is_refused() {
    let dir = temp("refused");
    let tank = "width: 24.0, height: 16.0, depth: 13.0, roof: true";
    let c = case(
        &dir,
        tank,
        "scheme: \"modern\", dx: 1.0, eos_b: 1.013e5",
        0.05,
        "0.0",
    );
    let (ok, err, summary) = run(&c, &dir.join("out"));
    assert!(!ok);
    assert!(
        err.contains("compressed by 6.") && err.contains("allow_compressible"),
        "{err}"
    );
    // The folder's summary says why, not "running".
    assert!(
        summary.contains("status: \"failed\"") && summary.contains("compressed by 6."),
        "{summary}"
    );
    let c = case(
        &dir,
        tank,
        "scheme: \"modern\", dx: 1.0, eos_b: 1.013e5, allow_compressible: true",
        0.05,
        "0.0",
    );
    let (ok, err, summary) = run(&c, &dir.join("out2"));
    assert!(ok, "{err}");
    assert!(
        err.contains("warning: the liquid is compressed by 6."),
        "{err}"
    );
    assert!(
        summary.contains("warnings: [\n        \"the liquid is compressed"),
        "{summary}"
    );
}

/// Without any numerics override the sound speed follows the tank: 10 √(g H_ref) with H_ref
/// the 16 m roof height, the still liquid compressed by < 0.5 % (predicted and measured).
#[test]
fn default_sound_speed_follows_the_tank() {
    let dir = temp("default_rule");
    let tank = "width: 24.0, height: 16.0, depth: 13.0, roof: true";
    let c = case(&dir, tank, "scheme: \"modern\", dx: 1.0", 0.2, "0.0");
    let (ok, err, summary) = run(&c, &dir.join("out"));
    assert!(ok, "{err}");
    let c0 = field(&summary, "sound_speed");
    assert!((c0 - 10.0 * (9.81f64 * 16.0).sqrt()).abs() < 1e-9, "{c0}");
    let b = field(&summary, "eos_b");
    assert!((b - 1000.0 * c0 * c0 / 7.0).abs() < 1e-6 * b);
    // Tait compression of 13 m under c0 = 125 m/s: ≈ g H/(2 c0²) = 0.41 %.
    let predicted = field(&summary, "hydrostatic_compression_predicted");
    assert!((predicted - 0.0040).abs() < 0.0003, "{predicted}");
    let measured = field(&summary, "hydrostatic_compression");
    assert!(
        (measured - predicted).abs() < 0.001,
        "{measured} vs {predicted}"
    );
    // The one warning: the 3 m clearance holds 3 spacings of dx = 1 m, so the roof load sees
    // a clearance ≈ 2 dx short (docs/roof-loads.md); nothing about the sound speed.
    assert!(
        summary.contains(
            "warnings: [\n        \"the roof clearance H′ = 3.0000 m holds 3.0 particle spacings"
        ),
        "{summary}"
    );
    assert!(!summary.contains("compressed"), "{summary}");
    assert!(summary.contains("sound_speed_rule: \"10 √(g H_ref) with H_ref = 16.0000 m\""));
}

/// A soft EOS (c0 = 10 m/s in 0.5 m of water: 2.5 % compression) and a flow at Mach ≈ 0.2
/// (a 0.4 m tilt released): both warnings, run completed.
#[test]
fn soft_eos_and_fast_flow_are_warned() {
    let dir = temp("mach");
    let tank = "width: 1.0, height: 1.0, depth: 0.5, roof: true, tilt: 0.4";
    let c = case(
        &dir,
        tank,
        "scheme: \"modern\", dx: 0.04, sound_speed: 10.0",
        0.5,
        "0.0",
    );
    let (ok, err, summary) = run(&c, &dir.join("out"));
    assert!(ok, "{err}");
    assert!(
        err.contains("warning: the liquid is compressed by 2."),
        "{err}"
    );
    assert!(err.contains("warning: the flow reached Mach"), "{err}");
    assert!(field(&summary, "max_mach") > 0.1);
    assert!(field(&summary, "steps_above_mach_limit") > 10.0);
}

/// `particles_per_depth` sets dx = depth / n; a width that is not a whole number of spacings
/// gets dx adjusted (within 2 %) and the summary says so; beyond 2 % it is refused.
#[test]
fn resolution_per_depth_and_lattice_fit() {
    let dir = temp("fit");
    let c = case(
        &dir,
        "width: 1.0, height: 1.0, depth: 0.5",
        "particles_per_depth: 15",
        0.02,
        "0.0",
    );
    let (ok, err, summary) = run(&c, &dir.join("out"));
    assert!(ok, "{err}");
    // dx = 0.5/15 = 0.0333 m: 30 spacings across 1.0 m exactly.
    assert!((field(&summary, "dx") - 0.5 / 15.0).abs() < 1e-12);
    let c = case(
        &dir,
        "width: 1.0, height: 0.95, depth: 0.5",
        "dx: 0.0303",
        0.02,
        "0.0",
    );
    let (ok, err, summary) = run(&c, &dir.join("out2"));
    assert!(ok, "{err}");
    // 1.0/0.0303 = 33.0: dx → 1/33 m; the roof goes to the nearest level, 31 spacings.
    assert!((field(&summary, "dx") - 1.0 / 33.0).abs() < 1e-12);
    assert!(
        summary.contains("so that the tank width 1 m holds 33 spacings"),
        "{summary}"
    );
    assert!(summary.contains("tank height 0.95 m →"), "{summary}");
    // 0.5 m is 16.5 rows of 1/33 m: the fill takes 16 rows, and the summary's tank and its
    // theory period are those of the depth simulated.
    assert!(summary.contains("fill depth 0.5 m → 0.4848"), "{summary}");
    let depth = 16.0 / 33.0;
    let k = std::f64::consts::PI;
    let period = 2.0 * k / (9.81 * k * (k * depth).tanh()).sqrt();
    assert!(
        (field(&summary, "period_1") - period).abs() < 1e-9,
        "{summary}"
    );
    let c = case(
        &dir,
        "width: 1.0, height: 1.0, depth: 0.5",
        "dx: 0.3",
        0.02,
        "0.0",
    );
    let (ok, err, _) = run(&c, &dir.join("out3"));
    assert!(!ok);
    assert!(
        err.contains("would change dx by") && err.contains("use dx ="),
        "{err}"
    );
    let c = case(
        &dir,
        "width: 1.0, height: 1.0, depth: 0.5",
        "dx: 0.02, particles_per_depth: 10",
        0.02,
        "0.0",
    );
    let (ok, err, _) = run(&c, &dir.join("out4"));
    assert!(!ok && err.contains("give one of dx"), "{err}");
}

// ----- the run folder -----

/// A folder whose lock is held by a live process is refused with that process's id; the
/// folder's files stay as they are.
#[test]
fn locked_folder_is_refused_with_the_holder() {
    let dir = temp("locked");
    let c = case(
        &dir,
        "width: 0.4, height: 0.4, depth: 0.2",
        "dx: 0.04",
        0.02,
        "0.0",
    );
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    // Another process holds the lock as a run does: the system's lock on the file (util-linux
    // `flock`, which keeps the shell's pid; `--close` keeps the lock from its child), its pid
    // and host written in the file.
    let lock = out.join(".slosh.lock");
    let mut holder = Command::new("sh")
        .arg("-c")
        .arg("echo \"$$ other-node\" > .slosh.lock && exec flock --close .slosh.lock sleep 30")
        .current_dir(&out)
        .spawn()
        .unwrap();
    let held = |lock: &std::path::Path| {
        !Command::new("flock")
            .args(["--nonblock", "--conflict-exit-code", "9"])
            .arg(lock)
            .arg("true")
            .status()
            .unwrap()
            .success()
    };
    let t0 = std::time::Instant::now();
    while !held(&lock) && t0.elapsed().as_secs() < 20 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let (ok, err, _) = run(&c, &out);
    let _ = holder.kill();
    let _ = holder.wait();
    assert!(!ok);
    assert!(
        err.contains(&format!("pid {} on other-node", holder.id())),
        "{err}"
    );
    // Once the holder is gone its lock is released (its file stays) and the run takes the
    // folder.
    let (ok, err, summary) = run(&c, &out);
    assert!(ok, "{err}");
    assert!(summary.contains("status: \"completed\""));
    assert!(!out.join(".slosh.lock").exists());
}

/// Two runs started into one folder: the second is refused, naming the first's pid, and the
/// first completes with its own series.
#[test]
fn a_second_run_into_a_busy_folder_is_refused() {
    let dir = temp("two_runs");
    let c = case(
        &dir,
        "width: 0.8, height: 0.6, depth: 0.4",
        "dx: 0.02",
        2.0,
        "0.0",
    );
    let out = dir.join("out");
    let first = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["run", c.to_str().unwrap(), "--quiet", "--out"])
        .arg(&out)
        .spawn()
        .unwrap();
    wait_for_rows(&out, 3);
    let (ok, err, _) = run(&c, &out);
    assert!(!ok);
    assert!(err.contains(&format!("pid {}", first.id())), "{err}");
    let o = first.wait_with_output().unwrap();
    assert!(o.status.success());
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"completed\""), "{summary}");
    let series = slosh_io::read_table(out.join("series.csv")).unwrap();
    let t = series.column("t").unwrap();
    assert!(
        t.windows(2).all(|w| w[1] > w[0]),
        "time goes forward in one run's series"
    );
}

/// A rerun in a folder of an earlier run removes that run's outputs first (its summary,
/// plots, frames), and a folder of someone else's files is refused untouched.
#[test]
fn earlier_run_outputs_are_removed_and_foreign_folders_refused() {
    let dir = temp("rerun");
    let c = case(
        &dir,
        "width: 0.4, height: 0.4, depth: 0.2",
        "dx: 0.04",
        0.02,
        "0.0",
    );
    let out = dir.join("out");
    for d in ["plots", "frames"] {
        std::fs::create_dir_all(out.join(d)).unwrap();
    }
    std::fs::write(
        out.join("summary.ron"),
        "(status: \"completed\", case: \"old\")",
    )
    .unwrap();
    std::fs::write(out.join("plots/fig7_a.png"), "old").unwrap();
    std::fs::write(out.join("frames/frame_000999.vtp"), "old").unwrap();
    let (ok, err, summary) = run(&c, &out);
    assert!(ok, "{err}");
    assert!(!summary.contains("\"old\""), "{summary}");
    assert!(!out.join("plots/fig7_a.png").exists());
    assert!(!out.join("frames").exists());
    // The series rewritten with its low-pass columns left no staging folder behind.
    assert!(!out.join(".series-rewrite").exists());
    assert!(out.join("series_units.csv").exists());
    let foreign = dir.join("mine");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("notes.txt"), "keep").unwrap();
    let (ok, err, _) = run(&c, &foreign);
    assert!(!ok && err.contains("notes.txt"), "{err}");
    assert_eq!(
        std::fs::read_to_string(foreign.join("notes.txt")).unwrap(),
        "keep"
    );
}

/// A frame interval far below the time step would write a frame every step: warned with the
/// volume.
#[test]
fn tiny_frame_interval_is_warned() {
    let dir = temp("frames");
    let script = "tank(#{ shape: \"rect\", width: 2.0, height: 1.2, depth: 1.0 });\n\
                  numerics(#{ dx: 0.01 });\n\
                  run(#{ settle: 0.0, duration: 1000.0, output_interval: 0.01, frame_interval: 1e-9 });\n";
    let path = dir.join("case.rhai");
    std::fs::write(&path, script).unwrap();
    // The warning comes before the first step; stop the run as soon as it is printed.
    let mut child = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["run", path.to_str().unwrap(), "--out"])
        .arg(dir.join("out"))
        .arg("--quiet")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let mut text = String::new();
    let mut buf = [0u8; 4096];
    use std::io::Read;
    while !text.contains("GB") {
        let n = stderr.read(&mut buf).unwrap_or(0);
        if n == 0 {
            break;
        }
        text.push_str(&String::from_utf8_lossy(&buf[..n]));
    }
    let _ = child.kill();
    let _ = child.wait();
    assert!(
        text.contains("warning: the frames of this run") && text.contains("GB"),
        "{text}"
    );
}

/// A resolution that cannot fit in memory is refused before anything is allocated, with the
/// estimate and a dx that fits (the 3D cylinder at dx = 10 µm would need ≈ 5×10⁸ GB).
#[test]
fn a_run_that_cannot_fit_in_memory_is_refused_at_once() {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = temp("memory");
    let started = std::time::Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .arg("run")
        .arg(root.join("scripts/cylinder_3d.rhai"))
        .args(["--set", "dx=1e-5", "--quiet", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("this run needs ≈") && err.contains("use dx ≥"),
        "{err}"
    );
    assert!(started.elapsed().as_secs_f64() < 10.0);
    let o = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .arg("run")
        .arg(root.join("scripts/cylinder_3d.rhai"))
        .args(["--max-memory", "0.01", "--quiet", "--out"])
        .arg(dir.join("out2"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("--max-memory"), "{err}");

    // Under an address-space limit (`prlimit --as`, as a batch system or `ulimit -v` sets
    // it) the budget is that limit, not the machine's memory: refused with the reason, not
    // an abort when the allocation fails. dx = 8 mm needs ≈ 1.3 GB; the limit is 0.7 GB.
    if Command::new("prlimit").arg("--version").output().is_err() {
        eprintln!("prlimit (util-linux) not found: the address-space case is not checked");
        return;
    }
    let o = Command::new("prlimit")
        .arg("--as=700000000")
        .arg(env!("CARGO_BIN_EXE_slosh"))
        .arg("run")
        .arg(root.join("scripts/cylinder_3d.rhai"))
        .args(["--set", "dx=0.008", "--threads", "1", "--quiet", "--out"])
        .arg(dir.join("out3"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("address-space limit") && err.contains("use dx ≥"),
        "{err}"
    );
}

/// A plot that cannot be written (here: a file stands where the plots folder goes) is listed
/// in the summary's `output_errors`; the summary is written all the same and the run says so.
#[test]
fn a_plot_that_cannot_be_written_still_leaves_the_summary() {
    let dir = temp("plot_fails");
    let c = case(
        &dir,
        "width: 0.8, height: 0.6, depth: 0.4",
        "dx: 0.02",
        3.0,
        "0.0",
    );
    let out = dir.join("out");
    let child = Command::new(env!("CARGO_BIN_EXE_slosh"))
        .args(["run", c.to_str().unwrap(), "--quiet", "--out"])
        .arg(&out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Once the run has started (its folder cleaned, rows coming), block the plots folder.
    wait_for_rows(&out, 5);
    std::fs::write(out.join("plots"), "not a folder").unwrap();
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("some outputs could not be written"), "{err}");
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    assert!(summary.contains("status: \"completed\""), "{summary}");
    assert!(
        summary.contains("output_errors: [\n        \"plots:"),
        "{summary}"
    );
}
