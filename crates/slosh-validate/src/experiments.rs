//! Nonlinear sloshing against laboratory experiments: the wave elevation near a wall of a
//! rectangular tank under a horizontal harmonic sway, run as the experiment was and compared
//! with its digitised record (`data/README.md`) without any fitted time shift or scaling.
//!
//! Three records: Faltinsen, Rognebakke, Lukovsky & Timokha (2000, *J. Fluid Mech.* 407,
//! 201–234, Fig. 7), a 0.6 m deep tank swayed above its first mode (ω/ω₁ = 1.28) from rest,
//! whose response beats with crests of 0.24 H; Bouscasse, Antuono, Colagrossi & Lugni
//! (2013, *Int. J. Nonlinear Sci. Numer. Simul.* 14, 123–138, Fig. 19, series 5), a 3 cm deep
//! layer swayed by 2.3 H (ω/ω₁ = 1.23) in which a bore runs to and fro, with crests of 2 H;
//! and Okamoto & Kawahara (1992, *Proc. JSCE* 441/I-18, 39–49), the experiment the paper
//! compares its §3.1 case with (its Fig. 3 and ref. 17): the paper's 1 m tank with 0.5 m of
//! water driven at its first mode (ω/ω₁ = 0.999), the wave at the left wall growing to steep
//! crests of 0.5 H with troughs of 0.28 H. The set-up of the first two (tank, depth,
//! excitation, gauge, start) is the one the PySPH examples use to simulate the same
//! experiment, the source of the digitised records; the third is the paper's §3.1 case.
//!
//! Judged on the crests and the phase. Crests: every positive half cycle of the record (from
//! an upward to a downward crossing of the still level) gives a crest; the simulation's crest
//! is its largest elevation in the same time window widened by a tenth of the forcing period
//! on each side; the RMS of the relative crest differences must stay within 10 %. Phase: the
//! correlation coefficient of the simulated elevation, interpolated at the record's times,
//! with the record over its whole span must be at least 0.97. Reported beside them: the mean
//! ratio of the crest-to-trough heights of successive half cycles (the first-order wave,
//! which the crest–trough asymmetry of steep waves leaves alone).
//!
//! Faltinsen et al.'s record is reported, not judged: its start is not the stated one (the
//! paper's abstract: an initial variation of the excitation periods matters more there than
//! the initial conditions), and undamped linear theory of the stated sway, computed here
//! beside it, gives heights 1.27 × the record's at the record's phase.

use super::damping::at_most_check;
use super::run::{interpolate, step_until_around, zero_crossings, Context, GRAVITY};
use super::Verdict;
use super::{failed_run, fmt_num, info_row, open_if_failed, stayed_inside, Check, GroupResult};
use crate::run::paper_params;
use anyhow::Result;
use slosh_core::{Simulation, SphParams, Vector};
use slosh_geometry::RectTank2;
use slosh_io::{PlotSpec, Series};
use slosh_run::{HookError, StepPhase};
use slosh_theory::linear::RectangularTank;
use slosh_theory::modal::time_history_response;

/// The group of the report.
const GROUP: &str = "Nonlinear sloshing against experiments";
/// Tolerance of the RMS relative crest difference: 10 %. The digitised crests carry a few
/// millimetres of reading error (≈ 2–5 % of a crest), and the experiments' own repeatability
/// is of the same order; 10 % is what an engineer can use for freeboard.
const CREST_TOL: f64 = 0.10;
/// Least correlation of the simulated elevation with the record over its span: 0.97, a phase
/// drift of a few per cent of a period at the end of the record.
const CORRELATION_MIN: f64 = 0.97;
/// Settling time of the paper scheme before the experiment starts (s): its liquid starts at
/// uniform density and needs the paper's 2 s to come to rest; the modern scheme starts at
/// rest in its own compression and needs none.
const PAPER_SETTLE: f64 = 2.0;

