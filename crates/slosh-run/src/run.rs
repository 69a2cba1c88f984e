//! A case run: the time loop of [`crate::advance`] with the measurements of every output
//! interval (the columns of `series.csv`, see `docs/design.md`), the time-windowed loads, the
//! roof pressure map and impacts, and the low-pass load columns, collected into a
//! [`RunResult`] and handed row by row to an [`Observer`].

use crate::load_filter::{add_filtered_columns, LoadFilter, LoadPeak};
use crate::motion::{AfterSettling, GroundMotion, TIME_EPS};
use crate::roof::{
    crest, find_impacts, RoofImpact, RoofMonitor, RoofSnapshot, RoofTank, WET_PRESSURE,
};
use crate::roof_load::{RoofLoadMonitor, RoofLoadPlan, RoofLoadResult};
use crate::stepping::{advance, HookError, StepError, StepHooks, StopRequest, Until};
use slosh_core::{LoadPeaks, PartLoads, SimState, Simulation, StepStats, TankRotation};
use std::collections::VecDeque;
use std::time::Instant;

/// A free-surface gauge: a vertical line at a horizontal position.
#[derive(Clone, Debug, PartialEq)]
pub struct Gauge {
    /// Column name in the series (`eta_<name>`).
    pub name: String,
    /// Horizontal coordinates (x in 2D; x, y in 3D) (m).
    pub horizontal: Vec<f64>,
}

/// What a case run measures and for how long.
#[derive(Clone, Debug)]
pub struct RunPlan {
    /// Settling time with gravity only before the excitation starts (s).
    pub settle: f64,
    /// Total simulated time, settling included (s).
    pub duration: f64,
    /// Interval of the series rows (s).
    pub output_interval: f64,
    /// Interval of particle frames (s); 0 = no frames.
    pub frame_interval: f64,
    /// Free-surface gauges besides the two wall gauges.
    pub gauges: Vec<Gauge>,
    /// The low-pass filter of the load columns.
    pub load_filter: LoadFilter,
    /// The tank numbers of Kurihara's and Malhotra's roof pressures.
    pub roof_tank: RoofTank,
    /// Horizontal positions of the `eta_left` and `eta_right` gauges; `None`: one lattice
    /// spacing inside the walls on the x axis ([`wall_gauges`]).
    pub wall_gauges: Option<(Vec<f64>, Vec<f64>)>,
    /// Roof sensors and the roof oscillator of the roof load spectrum.
    pub roof_load: RoofLoadPlan,
    /// The ground turns the tank as well as translating it: the series gains the column
    /// `tank_angle` (rad) after the ground acceleration.
    pub turns: bool,
}

/// Receives what a case run produces, as it produces it: once per output row, frame or step,
/// never per particle. The files of a run (series, frames, progress display) are observers
/// of the front end.
pub trait Observer<const D: usize> {
    /// The series columns, `(name, unit)`, before the first row.
    fn columns(&mut self, _columns: &[(String, String)]) -> Result<(), HookError> {
        Ok(())
    }

    /// One completed series row (its loads time-windowed), in column order.
    fn row(&mut self, _values: &[f64]) -> Result<(), HookError> {
        Ok(())
    }

    /// The particles at a frame time `time` (s), when the plan asks for frames.
    fn frame(&mut self, _sim: &Simulation<D>, _time: f64) -> Result<(), HookError> {
        Ok(())
    }

    /// After each step: the simulated time (s) and the steps taken.
    fn progress(&mut self, _time: f64, _steps: u64) {}

    /// Whether a checkpoint is wanted now, asked after each step (simulated time `time` (s),
    /// `steps` taken); a run that wants none answers `false`, the default.
    fn checkpoint_due(&mut self, _time: f64, _steps: u64) -> bool {
        false
    }

    /// A checkpoint of the run: after a step where [`Self::checkpoint_due`] said so, when the
    /// run is stopped by its front end, and at the end of the run.
    fn checkpoint(&mut self, _state: &RunCheckpoint<D>) -> Result<(), HookError> {
        Ok(())
    }

    /// The whole series at the end, with the low-pass load columns appended.
    fn series(
        &mut self,
        _columns: &[(String, String)],
        _series: &[Vec<f64>],
    ) -> Result<(), HookError> {
        Ok(())
    }
}

/// Observes nothing: a run kept in memory only.
impl<const D: usize> Observer<D> for () {}

