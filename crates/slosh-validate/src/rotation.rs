//! The tank's rotating frame, checked against closed forms (`scripts/tank_pitch_2d.rhai` and
//! `scripts/tank_pitch_3d.rhai`, run as a user runs them):
//!
//! - a 2D tank tilted slowly to θ₀ and held: the surface level in the world (its slope in the
//!   tank's frame tan θ₀), the base shear M g sin θ₀ and the bottom force M g cos θ₀ of the
//!   hydrostatic liquid;
//! - the same tank pitched from rest, θ = θ₀ (1 − cos Ωt)/2 at Ω = 0.6 ω₁, about a pivot at
//!   its bottom (below the surface) and 0.3 m above the surface: the wall elevation against
//!   the linear modal solution of `slosh_theory::pitch` (Faltinsen & Timokha 2009, ch. 5);
//! - a 3D cylinder pitched about a horizontal axis turned 45° from y against the same motion
//!   about y: the same wave, turned with the axis.

use super::run::{Context, GRAVITY, RHO};
use super::scripts::{particle_steps, run_script, ScriptRun};
use super::{condition, failed_run, relative_check, GroupResult};
use anyhow::{Context as _, Result};
use slosh_theory::linear::RectangularTank;
use slosh_theory::modal::ModalTank;
use slosh_theory::pitch::{pitch_from_rest, PitchedRectangularTank};

/// Group title.
pub const GROUP: &str = "Rotating tank: the tank's frame (tank_pitch_2d.rhai, tank_pitch_3d.rhai)";

/// The 2D tank of the script's defaults (m).
const WIDTH: f64 = 1.0;
const DEPTH: f64 = 0.5;
/// Tilt and pitch amplitude θ₀ (rad).
const TILT: f64 = 0.05;
const PITCH: f64 = 0.04;
/// Pitch frequency over ω₁.
const FREQUENCY_RATIO: f64 = 0.6;
/// Settling before the motion (s), the script's default.
const SETTLE: f64 = 0.5;
/// Modes of the linear solution: the tail above them is taken quasi-statically.
const MODES: usize = 30;

/// The rows of the group.
pub fn frame_checks(ctx: &Context) -> GroupResult {
    let mut result = GroupResult::default();
    tilt_rows(ctx, &mut result);
    for (pivot, label) in [
        (0.0, "pivot at the bottom, 0.5 m below the surface"),
        (0.8, "pivot 0.3 m above the surface"),
    ] {
        pitch_rows(ctx, &mut result, pivot, label);
    }
    axis_rows(ctx, &mut result);
    result.notes.push(
        "The liquid is integrated in the tank's frame with gravity turning with the tank and \
         the Euler, centrifugal and Coriolis forces (`slosh_core::frame`); the scripts give \
         the angle alone and slosh takes its derivatives by central differences."
            .into(),
    );
    result
}

/// Mean of `ys` over the rows with `t` in [from, to].
fn mean_over(t: &[f64], ys: &[f64], from: f64, to: f64) -> f64 {
    let (sum, n) = t
        .iter()
        .zip(ys)
        .filter(|(ti, _)| **ti >= from && **ti <= to)
        .fold((0.0, 0usize), |(s, n), (_, y)| (s + y, n + 1));
    sum / n.max(1) as f64
}

