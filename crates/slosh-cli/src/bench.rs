//! `slosh bench`: fixed throughput cases (`docs/performance.md`).
//!
//! Every case is built, warmed up ([`WARMUP_STEPS`] steps under gravity and a small sine
//! ground acceleration), then timed for a fixed number of steps in a rayon pool of each
//! requested size. One simulation per (case, backend) serves all thread counts: the timed
//! steps are cut into [`BLOCKS`] blocks and the pools take turns block by block, so that a
//! slow spell of the host weighs on every thread count alike. Reported per run:
//! - particle-steps per second, counting fluid + wall particles (as engineering SPH codes
//!   quote), fluid-only, and over the median and the fastest of [`BLOCKS`] equal blocks of
//!   the timed steps (the least disturbed by other processes);
//! - the share of the wall time of the timed steps spent in each phase of
//!   [`Simulation::phase_times`] (`other` = the rest: the loop, the ground acceleration);
//! - memory: the per-case peak RSS (VmHWM, reset through `/proc/self/clear_refs` before each
//!   case, so it includes the process baseline), the solver's bytes per particle (see
//!   [`SolverBytes`]) and the RSS growth per particle as a cross-check;
//! - CPU utilisation (process CPU time / (wall time × threads)) and the 1-minute load
//!   average, to judge whether the machine was busy.

use anyhow::{bail, Context, Result};
use rayon::ThreadPool;
use slosh_core::{
    NeighbourBackend, ParticleSetup, PhaseTimes, Simulation, SphParams, Tensor, Vector,
};
use slosh_geometry::{CylinderTank, RectTank2, Roof};
use std::fmt::Write as _;
use std::mem::size_of;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Steps run before timing, under the excitation of [`ground_accel`].
pub const WARMUP_STEPS: usize = 20;
/// Untimed steps at the start of each thread count (spins up the pool, warms the caches).
const REWARM_STEPS: usize = 3;
/// The timed steps are split into this many blocks (for the best-block throughput).
pub const BLOCKS: usize = 10;
/// Amplitude (m/s²) and frequency (Hz) of the horizontal sine ground acceleration.
const GROUND_AMPLITUDE: f64 = 0.5;
const GROUND_FREQUENCY: f64 = 2.0;

/// Tank of a bench case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BenchTank {
    /// The paper's 2D tank: 1 m wide, 1 m high, 0.5 m of water, closed roof.
    PaperRect2,
    /// Cylinder R = 0.5 m, shell 0.6 m, 0.5 m of water, flat roof.
    Cylinder3,
    /// The real-scale tank of `scripts/tank_real_scale.rhai`: R = 12 m, shell 16 m, 13 m of
    /// water, cone roof rising 1.5 m; the sound speed from the tank (the laboratory cases keep
    /// the paper's stiffness so that their figures compare across commits).
    RealCylinder3,
    /// The roof-impact tank of paper §3.2 and Fig. 10: 1 m wide, flat roof at 0.6 m, 0.5 m of
    /// water.
    RoofRect2,
}

impl BenchTank {
    /// The tank, when it is a 2D one.
    fn rect2(self) -> Option<RectTank2> {
        match self {
            BenchTank::PaperRect2 => Some(RectTank2::new(1.0, 1.0, 0.5)),
            BenchTank::RoofRect2 => Some(RectTank2::new(1.0, 0.6, 0.5)),
            BenchTank::Cylinder3 | BenchTank::RealCylinder3 => None,
        }
    }

    /// The tank, when it is a 3D one.
    fn cylinder3(self) -> Option<CylinderTank> {
        match self {
            BenchTank::Cylinder3 => Some(CylinderTank::new(0.5, 0.6, 0.5, Roof::Flat)),
            BenchTank::RealCylinder3 => Some(CylinderTank::new(
                12.0,
                16.0,
                13.0,
                Roof::Cone { apex_height: 1.5 },
            )),
            BenchTank::PaperRect2 | BenchTank::RoofRect2 => None,
        }
    }
}

/// One fixed bench case.
#[derive(Clone, Debug)]
pub struct BenchCase {
    /// Case name (CSV `case` column).
    pub name: &'static str,
    /// The tank.
    pub tank: BenchTank,
    /// Particle spacing (m).
    pub dx: f64,
    /// Timed steps (fixed, so runs compare across commits).
    pub steps: usize,
    /// Also run the kd-tree backend.
    pub kdtree: bool,
}

/// The full case list. Step counts give a few seconds per run at the throughput of the
/// unoptimised solver on 2 cores; they stay fixed so that CSVs compare across commits.
pub fn full_cases() -> Vec<BenchCase> {
    vec![
        BenchCase {
            name: "2d-2k",
            tank: BenchTank::PaperRect2,
            dx: 0.02,
            steps: 2000,
            kdtree: true,
        },
        BenchCase {
            name: "2d-20k",
            tank: BenchTank::PaperRect2,
            dx: 0.005,
            steps: 500,
            kdtree: true,
        },
        BenchCase {
            name: "2d-80k",
            tank: BenchTank::PaperRect2,
            dx: 0.0025,
            steps: 300,
            kdtree: true,
        },
        BenchCase {
            name: "3d-100k",
            tank: BenchTank::Cylinder3,
            dx: 0.018,
            steps: 30,
            kdtree: true,
        },
        // kd-tree skipped at 500k: several times slower than the grid (see the 100k case).
        BenchCase {
            name: "3d-500k",
            tank: BenchTank::Cylinder3,
            dx: 0.01,
            steps: 20,
            kdtree: false,
        },
        // ≈ 1M particles: the size at which a GPU is judged against the CPU.
        BenchCase {
            name: "3d-1m",
            tank: BenchTank::Cylinder3,
            dx: 0.008,
            steps: 10,
            kdtree: false,
        },
        // The roof-impact tank at the finest lattice of the roof-load study (dx = 0.005 m).
        BenchCase {
            name: "2d-roof-5mm",
            tank: BenchTank::RoofRect2,
            dx: 0.005,
            steps: 500,
            kdtree: false,
        },
        // The real tank at 16, 24 and 32 particles per radius (≈ 25k, 75k and 180k particles):
        // what a recorded motion costs at the resolutions of a convergence study.
        BenchCase {
            name: "3d-real-16",
            tank: BenchTank::RealCylinder3,
            dx: 0.75,
            steps: 40,
            kdtree: false,
        },
        BenchCase {
            name: "3d-real",
            tank: BenchTank::RealCylinder3,
            dx: 0.5,
            steps: 40,
            kdtree: false,
        },
        BenchCase {
            name: "3d-real-32",
            tank: BenchTank::RealCylinder3,
            dx: 0.375,
            steps: 30,
            kdtree: false,
        },
    ]
}

