//! `--backend gpu` (f64) and `gpu_f32` end to end: the same case run on the GPU backend and on
//! the CPU gives the same free-sloshing period and damping and the same roof impact, its
//! summary names the device and the precision, a sweep passes the backend on to its cases,
//! and without a Vulkan device the run stops with a message that names the fix.
//!
//! Where no GPU is present the GPU runs use Mesa's software Vulkan device (lavapipe, which
//! offers the 64-bit floats the shaders need; `.ci/run` installs it). On a machine with no
//! Vulkan device at all the comparisons say on the terminal that they skipped and pass, except
//! where `CI` is set (then they fail); the refusal test runs everywhere.
//!
//! Why the GPU and CPU results must agree far closer than the validation suite's tolerances:
//! both backends step the same equations in f64 and differ only in round-off: the order in
//! which each particle's pair sums are added and the device's positions kept relative to
//! their cell (see `crates/slosh-gpu/tests/gpu_against_cpu.rs`), a
//! difference of round-off (≈ 1e-15 relative per step) that a gently sloshing liquid does not
//! amplify by more than a few orders over a few thousand steps. Results that agree to 1e-6
//! relative leave that room and still catch any term computed differently (a wrong term
//! changes a period or a roof peak by 1e-3 or more).

mod scenario;

/// How to get the Vulkan device the GPU scenarios need on a machine without a GPU.
const VULKAN_HOW: &str = "install Mesa's software Vulkan device (Debian: apt-get install \
                          mesa-vulkan-drivers libvulkan1; .ci/run does), then cargo test \
                          --release -p slosh-cli --test gpu_backend";

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn exe() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_slosh"))
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn temp(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join("slosh-gpu-cli-tests").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn slosh(args: &[&str]) -> Command {
    let mut c = Command::new(exe());
    c.args(args).current_dir(repo());
    // Mesa wants a runtime folder; test shells may have none.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        c.env("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    c
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Whether a run's failure is the absence of a usable Vulkan device (the message of the GPU
/// backend's attach).
fn no_device(o: &Output) -> bool {
    let t = text(o);
    !o.status.success() && (t.contains("no Vulkan device") || t.contains("64-bit float"))
}

/// Runs `script` with `sets` on `backend` into `out`; `None` when the GPU backend has no
/// device here (said on stderr), otherwise the run must succeed.
fn run(script: &str, sets: &[&str], backend: &str, out: &Path) -> Option<String> {
    let mut c = slosh(&["run", script, "--quiet", "--backend", backend, "--out"]);
    c.arg(out);
    for s in sets {
        c.args(["--set", s]);
    }
    let o = c.output().unwrap();
    if backend == "gpu" && no_device(&o) {
        scenario::skip_or_require(
            "a --backend gpu comparison",
            &format!("no usable Vulkan device ({})", text(&o).trim()),
            VULKAN_HOW,
        );
        return None;
    }
    assert!(o.status.success(), "{backend}: {}", text(&o));
    Some(std::fs::read_to_string(out.join("summary.ron")).unwrap())
}

/// The number after `name: ` (or the entry `("name", Float(..))` of `post`) in a summary.
fn number(summary: &str, name: &str) -> f64 {
    for line in summary.lines() {
        let l = line.trim();
        if let Some(rest) = l.strip_prefix(&format!("{name}: ")) {
            return rest.trim_end_matches(',').parse().unwrap();
        }
        if let Some(rest) = l.strip_prefix(&format!("(\"{name}\", Float(")) {
            return rest.trim_end_matches(")),").parse().unwrap();
        }
    }
    panic!("no {name} in summary:\n{summary}")
}

fn device(summary: &str) -> String {
    summary
        .lines()
        .find_map(|l| l.trim().strip_prefix("device: "))
        .unwrap_or_else(|| panic!("no device in summary:\n{summary}"))
        .to_string()
}

/// Relative agreement of the f64 GPU backend with the CPU (see the module docs for why 1e-6).
const BACKEND_AGREEMENT: f64 = 1e-6;

/// Relative agreement of the f32 GPU backend with the CPU: 1 %. f32 round-off (≈ 1e-5 of a
/// particle's acceleration per step, `crates/slosh-gpu/tests/gpu_against_cpu.rs`) grows over
/// the thousands of steps of these runs into differences of 1e-5 (the period) to 2e-3 (the
/// filtered roof force) of the results (measured); 1 % leaves room over that and is still
/// far inside the validation suite's tolerances (1.5 % on the period at this resolution, 20 %
/// on impact pressures), so an f32 run answers the engineering question as the f64 run does.
const F32_AGREEMENT: f64 = 1e-2;

fn assert_close_within(name: &str, cpu: f64, gpu: f64, bound: f64) {
    let rel = (gpu - cpu).abs() / cpu.abs().max(1e-300);
    assert!(
        rel <= bound,
        "{name}: cpu {cpu}, gpu {gpu} (rel {rel:.2e}, bound {bound:e})"
    );
}

fn assert_close(name: &str, cpu: f64, gpu: f64) {
    assert_close_within(name, cpu, gpu, BACKEND_AGREEMENT);
}

/// Free decay of the first mode in the 1.0 m × 0.5 m tank at 10 particles per depth for three
/// periods: the GPU's period within 1.5 % of potential theory (the damping stage holds 1 %
/// at 20 per depth; at 10 per depth the period has converged to well under 1 %, measured
/// +0.7 %), and its period and damping ratio those of the CPU run; the same in f32 within
/// [`F32_AGREEMENT`].
#[test]
fn free_decay_period_and_damping_match_the_cpu() {
    let dir = temp("free_decay");
    let sets = ["particles_per_depth=10", "periods=3", "tilt=0.1"];
    let Some(gpu) = run("scripts/free_decay_2d.rhai", &sets, "gpu", &dir.join("gpu")) else {
        return;
    };
    let f32_run = run(
        "scripts/free_decay_2d.rhai",
        &sets,
        "gpu_f32",
        &dir.join("f32"),
    )
    .unwrap();
    let cpu = run("scripts/free_decay_2d.rhai", &sets, "cpu", &dir.join("cpu")).unwrap();
    assert!(
        device(&f32_run).contains("f32 (positions relative to their cell)"),
        "{}",
        device(&f32_run)
    );
    let error = number(&f32_run, "period_error");
    assert!(
        error.abs() < 0.015,
        "GPU f32 period {error:+.4} from theory"
    );
    for name in ["period_first_mode", "zeta_first_mode", "max_eta_left"] {
        assert_close_within(
            name,
            number(&cpu, name),
            number(&f32_run, name),
            F32_AGREEMENT,
        );
    }
    assert!(device(&gpu).contains("Vulkan"), "{}", device(&gpu));
    assert!(device(&gpu).ends_with("f64\","), "{}", device(&gpu));
    assert_eq!(device(&cpu), "\"cpu\",");
    let error = number(&gpu, "period_error");
    assert!(error.abs() < 0.015, "GPU period {error:+.4} from theory");
    for name in ["period_first_mode", "zeta_first_mode", "max_eta_left"] {
        assert_close(name, number(&cpu, name), number(&gpu, name));
    }
}

/// The paper's roofed tank (clearance 0.1 m) under its resonant sine with the modern preset,
/// sound speed from the tank, dx = 0.025 m: the liquid reaches the roof 1 s after the start and
/// peaks at ≈ 15 kPa; the GPU's roof peak, roof force and wave heights those of the CPU (f32:
/// within [`F32_AGREEMENT`]).
#[test]
fn roof_impact_matches_the_cpu() {
    let dir = temp("roof_impact");
    let sets = [
        "scheme=modern",
        "eos_b=0",
        "settle=0.5",
        "duration=2.5",
        "dx=0.025",
    ];
    let Some(gpu) = run("scripts/paper_2d_roof.rhai", &sets, "gpu", &dir.join("gpu")) else {
        return;
    };
    let f32_run = run(
        "scripts/paper_2d_roof.rhai",
        &sets,
        "gpu_f32",
        &dir.join("f32"),
    )
    .unwrap();
    let cpu = run("scripts/paper_2d_roof.rhai", &sets, "cpu", &dir.join("cpu")).unwrap();
    assert!(
        number(&cpu, "max_roof_p") > 1000.0,
        "no roof impact:\n{cpu}"
    );
    for name in [
        "max_roof_p",
        "max_roof_force_up",
        "max_roof_force_up_lp",
        "max_eta_left",
        "max_eta_right",
    ] {
        assert_close(name, number(&cpu, name), number(&gpu, name));
        assert_close_within(
            name,
            number(&cpu, name),
            number(&f32_run, name),
            F32_AGREEMENT,
        );
    }
}

/// `slosh sweep --backend gpu` runs every case on the GPU backend.
#[test]
fn sweep_passes_the_backend_to_its_cases() {
    let dir = temp("sweep");
    let out = dir.join("sweep");
    // A one-value --vary fixes a parameter.
    let o = slosh(&[
        "sweep",
        "scripts/paper_2d_sloshing.rhai",
        "--vary",
        "amplitude=0.005,0.0093",
        "--vary",
        "scheme=modern",
        "--vary",
        "eos_b=0",
        "--vary",
        "dx=0.04",
        "--vary",
        "settle=0.05",
        "--vary",
        "duration=0.2",
        "--vary",
        "frame_interval=0",
        "--backend",
        "gpu",
        "--out",
        out.to_str().unwrap(),
    ])
    .output()
    .unwrap();
    let summaries: Vec<String> = std::fs::read_dir(&out)
        .map(|entries| {
            entries
                .filter_map(|e| std::fs::read_to_string(e.ok()?.path().join("summary.ron")).ok())
                .collect()
        })
        .unwrap_or_default();
    if summaries.iter().any(|s| s.contains("no Vulkan device")) {
        scenario::skip_or_require(
            "the GPU sweep",
            "no usable Vulkan device (its cases' summaries say \"no Vulkan device\")",
            VULKAN_HOW,
        );
        return;
    }
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(summaries.len(), 2, "{}", text(&o));
    for s in &summaries {
        assert!(s.contains("status: \"completed\""), "{s}");
        assert!(device(s).contains("Vulkan"), "{}", device(s));
    }
}

/// Without any Vulkan driver (the loader pointed at none) a GPU run stops with a message that
/// says what to install or to run on the CPU, exits non-zero, and leaves its summary.
#[test]
fn without_a_vulkan_device_the_gpu_backend_is_refused_clearly() {
    let dir = temp("no_device");
    let out = dir.join("run");
    let o = slosh(&[
        "run",
        "scripts/free_decay_2d.rhai",
        "--quiet",
        "--backend",
        "gpu",
        "--set",
        "particles_per_depth=10",
        "--set",
        "tilt=0.1",
        "--set",
        "periods=0.5",
        "--out",
        out.to_str().unwrap(),
    ])
    .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
    .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
    .output()
    .unwrap();
    let t = text(&o);
    assert!(!o.status.success(), "{t}");
    assert!(t.contains("no Vulkan device"), "{t}");
    assert!(
        t.contains("mesa-vulkan-drivers") && t.contains("CPU"),
        "{t}"
    );
    assert!(!t.contains("panicked"), "{t}");
    assert!(out.join("summary.ron").exists(), "{t}");
}

/// Without a runtime folder (a batch job, a CI shell) a GPU run prints no stray
/// "XDG_RUNTIME_DIR is invalid" line of Mesa's device-selection layer; on a software device
/// (lavapipe) it warns that no GPU was found, in the terminal and in the summary.
#[test]
fn without_a_runtime_folder_the_gpu_run_is_quiet_and_names_a_software_device() {
    let dir = temp("no_runtime_dir");
    let out = dir.join("run");
    let o = Command::new(exe())
        .args([
            "run",
            "scripts/free_decay_2d.rhai",
            "--quiet",
            "--backend",
            "gpu",
            "--set",
            "particles_per_depth=10",
            "--set",
            "tilt=0.1",
            "--set",
            "periods=0.2",
            "--out",
        ])
        .arg(&out)
        .current_dir(repo())
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("NODEVICE_SELECT")
        .output()
        .unwrap();
    if no_device(&o) {
        scenario::skip_or_require(
            "the GPU run without a runtime folder",
            &format!("no usable Vulkan device ({})", text(&o).trim()),
            VULKAN_HOW,
        );
        return;
    }
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(!t.contains("XDG_RUNTIME_DIR"), "{t}");
    let summary = std::fs::read_to_string(out.join("summary.ron")).unwrap();
    if device(&summary).contains("llvmpipe") {
        assert!(t.contains("a software device on the CPU"), "{t}");
        assert!(summary.contains("Vulkan sees no GPU"), "{summary}");
    }
}