const FALTINSEN: &str =
    include_str!("../../../data/sloshing_Faltinsen2000_h0p6_T1p3_elevation.csv");
const BOUSCASSE: &str = include_str!("../../../data/sloshing_Bouscasse2013_series5_elevation.csv");
const OKAMOTO: &str = include_str!("../../../data/sloshing_Okamoto1992_resonance_wall_level.csv");

/// How the tank starts moving at the start of the experiment (time 0 of its record).
#[derive(Clone, Copy, Debug)]
enum Start {
    /// Tank displacement x(t) = A cos ωt from rest (tank acceleration −A ω² cos ωt): the tank
    /// is at rest at its extreme position at t = 0 (Faltinsen et al. 2000 as PySPH runs it).
    CosineFromRest,
    /// x(t) = A sin ωt: the tank is set moving at A ω at t = 0, the liquid left at −A ω
    /// relative to it (Bouscasse et al. 2013 as PySPH runs it).
    SineImpulsive,
    /// Tank acceleration A ω² sin ωt from rest: the liquid, at rest in the tank at t = 0,
    /// feels the inertial force −A ω² sin ωt (the paper's §3.1, Okamoto & Kawahara 1992).
    SineAccelerationFromRest,
}

impl Start {
    /// The tank's acceleration (m/s²) at time `t` (s) after the start, for a sway of
    /// amplitude `amplitude` (m) at `omega` (rad/s); the liquid feels its negative.
    fn tank_acceleration(self, amplitude: f64, omega: f64, t: f64) -> f64 {
        let peak = amplitude * omega * omega;
        match self {
            Start::CosineFromRest => -peak * (omega * t).cos(),
            Start::SineImpulsive => -peak * (omega * t).sin(),
            Start::SineAccelerationFromRest => peak * (omega * t).sin(),
        }
    }
}

/// One experiment.
struct Experiment {
    /// Short label.
    label: &'static str,
    /// File stem of its plot.
    stem: &'static str,
    /// The digitised record (`data/`).
    data: &'static str,
    /// Whether the record's time column is t/T (else seconds).
    time_in_periods: bool,
    /// The record's still level (m), subtracted from its second column: 0 where that column
    /// is the elevation above the still level already, the depth where it is the level
    /// above the floor.
    datum: f64,
    /// Tank length L, height and still depth H (m).
    tank: (f64, f64, f64),
    /// Whether the tank has a roof at its height.
    roof: bool,
    /// Sway amplitude A (m) and circular frequency ω (rad/s).
    amplitude: f64,
    omega: f64,
    /// How the sway starts.
    start: Start,
    /// Gauge distance from the left wall (m).
    gauge_x: f64,
    /// Resolutions, particles per still depth: (quick suite, full suite); `None` in the quick
    /// suite skips the experiment there.
    per_depth: (Option<usize>, usize),
    /// Why the record cannot judge a simulation of the stated set-up, if it cannot: its
    /// rows are then reported, not judged.
    not_judged: Option<&'static str>,
}

/// Why Faltinsen et al.'s Fig. 7 is reported and not judged: the record's start is not the
/// stated one.
const FALTINSEN_START: &str = "the record is not the response to the stated excitation from \
    t = 0: the paper's abstract says that for these transient records an initial variation of \
    the excitation periods matters more than the initial conditions, and neither that \
    variation nor the experiment's start is documented with the record; undamped linear \
    theory of the stated constant-period sway from rest follows the record's phase \
    (correlation row below) but its crest-to-trough heights come out ≈ 1.27 × the record's, \
    and the modern preset's heights are linear theory's (rows below), not the record's";

