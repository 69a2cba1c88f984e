//! Running a case: the time loop, the measurements of every output interval, and the files
//! listed in the README, *Outputs* (`series.csv`, `summary.ron`, frames, plots).

use crate::build;
use crate::progress::Progress;
use anyhow::Result;
use serde::Serialize;
use slosh_core::{Simulation, SoundSpeedRule, SphParams, Vector};
use slosh_io::{FrameSeries, PlotSpec, PointArray, Series, SeriesWriter};
use slosh_run::{
    Gauge, HookError, LoadFilter, LoadPeak, Observer, RoofImpact, RoofTank, RunPlan, RunResult,
    RunStatus, StepError, StopRequest,
};
use slosh_script::{Case, ParamValue, TankSpec};
use std::path::{Path, PathBuf};
use std::time::Instant;

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

/// The summary written to `summary.ron` (the fields are listed in the README, *Outputs*). `Default` gives its layout with zeros
/// (a sweep names its `sweep.csv` columns from it before any case has run).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    /// Program version.
    pub version: String,
    /// Case name.
    pub case: String,
    /// Script file.
    pub script: String,
    /// "completed", "failed", or "interrupted" (SIGINT/SIGTERM: the outputs up to the step
    /// the signal came in).
    pub status: String,
    /// The error message when the run failed.
    pub error: Option<String>,
    /// Space dimension.
    pub dim: usize,
    /// Fluid particles at the start.
    pub particles_fluid: usize,
    /// Wall particles.
    pub particles_wall: usize,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached (s).
    pub sim_time: f64,
    /// Settling time (s).
    pub settle: f64,
    /// Requested duration (s).
    pub duration: f64,
    /// Smallest time step (s).
    pub dt_min: f64,
    /// Largest time step (s).
    pub dt_max: f64,
    /// Smallest CFL bound seen (s).
    pub dt_bound_min: f64,
    /// Steps whose fixed dt exceeded the bound.
    pub steps_above_dt_bound: u64,
    /// Wall-clock time of the time loop (s).
    pub wall_time_s: f64,
    /// (fluid + wall particles) × steps / wall time, the figure engineering SPH codes quote.
    pub particle_steps_per_s: f64,
    /// fluid particles × steps / wall time.
    pub fluid_particle_steps_per_s: f64,
    /// Worker threads.
    pub threads: usize,
    /// Largest upward roof force (N; 2D N/m), time-windowed pressures.
    pub max_roof_force_up: f64,
    /// Time of the largest upward roof force (s).
    pub t_max_roof_force_up: f64,
    /// Largest roof pressure (Pa), time-windowed.
    pub max_roof_p: f64,
    /// Time of the largest roof pressure (s).
    pub t_max_roof_p: f64,
    /// Largest elevation at the left wall (m), over the output rows.
    pub max_eta_left: f64,
    /// Lowest elevation at the left wall (m).
    pub min_eta_left: f64,
    /// Largest elevation at the right wall (m).
    pub max_eta_right: f64,
    /// Largest |base shear x| (N; 2D N/m), time-windowed.
    pub max_abs_base_shear_x: f64,
    /// Fluid particles no longer inside the tank at the end.
    pub lost_particles: usize,
    /// Smoothing length h (m).
    pub smoothing_length: f64,
    /// Lattice spacing dx (m).
    pub dx: f64,
    /// EOS sound speed c0 (m/s).
    pub sound_speed: f64,
    /// Sound speed of the artificial viscosity (m/s).
    pub av_sound_speed: f64,
    /// Scheme preset.
    pub scheme: String,
    /// Script parameters with the values used.
    pub parameters: Vec<(String, ParamValue)>,
    /// Solver parameters used.
    pub numerics: SphParams,
    /// The tank as simulated (dimensions fitted to the lattice, the fill depth it holds).
    pub tank: TankSpec,
    /// The tank as the script gave it.
    pub tank_requested: TankSpec,
    /// How the lattice changed the tank or dx (empty when it fits exactly).
    pub lattice_notes: Vec<String>,
    /// The tank's wall parts: name and the boundary area its particles stand for (m²; 2D m
    /// per m of depth), e.g. ("roof", 24.19) for the cone roof of a 24 m section.
    pub parts: Vec<(String, f64)>,
    /// Tait stiffness B used (Pa).
    pub eos_b: f64,
    /// The rule that chose c0 and B.
    pub sound_speed_rule: String,
    /// H_ref of the sound-speed rule: the largest liquid column the tank can hold (m).
    pub reference_depth: f64,
    /// U_ref of the sound-speed rule: half the peak-to-peak ground velocity (m/s).
    pub reference_flow_speed: f64,
    /// Compression of the still liquid under its own weight predicted by the Tait EOS
    /// (fraction of the depth).
    pub hydrostatic_compression_predicted: f64,
    /// Compression of the liquid measured when the excitation starts (at the end of the run
    /// when there is no settling): 1 − Σ(m/ρ)/V0 (fraction; with vertical walls, the drop of
    /// the still surface over the depth).
    pub hydrostatic_compression: f64,
    /// Largest Mach number max|v|/c0 reached.
    pub max_mach: f64,
    /// Steps with a Mach number above 0.1.
    pub steps_above_mach_limit: u64,
    /// Warnings about the run's numerics and outputs (also printed on stderr).
    pub warnings: Vec<String>,
    /// Outputs that could not be written (plots, roof map, post-processing files), with why.
    pub output_errors: Vec<String>,
    /// Still-water level the elevations are measured from (m): the fill level lowered by the
    /// EOS compression of the liquid under its own weight.
    pub still_level: f64,
    /// Closed-form references for this tank.
    pub theory: TheoryNumbers,
    /// Roof impacts with Kurihara's and Malhotra's pressures beside the SPH peak.
    pub impacts: Vec<RoofImpact>,
    /// Kurihara (Eq. 28) at the impact with the largest SPH roof pressure (Pa; 0 = no impact).
    pub kurihara_at_max: f64,
    /// Malhotra (Eq. 27) at the impact with the largest SPH roof pressure (Pa).
    pub malhotra_at_max: f64,
    /// Ground-motion records the script read (file, hash, scaling, processing).
    pub motions: Vec<slosh_script::MotionInfo>,
    /// Response spectrum of the applied x acceleration with the codes' wave heights.
    pub input_spectrum: Option<crate::spectrum::SpectrumSummary>,
    /// Results of the script's `post(run)`.
    pub post: Vec<(String, ParamValue)>,
    /// The error of the script's `post(run)` when it failed (the run's other outputs stand).
    pub post_error: Option<String>,
    // Loads as engineers read them, and whether the liquid reached the roof.
    /// The low-pass filter of the `*_lp` load columns of `series.csv`.
    pub load_filter: LoadFilter,
    /// Largest |base_shear_x_lp| over the output rows (N; 2D N/m).
    pub max_abs_base_shear_x_lp: f64,
    /// Largest roof_force_up_lp over the output rows (N; 2D N/m).
    pub max_roof_force_up_lp: f64,
    /// Peaks of each raw load column of `series.csv` and of its filtered copy.
    pub load_peaks: Vec<LoadPeak>,
    /// True when the liquid touched the roof (a time-windowed roof pressure above 1 Pa).
    pub roof_contact: bool,
    /// Why there are no roof plots, when there are none.
    pub roof_note: Option<String>,
    /// Each interruption of the run and its resumption (`slosh resume`), in order.
    pub resumes: Vec<crate::checkpoint::ResumeRecord>,
    /// Checkpoints written by the last process of the run (into `checkpoint/`).
    pub checkpoints_written: u64,
    /// Why a checkpoint could not be written, when one could not.
    pub checkpoint_error: Option<String>,
}

