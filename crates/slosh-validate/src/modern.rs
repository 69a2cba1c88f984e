//! The modern scheme beside the paper scheme: free-sloshing period, hydrostatic
//! pressure and its scatter, resonant growth, roof impact of the paper's §3.2 case, and (full
//! suite) the 50 s run of the §3.3 case. The dam-break checks of the modern scheme live in
//! `dambreak.rs` beside the paper scheme's.

use super::run::{
    hydrostatic_fit, max_in_window, rect_sim_with, rms, Context, Runner, Scheme, SineExcitation,
    GRAVITY, RHO,
};
use super::sloshing::running_mean;
use super::three_d::free_run;
use super::{
    failed_run, fmt_num, info_row, open_if_failed, ratio_band_check, relative_check, stayed_inside,
    Check, GroupResult, Verdict,
};
use crate::run::{step_until, step_until_around};
use slosh_core::{DensityDiffusion, Simulation, SphParams, PART_ROOF};
use slosh_geometry::{InitialSurface, RectTank2};
use slosh_io::{PlotSpec, Series};
use slosh_run::StepPhase;
use slosh_theory::damping::{free_slip_viscous_mode, rectangular_viscous_decay};
use slosh_theory::linear::RectangularTank;
use slosh_theory::modal::sine_response;
use slosh_theory::natural::rectangular_period;

// The paper's §3.1 tank and excitation, shared with the paper-scheme checks.
use super::sloshing::{
    MODES, PAPER_AMPLITUDE as AMPLITUDE, PAPER_DEPTH as DEPTH, PAPER_DX as DX,
    PAPER_HEIGHT as HEIGHT, PAPER_OMEGA as OMEGA, PAPER_SETTLE as SETTLE, PAPER_WIDTH as WIDTH,
    SAMPLE,
};

/// Period tolerance of the modern scheme: 1.5 %. Its walls hold the liquid at dx/2
/// (no kernel-width gap), so what remains is the resolution (H/dx = 15–25) and the
/// measurement over two periods.
const PERIOD_TOL: f64 = 0.015;
/// Hydrostatic slope tolerance of the modern scheme: 2 %.
const SLOPE_TOL: f64 = 0.02;
/// The scatter of the modern scheme's particle pressures about the hydrostatic line must be at
/// least 5× smaller than the paper scheme's.
const SCATTER_FACTOR: f64 = 5.0;
/// Resonant crest band of the modern scheme: within 25 % of undamped linear theory.
const RESONANT_BAND: (f64, f64) = (0.75, 1.25);
/// Roof-pressure spikes (step-scale departures, see [`roughness`]): the modern scheme's must be
/// at most half the paper scheme's (a history "without the spurious spikes").
const ROUGHNESS_FACTOR: f64 = 2.0;

/// What is known of the modern scheme's roof-pressure spikes, shown if that row fails.
const ROOF_GAP: &str = "spikes shorter than the sound crossing of one kernel support \
    remain in the modern history; particle shifting removes most of them (row below) but is off \
    by default: it raises the dam-break wall pressures (three-sensor mean +21 % → +38 %, \
    Buchner first peak +8 % → +51 %)";
/// Start (s after the excitation start) of the roof-pressure plot: the first contact is at ≈ 1 s.
const PLOT_ROOF_FROM_S: f64 = 0.9;
/// Free-decay tank (m): the §3.1 section, open.
const DAMPING_WIDTH: f64 = 1.0;
/// Still depth of the free-decay tank (m).
const DAMPING_DEPTH: f64 = 0.5;
/// First-mode start of the free decay: the surface at the wall 5 % of the depth above still.
const DAMPING_TILT: f64 = 0.05;
/// Kinematic viscosity of the viscous liquid (m²/s): a Stokes layer δ = √(2ν/ω) of 4.3 dx at
/// [`DAMPING_DX`] and δk = 0.14, so that the boundary-layer theory applies roughly.
const DAMPING_NU: f64 = 0.005;
/// Kinematic viscosity of water at 20 °C (m²/s).
const WATER_NU: f64 = 1.0e-6;
/// Particle spacing of the free-decay runs (m): 100 particles over the width.
const DAMPING_DX: f64 = 0.01;
/// Length of the free decay in first-mode periods.
const DAMPING_PERIODS: f64 = 6.0;
/// Particle-shifting coefficient of the roof-impact comparison row (Skillen et al. 2013 use 2).
const SHIFTING_COMPARED: f64 = 2.0;

/// All groups of the modern scheme (the dam break excepted).
pub fn groups(ctx: &Context) -> Vec<(String, GroupResult)> {
    vec![
        (
            "Modern scheme: free-sloshing period".to_string(),
            period(ctx),
        ),
        (
            "Modern scheme: hydrostatics and resonant growth".to_string(),
            forced(ctx),
        ),
        (
            "Modern scheme: roof impact (paper §3.2)".to_string(),
            roof_impact(ctx),
        ),
    ]
}

