//! Sloshing checks against potential theory and Housner: hydrostatic pressure (paper Fig. 2),
//! resonant and off-resonance forced response (Fig. 3), wall pressure against Housner (Fig. 4),
//! base shear (Fig. 5) and the free-sloshing period of three tanks.

use super::run::{
    interpolate, max_in_window, paper_params, rect_sim, rect_sim_with, rms, slope_through_origin,
    zero_crossings, Context, Runner, SineExcitation, GRAVITY, RHO,
};
use super::{
    failed_run, fmt_num, info_row, plot_path, ratio_band_check, relative_check, GroupResult,
    PlotRef,
};
use slosh_core::{Simulation, SphParams};
use slosh_io::{scatter_with_identity, PlotSpec, Series};
use slosh_theory::housner;
use slosh_theory::linear::RectangularTank;
use slosh_theory::modal::{sine_response, ModalTank};
use slosh_theory::natural::rectangular_period;

/// The paper's §3.1 tank: 1.0 m wide, 1.0 m high with a roof, 0.5 m of water.
pub(crate) const PAPER_WIDTH: f64 = 1.0;
pub(crate) const PAPER_HEIGHT: f64 = 1.0;
pub(crate) const PAPER_DEPTH: f64 = 0.5;
/// The paper's excitation: A = 0.0093 m, ω = 5.311 rad/s after 2 s of settling.
pub(crate) const PAPER_AMPLITUDE: f64 = 0.0093;
pub(crate) const PAPER_OMEGA: f64 = 5.311;
pub(crate) const PAPER_SETTLE: f64 = 2.0;
/// The paper's particle spacing (m).
pub(crate) const PAPER_DX: f64 = 0.02;
/// Modes carried by the linear solution (higher ones quasi-static; 10 is converged to 1e-4).
pub(crate) const MODES: usize = 10;
/// Interval of the elevation samples (s).
pub(crate) const SAMPLE: f64 = 0.005;

/// Tolerance of the hydrostatic slope: 5 %. The summation density of the first
/// particle rows next to the walls and the surface reset (Eq. 20) bias particle pressures by a
/// few per cent of ρ g d; a larger slope error would mean a wrong EOS or gravity.
const HYDROSTATIC_TOL: f64 = 0.05;
/// Resonant crest band (ratio SPH / undamped linear theory): a prototype of the scheme measured 0.04–0.05 m
/// against 0.058 m of linear theory at 2 s (ratio 0.7–0.86). Linear theory has no damping, so
/// the SPH crest must be lower, but not by more than 40 % (the paper's Fig. 3 shows the wave
/// "somewhat below" experiment); above 1.1 would mean energy gain or a wrong forcing.
const RESONANT_BAND: (f64, f64) = (0.6, 1.1);
/// Slope tolerance of wall pressure against Housner at 3.0 s (total pressure): the 5 % of the
/// hydrostatic part plus 5 % for Housner's plane-surface approximation (its masses and
/// frequency are within ≈ 3–5 % of potential theory, Housner 1957).
const HOUSNER_PRESSURE_TOL: f64 = 0.10;
/// Tolerance of the normalised RMS difference of the base-shear history against Housner fed
/// with the SPH's own surface slope. Housner's convective force for a plane surface differs
/// from the cosine first mode by ≈ 10 % when the slope is taken from the wall elevations
/// (8/π² = 0.81 vs 1, partly offset by the convective-mass approximation), and the ±20-step
/// windowed SPH wall pressure keeps noise of ≈ 10–20 % of the signal: 30 % in all.
const HOUSNER_SHEAR_TOL: f64 = 0.30;
/// The period tolerance of the paper scheme: 5 %. The dynamic-boundary walls hold
/// the liquid about one kernel width away, a narrower effective tank: the period comes out a
/// few per cent short (a prototype of the scheme: 1.5–6 %).
const PERIOD_TOL: f64 = 0.05;

/// The paper's §3.1 run (hydrostatic, resonant crest, Housner pressure at 3 s and 7 s, base
/// shear); one simulation feeds four groups.
pub fn paper_forced_case(ctx: &Context) -> Vec<(String, GroupResult)> {
    let titles = [
        "Hydrostatic pressure (paper Fig. 2)",
        "Linear forced response, resonant (paper Fig. 3)",
        "Wall pressure against Housner (paper Fig. 4)",
        "Base shear (paper Fig. 5)",
    ];
    match paper_forced_inner(ctx) {
        Ok(groups) => titles.iter().map(|t| t.to_string()).zip(groups).collect(),
        Err(e) => titles
            .iter()
            .map(|t| {
                let mut g = GroupResult::default();
                g.checks
                    .push(failed_run(t, "paper §3.1 run", &format!("{e:#}")));
                (t.to_string(), g)
            })
            .collect(),
    }
}

