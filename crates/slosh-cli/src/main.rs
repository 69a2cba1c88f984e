//! `slosh`: sloshing loads on storage tanks by SPH. See `slosh --help`.

use anyhow::{bail, Context, Result};
use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use slosh_cli::{parse_sets, run_case, RunOptions};
use slosh_script::{list_params_with, load_case, CaseOptions};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "slosh",
    version,
    about = "Sloshing loads on liquid storage tanks (roof, walls, floor) by SPH"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a case script and write series.csv, summary.ron, frames and plots.
    Run(RunArgs),
    /// Continue the interrupted run in DIR from its last checkpoint; the finished outputs are
    /// those of the run done without interruption.
    Resume(ResumeArgs),
    /// Run a case over the cartesian product of parameter values (parallel, resumable) into
    /// one sub-folder per case plus sweep.csv.
    Sweep(SweepArgs),
    /// Run a case at successive resolutions (a sweep of its resolution parameter) and write
    /// DIR/convergence.md and convergence.csv: each result's observed order, extrapolated
    /// value and grid convergence index (Celik et al. 2008).
    Converge(ConvergeArgs),
    /// Assess a tank under a suite of ground motions (one run per motion, locally or as a
    /// Slurm job array); writes DIR/assessment.md, assessment.csv and plots.
    Assess(slosh_cli::assess::cli::AssessArgs),
    /// Closed-form numbers for a tank (natural periods, masses, Housner, code wave height).
    Theory(TheoryArgs),
    /// Run the validation suite; writes DIR/report.md and plots; exit code 1 on any FAIL.
    Validate(ValidateArgs),
    /// Throughput benchmark: fixed 2D and 3D cases, particle-steps/s, phases, memory.
    Bench(BenchArgs),
}

#[derive(Args)]
struct BenchArgs {
    /// Only the ≈20k 2D and ≈100k 3D cases, grid backend (under a minute).
    #[arg(long)]
    quick: bool,
    /// Output folder for bench.csv (default: out/bench).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Thread counts to time, comma-separated (default: all cores, then 1).
    #[arg(long, value_delimiter = ',', value_parser = slosh_cli::thread_count)]
    threads: Option<Vec<usize>>,
    /// Only these cases, comma-separated (e.g. `--case 2d-80k`); names as in bench.csv.
    #[arg(long, value_delimiter = ',')]
    case: Option<Vec<String>>,
    /// Scheme to time: paper (default), modern (symplectic, δ-SPH, Adami walls) or
    /// modern-riemann (the modern preset with the Riemann-solver pair).
    #[arg(long, default_value = "paper")]
    scheme: String,
    /// Where the step runs: cpu (default), gpu or gpu_f32 (the modern scheme on the first
    /// Vulkan device in f64 or f32: particle-steps/s and the share of each kernel, into
    /// bench_gpu.csv).
    #[arg(long, value_parser = slosh_core::Backend::NAMES, default_value = "cpu")]
    backend: String,
    /// Smoothing length over particle spacing h/dx in place of the scheme's (paper 1.3,
    /// modern 2.0), e.g. 1.5 to time the modern preset's former kernel width (CPU only).
    #[arg(long)]
    h_over_dx: Option<f64>,
}

#[derive(Args)]
struct ValidateArgs {
    /// Quick subset (about 2 min): skips dx = 0.005 m and the 7 s Housner snapshot.
    #[arg(long)]
    quick: bool,
    /// Output folder.
    #[arg(long, default_value = "out/validate")]
    out: PathBuf,
    /// Run only the stages whose name contains this text, e.g. `--only modern`, `--only 3d`,
    /// `--only "dam break"` (case-insensitive).
    #[arg(long)]
    only: Option<String>,
    /// Wall time between checkpoints of the longest runs (the hours-long real-scale and 3D
    /// stages) into OUT/checkpoint/ (600, 30s, 10m, 1h; 0 = none); the same stage run again
    /// with the same --out continues from its checkpoint.
    #[arg(long, value_name = "DURATION", default_value = "10m")]
    checkpoint_every: String,
}