/// One free decay of the first mode in the open 1.0 × 0.5 m tank: the centre-of-mass history,
/// the still depth (m), the tank's centre (m), the particle-steps and the inside check.
fn decay_run(
    ctx: &Context,
    label: &str,
    params: SphParams,
    dx: f64,
    periods: f64,
    group: &str,
) -> anyhow::Result<(super::three_d::ComHistory, f64, f64, f64, Check)> {
    let (w, d) = (DAMPING_WIDTH, DAMPING_DEPTH);
    let tank_height = ((d + 0.2) / dx).round() * dx;
    let setup = RectTank2::new(w, tank_height, d)
        .with_roof(false)
        .with_initial_tilt(DAMPING_TILT * d)
        .with_initial_shape(InitialSurface::FirstMode)
        .with_layers(params.wall_layers())
        .build(dx)?;
    let mut sim = Simulation::new(setup, params)?;
    let (lo, hi) = sim.interior_bounds();
    let depth = sim.fill_level() - lo.y;
    let centre = 0.5 * (lo.x + hi.x);
    let t1 = rectangular_period(w, depth, GRAVITY, 1);
    ctx.say(&format!(
        "free decay, {label}: tank {w} × {depth:.3} m, dx = {dx} m, {} fluid particles, {periods} T₁",
        sim.fluid().position.len()
    ));
    let (h, steps) = free_run(&mut sim, periods * t1, t1 / 100.0)?;
    Ok((h, depth, centre, steps, stayed_inside(group, &sim)))
}

/// Free decay of the first sloshing mode (full suite): a viscous liquid on free-slip walls
/// against the exact linear solution ([`free_slip_viscous_mode`]) and on no-slip walls against
/// the laminar boundary-layer theory ([`rectangular_viscous_decay`]), both with the physical
/// viscosity alone (no artificial viscosity); then water's numerical damping in both schemes
/// as they run by default, beside the laminar value and the 0.5 % the codes assume for the
/// convective mode. Reported, not judged: what the SPH's damping is, with its known gaps.
pub fn damping(ctx: &Context) -> GroupResult {
    let group = "Modern damping";
    let mut g = GroupResult::default();
    let dx = DAMPING_DX;
    let viscous = |no_slip: bool| {
        let mut p = SphParams::modern().with_paper_stiffness();
        p.dynamic_viscosity = RHO * DAMPING_NU;
        p.wall_no_slip = no_slip;
        p.av_alpha = 0.0;
        p
    };
    /// What a free decay is compared with.
    enum DecayReference {
        /// The exact linear mode with free-slip walls.
        FreeSlipExact,
        /// The Stokes-layer energy balance with no-slip walls.
        BoundaryLayer,
        /// Water: the laminar value and the codes' 0.5 % (numerical damping).
        Numerical,
    }
    use DecayReference::*;
    let runs: [(&str, SphParams, f64, DecayReference); 4] = [
        (
            "viscous liquid, free-slip walls",
            viscous(false),
            DAMPING_NU,
            FreeSlipExact,
        ),
        (
            "viscous liquid, no-slip walls",
            viscous(true),
            DAMPING_NU,
            BoundaryLayer,
        ),
        (
            "water, modern scheme",
            SphParams::modern().with_paper_stiffness(),
            WATER_NU,
            Numerical,
        ),
        (
            "water, paper scheme",
            Scheme::paper().params,
            WATER_NU,
            Numerical,
        ),
    ];
    let mut curves: Vec<(&str, Vec<f64>, Vec<f64>)> = Vec::new();
    for (label, params, nu, reference) in runs {
        let (h, depth, centre, steps, inside) =
            match decay_run(ctx, label, params, dx, DAMPING_PERIODS, group) {
                Ok(r) => r,
                Err(e) => {
                    g.checks.push(failed_run(group, label, &format!("{e:#}")));
                    continue;
                }
            };
        g.particle_steps += steps;
        g.checks.push(inside);
        let laminar = rectangular_viscous_decay(DAMPING_WIDTH, depth, nu, GRAVITY, 1);
        let t1 = 2.0 * std::f64::consts::PI / laminar.omega;
        // From the first whole half cycle on: the start (a still, tilted surface) has settled
        // into the first mode by then.
        let gamma = h.decay_rate(centre, 0.5 * t1);
        let zeta = gamma / laminar.omega;
        let x0 = h.x[0] - centre;
        curves.push((
            label,
            h.t.iter().map(|t| t / t1).collect(),
            h.x.iter().map(|x| (x - centre) / x0).collect(),
        ));
        let pct = |z: f64| format!("{:.2} %", 100.0 * z);
        let rel = |m: f64, r: f64| format!("{:+.0} %", 100.0 * (m / r - 1.0));
        match reference {
            FreeSlipExact => {
                match free_slip_viscous_mode(DAMPING_WIDTH, depth, DAMPING_NU, GRAVITY, 1) {
                    Some(s) => g.checks.push(info_row(
                        group,
                        &format!("{label} (ν = {DAMPING_NU} m²/s): decay rate γ"),
                        format!("{gamma:.4} 1/s (ζ = {})", pct(zeta)),
                        format!(
                            "{:.4} 1/s (exact linear, Lamb §349 with a stress-free floor)",
                            -s.re
                        ),
                        rel(gamma, -s.re),
                        "diagnostic, not judged: the interior viscous term (Eq. 8 with the strain \
                     rate of Eq. 4–5) alone; the SPH damps more than the exact solution and \
                     the excess does not fall with dx (+29 % at dx = 0.02 m; see the notes)",
                    )),
                    None => {
                        g.checks
                            .push(failed_run(group, label, "no oscillating mode in theory"))
                    }
                }
            }
            BoundaryLayer => g.checks.push(info_row(
                group,
                &format!("{label} (ν = {DAMPING_NU} m²/s): decay rate γ"),
                format!("{gamma:.4} 1/s (ζ = {})", pct(zeta)),
                format!(
                    "{:.4} 1/s (Stokes layers + interior; δ = {:.3} m = {:.1} dx)",
                    laminar.rate(),
                    laminar.stokes_layer(nu),
                    laminar.stokes_layer(nu) / dx
                ),
                rel(gamma, laminar.rate()),
                "diagnostic, not judged: the boundary-layer theory leaves out terms of \
                 relative order δk and the moving contact line, which no-slip walls up to \
                 the free surface make dissipative; the wall share (this row less the \
                 free-slip one) is what to compare with the theory's floor + end walls",
            )),
            Numerical => g.checks.push(info_row(
                group,
                &format!("{label}: numerical damping ratio ζ of the first mode, dx = {dx} m"),
                pct(zeta),
                format!(
                    "{} laminar (no-slip); 0.5 % assumed by EN 1998-4 for the convective mode",
                    pct(laminar.damping_ratio())
                ),
                format!("{:.0}× laminar", zeta / laminar.damping_ratio()),
                "diagnostic, not judged: the default scheme's own damping (artificial \
                 viscosity, density diffusion, walls), which caps a resonant response; a \
                 value above the codes' 0.5 % under-predicts resonant crests and roof loads",
            )),
        }
    }
    g.add_line_plot(
        &ctx.out,
        "damping_free_decay",
        &PlotSpec::new(
            "Free decay of the first mode, tank 1.0 × 0.5 m",
            "t / T₁ (-)",
            "centre of mass x − L/2, normalised (-)",
        ),
        &curves
            .iter()
            .map(|(label, t, x)| Series::line(*label, t, x))
            .collect::<Vec<_>>(),
        "free decay of the first mode: viscous liquid on free-slip and no-slip walls, water in \
         both schemes",
    );
    g.notes.push(format!(
        "Open tank {DAMPING_WIDTH} × {DAMPING_DEPTH} m, dx = {dx} m, first-mode start with the \
         surface {DAMPING_TILT} H above still at the wall, {DAMPING_PERIODS} periods; γ from a \
         least-squares fit of ln(half-cycle peak) of the centre of mass. Viscous runs: the \
         modern preset with ν = {DAMPING_NU} m²/s and no artificial viscosity. Measured \
         before this stage was written (same runs at other settings): free slip, ν = 0.0025 \
         m²/s with α = 0.02, +67 % at dx = 0.01 m and +49 % at dx = 0.005 m over the exact \
         γ; ν = 0.01 m²/s, α = 0: +12 % at dx = 0.02 m, +23 % at dx = 0.01 m. No-slip, \
         ν = 0.0025 m²/s, α = 0.02: +73 % (dx = 0.01 m) and +68 % (dx = 0.005 m) over the \
         boundary-layer theory."
    ));
    g
}

