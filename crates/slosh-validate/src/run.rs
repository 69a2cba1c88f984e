//! Shared machinery of the checks: building the 2D tanks, stepping a simulation with a
//! horizontal ground acceleration while recording wall elevations and base shear, and small
//! numerical helpers (interpolation, zero crossings, least squares).

use anyhow::{anyhow, Result};
use slosh_core::loads::base_shear_x;
use slosh_core::{Simulation, SphParams, PART_ROOF};
use slosh_geometry::RectTank2;
use slosh_run::{EachStep, HookError, StepPhase, Until};
use std::path::PathBuf;

/// Gravity of every case (m/s²), the paper's value.
pub const GRAVITY: f64 = 9.81;
/// Water density ρ0 (kg/m³).
pub const RHO: f64 = 1000.0;

/// Options every check group sees.
#[derive(Clone)]
pub struct Context {
    /// Quick subset.
    pub quick: bool,
    /// Output folder.
    pub out: PathBuf,
    /// Where progress lines go (`None` = nowhere).
    pub progress: Option<fn(&str)>,
    /// Wall time between checkpoints of the long free runs (`None` = no checkpoints, and
    /// none read).
    pub checkpoint_every: Option<std::time::Duration>,
    /// The number of the stage these checks belong to, on its progress lines when stages run
    /// side by side (0: none shown).
    pub stage: usize,
}

impl Context {
    /// A progress line (indented under its stage, with the stage's number when it has one).
    pub fn say(&self, what: &str) {
        if let Some(progress) = self.progress {
            if self.stage == 0 {
                progress(&format!("    {what}"));
            } else {
                progress(&format!("    #{} {what}", self.stage));
            }
        }
    }
}

/// The paper scheme (paper §2): the solver's defaults.
///
/// Wall loads (base shear) are evaluated with the Shepard kernel extrapolation to the wall
/// face (`WallPressureMethod::KernelExtrapolation`): the paper's nearest-fluid method (§2.6)
/// samples the pressure about 1.3 dx inside the liquid and Eq. 23 pulls it towards the interior,
/// which reads the hydrostatic wall pressure ≈ 10 % low; the flow itself is the paper scheme's.
pub fn paper_params() -> SphParams {
    SphParams {
        wall_pressure: slosh_core::WallPressureMethod::KernelExtrapolation,
        ..SphParams::default().with_paper_stiffness()
    }
}

/// A 2D rectangular tank (floor at y = 0, left wall at x = 0) with the paper scheme.
pub fn rect_sim(
    width: f64,
    tank_height: f64,
    depth: f64,
    roof: bool,
    tilt: f64,
    dx: f64,
) -> Result<Simulation<2>> {
    rect_sim_with(paper_params(), width, tank_height, depth, roof, tilt, dx)
}

/// The same tank with any solver parameters.
pub fn rect_sim_with(
    params: SphParams,
    width: f64,
    tank_height: f64,
    depth: f64,
    roof: bool,
    tilt: f64,
    dx: f64,
) -> Result<Simulation<2>> {
    let setup = RectTank2::new(width, tank_height, depth)
        .with_roof(roof)
        .with_initial_tilt(tilt)
        .with_layers(params.wall_layers())
        .build(dx)?;
    Ok(Simulation::new(setup, params)?)
}

/// A named solver configuration a check group runs with.
#[derive(Clone, Debug)]
pub struct Scheme {
    /// Short name for labels ("paper scheme", "modern scheme").
    pub label: &'static str,
    /// Solver parameters.
    pub params: SphParams,
    /// True for the paper's scheme: its rows are judged against the paper-scheme tolerances
    /// and its plots keep the paper-case file names.
    pub is_paper: bool,
}

impl Scheme {
    /// The paper scheme as the validation runs it ([`paper_params`]).
    pub fn paper() -> Self {
        Scheme {
            label: "paper scheme",
            params: paper_params(),
            is_paper: true,
        }
    }
    /// The modern preset (`SphParams::modern()`).
    pub fn modern() -> Self {
        Scheme {
            label: "modern scheme",
            params: SphParams::modern().with_paper_stiffness(),
            is_paper: false,
        }
    }
}

/// Sine ground acceleration a_g = A ω² sin(ω (t − settle)) after `settle` s of gravity only
/// (tank frame: the liquid feels −a_g, the paper's −A ω² sin ωt).
#[derive(Clone, Copy, Debug)]
pub struct SineExcitation {
    /// Ground displacement amplitude A (m).
    pub amplitude: f64,
    /// Circular frequency ω (rad/s).
    pub omega: f64,
    /// Settling time before the excitation starts (s).
    pub settle: f64,
}

impl SineExcitation {
    /// No excitation at all.
    pub fn none() -> Self {
        SineExcitation {
            amplitude: 0.0,
            omega: 1.0,
            settle: 0.0,
        }
    }
    /// Ground acceleration (m/s²) at simulation time t (s).
    pub fn ground_accel(&self, t: f64) -> f64 {
        let te = t - self.settle;
        if te < 0.0 {
            0.0
        } else {
            self.amplitude * self.omega * self.omega * (self.omega * te).sin()
        }
    }
    /// Amplitude of the body force on the liquid, F in f = F sin ωt' (m/s²): F = −A ω².
    pub fn body_force_amplitude(&self) -> f64 {
        -self.amplitude * self.omega * self.omega
    }
}

