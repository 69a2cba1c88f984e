//! 3D checks, modern scheme: free-sloshing period of an upright cylinder for two
//! aspect ratios against ω₁² = (g ξ₁/R) tanh(ξ₁ H/R); the small-amplitude forced response and
//! base shear of a cylinder against the linear (Veletsos-type rigid tank) modal solution with
//! Housner's approximation beside it; a thin 3D box against the 2D code; the same cylinder
//! given as a closed OBJ mesh of its interior against theory and the built-in cylinder.

use super::run::{fitted_slope, rms, zero_crossings, Context, GRAVITY, RHO};
use super::sloshing::period_from_crossings;
use super::{
    failed_run, fmt_num, info_row, plot_path, relative_check, stayed_inside, Check, GroupResult,
    PlotRef, Verdict,
};
use crate::run::step_until;
use anyhow::Result;
use slosh_core::loads::base_shear_x;
use slosh_core::{Simulation, SphParams, PART_ROOF};
use slosh_geometry::{
    revolve_profile, BoxTank, CylinderLattice, CylinderTank, InitialSurface, MeshTank, Roof,
};
use slosh_io::{line_plot, PlotSpec, Series};
use slosh_theory::cylinder::{
    housner_cylinder_convective_mass_ratio, housner_cylinder_convective_omega,
    housner_cylinder_impulsive_mass_ratio, CylindricalTank,
};
use slosh_theory::modal::{sine_response, ModalTank};
use slosh_theory::natural::rectangular_period;

/// Period tolerance in 3D: 3 %. At 12–16 particles across the radius the kernel smoothing of
/// the surface (and, on the cubic lattice, the staircase of the curved wall) are a few per
/// cent.
const PERIOD_TOL_3D: f64 = 0.03;
/// 2D against 3D box: the same code in both dimensions; the box's side walls are free-slip
/// Adami walls, so the two runs differ only by the kernel's dimension and the side walls'
/// particles: 1.5 %. Holds for a start of ≥ 2 dx at the wall ([`BOX_TILT`]); below ≈ 1 dx the
/// SPH period of both runs is short by an amplitude-dependent amount, more in the 3-particle
/// box (measured at dx = 0.025 m: 2D −1.1 %, 3D −3.0 % at 0.02 m; −0.5 % and −0.9 % at 0.05 m).
const BOX_TOL: f64 = 0.015;
/// Initial elevation at the wall of the box comparison (m): 0.1 H = 2 dx, the relative start of
/// the 2D modern period check. At 0.02 m (0.8 dx) the surface is below one particle row: the
/// lattice carries it as a one-row step (2D cut) or a dithered staircase (3D error diffusion),
/// the two starts differ by 20 % in first-mode amplitude, and the small-amplitude bias of the
/// period (larger in the thin box, which also damps more) made the 3D box 1.9 % short of 2D.
const BOX_TILT: f64 = 0.05;
/// Forced response: normalised RMS difference of the wall elevation and base shear against
/// linear theory. Off resonance the response is linear and hardly damped; the windowed wall
/// pressure and the gauge at 12 particles per radius carry ≈ 10–15 % noise: 25 %.
const FORCED_TOL: f64 = 0.25;
/// Base shear against Housner's impulsive + convective model (time history from rest): the
/// forced tolerance plus 5 % for Housner's masses and frequency (within 3–5 % of potential
/// theory): 30 %.
const HOUSNER_SHEAR_TOL_3D: f64 = 0.30;
/// Modes of the linear solution.
const MODES: usize = 10;

/// The two cylinder groups (the thin box is its own stage, [`box_vs_2d`], so that
/// `--only "3D box"` runs it alone).
pub fn cylinder_groups(ctx: &Context) -> Vec<(String, GroupResult)> {
    vec![
        (
            "3D: cylinder free-sloshing period".into(),
            cylinder_periods(ctx),
        ),
        (
            "3D: cylinder forced response and base shear".into(),
            cylinder_forced(ctx),
        ),
    ]
}

/// Crossings of the liquid's centre of mass along x (about its mean) after the first one:
/// the period of the first mode (the start is the first-mode surface, so higher modes carry
/// almost nothing; the centre of mass is a volume integral, free of gauge noise).
pub(crate) struct ComHistory {
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Centre of mass x (m).
    pub x: Vec<f64>,
}