/// How a run ended.
#[derive(Debug)]
pub enum RunStatus {
    /// The run reached its duration.
    Finished,
    /// The ground motion or the solver failed; the result holds the run up to that step.
    Failed(StepError),
    /// The front end asked the run to stop (the code of its request, a signal number for
    /// example); the result holds the run up to that step.
    Interrupted {
        /// The stop code.
        code: i32,
    },
}

/// What a run produced, in memory.
pub struct RunResult<const D: usize> {
    /// How the run ended.
    pub status: RunStatus,
    /// Series columns `(name, unit)`, the low-pass load columns last.
    pub columns: Vec<(String, String)>,
    /// The series, one vector per column, one value per output row.
    pub series: Vec<Vec<f64>>,
    /// The low-pass filter of the load columns as applied.
    pub load_filter: LoadFilter,
    /// Peaks of each raw load column and of its filtered copy.
    pub load_peaks: Vec<LoadPeak>,
    /// Extremes of the time-windowed loads over every step.
    pub peaks: LoadPeaks,
    /// Time-step statistics.
    pub stats: StepStats,
    /// The roof pressure map and the 2D snapshots of paper Fig. 7.
    pub roof: RoofMonitor<D>,
    /// 2D runs: the fluid at the output row of the largest wave, the largest |η| at either
    /// wall gauge (`eta_left`, `eta_right`), with that |η| (m); `None` in 3D. After a resume
    /// from a checkpoint, the largest wave since the resume.
    pub largest_wave_frame: Option<(RoofSnapshot, f64)>,
    /// True when the liquid touched the roof (a time-windowed roof pressure above
    /// [`WET_PRESSURE`] in a row or at any step).
    pub roof_contact: bool,
    /// Roof impacts with Kurihara's and Malhotra's pressures beside the SPH peak.
    pub impacts: Vec<RoofImpact>,
    /// The roof load from every step: impulse, sensors, the roof load spectrum; `None`
    /// without a roof.
    pub roof_load: Option<RoofLoadResult>,
    /// Compression of the liquid when the excitation started (at the end of the run without
    /// settling): 1 − Σ(m/ρ)/V0.
    pub hydrostatic_compression: f64,
    /// Fluid particles at the start.
    pub particles_fluid: usize,
    /// Wall particles.
    pub particles_wall: usize,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached (s).
    pub sim_time: f64,
    /// Fluid particles no longer inside the tank at the end.
    pub lost_particles: usize,
    /// Wall-clock time of the time loop (s).
    pub wall_time_s: f64,
}

impl<const D: usize> RunResult<D> {
    /// The values of the column `name`, if the series has it.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .position(|(n, _)| n == name)
            .map(|i| self.series[i].as_slice())
    }

    /// Largest finite value of a column (−∞ when it has none, NaN when there is no such
    /// column).
    pub fn max_of(&self, name: &str) -> f64 {
        self.column(name).map_or(f64::NAN, |v| {
            v.iter()
                .copied()
                .filter(|x| x.is_finite())
                .fold(f64::NEG_INFINITY, f64::max)
        })
    }

    /// Smallest finite value of a column (+∞ when it has none, NaN when there is no such
    /// column).
    pub fn min_of(&self, name: &str) -> f64 {
        self.column(name).map_or(f64::NAN, |v| {
            v.iter()
                .copied()
                .filter(|x| x.is_finite())
                .fold(f64::INFINITY, f64::min)
        })
    }
}