fn experiments() -> [Experiment; 3] {
    let bouscasse_omega = {
        // ω = 1.231 ω₁ of the 1 m tank with H = 0.03 m (the series' definition).
        let k = std::f64::consts::PI / 1.0;
        1.231 * (GRAVITY * k * (k * 0.03f64).tanh()).sqrt()
    };
    [
        Experiment {
            label: "Faltinsen et al. 2000, L = 1.73 m, H = 0.6 m, A = 0.032 m, T = 1.3 s",
            stem: "faltinsen2000",
            data: FALTINSEN,
            time_in_periods: false,
            datum: 0.0,
            tank: (1.73, 1.15, 0.6),
            roof: true,
            amplitude: 0.032,
            omega: 2.0 * std::f64::consts::PI / 1.3,
            start: Start::CosineFromRest,
            gauge_x: 0.05,
            per_depth: (Some(20), 40),
            not_judged: Some(FALTINSEN_START),
        },
        Experiment {
            label: "Bouscasse et al. 2013 series 5, L = 1 m, H = 0.03 m, A = 0.07 m",
            stem: "bouscasse2013",
            data: BOUSCASSE,
            time_in_periods: true,
            datum: 0.0,
            tank: (1.0, 0.2, 0.03),
            roof: false,
            amplitude: 2.333 * 0.03,
            omega: bouscasse_omega,
            start: Start::SineImpulsive,
            gauge_x: 0.05,
            per_depth: (None, 10),
            not_judged: None,
        },
        Experiment {
            label: "Okamoto & Kawahara 1992, L = 1 m, H = 0.5 m, A = 0.0093 m, ω = 5.311 rad/s",
            stem: "okamoto1992",
            data: OKAMOTO,
            time_in_periods: false,
            datum: 0.5,
            tank: (1.0, 1.0, 0.5),
            roof: false,
            amplitude: 0.0093,
            omega: 5.311,
            start: Start::SineAccelerationFromRest,
            gauge_x: 0.02,
            per_depth: (Some(25), 50),
            not_judged: None,
        },
    ]
}

/// Reads a record: `#` comment lines, one header line, then "t,η" rows.
fn read_record(text: &str) -> Vec<(f64, f64)> {
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .skip(1)
        .filter_map(|l| {
            let mut it = l.split(',');
            let t = it.next()?.trim().parse().ok()?;
            let e = it.next()?.trim().parse().ok()?;
            Some((t, e))
        })
        .collect()
}

/// The simulated elevation at the gauge: times since the experiment started (s) and η (m).
struct Simulated {
    t: Vec<f64>,
    eta: Vec<f64>,
    depth: f64,
    dx: f64,
    particles: usize,
    particle_steps: f64,
    wall_s: f64,
    inside: Check,
}

