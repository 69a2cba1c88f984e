//! Running one case: claim the run folder, fit the tank to the lattice, build the particles,
//! run them through the time loop of `slosh-run` with the run's files as its observer, and
//! write the summary, the roof files, the input spectrum, the script's `post(run)` outputs and
//! the plots (the files are listed in `docs/formats.md`).

use crate::build;
use crate::files::{write_plots, RunFiles};
use crate::progress::Progress;
use crate::stop::{Interrupted, RunStop};
use crate::summary::{Summary, TheoryNumbers};
use anyhow::Result;
use slosh_core::{Simulation, SoundSpeedRule, SphParams, Vector};
use slosh_io::FrameSeries;
use slosh_run::{
    Gauge, LoadFilter, LoadPeak, RoofLoadSummary, RoofTank, RunPlan, RunResult, RunStatus,
    StepError, StopRequest,
};
use slosh_script::{Case, SectionOutlineSpec, TankSpec};
use std::path::PathBuf;
use std::time::Instant;

/// The end of the refusal to resume a run whose checkpoint is of its end (a run killed while
/// it wrote its summary and plots); a sweep recognises it and runs the case again.
pub const NOTHING_TO_RESUME: &str = "nothing to resume";

/// How to run a case.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder.
    pub out_dir: PathBuf,
    /// Show progress: a bar when stderr is a terminal, otherwise a line every 10 % of the
    /// simulated time (or 30 s of wall time).
    pub progress: bool,
    /// Print the particle counts and the result line.
    pub verbose: bool,
    /// Write plots (PNG + SVG) at the end.
    pub plots: bool,
    /// Memory the run may use (bytes); `None` = what the machine has available.
    pub max_memory_bytes: Option<f64>,
    /// Checkpoints: what the run was started with, and the wall time between two
    /// checkpoints (besides those when it is interrupted and at its end); `None`: none.
    pub checkpoints: Option<(crate::checkpoint::RunRecord, std::time::Duration)>,
    /// Continue the interrupted run in `out_dir` from its checkpoint.
    pub resume: bool,
}

/// Runs a case into the folder `opts.out_dir` to the end (or to a blow-up or a stop, keeping
/// what was written) and returns its summary. `stop` is asked after every step: `Some(code)`
/// ends the run as an interruption by signal `code` ([`Interrupted`]; its outputs are written
/// up to that step, with a checkpoint when checkpoints are on). The command line passes the
/// signals its handlers received, the Python package Ctrl-C; `SLOSH_TEST_STOP_AT`
/// ([`crate::TEST_STOP_AT_ENV`]) adds a stop at a simulated time.
pub fn run_case_with_stop(
    mut case: Case,
    opts: &RunOptions,
    stop: &mut dyn StopRequest,
) -> Result<Summary> {
    // Held until the run's outputs are complete.
    let folder = if opts.resume {
        crate::run_folder::RunFolder::claim_to_resume(&opts.out_dir, &case.name, &case.script)?
    } else {
        crate::run_folder::RunFolder::claim(&opts.out_dir, &case.name, &case.script)?
    };
    let result = build_and_run(&mut case, opts, stop);
    match result {
        Err(e) => match folder.mark_failed_if_running(&format!("{e:#}")) {
            Ok(()) => Err(e),
            Err(summary_error) => Err(e.context(format!("{summary_error:#}"))),
        },
        ok => ok,
    }
}

/// Fits, builds and runs a claimed case.
fn build_and_run(
    case: &mut Case,
    opts: &RunOptions,
    stop: &mut dyn StopRequest,
) -> Result<Summary> {
    let fit = build::fit_to_lattice(&case.tank, case.dx)?;
    crate::memory::check_memory_budget(
        &fit.tank,
        fit.dx,
        case.sph.wall_layers(),
        opts.max_memory_bytes,
    )?;
    let mut sph = case.sph.clone();
    if let SoundSpeedRule::FromCase { coefficient, .. } = sph.sound_speed {
        let flow_speed = case.excitation_speed()?;
        sph.sound_speed = SoundSpeedRule::FromCase {
            coefficient,
            flow_speed,
        };
    }
    match case.dim() {
        2 => {
            let setup = build::build_2d(&fit.tank, fit.dx, sph.wall_layers())?;
            let mut sim = Simulation::<2>::new(setup, sph)?;
            attach_backend(&mut sim)?;
            run_built(sim, case, fit, opts, stop)
        }
        _ => {
            let setup = build::build_3d(&fit.tank, fit.dx, sph.wall_layers(), &case.sandbox)?;
            let mut sim = Simulation::<3>::new(setup, sph)?;
            attach_backend(&mut sim)?;
            run_built(sim, case, fit, opts, stop)
        }
    }
}