#[derive(Args)]
struct RunArgs {
    /// The case script (.rhai).
    case: PathBuf,
    /// Output folder (default: out/<case-name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Override a parameter the script declares with param(NAME, default).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// List the script's parameters with their defaults and exit.
    #[arg(long)]
    list_params: bool,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = slosh_cli::thread_count)]
    threads: Option<usize>,
    /// No progress bar and no summary line.
    #[arg(long)]
    quiet: bool,
    /// Also let the script read files below DIR (repeatable); by default it reads only below
    /// its own folder and its project folder (one holding slosh.toml, or the repository root).
    #[arg(long = "allow-read", value_name = "DIR")]
    allow_read: Vec<PathBuf>,
    /// Memory the run may use (GB); without it, what the machine has available. A run whose
    /// estimated need exceeds it is refused before anything is allocated.
    #[arg(long, value_name = "GB", value_parser = positive_gb)]
    max_memory: Option<f64>,
    /// Wall time between checkpoints into DIR/checkpoint/ (600, 30s, 10m, 1h; 0 = none). A
    /// run also checkpoints when interrupted (SIGINT, SIGTERM) and at its end;
    /// `slosh resume DIR` continues it.
    #[arg(long, value_name = "DURATION", default_value = "10m")]
    checkpoint_every: String,
    /// Where the step runs: cpu, gpu (the modern scheme on the first Vulkan device, f64) or
    /// gpu_f32 (the same in f32); overrides the script's `numerics` backend.
    #[arg(long, value_parser = slosh_core::Backend::NAMES)]
    backend: Option<String>,
}

#[derive(Args)]
struct ResumeArgs {
    /// The run folder of the interrupted run.
    dir: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = slosh_cli::thread_count)]
    threads: Option<usize>,
    /// No progress bar and no summary line.
    #[arg(long)]
    quiet: bool,
    /// Wall time between checkpoints (default: as the run was started).
    #[arg(long, value_name = "DURATION")]
    checkpoint_every: Option<String>,
    /// Memory the run may use (GB).
    #[arg(long, value_name = "GB", value_parser = positive_gb)]
    max_memory: Option<f64>,
    /// Where the step runs (default: where the run started).
    #[arg(long, value_parser = slosh_core::Backend::NAMES)]
    backend: Option<String>,
}

/// A positive, finite number of GB.
fn positive_gb(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err(format!("must be a positive number of GB (got {text})")),
    }
}

#[derive(Args)]
struct ConvergeArgs {
    /// The case script (.rhai).
    case: PathBuf,
    /// The script parameter that sets the resolution; its value (the script's default or
    /// --set) is the coarsest level.
    #[arg(long, default_value = "dx")]
    param: String,
    /// Number of levels (3 or more give an order and a GCI).
    #[arg(long, default_value_t = 3)]
    levels: usize,
    /// Refinement ratio between consecutive levels.
    #[arg(long, default_value_t = 2.0)]
    ratio: f64,
    /// Whether a finer level divides the parameter (a spacing: dx) or multiplies it (a count:
    /// particles_per_depth); default from the parameter's name.
    #[arg(long, value_parser = ["divide", "multiply"])]
    refine: Option<String>,
    /// Another parameter, NAME=VALUE, the same at every level (repeatable); the resolution
    /// parameter's own (--set dx=0.04) sets the coarsest level.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// Folder of the study (default: out/<case-name>-converge).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Levels run at once, each with cores/jobs threads (default 0: one per core, up to the
    /// number of levels).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Report failures only.
    #[arg(long)]
    quiet: bool,
    /// Also let the script read files below DIR (repeatable), as `slosh run --allow-read`.
    #[arg(long = "allow-read", value_name = "DIR")]
    allow_read: Vec<PathBuf>,
    /// Slurm: write DIR/sweep.sbatch, one array task per level; then `slosh converge …
    /// --collect` writes the report.
    #[command(flatten)]
    slurm: slosh_cli::slurm::SlurmArgs,
    /// Write the report from the levels finished so far (after a --slurm job).
    #[arg(long, conflicts_with = "slurm")]
    collect: bool,
    /// Where the levels' steps run: cpu, gpu or gpu_f32 (as `slosh run --backend`).
    #[arg(long, value_parser = slosh_core::Backend::NAMES)]
    backend: Option<String>,
}

