//! The summary of a run, written to `summary.ron`.

use serde::Serialize;
use slosh_core::SphParams;
use slosh_run::{LoadFilter, LoadPeak, RoofImpact, RoofLoadSummary};
use slosh_script::{ParamValue, TankSpec};

/// The summary written to `summary.ron` (the fields are listed in `docs/formats.md`). `Default` gives its layout with zeros
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
    /// Where the step ran: "cpu", or the GPU device and its precision ("llvmpipe (Vulkan,
    /// Mesa 22.3.6), f64").
    pub device: String,
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
    /// The roof load from every step (`docs/roof-loads.md`): impulse, the equivalent static
    /// load F_eq at the roof periods, the sensors, the impacts' spread; `None` without a
    /// roof.
    pub roof_load: Option<RoofLoadSummary>,
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