fn tilt_rows(ctx: &Context, result: &mut GroupResult) {
    let ramp = 3.0;
    let hold = 3.0;
    let per_depth = if ctx.quick { 20 } else { 25 };
    let dx = DEPTH / per_depth as f64;
    let name =
        format!("tilt to θ₀ = {TILT} rad over {ramp} s, held {hold} s ({per_depth} per depth)");
    let sets = vec![
        "motion=tilt".to_string(),
        format!("pitch_amplitude={TILT}"),
        format!("ramp={ramp}"),
        format!("hold={hold}"),
        format!("particles_per_depth={per_depth}"),
    ];
    let measured = run_script(ctx, "tank_pitch_2d.rhai", "rotation_tilt", &sets).and_then(|run| {
        let [t, left, right, shear, bottom] = run.columns([
            "t",
            "eta_left",
            "eta_right",
            "base_shear_x",
            "bottom_force_down",
        ])?;
        // The last 2 s of the hold: the ramp's small free oscillation averages out.
        let end = SETTLE + ramp + hold;
        let from = end - 2.0;
        let mean = |y: &[f64]| mean_over(&t, y, from, end);
        // The wall gauges stand one spacing inside the walls.
        let slope = (mean(&right) - mean(&left)) / (WIDTH - 2.0 * dx);
        result.particle_steps += particle_steps(&run.summary);
        Ok((slope, mean(&shear), mean(&bottom)))
    });
    let weight = RHO * GRAVITY * WIDTH * DEPTH;
    match measured {
        Ok((slope, shear, bottom)) => {
            result.checks.push(relative_check(
                GROUP,
                &format!("{name}: surface slope in the tank's frame (level in the world)"),
                slope,
                TILT.tan(),
                "",
                0.03,
                "a level surface seen from the tilted tank has the slope tan θ₀; 3 %: the wall \
                 gauges read the surface through the kernel and are biased by about a \
                 millimetre on a sloping surface",
            ));
            result.checks.push(relative_check(
                GROUP,
                &format!("{name}: base shear"),
                shear,
                weight * TILT.sin(),
                "N/m",
                0.02,
                "hydrostatics in the turned frame: the walls hold the weight's component along \
                 the tank's floor, M g sin θ₀; 2 %: the wall-pressure load of still liquid is \
                 within a few tenths of a per cent of its weight at this resolution",
            ));
            result.checks.push(relative_check(
                GROUP,
                &format!("{name}: bottom force"),
                bottom,
                weight * TILT.cos(),
                "N/m",
                0.01,
                "hydrostatics in the turned frame: the floor holds M g cos θ₀ whatever the \
                 slope of the surface; 1 %: as for the base shear",
            ));
        }
        Err(e) => result
            .checks
            .push(failed_run(GROUP, &name, &format!("{e:#}"))),
    }
}

/// The antisymmetric part of the wall elevations, (η_R − η_L)/2 (m): the part a pitch drives
/// linearly, free of the surface's second-order set-down and of the gauges' common offset.
fn antisymmetric(left: &[f64], right: &[f64]) -> Vec<f64> {
    left.iter().zip(right).map(|(l, r)| 0.5 * (r - l)).collect()
}

/// Largest |v|.
fn largest_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// RMS of a − b, sample by sample over their common length.
fn rms_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / n.max(1) as f64).sqrt()
}

fn pitch_rows(ctx: &Context, result: &mut GroupResult, pivot_above_bottom: f64, label: &str) {
    let per_depth = 25;
    let dx = DEPTH / per_depth as f64;
    let periods = if ctx.quick { 2.0 } else { 3.0 };
    let name = format!(
        "pitch θ₀ = {PITCH} rad at Ω = {FREQUENCY_RATIO} ω₁, {label} ({per_depth} per depth, \
         {periods} periods)"
    );
    let sets = vec![
        "motion=pitch".to_string(),
        format!("pitch_amplitude={PITCH}"),
        format!("frequency_ratio={FREQUENCY_RATIO}"),
        format!("pivot_height={pivot_above_bottom}"),
        format!("periods={periods}"),
        format!("particles_per_depth={per_depth}"),
    ];
    let run_name = format!("rotation_pitch_{pivot_above_bottom}");
    let measured = run_script(ctx, "tank_pitch_2d.rhai", &run_name, &sets).and_then(|run| {
        let [t, left, right] = run.columns(["t", "eta_left", "eta_right"])?;
        result.particle_steps += particle_steps(&run.summary);
        let sph = antisymmetric(&left, &right);
        let theory = pitch_theory(pivot_above_bottom - DEPTH, &t, dx)?;
        let (sph, theory): (Vec<f64>, Vec<f64>) = t
            .iter()
            .zip(sph.iter().zip(&theory))
            .filter(|(ti, _)| **ti >= SETTLE)
            .map(|(_, (s, th))| (*s, *th))
            .unzip();
        anyhow::ensure!(!sph.is_empty(), "no row after the settling time");
        Ok((
            largest_abs(&sph),
            largest_abs(&theory),
            rms_difference(&sph, &theory),
        ))
    });
    match measured {
        Ok((sph_max, theory_max, rms)) => {
            result.checks.push(relative_check(
                GROUP,
                &format!("{name}: largest wall elevation (η_R − η_L)/2"),
                sph_max,
                theory_max,
                "m",
                0.05,
                "the linear modal solution of a pitched rectangular tank from rest \
                 (slosh_theory::pitch, Faltinsen & Timokha 2009 ch. 5; 30 modes, undamped); \
                 5 %: the crest is 0.06 H, where second-order effects are a few per cent, and \
                 the antisymmetric part leaves out the surface's even second-order set-down",
            ));
            let ratio = rms / theory_max;
            result.checks.push(condition(
                GROUP,
                &format!("{name}: RMS difference from the linear solution over the run"),
                format!("{:.1} % of the largest", 100.0 * ratio),
                "linear modal solution".into(),
                ratio <= 0.05,
                "≤ 5 %",
                "phase and amplitude together, sample by sample: a frame force missing or of \
                 the wrong sign (the Euler force's lever about the pivot, gravity turning) \
                 changes the response by tens of per cent",
            ));
        }
        Err(e) => result
            .checks
            .push(failed_run(GROUP, &name, &format!("{e:#}"))),
    }
}

