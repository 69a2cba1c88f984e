//! The roof files of a run: `roof_pressure.csv` (with `roof_points.csv`/`.vtp` in 3D), the
//! roof pressure map and the pressure-field snapshots of paper Fig. 7, written from the
//! roof analysis of `slosh-run`, and the 2D frame at the largest wave.

use anyhow::Result;
use slosh_io::{Field2d, PlotSpec, PointArray};
use slosh_run::{RoofMonitor, RoofSnapshot};
use std::path::Path;

/// Writes `roof_pressure.csv` (2D: rows = time, columns = x along the roof; 3D, and a 2D
/// roof whose points share an x: columns = roof point index, with `roof_points.csv` (and in
/// 3D `roof_points.vtp`) giving the points, their peak pressure and its time) and the 2D map
/// plot.
pub fn write_roof_pressure<const D: usize>(
    roof: &RoofMonitor<D>,
    out: &Path,
    plots: bool,
) -> Result<()> {
    let (positions, areas) = roof.points();
    let (times, map) = (roof.times(), roof.map());
    if positions.is_empty() || times.is_empty() {
        return Ok(());
    }
    let n = positions.len();
    let xs: Vec<f64> = positions.iter().map(|p| p[0]).collect();
    // A 2D roof names its columns by x along the roof, unless two of its points share an x
    // (a steep cone, a stepped roof): then by index, as in 3D, with `roof_points.csv`.
    let by_x = D == 2 && {
        let mut names: Vec<String> = xs.iter().map(|&x| slosh_io::format_f64(x)).collect();
        names.sort();
        names.windows(2).all(|w| w[0] != w[1])
    };
    let idx: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let columns = if by_x { &xs } else { &idx };
    slosh_io::write_grid_csv(out.join("roof_pressure.csv"), "t", times, columns, map)?;
    if D == 2 && plots {
        slosh_io::heatmap(
            out.join("plots").join("roof_pressure_map"),
            &PlotSpec::new(
                "Roof pressure (time-windowed)",
                "time t [s]",
                if by_x {
                    "x along the roof [m]"
                } else {
                    "roof point (roof_points.csv)"
                },
            ),
            &Field2d {
                xs: times,
                ys: columns,
                values: map,
                value_label: "p [Pa]".into(),
            },
        )?;
    }
    if !by_x {
        let header: &[&str] = if D == 2 {
            &["index", "x", "y", "area", "p_peak", "t_peak"]
        } else {
            &["index", "x", "y", "z", "area", "p_peak", "t_peak"]
        };
        let mut table = slosh_io::TableWriter::create_whole(out.join("roof_points.csv"), header)?;
        let (peak, t_peak) = roof.peaks();
        let mut row = Vec::with_capacity(header.len());
        for i in 0..n {
            row.clear();
            row.push(i as f64);
            row.extend((0..D).map(|k| positions[i][k]));
            row.extend([areas[i], peak[i], t_peak[i]]);
            table.write_row(&row)?;
        }
        table.finish()?;
        if D == 3 {
            let points: Vec<[f64; 3]> = positions.iter().map(|p| [p[0], p[1], p[2]]).collect();
            slosh_io::write_vtp(
                out.join("roof_points.vtp"),
                &points,
                &[
                    PointArray::scalar("p_peak", &peak),
                    PointArray::scalar("t_peak", &t_peak),
                    PointArray::scalar("area", areas),
                ],
            )?;
        }
    }
    Ok(())
}

/// Draws the 2D pressure field at t_peak − 0.06 s, t_peak, t_peak + 0.06 s (paper Fig. 7
/// shows 1.55, 1.61 and 1.67 s after the excitation start) as `plots/fig7_*.png`.
pub fn write_fig7<const D: usize>(
    roof: &RoofMonitor<D>,
    out: &Path,
    t_peak: f64,
    settle: f64,
) -> Result<()> {
    let snapshots = roof.snapshots();
    if snapshots.is_empty() || D != 2 {
        return Ok(());
    }
    let dir = out.join("plots");
    std::fs::create_dir_all(&dir)?;
    for (label, offset) in [("a", -0.06), ("b", 0.0), ("c", 0.06)] {
        let target = t_peak + offset;
        let Some(snap) = snapshots
            .iter()
            .min_by(|a, b| (a.time - target).abs().total_cmp(&(b.time - target).abs()))
        else {
            continue;
        };
        let title = format!(
            "Pressure field at {:.2} s after the excitation start",
            snap.time - settle
        );
        draw_snapshot(roof, snap, &dir.join(format!("fig7_{label}")), title)?;
    }
    Ok(())
}

/// Draws the 2D fluid at the output row of the largest wave (the largest |η| at either wall
/// gauge), coloured by pressure, as `plots/frame_peak.png` (and `.svg`).
pub fn write_frame_peak<const D: usize>(
    roof: &RoofMonitor<D>,
    out: &Path,
    frame: &(RoofSnapshot, f64),
    settle: f64,
) -> Result<()> {
    if D != 2 {
        return Ok(());
    }
    let dir = out.join("plots");
    std::fs::create_dir_all(&dir)?;
    let (snap, wave) = frame;
    let title = format!(
        "Pressure field at the largest wave (|η| = {wave:.3} m), {:.2} s after the excitation start",
        snap.time - settle
    );
    draw_snapshot(roof, snap, &dir.join("frame_peak"), title)
}