/// Hands the step to the GPU when the run's numerics ask for it (`backend: "gpu"` or
/// `"gpu_f32"`).
fn attach_backend<const D: usize>(sim: &mut Simulation<D>) -> Result<()> {
    if sim.params().backend == slosh_core::Backend::Cpu {
        return Ok(());
    }
    #[cfg(feature = "gpu")]
    {
        if let Some(precision) = slosh_gpu::Precision::of(sim.params().backend) {
            slosh_gpu::attach(sim, precision)?;
        }
        Ok(())
    }
    #[cfg(not(feature = "gpu"))]
    {
        anyhow::bail!(
            "this slosh was built without the GPU backend (cargo feature \"gpu\" of slosh-case); \
             build it with the default features, or run on the CPU (backend \"cpu\")"
        )
    }
}

/// Bytes of one particle in a frame file (positions, velocity, pressure, density, kind, part,
/// id, as written by `slosh_io::FrameSeries`), for the size warning.
const FRAME_BYTES_PER_PARTICLE: f64 = 80.0;
/// Frame volume (bytes) above which a run is warned.
const FRAME_VOLUME_WARNING: f64 = 2.0e9;

/// A warning when the frames of a run would fill more than [`FRAME_VOLUME_WARNING`] bytes.
fn frame_volume_warning(duration: f64, frame_interval: f64, particles: usize) -> Option<String> {
    let frames = (duration / frame_interval).floor() + 1.0;
    let bytes = frames * particles as f64 * FRAME_BYTES_PER_PARTICLE;
    (bytes > FRAME_VOLUME_WARNING).then(|| {
        format!(
            "the frames of this run (one every {frame_interval:.3e} s, ≈ {frames:.0} frames \
             of {particles} particles) fill ≈ {:.1} GB; raise frame_interval (0 = no frames)",
            bytes / 1e9
        )
    })
}

/// The tank as simulated: the fitted dimensions with the fill depth the lattice holds
/// (whole rows of dx; the paper layout keeps its nominal depth, see `Layout::Paper`).
fn simulated_tank<const D: usize>(sim: &Simulation<D>, fit: &mut build::FittedTank) -> TankSpec {
    let (lo, _) = sim.interior_bounds();
    let held = sim.fill_level() - lo[D - 1];
    let mut tank = fit.tank.clone();
    let paper_layout = matches!(&tank, TankSpec::Rect { layout, .. } if layout == "paper");
    if !paper_layout {
        let depth = match &mut tank {
            TankSpec::Rect { depth, .. }
            | TankSpec::Section { depth, .. }
            | TankSpec::Sphere { depth, .. }
            | TankSpec::Cylinder { depth, .. }
            | TankSpec::Box { depth, .. }
            | TankSpec::Mesh { depth, .. } => depth,
        };
        if (held - *depth).abs() > 1e-9 * depth.max(1.0) {
            fit.notes.push(format!(
                "fill depth {} m → {held} m (whole rows of dx = {} m)",
                *depth,
                sim.spacing()
            ));
            *depth = held;
        }
    }
    tank
}