/// A snapshot of the fluid particles' pressures (paper Fig. 4 plots every particle).
struct WallSnapshot {
    time: f64,
    positions: Vec<(f64, f64)>,
    pressure: Vec<f64>,
}

fn paper_forced_inner(ctx: &Context) -> anyhow::Result<Vec<GroupResult>> {
    let sim = rect_sim(PAPER_WIDTH, PAPER_HEIGHT, PAPER_DEPTH, true, 0.0, PAPER_DX)?;
    let excitation = SineExcitation {
        amplitude: PAPER_AMPLITUDE,
        omega: PAPER_OMEGA,
        settle: PAPER_SETTLE,
    };
    let mut runner = Runner::new(sim, excitation, SAMPLE);
    let still = runner.still_level;

    // Snapshot times after the excitation start: 3.0 s always, 7.0 s in the full suite.
    let targets: Vec<f64> = if ctx.quick { vec![3.0] } else { vec![3.0, 7.0] };
    let t_end = PAPER_SETTLE + targets.last().copied().unwrap_or(3.0) + 0.05;
    ctx.say(&format!(
        "paper tank 1.0 × 0.5 m, dx = {PAPER_DX} m, {} fluid particles, to t = {t_end:.2} s",
        runner.sim.fluid().position.len()
    ));
    let mut hydro: Option<(Vec<f64>, Vec<f64>)> = None;
    let mut snaps: Vec<WallSnapshot> = Vec::new();
    runner.run_until(t_end, |sim| {
        if hydro.is_none() && sim.time() >= PAPER_SETTLE {
            let f = sim.fluid();
            let depth: Vec<f64> = f.position.iter().map(|p| still - p.y).collect();
            hydro = Some((depth, f.pressure.clone()));
        }
        let next = snaps.len();
        if next < targets.len() && sim.time() >= PAPER_SETTLE + targets[next] {
            let f = sim.fluid();
            snaps.push(WallSnapshot {
                time: sim.time(),
                positions: f.position.iter().map(|p| (p.x, p.y)).collect(),
                pressure: f.pressure.clone(),
            });
        }
    })?;
    let h = runner.history.clone();
    let theory = RectangularTank::water(PAPER_WIDTH, PAPER_DEPTH);
    let force = excitation.body_force_amplitude();
    let gauge = runner.gauge_x;
    let out = &ctx.out;

    // ---- Fig. 2: hydrostatic pressure ----
    let mut g_hydro = GroupResult::default();
    let group = "Hydrostatic";
    if let Some((depth, pressure)) = hydro {
        let reference: Vec<f64> = depth.iter().map(|d| RHO * GRAVITY * d).collect();
        let (slope, r2) = slope_through_origin(&reference, &pressure);
        g_hydro.checks.push(relative_check(
            group,
            "slope of p against ρ g d, all fluid particles at t = 2.0 s (end of settling)",
            slope,
            1.0,
            "",
            HYDROSTATIC_TOL,
            "5 %: summation density of the rows next to walls and surface reset bias \
             particle pressures by a few % of ρgd; more would mean a wrong EOS or gravity",
        ));
        g_hydro.checks.push(info_row(
            group,
            "R² of that fit (instantaneous particle pressure scatter)",
            format!("{r2:.3}"),
            "1".into(),
            format!("{:.3}", 1.0 - r2),
            "reported: the paper scheme's pressure noise (≈ 19 % of ρgH)",
        ));
        let stem = "fig2_hydrostatic";
        let _ = scatter_with_identity(
            plot_path(out, stem),
            &PlotSpec::new(
                "Hydrostatic pressure after 2 s settling (paper Fig. 2), dx = 0.02 m",
                "ρ g d (Pa)",
                "SPH particle pressure p (Pa)",
            ),
            &[Series::points("fluid particles", &reference, &pressure)],
        );
        g_hydro.plots.push(PlotRef {
            file: format!("{stem}.png"),
            caption: "particle pressure against ρ g d after settling, with p = ρ g d".into(),
        });
    } else {
        g_hydro
            .checks
            .push(failed_run(group, "hydrostatic slope", "no snapshot taken"));
    }
    g_hydro.notes.push(format!(
        "Paper §3.1 tank (1.0 m wide, 0.5 m water, roof at 1.0 m), dx = 0.02 m, paper scheme \
         (`SphParams::default()`); depth d measured from the still level {still:.4} m \
         (fill level lowered by the EOS compression)."
    ));
    g_hydro.particle_steps = h.particle_steps;

    // ---- Fig. 3: resonant response ----
    let mut g_res = GroupResult::default();
    let group = "Resonant";
    let te: Vec<f64> = h.t.iter().map(|t| t - PAPER_SETTLE).collect();
    let theory_eta: Vec<f64> = te
        .iter()
        .map(|&t| {
            if t < 0.0 {
                0.0
            } else {
                theory.elevation(
                    &sine_response(&theory, force, PAPER_OMEGA, t, MODES),
                    gauge.0,
                )
            }
        })
        .collect();
    let (sph_crest, t_sph) = max_in_window(&te, &h.eta_left, 1.2, 2.4);
    let (lin_crest, t_lin) = max_in_window(&te, &theory_eta, 1.2, 2.4);
    g_res.checks.push(ratio_band_check(
        group,
        &format!("first crest at the left wall (SPH at {t_sph:.2} s, theory at {t_lin:.2} s after start)"),
        sph_crest,
        lin_crest,
        "m",
        RESONANT_BAND,
        "undamped linear theory must lie above the SPH crest; a prototype of the scheme: 0.7–0.86; \
         below 0.6 = excess numerical damping, above 1.1 = spurious energy",
    ));
    let (sph_trough, _) = max_in_window(
        &te,
        &h.eta_left.iter().map(|v| -v).collect::<Vec<_>>(),
        0.0,
        3.0,
    );
    let (lin_trough, _) = max_in_window(
        &te,
        &theory_eta.iter().map(|v| -v).collect::<Vec<_>>(),
        0.0,
        3.0,
    );
    g_res.checks.push(info_row(
        group,
        "deepest trough at the left wall, first 3 s",
        format!("{} m", fmt_num(-sph_trough)),
        format!("{} m", fmt_num(-lin_trough)),
        format!("ratio {:.3}", sph_trough / lin_trough),
        "reported: troughs are smaller than crests in the SPH",
    ));
    if !ctx.quick {
        let (c2, t2) = max_in_window(&te, &h.eta_left, 4.7, 5.9);
        let (l2, _) = max_in_window(&te, &theory_eta, 4.7, 5.9);
        g_res.checks.push(info_row(
            group,
            &format!("second crest (SPH at {t2:.2} s)"),
            format!("{} m", fmt_num(c2)),
            format!("{} m", fmt_num(l2)),
            format!("ratio {:.3}", c2 / l2),
            "reported: linear theory grows without bound at resonance; the SPH is damped and \
             nonlinear by then (ζ/H ≈ 0.3)",
        ));
    }
    let stem = "fig3_resonant_eta_left";
    let mask: Vec<usize> = (0..te.len()).filter(|&k| te[k] >= -0.2).collect();
    let (xs, ys_s, ys_t): (Vec<f64>, Vec<f64>, Vec<f64>) = (
        mask.iter().map(|&k| te[k]).collect(),
        mask.iter().map(|&k| h.eta_left[k]).collect(),
        mask.iter().map(|&k| theory_eta[k]).collect(),
    );
    g_res.add_line_plot(
        out,
        stem,
        &PlotSpec::new(
            "Resonant sloshing, paper case: elevation at the left wall (paper Fig. 3)",
            "time since excitation start t (s)",
            "η at left wall (m)",
        ),
        &[
            Series::line("SPH (paper scheme, dx = 0.02 m)", &xs, &ys_s),
            Series::dashed("linear potential theory (10 modes)", &xs, &ys_t),
        ],
        "η at the left wall, SPH against linear theory, A = 0.0093 m, ω = 5.311 rad/s",
    );
    g_res.notes.push(
        "Gauge one lattice spacing inside the left wall (as `slosh run`); theory evaluated at the \
         same x. Excitation a_g = A ω² sin ωt after 2 s settling (liquid feels −a_g)."
            .into(),
    );

    // ---- Fig. 4: Housner pressure ----
    let mut g_hou = GroupResult::default();
    let group = "Housner pressure";
    let l = 0.5 * PAPER_WIDTH;
    let depth_still = still; // floor at y = 0
    let omega_h = housner::convective_omega(l, depth_still, GRAVITY);
    let slope_at = |t: f64| {
        let el = interpolate(&h.t, &h.eta_left, t);
        let er = interpolate(&h.t, &h.eta_right, t);
        (er - el) / (gauge.1 - gauge.0)
    };
    let housner_wall_pressure = |t_sim: f64, x: f64, y: f64| {
        let f = force * (PAPER_OMEGA * (t_sim - PAPER_SETTLE)).sin();
        let xc = (x - l).clamp(-l, l);
        let below = (still - y).max(0.0);
        RHO * GRAVITY * below
            + housner::impulsive_pressure(RHO, f, depth_still, l, xc, below)
            + housner::convective_pressure(
                RHO,
                l,
                depth_still,
                omega_h,
                slope_at(t_sim),
                xc,
                y.max(0.0),
            )
    };
    let mut scatter: Vec<(String, Vec<f64>, Vec<f64>)> = Vec::new();
    for (k, &target) in targets.iter().enumerate() {
        let Some(s) = snaps.get(k) else {
            g_hou.checks.push(failed_run(
                group,
                &format!("{target} s"),
                "no snapshot taken",
            ));
            continue;
        };
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for (&(x, y), &p) in s.positions.iter().zip(&s.pressure) {
            if y < still {
                xs.push(housner_wall_pressure(s.time, x, y));
                ys.push(p);
            }
        }
        let (slope, r2) = slope_through_origin(&xs, &ys);
        let name = format!(
            "fit slope of particle p against Housner at {target:.1} s after start (R² = {r2:.3})"
        );
        if k == 0 {
            g_hou.checks.push(relative_check(
                group,
                &name,
                slope,
                1.0,
                "",
                HOUSNER_PRESSURE_TOL,
                "10 %: 5 % hydrostatic (Fig. 2) + 5 % Housner's plane-surface approximation",
            ));
        } else {
            g_hou.checks.push(info_row(
                group,
                &name,
                format!("{slope:.3}"),
                "1".into(),
                format!("{:+.1} %", 100.0 * (slope - 1.0)),
                "reported, no tolerance: the paper finds SPH above Housner at 7 s (nonlinear \
                 wave, ζ/H ≈ 0.25, outside Housner's linear range)",
            ));
        }
        scatter.push((format!("{target:.1} s after start"), xs, ys));
    }
    if ctx.quick {
        g_hou.checks.push(info_row(
            group,
            "fit slope at 7.0 s after start",
            "not run in --quick".into(),
            "1".into(),
            "—".into(),
            "the 7 s snapshot needs a 9 s run; the full suite reports it (no tolerance)",
        ));
    }
    let stem = "fig4_housner_pressure";
    let series: Vec<Series> = scatter
        .iter()
        .map(|(label, xs, ys)| Series::points(label.clone(), xs, ys))
        .collect();
    let _ = scatter_with_identity(
        plot_path(out, stem),
        &PlotSpec::new(
            "Particle pressure against Housner (paper Fig. 4)",
            "Housner p = ρgd + impulsive + convective (Pa)",
            "SPH particle pressure (Pa)",
        ),
        &series,
    );
    g_hou.plots.push(PlotRef {
        file: format!("{stem}.png"),
        caption: "fluid particle pressure against Housner (Eq. 24–26), as the paper's Fig. 4"
            .into(),
    });
    g_hou.notes.push(
        "Pressure of every fluid particle below the still level, as in the paper's Fig. 4 \
         (instantaneous EOS pressure). Housner: hydrostatic + \
         Eq. 25 with the applied body force + Eq. 26 with the surface slope measured in the SPH \
         ((η_right − η_left)/gauge distance), ω from Housner's own formula."
            .into(),
    );

    // ---- Fig. 5: base shear ----
    let mut g_bs = GroupResult::default();
    let group = "Base shear";
    let lt: Vec<f64> = h.load_t.iter().map(|t| t - PAPER_SETTLE).collect();
    let mut t_b = Vec::new();
    let mut v_sph = Vec::new();
    let mut v_lin = Vec::new();
    let mut v_hou = Vec::new();
    let m_i = housner::impulsive_mass(RHO, l, depth_still);
    for (k, &t) in lt.iter().enumerate() {
        if t < 0.0 {
            continue;
        }
        let s = sine_response(&theory, force, PAPER_OMEGA, t, MODES);
        let f = s.body_force;
        t_b.push(t);
        v_sph.push(h.base_shear[k]);
        v_lin.push(theory.base_shear(&s));
        v_hou
            .push(m_i * f + housner::convective_base_shear(RHO, l, omega_h, slope_at(h.load_t[k])));
    }
    let window = |ys: &[f64], a: f64, b: f64| -> Vec<f64> {
        t_b.iter()
            .zip(ys)
            .filter(|(t, _)| **t >= a && **t <= b)
            .map(|(_, v)| *v)
            .collect()
    };
    let (w0, w1) = (1.8, 3.0);
    let rms_sph = rms(&window(&v_sph, w0, w1));
    let rms_lin = rms(&window(&v_lin, w0, w1));
    g_bs.checks.push(ratio_band_check(
        group,
        "RMS base shear over 1.8–3.0 s after start, SPH / linear modal theory",
        rms_sph,
        rms_lin,
        "N/m",
        RESONANT_BAND,
        "same band as the resonant crest: the convective base shear is proportional to the \
         first-mode amplitude, which undamped theory overestimates",
    ));
    let t_hi = *targets.last().unwrap_or(&3.0);
    // 0.1 s centred running mean of the SPH shear: removes the acoustic noise of the weakly
    // compressible scheme, attenuates the 1.2 s sloshing signal by only sinc(π·0.1/1.18) ≈ 1 %.
    let v_smooth = running_mean(&t_b, &v_sph, 0.05);
    let diff: Vec<f64> = v_smooth.iter().zip(&v_hou).map(|(a, b)| a - b).collect();
    let nrms = rms(&window(&diff, 0.0, t_hi)) / rms(&window(&v_hou, 0.0, t_hi));
    g_bs.checks.push(Check {
        group: group.into(),
        name: format!(
            "normalised RMS difference of V(t) (0.1 s running mean) against Housner, 0–{t_hi:.0} s"
        ),
        measured: format!("{nrms:.3}"),
        reference: "0".into(),
        error: format!("{:.1} %", 100.0 * nrms),
        tolerance: format!("≤ {:.0} %", 100.0 * HOUSNER_SHEAR_TOL),
        reason: "plane-surface convective force vs cosine mode ≈ 10 %, windowed wall-pressure \
                 noise 10–20 % of the signal"
            .into(),
        verdict: if nrms.is_finite() && nrms <= HOUSNER_SHEAR_TOL {
            super::Verdict::Pass
        } else {
            super::Verdict::Fail
        },
    });
    let peak = |ys: &[f64]| ys.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    g_bs.checks.push(info_row(
        group,
        "peak |V| over 0–3 s, SPH vs linear",
        format!("{} N/m", fmt_num(peak(&window(&v_sph, 0.0, 3.0)))),
        format!("{} N/m", fmt_num(peak(&window(&v_lin, 0.0, 3.0)))),
        format!(
            "ratio {:.3}",
            peak(&window(&v_sph, 0.0, 3.0)) / peak(&window(&v_lin, 0.0, 3.0))
        ),
        "reported: single peaks include the windowed pressure noise",
    ));
    let stem = "fig5_base_shear";
    g_bs.add_line_plot(
        out,
        stem,
        &PlotSpec::new(
            "Base shear, paper case (paper Fig. 5)",
            "time since excitation start t (s)",
            "base shear V (N/m)",
        ),
        &[
            Series::line("SPH (bottom + walls, ±20-step window)", &t_b, &v_sph),
            Series::line("SPH, 0.1 s running mean", &t_b, &v_smooth),
            Series::dashed("linear modal theory", &t_b, &v_lin),
            Series::dashed("Housner (SPH surface slope)", &t_b, &v_hou),
        ],
        "base shear: SPH, linear modal theory, Housner",
    );
    g_bs.notes.push(format!(
        "V = x-force of the liquid on parts `bottom` + `wall` from the time-windowed load points \
         (`slosh_core::loads::base_shear_x`). Linear theory: impulsive + convective modal sum; \
         Housner: m_i f + (2/3) ρ l³ ω_H² s with m_i = {m_i:.1} kg/m, ω_H = {omega_h:.4} rad/s."
    ));
    Ok(vec![g_hydro, g_res, g_hou, g_bs])
}

