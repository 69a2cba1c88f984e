//! The response spectrum of the applied ground motion, with the tank's convective period
//! marked and the codes' sloshing wave heights beside the SPH maximum.
//!
//! Input: the x ground acceleration applied from the start of the excitation. Best is the
//! motion itself on a uniform grid: [`write_case_input_spectrum`] calls the script's
//! `ground_accel` every 0.005 s, which reproduces a record sampled at 0.01 or 0.02 s exactly
//! (it is linear between samples). The rows of `series.csv` work too, but with a CFL-variable
//! step they sit at the step times just after each output time, so [`write_input_spectrum`]
//! resamples them linearly onto a uniform grid, which smooths the record's peaks a little.
//!
//! Output: `input_spectrum.csv` (periods log-spaced from 0.02 s to max(10 s, 2 T_c)), the plot
//! `plots/input_spectrum.png/.svg`, and a [`SpectrumSummary`] for `summary.ron`.

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};
use slosh_io::{PlotSpec, Series, TableWriter};
use slosh_motion::{log_spaced_periods, response_spectrum, GRAVITY_M_S2};
use slosh_script::{Case, TankSpec};
use std::path::Path;

/// Step at which [`write_case_input_spectrum`] samples the script's `ground_accel`, s. A
/// divisor of the usual record intervals (0.01, 0.02 s), so a record is reproduced exactly.
pub const MOTION_SAMPLE_INTERVAL_S: f64 = 0.005;

/// Damping ratio of the spectrum written to the CSV and plotted first (5 % of critical).
pub const STRUCTURAL_DAMPING: f64 = 0.05;
/// Damping ratio the codes (API 650, ACI 350.3, EN 1998-4) use for the convective mode (0.5 %).
pub const CONVECTIVE_DAMPING: f64 = 0.005;

/// One code's sloshing wave height for this tank and this input.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CodeWaveHeight {
    /// Code and clause.
    pub code: String,
    /// The formula, with S_a = S_a(T_c) at 0.5 % damping from the input's own spectrum.
    pub formula: String,
    /// Peak wave height above the still level, m.
    pub wave_height_m: f64,
}

/// What `summary.ron` gets about the input's response spectrum.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SpectrumSummary {
    /// The tank's first convective period T_c used, s.
    pub convective_period_s: f64,
    /// S_a(T_c) at 0.5 % damping (the codes' convective damping), m/s².
    pub sa_tc_0p5pct_m_s2: f64,
    /// S_a(T_c) at 0.5 % damping, g (9.81 m/s²).
    pub sa_tc_0p5pct_g: f64,
    /// S_a(T_c) at 5 % damping, m/s².
    pub sa_tc_5pct_m_s2: f64,
    /// S_a(T_c) at 5 % damping, g.
    pub sa_tc_5pct_g: f64,
    /// Largest S_a of the 5 % spectrum, g.
    pub peak_sa_5pct_g: f64,
    /// Period of that peak, s.
    pub peak_period_5pct_s: f64,
    /// Peak |a_x| of the input, m/s².
    pub input_pga_m_s2: f64,
    /// Sample interval the spectrum was computed with, s.
    pub input_dt_s: f64,
    /// Length of the input, s.
    pub input_duration_s: f64,
    /// Code wave heights from this spectrum.
    pub code_wave_heights: Vec<CodeWaveHeight>,
    /// The SPH result to compare with: largest free-surface elevation at the walls, m.
    pub sph_max_eta_m: f64,
    /// Freeboard H′ from the still level to the roof at the wall (m), when the tank has a roof.
    pub freeboard_m: Option<f64>,
    /// Malhotra's roof pressure from each code wave height that exceeds the freeboard.
    pub malhotra_roof_pressures: Vec<CodeRoofPressure>,
}