impl ComHistory {
    /// Mean period from the crossings of the mean (first crossing skipped), s.
    pub(crate) fn period(&self) -> f64 {
        let mean = self.x.iter().sum::<f64>() / self.x.len().max(1) as f64;
        let centred: Vec<f64> = self.x.iter().map(|x| x - mean).collect();
        let amp = centred.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let crossings = zero_crossings(&self.t, &centred, 0.2 * amp);
        period_from_crossings(&crossings[1.min(crossings.len())..])
    }

    /// The extreme of each half cycle about `centre` (m, the centre of mass at rest): times
    /// (s) and |x − centre| (m), each refined by a parabola through the three samples about
    /// the largest. The half cycles cut by the start and the end of the record are left out.
    pub(crate) fn half_cycle_peaks(&self, centre: f64) -> (Vec<f64>, Vec<f64>) {
        let y: Vec<f64> = self.x.iter().map(|x| x - centre).collect();
        let (mut ts, mut peaks) = (Vec::new(), Vec::new());
        // Sample index where the current half cycle began (None before the first crossing).
        let mut start: Option<usize> = None;
        for i in 1..y.len() {
            if (y[i] > 0.0) == (y[i - 1] > 0.0) {
                continue;
            }
            if let Some(s) = start {
                let best = (s..i)
                    .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
                    .unwrap_or(s);
                if best > 0 && best + 1 < y.len() {
                    let (a, b, c) = (y[best - 1].abs(), y[best].abs(), y[best + 1].abs());
                    let curvature = a - 2.0 * b + c;
                    let shift = if curvature < 0.0 {
                        (0.5 * (a - c) / curvature).clamp(-0.5, 0.5)
                    } else {
                        0.0
                    };
                    let dt = 0.5 * (self.t[best + 1] - self.t[best - 1]);
                    ts.push(self.t[best] + shift * dt);
                    peaks.push(b - 0.25 * (a - c) * shift);
                }
            }
            start = Some(i);
        }
        (ts, peaks)
    }

    /// Amplitude decay rate γ (1/s) of the oscillation about `centre`: minus the least-squares
    /// slope of ln(peak) against time over the half-cycle peaks that start at or after
    /// `from` (s). NaN with fewer than three peaks.
    pub(crate) fn decay_rate(&self, centre: f64, from: f64) -> f64 {
        let (ts, peaks) = self.half_cycle_peaks(centre);
        let (t, ln): (Vec<f64>, Vec<f64>) = ts
            .iter()
            .zip(&peaks)
            .filter(|(t, p)| **t >= from && **p > 0.0)
            .map(|(t, p)| (*t, p.ln()))
            .unzip();
        if t.len() < 3 {
            return f64::NAN;
        }
        -fitted_slope(&t, &ln)
    }
}

pub(crate) fn com_x<const D: usize>(sim: &Simulation<D>) -> f64 {
    let f = &sim.fluid().position;
    f.iter().map(|p| p[0]).sum::<f64>() / f.len() as f64
}

/// Runs a simulation without excitation to `t_end`, sampling the centre of mass every
/// `sample` s.
pub(crate) fn free_run<const D: usize>(
    sim: &mut Simulation<D>,
    t_end: f64,
    sample: f64,
) -> Result<(ComHistory, f64)> {
    free_run_observed(sim, t_end, sample, |_| {})
}

/// [`free_run`], calling `observe` with the simulation at every sample as well.
pub(crate) fn free_run_observed<const D: usize>(
    sim: &mut Simulation<D>,
    t_end: f64,
    sample: f64,
    mut observe: impl FnMut(&Simulation<D>),
) -> Result<(ComHistory, f64)> {
    let mut run = FreeRun::start(sim, sample);
    run.advance(sim, t_end, sample, |sim, _| observe(sim))?;
    Ok((run.history, run.particle_steps))
}

/// A free run as it goes: the centre-of-mass record so far, the time of its next sample and
/// the particle-steps taken.
pub(crate) struct FreeRun {
    /// Centre of mass sampled so far.
    pub history: ComHistory,
    /// Time of the next sample (s).
    pub next_sample: f64,
    /// Particle-steps taken so far.
    pub particle_steps: f64,
}

impl FreeRun {
    /// A run whose record starts with `sim` as it is, next sampled at `first_sample` (s).
    pub(crate) fn start<const D: usize>(sim: &Simulation<D>, first_sample: f64) -> Self {
        FreeRun {
            history: ComHistory {
                t: vec![sim.time()],
                x: vec![com_x(sim)],
            },
            next_sample: first_sample,
            particle_steps: 0.0,
        }
    }