/// First-mode period of two tanks of aspect ratio 2:1, both schemes: open tank, first-mode
/// start (tilt 0.1 H at the wall), period from the crossings of the liquid's centre of mass
/// over 2.3 T₁ (a volume integral: no gauge noise, no higher modes to shift the crossings).
fn period(ctx: &Context) -> GroupResult {
    let group = "Modern period";
    let mut g = GroupResult::default();
    for (w, d) in [(1.0, 0.5), (0.6, 0.3)] {
        for scheme in [Scheme::modern(), Scheme::paper()] {
            let run = || -> anyhow::Result<(f64, f64, f64, f64)> {
                let tank_height = ((d + 0.2) / DX).round() * DX;
                let setup = RectTank2::new(w, tank_height, d)
                    .with_roof(false)
                    .with_initial_tilt(0.1 * d)
                    .with_initial_shape(InitialSurface::FirstMode)
                    .with_layers(scheme.params.wall_layers())
                    .build(DX)?;
                let mut sim = Simulation::new(setup, scheme.params.clone())?;
                let depth = sim.fill_level() - sim.interior_bounds().0.y;
                let t1 = rectangular_period(w, depth, GRAVITY, 1);
                ctx.say(&format!(
                    "{}: free sloshing {w} × {depth:.3} m, {} fluid particles, 2.3 T₁",
                    scheme.label,
                    sim.fluid().position.len()
                ));
                let (h, steps) = free_run(&mut sim, 2.3 * t1, t1 / 200.0)?;
                Ok((h.period(), t1, depth, steps))
            };
            match run() {
                Ok((measured, t1, depth, steps)) => {
                    g.particle_steps += steps;
                    let name = format!(
                        "{}: first-mode period, tank {w} × {depth:.2} m",
                        scheme.label
                    );
                    if scheme.label == "modern scheme" {
                        g.checks.push(relative_check(
                            group,
                            &name,
                            measured,
                            t1,
                            "s",
                            PERIOD_TOL,
                            "1.5 %: Adami walls hold the liquid at dx/2 from the wall, \
                             no kernel-width gap; what remains is resolution",
                        ));
                    } else {
                        g.checks.push(info_row(
                            group,
                            &name,
                            format!("{} s", fmt_num(measured)),
                            format!("{} s", fmt_num(t1)),
                            format!("{:+.2} %", 100.0 * (measured / t1 - 1.0)),
                            "reported beside the modern scheme (the paper scheme's 5 % check \
                             is in the free-sloshing group)",
                        ));
                    }
                }
                Err(e) => g.checks.push(failed_run(
                    group,
                    &format!("{} tank {w} × {d} m", scheme.label),
                    &format!("{e:#}"),
                )),
            }
        }
    }
    g.notes.push(format!(
        "Open tanks, dx = {DX} m, first-mode start cos(πx/L) with 0.1 H at the left wall; \
         theory for the depth the lattice holds."
    ));
    g
}

/// One scheme's run of the §3.1 case: hydrostatic snapshot at the end of settling, then the
/// resonant excitation.
struct ForcedRun {
    slope: f64,
    scatter: f64,
    t: Vec<f64>,
    eta_left: Vec<f64>,
    gauge_x: f64,
    particle_steps: f64,
    inside: Check,
}