/// Runs one experiment with `params` at `per_depth` particles per depth until `t_end` s of
/// experiment time, sampling the gauge every `sample` s.
fn simulate(
    ctx: &Context,
    e: &Experiment,
    params: &SphParams,
    settle: f64,
    per_depth: usize,
    t_end: f64,
) -> Result<Simulated> {
    let (length, height, depth) = e.tank;
    let dx = length / (length / (depth / per_depth as f64)).round();
    let height = (height / dx).round() * dx;
    let setup = RectTank2::new(length, height, depth)
        .with_roof(e.roof)
        .with_layers(params.wall_layers())
        .build(dx)?;
    let mut sim = Simulation::new(setup, params.clone())?;
    let (lo, _) = sim.interior_bounds();
    let held = sim.fill_level() - lo.y;
    let still = sim.still_level();
    let particles = sim.fluid().position.len() + sim.walls().position.len();
    ctx.say(&format!(
        "{}: {per_depth} per depth (dx = {dx:.5} m, depth held {held:.4} m), {} fluid \
         particles, c0 = {:.1} m/s, {t_end:.1} s",
        e.label,
        sim.fluid().position.len(),
        sim.sound_speed()
    ));
    let (a, w) = (e.amplitude, e.omega);
    // Tank acceleration (m/s²) at experiment time te ≥ 0; the liquid feels its negative.
    let tank_accel = move |te: f64| e.start.tank_acceleration(a, w, te);
    let start = std::time::Instant::now();
    let gauge = lo.x + e.gauge_x;
    let sample = (2.0 * std::f64::consts::PI / w) / 200.0;
    let (mut t, mut eta) = (Vec::new(), Vec::new());
    let mut next = 0.0;
    let mut particle_steps = 0.0;
    if settle > 0.0 {
        step_until_around(
            &mut sim,
            |_| [0.0; 3],
            settle,
            "the settling run stopped",
            |_, _| Ok(()),
        )?;
    }
    if let Start::SineImpulsive = e.start {
        let mut v = Vector::<2>::zeros();
        v[0] = -a * w;
        sim.jump_velocity(v)?;
    }
    let t0 = sim.time();
    step_until_around(
        &mut sim,
        |ts| [tank_accel(ts - t0), 0.0, 0.0],
        t0 + t_end,
        "the experiment's run stopped",
        |phase, sim| -> Result<(), HookError> {
            match phase {
                StepPhase::Before(_) => {
                    let te = sim.time() - t0;
                    if te >= next - 1e-12 {
                        t.push(te);
                        eta.push(
                            sim.surface_level_at(&[gauge])
                                .map_or(f64::NAN, |z| z - still),
                        );
                        next += sample;
                    }
                }
                StepPhase::After => particle_steps += particles as f64,
            }
            Ok(())
        },
    )?;
    Ok(Simulated {
        t,
        eta,
        depth: held,
        dx,
        particles,
        particle_steps,
        wall_s: start.elapsed().as_secs_f64(),
        inside: stayed_inside(GROUP, &sim),
    })
}

/// The extremes of the record, one per half cycle between crossings of the still level
/// (time window centre, record extreme, signed), and the simulation's extreme of the same
/// sign in each window widened by `slack` s on both sides.
fn extreme_pairs(
    record: &[(f64, f64)],
    sim_t: &[f64],
    sim_eta: &[f64],
    slack: f64,
) -> Vec<(f64, f64, f64)> {
    let ts: Vec<f64> = record.iter().map(|p| p.0).collect();
    let es: Vec<f64> = record.iter().map(|p| p.1).collect();
    // Crossings of the still level with a hysteresis of 2 % of the record's largest |η|
    // (above the digitisation's scatter about zero).
    let band = 0.02 * es.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    let crossings = zero_crossings(&ts, &es, band);
    let mut out = Vec::new();
    for w in crossings.windows(2) {
        let ((t0, side), (t1, _)) = (w[0], w[1]);
        let sign = f64::from(side);
        let pick = |t: &[f64], e: &[f64], lo: f64, hi: f64| {
            t.iter()
                .zip(e)
                .filter(|(t, e)| **t >= lo && **t <= hi && e.is_finite())
                .map(|(_, e)| sign * *e)
                .fold(f64::NAN, f64::max)
                * sign
        };
        let recorded = pick(&ts, &es, t0, t1);
        let simulated = pick(sim_t, sim_eta, t0 - slack, t1 + slack);
        if recorded.is_finite() && simulated.is_finite() {
            out.push((0.5 * (t0 + t1), recorded, simulated));
        }
    }
    out
}

/// Mean ratio of the simulated to the recorded crest-to-trough heights over successive
/// extremes of [`extreme_pairs`]: the first-order wave, free of the second-order crest–trough
/// asymmetry that single crests carry.
fn height_ratio(pairs: &[(f64, f64, f64)]) -> f64 {
    let ratios: Vec<f64> = pairs
        .windows(2)
        .filter(|w| w[0].1.signum() != w[1].1.signum())
        .map(|w| (w[0].2 - w[1].2).abs() / (w[0].1 - w[1].1).abs())
        .collect();
    ratios.iter().sum::<f64>() / ratios.len().max(1) as f64
}