    /// Steps `sim` without excitation to `t_end`, sampling the centre of mass at
    /// `next_sample` and every `sample` s after; `at_sample` is called after each sample
    /// with the simulation and the run.
    pub(crate) fn advance<const D: usize>(
        &mut self,
        sim: &mut Simulation<D>,
        t_end: f64,
        sample: f64,
        mut at_sample: impl FnMut(&Simulation<D>, &FreeRun),
    ) -> Result<()> {
        let n_all = (sim.fluid().position.len() + sim.walls().position.len()) as f64;
        step_until(
            sim,
            |_| [0.0; 3],
            t_end,
            "stopped",
            |sim| {
                self.particle_steps += n_all;
                if sim.time() >= self.next_sample {
                    self.next_sample += sample;
                    self.history.t.push(sim.time());
                    self.history.x.push(com_x(sim));
                    at_sample(sim, self);
                }
                Ok(())
            },
        )
    }
}

/// First-mode period of cylinders of H/R = 1 and 0.5 (modern scheme, first-mode start).
fn cylinder_periods(ctx: &Context) -> GroupResult {
    let group = "3D period";
    let mut g = GroupResult::default();
    let mut curves = Vec::new();
    for (radius, depth, dx) in [(0.5, 0.5, 0.04), (0.4, 0.2, 0.025)] {
        let run = || -> Result<(f64, f64, f64, ComHistory, Check, f64)> {
            let setup = CylinderTank::new(radius, depth + 0.2, depth, Roof::None)
                .with_initial_tilt(0.02 * radius)
                .with_initial_shape(InitialSurface::FirstMode)
                .with_layers(SphParams::modern().wall_layers())
                .with_lattice(CylinderLattice::Polar)
                .build(dx)?;
            let mut sim = Simulation::new(setup, SphParams::modern().with_paper_stiffness())?;
            let fill = sim.fill_level();
            let theory = CylindricalTank::new(radius, fill, RHO, GRAVITY);
            let t1 = 2.0 * std::f64::consts::PI / theory.modal_omega(0);
            ctx.say(&format!(
                "3D cylinder R = {radius} m, H = {fill:.3} m, dx = {dx} m, {} + {} particles, 2.6 T₁",
                sim.fluid().position.len(),
                sim.walls().position.len()
            ));
            let (h, steps) = free_run(&mut sim, 2.6 * t1, t1 / 100.0)?;
            let inside = stayed_inside(group, &sim);
            Ok((h.period(), t1, fill, h, inside, steps))
        };
        match run() {
            Ok((measured, t1, fill, h, inside, steps)) => {
                g.particle_steps += steps;
                g.checks.push(inside);
                g.checks.push(relative_check(
                    group,
                    &format!(
                        "period, R = {radius} m, H = {fill:.3} m (H/R = {:.2}), dx = {dx} m",
                        fill / radius
                    ),
                    measured,
                    t1,
                    "s",
                    PERIOD_TOL_3D,
                    "3 %: 12–16 particles per radius; surface smoothing",
                ));
                let x0 = h.x[0];
                curves.push((
                    format!("R = {radius} m, H = {fill:.2} m"),
                    h.t.iter().map(|t| t / t1).collect::<Vec<_>>(),
                    h.x.iter().map(|x| x / x0).collect::<Vec<_>>(),
                ));
            }
            Err(e) => g.checks.push(failed_run(
                group,
                &format!("cylinder R = {radius} m, H = {depth} m"),
                &format!("{e:#}"),
            )),
        }
    }
    let stem = "cylinder_free_sloshing";
    let series: Vec<Series> = curves
        .iter()
        .map(|(l, x, y)| Series::line(l.clone(), x, y))
        .collect();
    g.add_line_plot(
        &ctx.out,
        stem,
        &PlotSpec::new(
            "Cylinder free sloshing (modern scheme), first-mode start",
            "t / T₁ (theory) (-)",
            "centre of mass x / initial (-)",
        ),
        &series,
        "normalised centre-of-mass oscillation of the two cylinders",
    );
    g.notes.push(
        "Start: the first mode's surface −(x/r) J₁(ξ₁ r/R)/J₁(ξ₁) with 0.02 R at the wall, on \
         the lattice by error diffusion; theory for the depth the lattice holds (whole rows). \
         Period from the zero crossings of the liquid's centre of mass along x."
            .into(),
    );
    g
}