/// `--quick`: the ≈20k 2D and ≈100k 3D cases, grid backend only.
pub fn quick_cases() -> Vec<BenchCase> {
    full_cases()
        .into_iter()
        .filter(|c| c.name == "2d-20k" || c.name == "3d-100k")
        .map(|c| BenchCase { kdtree: false, ..c })
        .collect()
}

/// The cases of a run: the full or `--quick` list, restricted to `names` when given (an
/// unknown name is an error that lists the known ones).
pub fn select_cases(quick: bool, names: Option<&[String]>) -> Result<Vec<BenchCase>> {
    let mut cases = if quick { quick_cases() } else { full_cases() };
    if let Some(names) = names {
        let known: Vec<&str> = cases.iter().map(|c| c.name).collect();
        if let Some(bad) = names.iter().find(|n| !known.contains(&n.as_str())) {
            bail!(
                "unknown bench case '{bad}'{}: the cases are {}",
                if quick { " (with --quick)" } else { "" },
                known.join(", ")
            );
        }
        cases.retain(|c| names.iter().any(|n| n == c.name));
    }
    Ok(cases)
}

/// One timed run: a case, a backend and a thread count.
#[derive(Clone, Debug)]
pub struct BenchRow {
    pub case: String,
    pub dim: usize,
    /// "paper", "modern" or "modern-riemann".
    pub scheme: &'static str,
    pub backend: &'static str,
    /// Threads of the rayon pool the steps ran in.
    pub threads: usize,
    pub dx: f64,
    /// Fluid + wall particles.
    pub particles: usize,
    pub fluid_particles: usize,
    pub steps: usize,
    /// Wall time of the timed steps (s).
    pub wall_s: f64,
    /// (fluid + wall) × steps / wall_s.
    pub particle_steps_per_s: f64,
    /// fluid × steps / wall_s.
    pub fluid_steps_per_s: f64,
    /// (fluid + wall) particle-steps per second over the fastest block of steps.
    pub best_block_particle_steps_per_s: f64,
    /// (fluid + wall) particle-steps per second of the median block (per-step time): on a
    /// shared host, the figure least moved by slow spells, for comparisons across commits.
    pub median_block_particle_steps_per_s: f64,
    /// Shares of wall_s: neighbour search, density, forces, integration, loads, other.
    pub shares: [f64; 6],
    /// Solver bytes per (fluid + wall) particle: reachable arrays + estimated private buffers.
    pub bytes_per_particle: f64,
    /// Only the arrays reachable through the public API (fluid, walls, load points).
    pub bytes_per_particle_arrays: f64,
    /// RSS growth from before the build to after the warm-up, per particle (cross-check).
    pub rss_bytes_per_particle: f64,
    /// Peak RSS (MiB) of the process since the start of this case (includes the baseline).
    pub peak_rss_mb: f64,
    /// Process CPU time / (wall_s × threads).
    pub cpu_util: f64,
    /// (fluid + wall) particle-steps per second of process CPU time: with 1 thread, an
    /// estimate of the unloaded throughput when other processes took the CPU.
    pub particle_steps_per_cpu_s: f64,
    /// 1-minute load average at the end of the case's timed blocks.
    pub load_avg: f64,
    pub version: String,
    /// Wall time per simulated second (s/s): what a run of the case costs per second of
    /// ground motion at this throughput.
    pub wall_s_per_simulated_s: f64,
    /// Smoothing length over particle spacing h/dx of the timed scheme.
    pub h_over_dx: f64,
}

/// Columns of `bench.csv`, in order.
pub const CSV_COLUMNS: [&str; 31] = [
    "case",
    "dim",
    "particles",
    "threads",
    "particle_steps_per_s",
    "bytes_per_particle",
    "backend",
    "fluid_particles",
    "dx",
    "steps",
    "wall_s",
    "fluid_steps_per_s",
    "best_block_particle_steps_per_s",
    "share_neighbour",
    "share_density",
    "share_forces",
    "share_integration",
    "share_loads",
    "share_other",
    "bytes_per_particle_arrays",
    "rss_bytes_per_particle",
    "peak_rss_mb",
    "cpu_util",
    "particle_steps_per_cpu_s",
    "load_avg_1m",
    "version",
    "warmup_steps",
    "median_block_particle_steps_per_s",
    "scheme",
    "wall_s_per_simulated_s",
    "h_over_dx",
];

