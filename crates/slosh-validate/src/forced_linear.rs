//! The forced linear response from rest, judged crest by crest: a horizontal harmonic ground
//! motion above the first natural frequency, sized so that linear theory's largest early crest
//! at the wall is 0.12 of the depth, and the same at half the amplitude, in both presets; the
//! first three crest-to-trough heights of the wall elevation (judged at 0.12 H) and the first
//! three base-shear extremes (judged at 0.06 H, where linear theory holds the force to about
//! 1 %) against the undamped linear closed form from rest (`slosh_theory::modal::sine_response`).
//!
//! Beside the two presets the modern preset is run with one part changed at a time (the wall
//! pressure floor, the start, the kernel, the density, the walls, the integrator, the
//! artificial viscosity) and with a second gauge further from the wall, so that what makes a
//! crest overshoot is measured, not guessed.

use super::run::{interpolate, zero_crossings, Context, Runner, Scheme, SineExcitation};
use super::sloshing::{running_mean, MODES};
use super::{failed_run, info_row, open_if_failed, Check, GroupResult, Verdict};
use slosh_core::{
    BoundaryMethod, DensityDiffusion, DensityMethod, Integrator, KernelKind, Simulation, SphParams,
    ViscousOperator,
};
use slosh_geometry::RectTank2;
use slosh_io::{PlotSpec, Series};
use slosh_theory::linear::RectangularTank;
use slosh_theory::modal::{sine_response, ModalTank};

/// The group of the report.
const GROUP: &str = "Forced linear response from rest";
/// Tank (m): the paper's 1.0 m section with 0.5 m of water, open, walls 0.8 m high.
const WIDTH: f64 = 1.0;
/// Still depth (m).
const DEPTH: f64 = 0.5;
/// Tank height (m).
const HEIGHT: f64 = 0.8;
/// Spacing (m): 25 particles per depth.
const DX: f64 = 0.02;
/// Forcing frequency over the first natural frequency: above resonance, where the response
/// from rest beats between Ω and ω₁ and its crests grow over the first cycles.
const FREQUENCY_RATIO: f64 = 1.25;
/// Linear theory's largest wall crest over the judged half cycles, over the depth.
const CREST_OVER_DEPTH: f64 = 0.12;
/// Settling before the excitation (s): the start-up transient of either preset has died out.
const SETTLE: f64 = 0.5;
/// Crest tolerance: 5 % of linear theory (at a crest of 0.12 H the second-order correction of
/// a standing wave is of order k a/2 ≈ 10 % on crests and troughs alike in opposite senses,
/// and the half-cycle extremes compared here are the crests of one wall and its troughs).
const CREST_TOL: f64 = 0.05;
/// Half cycles judged.
const CRESTS: usize = 3;
/// Amplitude scale of the base-shear judgement: half the ground amplitude, crests of 0.06 H.
/// The horizontal force of a wave excited horizontally is odd in the wave height, so it
/// leaves linear theory at third order, by (k a)² with k = π/L and a the crest (about 3.6 %
/// at 0.12 H in this tank, 0.9 % at 0.06 H): at 0.12 H that alone would take most of the
/// 5 % tolerance.
const SHEAR_JUDGED_SCALE: f64 = 0.5;
/// Running mean of the base shear (± s) before its extremes are read: the load points'
/// pressure noise of the paper scheme is at the step scale.
const SHEAR_MEAN_HALF: f64 = 0.025;

/// The linear theory of the case: the tank, the forcing, and the first [`CRESTS`] half-cycle
/// windows of the wall elevation (from its zero crossings).
#[derive(Clone, Copy)]
struct Case {
    tank: RectangularTank,
    omega: f64,
    amplitude: f64,
    duration: f64,
}