/// The input spectrum of a case after its run: samples the script's `ground_accel` (x
/// component) every [`MOTION_SAMPLE_INTERVAL_S`] from the end of settling to the end of the
/// run and calls [`write_input_spectrum`] with the size of `tank`, the tank as simulated
/// (fitted to the particle lattice, with the fill depth the lattice holds: the summary's
/// `tank`), whose freeboard is also the one reported. `convective_period_s` is the tank's first
/// sloshing period (e.g. the summary's `theory.period_1`), `sph_max_eta` the SPH maximum
/// elevation at the walls. Returns `None` (and writes nothing) when the x excitation is zero
/// throughout or shorter than two samples.
pub fn write_case_input_spectrum(
    out: &Path,
    case: &mut Case,
    tank: &TankSpec,
    convective_period_s: f64,
    sph_max_eta: f64,
) -> Result<Option<SpectrumSummary>> {
    if !case.excitation.has_ground_accel() {
        return Ok(None);
    }
    let span = case.run.duration - case.run.settle;
    let n = (span / MOTION_SAMPLE_INTERVAL_S + 1e-9).floor() as usize + 1;
    if span <= 0.0 || n < 2 {
        return Ok(None);
    }
    let mut times = Vec::with_capacity(n);
    let mut accel_x = Vec::with_capacity(n);
    for i in 0..n {
        let t = i as f64 * MOTION_SAMPLE_INTERVAL_S;
        times.push(t);
        accel_x.push(case.excitation.ground_accel(t)?[0]);
    }
    if accel_x.iter().all(|a| *a == 0.0) {
        return Ok(None);
    }
    let (size, is_cylinder) = match tank {
        TankSpec::Rect { width, .. } => (*width, false),
        TankSpec::Section { .. } | TankSpec::Sphere { .. } | TankSpec::Mesh { .. } => {
            (tank.horizontal_size(), false)
        }
        TankSpec::Box { length, .. } => (*length, false),
        TankSpec::Cylinder { radius, .. } => (2.0 * radius, true),
    };
    let mut summary = write_input_spectrum(
        out,
        &times,
        &accel_x,
        convective_period_s,
        size,
        is_cylinder,
        sph_max_eta,
    )?;
    let freeboard = match tank {
        TankSpec::Rect {
            height,
            depth,
            roof: true,
            ..
        }
        | TankSpec::Box {
            height,
            depth,
            roof: true,
            ..
        } => Some(height - depth),
        TankSpec::Cylinder {
            height,
            depth,
            roof,
            ..
        } if roof != "none" => Some(height - depth),
        TankSpec::Mesh {
            depth,
            extent:
                slosh_script::MeshExtent {
                    roof_base: Some(base),
                    ..
                },
            ..
        } => Some(base - depth),
        _ => None,
    };
    summary.freeboard_m = freeboard;
    if let Some(h_free) = freeboard {
        summary.malhotra_roof_pressures = malhotra_from_code_waves(
            &summary.code_wave_heights,
            h_free,
            0.5 * size,
            case.sph.rest_density,
            case.sph.gravity,
        );
    }
    Ok(Some(summary))
}

/// Malhotra's (2005) roof pressure for each code wave height d that exceeds the freeboard
/// H′: the liquid surface, inclined at θ = π/4 (paper §3.2), is cut by the roof over the
/// contact extent x_f = (d − H′)/tan θ from the wall (at most the half-width or radius), and
/// P_max = ρ g x_f tan θ (paper Eq. 27).
fn malhotra_from_code_waves(
    waves: &[CodeWaveHeight],
    freeboard: f64,
    half_width: f64,
    density: f64,
    gravity: f64,
) -> Vec<CodeRoofPressure> {
    let theta = slosh_theory::roof::MALHOTRA_DEFAULT_ANGLE;
    waves
        .iter()
        .map(|w| {
            let extent = ((w.wave_height_m - freeboard).max(0.0) / theta.tan()).min(half_width);
            CodeRoofPressure {
                wave_from: w.code.clone(),
                contact_extent_m: extent,
                pressure_pa: slosh_theory::roof::malhotra_roof_pressure(
                    density, gravity, extent, theta,
                ),
            }
        })
        .collect()
}

/// Malhotra's roof pressure from one code's wave height (0 when the wave stays below the
/// roof).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CodeRoofPressure {
    /// The code whose wave height was used.
    pub wave_from: String,
    /// Contact extent x_f of the liquid with the roof, from the wall (m).
    pub contact_extent_m: f64,
    /// Peak roof pressure P_max = ρ g x_f tan θ (Pa).
    pub pressure_pa: f64,
}