/// Closed-form numbers written beside the SPH result.
#[derive(Clone, Debug, Default, Serialize)]
pub struct TheoryNumbers {
    /// First sloshing mode, circular frequency (rad/s), potential theory.
    pub omega_1: f64,
    /// First sloshing period (s).
    pub period_1: f64,
}

/// Runs a case to the end (or to a blow-up, keeping what was written) and returns the summary.
/// SIGINT and SIGTERM stop it once [`crate::interrupt::install`] has installed the handlers.
pub fn run_case(case: Case, opts: &RunOptions) -> Result<Summary> {
    run_case_with_stop(case, opts, &mut crate::interrupt::received)
}

/// [`run_case`] with the caller's stop request, asked after every step: `Some(code)` ends the
/// run as an interruption by signal `code` (its outputs are written up to that step). A front
/// end that handles signals itself (the Python package) passes its own.
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
    if let Err(e) = &result {
        folder.mark_failed_if_running(&format!("{e:#}"));
    }
    result
}

/// Fits, builds and runs a claimed case.
fn build_and_run(
    case: &mut Case,
    opts: &RunOptions,
    stop: &mut dyn StopRequest,
) -> Result<Summary> {
    let fit = build::fit_to_lattice(&case.tank, case.dx)?;
    crate::memory::check_memory_budget(&fit.tank, fit.dx, opts.max_memory_bytes)?;
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
            let setup = build::build_2d(&fit.tank, fit.dx)?;
            let sim = Simulation::<2>::new(setup, sph)?;
            run_built(sim, case, fit, opts, stop)
        }
        _ => {
            let setup = build::build_3d(&fit.tank, fit.dx, &case.sandbox)?;
            let sim = Simulation::<3>::new(setup, sph)?;
            run_built(sim, case, fit, opts, stop)
        }
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
            | TankSpec::Box { depth, .. } => depth,
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
        // an estimate: the rectangle of the section's width and the liquid depth
        TankSpec::Section { depth, .. } => {
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

/// The files a run writes while it runs, as an observer of the run loop: `series.csv`
/// streamed row by row (written again at the end with the low-pass load columns), the
/// particle frames, and the progress display.
struct RunFiles {
    out: PathBuf,
    series: Option<SeriesWriter>,
    frames: Option<FrameSeries>,
    progress: Option<Progress>,
    started: Instant,
    checkpoints: Option<crate::checkpoint::CheckpointWriter>,
    /// Rows a resumed run wrote before its checkpoint, written again after the header.
    earlier_rows: Vec<Vec<f64>>,
    /// A checkpoint that could not be written (the run goes on; the summary says so).
    checkpoint_error: Option<String>,
    /// Simulated time after the last step (s), for [`RunStop`].
    time_reached: std::rc::Rc<std::cell::Cell<f64>>,
}

impl<const D: usize> Observer<D> for RunFiles {
    fn columns(&mut self, columns: &[(String, String)]) -> Result<(), HookError> {
        let mut writer = SeriesWriter::create(self.out.join("series.csv"), columns)?;
        for row in std::mem::take(&mut self.earlier_rows) {
            writer.write_row(&row)?;
        }
        self.series = Some(writer);
        Ok(())
    }

    fn checkpoint_due(&mut self, _time: f64, _steps: u64) -> bool {
        self.checkpoints.as_ref().is_some_and(|c| c.due())
    }

    fn checkpoint(&mut self, state: &slosh_run::RunCheckpoint<D>) -> Result<(), HookError> {
        let Some(writer) = self.checkpoints.as_mut() else {
            return Ok(());
        };
        // The rows so far must be on disk before a checkpoint that counts them.
        if let Some(series) = self.series.as_mut() {
            series.flush()?;
        }
        let frames = self
            .frames
            .as_ref()
            .map(|f| f.index().entries().to_vec())
            .unwrap_or_default();
        if let Err(e) = writer.write(&frames, state) {
            let message = format!("{e:#}");
            eprintln!("warning: checkpoint not written: {message}");
            self.checkpoint_error = Some(message);
        }
        Ok(())
    }

    fn row(&mut self, values: &[f64]) -> Result<(), HookError> {
        if let Some(writer) = self.series.as_mut() {
            writer.write_row(values)?;
        }
        Ok(())
    }

    fn frame(&mut self, sim: &Simulation<D>, time: f64) -> Result<(), HookError> {
        if let Some(frames) = self.frames.as_mut() {
            write_frame(frames, sim, time)?;
        }
        Ok(())
    }

    fn progress(&mut self, time: f64, steps: u64) {
        self.time_reached.set(time);
        if let Some(progress) = self.progress.as_mut() {
            progress.update(time, steps, self.started);
        }
    }

    fn series(
        &mut self,
        columns: &[(String, String)],
        series: &[Vec<f64>],
    ) -> Result<(), HookError> {
        if let Some(progress) = &self.progress {
            progress.finish();
        }
        if let Some(mut writer) = self.series.take() {
            writer.flush()?;
        }
        rewrite_series(&self.out.join("series.csv"), columns, series)?;
        Ok(())
    }
}

/// Environment variable of a testing aid: `SLOSH_TEST_STOP_AT=T` stops the run as a SIGTERM
/// would (checkpoint, `status: "interrupted"`, exit code 143) after the first step that ends
/// at or past the simulated time T (s). It makes an interruption land on a chosen step, so
/// that tests can check a resumed run against an uninterrupted one at set points; it applies
/// to the process it is set for (unset it before `slosh resume`).
pub const TEST_STOP_AT_ENV: &str = "SLOSH_TEST_STOP_AT";

/// The stop request of a run: the caller's (a SIGINT or SIGTERM received, Ctrl-C in Python),
/// or the time of [`TEST_STOP_AT_ENV`] reached.
struct RunStop<'s> {
    caller: &'s mut dyn StopRequest,
    stop_at_s: Option<f64>,
    time_reached: std::rc::Rc<std::cell::Cell<f64>>,
}