impl Case {
    fn new() -> Case {
        let tank = RectangularTank::water(WIDTH, DEPTH);
        let omega = FREQUENCY_RATIO * tank.modal_omega(0);
        // Linear: the crest for A = 1 m gives the amplitude of a 0.12 H crest.
        let unit = Case {
            tank,
            omega,
            amplitude: 1.0,
            duration: 6.0 * 2.0 * std::f64::consts::PI / omega,
        };
        let (ts, eta) = unit.theory(unit.duration, DX, |s, x| unit.tank.elevation(s, x));
        let extremes = half_cycle_windows(&ts, &eta);
        let largest = extremes
            .iter()
            .take(CRESTS)
            .map(|w| w.2.abs())
            .fold(0.0, f64::max);
        // Through the half cycle after the judged ones (its extreme closes the third height),
        // with a quarter of it to spare for a phase error.
        let end = extremes
            .get(CRESTS)
            .map(|w| w.1 + 0.25 * (w.1 - w.0))
            .unwrap_or(unit.duration);
        Case {
            amplitude: CREST_OVER_DEPTH * DEPTH / largest,
            duration: end,
            ..unit
        }
    }

    fn excitation(&self) -> SineExcitation {
        SineExcitation {
            amplitude: self.amplitude,
            omega: self.omega,
            settle: SETTLE,
        }
    }

    /// Theory at 1 ms samples from the excitation start to `until` (s) of `quantity`(state, x)
    /// at x = `x` from the left wall.
    fn theory(
        &self,
        until: f64,
        x: f64,
        quantity: impl Fn(&slosh_theory::modal::ModalState, f64) -> f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let force = -self.amplitude * self.omega * self.omega;
        let n = (until / 1e-3).ceil() as usize;
        (0..=n)
            .map(|k| {
                let t = k as f64 * 1e-3;
                let s = sine_response(&self.tank, force, self.omega, t, MODES);
                (t, quantity(&s, x))
            })
            .unzip()
    }
}

/// The half cycles of `ys`(`ts`): (start, end, extreme of the theory) between its zero
/// crossings, the first from the start of the record.
fn half_cycle_windows(ts: &[f64], ys: &[f64]) -> Vec<(f64, f64, f64)> {
    let amp = ys.iter().fold(0.0f64, |m, y| m.max(y.abs()));
    let mut bounds = vec![ts[0]];
    bounds.extend(zero_crossings(ts, ys, 0.02 * amp).iter().map(|c| c.0));
    bounds
        .windows(2)
        .map(|w| {
            let ext = ts
                .iter()
                .zip(ys)
                .filter(|(t, _)| **t >= w[0] && **t <= w[1])
                .map(|(_, y)| *y)
                .fold(0.0f64, |m, y| if y.abs() > m.abs() { y } else { m });
            (w[0], w[1], ext)
        })
        .collect()
}

/// SPH extremes of the same sign as theory's in each theory half cycle (widened by a quarter
/// of its length on each side, for a phase error), beside theory's: (SPH, theory) per half
/// cycle, the first [`CRESTS`] + 1.
fn extreme_ratios(windows: &[(f64, f64, f64)], ts: &[f64], ys: &[f64]) -> Vec<(f64, f64)> {
    windows
        .iter()
        .take(CRESTS + 1)
        .map(|&(a, b, ext)| {
            let pad = 0.25 * (b - a);
            let sph = ts
                .iter()
                .zip(ys)
                .filter(|(t, y)| **t >= a - pad && **t <= b + pad && y.is_finite())
                .map(|(_, y)| y * ext.signum())
                .fold(f64::NEG_INFINITY, f64::max);
            (sph * ext.signum(), ext)
        })
        .collect()
}

/// The horizontal force of the liquid on the tank from the liquid's own momentum balance in
/// the tank's frame, F = M f − dP/dt (N/m), with P the liquid's horizontal momentum sampled
/// at `ts` (s), M its mass (kg/m) and f(t) the body force (m/s²): the force every wall
/// exerts on the liquid, whatever the wall pressures read. Centred differences; the samples
/// (interior ones) and their times.
fn momentum_shear(
    ts: &[f64],
    momentum: &[f64],
    liquid_mass: f64,
    body_force: impl Fn(f64) -> f64,
) -> (Vec<f64>, Vec<f64>) {
    (1..ts.len().saturating_sub(1))
        .filter(|&k| ts[k + 1] > ts[k - 1])
        .map(|k| {
            let rate = (momentum[k + 1] - momentum[k - 1]) / (ts[k + 1] - ts[k - 1]);
            (ts[k], liquid_mass * body_force(ts[k]) - rate)
        })
        .unzip()
}