/// The left and right wall gauges of a tank whose walls need not be vertical (a polygon or
/// circle section, a sphere): on the x axis through the centre, one lattice spacing inside the
/// liquid's extent at mid-depth (the gauge's reference height), where the vertical line holds
/// liquid from mid-depth up.
/// Refuses a gauge of the script whose horizontal position is not a finite point over the
/// tank's interior: its column would be NaN for the whole run.
fn check_gauges_inside<const D: usize>(
    gauges: &[slosh_script::GaugeSpec],
    sim: &Simulation<D>,
) -> Result<()> {
    let (lo, hi) = sim.interior_bounds();
    for g in gauges {
        for (axis, &x) in g.horizontal.iter().enumerate().take(D - 1) {
            if !(x.is_finite() && lo[axis] <= x && x <= hi[axis]) {
                anyhow::bail!(
                    "gauge \"{}\": {} = {x} m is outside the tank, whose interior spans {} = \
                     {:.4} to {:.4} m; place the gauge over the liquid",
                    g.name,
                    ["x", "y"][axis],
                    ["x", "y"][axis],
                    lo[axis],
                    hi[axis]
                );
            }
        }
    }
    Ok(())
}

fn liquid_edge_gauges<const D: usize>(sim: &Simulation<D>) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = sim.interior_bounds();
    let dx = sim.spacing();
    let floor = lo[D - 1];
    let mid_depth = floor + 0.5 * (sim.fill_level() - floor);
    let on_axis = |x: &Vector<D>| (1..D - 1).all(|k| (x[k] - 0.5 * (lo[k] + hi[k])).abs() <= dx);
    let (mut left, mut right) = (hi[0], lo[0]);
    for x in &sim.fluid().position {
        if (x[D - 1] - mid_depth).abs() <= dx && on_axis(x) {
            left = left.min(x[0]);
            right = right.max(x[0]);
        }
    }
    let (mut left_gauge, mut right_gauge) = slosh_run::wall_gauges(sim);
    if left <= right {
        left_gauge[0] = left + dx;
        right_gauge[0] = right - dx;
    }
    (left_gauge, right_gauge)
}

fn theory_numbers(tank: &TankSpec, gravity: f64) -> TheoryNumbers {
    use slosh_theory::natural;
    let omega_1 = match tank {
        TankSpec::Rect { width, depth, .. } => {
            natural::rectangular_omega(*width, *depth, gravity, 1)
        }
        // a circle: its own first antisymmetric mode (potential-flow Ritz value, 1.3557 g/R
        // at half fill: Budiansky 1960, McIver 1989)
        TankSpec::Section {
            outline: SectionOutlineSpec::Circle { radius },
            depth,
            ..
        } if *depth > 0.0 && *depth < 2.0 * radius => {
            let lambda = slosh_theory::section_modes::circle_eigenvalue(depth / radius);
            (lambda * gravity / radius).sqrt()
        }
        // an estimate: the rectangle of the section's (mesh's) width and the liquid depth
        TankSpec::Section { depth, .. } | TankSpec::Mesh { depth, .. } => {
            natural::rectangular_omega(tank.horizontal_size(), *depth, gravity, 1)
        }
        TankSpec::Box { length, depth, .. } => {
            natural::rectangular_omega(*length, *depth, gravity, 1)
        }
        TankSpec::Cylinder { radius, depth, .. } => {
            natural::cylinder_omega(*radius, *depth, gravity, 1, 1)
        }
        // an estimate: the upright cylinder of the sphere's radius and the liquid depth
        TankSpec::Sphere { radius, depth, .. } => {
            natural::cylinder_omega(*radius, *depth, gravity, 1, 1)
        }
    };
    TheoryNumbers {
        omega_1,
        period_1: 2.0 * std::f64::consts::PI / omega_1,
    }
}