fn forced_run(
    ctx: &Context,
    scheme: &Scheme,
    excitation_time: f64,
    group: &str,
) -> anyhow::Result<ForcedRun> {
    let sim = rect_sim_with(scheme.params.clone(), WIDTH, HEIGHT, DEPTH, true, 0.0, DX)?;
    let excitation = SineExcitation {
        amplitude: AMPLITUDE,
        omega: OMEGA,
        settle: SETTLE,
    };
    let mut runner = Runner::new(sim, excitation, SAMPLE);
    ctx.say(&format!(
        "{}: paper tank, {} fluid particles, to t = {:.1} s",
        scheme.label,
        runner.sim.fluid().position.len(),
        SETTLE + excitation_time
    ));
    let still = runner.still_level;
    let mut hydro: Option<(f64, f64)> = None;
    runner.run_until(SETTLE + excitation_time, |sim| {
        if hydro.is_none() && sim.time() >= SETTLE {
            hydro = Some(hydrostatic_fit(sim, still));
        }
    })?;
    let (slope, scatter) = hydro.unwrap_or((f64::NAN, f64::NAN));
    Ok(ForcedRun {
        slope,
        scatter,
        t: runner.history.t.iter().map(|t| t - SETTLE).collect(),
        eta_left: runner.history.eta_left.clone(),
        gauge_x: runner.gauge_x.0,
        particle_steps: runner.history.particle_steps,
        inside: stayed_inside(group, &runner.sim),
    })
}

/// Hydrostatic slope and scatter, resonant crest at 2 s and growth over 10 s, both schemes.
fn forced(ctx: &Context) -> GroupResult {
    let group = "Modern forced";
    let mut g = GroupResult::default();
    let excitation_time = if ctx.quick { 2.5 } else { 10.0 };
    let mut runs = Vec::new();
    for scheme in [Scheme::modern(), Scheme::paper()] {
        match forced_run(ctx, &scheme, excitation_time, group) {
            Ok(r) => runs.push((scheme, r)),
            Err(e) => {
                g.checks.push(failed_run(
                    group,
                    &format!("{} §3.1 run", scheme.label),
                    &format!("{e:#}"),
                ));
                return g;
            }
        }
    }
    let (modern, paper) = (&runs[0].1, &runs[1].1);
    g.particle_steps = modern.particle_steps + paper.particle_steps;
    g.checks.push(modern.inside.clone());
    g.checks.push(relative_check(
        group,
        "modern: hydrostatic slope dp/d(ρ0 g d), least squares over all fluid particles at t = 2.0 s",
        modern.slope,
        1.0,
        "",
        SLOPE_TOL,
        "2 %: continuity density from a hydrostatic start and Adami walls; the EOS \
         compression itself makes ρ ≈ 1.005 ρ0 at mid-depth",
    ));
    g.checks.push(info_row(
        group,
        "paper: hydrostatic slope (same instant)",
        fmt_num(paper.slope),
        "1".into(),
        format!("{:+.1} %", 100.0 * (paper.slope - 1.0)),
        "reported beside the modern scheme",
    ));
    let factor = paper.scatter / modern.scatter;
    g.checks.push(Check {
        group: group.into(),
        name: "pressure scatter about ρ g d, RMS / ρ g H: paper ÷ modern".into(),
        measured: format!(
            "{:.1}× (paper {:.2} %, modern {:.2} %)",
            factor,
            100.0 * paper.scatter,
            100.0 * modern.scatter
        ),
        reference: format!("≥ {SCATTER_FACTOR:.0}×"),
        error: format!("{factor:.1}×"),
        tolerance: format!("≥ {SCATTER_FACTOR:.0}×"),
        reason: "the modern pressure field must be at least 5× quieter".into(),
        verdict: if factor >= SCATTER_FACTOR {
            Verdict::Pass
        } else {
            Verdict::Fail
        },
    });

    // Linear theory at the gauge of each run (the same x for both).
    let tank = RectangularTank::water(WIDTH, DEPTH);
    let force = -AMPLITUDE * OMEGA * OMEGA;
    let theory = |ts: &[f64], x: f64| -> Vec<f64> {
        ts.iter()
            .map(|&t| {
                if t < 0.0 {
                    0.0
                } else {
                    tank.elevation(&sine_response(&tank, force, OMEGA, t, MODES), x)
                }
            })
            .collect()
    };
    let lin_m = theory(&modern.t, modern.gauge_x);
    let (crest_m, t_m) = max_in_window(&modern.t, &modern.eta_left, 1.2, 2.4);
    let (crest_lin, t_lin) = max_in_window(&modern.t, &lin_m, 1.2, 2.4);
    let (crest_p, _) = max_in_window(&paper.t, &paper.eta_left, 1.2, 2.4);
    g.checks.push(ratio_band_check(
        group,
        &format!(
            "modern: first crest at the left wall (SPH at {t_m:.2} s, theory at {t_lin:.2} s \
             after start; paper scheme {} m)",
            fmt_num(crest_p)
        ),
        crest_m,
        crest_lin,
        "m",
        RESONANT_BAND,
        "25 %: undamped linear theory is an upper bound; the modern scheme's wall \
         gap is gone, so its resonance is not detuned",
    ));
    if !ctx.quick {
        for k in 1..5 {
            let (t0, t1) = (2.0 * k as f64, 2.0 * (k + 1) as f64);
            let (cm, _) = max_in_window(&modern.t, &modern.eta_left, t0, t1);
            let (cp, _) = max_in_window(&paper.t, &paper.eta_left, t0, t1);
            let (cl, _) = max_in_window(&modern.t, &lin_m, t0, t1);
            g.checks.push(info_row(
                group,
                &format!("largest crest {t0:.0}–{t1:.0} s after start: modern (paper)"),
                format!("{} m ({} m)", fmt_num(cm), fmt_num(cp)),
                format!("{} m (linear)", fmt_num(cl)),
                format!("ratio {:.2} ({:.2})", cm / cl, cp / cl),
                "reported: growth over 10 s; linear theory grows without bound at resonance",
            ));
        }
    }
    let stem = "modern_resonant_eta_left";
    g.add_line_plot(
        &ctx.out,
        stem,
        &PlotSpec::new(
            "Resonant paper case: elevation at the left wall, both schemes",
            "time since excitation start t (s)",
            "η at left wall (m)",
        ),
        &[
            Series::line("modern scheme", &modern.t, &modern.eta_left),
            Series::line("paper scheme", &paper.t, &paper.eta_left),
            Series::dashed("linear potential theory", &modern.t, &lin_m),
        ],
        "η at the left wall, modern and paper schemes against linear theory",
    );
    g.notes.push(format!(
        "Paper §3.1 tank, dx = {DX} m, A = {AMPLITUDE} m, ω = {OMEGA} rad/s after {SETTLE} s of \
         settling; the hydrostatic snapshot is taken at the end of settling."
    ));
    g
}