/// Facets around the axis of the mesh cylinder: 72 (5° each, the chord 1 mm short of the
/// circle at R = 0.5 m), a coarse CAD-like export rather than the built-in shape's facets of
/// ≤ dx with a chord error ≤ dx/1000.
const MESH_CYLINDER_SEGMENTS: usize = 72;

/// Free-sloshing period of an upright cylinder R = H = 0.5 m given as a closed OBJ mesh of its
/// interior (`MeshTank`), against ω₁² = (g ξ₁/R) tanh(ξ₁ H/R), with the built-in cylinder of
/// the same size, roof, start and dx beside it (the first row of the period stage).
pub fn mesh_cylinder_period(ctx: &Context) -> GroupResult {
    let group = "3D mesh tank";
    GroupResult::or_failed_run(group, mesh_cylinder_inner(ctx, group))
}

fn mesh_cylinder_inner(ctx: &Context, group: &str) -> Result<GroupResult> {
    let (radius, depth, dx) = (0.5, 0.5, 0.04);
    let height = depth + 0.2;
    let mut g = GroupResult::default();
    std::fs::create_dir_all(&ctx.out)?;
    let path = ctx.out.join("mesh_cylinder_R0.5_H0.7.obj");
    let profile = [[0.0, 0.0], [radius, 0.0], [radius, height], [0.0, height]];
    revolve_profile(&profile, false, MESH_CYLINDER_SEGMENTS, 0.05).write_obj(
        &path,
        "upright cylinder R = 0.5 m, height 0.7 m, 72 facets around; units m, normals out of the liquid",
    )?;
    let tilt = 0.02 * radius;
    let mesh_setup = MeshTank::new(&path, depth)
        .with_initial_tilt(tilt)
        .with_cylinder_mode(radius)
        .with_layers(SphParams::modern().wall_layers())
        .build(dx)?;
    let built_in = CylinderTank::new(radius, height, depth, Roof::Flat)
        .with_initial_tilt(tilt)
        .with_initial_shape(InitialSurface::FirstMode)
        .with_layers(SphParams::modern().wall_layers())
        .build(dx)?;
    let mut periods = Vec::new();
    let mut curves = Vec::new();
    for (label, setup) in [("mesh (OBJ)", mesh_setup), ("built-in", built_in)] {
        let mut sim = Simulation::new(setup, SphParams::modern().with_paper_stiffness())?;
        let fill = sim.fill_level();
        let theory = CylindricalTank::new(radius, fill, RHO, GRAVITY);
        let t1 = 2.0 * std::f64::consts::PI / theory.modal_omega(0);
        ctx.say(&format!(
            "{label} cylinder R = {radius} m, H = {fill:.3} m, dx = {dx} m, {} + {} particles, 2.6 T₁",
            sim.fluid().position.len(),
            sim.walls().position.len()
        ));
        let (h, steps) = free_run(&mut sim, 2.6 * t1, t1 / 100.0)?;
        g.particle_steps += steps;
        g.checks.push(stayed_inside(group, &sim));
        let measured = h.period();
        g.checks.push(relative_check(
            group,
            &format!("period, {label} cylinder R = {radius} m, H = {fill:.3} m, dx = {dx} m"),
            measured,
            t1,
            "s",
            PERIOD_TOL_3D,
            "3 %, the built-in cylinder's tolerance: 12.5 particles per radius; staircase wall \
             and surface smoothing",
        ));
        periods.push(measured);
        let x0 = h.x[0];
        curves.push((
            label.to_string(),
            h.t.iter().map(|t| t / t1).collect::<Vec<_>>(),
            h.x.iter().map(|x| x / x0).collect::<Vec<_>>(),
        ));
    }
    g.checks.push(info_row(
        group,
        "period, mesh against built-in cylinder",
        format!("{:.4} s", periods[0]),
        format!("{:.4} s", periods[1]),
        format!("{:+.2} %", 100.0 * (periods[0] / periods[1] - 1.0)),
        "the same tank from a 72-facet OBJ and from the built-in shape (facets ≤ dx)",
    ));
    g.add_line_plot(
        &ctx.out,
        "mesh_cylinder_free_sloshing",
        &PlotSpec::new(
            "Cylinder as a mesh and built in: free sloshing (modern scheme)",
            "t / T₁ (theory) (-)",
            "centre of mass x / initial (-)",
        ),
        &curves
            .iter()
            .map(|(l, x, y)| Series::line(l.clone(), x, y))
            .collect::<Vec<_>>(),
        "normalised centre-of-mass oscillation, mesh and built-in cylinder",
    );
    g.notes.push(
        "Both tanks closed 0.2 m above the liquid; start: the first mode's surface with 0.02 R \
         at the wall; theory for the depth the lattice holds. The mesh is written by the stage \
         (revolve_profile, 72 facets around)."
            .into(),
    );
    Ok(g)
}