/// Whether `error` (or an error it wraps) is a file operation that failed: an output of the
/// run that could not be written, as opposed to a refused resume or a bad state.
fn is_output_failure(error: &(dyn std::error::Error + 'static)) -> bool {
    let mut next = Some(error);
    while let Some(e) = next {
        if e.is::<std::io::Error>() || e.is::<slosh_io::IoError>() {
            return true;
        }
        next = e.source();
    }
    false
}

/// The run's failure as the front ends report it: the solver's or the script's own error,
/// or [`Interrupted`] for a signal.
fn failure_of(status: RunStatus) -> Option<anyhow::Error> {
    match status {
        RunStatus::Finished => None,
        RunStatus::Interrupted { code } => Some(Interrupted { signal: code }.into()),
        RunStatus::Failed(StepError::Motion { error, .. }) => Some(anyhow::anyhow!(error)),
        RunStatus::Failed(e) => Some(e.into()),
    }
}

fn run_built<const D: usize>(
    mut sim: Simulation<D>,
    case: &mut Case,
    mut fit: build::FittedTank,
    opts: &RunOptions,
    stop: &mut dyn StopRequest,
) -> Result<Summary> {
    for warning in &case.warnings {
        eprintln!("warning: {warning}");
    }
    let out = &opts.out_dir;
    let n_fluid0 = sim.fluid().position.len();
    let n_wall = sim.walls().position.len();
    let tank = simulated_tank(&sim, &mut fit);
    let numerics_warnings: Vec<String> = sim
        .sound_speed_choice()
        .compression_warning()
        .into_iter()
        .collect();
    for w in &numerics_warnings {
        eprintln!("warning: {w}");
    }
    // The input's warnings (printed above) and the numerics', in the summary.
    let mut warnings: Vec<String> = case
        .warnings
        .iter()
        .cloned()
        .chain(numerics_warnings)
        .collect();
    #[cfg(feature = "gpu")]
    if let Some(device) = sim
        .device_description()
        .filter(|d| d.contains(slosh_gpu::SOFTWARE_DEVICE))
    {
        let w = format!(
            "the GPU backend runs on {device}: Vulkan sees no GPU on this machine; the results \
             are those of the GPU step, but it runs slower than --backend cpu"
        );
        eprintln!("warning: {w}");
        warnings.push(w);
    }
    if opts.verbose {
        for note in &fit.notes {
            eprintln!("{}: lattice: {note}", case.name);
        }
        eprintln!(
            "{}: {}D, {} fluid + {} wall particles, dx = {} m, h = {:.4} m, c0 = {:.2} m/s",
            case.name,
            D,
            n_fluid0,
            n_wall,
            sim.spacing(),
            sim.smoothing_length(),
            sim.sound_speed()
        );
    }
    if case.excitation.turns() {
        if let Some(device) = sim.device_description() {
            anyhow::bail!(
                "{}: the script turns the tank (fn ground_rotation) and the run asks for the \
                 device backend ({device}); a turning tank runs on the CPU backend only: run \
                 it with --backend cpu",
                case.name
            );
        }
        // The default pivot: the centre of the tank's base.
        let (low, high) = sim.interior_bounds();
        let mut base = [0.0; 3];
        for (k, b) in base.iter_mut().enumerate().take(D - 1) {
            *b = 0.5 * (low[k] + high[k]);
        }
        base[2] = low[D - 1];
        case.excitation.set_default_pivot(base);
    }
    if (case.excitation.has_ground_accel() || case.excitation.turns())
        && case.run.duration <= case.run.settle
    {
        // The excitation starts after the settling time: this run never shakes the tank.
        let w = format!(
            "the run ends at {} s, before the excitation starts (settle = {} s): the tank is \
             never shaken; give a duration longer than settle (duration counts the settling)",
            case.run.duration, case.run.settle
        );
        eprintln!("warning: {w}");
        warnings.push(w);
    }
    let mut frames = if case.run.frame_interval > 0.0 {
        // A frame is written at most once per step; the step is about C h / c0.
        let step = sim.params().cfl_number * sim.smoothing_length() / sim.sound_speed();
        let interval = case.run.frame_interval.max(step);
        if let Some(w) = frame_volume_warning(case.run.duration, interval, n_fluid0 + n_wall) {
            eprintln!("warning: {w}");
            warnings.push(w);
        }
        Some(FrameSeries::new(out.join("frames")))
    } else {
        None
    };
    // Resuming: the state of the interrupted run, its frames and its earlier interruptions.
    let mut earlier_rows = Vec::new();
    let mut resumes = Vec::new();
    let resume_state = if opts.resume {
        let file = crate::checkpoint::read_state::<D>(out)?;
        if file.state.sim.time >= case.run.duration - 1e-9 {
            anyhow::bail!(
                "the run in {} is complete (t = {} s of {} s): {NOTHING_TO_RESUME}",
                out.display(),
                file.state.sim.time,
                case.run.duration
            );
        }
        if let Some(f) = frames.as_mut() {
            *f = FrameSeries::continuing(out.join("frames"), &file.frames);
        }
        let columns = &file.state.series;
        let n_rows = columns.first().map_or(0, Vec::len);
        earlier_rows = (0..n_rows)
            .map(|r| columns.iter().map(|c| c[r]).collect())
            .collect();
        resumes = file.resumes;
        resumes.push(crate::checkpoint::ResumeRecord {
            from_time: file.state.sim.time,
            from_step: file.state.sim.step,
            resumed_at_unix_s: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
        });
        if opts.verbose {
            eprintln!(
                "{}: resuming at t = {:.4} s (step {})",
                case.name, file.state.sim.time, file.state.sim.step
            );
        }
        Some(file.state)
    } else {
        None
    };
    let checkpoints = match &opts.checkpoints {
        Some((record, every)) => {
            let mut writer = crate::checkpoint::CheckpointWriter::start(out, record, D, *every)?;
            writer.resumes = resumes.clone();
            Some(writer)
        }
        None => None,
    };
    let wall_gauges = match &case.tank {
        TankSpec::Section { .. } | TankSpec::Sphere { .. } | TankSpec::Mesh { .. } => {
            Some(liquid_edge_gauges(&sim))
        }
        _ => None,
    };
    check_gauges_inside(&case.gauges, &sim)?;
    let settle = case.run.settle;
    let duration = case.run.duration;
    let theory = theory_numbers(&tank, sim.params().gravity);
    let plan = RunPlan {
        settle,
        duration,
        output_interval: case.run.output_interval,
        frame_interval: case.run.frame_interval,
        gauges: case
            .gauges
            .iter()
            .map(|g| Gauge {
                name: g.name.clone(),
                horizontal: g.horizontal.clone(),
            })
            .collect(),
        // The filter's default cut-off follows the tank as the script gave it.
        load_filter: LoadFilter::new(
            case.run.load_filter_hz,
            theory_numbers(&case.tank, sim.params().gravity).omega_1,
        ),
        roof_tank: roof_tank(&tank, sim.params(), theory.omega_1),
        wall_gauges,
        roof_load: slosh_run::RoofLoadPlan {
            sensors: case.pressure_sensors.clone(),
            damping_ratio: case.run.roof_damping,
            design_periods: case.run.roof_periods.clone(),
        },
        turns: case.excitation.turns(),
    };
    // Roof loads: the clearance against the particle spacing (the roof's reach through the
    // kernel shortens the clearance the roof load sees).
    let roof_part = sim.part_names().iter().position(|n| n == "roof");
    if roof_part.is_some_and(|r| sim.walls().part.iter().any(|&p| p as usize == r)) {
        if let Some(w) = slosh_run::roof_load::clearance_resolution_warning(
            plan.roof_tank.freeboard,
            sim.spacing(),
        ) {
            eprintln!("warning: {w}");
            warnings.push(w);
        }
    }
    let mut files = RunFiles {
        out: out.clone(),
        series: None,
        frames,
        progress: Progress::start(opts.progress, &case.name, duration),
        started: Instant::now(),
        checkpoints,
        earlier_rows,
        checkpoint_error: None,
        time_reached: std::rc::Rc::new(std::cell::Cell::new(f64::NEG_INFINITY)),
    };
    let mut stop = RunStop::from_env(stop, std::rc::Rc::clone(&files.time_reached))?;
    let resumed_from = resume_state.as_ref().map(|s| s.sim.time);
    let mut result: RunResult<D> = slosh_run::run_case_from(
        &mut sim,
        &plan,
        &mut case.excitation,
        &mut files,
        &mut stop,
        resume_state,
    )
    .map_err(|e| {
        if !is_output_failure(e.as_ref()) {
            return anyhow::anyhow!(e);
        }
        // An output that could not be written (a full disk): what is left and how to go on.
        let kept = match files
            .checkpoints
            .as_ref()
            .and_then(|c| c.last_time)
            .or(resumed_from)
        {
            Some(t) if opts.checkpoints.is_some() => format!(
                "the last checkpoint (t = {t:.4} s) is kept: make room and continue with \
                 `slosh resume {}`",
                out.display()
            ),
            _ => "no checkpoint was written: make room and run the case again".to_string(),
        };
        anyhow::anyhow!(e).context(format!(
            "the run stopped at t = {:.4} s because an output could not be written; \
             series.csv ends at its last whole row; {kept}",
            files.time_reached.get().max(0.0)
        ))
    })?;
    let failure = failure_of(std::mem::replace(&mut result.status, RunStatus::Finished));
    let (stats, peaks, wall_time) = (result.stats, result.peaks, result.wall_time_s);
    let measured_compression = result.hydrostatic_compression;
    let roof_contact = result.roof_contact;
    let particles = (n_fluid0 + n_wall) as f64;
    let steps = result.steps;
    let choice = sim.sound_speed_choice().clone();
    if choice.compression_warning().is_none()
        && measured_compression > slosh_core::sound_speed::COMPRESSION_WARNING
    {
        let w = format!(
            "the still liquid was compressed by {:.2} % of its volume at the end of settling \
             (c0 = {:.1} m/s, {}); raise the sound speed (sound_speed_coefficient)",
            100.0 * measured_compression,
            choice.sound_speed,
            choice.rule
        );
        eprintln!("warning: {w}");
        warnings.push(w);
    }
    if let Some(w) = stats.mach_warning(choice.sound_speed) {
        eprintln!("warning: {w}");
        warnings.push(w);
    }
    let mut summary = Summary {
        version: env!("CARGO_PKG_VERSION").to_string(),
        case: case.name.clone(),
        script: case.script.display().to_string(),
        status: match &failure {
            None => "completed",
            Some(e) if e.is::<Interrupted>() => "interrupted",
            Some(_) => "failed",
        }
        .into(),
        error: failure.as_ref().map(|e| format!("{e:#}")),
        dim: D,
        particles_fluid: n_fluid0,
        particles_wall: n_wall,
        steps,
        sim_time: result.sim_time,
        settle,
        duration,
        dt_min: if steps > 0 { stats.dt_min } else { 0.0 },
        dt_max: stats.dt_max,
        dt_bound_min: if steps > 0 { stats.dt_bound_min } else { 0.0 },
        steps_above_dt_bound: stats.steps_above_bound,
        wall_time_s: wall_time,
        particle_steps_per_s: particles * steps as f64 / wall_time.max(1e-9),
        fluid_particle_steps_per_s: n_fluid0 as f64 * steps as f64 / wall_time.max(1e-9),
        threads: rayon::current_num_threads(),
        max_roof_force_up: peaks.max_roof_force_up,
        t_max_roof_force_up: peaks.t_max_roof_force_up,
        max_roof_p: peaks.max_roof_p,
        t_max_roof_p: peaks.t_max_roof_p,
        max_eta_left: result.max_of("eta_left"),
        min_eta_left: result.min_of("eta_left"),
        max_eta_right: result.max_of("eta_right"),
        max_abs_base_shear_x: peaks.max_abs_base_shear_x,
        lost_particles: result.lost_particles,
        smoothing_length: sim.smoothing_length(),
        dx: sim.spacing(),
        sound_speed: sim.sound_speed(),
        av_sound_speed: sim.av_sound_speed(),
        scheme: case.scheme.clone(),
        parameters: case
            .params
            .iter()
            .map(|p| (p.name.clone(), p.value.clone()))
            .collect(),
        numerics: sim.params().clone(),
        device: sim.device_description().unwrap_or_else(|| "cpu".into()),
        theory,
        tank,
        tank_requested: case.tank.clone(),
        lattice_notes: fit.notes.clone(),
        parts: sim
            .part_names()
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let walls = sim.walls();
                let area = (walls.part.iter().zip(&walls.area))
                    .filter(|(&p, _)| p as usize == k)
                    .map(|(_, a)| a)
                    .sum();
                (name.clone(), area)
            })
            .collect(),
        still_level: sim.still_level(),
        eos_b: choice.eos_stiffness,
        sound_speed_rule: choice.rule.clone(),
        reference_depth: choice.reference_depth,
        reference_flow_speed: choice.reference_flow_speed,
        hydrostatic_compression_predicted: choice.compression_fraction,
        hydrostatic_compression: measured_compression,
        max_mach: stats.max_mach,
        steps_above_mach_limit: stats.steps_above_mach_limit,
        warnings,
        output_errors: Vec::new(),
        impacts: Vec::new(),
        roof_load: result.roof_load.as_ref().map(RoofLoadSummary::of),
        kurihara_at_max: 0.0,
        malhotra_at_max: 0.0,
        motions: case.motions.clone(),
        input_spectrum: None,
        post: Vec::new(),
        post_error: None,
        load_filter: result.load_filter.clone(),
        max_abs_base_shear_x_lp: peak_lp(&result.load_peaks, "base_shear_x"),
        max_roof_force_up_lp: result.max_of("roof_force_up_lp").max(0.0),
        load_peaks: result.load_peaks.clone(),
        roof_contact,
        roof_note: roof_note(result.roof.has_roof(), roof_contact),
        resumes: files
            .checkpoints
            .as_ref()
            .map(|c| c.resumes.clone())
            .unwrap_or_default(),
        checkpoints_written: files.checkpoints.as_ref().map_or(0, |c| c.written),
        checkpoint_error: files.checkpoint_error.clone(),
    };
    if result.roof.has_roof() {
        summary.impacts = std::mem::take(&mut result.impacts);
        if let Some(top) = summary
            .impacts
            .iter()
            .max_by(|a, b| a.p_max_sph.total_cmp(&b.p_max_sph))
        {
            summary.kurihara_at_max = top.p_kurihara;
            summary.malhotra_at_max = top.p_malhotra;
        }
        if let Some(load) = &result.roof_load {
            if let Err(e) =
                crate::roof_files::write_roof_spectrum(load, out, D, opts.plots && roof_contact)
            {
                summary
                    .output_errors
                    .push(format!("roof load spectrum: {e:#}"));
            }
        }
        if let Err(e) =
            crate::roof_files::write_roof_pressure(&result.roof, out, opts.plots && roof_contact)
        {
            summary
                .output_errors
                .push(format!("roof pressure map: {e:#}"));
        }
        if opts.plots && roof_contact && summary.max_roof_p > 0.0 {
            if let Err(e) =
                crate::roof_files::write_fig7(&result.roof, out, summary.t_max_roof_p, settle)
            {
                summary.output_errors.push(format!("Fig. 7 plots: {e:#}"));
            }
        }
    }
    if failure.is_none() {
        let max_eta = summary.max_eta_left.max(summary.max_eta_right);
        // The tank as simulated (fitted to the lattice): its size and freeboard.
        let simulated = summary.tank.clone();
        match crate::spectrum::write_case_input_spectrum(
            out,
            case,
            &simulated,
            summary.theory.period_1,
            max_eta,
        ) {
            Ok(s) => summary.input_spectrum = s,
            Err(e) => eprintln!("warning: input spectrum not written: {e:#}"),
        }
    }
    // Post-processing hook of the script (keeps the other outputs when it fails).
    let mut post_error = None;
    if case.excitation.has_post() {
        let mut data = crate::post::run_data(&summary, &result.columns, &result.series);
        data.maps
            .push(("roof_pressure".into(), result.roof.map_rows()));
        match case.excitation.post(&data) {
            Ok(result) => {
                summary.post = result.values.clone();
                if let Err(e) = crate::post::write_post_outputs(out, &result) {
                    summary
                        .output_errors
                        .push(format!("post(run) tables and plots: {e:#}"));
                }
            }
            Err(e) => {
                summary.post_error = Some(e.to_string());
                post_error = Some(e);
            }
        }
    }
    if opts.plots {
        if let Err(e) = write_plots(out, &result.columns, &result.series, D, &summary) {
            summary.output_errors.push(format!("plots: {e:#}"));
        }
    }
    // 2D: the fluid at the largest wave, whether or not the roof was struck
    if opts.plots {
        if let Some(frame) = &result.largest_wave_frame {
            if let Err(e) = crate::roof_files::write_frame_peak(&result.roof, out, frame, settle) {
                summary
                    .output_errors
                    .push(format!("largest-wave frame plot: {e:#}"));
            }
        }
    }
    slosh_io::write_ron(out.join("summary.ron"), &summary)?;
    if let Some(e) = failure {
        let how = match (e.is::<Interrupted>(), opts.checkpoints.is_some()) {
            (true, true) => format!(
                "; its checkpoint is kept: continue it with `slosh resume {}`",
                out.display()
            ),
            (true, false) => {
                "; it ran without checkpoints, so run the case again to redo it".to_string()
            }
            _ => String::new(),
        };
        return Err(e.context(format!(
            "the run stopped at t = {:.4} s; the outputs written so far are in {}{how}",
            sim.time(),
            out.display()
        )));
    }
    if !summary.output_errors.is_empty() {
        anyhow::bail!(
            "the run completed, but some outputs could not be written ({}); summary.ron and \
             series.csv are in {}",
            summary.output_errors.join("; "),
            out.display()
        );
    }
    if let Some(e) = post_error {
        return Err(anyhow::Error::new(e).context(format!(
            "post(run) failed; the run's other outputs are in {}",
            out.display()
        )));
    }
    if opts.verbose {
        eprintln!(
            "{}: {} steps in {:.1} s ({:.3e} particle-steps/s); max eta_left {:.4} m, max |base shear x| {:.1} {unit} ({:.1} {unit} low-pass {:.2} Hz), max roof p {:.1} Pa",
            case.name,
            steps,
            wall_time,
            summary.particle_steps_per_s,
            summary.max_eta_left,
            summary.max_abs_base_shear_x,
            summary.max_abs_base_shear_x_lp,
            summary.load_filter.cutoff_hz,
            summary.max_roof_p,
            unit = if D == 2 { "N/m" } else { "N" },
        );
        if let Some(note) = &summary.roof_note {
            eprintln!("{}: {note}", case.name);
        }
    }
    Ok(summary)
}