/// Roughness of a pressure history: RMS of its departure from the centred running mean over
/// ±`half` s, divided by the largest value of the ±`scale_half` s running mean (the level of
/// the impact pulses). With `half` at the acoustic crossing time of one kernel support
/// ([`RoofRun::support_crossing_s`]) it measures spikes shorter than anything the scheme can
/// resolve — the spurious ones; with `half` = 10 ms it also counts the ringing of the impact
/// pulses themselves.
fn roughness(ts: &[f64], ps: &[f64], half: f64, scale_half: f64) -> f64 {
    if ts.len() < 3 {
        return f64::NAN;
    }
    let level = running_mean(ts, ps, scale_half);
    let peak = level.iter().fold(0.0f64, |m, &v| m.max(v));
    let mean = running_mean(ts, ps, half);
    let departure: Vec<f64> = ps.iter().zip(&mean).map(|(p, m)| p - m).collect();
    rms(&departure) / peak
}

/// Indices of the load points on the roof part (none if the tank has no roof).
fn roof_load_points(sim: &Simulation<2>) -> Vec<usize> {
    let roof = sim.part_names().iter().position(|n| n == PART_ROOF);
    sim.loads()
        .parts()
        .iter()
        .enumerate()
        .filter(|(_, &p)| Some(p as usize) == roof)
        .map(|(k, _)| k)
        .collect()
}

/// One scheme's roof-pressure history in the §3.2 case.
struct RoofRun {
    t: Vec<f64>,
    /// Largest instantaneous roof pressure (Pa) per step.
    raw: Vec<f64>,
    /// Largest ±N-step windowed roof pressure (Pa) per step.
    windowed: Vec<f64>,
    particle_steps: f64,
    inside: Check,
    /// Time (s) sound takes to cross one kernel support, 2h/c₀: the shortest time scale of
    /// pressure the scheme resolves.
    support_crossing_s: f64,
}

fn roof_run(
    ctx: &Context,
    params: SphParams,
    label: &str,
    group: &str,
    excitation_time: f64,
) -> anyhow::Result<RoofRun> {
    let mut sim = rect_sim_with(params, WIDTH, 0.6, DEPTH, true, 0.0, DX)?;
    let excitation = SineExcitation {
        amplitude: 0.0279,
        omega: OMEGA,
        settle: SETTLE,
    };
    let n_all = (sim.fluid().position.len() + sim.walls().position.len()) as f64;
    ctx.say(&format!(
        "{label}: §3.2 roof case (tank 0.6 m, A = 0.0279 m), {} fluid particles",
        sim.fluid().position.len()
    ));
    let on_roof = roof_load_points(&sim);
    if on_roof.is_empty() {
        anyhow::bail!("the §3.2 tank has no roof load points");
    }
    let (mut ts, mut windowed, mut particle_steps) = (Vec::new(), Vec::new(), 0.0);
    let mut raw_by_step: Vec<(f64, f64)> = Vec::new();
    let mut last = None;
    let ground = |t| [excitation.ground_accel(t), 0.0, 0.0];
    step_until(
        &mut sim,
        ground,
        SETTLE + excitation_time,
        "stopped",
        |sim| {
            particle_steps += n_all;
            let l = sim.loads();
            let p_raw = on_roof
                .iter()
                .map(|&k| l.instantaneous_pressure()[k])
                .fold(0.0f64, f64::max);
            raw_by_step.push((sim.time() - SETTLE, p_raw));
            if let Some(c) = l.centred() {
                if last != Some(c.step) {
                    last = Some(c.step);
                    let p = on_roof
                        .iter()
                        .map(|&k| l.centred_pressure()[k])
                        .fold(0.0f64, f64::max);
                    ts.push(c.time - SETTLE);
                    windowed.push(p);
                }
            }
            Ok(())
        },
    )?;
    // The raw series on the windowed series' times (the window lags N steps).
    let n = ts.len().min(raw_by_step.len());
    let raw: Vec<f64> = raw_by_step[..n].iter().map(|r| r.1).collect();
    ts.truncate(n);
    windowed.truncate(n);
    Ok(RoofRun {
        t: ts,
        raw,
        windowed,
        particle_steps,
        inside: stayed_inside(group, &sim),
        support_crossing_s: sim.kernel().support() / sim.sound_speed(),
    })
}