impl BenchRow {
    fn csv_line(&self) -> String {
        let s = &self.shares;
        format!(
            "{},{},{},{},{:.0},{:.1},{},{},{},{},{:.4},{:.0},{:.0},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.1},{:.1},{:.1},{:.3},{:.0},{:.2},{},{},{:.0},{},{:.2},{}",
            self.case,
            self.dim,
            self.particles,
            self.threads,
            self.particle_steps_per_s,
            self.bytes_per_particle,
            self.backend,
            self.fluid_particles,
            self.dx,
            self.steps,
            self.wall_s,
            self.fluid_steps_per_s,
            self.best_block_particle_steps_per_s,
            s[0],
            s[1],
            s[2],
            s[3],
            s[4],
            s[5],
            self.bytes_per_particle_arrays,
            self.rss_bytes_per_particle,
            self.peak_rss_mb,
            self.cpu_util,
            self.particle_steps_per_cpu_s,
            self.load_avg,
            self.version,
            WARMUP_STEPS,
            self.median_block_particle_steps_per_s,
            self.scheme,
            self.wall_s_per_simulated_s,
            self.h_over_dx,
        )
    }
}

/// What a bench run does, besides the cases.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Thread counts, each run in its own rayon pool (first one also builds the case).
    pub threads: Vec<usize>,
    /// The scheme timed: the paper's (default) or the modern preset (symplectic, continuity
    /// density with δ-SPH, Adami walls, Wendland C2: the physics of the reference code).
    pub modern: bool,
    /// With `modern`: the Riemann-solver pair of Zhang, Hu & Adams 2017 in place of Eq. 8
    /// (`pair_scheme: "riemann"`).
    pub riemann: bool,
    /// Smoothing length over particle spacing h/dx in place of the preset's (paper 1.3,
    /// modern 2.0); the wall layers follow it as in a run.
    pub h_over_dx: Option<f64>,
    /// Print the table and the checks.
    pub verbose: bool,
}

/// `slosh bench [--quick] [--out DIR] [--threads 1,2] [--case NAME,..] [--scheme S]
/// [--h-over-dx R]`: runs the fixed cases (those named by `--case` only) with the paper or the
/// modern scheme, prints a table and the throughput and memory checks, writes
/// `DIR/bench.csv` (default `out/bench`). Always succeeds when the runs complete: the checks
/// report, they do not fail the command.
pub fn cli_bench(
    quick: bool,
    out: Option<PathBuf>,
    threads_list: Option<Vec<usize>>,
    only_cases: Option<Vec<String>>,
    scheme: &str,
    h_over_dx: Option<f64>,
) -> Result<()> {
    if let Some(r) = h_over_dx {
        if !(r.is_finite() && r > 0.0) {
            bail!("--h-over-dx takes the smoothing length over the particle spacing, a number > 0 (e.g. 1.5), not {r}");
        }
    }
    let (modern, riemann) = match scheme {
        "paper" => (false, false),
        "modern" => (true, false),
        "modern-riemann" => (true, true),
        other => {
            bail!("unknown scheme '{other}' for bench: use paper, modern or modern-riemann")
        }
    };
    let machine = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let threads = match threads_list {
        Some(list) => {
            if list.is_empty() || list.contains(&0) {
                bail!("--threads takes a list of thread counts ≥ 1, e.g. --threads 1,2");
            }
            list
        }
        None if machine > 1 => vec![machine, 1],
        None => vec![1],
    };
    let cases = select_cases(quick, only_cases.as_deref())?;
    let out = out.unwrap_or_else(|| PathBuf::from("out").join("bench"));
    let config = BenchConfig {
        threads,
        modern,
        riemann,
        h_over_dx,
        verbose: true,
    };
    println!(
        "slosh bench{}: {} cases, {scheme} scheme{}, threads {:?} (machine: {machine}), load average {}",
        if quick { " --quick" } else { "" },
        cases.len(),
        h_over_dx.map_or(String::new(), |r| format!(" with h = {r} dx")),
        config.threads,
        load_avg_line()
    );
    let started = Instant::now();
    let rows = run_bench(&cases, &config, &out)?;
    print_checks(&rows, quick);
    println!(
        "{} runs in {:.1} s; load average now {}; wrote {}",
        rows.len(),
        started.elapsed().as_secs_f64(),
        load_avg_line(),
        out.join("bench.csv").display()
    );
    Ok(())
}

/// Steps of the GPU bench's profiling pass (each kernel submitted and timed alone).
const GPU_PROFILE_STEPS: u64 = 5;