/// The series columns of a run: `(name, unit)` and where the loads start. `extra_parts` are
/// the names of the parts after `bottom`, `wall` and `roof` (internal solids, parts named by
/// the user): each gets the force of the liquid on it, `<part>_force_x` and the other axes.
fn columns(
    dim: usize,
    gauges: &[Gauge],
    extra_parts: &[String],
    roof_load: &RoofLoadPlan,
    has_roof: bool,
    turns: bool,
) -> (Vec<(String, String)>, usize) {
    let force = if dim == 2 { "N/m" } else { "N" };
    let energy = if dim == 2 { "J/m" } else { "J" };
    let mut names: Vec<(String, String)> = vec![("t".into(), "s".into())];
    names.push(("accel_x".into(), "m/s2".into()));
    if dim == 3 {
        names.push(("accel_y".into(), "m/s2".into()));
        names.push(("accel_z".into(), "m/s2".into()));
    } else {
        names.push(("accel_y".into(), "m/s2".into()));
    }
    if turns {
        names.push(("tank_angle".into(), "rad".into()));
    }
    names.push(("eta_left".into(), "m".into()));
    names.push(("eta_right".into(), "m".into()));
    for g in gauges {
        names.push((format!("eta_{}", g.name), "m".into()));
    }
    names.push(("crest_z".into(), "m".into()));
    names.push(("crest_vz".into(), "m/s".into()));
    names.push(("kinetic_energy".into(), energy.into()));
    names.push(("n_fluid".into(), "1".into()));
    names.push(("dt".into(), "s".into()));
    let n_before_loads = names.len();
    names.push(("base_shear_x".into(), force.into()));
    if dim == 3 {
        names.push(("base_shear_y".into(), force.into()));
    }
    names.push(("roof_force_up".into(), force.into()));
    names.push(("roof_p_max".into(), "Pa".into()));
    names.push(("wall_p_max".into(), "Pa".into()));
    names.push(("bottom_force_down".into(), force.into()));
    names.push(("roof_contact_extent".into(), "m".into()));
    if dim == 2 {
        names.push(("overturning_moment".into(), "N·m/m".into()));
    } else {
        names.push(("overturning_moment_y".into(), "N·m".into()));
        names.push(("overturning_moment_x".into(), "N·m".into()));
    }
    for part in extra_parts {
        for axis in PART_FORCE_AXES[dim - 2] {
            names.push((part_force_column(part, axis), force.into()));
        }
    }
    for sensor in &roof_load.sensors {
        names.push((sensor_column(&sensor.name), "Pa".into()));
    }
    if has_roof {
        let impulse = if dim == 2 { "N·s/m" } else { "N·s" };
        names.push(("roof_impulse".into(), impulse.into()));
    }
    (names, n_before_loads)
}

/// Number of built-in wall parts (`bottom`, `wall`, `roof`) before the internal solids and the
/// parts named by the user.
const BUILT_IN_PARTS: usize = 3;

/// The axes of the per-part force columns in 2D and in 3D (the last is vertical, up positive).
const PART_FORCE_AXES: [&[&str]; 2] = [&["x", "y"], &["x", "y", "z"]];

/// Name of the series column of the force of the liquid on `part` along `axis` (N or N/m):
/// `<part>_force_<axis>`.
pub fn part_force_column(part: &str, axis: &str) -> String {
    format!("{part}_force_{axis}")
}

/// Name of the series column of a roof sensor's time-windowed mean pressure (Pa):
/// `p_<name>`.
pub fn sensor_column(name: &str) -> String {
    format!("p_{name}")
}

/// Horizontal positions of the left and right wall gauges: on the x axis, one lattice
/// spacing inside the interior from the wall face.
pub fn wall_gauges<const D: usize>(sim: &Simulation<D>) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = sim.interior_bounds();
    let dx = sim.spacing();
    let mut left = vec![0.0; D - 1];
    let mut right = vec![0.0; D - 1];
    left[0] = lo[0] + dx;
    right[0] = hi[0] - dx;
    for k in 1..D - 1 {
        let centre = 0.5 * (lo[k] + hi[k]);
        left[k] = centre;
        right[k] = centre;
    }
    (left, right)
}

/// Overturning-moment coefficients c_k of the load points, M = Σ_k p_k c_k: the moment of the
/// liquid's pressure on walls, bottom and roof about a horizontal axis through the centre of
/// the floor (Housner's overturning moment including the base pressure). 2D: about the axis
/// normal to the section, M = Σ p A [(z − z_f) n_x − (x − x_c) n_z] (N·m/m), positive when the
/// liquid pushes the tank over towards +x. 3D: that moment about the y axis, and about the x
/// axis M_x = Σ p A [(y − y_c) n_z − (z − z_f) n_y].
fn overturning_levers<const D: usize>(sim: &Simulation<D>) -> Vec<Vec<f64>> {
    let loads = sim.loads();
    let (lo, hi) = sim.interior_bounds();
    let centre: Vec<f64> = (0..D - 1).map(|k| 0.5 * (lo[k] + hi[k])).collect();
    let floor = lo[D - 1];
    let about_y = |k: usize| {
        let (x, n, a) = (loads.positions()[k], loads.normals()[k], loads.areas()[k]);
        a * ((x[D - 1] - floor) * n[0] - (x[0] - centre[0]) * n[D - 1])
    };
    let mut levers = vec![(0..loads.len()).map(about_y).collect::<Vec<f64>>()];
    if D == 3 {
        levers.push(
            (0..loads.len())
                .map(|k| {
                    let (x, n, a) = (loads.positions()[k], loads.normals()[k], loads.areas()[k]);
                    a * ((x[1] - centre[1]) * n[2] - (x[2] - floor) * n[1])
                })
                .collect(),
        );
    }
    levers
}