/// Paper §3.2 (tank height 0.6 m): roof-pressure histories of both schemes together.
fn roof_impact(ctx: &Context) -> GroupResult {
    let group = "Modern roof impact";
    let mut g = GroupResult::default();
    let excitation_time = 2.2;
    let modern = roof_run(
        ctx,
        SphParams::modern().with_paper_stiffness(),
        "modern scheme",
        group,
        excitation_time,
    );
    let paper = roof_run(
        ctx,
        SphParams::paper().with_paper_stiffness(),
        "paper scheme",
        group,
        excitation_time,
    );
    let mut with_shifting = SphParams::modern().with_paper_stiffness();
    with_shifting.shifting = Some(SHIFTING_COMPARED);
    let shifted = roof_run(
        ctx,
        with_shifting,
        "modern scheme with particle shifting",
        group,
        excitation_time,
    );
    let (modern, paper) = match (modern, paper) {
        (Ok(m), Ok(p)) => (m, p),
        (m, p) => {
            for (label, r) in [("modern", m.err()), ("paper", p.err())] {
                if let Some(e) = r {
                    g.checks.push(failed_run(group, label, &format!("{e:#}")));
                }
            }
            return g;
        }
    };
    g.particle_steps = modern.particle_steps + paper.particle_steps;
    g.checks.push(modern.inside.clone());
    // Spikes: departures from the running mean over ± the longer of the two schemes' support
    // crossing times (≈ 2 ms), scaled by the ±10 ms level of the impact pulses.
    let level_half = 0.01;
    let spike_half = modern.support_crossing_s.max(paper.support_crossing_s);
    let rough = |r: &RoofRun, raw: bool, half: f64| {
        roughness(
            &r.t,
            if raw { &r.raw } else { &r.windowed },
            half,
            level_half,
        )
    };
    let (m_spike, p_spike) = (
        rough(&modern, true, spike_half),
        rough(&paper, true, spike_half),
    );
    let (m_raw, p_raw) = (
        rough(&modern, true, level_half),
        rough(&paper, true, level_half),
    );
    let (m_win, p_win) = (
        rough(&modern, false, level_half),
        rough(&paper, false, level_half),
    );
    let factor = p_spike / m_spike;
    g.checks.push(open_if_failed(
        Check {
            group: group.into(),
            name: "spikes of the instantaneous peak roof pressure: paper ÷ modern".into(),
            measured: format!("{factor:.1}× (paper {p_spike:.4}, modern {m_spike:.4})"),
            reference: format!("≥ {ROUGHNESS_FACTOR:.0}×"),
            error: format!("{factor:.1}×"),
            tolerance: format!("≥ {ROUGHNESS_FACTOR:.0}×"),
            reason: format!(
                "the modern history without the paper scheme's spurious spikes; spikes \
                 = RMS departure from the ±{:.1} ms running mean (sound crossing one kernel \
                 support, 2h/c₀: nothing shorter is resolved physics) ÷ the peak of the ±10 ms \
                 mean",
                1e3 * spike_half
            ),
            verdict: if factor >= ROUGHNESS_FACTOR {
                Verdict::Pass
            } else {
                Verdict::Fail
            },
        },
        ROOF_GAP,
    ));
    g.checks.push(info_row(
        group,
        "roughness over ±10 ms of the instantaneous peak roof pressure: paper ÷ modern",
        format!(
            "{:.1}× (paper {p_raw:.3}, modern {m_raw:.3})",
            p_raw / m_raw
        ),
        "-".into(),
        "-".into(),
        "reported: departures from the ±10 ms running mean also count the impact pulses' own \
         ringing (≈ 13 ms period in the modern history), which is resolved, not spurious; the \
         paper scheme's figure moves by 2× between builds (its spikes are chaotic)",
    ));
    match &shifted {
        Ok(shifted) => {
            let s_spike = rough(shifted, true, spike_half);
            g.particle_steps += shifted.particle_steps;
            g.checks.push(info_row(
                group,
                &format!("spikes with particle shifting (A = {SHIFTING_COMPARED}): paper ÷ modern"),
                format!("{:.1}× (modern + shifting {s_spike:.4})", p_spike / s_spike),
                format!("≥ {ROUGHNESS_FACTOR:.0}×"),
                "-".into(),
                "reported: shifting is off in the modern preset, as it raises the dam-break wall \
                 pressures (quick suite: three-sensor mean +21 % → +38 %, Buchner first peak \
                 +8 % → +51 %)",
            ));
        }
        Err(e) => g
            .checks
            .push(failed_run(group, "modern + shifting", &format!("{e:#}"))),
    }
    g.checks.push(info_row(
        group,
        "roughness of the ±20-step windowed history: modern (paper)",
        format!("{m_win:.3} ({p_win:.3})"),
        "-".into(),
        format!("ratio {:.1}", p_win / m_win),
        "reported: the paper's time window (§2.6) hides part of its spikes",
    ));
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, &x| m.max(x));
    g.checks.push(info_row(
        group,
        "peak roof pressure, ±20-step window: modern (paper)",
        format!(
            "{} kPa ({} kPa)",
            fmt_num(peak(&modern.windowed) / 1e3),
            fmt_num(peak(&paper.windowed) / 1e3)
        ),
        "-".into(),
        "-".into(),
        "reported: the impact peak (paper Fig. 8: 0.6 m tank)",
    ));
    // The contacts start ≈ 1 s after the excitation: the plot shows them, not the settling.
    let from = PLOT_ROOF_FROM_S;
    let tail = |r: &RoofRun| {
        let k = r.t.partition_point(|&t| t < from);
        (
            r.t[k..].to_vec(),
            r.raw[k..].to_vec(),
            r.windowed[k..].to_vec(),
        )
    };
    let (pt, praw, pwin) = tail(&paper);
    let (mt, mraw, mwin) = tail(&modern);
    let shifted_tail = shifted.as_ref().ok().map(tail);
    let stem = "modern_roof_pressure";
    g.add_line_plot(
        &ctx.out,
        stem,
        &PlotSpec::new(
            "Paper §3.2 (tank 0.6 m): largest roof pressure, both schemes",
            "time since excitation start t (s)",
            "largest roof pressure (Pa)",
        ),
        &[
            Series::line("paper scheme, instantaneous", &pt, &praw),
            Series::line("modern scheme, instantaneous", &mt, &mraw),
            Series::dashed("paper scheme, ±20 steps", &pt, &pwin),
            Series::dashed("modern scheme, ±20 steps", &mt, &mwin),
        ]
        .into_iter()
        .chain(shifted_tail.as_ref().map(|(st, sraw, _)| {
            Series::line("modern scheme + particle shifting, instantaneous", st, sraw)
        }))
        .collect::<Vec<_>>(),
        "largest roof pressure in the §3.2 case, paper and modern schemes",
    );
    g.notes.push(
        "Paper §3.2: 1.0 m wide tank, roof at 0.6 m, 0.5 m of water, A = 0.0279 m, ω = 5.311 \
         rad/s after 2 s settling, dx = 0.02 m; each scheme with its own wall-pressure method \
         (paper: nearest fluid + Eq. 23; modern: Adami extrapolation at the wall face)."
            .into(),
    );
    g
}