/// Time histories recorded while stepping.
#[derive(Clone, Debug, Default)]
pub struct History {
    /// Sample times (s, simulation time).
    pub t: Vec<f64>,
    /// Free-surface elevation at the left-wall gauge (m, above the still level).
    pub eta_left: Vec<f64>,
    /// Same at the right-wall gauge (m).
    pub eta_right: Vec<f64>,
    /// Times of the time-windowed loads (s).
    pub load_t: Vec<f64>,
    /// Base shear along x from the windowed loads, parts "bottom" + "wall" (N/m).
    pub base_shear: Vec<f64>,
    /// Particle-steps done (fluid + wall particles × steps).
    pub particle_steps: f64,
}

/// A running simulation with its gauges and recorder.
pub struct Runner {
    /// The simulation.
    pub sim: Simulation<2>,
    /// The excitation.
    pub excitation: SineExcitation,
    /// Recorded histories.
    pub history: History,
    /// Gauge x positions (m): one lattice spacing inside each side wall, as `slosh run`.
    pub gauge_x: (f64, f64),
    /// Still-water level the elevations are measured from (m).
    pub still_level: f64,
    /// Interval between elevation samples (s).
    pub sample_interval: f64,
    next_sample: f64,
    roof_part: Option<usize>,
    last_load_step: Option<u64>,
}

impl Runner {
    /// Wraps a simulation; elevations every `sample_interval` s.
    pub fn new(sim: Simulation<2>, excitation: SineExcitation, sample_interval: f64) -> Self {
        let (lo, hi) = sim.interior_bounds();
        let dx = sim.spacing();
        let roof_part = sim.part_names().iter().position(|n| n == PART_ROOF);
        let still_level = sim.still_level();
        Runner {
            gauge_x: (lo[0] + dx, hi[0] - dx),
            still_level,
            sim,
            excitation,
            history: History::default(),
            sample_interval,
            next_sample: 0.0,
            roof_part,
            last_load_step: None,
        }
    }

    /// Steps until simulation time `t_end` (s), calling `hook` after every step.
    pub fn run_until<F: FnMut(&Simulation<2>)>(&mut self, t_end: f64, mut hook: F) -> Result<()> {
        let n_particles =
            (self.sim.fluid().position.len() + self.sim.walls().position.len()) as f64;
        let Runner {
            sim,
            excitation,
            history,
            gauge_x,
            still_level,
            sample_interval,
            next_sample,
            roof_part,
            last_load_step,
        } = self;
        step_until_around(
            sim,
            |t| [excitation.ground_accel(t), 0.0, 0.0],
            t_end,
            "the simulation stopped",
            |phase, sim| {
                match phase {
                    StepPhase::Before(_) => {
                        if sim.time() >= *next_sample - 1e-12 {
                            let (l, r) = wall_elevations(sim, *gauge_x, *still_level);
                            history.t.push(sim.time());
                            history.eta_left.push(l);
                            history.eta_right.push(r);
                            *next_sample += *sample_interval;
                        }
                    }
                    StepPhase::After => {
                        history.particle_steps += n_particles;
                        if let Some(c) = sim.loads().centred() {
                            if *last_load_step != Some(c.step) {
                                *last_load_step = Some(c.step);
                                history.load_t.push(c.time);
                                history.base_shear.push(base_shear_x(c, *roof_part));
                            }
                        }
                        hook(sim);
                    }
                }
                Ok(())
            },
        )
    }
}

/// Elevations (m) above `still_level` at the wall gauges `gauge_x` of a 2D tank.
fn wall_elevations(sim: &Simulation<2>, gauge_x: (f64, f64), still_level: f64) -> (f64, f64) {
    let eta = |x: f64| {
        sim.surface_level_at(&[x])
            .map(|z| z - still_level)
            .unwrap_or(f64::NAN)
    };
    (eta(gauge_x.0), eta(gauge_x.1))
}

/// Advances `sim` while its time is below `t_end` (s) under the ground acceleration
/// `accel(t)` (`[x, y, vertical]`, m/s²) through the run loop of `slosh-run`, calling `after`
/// after each step; a failure says that `what` stopped and when.
pub fn step_until<const D: usize>(
    sim: &mut Simulation<D>,
    mut accel: impl FnMut(f64) -> [f64; 3],
    t_end: f64,
    what: &str,
    after: impl FnMut(&Simulation<D>) -> Result<(), HookError>,
) -> Result<()> {
    slosh_run::advance_with(sim, &mut accel, Until::Time(t_end), after)
        .map_err(|e| anyhow!("{what} at t = {:.3} s: {e}", sim.time()))
}