/// Everything a case run continues from: the solver's state and the measurements so far
/// (the completed series rows, the rows waiting for their time window, the roof map, the
/// next output and frame times). [`run_case_from`] with it continues the run bit for bit.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct RunCheckpoint<const D: usize> {
    /// The solver's state.
    pub sim: SimState<D>,
    /// The completed series rows, one vector per column.
    pub series: Vec<Vec<f64>>,
    pending: Vec<PendingRow>,
    roof: RoofMonitor<D>,
    roof_load: RoofLoadMonitor,
    next_output: f64,
    next_frame: f64,
    compression: Option<f64>,
    /// Wall-clock time of the time loop before this checkpoint (s).
    pub wall_time_s: f64,
}

/// One series row waiting for its time-windowed loads.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
struct PendingRow {
    step: u64,
    values: Vec<f64>,
}

/// The measurements of a case run, done around each step.
struct CaseMeasurements<'o, const D: usize, O: ?Sized> {
    observer: &'o mut O,
    plan: &'o RunPlan,
    n_columns: usize,
    n_before_loads: usize,
    series: Vec<Vec<f64>>,
    pending: VecDeque<PendingRow>,
    roof: RoofMonitor<D>,
    roof_load: RoofLoadMonitor,
    levers: Vec<Vec<f64>>,
    wall_gauges: (Vec<f64>, Vec<f64>),
    still_level: f64,
    roof_part: Option<usize>,
    wall_part: Option<usize>,
    bottom_part: Option<usize>,
    next_output: f64,
    next_frame: f64,
    compression: Option<f64>,
    /// The tank's angle about its pivot for the coming row (rad; 0 when it does not turn).
    tank_angle: f64,
    /// 2D: the fluid at the row of the largest wall-gauge |η| so far, and that |η| (m).
    largest_wave: Option<(RoofSnapshot, f64)>,
    /// Wall time of the loop before this call of the run (s), from a checkpoint.
    wall_time_before: f64,
    started: Instant,
    /// The observer asked for a checkpoint after the coming step.
    checkpoint_pending: bool,
}

impl<const D: usize, O: Observer<D> + ?Sized> CaseMeasurements<'_, D, O> {
    /// The checkpoint of the run as it stands between two steps.
    fn checkpoint(&self, sim: &Simulation<D>) -> RunCheckpoint<D> {
        RunCheckpoint {
            sim: sim.state(),
            series: self.series.clone(),
            pending: self.pending.iter().cloned().collect(),
            roof: self.roof.clone(),
            roof_load: self.roof_load.clone(),
            next_output: self.next_output,
            next_frame: self.next_frame,
            compression: self.compression,
            wall_time_s: self.wall_time_before + self.started.elapsed().as_secs_f64(),
        }
    }

    /// Hands a checkpoint to the observer.
    fn write_checkpoint(&mut self, sim: &Simulation<D>) -> Result<(), HookError> {
        let state = self.checkpoint(sim);
        self.observer.checkpoint(&state)
    }

    /// Completes a pending row with the loads of its step and hands it on.
    fn complete_row(
        &mut self,
        row: PendingRow,
        loads: &PartLoads<D>,
        centred_pressure: &[f64],
    ) -> Result<(), HookError> {
        let mut values = row.values;
        let contact = self.roof.record(loads.time, centred_pressure);
        let roof_part = self.roof_part;
        let shear = slosh_core::loads::base_shear_x(loads, roof_part);
        values.push(shear);
        if D == 3 {
            let shear_y: f64 = loads
                .force
                .iter()
                .enumerate()
                .filter(|(k, _)| Some(*k) != roof_part)
                .map(|(_, f)| f[1])
                .sum();
            values.push(shear_y);
        }
        let pick = |part: Option<usize>| part.map(|k| loads.force[k][D - 1]).unwrap_or(0.0);
        values.push(pick(roof_part));
        values.push(roof_part.map(|k| loads.peak_pressure[k]).unwrap_or(0.0));
        values.push(
            self.wall_part
                .map(|k| loads.peak_pressure[k])
                .unwrap_or(0.0),
        );
        values.push(-pick(self.bottom_part));
        values.push(contact);
        for lever in &self.levers {
            values.push(lever.iter().zip(centred_pressure).map(|(c, p)| c * p).sum());
        }
        for force in loads.force.iter().skip(BUILT_IN_PARTS) {
            values.extend(force.iter().copied());
        }
        for i in 0..self.roof_load.sensor_count() {
            values.push(self.roof_load.sensor_pressure(i, centred_pressure));
        }
        if self.roof_load.has_roof() {
            let row = self.series.first().map_or(0, Vec::len);
            values.push(self.roof_load.row_impulse(row));
        }
        self.push_row(values)
    }

    /// Keeps a finished row and hands it to the observer.
    fn push_row(&mut self, values: Vec<f64>) -> Result<(), HookError> {
        self.observer.row(&values)?;
        for (h, v) in self.series.iter_mut().zip(&values) {
            h.push(*v);
        }
        Ok(())
    }

    /// Completes the rows whose loads the latest time window finished.
    fn complete_ready_rows(&mut self, sim: &Simulation<D>) -> Result<(), HookError> {
        if let Some(loads) = sim.loads().centred() {
            while self.pending.front().is_some_and(|r| r.step <= loads.step) {
                let Some(row) = self.pending.pop_front() else {
                    break;
                };
                self.complete_row(row, loads, sim.loads().centred_pressure())?;
            }
        }
        Ok(())
    }
}