/// Ratios SPH / theory of the extremes themselves (the first [`CRESTS`]).
fn extreme_ratios_of(pairs: &[(f64, f64)]) -> Vec<f64> {
    pairs.iter().take(CRESTS).map(|(s, t)| s / t).collect()
}

/// Ratios SPH / theory of the heights between successive extremes (crest to trough), the
/// first [`CRESTS`]: the first-order part of the response, free of the second-order
/// crest–trough asymmetry of a standing wave.
fn height_ratios_of(pairs: &[(f64, f64)]) -> Vec<f64> {
    pairs
        .windows(2)
        .take(CRESTS)
        .map(|w| (w[0].0 - w[1].0).abs() / (w[0].1 - w[1].1).abs())
        .collect()
}

/// One forced run: the ratios SPH / linear theory of the first half-cycle extremes of the
/// wall elevation (gauge one spacing inside the left wall), of a second gauge three spacings
/// inside it, and of the base shear; the particle-steps; the curves for the plot.
struct ForcedResult {
    eta: Vec<(f64, f64)>,
    eta_inner: Vec<(f64, f64)>,
    shear: Vec<(f64, f64)>,
    /// The base shear from the liquid's momentum balance (see [`momentum_shear`]).
    shear_momentum: Vec<(f64, f64)>,
    particle_steps: f64,
    curve: (Vec<f64>, Vec<f64>),
}

fn forced_run(
    ctx: &Context,
    case: &Case,
    label: &str,
    params: SphParams,
    settle: f64,
    amplitude_scale: f64,
) -> anyhow::Result<ForcedResult> {
    let scaled = Case {
        amplitude: amplitude_scale * case.amplitude,
        ..*case
    };
    let case = &scaled;
    let setup = RectTank2::new(WIDTH, HEIGHT, DEPTH)
        .with_roof(false)
        .with_layers(params.wall_layers())
        .build(DX)?;
    let sim = Simulation::new(setup, params)?;
    let excitation = SineExcitation {
        settle,
        ..case.excitation()
    };
    let mut runner = Runner::new(sim, excitation, 2e-3);
    let inner_x = runner.gauge_x.0 + 2.0 * DX;
    let still = runner.still_level;
    ctx.say(&format!(
        "forced from rest, {label}: Ω = {:.3} rad/s = {FREQUENCY_RATIO} ω₁, A = {:.4} m, settle {settle} s",
        case.omega, case.amplitude
    ));
    let (mut ts_inner, mut inner, mut momentum) = (Vec::new(), Vec::new(), Vec::new());
    let particle_mass = runner.sim.particle_mass();
    let mut next = 0.0;
    runner.run_until(settle + case.duration, |sim| {
        if sim.time() >= next {
            next += 2e-3;
            ts_inner.push(sim.time() - settle);
            inner.push(
                sim.surface_level_at(&[inner_x])
                    .map(|z| z - still)
                    .unwrap_or(f64::NAN),
            );
            let velocity = &sim.fluid().velocity;
            momentum.push(particle_mass * velocity.iter().map(|v| v.x).sum::<f64>());
        }
    })?;
    let h = &runner.history;
    let (lo, _) = runner.sim.interior_bounds();
    let gauge = runner.gauge_x.0 - lo.x;
    let t: Vec<f64> = h.t.iter().map(|t| t - settle).collect();
    let (tt, eta_theory) = case.theory(case.duration, gauge, |s, x| case.tank.elevation(s, x));
    let windows = half_cycle_windows(&tt, &eta_theory);
    let eta = extreme_ratios(&windows, &t, &h.eta_left);
    let (_, inner_theory) = case.theory(case.duration, inner_x - lo.x, |s, x| {
        case.tank.elevation(s, x)
    });
    let eta_inner = extreme_ratios(&half_cycle_windows(&tt, &inner_theory), &ts_inner, &inner);
    let (_, shear_theory) = case.theory(case.duration, 0.0, |s, _| case.tank.base_shear(s));
    let shear_theory = running_mean(&tt, &shear_theory, SHEAR_MEAN_HALF);
    let load_t: Vec<f64> = h.load_t.iter().map(|t| t - settle).collect();
    let shear_sph = running_mean(&load_t, &h.base_shear, SHEAR_MEAN_HALF);
    let shear_windows = half_cycle_windows(&tt, &shear_theory);
    let shear = extreme_ratios(&shear_windows, &load_t, &shear_sph);
    let liquid_mass = particle_mass * runner.sim.fluid().velocity.len() as f64;
    // The liquid feels −a_g; the momentum samples' times are since the excitation start.
    let body_force = |t: f64| -excitation.ground_accel(t + settle);
    let (ts_momentum, by_momentum) = momentum_shear(&ts_inner, &momentum, liquid_mass, body_force);
    let by_momentum = running_mean(&ts_momentum, &by_momentum, SHEAR_MEAN_HALF);
    let shear_momentum = extreme_ratios(&shear_windows, &ts_momentum, &by_momentum);
    let curve_t: Vec<f64> = t.iter().copied().filter(|t| *t >= 0.0).collect();
    let curve_eta: Vec<f64> = curve_t
        .iter()
        .map(|&s| interpolate(&t, &h.eta_left, s))
        .collect();
    Ok(ForcedResult {
        eta,
        eta_inner,
        shear,
        shear_momentum,
        particle_steps: h.particle_steps,
        curve: (curve_t, curve_eta),
    })
}