/// The filtered peak of `column` (0 when the run has no such column).
fn peak_lp(peaks: &[LoadPeak], column: &str) -> f64 {
    peaks
        .iter()
        .find(|p| p.column == column)
        .map_or(0.0, |p| p.max_abs_lp)
}

/// What the summary says when there are no roof plots.
fn roof_note(has_roof: bool, contact: bool) -> Option<String> {
    match (has_roof, contact) {
        (false, _) => Some("no roof: the tank is open, no roof loads or roof plots".into()),
        (true, false) => Some(
            "no roof contact: the liquid never touched the roof (no roof pressure above 1 Pa); \
             roof_force.png, roof_pressure.png and roof_pressure_map.png are not drawn"
                .into(),
        ),
        (true, true) => None,
    }
}

/// Kurihara's tank numbers from the script's tank: depth H, freeboard H′ at the wall,
/// half-width l (or radius), ω = the first sloshing mode.
fn roof_tank(tank: &TankSpec, params: &SphParams, omega_1: f64) -> RoofTank {
    let (depth, height, half_width) = match tank {
        TankSpec::Rect {
            width,
            height,
            depth,
            ..
        } => (*depth, *height, 0.5 * width),
        TankSpec::Section { outline, depth, .. } => {
            let (lo, hi) = outline.bounds();
            (*depth, hi[1] - lo[1], 0.5 * (hi[0] - lo[0]))
        }
        TankSpec::Sphere { radius, depth, .. } => (*depth, 2.0 * radius, *radius),
        // the freeboard up to the lowest corner of the roof part (or the top without a roof)
        TankSpec::Mesh { depth, extent, .. } => (
            *depth,
            extent.roof_base.unwrap_or(extent.max[2]),
            0.5 * (extent.max[0] - extent.min[0]),
        ),
        TankSpec::Cylinder {
            radius,
            height,
            depth,
            ..
        } => (*depth, *height, *radius),
        TankSpec::Box {
            length,
            height,
            depth,
            ..
        } => (*depth, *height, 0.5 * length),
    };
    RoofTank {
        density: params.rest_density,
        gravity: params.gravity,
        depth,
        freeboard: height - depth,
        half_width,
        omega: omega_1,
    }
}