impl<const D: usize, O: Observer<D> + ?Sized> StepHooks<D> for CaseMeasurements<'_, D, O> {
    fn before_step_turning(
        &mut self,
        sim: &Simulation<D>,
        accel: [f64; 3],
        rotation: Option<&TankRotation>,
    ) -> Result<(), HookError> {
        self.tank_angle = rotation.map_or(0.0, |r| r.angle);
        self.before_step(sim, accel)
    }

    fn before_step(&mut self, sim: &Simulation<D>, accel: [f64; 3]) -> Result<(), HookError> {
        let t = sim.time();
        let settle = self.plan.settle;
        // At the end of settling; without settling, at the end of the run.
        if self.compression.is_none() && settle > 0.0 && t >= settle - TIME_EPS {
            self.compression = Some(sim.mean_compression());
        }
        if t >= self.next_output - TIME_EPS {
            let mut values = Vec::with_capacity(self.n_columns);
            values.push(t);
            values.push(accel[0]);
            if D == 3 {
                values.push(accel[1]);
                values.push(accel[2]);
            } else {
                values.push(accel[2]);
            }
            if self.plan.turns {
                values.push(self.tank_angle);
            }
            let fill = self.still_level;
            let eta = |h: &[f64]| {
                sim.surface_level_at(h)
                    .map(|z| z - fill)
                    .unwrap_or(f64::NAN)
            };
            let (left, right) = (eta(&self.wall_gauges.0), eta(&self.wall_gauges.1));
            values.push(left);
            values.push(right);
            let wave = left.abs().max(right.abs());
            if D == 2 && wave.is_finite() && self.largest_wave.as_ref().is_none_or(|w| wave > w.1) {
                let fluid = sim.fluid();
                let snapshot = RoofSnapshot {
                    time: t,
                    position: fluid.position.iter().map(|p| [p[0], p[D - 1]]).collect(),
                    pressure: fluid.pressure.clone(),
                };
                self.largest_wave = Some((snapshot, wave));
            }
            for g in &self.plan.gauges {
                values.push(eta(&g.horizontal));
            }
            let (crest_vz, crest_z) = crest(sim);
            values.push(crest_z);
            values.push(crest_vz);
            values.push(sim.kinetic_energy());
            values.push(sim.fluid_inside() as f64);
            self.roof.snapshot(sim);
            values.push(sim.last_dt());
            debug_assert_eq!(values.len(), self.n_before_loads);
            self.pending.push_back(PendingRow {
                step: sim.steps(),
                values,
            });
            self.roof_load.cut_row(t);
            while self.next_output <= t + TIME_EPS {
                self.next_output += self.plan.output_interval;
            }
        }
        if self.plan.frame_interval > 0.0 && t >= self.next_frame - TIME_EPS {
            self.observer.frame(sim, t)?;
            while self.next_frame <= t + TIME_EPS {
                self.next_frame += self.plan.frame_interval;
            }
        }
        Ok(())
    }

    fn after_step(&mut self, sim: &Simulation<D>) -> Result<(), HookError> {
        self.roof_load.after_step(sim);
        self.complete_ready_rows(sim)?;
        self.observer.progress(sim.time(), sim.steps());
        if std::mem::take(&mut self.checkpoint_pending) {
            self.write_checkpoint(sim)?;
        }
        Ok(())
    }

    /// Before a step: at an output row, a frame or the end of settling (the compression);
    /// after it: when the observer asks for a checkpoint.
    fn reads_particles(&mut self, sim: &Simulation<D>, before: bool) -> bool {
        let t = sim.time();
        if before {
            let settle = self.plan.settle;
            (self.compression.is_none() && settle > 0.0 && t >= settle - TIME_EPS)
                || t >= self.next_output - TIME_EPS
                || (self.plan.frame_interval > 0.0 && t >= self.next_frame - TIME_EPS)
        } else {
            self.checkpoint_pending = self.observer.checkpoint_due(t, sim.steps());
            self.checkpoint_pending
        }
    }
}