/// `slosh bench --backend gpu [--quick] [--case NAME,..] [--out DIR]`: the modern preset on
/// the first Vulkan device, each case timed over its fixed steps in one submission per step
/// (particle-steps/s, wall time per simulated second), then a few steps with each kernel
/// submitted alone for its share; prints a table and writes `DIR/bench_gpu.csv`.
pub fn cli_bench_gpu(
    quick: bool,
    out: Option<PathBuf>,
    only_cases: Option<Vec<String>>,
    backend: slosh_core::Backend,
) -> Result<()> {
    #[cfg(feature = "gpu")]
    {
        let cases = select_cases(quick, only_cases.as_deref())?;
        let out = out.unwrap_or_else(|| PathBuf::from("out").join("bench"));
        println!(
            "slosh bench --backend {}{}: {} cases, modern scheme, load average {}",
            backend.name(),
            if quick { " --quick" } else { "" },
            cases.len(),
            load_avg_line()
        );
        let Some(precision) = slosh_gpu::Precision::of(backend) else {
            bail!("the GPU bench needs backend gpu or gpu_f32");
        };
        let mut lines = Vec::new();
        let mut header = String::new();
        for case in &cases {
            let (row, kernels) = match (case.tank.rect2(), case.tank.cylinder3()) {
                (Some(tank), _) => gpu_case::<2>(case, precision, |layers| {
                    Ok(tank.clone().with_layers(layers).build(case.dx)?)
                }),
                (_, Some(tank)) => gpu_case::<3>(case, precision, |layers| {
                    Ok(tank.clone().with_layers(layers).build(case.dx)?)
                }),
                (None, None) => bail!("bench case {}: no tank", case.name),
            }
            .with_context(|| format!("GPU bench case {}", case.name))?;
            let total: f64 = kernels.iter().map(|k| k.1).sum();
            if header.is_empty() {
                header = "case,dim,particles,fluid_particles,steps,wall_s,particle_steps_per_s,\
                          wall_s_per_simulated_s,device"
                    .to_string();
                for (name, _) in &kernels {
                    header.push_str(&format!(",share_{name}"));
                }
            }
            let shares: Vec<String> = kernels
                .iter()
                .map(|(_, t)| format!("{:.4}", t / total.max(f64::MIN_POSITIVE)))
                .collect();
            println!(
                "{:<8} {:>9} particles  {:.3e} particle-steps/s  {:.1} s per simulated s  on {}",
                row.0, row.2, row.6, row.7, row.8
            );
            println!(
                "         kernel shares: {}",
                kernels
                    .iter()
                    .zip(&shares)
                    .map(|((name, _), s)| format!(
                        "{name} {:.0} %",
                        100.0 * s.parse::<f64>().unwrap_or(0.0)
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            lines.push(format!(
                "{},{},{},{},{},{:.4},{:.6e},{:.4},\"{}\",{}",
                row.0,
                row.1,
                row.2,
                row.3,
                row.4,
                row.5,
                row.6,
                row.7,
                row.8,
                shares.join(",")
            ));
        }
        std::fs::create_dir_all(&out)
            .with_context(|| format!("cannot create {}", out.display()))?;
        let path = out.join("bench_gpu.csv");
        slosh_io::write_atomic(
            &path,
            format!("{header}\n{}\n", lines.join("\n")).as_bytes(),
        )?;
        println!("wrote {}", path.display());
        Ok(())
    }
    #[cfg(not(feature = "gpu"))]
    {
        let _ = (quick, out, only_cases, backend);
        bail!("this slosh was built without the GPU backend (cargo feature \"gpu\")")
    }
}

/// One GPU bench case: (case, dim, particles, fluid, steps, wall s, particle-steps/s, wall s
/// per simulated s, device) and the kernel times of the profiling pass.
#[cfg(feature = "gpu")]
#[allow(clippy::type_complexity)]
fn gpu_case<const D: usize>(
    case: &BenchCase,
    precision: slosh_gpu::Precision,
    build: impl Fn(u8) -> Result<ParticleSetup<D>>,
) -> Result<(
    (String, usize, usize, usize, u64, f64, f64, f64, String),
    Vec<(String, f64)>,
)> {
    let base = if case.tank == BenchTank::RealCylinder3 {
        SphParams::modern()
    } else {
        SphParams::modern().with_paper_stiffness()
    };
    let mut sim = Simulation::new(build(base.wall_layers())?, base)?;
    let device = slosh_gpu::attach(&mut sim, precision)?;
    advance(&mut sim, WARMUP_STEPS)?;
    let fluid = sim.fluid().position.len();
    let particles = fluid + sim.walls().position.len();
    let steps = case.steps.max(1) as u64;
    let (t0, sim_t0) = (Instant::now(), sim.time());
    advance(&mut sim, steps as usize)?;
    let wall = t0.elapsed().as_secs_f64();
    let simulated = sim.time() - sim_t0;
    sim.set_device_profiling(true);
    advance(&mut sim, GPU_PROFILE_STEPS as usize)?;
    let kernels = sim.device_kernel_times();
    Ok((
        (
            case.name.to_string(),
            D,
            particles,
            fluid,
            steps,
            wall,
            (particles as u64 * steps) as f64 / wall,
            wall / simulated,
            device,
        ),
        kernels,
    ))
}

/// Runs `cases` and writes `out/bench.csv`; returns the rows.
pub fn run_bench(cases: &[BenchCase], config: &BenchConfig, out: &Path) -> Result<Vec<BenchRow>> {
    let pools = config
        .threads
        .iter()
        .map(|&n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .with_context(|| format!("cannot start a pool of {n} threads"))
        })
        .collect::<Result<Vec<ThreadPool>>>()?;
    let version = version_string();
    let mut rows = Vec::new();
    if config.verbose {
        print_header();
    }
    for case in cases {
        let mut backends = vec![NeighbourBackend::CellGrid];
        if case.kdtree {
            backends.push(NeighbourBackend::KdTree);
        }
        for backend in backends {
            let new_rows = match (case.tank.rect2(), case.tank.cylinder3()) {
                (Some(tank), _) => {
                    run_case::<2>(case, backend, config, &pools, &version, |layers| {
                        Ok(tank.clone().with_layers(layers).build(case.dx)?)
                    })
                }
                (_, Some(tank)) => {
                    run_case::<3>(case, backend, config, &pools, &version, |layers| {
                        Ok(tank.clone().with_layers(layers).build(case.dx)?)
                    })
                }
                (None, None) => bail!("bench case {}: no tank", case.name),
            }
            .with_context(|| format!("bench case {} ({})", case.name, backend_name(backend)))?;
            rows.extend(new_rows);
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut csv = CSV_COLUMNS.join(",");
    csv.push('\n');
    for r in &rows {
        csv.push_str(&r.csv_line());
        csv.push('\n');
    }
    let path = out.join("bench.csv");
    slosh_io::write_atomic(&path, csv.as_bytes())?;
    Ok(rows)
}

fn backend_name(b: NeighbourBackend) -> &'static str {
    match b {
        NeighbourBackend::CellGrid => "grid",
        NeighbourBackend::KdTree => "kdtree",
    }
}

/// Horizontal (x) sine ground acceleration `[x, y, vertical]` at time `t`.
fn ground_accel(t: f64) -> [f64; 3] {
    [
        GROUND_AMPLITUDE * (2.0 * std::f64::consts::PI * GROUND_FREQUENCY * t).sin(),
        0.0,
        0.0,
    ]
}

/// Takes `steps` steps under [`ground_accel`] through the run loop of `slosh-run`.
fn advance<const D: usize>(sim: &mut Simulation<D>, steps: usize) -> Result<()> {
    slosh_run::advance(
        sim,
        &mut ground_accel,
        slosh_run::Until::Steps(steps as u64),
        &mut (),
        &mut (),
    )?;
    Ok(())
}

/// Builds one (case, backend) with `build(wall layers)`, warms it up in the first pool, then
/// times it in every pool.
fn run_case<const D: usize>(
    case: &BenchCase,
    backend: NeighbourBackend,
    config: &BenchConfig,
    pools: &[ThreadPool],
    version: &str,
    build: impl Fn(u8) -> Result<ParticleSetup<D>> + Send + Sync,
) -> Result<Vec<BenchRow>> {
    reset_peak_rss();
    let rss_before = proc_status_kib("VmRSS:").unwrap_or(0) as f64 * 1024.0;
    let preset = if config.modern {
        if config.riemann {
            SphParams::modern().with_riemann_pair()
        } else {
            SphParams::modern()
        }
    } else {
        SphParams::paper()
    };
    let base = if case.tank == BenchTank::RealCylinder3 {
        preset
    } else {
        preset.with_paper_stiffness()
    };
    let params = SphParams {
        neighbour_backend: backend,
        smoothing_ratio: config.h_over_dx.unwrap_or(base.smoothing_ratio),
        ..base
    };
    let h_over_dx = params.smoothing_ratio;
    let mut sim = pools[0].install(|| -> Result<Simulation<D>> {
        let mut sim = Simulation::new(build(params.wall_layers())?, params)?;
        advance(&mut sim, WARMUP_STEPS)?;
        Ok(sim)
    })?;
    let fluid = sim.fluid().position.len();
    let particles = fluid + sim.walls().position.len();
    let rss_after = proc_status_kib("VmRSS:").unwrap_or(0) as f64 * 1024.0;
    let bytes = SolverBytes::of(&sim);
    let steps = case.steps.max(1);
    let blocks = BLOCKS.min(steps);
    // The thread counts take turns block by block, so that a slow spell of the host (other
    // virtual machines on the same cores and cache) falls on all of them alike and the
    // speed-up compares like with like. One untimed step after each change of pool wakes its
    // threads and moves the data to their caches, as a run that stays in one pool would have.
    let mut timings: Vec<PoolTiming> = pools
        .iter()
        .map(|pool| {
            pool.install(|| advance(&mut sim, REWARM_STEPS))
                .map(|()| PoolTiming::default())
        })
        .collect::<Result<_>>()?;
    let mut done = 0;
    for b in 0..blocks {
        let n = (steps * (b + 1)) / blocks - done;
        done += n;
        for (pool, timing) in pools.iter().zip(timings.iter_mut()) {
            pool.install(|| -> Result<()> {
                if pools.len() > 1 {
                    advance(&mut sim, 1)?;
                }
                let p0 = sim.phase_times();
                let cpu0 = process_cpu_s();
                let t0 = Instant::now();
                let sim_t0 = sim.time();
                advance(&mut sim, n)?;
                let wall = t0.elapsed().as_secs_f64();
                timing.sim_s += sim.time() - sim_t0;
                timing.wall_s += wall;
                timing.cpu_s += process_cpu_s() - cpu0;
                timing.block_step_s[b] = wall / n as f64;
                timing.phases = phase_sum(timing.phases, phase_delta(sim.phase_times(), p0));
                Ok(())
            })?;
        }
    }
    let mut rows = Vec::new();
    for (pool, timing) in pools.iter().zip(&timings) {
        let threads = pool.current_num_threads();
        let PoolTiming {
            wall_s,
            sim_s,
            cpu_s,
            phases,
            block_step_s,
        } = *timing;
        let mut per_step = block_step_s[..blocks].to_vec();
        per_step.sort_by(f64::total_cmp);
        let best_block = per_step[0];
        let median_step_s = if blocks % 2 == 1 {
            per_step[blocks / 2]
        } else {
            0.5 * (per_step[blocks / 2 - 1] + per_step[blocks / 2])
        };
        let s = |x: f64| x / wall_s;
        let shares = [
            s(phases.neighbour_search),
            s(phases.density),
            s(phases.forces),
            s(phases.integration),
            s(phases.loads),
            (1.0 - s(phases.total())).max(0.0),
        ];
        let row = BenchRow {
            case: case.name.to_string(),
            dim: D,
            scheme: match (config.modern, config.riemann) {
                (false, _) => "paper",
                (true, false) => "modern",
                (true, true) => "modern-riemann",
            },
            backend: backend_name(backend),
            threads,
            dx: case.dx,
            particles,
            fluid_particles: fluid,
            steps,
            wall_s,
            particle_steps_per_s: (particles * steps) as f64 / wall_s,
            fluid_steps_per_s: (fluid * steps) as f64 / wall_s,
            best_block_particle_steps_per_s: particles as f64 / best_block,
            median_block_particle_steps_per_s: particles as f64 / median_step_s,
            shares,
            bytes_per_particle: bytes.total() as f64 / particles as f64,
            bytes_per_particle_arrays: bytes.reachable as f64 / particles as f64,
            rss_bytes_per_particle: (rss_after - rss_before) / particles as f64,
            peak_rss_mb: 0.0, // filled below, after all thread counts
            cpu_util: cpu_s / (wall_s * threads as f64),
            particle_steps_per_cpu_s: (particles * steps) as f64 / cpu_s,
            load_avg: load_avg_1m(),
            version: version.to_string(),
            wall_s_per_simulated_s: wall_s / sim_s,
            h_over_dx,
        };
        rows.push(row);
    }
    let peak = proc_status_kib("VmHWM:").unwrap_or(0) as f64 / 1024.0;
    for r in &mut rows {
        r.peak_rss_mb = peak;
        if config.verbose {
            print_row(r);
        }
    }
    Ok(rows)
}

/// The timed blocks of one pool, summed.
#[derive(Clone, Copy, Debug, Default)]
struct PoolTiming {
    wall_s: f64,
    /// Simulated time of the timed steps (s).
    sim_s: f64,
    cpu_s: f64,
    phases: PhaseTimes,
    /// Wall time per step of each block (the first `blocks` entries).
    block_step_s: [f64; BLOCKS],
}

fn phase_sum(a: PhaseTimes, b: PhaseTimes) -> PhaseTimes {
    PhaseTimes {
        neighbour_search: a.neighbour_search + b.neighbour_search,
        density: a.density + b.density,
        forces: a.forces + b.forces,
        integration: a.integration + b.integration,
        loads: a.loads + b.loads,
    }
}

fn phase_delta(a: PhaseTimes, b: PhaseTimes) -> PhaseTimes {
    PhaseTimes {
        neighbour_search: a.neighbour_search - b.neighbour_search,
        density: a.density - b.density,
        forces: a.forces - b.forces,
        integration: a.integration - b.integration,
        loads: a.loads - b.loads,
    }
}

/// Heap bytes held by a simulation.
///
/// `reachable` is exact (capacity × element size) for the arrays the public API shows:
/// every `Fluid` and `Walls` array, and the load points of `LoadEvaluator` (8 per-point
/// arrays and the (2N+1)-step pressure history, sized from `len()` and `smoothing_steps()`).
/// `private` is an estimate, from the layout of `sim.rs` and `neighbours.rs` at the time of
/// writing, of what the API does not show: the solver's scratch buffers (one vector, f64,
/// tensor, 2 × u32 and next-density per fluid particle, next-density per wall particle) and
/// the neighbour structures (grid: search + sort grids, entries, cell starts and wall flags; kd-tree:
/// the trees, their scratch copy and the sort grid). Small fixed-size parts are ignored.
#[derive(Clone, Copy, Debug)]
pub struct SolverBytes {
    pub reachable: usize,
    pub private: usize,
}

impl SolverBytes {
    pub fn total(&self) -> usize {
        self.reachable + self.private
    }

    pub fn of<const D: usize>(sim: &Simulation<D>) -> SolverBytes {
        fn b<T>(v: &Vec<T>) -> usize {
            v.capacity() * size_of::<T>()
        }
        let (f, w) = (sim.fluid(), sim.walls());
        let fluid = b(&f.position)
            + b(&f.velocity)
            + b(&f.velocity_half)
            + b(&f.acceleration)
            + b(&f.density)
            + b(&f.pressure)
            + b(&f.kernel_sum)
            + b(&f.strain_rate)
            + b(&f.id)
            + b(&f.inverse_density)
            + f.neighbours.heap_bytes();
        let walls = b(&w.position)
            + b(&w.density)
            + b(&w.inverse_density)
            + b(&w.pressure)
            + b(&w.nearest_fluid)
            + b(&w.part)
            + b(&w.normal)
            + b(&w.area)
            + b(&w.layer);
        let vec = size_of::<Vector<D>>();
        let loads = sim.loads();
        let per_point = 4 + 2 + 8 + 2 * vec + 3 * 8 + (2 * loads.smoothing_steps() + 1) * 8;
        let reachable = fluid + walls + loads.len() * per_point;

        let (n, nw) = (f.position.len(), w.position.len());
        let scratch = n * (vec + 8 + size_of::<Tensor<D>>() + 4 + 4 + 8) + nw * 8;
        // The cell grids are counted exactly by `grid_bytes`; the k-d trees are estimated.
        let search = match sim.params().neighbour_backend {
            NeighbourBackend::CellGrid => 0,
            // ImmutableKdTree<f64, D>: D coordinates + u32 item per point, plus the fluid
            // tree's scratch copy of the positions.
            NeighbourBackend::KdTree => (n + nw) * (vec + 4) + n * vec,
        };
        SolverBytes {
            reachable,
            private: scratch + sim.grid_bytes() + search + sim.sweep_buffer_bytes(),
        }
    }
}

// ----- output -----

fn print_header() {
    println!(
        "{:<8} {:<6} {:>3} {:>8} {:>8} {:>5} {:>7} {:>8} {:>8} {:>8} {:>8} | {:>4} {:>4} {:>4} {:>4} {:>4} {:>4} | {:>6} {:>7} {:>4} {:>5} {:>8}",
        "case", "search", "thr", "particles", "fluid", "steps", "wall s", "Mpst/s", "fluid", "median", "best",
        "nbr", "dens", "forc", "intg", "load", "oth", "B/part", "peak MB", "cpu", "load", "wall/sim"
    );
}

fn print_row(r: &BenchRow) {
    let pct = |x: f64| format!("{:.0}%", 100.0 * x);
    println!(
        "{:<8} {:<6} {:>3} {:>8} {:>8} {:>5} {:>7.2} {:>8.3} {:>8.3} {:>8.3} {:>8.3} | {:>4} {:>4} {:>4} {:>4} {:>4} {:>4} | {:>6.0} {:>7.0} {:>4} {:>5.2} {:>8.1}",
        r.case,
        r.backend,
        r.threads,
        r.particles,
        r.fluid_particles,
        r.steps,
        r.wall_s,
        r.particle_steps_per_s / 1e6,
        r.fluid_steps_per_s / 1e6,
        r.median_block_particle_steps_per_s / 1e6,
        r.best_block_particle_steps_per_s / 1e6,
        pct(r.shares[0]),
        pct(r.shares[1]),
        pct(r.shares[2]),
        pct(r.shares[3]),
        pct(r.shares[4]),
        pct(r.shares[5]),
        r.bytes_per_particle,
        r.peak_rss_mb,
        pct(r.cpu_util),
        r.load_avg,
        r.wall_s_per_simulated_s,
    );
}

fn verdict(ok: bool) -> &'static str {
    if ok {
        "PASS"
    } else {
        "FAIL"
    }
}

/// Prints the project's throughput and memory targets as measured (default backend, most threads).
pub fn print_checks(rows: &[BenchRow], quick: bool) {
    let default = backend_name(SphParams::default().neighbour_backend);
    let max_threads = rows.iter().map(|r| r.threads).max().unwrap_or(1);
    let find = |case: &str, threads: usize| {
        rows.iter()
            .find(|r| r.case == case && r.backend == default && r.threads == threads)
    };
    println!("Columns: Mpst/s = 10⁶ (fluid + wall) particle-steps/s; fluid = fluid only; median / best = the median / fastest of {BLOCKS} blocks; shares of wall time; B/part = solver bytes per particle (arrays + estimated private buffers); peak MB = VmHWM during the case (incl. process baseline); cpu = CPU time / (wall × threads); load = 1-min load average.");
    println!("Throughput targets ({default} backend, {max_threads} threads; measured, not a pass condition of this command):");
    let line = |label: String, value: String, ok: Option<bool>| {
        let v = ok.map_or("n/a ", verdict);
        println!("  {v}  {label:<52} {value}");
    };
    for (case, target) in [
        ("2d-20k", 5e6),
        ("2d-80k", 5e6),
        ("3d-100k", 8e5),
        ("3d-500k", 8e5),
    ] {
        match find(case, max_threads) {
            Some(r) => line(
                format!("throughput {case} ≥ {:.1e} particle-steps/s", target),
                format!("{:.3e}", r.particle_steps_per_s),
                Some(r.particle_steps_per_s >= target),
            ),
            None if !quick => line(format!("throughput {case}"), "not run".into(), None),
            None => {}
        }
    }
    for r in rows
        .iter()
        .filter(|r| r.dim == 3 && r.backend == default && r.threads == max_threads)
    {
        line(
            format!("memory {} ≤ 1024 bytes/particle", r.case),
            format!(
                "{:.0} B (RSS growth {:.0} B)",
                r.bytes_per_particle, r.rss_bytes_per_particle
            ),
            Some(r.bytes_per_particle <= 1024.0),
        );
    }
    // Flat cost per particle-step, within one dimension (a 3D particle has ~3.5× the
    // neighbours of a 2D one, so 2D and 3D costs are not comparable).
    for (small, large) in [("2d-20k", "2d-80k"), ("3d-100k", "3d-500k")] {
        let label = format!("cost per particle-step {large} / {small} ≤ 1.25");
        match (find(small, max_threads), find(large, max_threads)) {
            (Some(a), Some(b)) => {
                let ratio = a.particle_steps_per_s / b.particle_steps_per_s;
                line(label, format!("{ratio:.2}"), Some(ratio <= 1.25));
            }
            _ if !quick => line(label, "not run".into(), None),
            _ => {}
        }
    }
    if let (Some(a), Some(b)) = (find("2d-20k", max_threads), find("3d-500k", max_threads)) {
        let ratio = a.particle_steps_per_s / b.particle_steps_per_s;
        println!("  info  cost per particle-step 3d-500k / 2d-20k (across dimensions): {ratio:.2}");
    }
    // The same targets on the median block: what a run reads when a slow spell of the host
    // falls on a few blocks only.
    let median: Vec<String> = ["2d-20k", "2d-80k", "3d-100k", "3d-500k"]
        .iter()
        .filter_map(|case| {
            find(case, max_threads)
                .map(|r| format!("{case} {:.2e}", r.median_block_particle_steps_per_s))
        })
        .collect();
    if !median.is_empty() {
        let speedup = match (find("2d-80k", 1), find("2d-80k", 2)) {
            (Some(a), Some(b)) => format!(
                "; speed-up at 80k {:.2}×",
                b.median_block_particle_steps_per_s / a.median_block_particle_steps_per_s
            ),
            _ => String::new(),
        };
        println!(
            "  info  median block (particle-steps/s): {}{speedup}",
            median.join(", ")
        );
    }
    let label = "2-thread speed-up on 2d-80k ≥ 1.7×".to_string();
    match (find("2d-80k", 1), find("2d-80k", 2)) {
        (Some(a), Some(b)) => {
            let speedup = b.particle_steps_per_s / a.particle_steps_per_s;
            line(label, format!("{speedup:.2}×"), Some(speedup >= 1.7));
        }
        _ if !quick => line(label, "needs --threads with 1 and 2".into(), None),
        _ => {}
    }
    let machine = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1) as f64;
    let busy = rows
        .iter()
        .filter(|r| r.cpu_util < 0.85 || r.load_avg > machine + 0.5)
        .count();
    if busy > 0 {
        let max_load = rows.iter().map(|r| r.load_avg).fold(0.0, f64::max);
        println!(
            "  WARNING: {busy} of {} runs had CPU utilisation < 85 % or a load average above the \
             {machine} cores (up to {max_load:.2}): other processes took CPU time, these figures \
             understate the real throughput (the 1-thread particle_steps_per_cpu_s column of \
             bench.csv estimates it). Re-run on an idle machine.",
            rows.len()
        );
    }
}

// ----- process measurements -----

/// A `/proc/self/status` field in KiB (VmRSS, VmHWM).
fn proc_status_kib(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    line[key.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()
}

/// Resets VmHWM to the current RSS (Linux ≥ 4.0); harmless where unsupported.
fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// User + system CPU time of the process (s), from `/proc/self/stat` (clock ticks of 1/100 s).
fn process_cpu_s() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the command name (which may hold spaces): state is field 3, utime 14.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| {
        f.get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(f64::NAN)
    };
    (ticks(11) + ticks(12)) / 100.0
}

fn load_avg_line() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "n/a".into())
}