#[derive(Args)]
struct SweepArgs {
    /// The case script (.rhai).
    case: PathBuf,
    /// Values of one parameter: NAME=V1,V2,... or NAME=START:STOP:STEP (STOP included).
    /// Repeat for more parameters; the first --vary varies slowest.
    #[arg(long = "vary", value_name = "NAME=VALUES", required = true)]
    vary: Vec<String>,
    /// Sweep folder (default: out/<case-name>-sweep).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Cases run at once, each with cores/jobs threads (default 0: one per core, up to the
    /// number of cases).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Plot columns of sweep.csv after the sweep: X:Y1,Y2[:GROUP1+GROUP2] (repeatable),
    /// e.g. tank_height:max_roof_p:smoothing_steps.
    #[arg(long = "plot", value_name = "X:Y[:GROUP]")]
    plot: Vec<String>,
    /// Report failures only: no progress lines and no closing table.
    #[arg(long)]
    quiet: bool,
    /// Also let the script read files below DIR (repeatable), as `slosh run --allow-read`.
    #[arg(long = "allow-read", value_name = "DIR")]
    allow_read: Vec<PathBuf>,
    /// Slurm: write DIR/sweep.sbatch, one array task per case.
    #[command(flatten)]
    slurm: slosh_cli::slurm::SlurmArgs,
    /// Run case I of the sweep only (default: $SLURM_ARRAY_TASK_ID), as an array task does.
    #[arg(long, value_name = "I", num_args = 0..=1, conflicts_with_all = ["slurm", "collect"])]
    task: Option<Option<usize>>,
    /// Threads of the task's run (with --task; default: $SLURM_CPUS_PER_TASK when set, else
    /// all cores).
    #[arg(long, value_name = "N", requires = "task", value_parser = slosh_cli::thread_count)]
    threads: Option<usize>,
    /// Write sweep.csv from the cases finished so far (after a --slurm job).
    #[arg(long, conflicts_with = "slurm")]
    collect: bool,
    /// Where the cases' steps run: cpu, gpu or gpu_f32 (as `slosh run --backend`; passed to each case's
    /// run, and to the array tasks of a Slurm job, as SLOSH_BACKEND).
    #[arg(long, value_parser = slosh_core::Backend::NAMES)]
    backend: Option<String>,
}

#[derive(Args)]
#[command(allow_negative_numbers = true)]
struct TheoryArgs {
    /// Tank shape: rect (2D section / rectangular tank) or cylinder.
    shape: String,
    /// Inner width 2l of a rectangular tank (m).
    #[arg(long)]
    width: Option<f64>,
    /// Inner radius R of a cylinder (m).
    #[arg(long)]
    radius: Option<f64>,
    /// Still liquid depth H (m).
    #[arg(long)]
    depth: f64,
    /// Tank (roof) height above the floor (m), for the freeboard check.
    #[arg(long)]
    tank_height: Option<f64>,
    /// Peak ground acceleration (m/s²).
    #[arg(long)]
    pga: Option<f64>,
    /// Convective spectral acceleration S_a(T_c) (in g).
    #[arg(long)]
    sa: Option<f64>,
    /// Sine excitation amplitude A (m): ground displacement A sin ωt.
    #[arg(long)]
    amplitude: Option<f64>,
    /// Sine excitation circular frequency ω (rad/s).
    #[arg(long)]
    omega: Option<f64>,
    /// Gravity (m/s²).
    #[arg(long, default_value_t = 9.81)]
    gravity: f64,
    /// Print RON instead of a table.
    #[arg(long)]
    ron: bool,
}

/// Stops with a clear message when the binary was built for vector instructions (x86-64-v3,
/// see `.cargo/config.toml`) that this CPU lacks, instead of dying on an illegal instruction
/// in the middle of a run. Kept out of line and free of allocation and formatting: code this
/// crate compiles may itself use those instructions, so the failure path only tests bits,
/// writes a fixed message through std (built for the baseline CPU) and exits.
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
#[inline(never)]
fn exit_unless_cpu_supports_build() {
    use std::io::Write;
    if x86_64_v3_supported() {
        return;
    }
    let _ = std::io::stderr().write_all(
        b"error: this slosh was built for x86-64-v3 CPUs (AVX2, FMA, BMI2), which this CPU is \
not; rebuild it for this machine with RUSTFLAGS=\"-C target-cpu=native\" cargo build --release\n",
    );
    std::process::exit(1);
}

#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
fn exit_unless_cpu_supports_build() {}