/// Runs a case on `sim` to `plan.duration` under `motion` (given in time since the excitation
/// started, applied after `plan.settle`), measuring every output interval, handing rows,
/// frames and progress to `observer`, and checking `stop` after every step.
///
/// A failure of the motion or the solver, or a stop request, ends the run with the outputs so
/// far ([`RunResult::status`] says which); an error of the observer ends it with that error.
pub fn run_case<const D: usize, M, O, S>(
    sim: &mut Simulation<D>,
    plan: &RunPlan,
    motion: &mut M,
    observer: &mut O,
    stop: &mut S,
) -> Result<RunResult<D>, HookError>
where
    M: GroundMotion + ?Sized,
    O: Observer<D> + ?Sized,
    S: StopRequest + ?Sized,
{
    run_case_from(sim, plan, motion, observer, stop, None)
}

/// [`run_case`], continuing from `resume` when given: `sim` is the simulation built again
/// from the same case, and the checkpoint's solver state and measurements are put back
/// before the first step. The observer is given the columns, then only the rows completed
/// after the checkpoint (a front end that writes files keeps the rows it wrote before), and
/// the whole series at the end. The finished outputs are bit for bit those of the run done
/// without interruption.
pub fn run_case_from<const D: usize, M, O, S>(
    sim: &mut Simulation<D>,
    plan: &RunPlan,
    motion: &mut M,
    observer: &mut O,
    stop: &mut S,
    resume: Option<RunCheckpoint<D>>,
) -> Result<RunResult<D>, HookError>
where
    M: GroundMotion + ?Sized,
    O: Observer<D> + ?Sized,
    S: StopRequest + ?Sized,
{
    let particles_fluid = sim.fluid().position.len();
    let particles_wall = sim.walls().position.len();
    let extra_parts: Vec<String> = sim
        .part_names()
        .iter()
        .skip(BUILT_IN_PARTS)
        .cloned()
        .collect();
    let roof_load = RoofLoadMonitor::new(sim, &plan.roof_load).map_err(HookError::from)?;
    let (names, n_before_loads) = columns(
        D,
        &plan.gauges,
        &extra_parts,
        &plan.roof_load,
        roof_load.has_roof(),
        plan.turns,
    );
    observer.columns(&names)?;
    let part = |name: &str| sim.part_names().iter().position(|n| n == name);
    let expected_rows = (plan.duration / plan.output_interval).ceil() as usize + 2;
    let mut m = CaseMeasurements {
        n_columns: names.len(),
        n_before_loads,
        series: vec![Vec::new(); names.len()],
        pending: VecDeque::new(),
        roof: RoofMonitor::new(sim, expected_rows),
        roof_load,
        levers: overturning_levers(sim),
        wall_gauges: plan.wall_gauges.clone().unwrap_or_else(|| wall_gauges(sim)),
        still_level: sim.still_level(),
        roof_part: part("roof"),
        wall_part: part("wall"),
        bottom_part: part("bottom"),
        next_output: 0.0,
        next_frame: 0.0,
        compression: None,
        tank_angle: 0.0,
        largest_wave: None,
        wall_time_before: 0.0,
        started: Instant::now(),
        checkpoint_pending: false,
        observer,
        plan,
    };
    if let Some(checkpoint) = resume {
        if checkpoint.series.len() != names.len() {
            return Err(HookError::from(format!(
                "the checkpoint holds {} series columns where this case has {}",
                checkpoint.series.len(),
                names.len()
            )));
        }
        sim.restore(checkpoint.sim)
            .map_err(|e| HookError::from(e.to_string()))?;
        m.series = checkpoint.series;
        m.pending = checkpoint.pending.into();
        m.roof = checkpoint.roof;
        m.roof_load = std::mem::take(&mut m.roof_load).resumed(checkpoint.roof_load);
        m.next_output = checkpoint.next_output;
        m.next_frame = checkpoint.next_frame;
        m.compression = checkpoint.compression;
        m.wall_time_before = checkpoint.wall_time_s;
    }
    let mut motion = AfterSettling::new(plan.settle, motion);
    let started = Instant::now();
    let outcome = advance(
        sim,
        &mut motion,
        Until::Time(plan.duration - TIME_EPS),
        &mut m,
        stop,
    );
    let wall_time_s = m.wall_time_before + started.elapsed().as_secs_f64();
    let status = match outcome {
        Ok(()) => RunStatus::Finished,
        Err(StepError::Hook(e)) => return Err(e),
        Err(StepError::Stopped { code, .. }) => RunStatus::Interrupted { code },
        Err(e) => RunStatus::Failed(e),
    };
    // The state to continue from (before the time window is closed at the end below): when
    // the front end stopped the run, and at its end.
    if !matches!(status, RunStatus::Failed(_)) {
        m.write_checkpoint(sim)?;
    }
    // The last N steps: windows cut at the end of the run.
    let mut tail = Vec::new();
    sim.loads_mut()
        .flush_tail(|loads, pressure| tail.push((loads.clone(), pressure.to_vec())));
    for (loads, pressure) in tail {
        while m.pending.front().is_some_and(|r| r.step <= loads.step) {
            let Some(row) = m.pending.pop_front() else {
                break;
            };
            m.complete_row(row, &loads, &pressure)?;
        }
    }
    // Rows of a run without any load point (no wall area) or after a failure before the
    // first load evaluation: zeros for the loads.
    while let Some(row) = m.pending.pop_front() {
        let mut values = row.values;
        values.resize(names.len(), 0.0);
        m.push_row(values)?;
    }
    let CaseMeasurements {
        observer,
        mut series,
        roof,
        roof_load,
        compression,
        largest_wave,
        ..
    } = m;
    let mut columns = names;
    let mut load_filter = plan.load_filter.clone();
    let load_peaks = add_filtered_columns(&mut load_filter, &mut columns, &mut series);
    observer.series(&columns, &series)?;
    let peaks = sim.loads().peaks();
    let mut result = RunResult {
        status,
        columns,
        series,
        load_filter,
        load_peaks,
        peaks,
        stats: sim.step_stats(),
        roof_contact: false,
        impacts: Vec::new(),
        roof_load: None,
        roof,
        largest_wave_frame: largest_wave,
        hydrostatic_compression: compression.unwrap_or_else(|| sim.mean_compression()),
        particles_fluid,
        particles_wall,
        steps: sim.steps(),
        sim_time: sim.time(),
        lost_particles: particles_fluid - sim.fluid_inside(),
        wall_time_s,
    };
    result.roof_contact =
        result.roof.has_roof() && result.max_of("roof_p_max").max(peaks.max_roof_p) > WET_PRESSURE;
    if plan.frame_interval > 0.0 && matches!(result.status, RunStatus::Finished) {
        observer.frame(sim, sim.time())?;
    }
    if roof_load.measures() {
        let loads = roof_load.result(&plan.roof_tank, sim.spacing(), &plan.roof_load.sensors);
        if result.roof.has_roof() && roof_load.has_roof() {
            let column = |name: &str| result.column(name).unwrap_or_default();
            result.impacts = find_impacts(
                &loads,
                column("t"),
                column("roof_force_up"),
                column("roof_p_max"),
                column("crest_vz"),
                column("roof_contact_extent"),
                &plan.roof_tank,
            );
        }
        result.roof_load = Some(loads);
    }
    Ok(result)
}