use super::Check;

/// Off-resonance forced response, Ω = 0.7 ω₁, paper tank.
pub fn off_resonance(ctx: &Context) -> GroupResult {
    match off_resonance_inner(ctx) {
        Ok(g) => g,
        Err(e) => {
            let mut g = GroupResult::default();
            g.checks
                .push(failed_run("Off resonance", "run", &format!("{e:#}")));
            g
        }
    }
}

/// Amplitude of the off-resonance run (m): larger than the paper's so that the response
/// (≈ 0.03 m, ζ/H ≈ 0.06) stands well above the gauge noise (≈ 1 mm) while staying linear.
const OFF_RES_AMPLITUDE: f64 = 0.02;
/// Settling before the off-resonance excitation (s): shorter than the paper's 2 s to fit the
/// quick budget; the start-up compression transient (≈ 1 mm) has died out by then.
const OFF_RES_SETTLE: f64 = 0.5;

fn off_resonance_inner(ctx: &Context) -> anyhow::Result<GroupResult> {
    let theory = RectangularTank::water(PAPER_WIDTH, PAPER_DEPTH);
    let w1 = theory.modal_omega(0);
    let omega = 0.7 * w1;
    let cycles = if ctx.quick { 1.5 } else { 3.0 };
    let t_exc = cycles * 2.0 * std::f64::consts::PI / omega;
    let excitation = SineExcitation {
        amplitude: OFF_RES_AMPLITUDE,
        omega,
        settle: OFF_RES_SETTLE,
    };
    let sim = rect_sim(PAPER_WIDTH, PAPER_HEIGHT, PAPER_DEPTH, true, 0.0, PAPER_DX)?;
    let mut runner = Runner::new(sim, excitation, SAMPLE);
    ctx.say(&format!(
        "off resonance Ω = {omega:.3} rad/s, A = {OFF_RES_AMPLITUDE} m, {cycles} cycles"
    ));
    runner.run_until(OFF_RES_SETTLE + t_exc, |_| {})?;
    let h = &runner.history;
    let force = excitation.body_force_amplitude();
    let gauge = runner.gauge_x.0;
    // Theory with all natural frequencies raised by 5 % (g scaled; modal gains ω²/g unchanged):
    // what the allowed 5 % period error of the paper scheme does to this response.
    let shifted = RectangularTank {
        gravity: GRAVITY / 0.95f64.powi(2),
        ..theory
    };
    let (mut ts, mut sph, mut lin, mut lin_shift) = (vec![], vec![], vec![], vec![]);
    for (k, &t) in h.t.iter().enumerate() {
        let te = t - OFF_RES_SETTLE;
        if te < 0.0 || !h.eta_left[k].is_finite() {
            continue;
        }
        ts.push(te);
        sph.push(h.eta_left[k]);
        lin.push(theory.elevation(&sine_response(&theory, force, omega, te, MODES), gauge));
        lin_shift.push(shifted.elevation(&sine_response(&shifted, force, omega, te, MODES), gauge));
    }
    let amp_ratio = rms(&sph) / rms(&lin);
    let amp_shift = rms(&lin_shift) / rms(&lin);
    let lag = best_lag(&ts, &sph, &lin);
    let lag_shift = best_lag(&ts, &lin_shift, &lin);
    let amp_tol = (amp_shift - 1.0).abs() + 0.05;
    let lag_tol = lag_shift.abs() + 0.02;
    let mut g = GroupResult::default();
    let group = "Off resonance";
    let mut c = relative_check(
        group,
        &format!("RMS of η at the left wall over {cycles} forcing cycles, Ω = 0.7 ω₁"),
        rms(&sph),
        rms(&lin),
        "m",
        amp_tol,
        "",
    );
    c.tolerance = format!("± {:.0} %", 100.0 * amp_tol);
    c.reason = format!(
        "what a 5 % shorter natural period (the paper scheme's allowance) does to linear \
         theory ({:+.1} %), + 5 % for gauge noise and numerical damping",
        100.0 * (amp_shift - 1.0)
    );
    g.checks.push(c);
    let phase_deg = lag * omega.to_degrees();
    g.checks.push(Check {
        group: group.into(),
        name: "time lag of SPH behind theory (cross-correlation)".into(),
        measured: format!("{lag:+.3} s ({phase_deg:+.0}° of the forcing)"),
        reference: "0 s".into(),
        error: format!("{lag:+.3} s"),
        tolerance: format!("|lag| ≤ {lag_tol:.3} s"),
        reason: format!(
            "lag that a 5 % shorter natural period produces in theory ({lag_shift:+.3} s) + \
             0.02 s (4 samples) for noise"
        ),
        verdict: if lag.is_finite() && lag.abs() <= lag_tol {
            super::Verdict::Pass
        } else {
            super::Verdict::Fail
        },
    });
    let _ = amp_ratio;
    let stem = "off_resonance_eta_left";
    g.add_line_plot(
        &ctx.out,
        stem,
        &PlotSpec::new(
            "Off-resonance forcing Ω = 0.7 ω₁, A = 0.02 m: elevation at the left wall",
            "time since excitation start t (s)",
            "η at left wall (m)",
        ),
        &[
            Series::line("SPH (paper scheme, dx = 0.02 m)", &ts, &sph),
            Series::dashed("linear potential theory", &ts, &lin),
            Series::dashed("theory, natural periods 5 % shorter", &ts, &lin_shift),
        ],
        "off-resonance response against linear theory",
    );
    g.notes.push(format!(
        "Paper tank, dx = 0.02 m, A = {OFF_RES_AMPLITUDE} m, Ω = 0.7 ω₁ = {omega:.3} rad/s after \
         {OFF_RES_SETTLE} s settling. Tolerances are derived, not chosen: theory is re-evaluated \
         with every natural period 5 % shorter (the paper scheme's period allowance) and the \
         change it makes is the bulk of the tolerance."
    ));
    g.particle_steps = h.particle_steps;
    Ok(g)
}