/// Sine excitation off resonance: wall elevation and base shear against linear theory.
fn cylinder_forced(ctx: &Context) -> GroupResult {
    let group = "3D forced";
    GroupResult::or_failed_run(
        group,
        cylinder_forced_inner(ctx, group, &ForcedCylinder::LAB),
    )
}

/// A cylinder under a sine at 0.8 ω₁ (flat roof well above the wave), the modern preset.
pub(crate) struct ForcedCylinder {
    /// Inner radius R (m).
    pub radius: f64,
    /// Still depth (m).
    pub depth: f64,
    /// Height of the flat roof (m).
    pub roof_height: f64,
    /// Lattice spacing (m).
    pub dx: f64,
    /// Ground displacement amplitude A (m).
    pub amplitude: f64,
    /// Rest before the excitation (s).
    pub settle: f64,
    /// Excitation time compared with theory (s).
    pub excitation_time: f64,
    /// The EOS stiffness of the paper (the laboratory check) or the case's rule.
    pub paper_stiffness: bool,
    /// Prefix of the plot files.
    pub stem: &'static str,
}

impl ForcedCylinder {
    /// The laboratory cylinder: R = H = 0.5 m, A = 5 mm, 12.5 particles per radius.
    pub const LAB: ForcedCylinder = ForcedCylinder {
        radius: 0.5,
        depth: 0.5,
        roof_height: 0.8,
        dx: 0.04,
        amplitude: 0.005,
        settle: 0.3,
        excitation_time: 4.0,
        paper_stiffness: true,
        stem: "cylinder",
    };
}

