//! Real tanks at real size, with the sound speed chosen from the tank (c0 = 10 √(g H_ref),
//! `slosh_core::sound_speed`): Froude similarity between the paper's tank and the same tank
//! 25 times larger; hydrostatics under 20 m of liquid; free sloshing of 2D sections and of a
//! 24 m cylinder against potential theory, with the numerical damping beside EN 1998-4's
//! 0.5 %; a forced real-scale cylinder against the linear modal solution and Housner.

use super::resume::free_run_resumable;
use super::run::{
    fitted_slope, hydrostatic_fit, interpolate, rms, Context, Runner, SineExcitation, GRAVITY, RHO,
};
use super::three_d::{cylinder_forced_inner, free_run, free_run_observed, ForcedCylinder};
use super::{
    failed_run, fmt_num, info_row, open_if_failed, relative_check, stayed_inside, Check,
    GroupResult, Verdict,
};
use crate::run::step_until;
use anyhow::Result;
use slosh_core::{
    NeighbourBackend, Simulation, SphParams, WallPressureMethod, PART_BOTTOM, PART_WALL,
};
use slosh_geometry::{CylinderLattice, CylinderTank, InitialSurface, RectTank2, Roof};
use slosh_io::{PlotSpec, Series};
use slosh_theory::cylinder::CylindricalTank;
use slosh_theory::modal::ModalTank;
use slosh_theory::natural::rectangular_period;

/// Length scale of the Froude check: the paper's 1 m tank becomes 25 m wide.
const FROUDE_SCALE: f64 = 25.0;
/// Froude similarity: RMS of the difference of η/H over the RMS of the lab signal. With the
/// sound speed scaled as √λ every term of the scheme is similar except the physical viscosity
/// (Reynolds number ×125, a term of relative size ν/(U L) ≈ 2×10⁻⁵ here) and round-off, which
/// the particle motion amplifies: 2 %.
const FROUDE_TOL: f64 = 0.02;
/// First-mode period at real scale: 1.5 %, the tolerance of the modern preset's laboratory
/// check (Adami walls hold the liquid dx/2 from the wall; what remains is resolution).
const PERIOD_TOL: f64 = 0.015;
/// First-mode period of the real-scale section run with no numerics override: 2 %, what the
/// sound-speed rule must deliver in either scheme (the paper scheme's own laboratory
/// tolerance is 5 %).
const FIRST_RUN_PERIOD_TOL: f64 = 0.02;
/// Hydrostatic slope dp/d(ρ0 g d) under 20 m of liquid: 1 % (the density varies by
/// g H/c0² ≤ 1 % with the rule's c0; the slope is a least-squares fit over every particle).
const SLOPE_TOL: f64 = 0.01;
/// Still level under 20 m of liquid against the fill: 0.5 % (the Tait compression with
/// c0 = 10 √(g H_ref) is H/(2·100·H_ref) ≤ 0.5 % of the depth).
const STILL_LEVEL_TOL: f64 = 0.005;
/// Time (s) at the end of the hydrostatics run over which the slopes and the floor force are
/// averaged: the liquid started on a square lattice is never quite at rest (the lattice
/// rearranges in the first seconds; the floor force then swings by ±1.5 % with a period of
/// ≈ 1.6 s under 20 m), so a single instant is not a measurement.
const HYDROSTATIC_AVERAGE: f64 = 4.0;
/// Why the paper scheme's wall loads at rest are reported, not judged, at real scale: the
/// reading belongs to the paper's method and shows in its laboratory tank too.
const PAPER_METHOD_GAP: &str = "the paper scheme's wall loads are read from the pressure of \
    the liquid beside the wall (summation density with dynamic wall particles, Eq. 19, whose \
    particle pressures scatter by ≈ 20 % of ρ g H at rest), and that reading lies below ρ0 g d \
    in the paper's own tank as well, while its particles' own slope over the tank is within \
    1 %; the modern preset (Adami walls, docs/scheme.md) is the scheme judged at real scale";
/// What is known of a real-scale forced comparison beyond the laboratory tolerance.
const FORCED_GAP: &str = "on the polar lattice this cylinder damps its first mode by ζ = \
    0.24 % at 24 particles per radius and the wall elevation and base shear came within 7.5 % \
    and 3.5 % of undamped linear theory (10.4 % and 8.2 % on the cubic lattice, 18–25 % with \
    h = 1.5 dx); undamped theory keeps the free transient the SPH damps over the 19.6 s (3.8 \
    periods), so a miss here is that damping come back";
/// EN 1998-4 (Annex A) assumes 0.5 % damping for the convective mode.
const EC8_CONVECTIVE_DAMPING: f64 = 0.005;