/// The Riemann-solver pair of Zhang, Hu & Adams 2017 (`PairScheme::Riemann`, with and
/// without the preset's δ-SPH diffusion) beside the modern preset, each run once (full suite):
/// the hydrostatic slope and pressure scatter about ρ g d at the end of settling in the §3.1
/// tank, and the peak roof pressure of the §3.2 case. Reported, not judged.
pub fn riemann_pair(ctx: &Context) -> GroupResult {
    let group = "Modern scheme: Riemann pair";
    let mut g = GroupResult::default();
    let riemann = |diffusion| {
        SphParams {
            density_diffusion: diffusion,
            ..SphParams::modern().with_riemann_pair()
        }
        .with_paper_stiffness()
    };
    let schemes = [
        Scheme::modern(),
        Scheme {
            label: "modern, Riemann pair with δ-SPH",
            params: riemann(SphParams::modern().density_diffusion),
            is_paper: false,
        },
        Scheme {
            label: "modern, Riemann pair without δ-SPH",
            params: riemann(DensityDiffusion::None),
            is_paper: false,
        },
    ];
    let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, &x| m.max(x));
    for scheme in &schemes {
        match forced_run(ctx, scheme, 0.1, group) {
            Ok(r) => {
                g.particle_steps += r.particle_steps;
                g.checks.push(r.inside.clone());
                g.checks.push(info_row(
                    group,
                    &format!(
                        "{}: hydrostatic slope dp/d(ρ0 g d) and pressure scatter about ρ g d                          (RMS / ρ g H), all fluid particles at t = {SETTLE} s",
                        scheme.label
                    ),
                    format!("slope {}, scatter {:.2} %", fmt_num(r.slope), 100.0 * r.scatter),
                    "slope 1, scatter 0".into(),
                    format!("{:+.2} %", 100.0 * (r.slope - 1.0)),
                    "reported: the §3.1 tank settled from a hydrostatic start",
                ));
            }
            Err(e) => g.checks.push(failed_run(
                group,
                &format!("{} §3.1 settling", scheme.label),
                &format!("{e:#}"),
            )),
        }
        match roof_run(ctx, scheme.params.clone(), scheme.label, group, 2.2) {
            Ok(r) => {
                g.particle_steps += r.particle_steps;
                g.checks.push(r.inside.clone());
                g.checks.push(info_row(
                    group,
                    &format!("{}: peak roof pressure of the §3.2 case", scheme.label),
                    format!(
                        "{} kPa (±20-step window), {} kPa instantaneous",
                        fmt_num(peak(&r.windowed) / 1e3),
                        fmt_num(peak(&r.raw) / 1e3)
                    ),
                    "-".into(),
                    "-".into(),
                    "reported: the impact peak (paper Fig. 8: 0.6 m tank)",
                ));
            }
            Err(e) => g.checks.push(failed_run(
                group,
                &format!("{} §3.2 roof case", scheme.label),
                &format!("{e:#}"),
            )),
        }
    }
    g.notes.push(format!(
        "Hydrostatics: paper §3.1 tank, dx = {DX} m, the snapshot at the end of {SETTLE} s of          settling. Roof: paper §3.2 (1.0 m wide tank, roof at 0.6 m, 0.5 m of water,          A = 0.0279 m, ω = 5.311 rad/s, 2.2 s of excitation after {SETTLE} s of settling), wall          loads from the Adami extrapolation at the wall face. The paper's stiffness B =          1.013×10⁵ Pa throughout."
    ));
    g
}

/// What the 50 s run returns.
struct StabilityRun {
    /// Time reached (s).
    end_time: f64,
    /// Largest roof pressure (Pa), ±20-step window.
    roof_peak: f64,
    /// The "stayed inside" row.
    inside: Check,
    particle_steps: f64,
    /// Mean fluid density (kg/m³) at the excitation start and at the end.
    mean_density: (f64, f64),
}