/// Draws one 2D fluid snapshot as a pressure heat map on the lattice cells of the tank
/// interior, into `<path>.png` and `<path>.svg`.
fn draw_snapshot<const D: usize>(
    roof: &RoofMonitor<D>,
    snap: &RoofSnapshot,
    path: &Path,
    title: String,
) -> Result<()> {
    let ((lo, hi), dx) = roof.interior();
    let nx = ((hi[0] - lo[0]) / dx).round().max(1.0) as usize;
    let ny = ((hi[D - 1] - lo[D - 1]) / dx).round().max(1.0) as usize;
    let xs: Vec<f64> = (0..nx).map(|i| lo[0] + (i as f64 + 0.5) * dx).collect();
    let ys: Vec<f64> = (0..ny).map(|j| lo[D - 1] + (j as f64 + 0.5) * dx).collect();
    let mut values = vec![f64::NAN; nx * ny];
    for (p, &pr) in snap.position.iter().zip(&snap.pressure) {
        let i = ((p[0] - lo[0]) / dx).floor();
        let j = ((p[1] - lo[D - 1]) / dx).floor();
        if i >= 0.0 && j >= 0.0 && (i as usize) < nx && (j as usize) < ny {
            values[i as usize * ny + j as usize] = pr;
        }
    }
    fill_interior_holes(&mut values, nx, ny);
    slosh_io::heatmap(
        path,
        &PlotSpec::new(title, "x [m]", "y [m]"),
        &Field2d {
            xs: &xs,
            ys: &ys,
            values: &values,
            value_label: "p [Pa]".into(),
        },
    )?;
    Ok(())
}

/// Fills the empty cells of a binned snapshot that lie inside the liquid — all but at most
/// two of their neighbours (and at least four) hold a particle — with the mean of those
/// neighbours. A disordered
/// particle arrangement leaves some lattice cells empty and others doubly filled; the free
/// surface and splashes (cells with fewer filled neighbours) stay empty.
fn fill_interior_holes(values: &mut [f64], nx: usize, ny: usize) {
    let source = values.to_vec();
    for i in 0..nx {
        for j in 0..ny {
            if !source[i * ny + j].is_nan() {
                continue;
            }
            let (mut sum, mut filled, mut neighbours) = (0.0, 0, 0);
            for (di, dj) in [
                (-1, -1),
                (-1, 0),
                (-1, 1),
                (0, -1),
                (0, 1),
                (1, -1),
                (1, 0),
                (1, 1),
            ] {
                let (a, b) = (i as i64 + di, j as i64 + dj);
                if a < 0 || b < 0 || a >= nx as i64 || b >= ny as i64 {
                    continue;
                }
                neighbours += 1;
                let v = source[a as usize * ny + b as usize];
                if !v.is_nan() {
                    sum += v;
                    filled += 1;
                }
            }
            if filled >= 4 && filled + 2 >= neighbours {
                values[i * ny + j] = sum / filled as f64;
            }
        }
    }
}

/// Writes `roof_spectrum.csv`, the roof load spectrum (`docs/roof-loads.md`): for each roof
/// period T_r the equivalent static roof force F_eq and its dynamic load factor, then for
/// each sensor its equivalent static pressure and factor; and its plot.
pub fn write_roof_spectrum(
    load: &slosh_run::RoofLoadResult,
    out: &Path,
    dim: usize,
    plots: bool,
) -> Result<()> {
    let Some(roof) = &load.roof else {
        return Ok(());
    };
    let mut header: Vec<String> = vec!["period".into(), "roof_f_eq".into(), "roof_dlf".into()];
    for s in &load.sensors {
        header.push(format!("p_{}_eq", s.sensor.name));
        header.push(format!("p_{}_dlf", s.sensor.name));
    }
    let dlf = |f: f64, peak: f64| if peak > 0.0 { f / peak } else { f64::NAN };
    let mut table = slosh_io::TableWriter::create_whole(out.join("roof_spectrum.csv"), &header)?;
    let mut row = Vec::with_capacity(header.len());
    for (i, &t) in load.spectrum_periods.iter().enumerate() {
        row.clear();
        row.extend([t, roof.spectrum[i], dlf(roof.spectrum[i], roof.peak)]);
        for s in &load.sensors {
            row.push(s.load.spectrum[i]);
            row.push(dlf(s.load.spectrum[i], s.load.peak));
        }
        table.write_row(&row)?;
    }
    table.finish()?;
    if plots {
        let log_t: Vec<f64> = load.spectrum_periods.iter().map(|t| t.log10()).collect();
        let unit = if dim == 2 { "N/m" } else { "N" };
        slosh_io::line_plot(
            out.join("plots").join("roof_spectrum"),
            &PlotSpec::new(
                format!(
                    "Roof load spectrum (ζ_r = {:.1} %)",
                    100.0 * load.damping_ratio
                ),
                "roof period log₁₀ T_r [s]",
                format!("equivalent static roof force F_eq [{unit}]"),
            ),
            &[slosh_io::Series::line("F_eq", &log_t, &roof.spectrum)],
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::fill_interior_holes;

    /// A 4 × 4 block of liquid under 2 empty rows, with one empty cell inside and one at the
    /// side wall: both are filled with their neighbours' mean; the empty rows above the
    /// surface stay empty.
    #[test]
    fn holes_inside_the_liquid_are_filled_and_the_surface_is_kept() {
        let (nx, ny) = (4, 6);
        let mut values = vec![f64::NAN; nx * ny];
        for i in 0..nx {
            for j in 0..4 {
                values[i * ny + j] = 1.0;
            }
        }
        values[ny + 1] = f64::NAN; // inside
        values[2] = f64::NAN; // at the wall i = 0
        fill_interior_holes(&mut values, nx, ny);
        assert_eq!(values[ny + 1], 1.0);
        assert_eq!(values[2], 1.0);
        for i in 0..nx {
            assert!(values[i * ny + 4].is_nan() && values[i * ny + 5].is_nan());
        }
    }
}
