//! The roof load at successive resolutions: the 1.0 m roofed tank of paper Fig. 10
//! (`paper_2d_roof_sweep.rhai`, H′/H = 0.2, A = 0.0093 m at the first mode, modern preset, the
//! sound speed from the tank) cut to its first impacts (7.5 s), at dx = 0.02 and 0.01 m
//! (quick) and 0.02 to 0.0025 m (full). Per level: the impacts found, the roof impulse over two
//! fixed windows, the largest low-pass roof force, the equivalent static roof force F_eq at
//! T_r = 20 / 50 / 100 / 200 ms and the corner sensor's peak pressure. Across levels: the
//! impacts must be the same episodes on the finest two (their starts within T₁/10), and on
//! the finest three the impulses, the low-pass force and F_eq at T_r ≥ 50 ms are judged on
//! the grid convergence index (`docs/roof-loads.md`). The full suite also runs dx = 0.01 m with
//! the roof one spacing higher: the roof is felt ≈ 2 dx before the liquid reaches it, so that
//! run must give the first impact and the roof impulse of dx = 0.005 m at the nominal roof
//! (`docs/roof-loads.md`, *Why the roof load moves with resolution*).

use super::gci::{uncertainty, Behaviour};
use super::run::Context;
use super::scripts::{particle_steps, run_script_with};
use super::{condition, failed_run, info_row, GroupResult};

/// Group title.
pub const GROUP: &str = "Roof loads at successive resolutions (paper_2d_roof_sweep.rhai, 1.0 m \
                         tank, H'/H 0.2, modern preset, first impacts)";

/// The case's settings besides the lattice.
const SETS: [&str; 6] = [
    "width=1.0",
    "clearance_ratio=0.2",
    "amplitude=0.0093",
    "scheme=\"modern\"",
    "eos_b=0",
    "duration=7.5",
];
/// Lattices of the quick suite (m).
const QUICK_LEVELS: [f64; 2] = [0.02, 0.01];
/// Lattices of the full suite (m). The finest costs about 64 times the 0.01 m level (≈ 1 h
/// on 2 cores).
const FULL_LEVELS: [f64; 4] = [0.02, 0.01, 0.005, 0.0025];
/// Windows of the roof impulse (s, simulated time): the first contacts and the first hard
/// impact of the 0.01 m lattice.
const WINDOWS: [(f64, f64); 2] = [(4.5, 5.7), (5.7, 6.7)];
/// The window of the largest low-pass roof force (s).
const LOW_PASS_WINDOW: (f64, f64) = (4.5, 6.7);
/// Target of the fine-grid convergence index of the design loads (fraction).
const GCI_TARGET: f64 = 0.05;

/// What one level gives.
struct Level {
    dx: f64,
    impacts: Vec<f64>,
    window_impulse: Vec<f64>,
    low_pass: f64,
    f_eq: Vec<(f64, f64)>,
    sensor_peak: f64,
    period_1: f64,
    max_mach: f64,
    /// Roof impulse from the start to [`RAISED_ROOF_END`] (N·s/m).
    impulse_to_end: f64,
    /// The Tait stiffness B the run used (Pa).
    eos_b: f64,
}

/// The raised-roof check: the coarser lattice (m), and the end of its impulse window (s, the
/// first two hard impacts).
const RAISED_ROOF_DX: f64 = 0.01;
const RAISED_ROOF_END: f64 = 6.35;

/// The value of column `y` at time `t` by linear interpolation of the rows.
fn at(t: &[f64], y: &[f64], time: f64) -> f64 {
    let k = t.partition_point(|&x| x < time);
    if k == 0 {
        return y.first().copied().unwrap_or(f64::NAN);
    }
    if k >= t.len() {
        return y.last().copied().unwrap_or(f64::NAN);
    }
    let f = (time - t[k - 1]) / (t[k] - t[k - 1]);
    y[k - 1] + f * (y[k] - y[k - 1])
}