/// The §3.3 case (1.0 m wide, H = 0.5 m, clearance 0.2 H, A = 0.0093 m at ω₁) run 50 s with the
/// modern scheme (its own stage of the full suite).
pub fn stability(ctx: &Context) -> GroupResult {
    let group = "Modern 50 s";
    let mut g = GroupResult::default();
    let run = || -> anyhow::Result<StabilityRun> {
        let tank_height = DEPTH * 1.2;
        let mut sim = rect_sim_with(
            SphParams::modern().with_paper_stiffness(),
            WIDTH,
            tank_height,
            DEPTH,
            true,
            0.0,
            DX,
        )?;
        let omega = 2.0 * std::f64::consts::PI / rectangular_period(WIDTH, DEPTH, GRAVITY, 1);
        let excitation = SineExcitation {
            amplitude: AMPLITUDE,
            omega,
            settle: SETTLE,
        };
        let n_all = (sim.fluid().position.len() + sim.walls().position.len()) as f64;
        let on_roof = roof_load_points(&sim);
        let mut roof_p: f64 = 0.0;
        ctx.say(&format!(
            "modern scheme: §3.3 case 50 s (roof at {tank_height} m, ω₁ = {omega:.3} rad/s)"
        ));
        let mut steps = 0.0;
        let mean_density = |sim: &Simulation<2>| {
            let rho = &sim.fluid().density;
            rho.iter().sum::<f64>() / rho.len().max(1) as f64
        };
        let mut density_at_start = None;
        let ground = |t| [excitation.ground_accel(t), 0.0, 0.0];
        step_until_around(&mut sim, ground, SETTLE + 50.0, "stopped", |phase, sim| {
            match phase {
                StepPhase::Before(_) => {
                    if density_at_start.is_none() && sim.time() >= SETTLE {
                        density_at_start = Some(mean_density(sim));
                    }
                }
                StepPhase::After => {
                    steps += n_all;
                    let p = sim.loads().centred_pressure();
                    for &k in &on_roof {
                        roof_p = roof_p.max(p[k]);
                    }
                }
            }
            Ok(())
        })?;
        let densities = (density_at_start.unwrap_or(f64::NAN), mean_density(&sim));
        Ok(StabilityRun {
            end_time: sim.time(),
            roof_peak: roof_p,
            inside: stayed_inside(group, &sim),
            particle_steps: steps,
            mean_density: densities,
        })
    };
    match run() {
        Ok(StabilityRun {
            end_time: t,
            roof_peak: roof_p,
            inside,
            particle_steps: steps,
            mean_density: (rho_start, rho_end),
        }) => {
            g.particle_steps = steps;
            g.checks.push(inside);
            g.checks.push(info_row(
                group,
                "reached t (s) without blow-up; peak roof pressure",
                format!("{t:.2} s; {} kPa", fmt_num(roof_p / 1e3)),
                "52 s".into(),
                "-".into(),
                "a 50 s run of the §3.3 case stays stable (a blow-up fails the run)",
            ));
            g.checks.push(info_row(
                group,
                "mean fluid density at the excitation start and at the end (kg/m³)",
                format!("{rho_start:.2} → {rho_end:.2}"),
                "-".into(),
                format!("{:+.3} %", 100.0 * (rho_end / rho_start - 1.0)),
                "reported: a drift of the mean density is a drift of the liquid's volume (the \
                 particle masses are fixed)",
            ));
        }
        Err(e) => g
            .checks
            .push(failed_run(group, "50 s run", &format!("{e:#}"))),
    }
    g
}

#[cfg(test)]
mod tests {
    use super::roughness;

    /// A 30 ms half-sine impact pulse sampled every 0.25 ms (the modern roof case's step),
    /// alone and with a step-to-step alternating error of ε.
    fn pulse(noise: f64) -> (Vec<f64>, Vec<f64>) {
        let (dt, duration, n) = (2.5e-4, 0.03, 400);
        let ts: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
        let ps = ts
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                let smooth = if t < duration {
                    (std::f64::consts::PI * t / duration).sin()
                } else {
                    0.0
                };
                smooth + noise * if k % 2 == 0 { 1.0 } else { -1.0 }
            })
            .collect();
        (ts, ps)
    }

    #[test]
    fn spike_measure_ignores_a_resolved_pulse_and_finds_step_noise() {
        // A resolved pulse departs from its ±2.3 ms running mean by (ωw)²/6 ≈ 1 % of its
        // height along the sine and by a few per cent over the few samples at its sharp onset
        // and end: under 2 % in RMS over the record (the modern roof history reads 1.2 %, the
        // paper scheme's 7.9 %).
        let (ts, ps) = pulse(0.0);
        let smooth = roughness(&ts, &ps, 0.0023, 0.01);
        assert!(smooth < 0.02, "smooth pulse: {smooth}");
        // Alternating noise ε survives the running mean whole: the ±2.3 ms window holds 19
        // samples, 10 of them of the other sign than the centre's, so the departure is
        // ε (1 + 1/19); the ±10 ms mean of the pulse peaks at (3/π) sin(π/3) = 0.827 of its
        // height. So the measure is ε (1 + 1/19) / 0.827, to within the smooth part's 1.6 %
        // added in quadrature (1 % of the measure).
        let eps = 0.1;
        let (ts, ps) = pulse(eps);
        let noisy = roughness(&ts, &ps, 0.0023, 0.01);
        let expected = eps * (1.0 + 1.0 / 19.0)
            / (3.0 / std::f64::consts::PI * (std::f64::consts::PI / 3.0).sin());
        assert!(
            (noisy / expected - 1.0).abs() < 0.05,
            "noisy pulse: {noisy}, expected {expected}"
        );
    }
}