/// [`step_until`] with a hook called before each step (with the acceleration it applies) and
/// after it.
pub fn step_until_around<const D: usize>(
    sim: &mut Simulation<D>,
    mut accel: impl FnMut(f64) -> [f64; 3],
    t_end: f64,
    what: &str,
    each: impl FnMut(StepPhase, &Simulation<D>) -> Result<(), HookError>,
) -> Result<()> {
    slosh_run::advance(
        sim,
        &mut accel,
        Until::Time(t_end),
        &mut EachStep(each),
        &mut (),
    )
    .map_err(|e| anyhow!("{what} at t = {:.3} s: {e}", sim.time()))
}

/// Linear interpolation of (xs, ys) at x (xs increasing); NaN outside.
pub fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    if xs.is_empty() || x < xs[0] || x > xs[xs.len() - 1] {
        return f64::NAN;
    }
    let k = xs.partition_point(|&v| v <= x);
    if k == 0 {
        return ys[0];
    }
    if k >= xs.len() {
        return ys[xs.len() - 1];
    }
    let (x0, x1) = (xs[k - 1], xs[k]);
    let w = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
    ys[k - 1] * (1.0 - w) + ys[k] * w
}

/// Times of the sign changes of `ys` with hysteresis: a crossing is confirmed only when the
/// signal reaches beyond ±`band` on the other side, and noisy multiple crossings in between
/// count once, at the midpoint of the first and last. Returns (time, +1 upward / −1 downward).
pub fn zero_crossings(ts: &[f64], ys: &[f64], band: f64) -> Vec<(f64, i8)> {
    let mut out = Vec::new();
    let mut side = 0i8; // side of the last excursion beyond the band
    let mut candidates: Option<(f64, f64)> = None; // first and last zero crossing since then
    let mut last: Option<(f64, f64)> = None;
    for (&t, &y) in ts.iter().zip(ys) {
        if !y.is_finite() {
            continue;
        }
        if let Some((t0, y0)) = last {
            if (y > 0.0) != (y0 > 0.0) {
                let tc = t0 + (t - t0) * (-y0) / (y - y0);
                candidates = Some(match candidates {
                    None => (tc, tc),
                    Some((first, _)) => (first, tc),
                });
            }
        }
        let now: i8 = if y > band {
            1
        } else if y < -band {
            -1
        } else {
            0
        };
        if now != 0 && now != side {
            if side != 0 {
                if let Some((first, lastc)) = candidates {
                    out.push((0.5 * (first + lastc), now));
                }
            }
            side = now;
            candidates = None;
        } else if now != 0 {
            candidates = None;
        }
        last = Some((t, y));
    }
    out
}

/// The fluid particles' pressures against the hydrostatic ρ0 g (still − z) below the level
/// `still` (m): the least-squares slope dp/d(ρ0 g d) (with an intercept, so independent of
/// where the zero of d is put) and the RMS departure over ρ0 g still.
pub fn hydrostatic_fit(sim: &Simulation<2>, still: f64) -> (f64, f64) {
    let f = sim.fluid();
    let reference: Vec<f64> = f
        .position
        .iter()
        .map(|p| RHO * GRAVITY * (still - p.y))
        .collect();
    let slope = fitted_slope(&reference, &f.pressure);
    let n = reference.len() as f64;
    let ss: f64 = reference
        .iter()
        .zip(&f.pressure)
        .map(|(a, b)| (a - b) * (a - b))
        .sum();
    (slope, (ss / n).sqrt() / (RHO * GRAVITY * still))
}

/// Least-squares slope of y on x with an intercept.
pub fn fitted_slope(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Least-squares slope of y = s·x through the origin and the R² of that fit.
pub fn slope_through_origin(xs: &[f64], ys: &[f64]) -> (f64, f64) {
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| x * y).sum();
    let sxx: f64 = xs.iter().map(|x| x * x).sum();
    let s = sxy / sxx;
    let mean = ys.iter().sum::<f64>() / ys.len() as f64;
    let ss_res: f64 = xs.iter().zip(ys).map(|(x, y)| (y - s * x).powi(2)).sum();
    let ss_tot: f64 = ys.iter().map(|y| (y - mean).powi(2)).sum();
    (s, 1.0 - ss_res / ss_tot)
}

/// Largest value of `ys` with `ts` in [t0, t1] and its time; (NaN, NaN) if none.
pub fn max_in_window(ts: &[f64], ys: &[f64], t0: f64, t1: f64) -> (f64, f64) {
    let mut best = (f64::NAN, f64::NAN);
    for (&t, &y) in ts.iter().zip(ys) {
        if t >= t0 && t <= t1 && y.is_finite() && (best.0.is_nan() || y > best.0) {
            best = (y, t);
        }
    }
    best
}

/// Root mean square of the finite values.
pub fn rms(ys: &[f64]) -> f64 {
    let v: Vec<f64> = ys.iter().copied().filter(|y| y.is_finite()).collect();
    (v.iter().map(|y| y * y).sum::<f64>() / v.len().max(1) as f64).sqrt()
}