/// Lag τ (s, within ±0.3 s, 1 ms grid) maximising Σ a(t)·b(t − τ): positive when `a` is late.
fn best_lag(ts: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let mut best = (f64::NEG_INFINITY, f64::NAN);
    for k in -300..=300 {
        let tau = k as f64 * 1e-3;
        let mut sum = 0.0;
        for (&t, &y) in ts.iter().zip(a) {
            let v = interpolate(ts, b, t - tau);
            if v.is_finite() {
                sum += y * v;
            }
        }
        if sum > best.0 {
            best = (sum, tau);
        }
    }
    best.1
}

/// The three free-sloshing tanks: (width, depth) in m, widths/depths 1, 2 and 4.
const FREE_TANKS: [(f64, f64); 3] = [(0.5, 0.5), (1.0, 0.5), (1.0, 0.24)];

/// Free-sloshing period from an initial linear tilt, three tanks.
pub fn free_sloshing(ctx: &Context) -> GroupResult {
    let mut g = GroupResult::default();
    let mut curves: Vec<(String, Vec<f64>, Vec<f64>)> = Vec::new();
    for &(w, d) in &FREE_TANKS {
        match free_period(
            ctx,
            paper_params(),
            w,
            d,
            PAPER_DX,
            if ctx.quick { 1.6 } else { 2.6 },
        ) {
            Ok(r) => {
                g.checks.push(r.check(
                    "Free sloshing",
                    &format!(
                        "T₁, tank {w} × {d} m (W/H = {:.0}), dx = {PAPER_DX} m",
                        w / d
                    ),
                ));
                g.particle_steps += r.particle_steps;
                curves.push((format!("W/H = {:.0} SPH", w / d), r.t_scaled, r.eta_scaled));
                if g.notes.is_empty() {
                    g.notes.push(
                        "Open tank, initial linear tilt of the surface (elevation 0.1 H at the left \
                         wall), no settling. The surface at ten gauges across the tank is projected on \
                         the first mode, β₁ = (2/L)∫η cos(πx/L)dx (removes the higher modes of the \
                         tilt); period = time between the 1st and 3rd zero crossing of β₁ (full \
                         suite: mean over every such pair). Reference: T₁ = 2π/ω₁, \
                         ω₁² = g k tanh(kH), k = π/L."
                            .into(),
                    );
                }
                g.notes.push(r.note);
            }
            Err(e) => g.checks.push(failed_run(
                "Free sloshing",
                &format!("tank {w} × {d} m"),
                &format!("{e:#}"),
            )),
        }
    }
    let stem = "free_sloshing";
    let series: Vec<Series> = curves
        .iter()
        .map(|(label, xs, ys)| Series::line(label.clone(), xs, ys))
        .collect();
    g.add_line_plot(
        &ctx.out,
        stem,
        &PlotSpec::new(
            "Free sloshing from an initial tilt, three tanks",
            "t / T₁ (theory) (-)",
            "first-mode amplitude β₁ / β₁(0) (-)",
        ),
        &series,
        "normalised left-wall elevation of the three free-sloshing tanks",
    );
    g
}