pub(crate) fn cylinder_forced_inner(
    ctx: &Context,
    group: &str,
    case: &ForcedCylinder,
) -> Result<GroupResult> {
    let (radius, depth, dx) = (case.radius, case.depth, case.dx);
    let setup = CylinderTank::new(radius, case.roof_height, depth, Roof::Flat)
        .with_layers(SphParams::modern().wall_layers())
        .with_lattice(CylinderLattice::Polar)
        .build(dx)?;
    let params = if case.paper_stiffness {
        SphParams::modern().with_paper_stiffness()
    } else {
        SphParams::modern()
    };
    let mut sim = Simulation::new(setup, params)?;
    let fill = sim.fill_level();
    let still = sim.still_level();
    let theory = CylindricalTank::new(radius, fill, RHO, GRAVITY);
    let omega = 0.8 * theory.modal_omega(0);
    let amplitude = case.amplitude;
    let force = -amplitude * omega * omega;
    let settle = case.settle;
    let t_end = settle + case.excitation_time;
    let span = format!("0–{} s", fmt_num(case.excitation_time));
    let roof = sim.part_names().iter().position(|n| n == PART_ROOF);
    let n_all = (sim.fluid().position.len() + sim.walls().position.len()) as f64;
    let gauge = -radius + dx;
    ctx.say(&format!(
        "3D cylinder forced: ω = {omega:.3} rad/s = 0.8 ω₁, A = {amplitude} m, {} + {} particles",
        sim.fluid().position.len(),
        sim.walls().position.len()
    ));
    let (mut te, mut eta, mut eta_lin) = (Vec::new(), Vec::new(), Vec::new());
    let (mut tb, mut shear, mut shear_lin) = (Vec::new(), Vec::new(), Vec::new());
    let mut last = None;
    let mut steps = 0.0;
    let mut next = 0.0;
    let ground = |t: f64| {
        let t = t - settle;
        let a = if t < 0.0 {
            0.0
        } else {
            amplitude * omega * omega * (omega * t).sin()
        };
        [a, 0.0, 0.0]
    };
    step_until(&mut sim, ground, t_end, "stopped", |sim| {
        steps += n_all;
        let t = sim.time() - settle;
        if t >= 0.0 && sim.time() >= next {
            next = sim.time() + 0.0025 * case.excitation_time;
            if let Some(z) = sim.surface_level_at(&[gauge, 0.0]) {
                let s = sine_response(&theory, force, omega, t, MODES);
                te.push(t);
                eta.push(z - still);
                eta_lin.push(theory.elevation(&s, radius - dx, std::f64::consts::PI));
            }
        }
        if let Some(c) = sim.loads().centred() {
            if last != Some(c.step) {
                last = Some(c.step);
                let tc = c.time - settle;
                if tc >= 0.0 {
                    let s = sine_response(&theory, force, omega, tc, MODES);
                    tb.push(tc);
                    shear.push(base_shear_x(c, roof));
                    shear_lin.push(theory.base_shear(&s));
                }
            }
        }
        Ok(())
    })?;
    let mut g = GroupResult {
        particle_steps: steps,
        ..GroupResult::default()
    };
    g.checks.push(stayed_inside(group, &sim));
    let nrms = |a: &[f64], b: &[f64]| {
        let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
        rms(&d) / rms(b)
    };
    let e_eta = nrms(&eta, &eta_lin);
    let e_shear = nrms(&shear, &shear_lin);
    for (name, e) in [
        (format!("wall elevation at x = −R + dx, {span}"), e_eta),
        (format!("base shear (floor + shell), {span}"), e_shear),
    ] {
        g.checks.push(Check {
            group: group.into(),
            name: format!("normalised RMS difference from linear theory: {name}"),
            measured: format!("{e:.3}"),
            reference: "0".into(),
            error: format!("{:.1} %", 100.0 * e),
            tolerance: format!("≤ {:.0} %", 100.0 * FORCED_TOL),
            reason: format!(
                "off resonance the response is linear; gauge and windowed-pressure noise at \
                 12 particles per radius ≈ 10–15 % (this run: {:.0} per radius)",
                radius / dx
            ),
            verdict: if e.is_finite() && e <= FORCED_TOL {
                Verdict::Pass
            } else {
                Verdict::Fail
            },
        });
    }
    // Housner (1963): impulsive + first convective mass on springs, peak base shear for this
    // harmonic excitation (steady state, undamped): V = m_i A ω² + m_c A ω² /(1 − (ω/ω_c)²).
    let mass = theory.liquid_mass();
    let m_i = housner_cylinder_impulsive_mass_ratio(radius, fill) * mass;
    let m_c = housner_cylinder_convective_mass_ratio(radius, fill) * mass;
    let w_c = housner_cylinder_convective_omega(radius, fill, GRAVITY);
    let acc = amplitude * omega * omega;
    let v_housner = m_i * acc + m_c * acc / (1.0 - (omega / w_c).powi(2)).abs();
    // The same mechanical model as a time history from rest (transient included): the
    // convective mass's displacement relative to the tank, ẍ + ω_c² x = f(t), f = F sin ωt,
    // x = F/(ω_c² − ω²) (sin ωt − (ω/ω_c) sin ω_c t); base shear V = m_i f + m_c ω_c² x.
    let shear_housner: Vec<f64> = tb
        .iter()
        .map(|&t| {
            let f = force * (omega * t).sin();
            let x = force / (w_c * w_c - omega * omega)
                * ((omega * t).sin() - omega / w_c * (w_c * t).sin());
            m_i * f + m_c * w_c * w_c * x
        })
        .collect();
    let e_housner = nrms(&shear, &shear_housner);
    g.checks.push(Check {
        group: group.into(),
        name: format!(
            "normalised RMS difference of the base shear from Housner's model (impulsive + \
             convective mass, transient from rest), {span}"
        ),
        measured: format!("{e_housner:.3}"),
        reference: "0".into(),
        error: format!("{:.1} %", 100.0 * e_housner),
        tolerance: format!("≤ {:.0} %", 100.0 * HOUSNER_SHEAR_TOL_3D),
        reason: "the 25 % of the comparison with linear theory plus 5 % for Housner's masses and \
                 frequency (within 3–5 % of potential theory, Housner 1963)"
            .into(),
        verdict: if e_housner.is_finite() && e_housner <= HOUSNER_SHEAR_TOL_3D {
            Verdict::Pass
        } else {
            Verdict::Fail
        },
    });
    g.checks.push(info_row(
        group,
        "Housner's model against linear theory (both from rest): normalised RMS difference of \
         the base shear",
        format!("{:.3}", nrms(&shear_housner, &shear_lin)),
        "0".into(),
        "-".into(),
        "reported: how far the two-mass approximation is from the 10-mode potential solution",
    ));
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    g.checks.push(info_row(
        group,
        "peak |base shear|: SPH (linear theory, transient included)",
        format!(
            "{} N ({} N)",
            fmt_num(peak(&shear)),
            fmt_num(peak(&shear_lin))
        ),
        format!("{} N (Housner, steady state)", fmt_num(v_housner)),
        format!("ratio SPH/Housner {:.2}", peak(&shear) / v_housner),
        "reported: Housner's steady-state amplitude has no start-up transient (the beating \
         of the free and forced response can exceed it)",
    ));
    let stem = format!("{}_forced", case.stem);
    let title = format!(
        "Cylinder R = {} m, H = {} m, sine at 0.8 ω₁",
        fmt_num(radius),
        fmt_num(depth)
    );
    let _ = line_plot(
        plot_path(&ctx.out, &stem),
        &PlotSpec::new(
            format!("{title}: wall elevation"),
            "time since excitation start t (s)",
            "η at x = −R + dx (m)",
        ),
        &[
            Series::line(format!("SPH (modern scheme, dx = {dx} m)"), &te, &eta),
            Series::dashed("linear theory (10 modes)", &te, &eta_lin),
        ],
    );
    let stem2 = format!("{}_base_shear", case.stem);
    let _ = line_plot(
        plot_path(&ctx.out, &stem2),
        &PlotSpec::new(
            format!("{title}: base shear"),
            "time since excitation start t (s)",
            "base shear V_x (N)",
        ),
        &[
            Series::line("SPH (floor + shell, ±20-step window)", &tb, &shear),
            Series::dashed("linear theory (10 modes)", &tb, &shear_lin),
            Series::dashed(
                "Housner (impulsive + convective mass, from rest)",
                &tb,
                &shear_housner,
            ),
        ],
    );
    for (s, c) in [
        (
            &stem,
            "wall elevation of the forced cylinder against linear theory",
        ),
        (
            &stem2,
            "base shear of the forced cylinder against linear theory",
        ),
    ] {
        g.plots.push(PlotRef {
            file: format!("{s}.png"),
            caption: c.into(),
        });
    }
    g.notes.push(format!(
        "Cylinder R = {radius} m, H = {fill:.3} m, flat roof at {} m, dx = {dx} m, modern \
         scheme (c0 = {:.1} m/s); a_g = A ω² sin ωt, A = {amplitude} m, ω = {omega:.3} rad/s \
         after {settle} s at rest. Housner masses: impulsive {m_i:.4e} kg, convective \
         {m_c:.4e} kg of {mass:.4e} kg.",
        case.roof_height,
        sim.sound_speed()
    ));
    Ok(g)
}