fn level(ctx: &Context, dx: f64, g: &mut GroupResult) -> anyhow::Result<Level> {
    let mut sets: Vec<String> = SETS.iter().map(|s| s.to_string()).collect();
    sets.push(format!("dx={dx}"));
    run_level(ctx, &sets, &format!("roof_convergence_dx_{dx}"), dx, g)
}

fn run_level(
    ctx: &Context,
    sets: &[String],
    name: &str,
    dx: f64,
    g: &mut GroupResult,
) -> anyhow::Result<Level> {
    // The full suite's finer levels (≈ 15 min and ≈ 2 h on one thread) checkpoint.
    let r = run_script_with(ctx, "paper_2d_roof_sweep.rhai", name, sets, dx <= 0.005)?;
    g.particle_steps += particle_steps(&r.summary);
    let [t, impulse, low_pass] = r.columns(["t", "roof_impulse", "roof_force_up_lp"])?;
    let s = &r.summary;
    let load = s
        .roof_load
        .as_ref()
        .ok_or_else(|| anyhow::anyhow!("the run has no roof load"))?;
    let low = low_pass
        .iter()
        .zip(&t)
        .filter(|(_, &time)| time >= LOW_PASS_WINDOW.0 && time <= LOW_PASS_WINDOW.1)
        .map(|(f, _)| *f)
        .fold(f64::NEG_INFINITY, f64::max);
    Ok(Level {
        dx,
        impacts: s.impacts.iter().map(|i| i.t_start).collect(),
        window_impulse: WINDOWS
            .iter()
            .map(|&(a, b)| at(&t, &impulse, b) - at(&t, &impulse, a))
            .collect(),
        low_pass: low,
        f_eq: load
            .periods
            .iter()
            .copied()
            .zip(load.roof.design.iter().copied())
            .collect(),
        sensor_peak: load.sensors.first().map_or(f64::NAN, |s| s.load.peak),
        period_1: s.theory.period_1,
        max_mach: s.max_mach,
        impulse_to_end: at(&t, &impulse, RAISED_ROOF_END),
        eos_b: s.numerics.eos_stiffness,
    })
}

/// The full suite's raised-roof run: dx = 0.01 m with the roof one spacing higher (and the
/// stiffness of the nominal tank, so that only the roof moves), against dx = 0.005 m.
fn raised_roof(ctx: &Context, done: &[Level], g: &mut GroupResult) {
    let group = GROUP;
    let (Some(coarse), Some(fine)) = (
        done.iter().find(|l| (l.dx - RAISED_ROOF_DX).abs() < 1e-12),
        done.iter()
            .find(|l| (l.dx - 0.5 * RAISED_ROOF_DX).abs() < 1e-12),
    ) else {
        g.checks.push(failed_run(
            group,
            "raised roof",
            "not run: the dx = 0.01 m or 0.005 m level above did not finish",
        ));
        return;
    };
    // H′/H = 0.2 of H = 0.5 m, plus one spacing.
    let raised_ratio = 0.2 + RAISED_ROOF_DX / 0.5;
    let mut sets: Vec<String> = SETS
        .iter()
        .filter(|s| !s.starts_with("clearance_ratio=") && !s.starts_with("eos_b="))
        .map(|s| s.to_string())
        .collect();
    sets.push(format!("clearance_ratio={raised_ratio}"));
    sets.push(format!("eos_b={}", coarse.eos_b));
    sets.push(format!("dx={RAISED_ROOF_DX}"));
    let raised = match run_level(
        ctx,
        &sets,
        "roof_convergence_raised_roof",
        RAISED_ROOF_DX,
        g,
    ) {
        Ok(l) => l,
        Err(e) => {
            g.checks
                .push(failed_run(group, "raised roof", &format!("{e:#}")));
            return;
        }
    };
    let why = "the roof is felt ≈ 2 dx before the liquid reaches it (the kernel's reach): one \
               spacing higher, the 0.01 m lattice sees the clearance the 0.005 m lattice sees at \
               the nominal roof (short by 2 × 0.005 m either way), so what is left is the finer \
               lattice's own change of the wave before contact (≈ 1 %) and of the crest's shape";
    let (first_raised, first_fine) = (
        raised.impacts.first().copied().unwrap_or(f64::NAN),
        fine.impacts.first().copied().unwrap_or(f64::NAN),
    );
    let tolerance = 0.01 * fine.period_1;
    g.checks.push(condition(
        group,
        &format!(
            "first impact, dx = {RAISED_ROOF_DX} m with the roof one spacing higher, against \
             dx = {} m at the nominal roof",
            fine.dx
        ),
        format!("{first_raised:.3} s"),
        format!("{first_fine:.3} s"),
        (first_raised - first_fine).abs() <= tolerance,
        &format!("±{tolerance:.3} s (T₁/100)"),
        why,
    ));
    let change = (raised.impulse_to_end - fine.impulse_to_end) / fine.impulse_to_end;
    g.checks.push(condition(
        group,
        &format!(
            "roof impulse to {RAISED_ROOF_END} s, dx = {RAISED_ROOF_DX} m with the roof one \
             spacing higher, against dx = {} m at the nominal roof",
            fine.dx
        ),
        format!(
            "{:.1} N·s/m ({:+.1} %; at the nominal roof {:.1})",
            raised.impulse_to_end,
            100.0 * change,
            coarse.impulse_to_end
        ),
        format!("{:.1} N·s/m", fine.impulse_to_end),
        change.abs() <= 0.10,
        "± 10 %",
        why,
    ));
}