/// Whether the CPU and OS provide the x86-64-v3 instructions the build uses (AVX, AVX2, FMA,
/// BMI2), read from CPUID itself: `is_x86_feature_detected!` answers "present" without
/// asking the CPU when the build already enables the feature, which is the case to catch.
#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
#[inline(never)]
fn x86_64_v3_supported() -> bool {
    use std::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
    // CPUID is available on every x86-64 CPU.
    #[allow(unused_unsafe)]
    let (leaf1, leaf7) = unsafe { (__cpuid(1), __cpuid_count(7, 0)) };
    let bit = |reg: u32, n: u32| reg & (1 << n) != 0;
    // XGETBV only where CPUID.1:ECX.OSXSAVE says so; the OS must save the SSE and AVX
    // registers (XCR0 bits 1 and 2).
    let osxsave = bit(leaf1.ecx, 27);
    #[allow(unused_unsafe)]
    let avx_state = osxsave && unsafe { _xgetbv(0) } & 0b110 == 0b110;
    avx_state
        && bit(leaf1.ecx, 28) // AVX
        && bit(leaf7.ebx, 5) // AVX2
        && bit(leaf1.ecx, 12) // FMA
        && bit(leaf7.ebx, 8) // BMI2
}

/// Mesa's Vulkan device-selection layer asks a Wayland compositor for the default GPU and,
/// without a runtime folder (a batch job, a container, a CI shell), prints
/// "XDG_RUNTIME_DIR is invalid or not set" to the terminal of a run that is fine. There it
/// has no compositor to ask, so it is turned off the way the layer's manifest provides
/// (`NODEVICE_SELECT=1`), unless the user set that variable. Called first in `main`, before
/// any other thread exists.
fn quiet_vulkan_device_selection() {
    let runtime_dir_ok =
        std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| std::path::Path::new(&d).is_dir());
    if !runtime_dir_ok && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

fn main() -> ExitCode {
    quiet_vulkan_device_selection();
    exit_unless_cpu_supports_build();
    let cli = parse_command_line();
    if matches!(
        cli.command,
        Command::Run(_)
            | Command::Resume(_)
            | Command::Sweep(_)
            | Command::Converge(_)
            | Command::Assess(_)
    ) {
        if let Err(e) = slosh_cli::interrupt::install() {
            eprintln!("warning: SIGINT/SIGTERM handlers not installed ({e}): a signal ends the run at once");
        }
    }
    let result = match cli.command {
        Command::Run(args) => cmd_run(args),
        Command::Resume(args) => cmd_resume(args),
        Command::Sweep(args) => cmd_sweep(args),
        Command::Converge(args) => cmd_converge(args),
        Command::Assess(args) => {
            pass_backend_on(args.backend.as_deref());
            parse_sets(&args.set)
                .and_then(|sets| slosh_cli::assess::cli::cli_assess(args, sets.overrides))
        }
        Command::Theory(args) => cmd_theory(args),
        Command::Bench(args) => {
            let backend = slosh_core::Backend::from_name(&args.backend).unwrap_or_default();
            if backend != slosh_core::Backend::Cpu && args.h_over_dx.is_some() {
                Err(anyhow::anyhow!(
                    "--h-over-dx is for the CPU bench; the GPU bench times the modern preset \
                     as it is"
                ))
            } else if backend != slosh_core::Backend::Cpu {
                slosh_cli::bench::cli_bench_gpu(args.quick, args.out, args.case, backend)
            } else {
                slosh_cli::bench::cli_bench(
                    args.quick,
                    args.out,
                    args.threads,
                    args.case,
                    &args.scheme,
                    args.h_over_dx,
                )
            }
        }
        Command::Validate(args) => {
            let validated = slosh_case::checkpoint::parse_every(&args.checkpoint_every)
                .map_err(|e| anyhow::anyhow!("--checkpoint-every {e}"))
                .and_then(|every| {
                    slosh_cli::validate::cli_validate(args.quick, args.out, args.only, every)
                });
            match validated {
                Ok(true) => Ok(()),
                Ok(false) => {
                    eprintln!("validation: at least one check FAILED (see the report)");
                    return ExitCode::FAILURE;
                }
                Err(e) => Err(e),
            }
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            match e.downcast_ref::<slosh_cli::interrupt::Interrupted>() {
                Some(i) => ExitCode::from(i.exit_code()),
                None => ExitCode::FAILURE,
            }
        }
    }
}

/// Parses the command line; `slosh run --help` (and `slosh help run`) end with the shipped
/// case scripts and their purpose.
fn parse_command_line() -> Cli {
    let command = Cli::command().mut_subcommand("run", |run| {
        run.after_help(slosh_cli::shipped_scripts::help_text())
    });
    Cli::from_arg_matches(&command.get_matches()).unwrap_or_else(|e| e.exit())
}