impl<'s> RunStop<'s> {
    fn from_env(
        caller: &'s mut dyn StopRequest,
        time_reached: std::rc::Rc<std::cell::Cell<f64>>,
    ) -> Result<Self> {
        let stop_at_s = match std::env::var(TEST_STOP_AT_ENV) {
            Ok(text) => match text.trim().parse::<f64>() {
                Ok(t) if t.is_finite() => Some(t),
                _ => {
                    anyhow::bail!("{TEST_STOP_AT_ENV}={text}: expected a simulated time in seconds")
                }
            },
            Err(_) => None,
        };
        Ok(RunStop {
            caller,
            stop_at_s,
            time_reached,
        })
    }
}

impl slosh_run::StopRequest for RunStop<'_> {
    fn stop_requested(&mut self) -> Option<i32> {
        self.caller.stop_requested().or_else(|| {
            self.stop_at_s
                .filter(|&t| self.time_reached.get() >= t)
                .map(|_| libc::SIGTERM)
        })
    }
}

/// The run's failure as the command line reports it: the solver's or the script's own error,
/// or [`crate::interrupt::Interrupted`] for a signal.
fn failure_of(status: RunStatus) -> Option<anyhow::Error> {
    match status {
        RunStatus::Finished => None,
        RunStatus::Interrupted { code } => {
            Some(crate::interrupt::Interrupted { signal: code }.into())
        }
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
                "the run in {} is complete (t = {} s of {} s): nothing to resume",
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
        TankSpec::Section { .. } | TankSpec::Sphere { .. } => Some(liquid_edge_gauges(&sim)),
        _ => None,
    };
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
    };
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
    let mut result: RunResult<D> = slosh_run::run_case_from(
        &mut sim,
        &plan,
        &mut case.excitation,
        &mut files,
        &mut stop,
        resume_state,
    )
    .map_err(|e| anyhow::anyhow!(e))?;
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
            Some(e) if e.is::<crate::interrupt::Interrupted>() => "interrupted",
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
    slosh_io::write_ron(out.join("summary.ron"), &summary)?;
    if let Some(e) = failure {
        let how = if e.is::<crate::interrupt::Interrupted>() {
            "; run the case again to redo it (resume from a checkpoint is not available yet)"
        } else {
            ""
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

/// Writes `series.csv` (and its units file) again with every column, the filtered load
/// columns appended after the raw ones.
fn rewrite_series(path: &Path, names: &[(String, String)], history: &[Vec<f64>]) -> Result<()> {
    // Written in a folder of its own beside the series, then both files renamed into place:
    // the streamed series stays whole until the new one is complete.
    let dir = path.parent().unwrap_or(Path::new("."));
    let staging = dir.join(".series-rewrite");
    std::fs::create_dir_all(&staging)?;
    let staged = staging.join(path.file_name().unwrap_or("series.csv".as_ref()));
    let mut writer = SeriesWriter::create(&staged, names)?;
    let rows = history.first().map_or(0, Vec::len);
    let mut row = Vec::with_capacity(history.len());
    for r in 0..rows {
        row.clear();
        row.extend(history.iter().map(|c| c[r]));
        writer.write_row(&row)?;
    }
    writer.flush()?;
    let staged_units = writer.units_path().to_path_buf();
    drop(writer);
    std::fs::rename(&staged_units, slosh_io::units_path_for(path))?;
    std::fs::rename(&staged, path)?;
    std::fs::remove_dir(&staging)?;
    Ok(())
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

fn write_frame<const D: usize>(
    frames: &mut FrameSeries,
    sim: &Simulation<D>,
    t: f64,
) -> Result<()> {
    let fluid = sim.fluid();
    let walls = sim.walls();
    let pad = |p: &Vector<D>| {
        let mut a = [0.0; 3];
        a[..D].copy_from_slice(p.as_slice());
        a
    };
    let points: Vec<[f64; 3]> = fluid
        .position
        .iter()
        .chain(&walls.position)
        .map(pad)
        .collect();
    let velocity: Vec<[f64; 3]> = fluid
        .velocity
        .iter()
        .map(pad)
        .chain(walls.position.iter().map(|_| [0.0; 3]))
        .collect();
    let pressure: Vec<f64> = fluid
        .pressure
        .iter()
        .chain(&walls.pressure)
        .copied()
        .collect();
    let density: Vec<f64> = fluid
        .density
        .iter()
        .chain(&walls.density)
        .copied()
        .collect();
    let kind: Vec<i32> = std::iter::repeat_n(0, fluid.position.len())
        .chain(std::iter::repeat_n(1, walls.position.len()))
        .collect();
    let part: Vec<i32> = std::iter::repeat_n(-1, fluid.position.len())
        .chain(walls.part.iter().map(|&p| p as i32))
        .collect();
    let id: Vec<i32> = fluid
        .id
        .iter()
        .map(|&i| i as i32)
        .chain((0..walls.position.len()).map(|w| w as i32))
        .collect();
    frames.write_frame(
        t,
        &points,
        &[
            PointArray::vector3("velocity", &velocity),
            PointArray::scalar("pressure", &pressure),
            PointArray::scalar("density", &density),
            PointArray::int32("kind", &kind),
            PointArray::int32("part", &part),
            PointArray::int32("id", &id),
        ],
    )?;
    Ok(())
}

fn write_plots(
    out: &Path,
    names: &[(String, String)],
    history: &[Vec<f64>],
    dim: usize,
    summary: &Summary,
) -> Result<()> {
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots)?;
    let find = |n: &str| names.iter().position(|(c, _)| c == n);
    let t = &history[0];
    let force_unit = if dim == 2 { "N/m" } else { "N" };
    let plot = |file: &str, title: &str, ylabel: String, series: Vec<Series>| -> Result<()> {
        if series.is_empty() {
            return Ok(());
        }
        slosh_io::line_plot(
            plots.join(file),
            &PlotSpec::new(title, "time t [s]", &ylabel),
            &series,
        )?;
        Ok(())
    };
    let lines = |cols: &[&str]| -> Vec<Series> {
        cols.iter()
            .filter_map(|c| find(c).map(|i| Series::line(c.to_string(), t, &history[i])))
            .collect()
    };
    let gauges: Vec<&str> = names
        .iter()
        .map(|(n, _)| n.as_str())
        .filter(|n| n.starts_with("eta_"))
        .collect();
    plot(
        "eta",
        "Free-surface elevation at the walls and gauges",
        "elevation η [m]".into(),
        lines(&gauges),
    )?;
    plot(
        "base_shear",
        "Base shear (fluid on walls and bottom)",
        format!("base shear [{force_unit}]"),
        raw_and_filtered(
            &["base_shear_x", "base_shear_y"],
            &find,
            t,
            history,
            summary.load_filter.cutoff_hz,
        ),
    )?;
    if summary.roof_contact {
        plot(
            "roof_force",
            "Upward force on the roof",
            format!("roof force [{force_unit}]"),
            raw_and_filtered(
                &["roof_force_up"],
                &find,
                t,
                history,
                summary.load_filter.cutoff_hz,
            ),
        )?;
        plot(
            "roof_pressure",
            "Largest roof pressure",
            "pressure [Pa]".into(),
            lines(&["roof_p_max"]),
        )?;
    }
    plot(
        "ground_accel",
        "Ground acceleration",
        "acceleration [m/s²]".into(),
        lines(&["accel_x"]),
    )?;
    Ok(())
}

/// Each raw column (light) with its low-pass copy (dark) on top, labelled for the legend.
fn raw_and_filtered<'a>(
    columns: &[&str],
    find: &dyn Fn(&str) -> Option<usize>,
    t: &'a [f64],
    history: &'a [Vec<f64>],
    cutoff_hz: f64,
) -> Vec<Series<'a>> {
    const RAW: [(u8, u8, u8); 2] = [(160, 190, 230), (240, 190, 150)];
    const FILTERED: [(u8, u8, u8); 2] = [(20, 60, 160), (190, 80, 10)];
    let mut raw = Vec::new();
    let mut filtered = Vec::new();
    for (k, column) in columns.iter().enumerate() {
        let (Some(i), Some(j)) = (find(column), find(&format!("{column}_lp"))) else {
            continue;
        };
        let (r, g, b) = RAW[k % 2];
        raw.push(Series::line(format!("{column} (raw)"), t, &history[i]).with_color(r, g, b));
        let (r, g, b) = FILTERED[k % 2];
        filtered.push(
            Series::line(
                format!("{column}_lp (low-pass {cutoff_hz:.2} Hz)"),
                t,
                &history[j],
            )
            .with_color(r, g, b),
        );
    }
    raw.extend(filtered);
    raw
}