/// Runs the study.
pub fn study(ctx: &Context) -> GroupResult {
    let group = GROUP;
    let mut g = GroupResult::default();
    let levels: &[f64] = if ctx.quick {
        &QUICK_LEVELS
    } else {
        &FULL_LEVELS
    };
    let mut done: Vec<Level> = Vec::new();
    for &dx in levels {
        match level(ctx, dx, &mut g) {
            Ok(l) => {
                let f_eq: Vec<String> = l
                    .f_eq
                    .iter()
                    .map(|(t, f)| format!("{:.0} ms {f:.0}", 1000.0 * t))
                    .collect();
                let starts: Vec<String> = l.impacts.iter().map(|t| format!("{t:.2}")).collect();
                g.checks.push(info_row(
                    group,
                    &format!("dx = {dx} m: impacts (start, s); roof impulse 4.5–5.7 s and 5.7–6.7 s (N·s/m); largest low-pass roof force 4.5–6.7 s (N/m)"),
                    format!(
                        "[{}]; {:.1}, {:.1}; {:.0}",
                        starts.join(", "),
                        l.window_impulse[0],
                        l.window_impulse[1],
                        l.low_pass
                    ),
                    "—".into(),
                    "—".into(),
                    "reported per level",
                ));
                g.checks.push(info_row(
                    group,
                    &format!("dx = {dx} m: F_eq of the roof force (N/m) at T_r (ζ_r 2 %); corner sensor peak (Pa); largest Mach number"),
                    format!("{}; {:.0}; {:.3}", f_eq.join(", "), l.sensor_peak, l.max_mach),
                    "—".into(),
                    "—".into(),
                    "reported per level",
                ));
                done.push(l);
            }
            Err(e) => g.checks.push(failed_run(
                group,
                &format!("dx = {dx} m"),
                &format!("{e:#}"),
            )),
        }
    }
    if !ctx.quick {
        raised_roof(ctx, &done, &mut g);
    }
    if done.len() != levels.len() || done.len() < 2 {
        return g;
    }
    // The same episodes on the finest two levels: each impact of the finer that starts before
    // the last window's end has one on the coarser within T₁/10.
    let (coarse, fine) = (&done[done.len() - 2], &done[done.len() - 1]);
    let tolerance = 0.1 * fine.period_1;
    let last = WINDOWS[WINDOWS.len() - 1].1;
    let early: Vec<f64> = fine.impacts.iter().copied().filter(|&t| t < last).collect();
    let unmatched: Vec<f64> = early
        .iter()
        .copied()
        .filter(|t| !coarse.impacts.iter().any(|c| (c - t).abs() <= tolerance))
        .collect();
    g.checks.push(condition(
        group,
        &format!(
            "impacts before {last} s at dx = {} m found at dx = {} m (starts within T₁/10)",
            fine.dx, coarse.dx
        ),
        format!(
            "{} of {} matched",
            early.len() - unmatched.len(),
            early.len()
        ),
        "all".into(),
        !early.is_empty() && unmatched.is_empty(),
        &format!("±{tolerance:.3} s"),
        "an impact is a contact episode of the roof force above 2 % of ρ g H′ times the roof \
         area (off below 1 %, merged within T₁/4; kept when its impulse reaches 1 % of \
         ρ g H′ T₁ over the roof or per area on the corner sensor), so a particle grazing the \
         roof is none; the \
         crest's arrival converges (its height before contact within 1 % between these \
         lattices), so the episodes it starts must too",
    ));
    let h: Vec<f64> = done.iter().map(|l| l.dx).collect();
    // (name, values per level, judged on the GCI, why when it is not)
    let two_levels = "reported: two levels give a change, no order (the full suite judges the \
                      finest three)";
    let mut quantities: Vec<(String, Vec<f64>, bool, &str)> = Vec::new();
    for (k, &(a, b)) in WINDOWS.iter().enumerate() {
        quantities.push((
            format!("roof impulse {a}–{b} s"),
            done.iter().map(|l| l.window_impulse[k]).collect(),
            true,
            two_levels,
        ));
    }
    quantities.push((
        "largest low-pass roof force".into(),
        done.iter().map(|l| l.low_pass).collect(),
        true,
        two_levels,
    ));
    for (k, &(t, _)) in done[0].f_eq.iter().enumerate() {
        quantities.push((
            format!("F_eq at T_r = {:.0} ms", 1000.0 * t),
            done.iter()
                .map(|l| l.f_eq.get(k).map_or(f64::NAN, |x| x.1))
                .collect(),
            t >= 0.05 - 1e-12,
            if t >= 0.05 - 1e-12 {
                two_levels
            } else {
                "reported: a roof stiffer than 50 ms follows the impact's peak force, which \
                 does not converge point by point"
            },
        ));
    }
    quantities.push((
        "corner sensor peak pressure (a diagnostic)".into(),
        done.iter().map(|l| l.sensor_peak).collect(),
        false,
        "reported: a single peak is an extreme, not a design load",
    ));
    for (name, values, judged, why) in quantities {
        let u = uncertainty(&values, &h);
        let shown: Vec<String> = values.iter().map(|v| format!("{v:.1}")).collect();
        let measured = if done.len() >= 3 {
            format!(
                "{} → {}; p {:.2}, GCI {:.1} %",
                shown.join(" → "),
                u.behaviour.word(),
                u.order,
                100.0 * u.gci_fine
            )
        } else {
            format!(
                "{}; change {:.1} %",
                shown.join(" → "),
                100.0 * u.relative_change
            )
        };
        if done.len() >= 3 && judged {
            g.checks.push(condition(
                group,
                &format!("{name}: converges on the finest three levels"),
                measured,
                "monotone, GCI_fine ≤ 5 %".into(),
                u.behaviour == Behaviour::Monotone && u.gci_fine <= GCI_TARGET,
                "GCI ≤ 5 %",
                "the design loads' numerical uncertainty must be small beside the 20–40 % scatter \
                 of repeated sloshing-impact experiments",
            ));
        } else {
            g.checks.push(info_row(
                group,
                &name,
                measured,
                "—".into(),
                "—".into(),
                why,
            ));
        }
    }
    g
}