/// The linear solution's (η_R − η_L)/2 at the gauges (one spacing inside the walls) at the
/// series' times `t` (s, the excitation starting at [`SETTLE`]), pivot `pivot_height` (m)
/// above the still surface.
fn pitch_theory(pivot_height: f64, t: &[f64], dx: f64) -> Result<Vec<f64>> {
    let tank = PitchedRectangularTank {
        tank: RectangularTank::water(WIDTH, DEPTH),
        pivot_height,
    };
    let omega = FREQUENCY_RATIO * tank.tank.modal_omega(0);
    let step = 2e-4;
    let end = t.last().copied().context("empty series")? - SETTLE;
    let n = (end / step).ceil() as usize + 2;
    let (angle, accel) = pitch_from_rest(PITCH, omega, step, n);
    let right = tank.elevation_history(step, &angle, &accel, WIDTH - dx, MODES);
    let left = tank.elevation_history(step, &angle, &accel, dx, MODES);
    Ok(t.iter()
        .map(|&ti| {
            let s = ((ti - SETTLE) / step).max(0.0);
            let k = (s.floor() as usize).min(n - 2);
            let w = (s - k as f64).min(1.0);
            let at = |y: &[f64]| y[k] * (1.0 - w) + y[k + 1] * w;
            if ti < SETTLE {
                0.0
            } else {
                0.5 * (at(&right) - at(&left))
            }
        })
        .collect())
}

fn axis_rows(ctx: &Context, result: &mut GroupResult) {
    let dx = if ctx.quick { 0.05 } else { 0.04 };
    let name = format!(
        "3D cylinder R = 0.5 m pitched about an axis 45° from y against the same pitch about \
         y (dx = {dx} m)"
    );
    let run = |azimuth: f64| -> Result<ScriptRun> {
        run_script(
            ctx,
            "tank_pitch_3d.rhai",
            &format!("rotation_axis_{azimuth}"),
            &[format!("axis_azimuth={azimuth}"), format!("dx={dx}")],
        )
    };
    let measured = run(0.0).and_then(|about_y| {
        let turned = run(45.0)?;
        result.particle_steps += particle_steps(&about_y.summary) + particle_steps(&turned.summary);
        let [ty, ly, ry] = about_y.columns(["t", "eta_lowered", "eta_raised"])?;
        let [tt, lt, rt] = turned.columns(["t", "eta_lowered", "eta_raised"])?;
        let y_wave = antisymmetric(&ry, &ly);
        let turned_wave = antisymmetric(&rt, &lt);
        let largest = largest_abs(&y_wave);
        let rows = ty.len().min(tt.len());
        anyhow::ensure!(rows > 10 && largest > 0.0, "no wave in the runs");
        Ok((rms_difference(&y_wave, &turned_wave) / largest, largest))
    });
    match measured {
        Ok((ratio, largest)) => result.checks.push(condition(
            GROUP,
            &format!("{name}: RMS difference of the wave along the lowered diameter"),
            format!("{:.2} % of the largest ({:.4} m)", 100.0 * ratio, largest),
            "the run about y".into(),
            ratio <= 0.02,
            "≤ 2 %",
            "a cylinder has no preferred horizontal direction, so the wave turns with the \
             axis; 2 %: the polar lattice's rings are the same in every direction but their \
             particles are not",
        )),
        Err(e) => result
            .checks
            .push(failed_run(GROUP, &name, &format!("{e:#}"))),
    }
}