/// Computes the pseudo-acceleration spectrum of the applied x acceleration, writes
/// `out/input_spectrum.csv` and `out/plots/input_spectrum.{png,svg}`, and returns the summary.
///
/// * `times`, `accel_x`: the applied ground acceleration (m/s²) at increasing times (s) from
///   the start of the excitation. A uniform grid (within 1e-6 relative) is used as it is;
///   otherwise the series is resampled linearly onto a uniform grid at its median step. For a
///   faithful spectrum pass the motion itself on a fine uniform grid, e.g. the script's
///   `ground_accel(t)` for t = 0, 0.005, … up to `duration − settle`.
/// * `convective_period_s`: the tank's first convective (sloshing) period T_c, s.
/// * `tank_width_or_diameter_m`: inner width of a rectangular tank along x (L), or inner
///   diameter of a cylinder (D), m; `is_cylinder` says which.
/// * `sph_max_eta`: the SPH maximum free-surface elevation at the walls, m (copied into the
///   summary beside the code values).
pub fn write_input_spectrum(
    out: &Path,
    times: &[f64],
    accel_x: &[f64],
    convective_period_s: f64,
    tank_width_or_diameter_m: f64,
    is_cylinder: bool,
    sph_max_eta: f64,
) -> Result<SpectrumSummary> {
    if !(convective_period_s.is_finite() && convective_period_s > 0.0) {
        bail!("input spectrum: the convective period must be a positive number of seconds, got {convective_period_s}");
    }
    let (dt, accel) = uniform_series(times, accel_x)?;
    let g = GRAVITY_M_S2;

    let t_max = (2.0 * convective_period_s).max(10.0);
    let periods = log_spaced_periods(0.02, t_max, 200);
    let structural = response_spectrum(&accel, dt, &periods, STRUCTURAL_DAMPING)?;
    let convective = response_spectrum(&accel, dt, &periods, CONVECTIVE_DAMPING)?;
    let at_tc_5 = response_spectrum(&accel, dt, &[convective_period_s], STRUCTURAL_DAMPING)?
        .pseudo_accel_m_s2[0];
    let at_tc_05 = response_spectrum(&accel, dt, &[convective_period_s], CONVECTIVE_DAMPING)?
        .pseudo_accel_m_s2[0];

    let csv = out.join("input_spectrum.csv");
    let mut table = TableWriter::create_whole(
        &csv,
        &[
            "period_s",
            "sa_m_s2",
            "sa_g",
            "sa_0p5pct_m_s2",
            "sa_0p5pct_g",
        ],
    )
    .with_context(|| format!("cannot write {}", csv.display()))?;
    for ((&t, &sa5), &sa05) in periods
        .iter()
        .zip(&structural.pseudo_accel_m_s2)
        .zip(&convective.pseudo_accel_m_s2)
    {
        table.write_row(&[t, sa5, sa5 / g, sa05, sa05 / g])?;
    }
    table.finish()?;

    let sa5_g: Vec<f64> = structural.pseudo_accel_m_s2.iter().map(|a| a / g).collect();
    let sa05_g: Vec<f64> = convective.pseudo_accel_m_s2.iter().map(|a| a / g).collect();
    let top = sa05_g.iter().chain(&sa5_g).copied().fold(0.0, f64::max);
    let marker_t = [convective_period_s, convective_period_s];
    let marker_sa = [0.0, top];
    let marker_label = format!("T_c = {convective_period_s:.3} s");
    slosh_io::line_plot(
        out.join("plots").join("input_spectrum"),
        &PlotSpec::new(
            "Response spectrum of the input (pseudo-acceleration)",
            "period T [s]",
            "S_a [g]",
        ),
        &[
            Series::line("5 % damping", &periods, &sa5_g),
            Series::line("0.5 % damping (convective)", &periods, &sa05_g),
            Series::dashed(marker_label, &marker_t, &marker_sa).with_color(0, 0, 0),
        ],
    )?;

    let (peak_period, peak_sa) = structural.peak().unwrap_or((f64::NAN, f64::NAN));
    let sa_g = at_tc_05 / g;
    let size = tank_width_or_diameter_m;
    let code_wave_heights = if is_cylinder {
        vec![
            CodeWaveHeight {
                code: "API 650 Annex E (E.7.2)".into(),
                formula: "0.42 D A_f, A_f = S_a(T_c, 0.5 %)/g".into(),
                wave_height_m: slosh_theory::codes::api650_wave_height(size, sa_g),
            },
            CodeWaveHeight {
                code: "ACI 350.3-06 (7-2)".into(),
                formula: "(D/2) C_c I, C_c I = S_a(T_c, 0.5 %)/g".into(),
                wave_height_m: slosh_theory::codes::aci350_circular_wave_height(size, sa_g),
            },
            CodeWaveHeight {
                code: "EN 1998-4 Annex A (A.9)".into(),
                formula: "0.84 R S_e(T_c, 0.5 %)/g".into(),
                wave_height_m: slosh_theory::codes::ec8_circular_wave_height(0.5 * size, sa_g),
            },
        ]
    } else {
        vec![
            CodeWaveHeight {
                code: "ACI 350.3-06 (7-1)".into(),
                formula: "(L/2) A_f, A_f = S_a(T_c, 0.5 %)/g".into(),
                wave_height_m: slosh_theory::codes::aci350_rectangular_wave_height(size, sa_g),
            },
            CodeWaveHeight {
                code: "EN 1998-4 Annex A".into(),
                formula: "0.5 L S_e(T_c, 0.5 %)/g".into(),
                wave_height_m: slosh_theory::codes::ec8_rectangular_wave_height(size, sa_g),
            },
        ]
    };
    Ok(SpectrumSummary {
        convective_period_s,
        sa_tc_0p5pct_m_s2: at_tc_05,
        sa_tc_0p5pct_g: at_tc_05 / g,
        sa_tc_5pct_m_s2: at_tc_5,
        sa_tc_5pct_g: at_tc_5 / g,
        peak_sa_5pct_g: peak_sa / g,
        peak_period_5pct_s: peak_period,
        input_pga_m_s2: accel.iter().fold(0.0, |m: f64, a| m.max(a.abs())),
        input_dt_s: dt,
        input_duration_s: dt * accel.len().saturating_sub(1) as f64,
        code_wave_heights,
        sph_max_eta_m: sph_max_eta,
        freeboard_m: None,
        malhotra_roof_pressures: Vec::new(),
    })
}