/// The presets with the sound speed from the case (the laboratory checks pin the paper's).
fn presets() -> [(&'static str, SphParams); 2] {
    [
        (
            "paper scheme",
            SphParams {
                wall_pressure: WallPressureMethod::KernelExtrapolation,
                ..SphParams::paper()
            },
        ),
        ("modern scheme", SphParams::modern()),
    ]
}

/// The §3.1 case (1.0 m wide, 0.5 m of water, roof at 1.0 m, A = 9.3 mm, ω = 5.311 rad/s)
/// scaled by `scale` (lengths × λ, times × √λ), run with `params`; returns the samples
/// (t √(g/H), η_left/H) and the particle-steps.
fn paper_case_scaled(
    ctx: &Context,
    label: &str,
    params: &SphParams,
    scale: f64,
    settle_lab: f64,
    excitation_lab: f64,
) -> Result<ScaledRun> {
    let (width, height, depth, dx) = (1.0 * scale, 1.0 * scale, 0.5 * scale, 0.02 * scale);
    let setup = RectTank2::new(width, height, depth)
        .with_layers(params.wall_layers())
        .build(dx)?;
    let sim = Simulation::new(setup, params.clone())?;
    let time_scale = scale.sqrt();
    let excitation = SineExcitation {
        amplitude: 0.0093 * scale,
        omega: 5.311 / time_scale,
        settle: settle_lab * time_scale,
    };
    ctx.say(&format!(
        "{label}: §3.1 tank ×{scale}, {width} × {depth} m, dx = {dx} m, c0 = {:.1} m/s",
        sim.sound_speed()
    ));
    let mut runner = Runner::new(sim, excitation, 0.01 * time_scale);
    runner.run_until((settle_lab + excitation_lab) * time_scale, |_| {})?;
    let tau = (GRAVITY / depth).sqrt();
    let t: Vec<f64> = runner.history.t.iter().map(|t| t * tau).collect();
    let eta: Vec<f64> = runner.history.eta_left.iter().map(|e| e / depth).collect();
    Ok(ScaledRun {
        t,
        eta,
        particle_steps: runner.history.particle_steps,
        sound_speed: runner.sim.sound_speed(),
    })
}

/// One run of [`paper_case_scaled`] in Froude units.
struct ScaledRun {
    /// t √(g/H) (-).
    t: Vec<f64>,
    /// η at the left wall / H (-).
    eta: Vec<f64>,
    particle_steps: f64,
    /// c0 (m/s).
    sound_speed: f64,
}

impl ScaledRun {
    /// RMS of (other − self) at this run's times over the RMS of this run's signal.
    fn difference(&self, other: &ScaledRun) -> f64 {
        let diff: Vec<f64> = self
            .t
            .iter()
            .zip(&self.eta)
            .map(|(t, e)| interpolate(&other.t, &other.eta, *t) - e)
            .collect();
        rms(&diff) / rms(&self.eta)
    }
}

/// The paper's §3.1 tank and the same tank 25 times larger at the same particle count, both
/// schemes: η/H against t √(g/H).
pub fn froude_similarity(ctx: &Context) -> GroupResult {
    let group = "Froude similarity";
    let mut g = GroupResult::default();
    let (settle, excitation) = if ctx.quick { (1.0, 3.0) } else { (2.0, 10.0) };
    let mut curves: Vec<(String, Vec<f64>, Vec<f64>)> = Vec::new();
    for (label, params) in presets() {
        let mut run = || -> Result<(f64, f64, f64, f64, f64)> {
            let lab = paper_case_scaled(ctx, label, &params, 1.0, settle, excitation)?;
            let big = paper_case_scaled(ctx, label, &params, FROUDE_SCALE, settle, excitation)?;
            // The same laboratory run with the k-d tree search: only the order of the sums
            // changes, so the difference is the scheme's own sensitivity to round-off.
            let reordered = SphParams {
                neighbour_backend: NeighbourBackend::KdTree,
                ..params.clone()
            };
            let lab2 = paper_case_scaled(ctx, label, &reordered, 1.0, settle, excitation)?;
            let error = lab.difference(&big);
            let spread = lab.difference(&lab2);
            let steps = lab.particle_steps + big.particle_steps + lab2.particle_steps;
            let (c_lab, c_big) = (lab.sound_speed, big.sound_speed);
            curves.push((format!("{label}, 1 m tank"), lab.t, lab.eta));
            curves.push((format!("{label}, 25 m tank"), big.t, big.eta));
            Ok((error, spread, steps, c_lab, c_big))
        };
        match run() {
            Ok((error, spread, steps, c_lab, c_big)) => {
                g.particle_steps += steps;
                let tolerance = FROUDE_TOL + spread;
                g.checks.push(Check {
                    group: group.into(),
                    name: format!(
                        "{label}: η_left/H against t √(g/H), 25 m tank vs 1 m tank \
                         (c0 {} / {} m/s), RMS difference over RMS of the 1 m signal",
                        fmt_num(c_big),
                        fmt_num(c_lab)
                    ),
                    measured: format!("{:.2} %", 100.0 * error),
                    reference: "0".into(),
                    error: format!("{:.2} %", 100.0 * error),
                    tolerance: format!(
                        "≤ {:.0} % + round-off spread {:.2} % = {:.2} %",
                        100.0 * FROUDE_TOL,
                        100.0 * spread,
                        100.0 * tolerance
                    ),
                    reason: "with c0 ∝ √(g H) every term is Froude-similar except the \
                             physical viscosity (ν/(U L) ≈ 2×10⁻⁵): 2 %; no comparison can \
                             be closer than the scheme's own round-off spread (the 1 m run \
                             with the sums in another order), which is added"
                        .into(),
                    verdict: if error.is_finite() && error <= tolerance {
                        Verdict::Pass
                    } else {
                        Verdict::Fail
                    },
                });
                g.checks.push(info_row(
                    group,
                    &format!(
                        "{label}: round-off spread, the 1 m run with the k-d tree search \
                         (summation order) against the grid"
                    ),
                    format!("{:.2} %", 100.0 * spread),
                    "0".into(),
                    "-".into(),
                    "reported: how far the scheme's gauge signal moves under round-off alone \
                     (the paper scheme's free-surface reset and pressure clamp switch on \
                     round-off-level differences)",
                ));
            }
            Err(e) => g.checks.push(failed_run(group, label, &format!("{e:#}"))),
        }
    }
    let series: Vec<Series> = curves
        .iter()
        .enumerate()
        .map(|(k, (l, t, e))| {
            if k % 2 == 0 {
                Series::line(l.clone(), t, e)
            } else {
                Series::dashed(l.clone(), t, e)
            }
        })
        .collect();
    g.add_line_plot(
        &ctx.out,
        "froude_similarity",
        &PlotSpec::new(
            "Paper §3.1 case at 1 m and 25 m, sound speed from the tank",
            "t √(g/H) (-)",
            "η at the left wall / H (-)",
        ),
        &series,
        "the §3.1 case and the same case 25 times larger, both schemes, in Froude units",
    );
    g.notes.push(format!(
        "The 1 m case: width 1.0 m, roof at 1.0 m, 0.5 m of water, dx = 0.02 m, {settle} s at \
         rest, then A = 9.3 mm, ω = 5.311 rad/s for {excitation} s. The 25 m case: every \
         length × 25, ω ÷ 5, times × 5, the same 1,250 fluid particles. Both with the sound \
         speed of the rule c0 = 10 √(g H_ref), H_ref the 1 m / 25 m roof height."
    ));
    g
}

/// What a run at rest gives (see [`rest_reading`]).
struct RestReading {
    /// Least-squares slope of the side-wall pressures (the reported load) against ρ0 g d.
    wall_slope: f64,
    /// The same slope of every particle's pressure.
    particle_slope: f64,
    /// Floor force over the liquid's weight.
    floor_load: f64,
    /// Surface level (m), fill (m) and the level the Tait EOS predicts (m).
    level: f64,
    fill: f64,
    predicted: f64,
    particle_steps: f64,
}

/// An open 2D tank `width` × `shell` m with `depth` m of liquid at rest for `settle` s, dx
/// `dx`: slopes and floor force averaged over the last `average` s (every tenth step), the
/// surface at ¼, ½, ¾ of the width over the last `average`/4 s.
#[allow(clippy::too_many_arguments)]
fn rest_reading(
    ctx: &Context,
    label: &str,
    params: &SphParams,
    (width, shell, depth): (f64, f64, f64),
    dx: f64,
    settle: f64,
    average: f64,
) -> Result<RestReading> {
    let setup = RectTank2::new(width, shell, depth)
        .with_roof(false)
        .with_layers(params.wall_layers())
        .build(dx)?;
    let mut sim = Simulation::new(setup, params.clone())?;
    let fill = sim.fill_level();
    let predicted = sim.still_level();
    ctx.say(&format!(
        "{label}: {width} × {depth} m at rest, dx = {dx} m, c0 = {:.1} m/s, {settle:.2} s",
        sim.sound_speed()
    ));
    let gauges = [0.25 * width, 0.5 * width, 0.75 * width];
    let n_all = (sim.fluid().position.len() + sim.walls().position.len()) as f64;
    let (mut level_sum, mut level_n, mut particle_steps) = (0.0, 0.0f64, 0.0);
    // [wall slope, particle slope, floor force / weight], summed every tenth step of the
    // averaging window.
    let (mut sums, mut samples, mut step) = ([0.0; 3], 0.0f64, 0u64);
    step_until(
        &mut sim,
        |_| [0.0; 3],
        settle,
        "stopped",
        |sim| {
            particle_steps += n_all;
            step += 1;
            if sim.time() >= settle - 0.25 * average {
                for x in gauges {
                    if let Some(z) = sim.surface_level_at(&[x]) {
                        level_sum += z;
                        level_n += 1.0;
                    }
                }
            }
            if sim.time() >= settle - average && step % 10 == 0 {
                let sample = [
                    side_wall_slope(sim, predicted),
                    hydrostatic_fit(sim, predicted).0,
                    floor_force_over_weight(sim),
                ];
                for (s, v) in sums.iter_mut().zip(sample) {
                    *s += v;
                }
                samples += 1.0;
            }
            Ok(())
        },
    )?;
    let [wall_slope, particle_slope, floor_load] = sums.map(|s| s / samples.max(1.0));
    Ok(RestReading {
        wall_slope,
        particle_slope,
        floor_load,
        level: level_sum / level_n.max(1.0),
        fill,
        predicted,
        particle_steps,
    })
}

/// 20 m of liquid in an open 2D tank 10 m wide (shell 24 m), both schemes: hydrostatic slopes
/// and the floor force averaged over the last [`HYDROSTATIC_AVERAGE`] s at rest, and the still
/// level against the fill. The modern preset, the scheme for real tanks, is judged; the paper
/// scheme is reported beside the same tank 40 times smaller with the paper's stiffness (its
/// Froude-similar twin: the same particles per depth, c0/√(g H) 12 against 11), which tells
/// whether a reading is a matter of scale or of the paper's method.
pub fn hydrostatics_at_depth(ctx: &Context) -> GroupResult {
    let group = "Hydrostatics at depth";
    let mut g = GroupResult::default();
    let (width, shell, depth, dx) = (10.0, 24.0, 20.0, 0.5);
    // The Froude equivalent of the paper's 2 s of settling in its 0.5 m tank.
    let settle = 2.0 * (depth / 0.5f64).sqrt();
    for (label, params) in presets() {
        let judged = label == "modern scheme";
        let reading = match rest_reading(
            ctx,
            label,
            &params,
            (width, shell, depth),
            dx,
            settle,
            HYDROSTATIC_AVERAGE,
        ) {
            Ok(r) => r,
            Err(e) => {
                g.checks.push(failed_run(group, label, &format!("{e:#}")));
                continue;
            }
        };
        g.particle_steps += reading.particle_steps;
        // The paper scheme's twin: the same tank scaled to 0.5 m of liquid with the paper's
        // stiffness (times × √(1/40)).
        let lab = if judged {
            None
        } else {
            let scale = 0.5 / depth;
            let lab_params = SphParams {
                wall_pressure: params.wall_pressure,
                ..crate::run::paper_params()
            };
            match rest_reading(
                ctx,
                &format!("{label} (laboratory twin)"),
                &lab_params,
                (width * scale, shell * scale, depth * scale),
                dx * scale,
                settle * scale.sqrt(),
                HYDROSTATIC_AVERAGE * scale.sqrt(),
            ) {
                Ok(r) => {
                    g.particle_steps += r.particle_steps;
                    Some(r)
                }
                Err(e) => {
                    g.checks.push(failed_run(
                        group,
                        &format!("{label}, laboratory twin"),
                        &format!("{e:#}"),
                    ));
                    None
                }
            }
        };
        // A judged row of the modern preset, or the paper scheme's reading reported with its
        // laboratory twin's beside it.
        let row = |name: String,
                   measured: f64,
                   reference: f64,
                   unit: &str,
                   tol,
                   reason: &str,
                   twin: Option<(f64, f64)>| {
            match (judged, twin) {
                (true, _) => relative_check(group, &name, measured, reference, unit, tol, reason),
                (false, twin) => info_row(
                    group,
                    &name,
                    format!("{} {unit}", fmt_num(measured)),
                    format!("{} {unit}", fmt_num(reference)),
                    format!("{:+.1} %", 100.0 * (measured / reference - 1.0)),
                    &match twin {
                        Some((m, r)) => format!(
                            "reported: {PAPER_METHOD_GAP}; the laboratory twin (0.5 m, the \
                             paper's stiffness) reads {:+.1} %",
                            100.0 * (m / r - 1.0)
                        ),
                        None => format!("reported: {PAPER_METHOD_GAP}"),
                    },
                ),
            }
        };
        let r = &reading;
        g.checks.push(row(
            format!(
                "{label}: hydrostatic slope of the side-wall pressure (the load the tool reports, \
                 ±N-step window) dp/d(ρ0 g d) under {depth} m, mean over t = {:.1}–{settle:.1} s",
                settle - HYDROSTATIC_AVERAGE
            ),
            r.wall_slope,
            1.0,
            "",
            SLOPE_TOL,
            "1 %: with c0 = 10 √(g H_ref) the density varies by ≤ 1 % over the depth",
            lab.as_ref().map(|l| (l.wall_slope, 1.0)),
        ));
        g.checks.push(info_row(
            group,
            &format!(
                "{label}: slope of the particle pressures (least squares, all particles, the \
                 same mean)"
            ),
            fmt_num(r.particle_slope),
            "1".into(),
            format!("{:+.1} %", 100.0 * (r.particle_slope - 1.0)),
            "reported: the SPH pressure gradient of the particles themselves",
        ));
        g.checks.push(row(
            format!(
                "{label}: floor force (±N-step window, the same mean) against the weight of the \
                 liquid, n m g"
            ),
            r.floor_load,
            1.0,
            "",
            SLOPE_TOL,
            "1 %: the floor of a tank with vertical walls carries the whole weight \
             (independent of the compression); the pressure at the floor is the bottom of the \
             slope judged above",
            lab.as_ref().map(|l| (l.floor_load, 1.0)),
        ));
        g.checks.push(row(
            format!(
                "{label}: still level (surface at ¼, ½, ¾ of the width, last 1 s) against the fill"
            ),
            r.level,
            r.fill,
            "m",
            STILL_LEVEL_TOL,
            "0.5 %: the Tait compression at c0 = 10 √(g H_ref) is ≤ H/(2·100·H_ref)",
            None,
        ));
        g.checks.push(info_row(
            group,
            &format!("{label}: still level predicted by the Tait EOS"),
            format!("{} m", fmt_num(r.predicted)),
            format!("{} m (fill)", fmt_num(r.fill)),
            format!("{:+.2} %", 100.0 * (r.predicted / r.fill - 1.0)),
            "reported: the level wave elevations are measured from",
        ));
        if let Some(l) = &lab {
            g.checks.push(info_row(
                group,
                &format!(
                    "{label}: surface below the Tait level, {depth} m and its laboratory twin, \
                     in % of the depth"
                ),
                format!("{:+.2} %", 100.0 * (r.level - r.predicted) / r.fill),
                format!("{:+.2} % (twin)", 100.0 * (l.level - l.predicted) / l.fill),
                "—".into(),
                "reported: the paper's summation density (Eq. 19–20) under-counts the surface \
                 rows' neighbours, so they sit below the level the Tait EOS predicts, at any \
                 scale",
            ));
        }
    }
    g.notes.push(format!(
        "Open 2D tank {width} m wide, shell {shell} m, {depth} m of water, dx = {dx} m \
         (40 particles per depth), no excitation, {settle:.1} s at rest (the paper's 2 s in \
         Froude time); the paper scheme starts from a uniform lattice at ρ0, the modern one \
         from hydrostatic densities, sunk into its own Tait compression. Depth d below the \
         still level the Tait EOS predicts; slopes and floor force averaged over the last \
         {HYDROSTATIC_AVERAGE} s. The modern preset is judged; the paper scheme is reported \
         beside its laboratory twin (the same tank 0.5 m deep with the paper's stiffness \
         B = 1.013×10⁵ Pa, the same 40 particles per depth, times × √(1/40))."
    ));
    g
}

/// Vertical force of the liquid on the floor (time-windowed wall pressures) over its weight:
/// the fluid particles' mass times g.
fn floor_force_over_weight(sim: &Simulation<2>) -> f64 {
    let floor = sim.part_names().iter().position(|n| n == PART_BOTTOM);
    let force = match (sim.loads().centred(), floor) {
        (Some(l), Some(k)) => l.force[k].y.abs(),
        _ => f64::NAN,
    };
    let weight = sim.fluid().position.len() as f64 * sim.particle_mass() * GRAVITY;
    force / weight
}

/// Least-squares slope (with an intercept) of the time-windowed side-wall pressures below the
/// still level against ρ0 g (still − z).
fn side_wall_slope(sim: &Simulation<2>, still: f64) -> f64 {
    let loads = sim.loads();
    let wall = sim.part_names().iter().position(|n| n == PART_WALL);
    let (mut reference, mut pressure) = (Vec::new(), Vec::new());
    for (k, (x, p)) in loads
        .positions()
        .iter()
        .zip(loads.centred_pressure())
        .enumerate()
    {
        if Some(loads.parts()[k] as usize) == wall && x.y < still {
            reference.push(RHO * GRAVITY * (still - x.y));
            pressure.push(*p);
        }
    }
    fitted_slope(&reference, &pressure)
}

/// Free sloshing of real-size 2D sections (24 m × 13 m, 60 m × 20 m) at 24 and 48 particles
/// per depth (full suite) or the 24 m section at 24 per depth (quick), modern preset.
pub fn free_sloshing_2d(ctx: &Context) -> GroupResult {
    let group = "Real-scale free sloshing (2D)";
    let mut g = GroupResult::default();
    let cases: &[(f64, f64, f64)] = if ctx.quick {
        &[(24.0, 13.0, 24.0)]
    } else {
        &[
            (24.0, 13.0, 24.0),
            (24.0, 13.0, 48.0),
            (60.0, 20.0, 24.0),
            (60.0, 20.0, 48.0),
        ]
    };
    let mut curves = Vec::new();
    for &(width, depth, per_depth) in cases {
        let mut run = || -> Result<(f64, f64, f64, f64, f64, f64)> {
            let wanted = depth / per_depth;
            let dx = width / (width / wanted).round();
            let shell = ((1.25 * depth) / dx).round() * dx;
            let setup = RectTank2::new(width, shell, depth)
                .with_roof(false)
                .with_initial_tilt(0.05 * depth)
                .with_initial_shape(InitialSurface::FirstMode)
                .with_layers(SphParams::modern().wall_layers())
                .build(dx)?;
            let mut sim = Simulation::new(setup, SphParams::modern())?;
            let held = sim.fill_level() - sim.interior_bounds().0.y;
            let t1 = rectangular_period(width, held, GRAVITY, 1);
            ctx.say(&format!(
                "modern: {width} × {held:.2} m, dx = {dx:.4} m, c0 = {:.1} m/s, {} fluid \
                 particles, 3.3 T₁",
                sim.sound_speed(),
                sim.fluid().position.len()
            ));
            let centre = sim.fluid().position.iter().map(|p| p[0]).sum::<f64>()
                / sim.fluid().position.len() as f64;
            let rest = 0.5 * width;
            let (h, steps) = free_run(&mut sim, 3.3 * t1, t1 / 200.0)?;
            let gamma = h.decay_rate(rest, 0.5 * t1);
            let zeta = gamma * t1 / (2.0 * std::f64::consts::PI);
            curves.push((
                format!("{width} × {depth} m, {per_depth} per depth"),
                h.t.iter().map(|t| t / t1).collect::<Vec<_>>(),
                h.x.iter()
                    .map(|x| (x - rest) / (centre - rest))
                    .collect::<Vec<_>>(),
            ));
            Ok((h.period(), t1, held, zeta, dx, steps))
        };
        match run() {
            Ok((period, t1, held, zeta, dx, steps)) => {
                g.particle_steps += steps;
                g.checks.push(relative_check(
                    group,
                    &format!(
                        "modern: first-mode period, {width} × {held:.2} m, {per_depth} \
                         particles per depth (dx = {dx:.4} m)"
                    ),
                    period,
                    t1,
                    "s",
                    PERIOD_TOL,
                    "1.5 %, the laboratory tolerance of the modern preset: the sound speed \
                     follows the tank, so the real size is judged alike",
                ));
                g.checks.push(info_row(
                    group,
                    &format!("modern: damping ratio of the first mode, {width} × {depth} m, {per_depth} per depth"),
                    format!("{:.2} %", 100.0 * zeta),
                    format!("{:.1} % (EN 1998-4, convective)", 100.0 * EC8_CONVECTIVE_DAMPING),
                    format!("{:.2}× EN 1998-4", zeta / EC8_CONVECTIVE_DAMPING),
                    "reported: numerical damping from the half-cycle peaks of the centre of \
                     mass (laminar water damps ≈ 0.01 % at this size)",
                ));
            }
            Err(e) => g.checks.push(failed_run(
                group,
                &format!("{width} × {depth} m, {per_depth} per depth"),
                &format!("{e:#}"),
            )),
        }
    }
    let series: Vec<Series> = curves
        .iter()
        .map(|(l, x, y)| Series::line(l.clone(), x, y))
        .collect();
    g.add_line_plot(
        &ctx.out,
        "real_scale_free_sloshing_2d",
        &PlotSpec::new(
            "Real-scale 2D sections, free sloshing (modern scheme, c0 from the tank)",
            "t / T₁ (theory) (-)",
            "centre of mass x − L/2, normalised (-)",
        ),
        &series,
        "free decay of the first mode in real-size sections",
    );
    g.notes.push(
        "Open sections with the shell at 1.25 × the depth; first-mode start with 0.05 H at the \
         left wall; dx fitted so the width holds whole spacings; theory for the depth the \
         lattice holds. Period from the centre-of-mass crossings after the first; damping ratio \
         ζ = γ T₁/(2π), γ from the half-cycle peaks after T₁/2."
            .into(),
    );
    g
}

/// The 24 m cylinder (R = 12 m, 13 m of water) at 24 particles per radius: free-sloshing
/// period, and a forced run at 0.8 ω₁ against the linear modal solution and Housner.
pub fn cylinder(ctx: &Context) -> Vec<(String, GroupResult)> {
    vec![
        (
            "Real-scale cylinder: free sloshing, 24 particles per radius".into(),
            cylinder_free(ctx, 24.0),
        ),
        (
            "Real-scale cylinder: forced response".into(),
            real_forced(ctx),
        ),
    ]
}

/// The forced real-scale cylinder, its comparisons beyond the laboratory tolerance marked
/// OPEN with what is known of the cause.
fn real_forced(ctx: &Context) -> GroupResult {
    let group = "Real-scale forced";
    let mut g = GroupResult::or_failed_run(group, cylinder_forced_inner(ctx, group, &REAL_FORCED));
    g.checks = g
        .checks
        .into_iter()
        .map(|c| {
            if c.name.starts_with("normalised RMS difference") {
                open_if_failed(c, FORCED_GAP)
            } else {
                c
            }
        })
        .collect();
    g
}

/// The 24 m cylinder's free-sloshing period at 48 particles per radius (≈ 600k particles;
/// hours on 2 cores, so a stage of its own).
pub fn cylinder_fine(ctx: &Context) -> GroupResult {
    cylinder_free(ctx, 48.0)
}

/// The real-scale forced cylinder: the laboratory check scaled by λ = 24 in length
/// (R = 12 m, H = 13 m, A = 0.12 m, times × √24), at 24 particles per radius, the sound
/// speed from the tank.
const REAL_FORCED: ForcedCylinder = ForcedCylinder {
    radius: 12.0,
    depth: 13.0,
    roof_height: 16.0,
    dx: 0.5,
    amplitude: 0.12,
    settle: 1.5,
    excitation_time: 19.6,
    paper_stiffness: false,
    stem: "real_cylinder",
};

fn cylinder_free(ctx: &Context, n: f64) -> GroupResult {
    let group = "Real-scale cylinder period";
    let (radius, depth) = (12.0, 13.0);
    let mut g = GroupResult::default();
    {
        let dx = radius / n;
        let run = || -> Result<(f64, f64, f64, f64, Check, f64)> {
            let setup = CylinderTank::new(radius, 16.0, depth, Roof::None)
                .with_initial_tilt(0.02 * radius)
                .with_initial_shape(InitialSurface::FirstMode)
                .with_layers(SphParams::modern().wall_layers())
                .with_lattice(CylinderLattice::Polar)
                .build(dx)?;
            let mut sim = Simulation::new(setup, SphParams::modern())?;
            let fill = sim.fill_level();
            let theory = CylindricalTank::new(radius, fill, RHO, GRAVITY);
            let t1 = 2.0 * std::f64::consts::PI / theory.modal_omega(0);
            ctx.say(&format!(
                "cylinder R = {radius} m, H = {fill:.2} m, {n} per radius, c0 = {:.1} m/s, \
                 {} + {} particles, 2.6 T₁",
                sim.sound_speed(),
                sim.fluid().position.len(),
                sim.walls().position.len()
            ));
            let (h, steps, _) = free_run_resumable(
                ctx,
                &format!("real_cylinder_free_{n}"),
                &mut sim,
                2.6 * t1,
                t1 / 100.0,
            )?;
            let gamma = h.decay_rate(0.0, 0.5 * t1);
            let zeta = gamma * t1 / (2.0 * std::f64::consts::PI);
            Ok((
                h.period(),
                t1,
                fill,
                zeta,
                stayed_inside(group, &sim),
                steps,
            ))
        };
        match run() {
            Ok((period, t1, fill, zeta, inside, steps)) => {
                g.particle_steps += steps;
                g.checks.push(inside);
                g.checks.push(relative_check(
                    group,
                    &format!("period, R = {radius} m, H = {fill:.2} m, {n} particles per radius"),
                    period,
                    t1,
                    "s",
                    PERIOD_TOL,
                    "1.5 %, the real-scale period tolerance: at 24 particles per radius and \
                     more the surface smoothing stays below it",
                ));
                g.checks.push(info_row(
                    group,
                    &format!("damping ratio of the first mode, {n} per radius"),
                    format!("{:.2} %", 100.0 * zeta),
                    format!(
                        "{:.1} % (EN 1998-4, convective)",
                        100.0 * EC8_CONVECTIVE_DAMPING
                    ),
                    format!("{:.2}× EN 1998-4", zeta / EC8_CONVECTIVE_DAMPING),
                    "reported: numerical damping from the centre of mass's half-cycle peaks",
                ));
            }
            Err(e) => g.checks.push(failed_run(
                group,
                &format!("cylinder, {n} per radius"),
                &format!("{e:#}"),
            )),
        }
    }
    g.notes.push(
        "Open cylinder R = 12 m, shell 16 m, 13 m of water, first-mode start with 0.02 R at the \
         wall, modern preset with c0 = 10 √(g H_ref); theory for the depth the lattice holds."
            .into(),
    );
    g
}

/// What is known of the paper scheme's still level beyond 0.5 % in the first-run section
/// (`docs/validation.md`, *The paper scheme's still level at real scale*).
const PAPER_LEVEL_GAP: &str = "the paper scheme's liquid holds the volume the Tait EOS gives \
    (Σ m/ρ within 0.01 % of it), but its dynamic walls (§2.5, summation density and the EOS) \
    push back only as hard as the liquid packs them, and the rows next to the floor and the \
    side walls close in to 0.25–0.3 dx of the wall face instead of the lattice's 0.5 dx, \
    so the surface sits ≈ 0.2 dx below the Tait level; at rest it settles over ≈ 20 s to −0.70 % \
    at dx = 0.25 m (this stage reads it before it has settled). A stiffer liquid (k = 15, 20) \
    shrinks the Tait part only, and a start in the liquid's own compression settles lower \
    still (−0.8 %): not a sound-speed setting, a property of the paper's walls";

/// The 24 m section with 13 m of water under a 16 m roof, started with the surface tilted
/// by 0.5 m (rising linearly to the left wall) and left to slosh, run as a user first runs
/// it: no numerics override (the sound speed from the tank), both schemes, dx = 0.5 m in the
/// quick suite and 0.25 m in the full suite. Judged: the still level (the surface at ¼, ½
/// and ¾ of the width, where the first mode's contributions cancel, averaged over the run
/// after the first half period) within 0.5 % of the fill, and the first-mode period (the
/// centre of mass's crossings after the first) within 2 % of potential theory.
pub fn first_run_section(ctx: &Context) -> GroupResult {
    let group = "Real-scale section as first run";
    let mut g = GroupResult::default();
    let (width, height, depth, tilt) = (24.0, 16.0, 13.0, 0.5);
    let dx = if ctx.quick { 0.5 } else { 0.25 };
    let user_presets = [
        ("paper scheme", SphParams::paper()),
        ("modern scheme", SphParams::modern()),
    ];
    for (label, params) in user_presets {
        let run = || -> Result<(f64, f64, f64, f64, f64, Check, f64)> {
            let setup = RectTank2::new(width, height, depth)
                .with_roof(true)
                .with_initial_tilt(tilt)
                .with_layers(params.wall_layers())
                .build(dx)?;
            let mut sim = Simulation::new(setup, params.clone())?;
            let floor = sim.interior_bounds().0.y;
            let fill = sim.fill_level() - floor;
            let t1 = rectangular_period(width, fill, GRAVITY, 1);
            ctx.say(&format!(
                "{label}: {width} × {fill} m under a {height} m roof, tilt {tilt} m, dx = {dx} m, \
                 c0 = {:.1} m/s, {} fluid particles, 3.3 T₁",
                sim.sound_speed(),
                sim.fluid().position.len()
            ));
            let gauges = [0.25 * width, 0.5 * width, 0.75 * width];
            let (mut level_sum, mut level_n) = (0.0, 0.0f64);
            let (history, steps) = free_run_observed(&mut sim, 3.3 * t1, t1 / 100.0, |sim| {
                if sim.time() >= 0.5 * t1 {
                    for x in gauges {
                        if let Some(z) = sim.surface_level_at(&[x]) {
                            level_sum += z - floor;
                            level_n += 1.0;
                        }
                    }
                }
            })?;
            Ok((
                history.period(),
                t1,
                level_sum / level_n.max(1.0),
                fill,
                sim.still_level() - floor,
                stayed_inside(group, &sim),
                steps,
            ))
        };
        match run() {
            Ok((period, t1, level, fill, predicted, inside, steps)) => {
                g.particle_steps += steps;
                g.checks.push(inside);
                g.checks.push(open_if_failed(
                    relative_check(
                        group,
                        &format!("{label}: still level against the {fill} m fill, dx = {dx} m"),
                        level,
                        fill,
                        "m",
                        STILL_LEVEL_TOL,
                        "0.5 %: the Tait compression at c0 = 10 √(g H_ref), H_ref = 16 m, is \
                         0.40 % of 13 m",
                    ),
                    PAPER_LEVEL_GAP,
                ));
                g.checks.push(info_row(
                    group,
                    &format!("{label}: still level predicted by the Tait EOS"),
                    format!("{} m", fmt_num(predicted)),
                    format!("{} m (fill)", fmt_num(fill)),
                    format!("{:+.2} %", 100.0 * (predicted / fill - 1.0)),
                    "reported: the level wave elevations are measured from",
                ));
                g.checks.push(relative_check(
                    group,
                    &format!("{label}: first-mode period, dx = {dx} m"),
                    period,
                    t1,
                    "s",
                    FIRST_RUN_PERIOD_TOL,
                    "2 %: the section's period as the sound-speed rule must deliver it without \
                     any setting (the modern preset's own laboratory tolerance is 1.5 %)",
                ));
            }
            Err(e) => g.checks.push(failed_run(group, label, &format!("{e:#}"))),
        }
    }
    g.notes.push(format!(
        "2D section {width} m wide, roof at {height} m, {depth} m of water, surface tilted \
         linearly by {tilt} m at the left wall and released, no excitation, no numerics \
         override (c0 = 10 √(g H_ref), H_ref the roof height), dx = {dx} m; the paper scheme \
         as users get it (wall loads from the nearest fluid particle, Eq. 23). With the \
         paper's B = 1.013×10⁵ Pa this case compressed the liquid by 6.3 % and its surface \
         swung with a 1.7 s acoustic period."
    ));
    g
}