fn load_avg_1m() -> f64 {
    load_avg_line()
        .split_whitespace()
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(f64::NAN)
}

/// Package version plus `git describe --always --dirty` of the source tree, when available.
fn version_string() -> String {
    let mut v = env!("CARGO_PKG_VERSION").to_string();
    let git = std::process::Command::new("git")
        .args(["describe", "--always", "--dirty"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output();
    if let Ok(out) = git {
        let d = String::from_utf8_lossy(&out.stdout).trim().to_string();
        if out.status.success() && !d.is_empty() {
            let _ = write!(v, "+{d}");
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn micro_bench_writes_csv() {
        let case = BenchCase {
            name: "micro",
            tank: BenchTank::PaperRect2,
            dx: 0.04,
            steps: 50,
            kdtree: false,
        };
        let out = std::env::temp_dir().join(format!("slosh-bench-test-{}", std::process::id()));
        // Two pools taking turns block by block: one row each, all timed steps counted.
        let config = BenchConfig {
            threads: vec![2, 1],
            modern: false,
            riemann: false,
            h_over_dx: None,
            verbose: false,
        };
        let rows = run_bench(&[case], &config, &out).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].threads, 2);
        assert_eq!(rows[1].threads, 1);
        for r in &rows {
            assert_eq!(r.steps, 50);
            assert!(r.wall_s > 0.0 && r.best_block_particle_steps_per_s >= r.particle_steps_per_s);
            assert!(
                r.median_block_particle_steps_per_s > 0.0
                    && r.median_block_particle_steps_per_s <= r.best_block_particle_steps_per_s
            );
            assert!(r.shares.iter().sum::<f64>() <= 1.0 + 1e-9);
        }
        let text = std::fs::read_to_string(out.join("bench.csv")).unwrap();
        let _ = std::fs::remove_dir_all(&out);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        let header: Vec<&str> = lines[0].split(',').collect();
        let row: Vec<&str> = lines[2].split(',').collect();
        assert_eq!(header.len(), row.len());
        let col = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
        assert_eq!(col("case"), "micro");
        assert_eq!(col("dim"), "2");
        assert_eq!(col("threads"), "1");
        assert_eq!(col("steps"), "50");
        assert!(
            col("particles").parse::<usize>().unwrap()
                > col("fluid_particles").parse::<usize>().unwrap()
        );
        assert!(col("particle_steps_per_s").parse::<f64>().unwrap() > 0.0);
        assert!(col("bytes_per_particle").parse::<f64>().unwrap() > 100.0);
        assert_eq!(col("scheme"), "paper");
        assert_eq!(col("h_over_dx"), "1.3");
        // The modern preset times too, here with the kernel width given.
        let modern = BenchConfig {
            threads: vec![1],
            modern: true,
            riemann: false,
            h_over_dx: Some(1.5),
            verbose: false,
        };
        let case = BenchCase {
            name: "micro",
            tank: BenchTank::PaperRect2,
            dx: 0.04,
            steps: 10,
            kdtree: false,
        };
        let rows = run_bench(&[case], &modern, &out).unwrap();
        let _ = std::fs::remove_dir_all(&out);
        assert_eq!(rows[0].scheme, "modern");
        assert_eq!(rows[0].h_over_dx, 1.5);
        assert!(rows[0].particle_steps_per_s > 0.0);
    }

    #[test]
    fn case_filter_keeps_named_cases_and_rejects_unknown_ones() {
        let names = vec!["2d-80k".to_string(), "3d-100k".to_string()];
        let picked = select_cases(false, Some(&names)).unwrap();
        let picked: Vec<&str> = picked.iter().map(|c| c.name).collect();
        assert_eq!(picked, ["2d-80k", "3d-100k"]);
        let err = select_cases(true, Some(&["2d-80k".to_string()])).unwrap_err();
        let text = format!("{err}");
        assert!(
            text.contains("2d-80k") && text.contains("2d-20k, 3d-100k"),
            "{text}"
        );
        assert_eq!(select_cases(true, None).unwrap().len(), 2);
    }
}