/// The series on a uniform grid: (dt, samples). Uniform input (steps equal within 1e-6
/// relative) is returned as it is; other input is interpolated linearly at the median step.
fn uniform_series(times: &[f64], accel: &[f64]) -> Result<(f64, Vec<f64>)> {
    if times.len() != accel.len() {
        bail!(
            "input spectrum: {} times but {} accelerations",
            times.len(),
            accel.len()
        );
    }
    if times.len() < 2 {
        bail!("input spectrum: the excitation has fewer than 2 samples");
    }
    if times.iter().chain(accel).any(|x| !x.is_finite()) {
        bail!("input spectrum: the excitation holds non-finite values");
    }
    let mut steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    if steps.iter().any(|&s| s <= 0.0) {
        bail!("input spectrum: the times must increase strictly");
    }
    let span = times[times.len() - 1] - times[0];
    let mean_step = span / steps.len() as f64;
    if steps
        .iter()
        .all(|s| (s - mean_step).abs() <= 1e-6 * mean_step)
    {
        return Ok((mean_step, accel.to_vec()));
    }
    steps.sort_by(f64::total_cmp);
    let dt = steps[steps.len() / 2];
    let n = (span / dt).floor() as usize + 1;
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    for i in 0..n {
        let t = times[0] + i as f64 * dt;
        while k + 2 < times.len() && times[k + 1] < t {
            k += 1;
        }
        let w = ((t - times[k]) / (times[k + 1] - times[k])).clamp(0.0, 1.0);
        out.push(accel[k] * (1.0 - w) + accel[k + 1] * w);
    }
    Ok((dt, out))
}

#[cfg(test)]
mod tests {
    use super::uniform_series;

    #[test]
    fn uniform_input_is_kept_and_uneven_input_is_resampled() {
        let t = [0.0, 0.01, 0.02, 0.03];
        let a = [1.0, 2.0, 3.0, 4.0];
        let (dt, v) = uniform_series(&t, &a).unwrap();
        assert!((dt - 0.01).abs() < 1e-15);
        assert_eq!(v, a.to_vec());
        // Rows just after the output times: a linear ramp a = 100 t stays exact.
        let t = [0.0, 0.0102, 0.0201, 0.0303, 0.0400];
        let a: Vec<f64> = t.iter().map(|t| 100.0 * t).collect();
        let (dt, v) = uniform_series(&t, &a).unwrap();
        assert!((0.0097..=0.0102).contains(&dt), "dt {dt}");
        for (i, x) in v.iter().enumerate() {
            assert!((x - 100.0 * i as f64 * dt).abs() < 1e-12);
        }
        assert!(uniform_series(&[0.0, 0.0], &[1.0, 1.0]).is_err());
    }
}