/// A box 1.0 m long, 3 particles deep, against the 2D tank of the same section.
pub fn box_vs_2d(ctx: &Context) -> GroupResult {
    let group = "3D box vs 2D";
    let mut g = GroupResult::default();
    let (width, depth, height, dx) = (1.0, 0.5, 0.7, 0.025);
    let tilt = BOX_TILT;
    let t1 = rectangular_period(width, depth, GRAVITY, 1);
    let run = || -> Result<(f64, f64, ComHistory, ComHistory, Check, f64)> {
        let setup3 = BoxTank::new(width, 3.0 * dx, height, depth)
            .with_initial_tilt(tilt)
            .with_initial_shape(InitialSurface::FirstMode)
            .with_layers(SphParams::modern().wall_layers())
            .build(dx)?;
        let mut sim3 = Simulation::new(setup3, SphParams::modern().with_paper_stiffness())?;
        let setup2 = slosh_geometry::RectTank2::new(width, height, depth)
            .with_initial_tilt(tilt)
            .with_initial_shape(InitialSurface::FirstMode)
            .with_layers(SphParams::modern().wall_layers())
            .build(dx)?;
        let mut sim2 = Simulation::new(setup2, SphParams::modern().with_paper_stiffness())?;
        ctx.say(&format!(
            "3D box {width} × {} × {depth} m ({} + {} particles) against 2D ({} + {})",
            3.0 * dx,
            sim3.fluid().position.len(),
            sim3.walls().position.len(),
            sim2.fluid().position.len(),
            sim2.walls().position.len()
        ));
        let (h3, s3) = free_run(&mut sim3, 2.6 * t1, t1 / 100.0)?;
        let (h2, s2) = free_run(&mut sim2, 2.6 * t1, t1 / 100.0)?;
        Ok((
            h3.period(),
            h2.period(),
            h3,
            h2,
            stayed_inside(group, &sim3),
            s3 + s2,
        ))
    };
    match run() {
        Ok((p3, p2, h3, h2, inside, steps)) => {
            g.particle_steps = steps;
            g.checks.push(inside);
            g.checks.push(relative_check(
                group,
                "first-mode period, 3D box against the 2D run",
                p3,
                p2,
                "s",
                BOX_TOL,
                "1.5 %: the same solver in 2D and 3D; free-slip side walls; the kernel's \
                 dimension and the side walls' particles differ (start ≥ 2 dx, see notes)",
            ));
            g.checks.push(info_row(
                group,
                "2D and 3D periods against potential theory",
                format!("{} s / {} s", fmt_num(p2), fmt_num(p3)),
                format!("{} s", fmt_num(t1)),
                format!(
                    "{:+.2} % / {:+.2} %",
                    100.0 * (p2 / t1 - 1.0),
                    100.0 * (p3 / t1 - 1.0)
                ),
                "reported",
            ));
            let stem = "box_vs_2d";
            let norm = |h: &ComHistory| -> (Vec<f64>, Vec<f64>) {
                let c = 0.5 * width;
                let x0 = h.x[0] - c;
                (
                    h.t.iter().map(|t| t / t1).collect(),
                    h.x.iter().map(|x| (x - c) / x0).collect(),
                )
            };
            let (a, b) = norm(&h2);
            let (c, d) = norm(&h3);
            g.add_line_plot(
                &ctx.out,
                stem,
                &PlotSpec::new(
                    "Free sloshing 1.0 × 0.5 m: 2D against a thin 3D box (modern scheme)",
                    "t / T₁ (theory) (-)",
                    "centre of mass x − L/2, normalised (-)",
                ),
                &[Series::line("2D", &a, &b), Series::dashed("3D box", &c, &d)],
                "centre of mass of the 2D and 3D runs",
            );
        }
        Err(e) => g.checks.push(failed_run(group, "run", &format!("{e:#}"))),
    }
    g.notes.push(format!(
        "Box {width} m long, {:.3} m (3 particles) deep, walled on all sides (free-slip Adami \
         walls), against the 2D tank of the same section; dx = {dx} m, first-mode start of \
         {tilt} m ({:.0} dx). Smaller starts are not a fair test: below ≈ 1 dx the SPH period \
         depends on the amplitude (measured 3D/2D gap −1.9 % at 0.02 m, −0.3 % at 0.04 m) and \
         the lattice represents the start differently in 2D and 3D.",
        3.0 * dx,
        tilt / dx
    ));
    g
}