/// Runs `body` inside a pool of `threads` worker threads (default: one per core, or
/// `RAYON_NUM_THREADS`): the time step's parallel passes then start on a worker of the pool.
/// Called from outside the pool, every pass is handed to the workers and the caller sleeps
/// until it is done; for a case of a few thousand particles (a pass of tens of microseconds)
/// that hand-over cost as much system time as the step itself (the §3.1 case: 13 s of system
/// time in an 18 s run).
fn in_pool<T: Send>(threads: Option<usize>, body: impl FnOnce() -> Result<T> + Send) -> Result<T> {
    if let Some(n) = threads {
        // Checked by clap's parser already; a caller in code is held to the same bounds.
        slosh_cli::thread_count(&n.to_string()).map_err(|e| anyhow::anyhow!("--threads {e}"))?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    pool.install(body)
}

fn cmd_run(args: RunArgs) -> Result<()> {
    in_pool(args.threads, move || cmd_run_in_pool(args))
}

fn cmd_run_in_pool(args: RunArgs) -> Result<()> {
    let mut options = parse_sets(&args.set)?;
    options.allow_read = args.allow_read.clone();
    if args.list_params {
        let read_only = CaseOptions {
            allow_read: args.allow_read,
            ..CaseOptions::default()
        };
        print!(
            "{}",
            params_table(&list_params_with(&args.case, &read_only)?)
        );
        if let Ok(case) = load_case(&args.case, &read_only) {
            println!("\nwall parts (their loads: series.csv, summary.ron `parts`):");
            for (name, what) in case.tank.part_descriptions() {
                println!("{name:<20} {what}");
            }
        }
        return Ok(());
    }
    let mut case = load_case(&args.case, &options)?;
    set_backend(&mut case, args.backend.as_deref());
    let out = args
        .out
        .unwrap_or_else(|| PathBuf::from("out").join(&case.name));
    let every = slosh_case::checkpoint::parse_every(&args.checkpoint_every)
        .map_err(|e| anyhow::anyhow!("--checkpoint-every {e}"))?;
    let checkpoints = match every {
        Some(every) => {
            let mut record = slosh_case::checkpoint::RunRecord::new(
                &args.case,
                &args.set,
                &args.allow_read,
                every,
            )?;
            record.backend = args.backend.clone();
            Some((record, every))
        }
        None => None,
    };
    let opts = RunOptions {
        out_dir: out,
        progress: !args.quiet,
        verbose: !args.quiet,
        plots: true,
        max_memory_bytes: args.max_memory.map(|gb| gb * 1e9),
        checkpoints,
        resume: false,
    };
    run_case(case, &opts)?;
    Ok(())
}

/// `--backend` of a sweep or an assessment: its runs (child `slosh run` processes, or the
/// array tasks of its Slurm job, whose script exports it) read it from SLOSH_BACKEND.
fn pass_backend_on(backend: Option<&str>) {
    if let Some(b) = backend {
        // Set before any thread or child starts.
        std::env::set_var(slosh_cli::BACKEND_ENV, b);
    }
}

/// `--backend cpu|gpu|gpu_f32`: where the case's step runs, over what its script says; without the
/// flag, SLOSH_BACKEND (set by a sweep or an assessment for its runs) when it names one.
fn set_backend(case: &mut slosh_script::Case, backend: Option<&str>) {
    let from_env = std::env::var(slosh_cli::BACKEND_ENV).ok();
    if let Some(b) = backend
        .or(from_env.as_deref())
        .and_then(slosh_core::Backend::from_name)
    {
        case.sph.backend = b;
    }
}

fn cmd_resume(args: ResumeArgs) -> Result<()> {
    in_pool(args.threads, move || cmd_resume_in_pool(args))
}

fn cmd_resume_in_pool(args: ResumeArgs) -> Result<()> {
    let record = slosh_case::checkpoint::RunRecord::read(&args.dir)?;
    // The run continues where it started: its script and record paths may be relative.
    let dir = std::fs::canonicalize(&args.dir)
        .with_context(|| format!("cannot resolve {}", args.dir.display()))?;
    std::env::set_current_dir(&record.working_dir).with_context(|| {
        format!(
            "cannot enter {}, where the run started",
            record.working_dir.display()
        )
    })?;
    let mut options = parse_sets(&record.sets)?;
    options.allow_read = record.allow_read.clone();
    let mut case = load_case(&record.script, &options)?;
    set_backend(
        &mut case,
        args.backend.as_deref().or(record.backend.as_deref()),
    );
    if case.dim() != record.dim {
        anyhow::bail!(
            "the checkpoint in {} is of a {}D run; the script now builds a {}D case",
            dir.display(),
            record.dim,
            case.dim()
        );
    }
    let every = match &args.checkpoint_every {
        Some(text) => slosh_case::checkpoint::parse_every(text)
            .map_err(|e| anyhow::anyhow!("--checkpoint-every {e}"))?,
        None => Some(
            std::time::Duration::try_from_secs_f64(record.checkpoint_every_s)
                .unwrap_or(std::time::Duration::MAX),
        ),
    };
    // A resumed run keeps checkpointing (at least when interrupted again and at its end).
    let every = every.unwrap_or(std::time::Duration::MAX);
    let opts = RunOptions {
        out_dir: dir,
        progress: !args.quiet,
        verbose: !args.quiet,
        plots: true,
        max_memory_bytes: args.max_memory.map(|gb| gb * 1e9),
        checkpoints: Some((record, every)),
        resume: true,
    };
    run_case(case, &opts)?;
    Ok(())
}

/// The `--list-params` table: name, type, default, unit and description of each parameter
/// (`-` for a parameter without a unit, `(not documented)` when the script says nothing).
fn params_table(params: &[slosh_script::ParamDecl]) -> String {
    let mut text = format!(
        "{:<20} {:<10} {:<14} {:<8} description\n",
        "parameter", "type", "default", "unit"
    );
    for p in params {
        let default = p.default.to_string();
        text.push_str(&format!(
            "{:<20} {:<10} {:<14} {:<8} {}\n",
            p.name,
            p.default.type_name(),
            default,
            p.unit.as_deref().unwrap_or("-"),
            p.description.as_deref().unwrap_or("(not documented)")
        ));
    }
    text
}

fn cmd_converge(args: ConvergeArgs) -> Result<()> {
    use slosh_cli::converge::{cli_converge, print_table, ConvergeRequest, Refinement};
    use slosh_cli::sweep::{CaseStatus, SweepMode};
    pass_backend_on(args.backend.as_deref());
    let refine = args.refine.as_deref().map(Refinement::parse).transpose()?;
    let request = ConvergeRequest {
        param: args.param.clone(),
        levels: args.levels,
        ratio: args.ratio,
        refine,
        sets: args.set.clone(),
        out: args.out.clone(),
        jobs: args.jobs,
        quiet: args.quiet,
        allow_read: args.allow_read.clone(),
    };
    let mode = match (args.slurm.slurm, args.collect) {
        (true, _) => SweepMode::Slurm {
            options: args.slurm.options(),
            submit: args.slurm.submit,
        },
        (_, true) => SweepMode::Collect,
        _ => SweepMode::Run,
    };
    let exe =
        std::env::current_exe().context("cannot find the slosh executable that runs the levels")?;
    let outcome = cli_converge(&exe, &args.case, &request, &mode)?;
    if matches!(mode, SweepMode::Slurm { .. }) {
        eprintln!(
            "then, for the convergence report: the same slosh converge command with --collect \
             in place of --slurm (it collects the levels and writes {}/convergence.md)",
            outcome.sweep.out_dir.display()
        );
        return Ok(());
    }
    let unfinished: Vec<String> = outcome
        .sweep
        .cases
        .iter()
        .filter(|c| !matches!(c.status, CaseStatus::Completed | CaseStatus::Skipped))
        .map(|c| format!("{} ({})", c.folder, c.status))
        .collect();
    if !unfinished.is_empty() {
        bail!(
            "no convergence report: {} of {} levels have not completed: {}",
            unfinished.len(),
            outcome.sweep.cases.len(),
            unfinished.join(", ")
        );
    }
    if !args.quiet {
        print_table(&outcome, &args.param);
        if let Some(csv) = &outcome.csv {
            eprintln!(
                "convergence: {} and {}",
                csv.display(),
                csv.with_extension("md").display()
            );
        }
    }
    Ok(())
}

fn cmd_sweep(args: SweepArgs) -> Result<()> {
    pass_backend_on(args.backend.as_deref());
    use slosh_cli::sweep_plot::{draw, SweepPlot};
    // Check the plot requests before running anything.
    let plots: Vec<SweepPlot> = args
        .plot
        .iter()
        .map(|p| SweepPlot::parse(p))
        .collect::<Result<_>>()?;
    let varied: Vec<String> = args
        .vary
        .iter()
        .map(|v| slosh_cli::sweep::parse_vary(v).map(|v| v.name))
        .collect::<Result<_>>()?;
    let columns = slosh_cli::sweep::known_columns(&varied);
    for plot in &plots {
        plot.check_columns(&columns)?;
    }
    let exe = std::env::current_exe()
        .context("cannot find the slosh executable that runs the cases of the sweep")?;
    use slosh_cli::sweep::SweepMode;
    let mode = match (args.slurm.slurm, args.task, args.collect) {
        (true, ..) => SweepMode::Slurm {
            options: args.slurm.options(),
            submit: args.slurm.submit,
        },
        (_, Some(index), _) => SweepMode::Task {
            index,
            threads: args.threads,
        },
        (_, _, true) => SweepMode::Collect,
        _ => SweepMode::Run,
    };
    let outcome = slosh_cli::sweep::cli_sweep_as(
        &exe,
        &args.case,
        &args.vary,
        args.out,
        args.jobs,
        args.quiet,
        &args.allow_read,
        &mode,
    )?;
    match mode {
        SweepMode::Slurm { .. } => return Ok(()),
        SweepMode::Task { .. } => {
            return match outcome.cases.first() {
                Some(c) if c.status == slosh_cli::sweep::CaseStatus::Failed => bail!(
                    "case {} failed: {}",
                    c.folder,
                    c.error.as_deref().unwrap_or("unknown error")
                ),
                _ => Ok(()),
            }
        }
        _ => {}
    }
    for plot in &plots {
        let title = format!(
            "{} — {}",
            args.case.file_stem().unwrap_or_default().to_string_lossy(),
            plot.file_stem()
        );
        let stem = draw(&outcome.csv, plot, &title)?;
        if !args.quiet {
            eprintln!("plot: {}.png", stem.display());
        }
    }
    let missing = outcome
        .cases
        .iter()
        .filter(|c| c.status == slosh_cli::sweep::CaseStatus::Missing)
        .count();
    if missing > 0 {
        bail!(
            "{missing} of {} cases have not run yet (status `missing` in {}); collect again when the job has ended",
            outcome.cases.len(),
            outcome.csv.display()
        );
    }
    let failed = outcome.failed();
    if failed > 0 {
        bail!(
            "{failed} of {} cases failed; the errors are in the error column of {} and in each failed case's run.log",
            outcome.cases.len(),
            outcome.csv.display()
        );
    }
    Ok(())
}

fn cmd_theory(args: TheoryArgs) -> Result<()> {
    use slosh_theory::{tank_report, SineExcitation, TankInput};
    let mut input = match args.shape.as_str() {
        "rect" | "rectangle" | "rectangular" => {
            let w = args
                .width
                .context("a rectangular tank needs --width (inner width 2l, m)")?;
            TankInput::rectangular(w, args.depth)
        }
        "cylinder" | "cyl" => {
            let r = args
                .radius
                .context("a cylinder needs --radius (inner radius R, m)")?;
            TankInput::cylindrical(r, args.depth)
        }
        other => bail!("unknown tank shape \"{other}\": use rect or cylinder"),
    };
    input.gravity = args.gravity;
    input.tank_height = args.tank_height;
    input.peak_ground_accel = args.pga;
    input.spectral_accel_g = args.sa;
    match (args.amplitude, args.omega) {
        (Some(amplitude), Some(omega)) => {
            input.sine = Some(SineExcitation {
                amplitude,
                omega,
                duration: 10.0,
            })
        }
        (None, None) => {}
        _ => bail!("a sine excitation needs both --amplitude and --omega"),
    }
    input.check().map_err(|problems| {
        anyhow::anyhow!(
            "slosh theory: {problems}; give sizes in metres, e.g. --width 1.0 --depth 0.5"
        )
    })?;
    let report = tank_report(&input);
    let text = if args.ron {
        ron::ser::to_string_pretty(&report, ron::ser::PrettyConfig::default())?
    } else {
        report.to_string()
    };
    // A closed pipe (`slosh theory … | head`) ends the output quietly instead of panicking.
    match writeln!(std::io::stdout().lock(), "{text}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}