/// Pearson correlation of x and y (NaN pairs skipped).
fn correlation(x: &[f64], y: &[f64]) -> f64 {
    let pairs: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .collect();
    let n = pairs.len() as f64;
    let (mx, my) = (
        pairs.iter().map(|p| p.0).sum::<f64>() / n,
        pairs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in &pairs {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    sxy / (sxx * syy).sqrt()
}

/// Undamped linear modal theory of an experiment whose liquid starts from rest in the tank
/// ([`Start::CosineFromRest`], [`Start::SineAccelerationFromRest`]): the elevation at the
/// gauge (m) at times `t` (s), 20 excited modes, the load sampled every 1 ms.
fn linear_reference(e: &Experiment, t: &[f64]) -> Vec<f64> {
    let (length, _, depth) = e.tank;
    let tank = RectangularTank::water(length, depth);
    let dt = 1e-3;
    let t_end = t.last().copied().unwrap_or(0.0);
    let (a, w) = (e.amplitude, e.omega);
    // The liquid feels f = −a_tank.
    let force: Vec<f64> = (0..=(t_end / dt).ceil() as usize + 1)
        .map(|k| -e.start.tank_acceleration(a, w, k as f64 * dt))
        .collect();
    let states = time_history_response(&tank, dt, &force, 20, 0.0);
    let eta: Vec<f64> = states
        .iter()
        .map(|s| tank.elevation(s, e.gauge_x))
        .collect();
    let times: Vec<f64> = states.iter().map(|s| s.time).collect();
    t.iter().map(|&ti| interpolate(&times, &eta, ti)).collect()
}

/// How a simulated (or computed) elevation compares with a record.
struct Agreement {
    /// RMS of the relative crest differences, the largest one (signed), and the crests
    /// (time, record, simulation).
    crest_rms: f64,
    worst: f64,
    crests: Vec<(f64, f64, f64)>,
    /// Mean ratio of the crest-to-trough heights.
    heights: f64,
    /// Correlation over the record's span.
    correlation: f64,
}

impl Agreement {
    fn of(record: &[(f64, f64)], t: &[f64], eta: &[f64], slack: f64) -> Self {
        let pairs = extreme_pairs(record, t, eta, slack);
        let crests: Vec<(f64, f64, f64)> = pairs.iter().copied().filter(|p| p.1 > 0.0).collect();
        let rel: Vec<f64> = crests.iter().map(|(_, c, m)| m / c - 1.0).collect();
        let crest_rms = (rel.iter().map(|r| r * r).sum::<f64>() / rel.len().max(1) as f64).sqrt();
        let worst = rel
            .iter()
            .fold(0.0f64, |m, r| if r.abs() > m.abs() { *r } else { m });
        let at_record: Vec<f64> = record.iter().map(|p| interpolate(t, eta, p.0)).collect();
        let recorded: Vec<f64> = record.iter().map(|p| p.1).collect();
        Agreement {
            crest_rms,
            worst,
            heights: height_ratio(&pairs),
            correlation: correlation(&at_record, &recorded),
            crests,
        }
    }
}

/// The stage: each experiment with the paper scheme and the modern preset. The modern preset
/// is judged (a miss is OPEN while the fidelity work is open), the paper scheme reported; a
/// record that cannot judge the stated set-up (`Experiment::not_judged`) is reported for
/// both, beside linear theory of the same set-up where that applies.
pub fn against_experiments(ctx: &Context) -> GroupResult {
    let mut g = GroupResult::default();
    for e in experiments().iter() {
        let Some(per_depth) = (if ctx.quick {
            e.per_depth.0
        } else {
            Some(e.per_depth.1)
        }) else {
            continue;
        };
        let period = 2.0 * std::f64::consts::PI / e.omega;
        let slack = 0.1 * period;
        let record: Vec<(f64, f64)> = read_record(e.data)
            .into_iter()
            .map(|(t, eta)| {
                (
                    if e.time_in_periods { t * period } else { t },
                    eta - e.datum,
                )
            })
            .collect();
        let t_end = record.last().map_or(0.0, |p| p.0) + 0.05 * period;
        let mut curves: Vec<(String, Vec<f64>, Vec<f64>)> = vec![(
            "experiment".into(),
            record.iter().map(|p| p.0).collect(),
            record.iter().map(|p| p.1).collect(),
        )];
        if !matches!(e.start, Start::SineImpulsive) {
            let t: Vec<f64> = (0..=(t_end / 0.005) as usize)
                .map(|i| i as f64 * 0.005)
                .collect();
            let eta = linear_reference(e, &t);
            let a = Agreement::of(&record, &t, &eta, slack);
            g.checks.push(info_row(
                GROUP,
                &format!("undamped linear theory of the stated set-up: crest-to-trough heights over the record's, {}", e.label),
                format!("{:.3}", a.heights),
                "1".into(),
                format!("crests {:.1} % RMS, correlation {:.4}", 100.0 * a.crest_rms, a.correlation),
                "reported: 20 modes, the sway from rest as stated (slosh_theory::modal); tells \
                 what the stated excitation gives to first order",
            ));
            curves.push(("linear theory".into(), t, eta));
        }
        let schemes = [
            ("modern scheme", SphParams::modern(), 0.0, true),
            ("paper scheme", paper_params(), PAPER_SETTLE, false),
        ];
        for (scheme, params, settle, judged) in schemes {
            let name =
                |what: &str| format!("{scheme}: {what}, {} ({per_depth} per depth)", e.label);
            let s = match simulate(ctx, e, &params, settle, per_depth, t_end) {
                Ok(s) => s,
                Err(err) => {
                    g.checks
                        .push(failed_run(GROUP, &name("run"), &format!("{err:#}")));
                    continue;
                }
            };
            g.particle_steps += s.particle_steps;
            g.checks.push(s.inside.clone());
            let a = Agreement::of(&record, &s.t, &s.eta, slack);
            let crest_text = a
                .crests
                .iter()
                .map(|(t, c, m)| format!("t = {t:.2} s: {c:.4} / {m:.4} m"))
                .collect::<Vec<_>>()
                .join("; ");
            g.notes.push(format!(
                "{scheme}, {}: {per_depth} per depth (dx = {:.5} m, depth held {:.4} m, {} \
                 particles), {:.2e} particle-steps in {:.0} s. Crests experiment / SPH: {crest_text}. \
                 Correlation over the record {:.4}; crest-to-trough heights SPH / experiment {:.3}.",
                e.label, s.dx, s.depth, s.particles, s.particle_steps, s.wall_s, a.correlation, a.heights
            ));
            ctx.say(&format!(
                "  → {scheme}: crest RMS difference {:.1} % (worst {:+.1} %, {} crests), \
                 correlation {:.4}, heights {:.3} × the record's",
                100.0 * a.crest_rms,
                100.0 * a.worst,
                a.crests.len(),
                a.correlation,
                a.heights
            ));
            let crest_check = at_most_check(
                GROUP,
                &name("RMS relative crest difference"),
                a.crest_rms,
                CREST_TOL,
                &format!(
                    "{} crests of the record against the SPH's largest elevation in the same \
                     half cycle (± T/10), worst {:+.1} %; the digitised crests carry a few mm of \
                     reading error and the experiment's repeatability is of that order",
                    a.crests.len(),
                    100.0 * a.worst
                ),
            );
            let corr_check = Check {
                group: GROUP.into(),
                name: name("correlation with the record"),
                measured: format!("{:.4}", a.correlation),
                reference: "1".into(),
                error: format!("{:.4}", 1.0 - a.correlation),
                tolerance: format!("≥ {CORRELATION_MIN}"),
                reason: "the phase: no time shift is fitted; a drift of the simulated period or \
                         a late or early start lowers it"
                    .into(),
                verdict: if a.correlation >= CORRELATION_MIN {
                    Verdict::Pass
                } else {
                    Verdict::Fail
                },
            };
            for c in [crest_check, corr_check] {
                g.checks.push(match (judged, e.not_judged) {
                    (true, None) => open_if_failed(
                        c,
                        "nonlinear crests of steep waves and bores: the scheme's damping and \
                         the surface's resolution at the gauge",
                    ),
                    (_, why) => {
                        let mut c = c;
                        c.verdict = Verdict::Info;
                        if let Some(why) = why {
                            c.reason = format!("reported, not judged: {why}");
                        }
                        c
                    }
                });
            }
            g.checks.push(info_row(
                GROUP,
                &name("crest-to-trough heights over the record's"),
                format!("{:.3}", a.heights),
                "1".into(),
                format!("{:+.1} %", 100.0 * (a.heights - 1.0)),
                "reported: the first-order wave, free of the crest–trough asymmetry of steep \
                 waves",
            ));
            curves.push((format!("{scheme}, {per_depth} per depth"), s.t, s.eta));
        }
        let stem = format!("experiment_{}", e.stem);
        g.add_line_plot(
            &ctx.out,
            &stem,
            &PlotSpec::new(
                e.label.to_string(),
                "t since the sway started (s)",
                format!("η at {} m from the left wall (m)", fmt_num(e.gauge_x)),
            ),
            &curves
                .iter()
                .enumerate()
                .map(|(i, (l, t, y))| {
                    if i == 0 {
                        Series::points(l, t, y)
                    } else {
                        Series::line(l, t, y)
                    }
                })
                .collect::<Vec<_>>(),
            format!("wave elevation against the experiment: {}", e.label),
        );
        g.checks.push(info_row(
            GROUP,
            &format!("set-up, {}", e.label),
            format!(
                "ω/ω₁ = {:.3}",
                e.omega / first_mode_omega(e.tank.0, e.tank.2)
            ),
            "—".into(),
            "—".into(),
            match e.start {
                Start::CosineFromRest => {
                    "tank x = A cos ωt from rest, as the PySPH example of the experiment"
                }
                Start::SineImpulsive => {
                    "tank x = A sin ωt, the liquid starting at −Aω relative to it, as the PySPH \
                     example of the experiment"
                }
                Start::SineAccelerationFromRest => {
                    "tank acceleration A ω² sin ωt from rest, the liquid at rest in the tank: \
                     the inertial force −A ω² sin ωt of the paper's §3.1"
                }
            },
        ));
    }
    g
}

/// ω₁ = √(g k tanh kH), k = π/L (rad/s).
fn first_mode_omega(length: f64, depth: f64) -> f64 {
    let k = std::f64::consts::PI / length;
    (GRAVITY * k * (k * depth).tanh()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The records parse in full (171, 87 and 12 rows, `data/README.md`) and the correlation is
    /// that of its definition: 1 for a signal with itself, −1 against its negative.
    #[test]
    fn records_parse_and_correlation_is_pearson() {
        assert_eq!(read_record(FALTINSEN).len(), 171);
        assert_eq!(read_record(BOUSCASSE).len(), 87);
        assert_eq!(read_record(OKAMOTO).len(), 12);
        let x: Vec<f64> = (0..50).map(|i| (0.3 * i as f64).sin()).collect();
        let neg: Vec<f64> = x.iter().map(|v| -v).collect();
        assert!((correlation(&x, &x) - 1.0).abs() < 1e-12);
        assert!((correlation(&x, &neg) + 1.0).abs() < 1e-12);
    }

    /// A record against itself has extremes equal to its own, a crest per positive half
    /// cycle, and heights in the ratio 1.
    #[test]
    fn crests_of_a_record_against_itself_are_its_own() {
        let rec: Vec<(f64, f64)> = (0..400)
            .map(|i| {
                let t = 0.01 * i as f64;
                (t, (1.0 + 0.1 * t) * (2.0 * std::f64::consts::PI * t).sin())
            })
            .collect();
        let t: Vec<f64> = rec.iter().map(|p| p.0).collect();
        let e: Vec<f64> = rec.iter().map(|p| p.1).collect();
        let pairs = extreme_pairs(&rec, &t, &e, 0.0);
        let crests: Vec<_> = pairs.iter().filter(|p| p.1 > 0.0).collect();
        assert_eq!(crests.len(), 3, "{pairs:?}");
        for (_, c, m) in &pairs {
            assert_eq!(c, m);
        }
        assert_eq!(height_ratio(&pairs), 1.0);
    }

    /// The linear reference of a cosine sway from rest is the closed form of the undamped
    /// modal equations, η̈_n + ω_n² η_n = (4 L ω_n²/(g n² π²)) ẍ_tank over odd n with the
    /// surface Σ η_n cos(k_n x) (Ibrahim 2005, §2.3): for ẍ_tank = −A ω² cos ωt from rest,
    /// η_n = −(4 L ω_n² A ω²/(g n² π²)) (cos ωt − cos ω_n t)/(ω_n² − ω²); the surface at the
    /// left wall falls first. Within 1e-4 m against a 0.16 m wave: the reference samples the
    /// load every 1 ms and adds the quasi-static tilt of the modes past the 20 summed here.
    #[test]
    fn linear_reference_is_the_closed_form_of_a_cosine_sway() {
        let e = &experiments()[0];
        let (l, _, h) = e.tank;
        let (a, w, g) = (e.amplitude, e.omega, 9.81);
        let t = [0.5, 2.57, 5.3, 9.16];
        let eta = linear_reference(e, &t);
        for (ti, got) in t.iter().zip(eta) {
            let mut want = 0.0;
            for j in 0..20 {
                let n = (2 * j + 1) as f64;
                let k = n * std::f64::consts::PI / l;
                let wn2 = g * k * (k * h).tanh();
                let gain = 4.0 * l * wn2 * a * w * w / (g * n * n * std::f64::consts::PI.powi(2));
                want -= gain * ((w * ti).cos() - (wn2.sqrt() * ti).cos()) / (wn2 - w * w)
                    * (k * e.gauge_x).cos();
            }
            assert!((got - want).abs() < 1e-4, "t = {ti}: {got} vs {want}");
        }
    }

    /// The same for the paper's §3.1 start: tank acceleration ẍ = A ω² sin ωt from rest gives
    /// η_n = G (sin ωt − (ω/ω_n) sin ω_n t)/(ω_n² − ω²), G = 4 L ω_n² A ω²/(g n² π²): at
    /// resonance the left wall rises in the first half period, as the record does.
    #[test]
    fn linear_reference_is_the_closed_form_of_a_sine_acceleration_from_rest() {
        let e = &experiments()[2];
        assert!(matches!(e.start, Start::SineAccelerationFromRest));
        let (l, _, h) = e.tank;
        let (a, w, g) = (e.amplitude, e.omega, 9.81);
        let t = [0.6, 1.21, 3.03, 6.54];
        let eta = linear_reference(e, &t);
        for (ti, got) in t.iter().zip(&eta) {
            let mut want = 0.0;
            for j in 0..20 {
                let n = (2 * j + 1) as f64;
                let k = n * std::f64::consts::PI / l;
                let wn2 = g * k * (k * h).tanh();
                let wn = wn2.sqrt();
                let gain = 4.0 * l * wn2 * a * w * w / (g * n * n * std::f64::consts::PI.powi(2));
                want += gain * ((w * ti).sin() - w / wn * (wn * ti).sin()) / (wn2 - w * w)
                    * (k * e.gauge_x).cos();
            }
            assert!((got - want).abs() < 1e-4, "t = {ti}: {got} vs {want}");
        }
        assert!(eta[0] > 0.0 && eta[1] < 0.0, "{eta:?}");
    }
}