/// Result of one free-sloshing run.
pub struct FreePeriod {
    /// Measured period (s).
    pub measured: f64,
    /// Reference period: T₁ = 2π/ω₁ of potential theory (s).
    pub reference: f64,
    /// Time / T₁ samples for the plot.
    pub t_scaled: Vec<f64>,
    /// η / tilt samples for the plot.
    pub eta_scaled: Vec<f64>,
    /// Particle-steps.
    pub particle_steps: f64,
    /// A line for the notes.
    pub note: String,
}

impl FreePeriod {
    /// The report row.
    pub fn check(&self, group: &str, name: &str) -> Check {
        relative_check(
            group,
            name,
            self.measured,
            self.reference,
            "s",
            PERIOD_TOL,
            "5 %: the paper scheme's dynamic walls keep the liquid ≈ one kernel width \
             off the wall, a narrower tank: the period comes out a few % short",
        )
    }
}

/// Runs a tilted open tank for `periods` × T₁ and measures the period of the first mode.
///
/// The surface is sampled at ten gauges across the tank and projected on the first mode,
/// β₁(t) = (2/L) ∫ η cos(k₁x′) dx′ (midpoint rule), which removes the higher modes of the
/// initial linear tilt (n = 3 carries 11 % of it and would shift single zero crossings by
/// ≈ 2–3 %); the period is taken from the zero crossings of β₁.
pub fn free_period(
    ctx: &Context,
    params: SphParams,
    width: f64,
    depth: f64,
    dx: f64,
    periods: f64,
) -> anyhow::Result<FreePeriod> {
    let tilt = 0.1 * depth;
    // Open tank, walls 0.2 m above the still surface (whole multiples of dx).
    let tank_height = ((depth + 0.2) / dx).round() * dx;
    let sim = rect_sim_with(params, width, tank_height, depth, false, tilt, dx)?;
    // Theory for the depth the lattice represents (whole rows of dx).
    let depth = sim.fill_level() - sim.interior_bounds().0.y;
    let t1 = rectangular_period(width, depth, GRAVITY, 1);
    let sample = (t1 / 200.0).min(SAMPLE);
    let mut runner = Runner::new(sim, SineExcitation::none(), sample);
    ctx.say(&format!(
        "free sloshing {width} × {depth:.3} m, dx = {dx} m, {} fluid particles, {periods} T₁",
        runner.sim.fluid().position.len()
    ));
    let n_gauges = 10;
    let k1 = std::f64::consts::PI / width;
    let gauges: Vec<f64> = (0..n_gauges)
        .map(|i| (i as f64 + 0.5) * width / n_gauges as f64)
        .collect();
    let (mut ts, mut beta) = (Vec::new(), Vec::new());
    let mut next = 0.0;
    let still = runner.still_level;
    let project = |sim: &Simulation<2>, ts: &mut Vec<f64>, beta: &mut Vec<f64>| {
        let mut sum = 0.0;
        for &x in &gauges {
            let eta = sim.surface_level_at(&[x]).map(|z| z - still).unwrap_or(0.0);
            sum += eta * (k1 * x).cos();
        }
        ts.push(sim.time());
        beta.push(2.0 * sum / n_gauges as f64);
    };
    project(&runner.sim, &mut ts, &mut beta);
    runner.run_until(periods * t1, |sim| {
        if sim.time() >= next {
            next += sample;
            project(sim, &mut ts, &mut beta);
        }
    })?;
    let beta0 = beta[0];
    let measured = period_from_crossings(&zero_crossings(&ts, &beta, 0.2 * beta0.abs()));
    let note = format!(
        "Tank {width} × {depth:.3} m, dx = {dx} m: T₁ = {t1:.4} s, SPH {measured:.4} s \
         (initial first-mode amplitude {beta0:.4} m)."
    );
    Ok(FreePeriod {
        measured,
        reference: t1,
        t_scaled: ts.iter().map(|t| t / t1).collect(),
        eta_scaled: beta.iter().map(|e| e / beta0).collect(),
        particle_steps: runner.history.particle_steps,
        note,
    })
}

/// Mean of t(c_{k+2}) − t(c_k) over the crossings (one full period each); NaN if fewer than 3.
pub fn period_from_crossings(crossings: &[(f64, i8)]) -> f64 {
    if crossings.len() < 3 {
        return f64::NAN;
    }
    let periods: Vec<f64> = crossings.windows(3).map(|w| w[2].0 - w[0].0).collect();
    periods.iter().sum::<f64>() / periods.len() as f64
}

/// Centred running mean of `ys` over ±`half` s (samples with finite values only).
pub(crate) fn running_mean(ts: &[f64], ys: &[f64], half: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(ts.len());
    let (mut lo, mut hi) = (0usize, 0usize);
    let mut sum = 0.0;
    for &t in ts {
        while hi < ts.len() && ts[hi] <= t + half {
            sum += ys[hi];
            hi += 1;
        }
        while ts[lo] < t - half {
            sum -= ys[lo];
            lo += 1;
        }
        out.push(sum / (hi - lo) as f64);
    }
    out
}