/// A row judging the worst of the ratios against 1 ± [`CREST_TOL`].
fn ratios_check(name: &str, ratios: &[f64], reason: &str) -> Check {
    let worst = ratios.iter().copied().fold(1.0f64, |m, r| {
        if (r - 1.0).abs() > (m - 1.0).abs() {
            r
        } else {
            m
        }
    });
    let pass = ratios.len() == CRESTS && ratios.iter().all(|r| (r - 1.0).abs() <= CREST_TOL);
    Check {
        group: GROUP.into(),
        name: name.into(),
        measured: ratios
            .iter()
            .map(|r| format!("{r:.3}"))
            .collect::<Vec<_>>()
            .join(", "),
        reference: "1 (undamped linear theory from rest)".into(),
        error: format!("worst {:+.1} %", 100.0 * (worst - 1.0)),
        tolerance: format!("each within ± {:.0} %", 100.0 * CREST_TOL),
        reason: reason.into(),
        verdict: if pass { Verdict::Pass } else { Verdict::Fail },
    }
}

/// What is known of the forced overshoot, shown where a preset misses the target.
const FORCED_GAP: &str = "see the modern preset's variants below and docs/validation.md";

/// A variant of a preset: its name and the change it makes to the parameters.
type Variant = (&'static str, fn(&mut SphParams));

/// What a run of the stage is judged on.
#[derive(Clone, Copy, PartialEq)]
enum Judged {
    /// Crest-to-trough heights at the left wall (the preset at the full amplitude).
    Heights,
    /// Base-shear extremes (the preset at [`SHEAR_JUDGED_SCALE`] of the amplitude).
    BaseShear,
    /// Nothing: a diagnostic variant, reported.
    Reported,
}

/// One run of the stage: its label, parameters, settling time (s), amplitude scale and what
/// it is judged on.
struct StageRun {
    label: String,
    params: SphParams,
    settle: f64,
    scale: f64,
    judged: Judged,
}

impl StageRun {
    fn new(label: &str, params: SphParams, settle: f64, scale: f64, judged: Judged) -> Self {
        StageRun {
            label: label.into(),
            params,
            settle,
            scale,
            judged,
        }
    }
}

/// The third-order departure of the base shear from linear theory, (k a)², for the crest
/// a = `scale` × 0.12 H of the first mode k = π/L: its relative size.
fn third_order_size(scale: f64) -> f64 {
    let k = std::f64::consts::PI / WIDTH;
    let a = scale * CREST_OVER_DEPTH * DEPTH;
    (k * a).powi(2)
}

/// The stage: both presets judged, the modern preset's variants reported.
pub fn forced_from_rest(ctx: &Context) -> GroupResult {
    let mut g = GroupResult::default();
    let case = Case::new();
    let modern = Scheme::modern().params;
    let variant = |f: fn(&mut SphParams)| {
        let mut p = modern.clone();
        f(&mut p);
        p
    };
    let mut runs = vec![
        StageRun::new(
            "modern scheme",
            modern.clone(),
            SETTLE,
            1.0,
            Judged::Heights,
        ),
        StageRun::new(
            "paper scheme",
            Scheme::paper().params,
            SETTLE,
            1.0,
            Judged::Heights,
        ),
        StageRun::new(
            "modern scheme, half the amplitude (crest 0.06 H)",
            modern.clone(),
            SETTLE,
            SHEAR_JUDGED_SCALE,
            Judged::BaseShear,
        ),
        StageRun::new(
            "paper scheme, half the amplitude (crest 0.06 H)",
            Scheme::paper().params,
            SETTLE,
            SHEAR_JUDGED_SCALE,
            Judged::BaseShear,
        ),
    ];
    if !ctx.quick {
        let variants: [Variant; 9] = [
            ("modern, no wall-pressure floor", |p| {
                p.wall_separation = false
            }),
            ("modern, cubic spline h = 1.3 dx", |p| {
                p.kernel = KernelKind::CubicSpline;
                p.smoothing_ratio = 1.3;
            }),
            ("modern, summation density", |p| {
                p.density = DensityMethod::Summation;
                p.density_diffusion = DensityDiffusion::None;
            }),
            // The single-sum viscous operator is a term of the Adami-wall pair only, so the
            // dynamic walls take the paper's strain-rate operator with them.
            (
                "modern, dynamic walls (strain-rate viscous operator)",
                |p| {
                    p.boundary = BoundaryMethod::Dynamic;
                    p.viscous_operator = ViscousOperator::StrainRate;
                },
            ),
            ("modern, leap-frog", |p| p.integrator = Integrator::LeapFrog),
            ("modern, no artificial viscosity", |p| p.av_alpha = 0.0),
            ("modern, α = 0.01 with the paper's c (Eq. 17)", |p| {
                p.av_alpha = 0.01;
                p.av_sound_speed = slosh_core::ArtificialSoundSpeed::Eq17;
            }),
            (
                "modern, Riemann pair with δ-SPH (Zhang, Hu & Adams 2017)",
                |p| {
                    *p = p.clone().with_riemann_pair();
                },
            ),
            ("modern, Riemann pair without δ-SPH", |p| {
                *p = p.clone().with_riemann_pair();
                p.density_diffusion = DensityDiffusion::None;
            }),
        ];
        for (label, f) in variants {
            runs.push(StageRun::new(
                label,
                variant(f),
                SETTLE,
                1.0,
                Judged::Reported,
            ));
        }
        runs.push(StageRun::new(
            "modern, settled 2 s",
            modern.clone(),
            2.0,
            1.0,
            Judged::Reported,
        ));
    }
    let mut curves = Vec::new();
    let fmt = |r: &[f64]| {
        r.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for StageRun {
        label,
        params,
        settle,
        scale,
        judged,
    } in runs
    {
        let r = match forced_run(ctx, &case, &label, params, settle, scale) {
            Ok(r) => r,
            Err(e) => {
                g.checks.push(failed_run(GROUP, &label, &format!("{e:#}")));
                continue;
            }
        };
        g.particle_steps += r.particle_steps;
        let crest = scale * CREST_OVER_DEPTH;
        let heights = height_ratios_of(&r.eta);
        let shear = extreme_ratios_of(&r.shear);
        if judged == Judged::Heights {
            g.checks.push(open_if_failed(
                ratios_check(
                    &format!(
                        "{label}: first {CRESTS} crest-to-trough heights at the left wall, \
                         SPH / linear"
                    ),
                    &heights,
                    &format!(
                        "linear potential theory from rest gives the first-order wave at crests \
                         of {crest:.2} H; the height between successive extremes is free of the \
                         second-order crest–trough asymmetry (crests up, troughs up alike)"
                    ),
                ),
                FORCED_GAP,
            ));
        } else {
            g.checks.push(info_row(
                GROUP,
                &format!("{label}: crest-to-trough heights at the left wall, SPH / linear"),
                fmt(&heights),
                "1".into(),
                format!("crests of {crest:.2} H"),
                if judged == Judged::BaseShear {
                    "reported: the heights are judged at twice this amplitude, where the \
                     first extreme is not within a spacing of the still level"
                } else {
                    "diagnostic: one part of the modern preset changed"
                },
            ));
        }
        if judged == Judged::BaseShear {
            g.checks.push(open_if_failed(
                ratios_check(
                    &format!(
                        "{label}: first {CRESTS} base-shear extremes (±{SHEAR_MEAN_HALF} s \
                         mean), SPH / linear"
                    ),
                    &shear,
                    &format!(
                        "the base shear integrates the wall pressures: the same linear theory, \
                         which the force leaves at third order in the wave height, here by \
                         (k a)² = {:.1} %",
                        100.0 * third_order_size(scale)
                    ),
                ),
                FORCED_GAP,
            ));
        } else {
            g.checks.push(info_row(
                GROUP,
                &format!(
                    "{label}: first {CRESTS} base-shear extremes (±{SHEAR_MEAN_HALF} s mean), \
                     SPH / linear"
                ),
                fmt(&shear),
                "1".into(),
                format!(
                    "third-order departure of the force from linear theory (k a)² = {:.1} %",
                    100.0 * third_order_size(scale)
                ),
                if judged == Judged::Heights {
                    "reported: judged at half the amplitude, where linear theory holds the \
                     force to about 1 %"
                } else {
                    "diagnostic: one part of the modern preset changed"
                },
            ));
        }
        g.checks.push(info_row(
            GROUP,
            &format!(
                "{label}: base-shear extremes from the liquid's momentum balance, SPH / linear"
            ),
            fmt(&extreme_ratios_of(&r.shear_momentum)),
            "1".into(),
            format!(
                "from the wall pressures: {}",
                fmt(&extreme_ratios_of(&r.shear))
            ),
            "diagnostic: M f − dP/dt is the force all walls exert on the liquid, so it \
             separates the flow's own response from how the wall pressures are read",
        ));
        g.checks.push(info_row(
            GROUP,
            &format!("{label}: wall-elevation extremes (crest, trough, crest), SPH / linear"),
            fmt(&extreme_ratios_of(&r.eta)),
            "1".into(),
            format!(
                "gauge 3 spacings inside the wall: {}",
                fmt(&extreme_ratios_of(&r.eta_inner))
            ),
            "diagnostic: single extremes carry the second-order asymmetry of a standing \
             wave (crests above, troughs short of linear theory by about the same amount); \
             the second gauge tells whether the wall gauge itself reads high",
        ));
        curves.push((label, r.curve));
    }
    let (lo_t, theory) = {
        let (t, e) = case.theory(case.duration, DX, |s, x| case.tank.elevation(s, x));
        (t, e)
    };
    let mut series: Vec<Series> = curves
        .iter()
        .take(2)
        .map(|(l, (t, e))| Series::line(l, t, e))
        .collect();
    series.push(Series::dashed("linear theory from rest", &lo_t, &theory));
    g.add_line_plot(
        &ctx.out,
        "forced_from_rest_eta_left",
        &PlotSpec::new(
            "Forced from rest above resonance: elevation at the left wall",
            "time since excitation start (s)",
            "η at the left wall (m)",
        ),
        &series,
        "forced response from rest against undamped linear theory",
    );
    g.notes.push(format!(
        "Open tank {WIDTH} × {DEPTH} m, dx = {DX} m, Ω = {FREQUENCY_RATIO} ω₁ = {:.3} rad/s, \
         ground amplitude A = {:.4} m (linear theory's largest of the first {CRESTS} wall \
         extremes = {CREST_OVER_DEPTH} H; the heights are judged there, the base shear at half \
         that amplitude), {SETTLE} s at rest first; {MODES} modes in the \
         theory, which is evaluated at the gauge's own distance from the wall. Ratios are the \
         SPH extreme of the same sign in each half cycle of theory (±¼ half cycle) over \
         theory's.",
        case.omega, case.amplitude
    ));
    g
}