#[cfg(test)]
mod tests {
    use super::ComHistory;

    /// A damped cosine x = c + A e^{−γt} cos ωt has successive half-cycle peaks in the exact
    /// ratio e^{−γπ/ω}, wherever the sampling puts them; sampled at T/100 the parabola through
    /// three samples places each peak within ≈ 10⁻⁴ of the amplitude: γ within 0.5 %.
    #[test]
    fn decay_rate_recovers_a_damped_cosine() {
        let (centre, amp, gamma, omega) = (0.5, 0.01, 0.12, 5.3);
        let dt = 2.0 * std::f64::consts::PI / omega / 100.0;
        let t: Vec<f64> = (0..1200).map(|i| i as f64 * dt).collect();
        let x = t
            .iter()
            .map(|&t| centre + amp * (-gamma * t).exp() * (omega * t).cos())
            .collect();
        let h = ComHistory { t, x };
        let measured = h.decay_rate(centre, 0.0);
        assert!((measured / gamma - 1.0).abs() < 5e-3, "{measured}");
        let (ts, peaks) = h.half_cycle_peaks(centre);
        // 12 periods: 23 whole half cycles after the first crossing.
        assert!(peaks.len() >= 22, "{}", peaks.len());
        assert!(ts.windows(2).all(|w| w[1] > w[0]));
    }
}
